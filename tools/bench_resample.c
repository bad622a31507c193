/* lanecast bench --resample N,...: particles through deposited grids
 * (issue 28, K14's comparison): per scene, view and target, the exact
 * particle frame, then for each N the deposition to N^3 nodes over the set's
 * bounds (lc_particles_resample), its memory, the grid renderer's frame of
 * it with the same camera, TF and range, and the PSNR of that frame against
 * the exact one (tests/imgcmp.c over premultiplied RGBA). Medians of timed
 * rounds; one "resample" record per N. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "../tests/imgcmp.h"
#include "bench_run.h"

/* Renders d on dev for the group's rounds: the median wall time; the last image in rgba. */
static double time_frames(const bench_group *g, lc_device *dev, const lc_render_desc *d, float *rgba, double *cpu)
{
    double t[BENCH_MAX_ROUNDS], c[BENCH_MAX_ROUNDS], start = bench_now();
    int n = 0;
    for (int w = 0; w < g->warmup; w++)
        if (lc_render(dev, d, rgba, NULL) != LC_OK) return NAN;
    while (n < g->max_rounds && (n < g->min_rounds || bench_now() - start < g->seconds)) {
        double c0 = bench_cpu_now();
        lc_render_stats st;
        if (lc_render(dev, d, rgba, &st) != LC_OK) return NAN;
        c[n] = bench_cpu_now() - c0, t[n++] = st.seconds;
    }
    *cpu = bench_median(c, n);
    return bench_median(t, n);
}

static void record_head(const bench_group *g, lc_target t, int n)
{
    FILE *f = g->out;
    fprintf(f, "{\"record\": \"resample\", \"scene\": ");
    bench_json_str(f, g->scene->name);
    fprintf(f, ", \"source\": ");
    bench_json_str(f, g->scene->source);
    fprintf(f, ", \"count\": %zu, \"view\": \"%s\", \"width\": %d, \"height\": %d, \"mode\": \"%s\", \"shading\": \"%s\", "
               "\"threads\": %d, \"target\": \"%s\", \"grid\": %d",
            g->scene->count, g->view, g->width, g->height, g->mode_name, g->shading_name, g->threads,
            lc_target_name(t), n);
}

/* One target: the exact frame, then every N. Returns the failures. */
static int one_target(const bench_group *g, int ti, const lc_render_desc *d, const int *sizes, int nsizes)
{
    lc_device *dev = g->devs[ti];
    size_t px = (size_t)g->width * (size_t)g->height * 4;
    float *exact = malloc(sizeof(float) * px), *img = malloc(sizeof(float) * px);
    int bad = 0;
    double ecpu = NAN, exact_s = exact && img ? time_frames(g, dev, d, exact, &ecpu) : NAN;
    if (!isfinite(exact_s)) {
        fprintf(stderr, "lanecast bench: %s: exact frame: %s\n", g->scene->name, lc_last_error());
        free(exact), free(img);
        return 1;
    }
    lc_tf_field f0 = {0};
    int tf_range = d->tf && lc_tf_get_field(d->tf, 0, &f0) == LC_OK && f0.has_range;
    for (int k = 0; k < nsizes; k++) {
        int n = sizes[k];
        lc_resample_desc rd = {.size = {n, n, n}, .field = -1};
        lc_resample_info info;
        lc_status s = lc_particles_resample(dev, g->scene->vol, &rd, NULL, &info);
        size_t nodes = (size_t)n * n * n;
        float *values = s == LC_OK ? malloc(sizeof(float) * nodes) : NULL;
        double t[BENCH_MAX_ROUNDS], c[BENCH_MAX_ROUNDS], start = bench_now();
        int r = 0;
        long rss0 = bench_rss_now_kb();
        while (values && s == LC_OK && r < g->max_rounds && (r < g->min_rounds || bench_now() - start < g->seconds)) {
            double c0 = bench_cpu_now();
            s = lc_particles_resample(dev, g->scene->vol, &rd, values, &info);
            c[r] = bench_cpu_now() - c0, t[r++] = info.seconds;
        }
        lc_volume *grid = NULL;
        double gcpu = NAN, grid_s = NAN;
        imgcmp_result cmp = {0};
        if (s == LC_OK && values) {
            lc_grid_desc gd = {.size = {n, n, n}, .type = LC_VALUE_FLOAT32, .data = values, .spacing = info.spacing,
                               .origin = info.origin, .borrow = 1, .layout = LC_LAYOUT_LINEAR};
            s = lc_grid_create(dev, &gd, &grid);
        }
        if (s == LC_OK && grid) {
            lc_render_desc gdsc = *d;
            gdsc.volume = grid, gdsc.method = LC_METHOD_DEFAULT;
            if (!tf_range && gdsc.range[0] == 0.0f && gdsc.range[1] == 0.0f)
                gdsc.range[0] = g->scene->info.range[0], gdsc.range[1] = g->scene->info.range[1];
            grid_s = time_frames(g, dev, &gdsc, img, &gcpu);
            imgcmp_stats(img, exact, g->width, g->height, IMGCMP_MAX_DIFF_255, &cmp);
        }
        record_head(g, g->targets[ti], n);
        FILE *f = g->out;
        if (s != LC_OK || !values || !isfinite(grid_s)) {
            fprintf(f, ", \"error\": ");
            bench_json_str(f, values ? lc_last_error() : "out of memory for the values");
            bad++;
        } else {
            double dcpu = bench_median(c, r);
            bench_jnum(f, "deposit_median_s", bench_median(t, r));
            bench_jnum(f, "deposit_cpu_median_s", dcpu);
            fprintf(f, ", \"deposit_rounds\": %d, \"deposit_bytes\": %llu, \"entries\": %llu, \"evaluations\": %llu",
                    r, (unsigned long long)info.bytes, (unsigned long long)info.entries,
                    (unsigned long long)info.evaluations);
            bench_jnum(f, "grid_frame_median_s", grid_s);
            bench_jnum(f, "grid_frame_cpu_median_s", gcpu);
            bench_jnum(f, "exact_frame_median_s", exact_s);
            bench_jnum(f, "exact_frame_cpu_median_s", ecpu);
            bench_jnum(f, "psnr_db", cmp.psnr_db);
            bench_jnum(f, "max_diff_255", cmp.max_diff_255);
            fprintf(f, ", \"rss_before_kb\": %ld", rss0);
        }
        fprintf(f, ", \"rss_peak_kb\": %ld", bench_rss_peak_kb());
        bench_jnum(f, "loadavg", bench_loadavg());
        fprintf(f, ", %s}\n", g->machine);
        fflush(f);
        lc_volume_destroy(grid);
        free(values);
    }
    free(exact), free(img);
    return bad;
}

int bench_resample_group(const bench_group *g, const lc_render_desc *d, const int *sizes, int nsizes)
{
    if (g->scene->kind != LC_KIND_PARTICLES) {
        fprintf(stderr, "lanecast bench: --resample: %s is not a particle set (skipped)\n", g->scene->name);
        return 0;
    }
    int bad = 0;
    for (int i = 0; i < g->ntargets; i++) bad += one_target(g, i, d, sizes, nsizes);
    return bad;
}
