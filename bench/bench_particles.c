/* Particle rendering benchmark: fps and Gaussian evaluations per second per
 * data set, view, target, thread count, method and packet size. Warms up,
 * repeats, reports the median and the spread, one machine-readable line per
 * case (key=value). Procedural sets use a fixed seed; real molecules come from
 * ../shared/data. Run `bench_particles --help`. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>
#include "lanecast/lanecast.h"

typedef struct cfg {
    int width, height, repeats, warmup;
    double min_seconds;
    const char *targets, *threads, *methods, *packets, *views, *sets, *data_dir;
    int quick;
} cfg;

static const char help[] =
    "usage: bench_particles [options]\n"
    "  --size WxH         image size (default 1024x1024)\n"
    "  --sets LIST        comma list: 1e4,1e5,1e6,1e7 (procedural, uniform), dense1e6 (procedural, 40 dense\n"
    "                     clusters + 10 percent background), 1tii, 1tw7 (real) (default 1e4,1e5,1e6,1tii,1tw7)\n"
    "                     e.g. bench_particles --sets dense1e6,1e6 --targets avx512 --threads 2 --methods coherent\n"
    "  --targets LIST     scalar,sse4,avx2,avx512,avx512_8 (default: every supported)\n"
    "  --threads LIST     e.g. 1,2 (default 1,2)\n"
    "  --methods LIST     coherent,direct (default coherent,direct)\n"
    "  --packets LIST     group sides in rays: 0 = the library's default (16x16 groups for the\n"
    "                     coherent method), 8 = 8x8 groups, 1 = lane-width packets (default 0)\n"
    "                     e.g. bench_particles --sets 1e6 --packets 0,8 --methods coherent\n"
    "  --views LIST       far,close (default far,close)\n"
    "  --repeats N        timed renders per case (default 5; at least 1)\n"
    "  --min-seconds S    stop repeating a case after S seconds once 1 render is done (default 20)\n"
    "  --data DIR         shared data folder (default ../shared/data)\n"
    "  --quick            smoke run: 64x64, tiny sets, 1 repeat\n";

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmpd(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static int in_list(const char *list, const char *item)
{
    size_t n = strlen(item);
    for (const char *p = list; p && *p;) {
        const char *e = strchr(p, ',');
        size_t len = e ? (size_t)(e - p) : strlen(p);
        if (len == n && !strncmp(p, item, n)) return 1;
        p = e ? e + 1 : NULL;
    }
    return 0;
}

/* One xorshift step: a uniform float in [0, 1). */
static float urand(uint64_t *s)
{
    *s ^= *s << 13, *s ^= *s >> 7, *s ^= *s << 17;
    return (float)(*s >> 40) / 16777216.0f;
}

/* The dense clustered set ("dense1e6"): in the same cube, 90% of the
 * particles in 40 Gaussian clusters (centres uniform in the inner 80% of the
 * cube, standard deviation 3 units), 10% uniform background, every radius 1.
 * With sigma = 2 a cluster core holds ~2000 overlapping Gaussians, the
 * background ~0.4. It renders with the value range [0, 32] (dense_range), so
 * the preset TF (transparent below 10% of the range, i.e. phi < 3.2) leaves
 * the background and the cluster fringes fully transparent. Seed fixed. */
static void clustered(float *xyz, float *r, size_t n, float side)
{
    enum { NC = 40 };
    float cc[NC][3];
    uint64_t s = 0x2545f4914f6cdd1dull;
    for (int c = 0; c < NC; c++)
        for (int k = 0; k < 3; k++) cc[c][k] = side * (0.1f + 0.8f * urand(&s));
    for (size_t i = 0; i < n; i++) {
        r[i] = 1.0f;
        if (urand(&s) < 0.1f) {
            for (int k = 0; k < 3; k++) xyz[3 * i + k] = side * urand(&s);
            continue;
        }
        int c = (int)(urand(&s) * NC) % NC;
        for (int k = 0; k < 3; k++) {
            /* Box-Muller */
            float u1 = urand(&s), u2 = urand(&s);
            float g = sqrtf(-2.0f * logf(u1 + 1e-12f)) * cosf(6.2831853f * u2);
            xyz[3 * i + k] = cc[c][k] + 3.0f * g;
        }
    }
}

/* Uniform random particles in a cube at roughly liquid-atom density (one per
 * 8 cubic units, radius 0.6..1.2): the field looks alike at every size. */
static lc_status procedural(lc_device *dev, size_t n, int dense, lc_volume **out, double *gen_s)
{
    double t0 = now();
    float *xyz = malloc(sizeof(float) * 3 * n), *r = malloc(sizeof(float) * n);
    if (!xyz || !r) {
        free(xyz), free(r);
        return LC_ERROR_OUT_OF_MEMORY;
    }
    float side = 2.0f * cbrtf((float)n);
    uint64_t s = 0x9e3779b97f4a7c15ull;
    for (size_t i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++) {
            s ^= s << 13, s ^= s >> 7, s ^= s << 17;
            xyz[3 * i + k] = side * (float)(s >> 40) / 16777216.0f;
        }
        s ^= s << 13, s ^= s >> 7, s ^= s << 17;
        r[i] = 0.6f + 0.6f * (float)(s >> 40) / 16777216.0f;
    }
    if (dense) clustered(xyz, r, n, side);
    *gen_s = now() - t0;
    lc_status st = lc_particles_create(dev, &(lc_particles_desc){.count = n, .positions = xyz, .radii = r}, out);
    free(xyz);
    free(r);
    return st;
}

