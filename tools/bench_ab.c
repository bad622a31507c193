/* lanecast bench --baseline PATH: this build against another build of
 * lanecast on the same cases, in interleaved rounds (the order alternating,
 * so load drift falls on both alike). Each round runs both binaries' bench
 * with the caller's case flags (no check, a short roofline) into a
 * temporary file; records of the same case are paired by their keys, and
 * the ratio baseline / this of the median frame time (wall, and CPU when
 * both record it) is summarised over the rounds: median, min and max. One
 * JSON line per case (record "ab") and a table on stderr. */
#define _GNU_SOURCE
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include "bench_run.h"

#define AB_MAX_CASES 512
#define AB_MAX_ROUNDS 64

typedef struct ab_case {
    char key[256];
    double t[2][AB_MAX_ROUNDS], cpu[2][AB_MAX_ROUNDS]; /* [0] this build, [1] the baseline */
    int n[2], ncpu[2];
    char commit[2][128];
} ab_case;

/* The value of "name": in a JSON line we wrote: a string (unquoted into
 * buf) or a number (as text). 0 when absent. */
static int jfield(const char *line, const char *name, char *buf, size_t n)
{
    char pat[80];
    snprintf(pat, sizeof pat, "\"%s\": ", name);
    const char *p = strstr(line, pat);
    if (!p || n == 0) return 0;
    p += strlen(pat);
    size_t k = 0;
    if (*p == '"') {
        for (p++; *p && *p != '"' && k + 1 < n; p++) buf[k++] = *p == '\\' && p[1] ? *++p : *p;
    } else {
        for (; *p && *p != ',' && *p != '}' && k + 1 < n; p++) buf[k++] = *p;
    }
    buf[k] = '\0';
    return 1;
}

static int cmpd(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Reads one run's records into the cases; side 0 = this build. */
static void read_run(const char *path, int side, ab_case *cs, int *ncs)
{
    FILE *f = fopen(path, "r");
    if (!f) return;
    char *line = NULL;
    size_t cap = 0;
    static const char *const keys[] = {"scene", "view", "width", "height", "mode", "method", "packet",
                                       "shading", "alpha_stop", "sigma", "threads", "target"};
    while (getline(&line, &cap, f) > 0) {
        char v[128], med[64];
        if (!jfield(line, "record", v, sizeof v) || strcmp(v, "case") || !jfield(line, "median_s", med, sizeof med) ||
            !strcmp(med, "null"))
            continue;
        char key[256] = "";
        for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++)
            if (jfield(line, keys[k], v, sizeof v))
                snprintf(key + strlen(key), sizeof key - strlen(key), "%s%s", key[0] ? " " : "", v);
        int i = 0;
        while (i < *ncs && strcmp(cs[i].key, key)) i++;
        if (i == *ncs) {
            if (*ncs == AB_MAX_CASES) continue;
            memset(&cs[i], 0, sizeof cs[i]);
            snprintf(cs[i].key, sizeof cs[i].key, "%s", key);
            (*ncs)++;
        }
        ab_case *c = &cs[i];
        if (c->n[side] < AB_MAX_ROUNDS) c->t[side][c->n[side]++] = atof(med);
        if (jfield(line, "cpu_median_s", v, sizeof v) && strcmp(v, "null") && c->ncpu[side] < AB_MAX_ROUNDS)
            c->cpu[side][c->ncpu[side]++] = atof(v);
        if (jfield(line, "commit", v, sizeof v)) snprintf(c->commit[side], sizeof c->commit[side], "%s", v);
    }
    free(line);
    fclose(f);
}

/* Runs exe bench ARGS -o out, its output to /dev/null; 0 when it exited 0.
 * *cpu = the run's CPU seconds (user + system of every thread). */
