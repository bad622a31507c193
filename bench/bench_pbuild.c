/* Particle BVH build: time, node count and depth, and memory (the build's own
 * peak and the process's) of one procedural set, then optionally CPU time per
 * frame of a far and a close view. One set per run so peaks do not mix; run
 * builders in alternating processes (bench/pbuild_ab.sh) for A/B tables in
 * docs/bench/particles.md ("Build peak").
 *
 * Memory: VmHWM is reset (/proc/self/clear_refs "5") right before
 * lc_particles_create, so afterwards it is the process's peak during the
 * build; the build's own peak is that minus VmRSS before the call (the caller's
 * arrays, the device). Render time is CPU time of the process (user + system
 * of every thread, the quantity `perf stat -e task-clock` counts) per
 * lc_render call: steadier than wall time on a shared machine. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "lanecast/lanecast.h"

static const char help[] =
    "usage: bench_pbuild SET [options]\n"
    "  SET            uniform:N   lanecast bench's uniform set (radii 0.6..1.2, 1 per 8 cubic units)\n"
    "                 cluster:N   lanecast bench's 16 Gaussian clusters, radii 0.3..0.6\n"
    "                 dense:N     bench_particles' dense1e6 generator: 40 tight clusters + 10%% background, r = 1\n"
    "  --leaf N       leaf size (default 4)\n"
    "  --renders N    timed frames per view after one warm-up (default 0: build only)\n"
    "  --size N       image side (default 1024)\n"
    "  --threads N    render threads (default 2)\n"
    "  --target NAME  (default auto)\n"
    "prints one key=value line per view (or one for the build).\n"
    "example: LANECAST_PBVH_BUILDER=embree bench_pbuild uniform:1e7 --renders 5\n";

static uint64_t rng;
static double urand64(void) /* lanecast bench's xorshift64* */
{
    rng ^= rng >> 12, rng ^= rng << 25, rng ^= rng >> 27;
    return (double)((rng * 0x2545f4914f6cdd1dull) >> 11) / 9007199254740992.0;
}
static double nrand64(void) { return sqrt(-2.0 * log(1.0 - urand64())) * cos(6.283185307179586 * urand64()); }
static float urand32(uint64_t *s) /* bench_particles' xorshift */
{
    *s ^= *s << 13, *s ^= *s >> 7, *s ^= *s << 17;
    return (float)(*s >> 40) / 16777216.0f;
}

static void gen(int kind, size_t n, float *xyz, float *r)
{
    if (kind < 2) { /* tools/bench_scenes.c make_particles: uniform (0) or cluster (2 there) */
        double side = 2.0 * cbrt((double)n), c[16][3];
        int p = kind == 0 ? 0 : 2;
        rng = 0x9e3779b97f4a7c15ull + (uint64_t)p;
        for (int k = 0; k < 16; k++)
            for (int a = 0; a < 3; a++) c[k][a] = side * (0.15 + 0.7 * urand64());
        for (size_t i = 0; i < n; i++) {
            for (int a = 0; a < 3; a++)
                xyz[3 * i + a] = (float)(kind == 1 ? c[i % 16][a] + side / 24.0 * nrand64() : side * urand64());
            r[i] = kind == 0 ? (float)(0.6 + 0.6 * urand64()) : (float)(0.3 + 0.3 * urand64());
        }
        return;
    }
    /* bench/bench_particles.c clustered() */
    float side = 2.0f * cbrtf((float)n), cc[40][3];
    uint64_t s = 0x2545f4914f6cdd1dull;
    for (int c = 0; c < 40; c++)
        for (int k = 0; k < 3; k++) cc[c][k] = side * (0.1f + 0.8f * urand32(&s));
    for (size_t i = 0; i < n; i++) {
        r[i] = 1.0f;
        if (urand32(&s) < 0.1f) {
            for (int k = 0; k < 3; k++) xyz[3 * i + k] = side * urand32(&s);
            continue;
        }
        int c = (int)(urand32(&s) * 40) % 40;
        for (int k = 0; k < 3; k++) {
            float u1 = urand32(&s), u2 = urand32(&s);
            xyz[3 * i + k] = cc[c][k] + 3.0f * sqrtf(-2.0f * logf(u1 + 1e-12f)) * cosf(6.2831853f * u2);
        }
    }
}