/* CPU seconds of the whole process (every thread), user + system: steadier
 * than wall time on a shared machine. */
static double cpu_now(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec + (double)ru.ru_stime.tv_sec +
           1e-6 * (double)ru.ru_stime.tv_usec;
}

static long rss_mb(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_maxrss / 1024;
}

/* Resident memory now (not the peak), from /proc/self/statm. */
static long rss_now_mb(void)
{
    long pages = 0, res = 0;
    FILE *f = fopen("/proc/self/statm", "r");
    if (!f) return -1;
    if (fscanf(f, "%ld %ld", &pages, &res) != 2) res = -1;
    fclose(f);
    return res < 0 ? -1 : res * 4096 / (1024 * 1024);
}

static void run_set(const cfg *c, const char *set)
{
    char path[1024] = "";
    size_t n = 0;
    if (!strcmp(set, "1tii")) snprintf(path, sizeof path, "%s/particles/1tii.pdb", c->data_dir);
    else if (!strcmp(set, "1tw7")) snprintf(path, sizeof path, "%s/particles/1tw7_solvated.pdb", c->data_dir);
    else n = (size_t)strtod(set + (strncmp(set, "dense", 5) ? 0 : 5), NULL);
    if (!path[0] && n == 0) {
        fprintf(stderr, "bench_particles: unknown set '%s'\n", set);
        return;
    }
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        const char *tn = lc_target_name((lc_target)t);
        if (c->targets ? !in_list(c->targets, tn) : 0) continue;
        if (!lc_target_compiled((lc_target)t) || !lc_target_supported((lc_target)t)) {
            if (c->targets) printf("# skip target=%s: not supported here\n", tn);
            continue;
        }
        for (int th = 1; th <= 1024; th++) {
            char ths[16];
            snprintf(ths, sizeof ths, "%d", th);
            if (!in_list(c->threads, ths)) continue;
            lc_device *dev;
            if (lc_device_create(&(lc_device_desc){.target = (lc_target)t, .threads = th}, &dev) != LC_OK) {
                fprintf(stderr, "bench_particles: %s\n", lc_last_error());
                continue;
            }
            lc_volume *p = NULL;
            double gen = 0;
            lc_status s = path[0] ? lc_volume_load(dev, path, NULL, &p) : procedural(dev, n, !strncmp(set, "dense", 5), &p, &gen);
            if (s != LC_OK) {
                printf("# skip set=%s: %s\n", set, lc_last_error());
                lc_device_destroy(dev);
                return;
            }
            lc_particles_info pi;
            lc_particles_get_info(p, &pi);
            lc_tf *tf;
            lc_tf_preset(dev, "heat", 1, 1.0f / pi.max_radius, &tf);
            float *rgba = malloc(sizeof(float) * 4 * (size_t)c->width * (size_t)c->height);
            for (int vi = 0; vi < 2; vi++) {
                const char *view = vi ? "close" : "far";
                if (!in_list(c->views, view)) continue;
                lc_vec3 lo = pi.bounds.lo, hi = pi.bounds.hi;
                lc_vec3 ctr = {(lo.x + hi.x) / 2, (lo.y + hi.y) / 2, (lo.z + hi.z) / 2};
                float rad = 0.5f * sqrtf((hi.x - lo.x) * (hi.x - lo.x) + (hi.y - lo.y) * (hi.y - lo.y) +
                                         (hi.z - lo.z) * (hi.z - lo.z));
                /* far: the whole set in view; close: the eye at the front face, looking in */
                float dist = vi ? 0.5f * rad : rad / sinf(20.0f * 3.14159265f / 180.0f) * 1.05f;
                lc_camera cam = {.eye = {ctr.x, ctr.y, ctr.z + dist}, .at = ctr, .fovy = 40.0f};
                for (int mi = 0; mi < 2; mi++) {
                    const char *mn = mi ? "direct" : "coherent";
                    if (!in_list(c->methods, mn)) continue;
                    int direct_done = 0; /* direct ignores packets: its first only */
                    for (int pk = 0; pk <= 64; pk++) {
                        char pks[16];
                        snprintf(pks, sizeof pks, "%d", pk);
                        if (!in_list(c->packets, pks)) continue;
                        if (mi == 1 && direct_done++) continue;
                        lc_render_desc d = {.width = c->width, .height = c->height, .camera = cam, .tf = tf,
                                            .volume = p, .method = mi ? LC_METHOD_DIRECT : LC_METHOD_COHERENT,
                                            .packet = pk};
                        if (!strncmp(set, "dense", 5)) d.range[0] = 0.0f, d.range[1] = 32.0f;
                        lc_render_stats st;
                        for (int w = 0; w < c->warmup; w++) lc_render(dev, &d, rgba, &st);
                        double times[64], cpus[64];
                        int reps = 0;
                        double start = now();
                        uint64_t evals = 0, samples = 0;
                        while (reps < c->repeats && reps < 64) {
                            double c0 = cpu_now();
                            if (lc_render(dev, &d, rgba, &st) != LC_OK) {
                                fprintf(stderr, "bench_particles: %s\n", lc_last_error());
                                break;
                            }
                            cpus[reps] = cpu_now() - c0;
                            times[reps++] = st.seconds;
                            evals = st.kernel_evals, samples = st.samples;
                            if (now() - start > c->min_seconds) break;
                        }
                        if (!reps) continue;
                        long rss_now = rss_now_mb();
                        qsort(times, (size_t)reps, sizeof times[0], cmpd);
                        qsort(cpus, (size_t)reps, sizeof cpus[0], cmpd);
                        double cmed = reps % 2 ? cpus[reps / 2] : 0.5 * (cpus[reps / 2 - 1] + cpus[reps / 2]);
                        double med = reps % 2 ? times[reps / 2] : 0.5 * (times[reps / 2 - 1] + times[reps / 2]);
                        printf("particles set=%s n=%zu view=%s target=%s lanes=%d threads=%d method=%s packet=%d "
                               "size=%dx%d reps=%d median_s=%.5f min_s=%.5f max_s=%.5f cpu_median_s=%.5f cpu_min_s=%.5f "
                               "cpu_max_s=%.5f fps=%.3f gauss_per_s=%.4g "
                               "samples=%llu build_s=%.3f bvh_mb=%.2f data_mb=%.2f rss_now_mb=%ld rss_peak_mb=%ld\n",
                               set, pi.count, view, tn, lc_target_lanes((lc_target)t), th, mn, pk, c->width,
                               c->height, reps, med, times[0], times[reps - 1], cmed, cpus[0], cpus[reps - 1], 1.0 / med, (double)evals / med,
                               (unsigned long long)samples, pi.build_seconds, (double)pi.bvh_bytes / 1e6,
                               (double)pi.data_bytes / 1e6, rss_now, rss_mb());
                        fflush(stdout);
                    }
                }
            }
            free(rgba);
            lc_tf_destroy(tf);
            lc_volume_destroy(p);
            lc_device_destroy(dev);
        }
    }
}

