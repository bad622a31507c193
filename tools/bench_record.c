/* lanecast bench: what every record says about the machine and the build
 * (CPU model and SIMD flags from /proc/cpuinfo, the commit from meson's
 * vcs_tag at build time, the compiler), JSON string output, clocks and
 * memory. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/utsname.h>
#include <time.h>
#include <unistd.h>
#include "bench_common.h"
#include "bench_version.h"

double bench_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double bench_cpu_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

long bench_rss_peak_kb(void)
{
    struct rusage ru;
    return getrusage(RUSAGE_SELF, &ru) ? -1 : ru.ru_maxrss;
}

long bench_rss_now_kb(void)
{
    long pages = 0, res = -1;
    FILE *f = fopen("/proc/self/statm", "r");
    if (!f) return -1;
    if (fscanf(f, "%ld %ld", &pages, &res) != 2) res = -1;
    fclose(f);
    return res < 0 ? -1 : res * (sysconf(_SC_PAGESIZE) / 1024);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

double bench_median(double *v, int n)
{
    if (n < 1) return NAN;
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void bench_jnum(FILE *f, const char *key, double v)
{
    if (isfinite(v)) fprintf(f, ", \"%s\": %.6g", key, v);
    else fprintf(f, ", \"%s\": null", key);
}

double bench_loadavg(void)
{
    double l = -1;
    FILE *f = fopen("/proc/loadavg", "r");
    if (!f) return -1;
    if (fscanf(f, "%lf", &l) != 1) l = -1;
    fclose(f);
    return l;
}

void bench_json_str(FILE *f, const char *s)
{
    fputc('"', f);
    for (; s && *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\') fprintf(f, "\\%c", c);
        else if (c < 0x20) fprintf(f, "\\u%04x", c);
        else fputc(c, f);
    }
    fputc('"', f);
}

/* The SIMD-relevant flags of /proc/cpuinfo (the whole line is ~1.5 KB). */
static const char *const simd_flags[] = {"sse4_2", "avx", "avx2", "fma", "f16c", "bmi2", "avx512f", "avx512dq",
                                         "avx512bw", "avx512vl", "avx512_vnni", "avx512_bf16", "hypervisor"};

static void escape_into(char *dst, size_t size, const char *s)
{
    size_t o = 0;
    for (; *s && o + 3 < size; s++) {
        if (*s == '"' || *s == '\\') dst[o++] = '\\';
        dst[o++] = (unsigned char)*s < 0x20 ? ' ' : *s;
    }
    dst[o] = 0;
}

const char *bench_machine_json(void)
{
    static char buf[2048];
    if (buf[0]) return buf;
    char model[256] = "unknown", flags[512] = "", line[4096];
    FILE *f = fopen("/proc/cpuinfo", "r");
    int have_model = 0, have_flags = 0;
    while (f && fgets(line, sizeof line, f) && !(have_model && have_flags)) {
        char *colon = strchr(line, ':');
        if (!colon) continue;
        char *v = colon + 1 + (colon[1] == ' ');
        v[strcspn(v, "\n")] = 0;
        if (!have_model && !strncmp(line, "model name", 10)) escape_into(model, sizeof model, v), have_model = 1;
        if (!have_flags && !strncmp(line, "flags", 5)) {
            have_flags = 1;
            for (size_t i = 0; i < sizeof simd_flags / sizeof simd_flags[0]; i++) {
                char pat[64];
                snprintf(pat, sizeof pat, " %s ", simd_flags[i]);
                char padded[4096 + 2];
                snprintf(padded, sizeof padded, " %s ", v);
                if (strstr(padded, pat)) {
                    size_t l = strlen(flags);
                    snprintf(flags + l, sizeof flags - l, "%s%s", l ? " " : "", simd_flags[i]);
                }
            }
        }
    }
    if (f) fclose(f);
    struct utsname u;
    char host[128] = "", kernel[128] = "";
    if (!uname(&u)) escape_into(host, sizeof host, u.nodename), escape_into(kernel, sizeof kernel, u.release);
    char targets[128] = "";
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++)
        if (lc_target_compiled((lc_target)t) && lc_target_supported((lc_target)t)) {
            size_t l = strlen(targets);
            snprintf(targets + l, sizeof targets - l, "%s%s", l ? " " : "", lc_target_name((lc_target)t));
        }
    char date[32] = "unknown";
    time_t now = time(NULL);
    struct tm tm;
    if (gmtime_r(&now, &tm)) strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", &tm);
    snprintf(buf, sizeof buf,
             "\"date\": \"%s\", \"cpu\": \"%s\", \"cpu_flags\": \"%s\", \"cpus_online\": %ld, \"host\": \"%s\", \"kernel\": \"%s\", "
             "\"lanecast\": \"%s\", \"commit\": \"%s\", \"compiler\": \"%s\", \"targets_here\": \"%s\"",
             date, model, flags, sysconf(_SC_NPROCESSORS_ONLN), host, kernel, lc_version_string(), LC_BENCH_COMMIT,
#if defined(__clang__)
             "clang " __clang_version__,
#elif defined(__GNUC__)
             "gcc " __VERSION__,
#else
             "unknown",
#endif
             targets);
    return buf;
}