static int run_bench(const char *exe, char **args, int nargs, const char *out, double *cpu)
{
    char **av = calloc((size_t)nargs + 16, sizeof *av); /* the flags added below and NULL */
    if (!av) return -1;
    int k = 0;
    av[k++] = (char *)exe;
    av[k++] = "bench";
    for (int i = 0; i < nargs; i++) av[k++] = args[i];
    av[k++] = "--no-check";
    av[k++] = "--seconds"; /* every run renders the same frames: no time bound */
    av[k++] = "1e6";
    av[k++] = "--roof-seconds";
    av[k++] = "0.01";
    av[k++] = "-o";
    av[k++] = (char *)out;
    av[k] = NULL;
    pid_t pid = fork();
    if (pid == 0) {
        int null = open("/dev/null", O_WRONLY);
        if (null >= 0) dup2(null, 1), dup2(null, 2);
        execv(exe, av);
        _exit(127);
    }
    free(av);
    int st = 0;
    struct rusage ru;
    if (pid < 0 || wait4(pid, &st, 0, &ru) < 0) return -1;
    *cpu = (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec + (double)ru.ru_stime.tv_sec +
           1e-6 * (double)ru.ru_stime.tv_usec;
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static double median(const double *v, int n)
{
    double s[AB_MAX_ROUNDS];
    memcpy(s, v, sizeof(double) * (size_t)n);
    qsort(s, (size_t)n, sizeof s[0], cmpd);
    return n % 2 ? s[n / 2] : 0.5 * (s[n / 2 - 1] + s[n / 2]);
}

/* Ratios baseline / this per round (paired by round index), summarised. */
static int ratios(const double *a, int na, const double *b, int nb, double *med, double *lo, double *hi)
{
    int n = na < nb ? na : nb;
    double r[AB_MAX_ROUNDS];
    for (int i = 0; i < n; i++) r[i] = a[i] > 0 ? b[i] / a[i] : 0.0;
    if (n == 0) return 0;
    *med = median(r, n);
    qsort(r, (size_t)n, sizeof r[0], cmpd);
    *lo = r[0], *hi = r[n - 1];
    return n;
}

int bench_ab(const char *baseline, int rounds, char **args, int nargs, FILE *out)
{
    char self[4096];
    ssize_t len = readlink("/proc/self/exe", self, sizeof self - 1);
    if (len <= 0) {
        fprintf(stderr, "lanecast bench: --baseline: cannot find this program's own path\n");
        return 1;
    }
    self[len] = '\0';
    if (access(baseline, X_OK) != 0) {
        fprintf(stderr, "lanecast bench: --baseline %s: not an executable file\n", baseline);
        return 1;
    }
    char tmpl[] = "/tmp/lanecast-ab-XXXXXX";
    int fd = mkstemp(tmpl);
    if (fd < 0) {
        fprintf(stderr, "lanecast bench: --baseline: cannot create a temporary file\n");
        return 1;
    }
    close(fd);
    static ab_case cs[AB_MAX_CASES];
    int ncs = 0, bad = 0;
    double run_cpu[2][AB_MAX_ROUNDS]; /* whole runs: the same work in both builds (loads, builds, renders) */
    if (rounds > AB_MAX_ROUNDS) rounds = AB_MAX_ROUNDS;
    for (int r = 0; r < rounds && !bad; r++) {
        for (int k = 0; k < 2; k++) {
            int side = (r + k) % 2; /* this build first in even rounds */
            const char *exe = side ? baseline : self;
            FILE *t = fopen(tmpl, "w");
            if (t) fclose(t);
            fprintf(stderr, "lanecast bench: A/B round %d of %d: %s ...\n", r + 1, rounds, side ? "baseline" : "this build");
            int rc = run_bench(exe, args, nargs, tmpl, &run_cpu[side][r]);
            if (rc != 0) {
                fprintf(stderr, "lanecast bench: --baseline: %s bench exited with status %d (run it alone to see why)\n",
                        exe, rc);
                bad = 1;
                break;
            }
            read_run(tmpl, side, cs, &ncs);
        }
    }
    unlink(tmpl);
    if (bad) return 1;
    double rmed = 0, rlo = 0, rhi = 0;
    ratios(run_cpu[0], rounds, run_cpu[1], rounds, &rmed, &rlo, &rhi);
    fprintf(out, "{\"record\": \"ab_runs\", \"rounds\": %d, \"this_cpu_s\": %.4g, \"base_cpu_s\": %.4g, "
                 "\"cpu_ratio_median\": %.4f, \"cpu_ratio_min\": %.4f, \"cpu_ratio_max\": %.4f, \"baseline\": ",
            rounds, median(run_cpu[0], rounds), median(run_cpu[1], rounds), rmed, rlo, rhi);
    bench_json_str(out, baseline);
    fprintf(out, ", %s}\n", bench_machine_json());
    fprintf(stderr, "lanecast bench: whole runs' CPU time (loads, builds and the same renders): baseline / this %.3f "
                    "(%.3f..%.3f over %d rounds)\n", rmed, rlo, rhi, rounds);
    fprintf(stderr, "%-64s %10s %10s %8s %15s %8s\n", "case (baseline / this: > 1 = this is faster)", "this ms",
            "base ms", "ratio", "min..max", "cpu");
    for (int i = 0; i < ncs; i++) {
        ab_case *c = &cs[i];
        double med, lo, hi, cmed = 0, clo, chi;
        int n = ratios(c->t[0], c->n[0], c->t[1], c->n[1], &med, &lo, &hi);
        int ncpu = ratios(c->cpu[0], c->ncpu[0], c->cpu[1], c->ncpu[1], &cmed, &clo, &chi);
        if (!n) {
            fprintf(stderr, "%-64s only in %s\n", c->key, c->n[0] ? "this build" : "the baseline");
            continue;
        }
        double ma = median(c->t[0], c->n[0]), mb = median(c->t[1], c->n[1]);
        fprintf(out, "{\"record\": \"ab\", \"case\": ");
        bench_json_str(out, c->key);
        fprintf(out, ", \"rounds\": %d, \"this_median_s\": %.6g, \"base_median_s\": %.6g, \"ratio_median\": %.4f, "
                     "\"ratio_min\": %.4f, \"ratio_max\": %.4f",
                n, ma, mb, med, lo, hi);
        if (ncpu) fprintf(out, ", \"cpu_ratio_median\": %.4f, \"cpu_ratio_min\": %.4f, \"cpu_ratio_max\": %.4f", cmed, clo, chi);
        fprintf(out, ", \"baseline\": ");
        bench_json_str(out, baseline);
        fprintf(out, ", \"base_commit\": ");
        bench_json_str(out, c->commit[1]);
        fprintf(out, ", %s}\n", bench_machine_json());
        char cpu[16] = "-";
        if (ncpu) snprintf(cpu, sizeof cpu, "%.3f", cmed);
        fprintf(stderr, "%-64.64s %10.2f %10.2f %8.3f %7.3f..%-7.3f %8s\n", c->key, 1e3 * ma, 1e3 * mb, med, lo, hi, cpu);
    }
    return ncs ? 0 : 1;
}
