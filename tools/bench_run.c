/* lanecast bench: one case group = one scene, view, size, mode, method,
 * packet, shading, alpha_stop, sigma and thread count, over every target
 * asked for. First the check (checkasm's idea): each target's image against
 * the scalar target's at the check size with alpha_stop = 1, through the
 * tests' comparer (tests/imgcmp.c) at SPEC.md's tolerances (max 2/255,
 * PSNR >= 50 dB). Then timing: one warm-up round, then rounds in which every
 * target renders once (the order rotating each round) until the round or
 * time bound, so load drift falls on all targets alike. One JSON line per
 * target. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "bench_run.h"
#include "tests/imgcmp.h"

static int cmpd(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Quantile q of sorted v[0..n-1], linear between neighbours. */
static double quantile(const double *v, int n, double q)
{
    double p = q * (n - 1);
    int i = (int)p;
    return i + 1 < n ? v[i] + (p - i) * (v[i + 1] - v[i]) : v[n - 1];
}

static void jnum(FILE *f, const char *key, double v)
{
    if (isfinite(v)) fprintf(f, ", \"%s\": %.6g", key, v);
    else fprintf(f, ", \"%s\": null", key);
}

typedef struct target_result {
    double t[BENCH_MAX_ROUNDS];
    double cpu[BENCH_MAX_ROUNDS]; /* CPU seconds of the process per render (every thread) */
    int n;
    lc_render_stats st;
    int check_done, check_pass, render_failed;
    imgcmp_result cmp;
    char error[256];
} target_result;

static void check_targets(const bench_group *g, lc_render_desc d, target_result *res)
{
    int cw = g->width < g->check_size ? g->width : g->check_size;
    int ch = g->height < g->check_size ? g->height : g->check_size;
    size_t n = (size_t)cw * (size_t)ch * 4;
    float *ref = malloc(sizeof(float) * n), *img = malloc(sizeof(float) * n);
    d.width = cw, d.height = ch, d.alpha_stop = 1.0f;
    if (!ref || !img || lc_render(g->scalar_dev, &d, ref, NULL) != LC_OK) {
        for (int i = 0; i < g->ntargets; i++)
            snprintf(res[i].error, sizeof res[i].error, "check: scalar reference failed: %s",
                     ref && img ? lc_last_error() : "out of memory");
        free(ref), free(img);
        return;
    }
    for (int i = 0; i < g->ntargets; i++) {
        if (lc_render(g->devs[i], &d, img, NULL) != LC_OK) {
            snprintf(res[i].error, sizeof res[i].error, "check render: %s", lc_last_error());
            res[i].render_failed = 1;
            continue;
        }
        /* the self-test of the check (tests/test_bench_cli.sh): a target named
           in LANECAST_BENCH_BREAK gets 3/255 added to one pixel, which must fail */
        const char *brk = getenv("LANECAST_BENCH_BREAK");
        if (brk && !strcmp(brk, lc_target_name(g->targets[i]))) img[4 * (cw * (ch / 2) + cw / 2)] += 3.0f / 255.0f;
        imgcmp_stats(img, ref, cw, ch, IMGCMP_MAX_DIFF_255, &res[i].cmp); /* ndiff: pixels over 2/255 */
        res[i].check_done = 1;
        res[i].check_pass = res[i].cmp.nonfinite == 0 && res[i].cmp.max_diff_255 <= IMGCMP_MAX_DIFF_255 &&
                            res[i].cmp.psnr_db >= IMGCMP_MIN_PSNR_DB;
    }
    free(ref), free(img);
}

static void time_targets(const bench_group *g, const lc_render_desc *d, target_result *res)
{
    size_t n = (size_t)g->width * (size_t)g->height * 4;
    float *img = malloc(sizeof(float) * n);
    if (!img) {
        for (int i = 0; i < g->ntargets; i++) snprintf(res[i].error, sizeof res[i].error, "out of memory for the image");
        return;
    }
    double start = 0;
    for (int r = -g->warmup; r < g->max_rounds; r++) {
        if (r == 0) start = bench_now();
        if (r >= g->min_rounds && bench_now() - start > g->seconds) break;
        for (int k = 0; k < g->ntargets; k++) {
            int i = (k + (r < 0 ? 0 : r)) % g->ntargets; /* rotate the order each round */
            if (res[i].render_failed) continue;
            lc_render_stats st;
            double c0 = bench_cpu_now();
            if (lc_render(g->devs[i], d, img, &st) != LC_OK) {
                snprintf(res[i].error, sizeof res[i].error, "render: %s", lc_last_error());
                res[i].render_failed = 1;
                continue;
            }
            if (r >= 0) res[i].cpu[res[i].n] = bench_cpu_now() - c0, res[i].t[res[i].n++] = st.seconds, res[i].st = st;
        }
    }
    free(img);
}

