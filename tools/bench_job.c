/* lanecast bench --jobs: what an interactive user waits for, per case and
 * target (issue 24): the full frame (lc_render), the navigation frame
 * (pixel_scale 2, the viewer's default while the camera moves), a job's
 * preview pass and its refined image, and the cancel latency (from
 * lc_job_cancel to lc_job_wait returning) at random points of a frame. One
 * JSON line per target, record "job". */
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "bench_run.h"

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double quantile(double *v, int n, double q)
{
    if (n <= 0) return 0.0;
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    int i = (int)(q * (n - 1) + 0.5);
    return v[i];
}

static void sleep_s(double s)
{
    struct timespec ts = {(time_t)s, (long)((s - (double)(time_t)s) * 1e9)};
    nanosleep(&ts, NULL);
}

typedef struct pass_times {
    double t0, first;
} pass_times;

static void on_pass(void *user, const lc_job_pass *p)
{
    pass_times *t = user;
    if (p->pass == 1) t->first = bench_now() - t->t0;
}

/* Median seconds of `reps` lc_render calls of d; -1 on failure. */
static double render_median(lc_device *dev, const lc_render_desc *d, float *img, int reps)
{
    double t[16];
    for (int r = 0; r < reps; r++) {
        double a = bench_now();
        if (lc_render(dev, d, img, NULL) != LC_OK) return -1.0;
        t[r] = bench_now() - a;
    }
    return quantile(t, reps, 0.5);
}

/* Job times: preview pass and refined image (medians of reps). */
static int job_times(lc_device *dev, const lc_render_desc *d, float *img, int reps, double *preview, double *refined)
{
    double p[16], f[16];
    for (int r = 0; r < reps; r++) {
        pass_times pt = {bench_now(), 0.0};
        lc_job *job = NULL;
        if (lc_render_begin(dev, d, &(lc_job_desc){.on_pass = on_pass, .user = &pt}, img, &job) != LC_OK) return -1;
        lc_status s = lc_job_wait(job, -1.0, NULL);
        f[r] = bench_now() - pt.t0;
        p[r] = pt.first;
        lc_job_destroy(job);
        if (s != LC_OK) return -1;
    }
    *preview = quantile(p, reps, 0.5);
    *refined = quantile(f, reps, 0.5);
    return 0;
}

int bench_job_group(const bench_group *g, const lc_render_desc *d0, int trials)
{
    int bad = 0;
    size_t n = (size_t)g->width * (size_t)g->height * 4;
    float *img = malloc(sizeof(float) * n);
    double *lat = malloc(sizeof(double) * (size_t)(trials > 0 ? trials : 1));
    if (!img || !lat) {
        free(img), free(lat);
        return g->ntargets;
    }
    srand(12345);
    for (int i = 0; i < g->ntargets; i++) {
        lc_device *dev = g->devs[i];
        lc_render_desc d = *d0, nav = *d0;
        nav.pixel_scale = 2;
        lc_render(dev, &d, img, NULL); /* warm the volume's per-frame caches */
        double full = render_median(dev, &d, img, 3), navs = render_median(dev, &nav, img, 5);
        double preview = 0, refined = 0;
        if (full < 0 || navs < 0 || job_times(dev, &d, img, 3, &preview, &refined)) {
            fprintf(stderr, "lanecast bench: %s %s: %s\n", g->scene->name, lc_target_name(g->targets[i]), lc_last_error());
            bad++;
            continue;
        }
        int nc = 0, finished = 0;
        for (int t = 0; t < trials; t++) {
            lc_job *job = NULL;
            if (lc_render_begin(dev, &d, NULL, img, &job) != LC_OK) {
                bad++;
                break;
            }
            sleep_s(full * (double)rand() / RAND_MAX);
            double a = bench_now();
            lc_job_cancel(job);
            lc_status s = lc_job_wait(job, -1.0, NULL);
            double b = bench_now();
            lc_job_destroy(job);
            if (s == LC_CANCELLED) lat[nc++] = b - a;
            else finished++;
        }
        double med = quantile(lat, nc, 0.5), p95 = quantile(lat, nc, 0.95), worst = nc ? lat[nc - 1] : 0.0;
        FILE *f = g->out;
        fprintf(f, "{\"record\": \"job\", \"scene\": ");
        bench_json_str(f, g->scene->name);
        fprintf(f, ", \"view\": \"%s\", \"width\": %d, \"height\": %d, \"mode\": \"%s\", \"method\": \"%s\", "
                   "\"shading\": \"%s\", \"target\": \"%s\", \"threads\": %d, \"full_s\": %.6g, \"nav_s\": %.6g, "
                   "\"preview_s\": %.6g, \"refined_s\": %.6g, \"cancels\": %d, \"finished_before_cancel\": %d, "
                   "\"cancel_median_ms\": %.4g, \"cancel_p95_ms\": %.4g, \"cancel_worst_ms\": %.4g, \"loadavg\": %.2f, %s}\n",
                g->view, g->width, g->height, g->mode_name, g->method_name, g->shading_name,
                lc_target_name(g->targets[i]), g->threads, full, navs, preview, refined, nc, finished, 1e3 * med,
                1e3 * p95, 1e3 * worst, bench_loadavg(), g->machine);
        fflush(f);
        fprintf(stderr,
                "lanecast bench:   %s: full %.1f ms, navigation %.1f ms, preview %.1f ms, refined %.1f ms; cancel "
                "median %.2f ms, worst %.2f ms of %d\n",
                lc_target_name(g->targets[i]), 1e3 * full, 1e3 * navs, 1e3 * preview, 1e3 * refined, 1e3 * med,
                1e3 * worst, nc);
    }
    free(img), free(lat);
    return bad;
}
