/* lanecast bench --profile: where a grid frame's time goes (docs/bench/grid.md
 * "Stage profile"). The grid kernels are compiled again (tools/grid_prof.c,
 * tools/meson.build prof_masks) for avx2 and avx512 when built (else the
 * widest target), once per cumulative set of stages replaced by stand-ins
 * (kernels/grid_common.h GRID_PROF): variant i replaces one more stage than
 * variant i - 1, and every variant runs without early termination so all take
 * the same samples. The device's kernel table is swapped for each variant's
 * (host/internal.h: the benchmark's one look inside the library); the stage's
 * time is the median CPU time of the variant before its removal minus the one
 * after. Variants run round-robin so load changes hit them alike; CPU time
 * of the process, which moves much less with a shared machine's load than
 * wall time. */
#include <stdlib.h>
#include <string.h>
#include "bench_run.h"
#include "host/internal.h"

#define NPROF 7
#define PROF_NAME2(t, i) lc_kkind_grid_prof_##t##_##i
#define PROF_NAME(t, i) PROF_NAME2(t, i)
#define PROF_DECLS(t)                                                                                            \
    extern const lc_kkind PROF_NAME(t, 0), PROF_NAME(t, 1), PROF_NAME(t, 2), PROF_NAME(t, 3), PROF_NAME(t, 4), \
        PROF_NAME(t, 5), PROF_NAME(t, 6);
#define PROF_TABLE(t)                                                                                            \
    {&PROF_NAME(t, 0), &PROF_NAME(t, 1), &PROF_NAME(t, 2), &PROF_NAME(t, 3), &PROF_NAME(t, 4), &PROF_NAME(t, 5), \
     &PROF_NAME(t, 6)}
PROF_DECLS(LC_PROF_T0)
#ifdef LC_PROF_T1
PROF_DECLS(LC_PROF_T1)
#endif
static const struct {
    const char *target;
    const lc_kkind *kind[NPROF];
} prof_sets[] = {
    {LC_PROF_T0_NAME, PROF_TABLE(LC_PROF_T0)},
#ifdef LC_PROF_T1
    {LC_PROF_T1_NAME, PROF_TABLE(LC_PROF_T1)},
#endif
};
#define NPROF_SETS (int)(sizeof prof_sets / sizeof prof_sets[0])
/* the stage removed between variant i - 1 and i (variant 0: every stage, no early termination) */
static const char *const prof_stage[NPROF] = {"total", "fetch", "interpolation", "classification", "shading",
                                              "blending", "sample_loop"};

static int cmpd(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmpd);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

const char *bench_profile_targets(void)
{
    return NPROF_SETS > 1 ? LC_PROF_T0_NAME " " LC_PROF_T1_NAME : LC_PROF_T0_NAME;
}

/* One target: the shipped kernel (the case's alpha_stop) for reference, then
 * the variants. Returns 0, or 1 when a render failed or the variants took
 * other samples than the full one (the profile is void then). */
static int profile_one(const bench_group *g, lc_device *dev, const lc_kkind *const *kind, const lc_render_desc *d0)
{
    int n = g->max_rounds < 64 ? g->max_rounds : 64;
    float *rgba = malloc(sizeof(float) * 4 * (size_t)g->width * (size_t)g->height);
    double shipped[64], ts[NPROF][64];
    uint64_t samples[NPROF] = {0}, shipped_samples = 0;
    lc_render_stats st;
    lc_render_desc d = *d0;
    const lc_ktable *orig = dev->kt;
    lc_ktable kt = *orig;
    int ok = rgba && lc_render(dev, &d, rgba, &st) == LC_OK; /* warm-up */
    for (int r = 0; ok && r < n; r++) {
        double a = bench_cpu_now();
        ok = lc_render(dev, &d, rgba, &st) == LC_OK;
        shipped[r] = bench_cpu_now() - a, shipped_samples = st.samples;
    }
    d.alpha_stop = 1.0f;
    for (int r = -1; ok && r < n; r++) /* r = -1: a warm-up round */
        for (int v = 0; ok && v < NPROF; v++) {
            kt.kind[LC_KKIND_GRID] = kind[v];
            dev->kt = &kt;
            double a = bench_cpu_now();
            ok = lc_render(dev, &d, rgba, &st) == LC_OK;
            if (r >= 0) ts[v][r] = bench_cpu_now() - a;
            samples[v] = st.samples;
            dev->kt = orig;
        }
    free(rgba);
    if (!ok) {
        fprintf(stderr, "lanecast bench: --profile %s: %s\n", g->scene->name, lc_last_error());
        return 1;
    }
    int same = 1; /* every variant that still samples takes the same samples: like is compared with like */
    for (int v = 1; v < NPROF - 1; v++) same &= samples[v] == samples[0];
    FILE *f = g->out;
    double med[NPROF], lo[NPROF], hi[NPROF];
    for (int v = 0; v < NPROF; v++) med[v] = median(ts[v], n), lo[v] = ts[v][0], hi[v] = ts[v][n - 1];
    fprintf(f, "{\"record\": \"profile\", \"scene\": ");
    bench_json_str(f, g->scene->name);
    fprintf(f, ", \"kind\": \"grid\", \"view\": \"%s\", \"width\": %d, \"height\": %d, \"method\": \"%s\", "
               "\"shading\": \"%s\", \"threads\": %d, \"target\": \"%s\", \"rounds\": %d, \"shipped_cpu_s\": %.6g, "
               "\"shipped_samples\": %llu, \"nostop_samples\": %llu, \"same_samples\": %s, \"variant_cpu_s\": [",
            g->view, g->width, g->height, g->method_name, g->shading_name, g->threads, lc_target_name(dev->target), n,
            median(shipped, n), (unsigned long long)shipped_samples, (unsigned long long)samples[0],
            same ? "true" : "false");
    for (int v = 0; v < NPROF; v++) fprintf(f, "%s[%.6g, %.6g, %.6g]", v ? ", " : "", med[v], lo[v], hi[v]);
    fprintf(f, "], \"stage_cpu_s\": {");
    for (int v = 1; v < NPROF; v++) fprintf(f, "%s\"%s\": %.6g", v > 1 ? ", " : "", prof_stage[v], med[v - 1] - med[v]);
    fprintf(f, ", \"rest\": %.6g}, \"loadavg\": %.2f, %s}\n", med[NPROF - 1], bench_loadavg(), g->machine);
    fflush(f);
    if (!same) fprintf(stderr, "lanecast bench: --profile %s: the variants took different samples\n", g->scene->name);
    return !same;
}

int bench_profile_group(const bench_group *g, const lc_render_desc *d)
{
    if (g->scene->kind != LC_KIND_GRID || d->mode != LC_MODE_DVR) {
        fprintf(stderr, "lanecast bench: note: --profile measures grids' dvr frames: %s %s skipped\n", g->scene->name,
                d->mode == LC_MODE_DVR ? "(not a grid)" : g->mode_name);
        return 0;
    }
    int bad = 0, done = 0;
    for (int i = 0; i < g->ntargets; i++)
        for (int k = 0; k < NPROF_SETS; k++) {
            lc_target pt;
            if (lc_target_from_name(prof_sets[k].target, &pt) == LC_OK && g->targets[i] == pt)
                bad += profile_one(g, g->devs[i], prof_sets[k].kind, d), done++;
        }
    if (!done)
        fprintf(stderr, "lanecast bench: note: --profile: the variants are built for %s only: none of those asked for\n",
                bench_profile_targets());
    return bad;
}