static void print_record(const bench_group *g, int i, const target_result *res, double scalar_median)
{
    FILE *f = g->out;
    const target_result *r = &res[i];
    const bench_scene *sc = g->scene;
    lc_target t = g->targets[i];
    fprintf(f, "{\"record\": \"case\"");
    if (g->study[0]) fprintf(f, ", \"study\": \"%s\"", g->study);
    fprintf(f, ", \"scene\": ");
    bench_json_str(f, sc->name);
    fprintf(f, ", \"kind\": \"%s\", \"source\": ", lc_kind_name(sc->kind));
    bench_json_str(f, sc->source);
    fprintf(f, ", \"count\": %zu, \"view\": \"%s\", \"width\": %d, \"height\": %d, \"mode\": \"%s\", \"method\": \"%s\", "
               "\"packet\": %d, \"shading\": \"%s\", \"threads\": %d, \"target\": \"%s\", \"lanes\": %d",
            sc->count, g->view, g->width, g->height, g->mode_name, g->method_name, g->packet, g->shading_name, g->threads,
            lc_target_name(t), lc_target_lanes(t));
    jnum(f, "alpha_stop", g->alpha_stop > 0 ? g->alpha_stop : 0.97);
    if (sc->kind == LC_KIND_PARTICLES) jnum(f, "sigma", g->sigma > 0 ? g->sigma : 2.0);
    fprintf(f, ", \"warmup\": %d, \"rounds\": %d", g->warmup, r->n);
    jnum(f, "build_s", sc->build_seconds);
    jnum(f, "gen_s", sc->gen_seconds);
    jnum(f, "build_cpu_s", sc->build_cpu_s);
    /* build_peak_trimmed: the peak was taken after malloc_trim (bench_scenes.c), so no build reuses
       freed heap unseen */
    fprintf(f, ", \"bvh_bytes\": %zu, \"data_bytes\": %zu, \"build_peak_kb\": %ld, \"build_peak_trimmed\": true",
            sc->bvh_bytes, sc->data_bytes, sc->build_peak_kb);
    if (r->n > 0) {
        double s[BENCH_MAX_ROUNDS];
        memcpy(s, r->t, sizeof(double) * (size_t)r->n);
        qsort(s, (size_t)r->n, sizeof s[0], cmpd);
        double med = quantile(s, r->n, 0.5), secs = med > 0 ? med : 1e-9;
        const lc_render_stats *st = &r->st;
        jnum(f, "median_s", med);
        memcpy(s, r->cpu, sizeof(double) * (size_t)r->n);
        qsort(s, (size_t)r->n, sizeof s[0], cmpd);
        jnum(f, "cpu_median_s", quantile(s, r->n, 0.5)); /* not counting time spent waiting for a core */
        memcpy(s, r->t, sizeof(double) * (size_t)r->n);
        qsort(s, (size_t)r->n, sizeof s[0], cmpd);
        jnum(f, "min_s", s[0]);
        jnum(f, "max_s", s[r->n - 1]);
        jnum(f, "q1_s", quantile(s, r->n, 0.25));
        jnum(f, "q3_s", quantile(s, r->n, 0.75));
        jnum(f, "fps", 1.0 / secs);
        fprintf(f, ", \"rays\": %llu, \"samples\": %llu, \"kernel_evals\": %llu, \"nodes\": %llu, \"leaves\": %llu, "
                   "\"passes\": %llu",
                (unsigned long long)st->rays, (unsigned long long)st->samples, (unsigned long long)st->kernel_evals,
                (unsigned long long)st->nodes, (unsigned long long)st->leaves, (unsigned long long)st->passes);
        jnum(f, "ns_per_ray", st->rays ? 1e9 * secs / (double)st->rays : NAN);
        jnum(f, "samples_per_s", (double)st->samples / secs);
        double evals_s = (double)st->kernel_evals / secs;
        /* Gaussians for particles and RBF sets, voxel reconstructions for grids */
        jnum(f, sc->kind == LC_KIND_GRID ? "voxel_evals_per_s" : "gauss_per_s", evals_s);
        if (scalar_median > 0) jnum(f, "speedup_vs_scalar", scalar_median / secs);
        int cores = g->threads < g->cpus ? g->threads : g->cpus;
        const bench_roof *rf = g->roof;
        if (rf && rf->measured) {
            if (sc->kind == LC_KIND_GRID) {
                /* the grid-stream kernel: fetch and trilinear interpolation
                   along rays through the quad copy, the faster volume size */
                double roof = rf->grid_cache[t] > rf->grid_mem[t] ? rf->grid_cache[t] : rf->grid_mem[t];
                jnum(f, "roof_samples_per_s", cores * roof);
                jnum(f, "fraction_of_peak", roof > 0 ? (double)st->samples / secs / (cores * roof) : NAN);
                fprintf(f, ", \"peak\": \"trilinear samples streamed along rays\"");
            } else {
                jnum(f, "roof_gauss_per_s", cores * rf->gauss_per_s[t]);
                jnum(f, "fraction_of_peak", rf->gauss_per_s[t] > 0 ? evals_s / (cores * rf->gauss_per_s[t]) : NAN);
                fprintf(f, ", \"peak\": \"gaussian micro-kernel\"");
            }
            jnum(f, "roof_fma_gflops", cores * rf->fma_gflops[t]);
        }
    }
    fprintf(f, ", \"check\": ");
    if (r->check_done) {
        fprintf(f, "{\"ref\": \"scalar\", \"alpha_stop\": 1, \"size\": %d, \"pass\": %s, \"nonfinite\": %ld",
                g->width < g->check_size ? g->width : g->check_size, r->check_pass ? "true" : "false", r->cmp.nonfinite);
        jnum(f, "max_diff_255", r->cmp.max_diff_255);
        jnum(f, "psnr_db", r->cmp.psnr_db);
        fprintf(f, ", \"worst_pixel\": [%d, %d, %d], \"pixels_over_2\": %ld}", r->cmp.worst_x, r->cmp.worst_y,
                r->cmp.worst_channel, r->cmp.ndiff);
    } else fprintf(f, "null");
    if (r->error[0]) {
        fprintf(f, ", \"error\": ");
        bench_json_str(f, r->error);
    }
    fprintf(f, ", \"rss_peak_kb\": %ld, \"rss_now_kb\": %ld", bench_rss_peak_kb(), bench_rss_now_kb());
    jnum(f, "loadavg", bench_loadavg());
    fprintf(f, ", %s}\n", g->machine);
    fflush(f);
}