int main(int argc, char **argv)
{
    cfg c = {1024, 1024, 5, 1, 20.0, NULL, "1,2", "coherent,direct", "0", "far,close", "1e4,1e5,1e6,1tii,1tw7",
             "../shared/data", 0};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--help")) {
            fputs(help, stdout);
            return 0;
        } else if (!strcmp(a, "--quick")) {
            c.quick = 1;
        } else if (v && !strcmp(a, "--size")) {
            if (sscanf(v, "%dx%d", &c.width, &c.height) != 2 || c.width < 1 || c.height < 1) {
                fprintf(stderr, "bench_particles: --size: expected WxH, got '%s'\n", v);
                return 2;
            }
            i++;
        } else if (v && !strcmp(a, "--sets")) c.sets = v, i++;
        else if (v && !strcmp(a, "--targets")) c.targets = v, i++;
        else if (v && !strcmp(a, "--threads")) c.threads = v, i++;
        else if (v && !strcmp(a, "--methods")) c.methods = v, i++;
        else if (v && !strcmp(a, "--packets")) c.packets = v, i++;
        else if (v && !strcmp(a, "--views")) c.views = v, i++;
        else if (v && !strcmp(a, "--data")) c.data_dir = v, i++;
        else if (v && !strcmp(a, "--repeats")) c.repeats = atoi(v) < 1 ? 1 : atoi(v), i++;
        else if (v && !strcmp(a, "--min-seconds")) c.min_seconds = atof(v), i++;
        else {
            fprintf(stderr, "bench_particles: unknown or incomplete option '%s' (see --help)\n", a);
            return 2;
        }
    }
    if (c.quick) {
        c.width = c.height = 64;
        c.repeats = 1;
        c.warmup = 0;
        if (!strcmp(c.sets, "1e4,1e5,1e6,1tii,1tw7")) c.sets = "1e3,1tii";
    }
    printf("# lanecast %s bench_particles: %dx%d, median of up to %d renders after %d warm-up; procedural sets: "
           "uniform random, seed fixed, radius 0.6..1.2, 1 particle per 8 cubic units\n",
           lc_version_string(), c.width, c.height, c.repeats, c.warmup);
    char sets[1024];
    snprintf(sets, sizeof sets, "%s", c.sets);
    for (char *tok = strtok(sets, ","); tok; tok = strtok(NULL, ",")) run_set(&c, tok);
    return 0;
}