/* kB of a /proc/self/status line ("VmRSS:", "VmHWM:"), or -1 */
static long status_kb(const char *key)
{
    char line[256];
    long v = -1;
    FILE *f = fopen("/proc/self/status", "r");
    if (!f) return -1;
    while (fgets(line, sizeof line, f))
        if (!strncmp(line, key, strlen(key))) v = strtol(line + strlen(key), NULL, 10);
    fclose(f);
    return v;
}

static int reset_hwm(void)
{
    FILE *f = fopen("/proc/self/clear_refs", "w");
    if (!f) return -1;
    int ok = fputs("5", f) >= 0;
    return fclose(f) == 0 && ok ? 0 : -1;
}

static double cpu_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmpd(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

int main(int argc, char **argv)
{
    if (argc < 2 || !strcmp(argv[1], "--help")) {
        fputs(help, argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    const char *set = argv[1];
    int kind = !strncmp(set, "uniform:", 8) ? 0 : !strncmp(set, "cluster:", 8) ? 1 : !strncmp(set, "dense:", 6) ? 2 : -1;
    double nd = kind < 0 ? 0 : strtod(strchr(set, ':') + 1, NULL);
    if (kind < 0 || !(nd >= 1 && nd <= 1e9)) {
        fprintf(stderr, "bench_pbuild: bad set '%s' (uniform:N, cluster:N or dense:N)\n", set);
        return 2;
    }
    int leaf = 4, renders = 0, side = 1024, threads = 2;
    lc_target target = LC_TARGET_AUTO;
    for (int i = 2; i < argc; i++) {
        if (i + 1 >= argc) {
            fprintf(stderr, "bench_pbuild: %s needs a value\n", argv[i]);
            return 2;
        }
        const char *a = argv[i], *v = argv[++i];
        if (!strcmp(a, "--leaf")) leaf = atoi(v);
        else if (!strcmp(a, "--renders")) renders = atoi(v);
        else if (!strcmp(a, "--size")) side = atoi(v);
        else if (!strcmp(a, "--threads")) threads = atoi(v);
        else if (!strcmp(a, "--target")) {
            if (lc_target_from_name(v, &target) != LC_OK) {
                fprintf(stderr, "bench_pbuild: unknown target '%s'\n", v);
                return 2;
            }
        } else {
            fprintf(stderr, "bench_pbuild: unknown option '%s'\n%s", a, help);
            return 2;
        }
    }
    if (renders < 0 || renders > 64 || side < 16 || side > 8192 || threads < 1) {
        fprintf(stderr, "bench_pbuild: --renders 0..64, --size 16..8192, --threads >= 1\n");
        return 2;
    }
    size_t n = (size_t)nd;
    lc_device *dev;
    if (lc_device_create(&(lc_device_desc){.target = target, .threads = threads}, &dev) != LC_OK) {
        fprintf(stderr, "bench_pbuild: %s\n", lc_last_error());
        return 1;
    }
    float *xyz = malloc(sizeof(float) * 3 * n), *r = malloc(sizeof(float) * n);
    if (!xyz || !r) {
        fprintf(stderr, "bench_pbuild: out of memory\n");
        return 1;
    }
    gen(kind, n, xyz, r);
    long before = status_kb("VmRSS:");
    if (reset_hwm() != 0) fprintf(stderr, "bench_pbuild: note: cannot reset VmHWM; the peak is the process's so far\n");
    lc_volume *vol;
    double c0 = cpu_s();
    if (lc_particles_create(dev, &(lc_particles_desc){.count = n, .positions = xyz, .radii = r, .leaf_size = leaf},
                            &vol) != LC_OK) {
        fprintf(stderr, "bench_pbuild: %s\n", lc_last_error());
        return 1;
    }
    double build_cpu = cpu_s() - c0;
    long hwm = status_kb("VmHWM:"), after = status_kb("VmRSS:"), huge = -1;
    {
        char line[256];
        FILE *f = fopen("/proc/self/smaps_rollup", "r");
        while (f && fgets(line, sizeof line, f))
            if (!strncmp(line, "AnonHugePages:", 14)) huge = strtol(line + 14, NULL, 10);
        if (f) fclose(f);
    }
    free(xyz);
    free(r);
    lc_particles_info pi;
    lc_particles_get_info(vol, &pi);
    const char *b = getenv("LANECAST_PBVH_BUILDER");
    double budget = 2.0 * (double)pi.data_bytes + (double)pi.bvh_bytes;
    printf("set=%s n=%zu builder=%s leaf=%d build_s=%.3f build_cpu_s=%.3f nodes=%d depth=%d bvh_mb=%.2f data_mb=%.2f "
           "huge_pages_mb=%.1f rss_before_mb=%.1f rss_after_mb=%.1f process_peak_mb=%.1f build_peak_mb=%.1f budget_mb=%.1f",
           set, pi.count, b ? b : "default", leaf, pi.build_seconds, build_cpu, pi.bvh_nodes, pi.bvh_depth,
           (double)pi.bvh_bytes / 1e6, (double)pi.data_bytes / 1e6, huge * 1024.0 / 1e6, before * 1024.0 / 1e6, after * 1024.0 / 1e6,
           hwm * 1024.0 / 1e6, (hwm - before) * 1024.0 / 1e6, budget / 1e6);
    if (renders == 0) {
        printf("\n");
        lc_volume_destroy(vol);
        lc_device_destroy(dev);
        return 0;
    }
    printf("\n");
    lc_tf *tf;
    lc_tf_preset(dev, "heat", 1, 1.0f / pi.max_radius, &tf);
    float *rgba = malloc(sizeof(float) * 4 * (size_t)side * (size_t)side);
    if (!rgba) return 1;
    for (int vi = 0; vi < 2; vi++) { /* bench_particles' far and close views */
        lc_vec3 lo = pi.bounds.lo, hi = pi.bounds.hi;
        lc_vec3 ctr = {(lo.x + hi.x) / 2, (lo.y + hi.y) / 2, (lo.z + hi.z) / 2};
        float rad = 0.5f * sqrtf((hi.x - lo.x) * (hi.x - lo.x) + (hi.y - lo.y) * (hi.y - lo.y) +
                                 (hi.z - lo.z) * (hi.z - lo.z));
        float dist = vi ? 0.5f * rad : rad / sinf(20.0f * 3.14159265f / 180.0f) * 1.05f;
        lc_render_desc d = {.width = side, .height = side, .tf = tf, .volume = vol, .method = LC_METHOD_COHERENT,
                            .camera = {.eye = {ctr.x, ctr.y, ctr.z + dist}, .at = ctr, .fovy = 40.0f}};
        if (kind == 2) d.range[0] = 0.0f, d.range[1] = 32.0f;
        lc_render_stats st;
        double cpu[64], wall[64];
        if (lc_render(dev, &d, rgba, &st) != LC_OK) {
            fprintf(stderr, "bench_pbuild: %s\n", lc_last_error());
            return 1;
        }
        for (int k = 0; k < renders; k++) {
            double t = cpu_s();
            lc_render(dev, &d, rgba, &st);
            cpu[k] = cpu_s() - t, wall[k] = st.seconds;
        }
        qsort(cpu, (size_t)renders, sizeof cpu[0], cmpd);
        qsort(wall, (size_t)renders, sizeof wall[0], cmpd);
        printf("set=%s builder=%s view=%s renders=%d cpu_median_s=%.4f cpu_min_s=%.4f cpu_max_s=%.4f wall_median_s=%.4f "
               "nodes_visited=%llu leaves_visited=%llu gaussians=%llu samples=%llu\n",
               set, b ? b : "default", vi ? "close" : "far", renders, cpu[renders / 2], cpu[0], cpu[renders - 1],
               wall[renders / 2], (unsigned long long)st.nodes, (unsigned long long)st.leaves,
               (unsigned long long)st.kernel_evals, (unsigned long long)st.samples);
        fflush(stdout);
    }
    free(rgba);
    lc_tf_destroy(tf);
    lc_volume_destroy(vol);
    lc_device_destroy(dev);
    return 0;
}