int bench_run_group(const bench_group *g, const lc_render_desc *d)
{
    target_result *res = calloc((size_t)g->ntargets, sizeof *res);
    if (!res) return -1;
    if (g->check_size > 0) check_targets(g, *d, res);
    time_targets(g, d, res);
    double scalar_median = 0;
    for (int i = 0; i < g->ntargets; i++)
        if (g->targets[i] == LC_TARGET_SCALAR && res[i].n > 0) {
            double s[BENCH_MAX_ROUNDS];
            memcpy(s, res[i].t, sizeof(double) * (size_t)res[i].n);
            qsort(s, (size_t)res[i].n, sizeof s[0], cmpd);
            scalar_median = quantile(s, res[i].n, 0.5);
        }
    int bad = 0;
    for (int i = 0; i < g->ntargets; i++) {
        print_record(g, i, res, scalar_median);
        if ((res[i].check_done && !res[i].check_pass) || res[i].error[0]) {
            bad++;
            fprintf(stderr, "lanecast bench: %s %s %s %s %s threads=%d target=%s: %s\n", g->scene->name, g->view,
                    g->mode_name, g->method_name, g->shading_name, g->threads, lc_target_name(g->targets[i]),
                    res[i].error[0] ? res[i].error : "image differs from scalar beyond SPEC.md tolerances");
        }
    }
    free(res);
    return bad;
}
