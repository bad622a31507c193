/* Render jobs (lc_render_begin, lc_job_*; issue 24): on every target this
 * CPU runs, for particles, a grid and an RBF set, in each mode with the eye
 * outside and inside the data, a job's finished image is lc_render's to the
 * byte and its preview pass is every s-th pixel of the full image, filled;
 * navigation quality is one pass equal to lc_render's with the same desc;
 * cancelling at random points (200 trials: from the progress callback at a
 * random fraction, and after a random delay) returns LC_CANCELLED (or
 * LC_OK with the exact image when the job had ended) and leaves the device
 * rendering exactly; desc->cancel stops lc_render; overlapping jobs each
 * give their own image; a job destroyed while running or queued leaves
 * nothing running; bad arguments fail with messages. Also run under
 * ThreadSanitizer by scripts/tsan.sh.
 * usage: test_render_job [TRIALS] */
#define _POSIX_C_SOURCE 200809L
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "check.h"
#include "scenes3.h"

#define W 72
#define H 56
#define BW 192 /* the cancel trials' image */
#define BH 160

static size_t img_bytes(int w, int h) { return sizeof(float) * 4 * (size_t)w * (size_t)h; }

static int usable(lc_target t) { return lc_target_compiled(t) && lc_target_supported(t); }

static void sleep_us(long us)
{
    struct timespec ts = {us / 1000000, (us % 1000000) * 1000};
    nanosleep(&ts, NULL);
}

/* What the pass callback records: each pass's scale and a copy of the image. */
typedef struct passes {
    int n, scale[4], final[4];
    float *img[4];
    int w, h;
} passes;

static void on_pass(void *user, const lc_job_pass *p)
{
    passes *r = user;
    if (r->n >= 4) return;
    r->scale[r->n] = p->scale;
    r->final[r->n] = p->final;
    r->img[r->n] = malloc(img_bytes(p->width, p->height));
    if (r->img[r->n]) memcpy(r->img[r->n], p->rgba, img_bytes(p->width, p->height));
    r->n++;
}

static void passes_free(passes *r)
{
    for (int i = 0; i < r->n; i++) free(r->img[i]);
    memset(r, 0, sizeof *r);
}

/* The modes and eyes each scene renders in. */
static lc_render_desc scene_desc(const scenes3 *s, int k, int mode, int inside, int w, int h)
{
    lc_render_desc d = scenes3_desc(s, k, w, h, 0);
    d.mode = (lc_mode)mode;
    if (mode == LC_MODE_ISO) d.iso = k == 1 ? 0.6f : 0.35f, d.field = 0;
    if (mode == LC_MODE_SLICE) {
        d.nplanes = 1;
        d.planes[0] = (lc_plane){{0.1f, 0.0f, 0.2f}, {0.3f, 0.2f, 1.0f}};
    }
    if (inside) d.camera = (lc_camera){LC_PERSPECTIVE, {0.1f, 0.2f, 0.3f}, {1.0f, 0.1f, -0.4f}, {0, 1, 0}, 60.0f, 0.0f};
    return d;
}

/* Largest difference of the preview pass from the full image at the block
 * origins (s i, s j), the number of block pixels that differ from their
 * origin (filling), and the fraction of origins within 0.02. */
static void preview_check(const float *pre, const float *full, int w, int h, int s, float *within, long *unfilled)
{
    long n = 0, near = 0;
    *unfilled = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const float *o = pre + ((size_t)(y / s * s) * w + (size_t)(x / s * s)) * 4;
            const float *p = pre + ((size_t)y * w + x) * 4;
            if (memcmp(o, p, sizeof(float) * 4)) (*unfilled)++;
            if (x % s || y % s) continue;
            const float *f = full + ((size_t)y * w + x) * 4;
            float d = 0.0f;
            for (int c = 0; c < 4; c++) d = fmaxf(d, fabsf(p[c] - f[c]));
            n++;
            near += d <= 0.02f;
        }
    *within = n ? (float)near / (float)n : 0.0f;
}

/* Job == lc_render, preview == full image's pixels, navigation == lc_render. */
static void identity(lc_target t, const scenes3 *s, float *ref, float *img)
{
    const char *tn = lc_target_name(t);
    static const char *mname[] = {"dvr", "mip", "iso", "slice"};
    lc_device *dev = NULL;
    if (lc_device_create(&(lc_device_desc){.target = t, .threads = 2}, &dev) != LC_OK) {
        CHECK(0, "%s: device: %s", tn, lc_last_error());
        return;
    }
    int same = 0, runs = 0, shape_ok = 0, preview_ok = 0, nav_ok = 0;
    char bad[200] = "";
    for (int k = 0; k < 3; k++)
        for (int mode = 0; mode < LC_MODE_COUNT; mode++)
            for (int inside = 0; inside < 2; inside++) {
                lc_render_desc d = scene_desc(s, k, mode, inside, W, H);
                runs++;
                if (lc_render(dev, &d, ref, NULL) != LC_OK) {
                    CHECK(0, "%s %s %s: lc_render: %s", tn, s->name[k], mname[mode], lc_last_error());
                    continue;
                }
                passes rec = {.w = W, .h = H};
                int scale = 2 << (runs % 3); /* 2, 4, 8 */
                lc_job *job = NULL;
                memset(img, 0xff, img_bytes(W, H)); /* NaNs: every pixel must be written */
                lc_status st = lc_render_begin(dev, &d, &(lc_job_desc){.preview_scale = scale, .on_pass = on_pass, .user = &rec},
                                               img, &job);
                if (st == LC_OK) st = lc_job_wait(job, -1.0, NULL);
                lc_job_destroy(job);
                if (st == LC_OK && !memcmp(img, ref, img_bytes(W, H))) same++;
                else if (!bad[0])
                    snprintf(bad, sizeof bad, "; first not: %s %s eye %s (%s)", s->name[k], mname[mode],
                             inside ? "inside" : "outside", lc_status_string(st));
                shape_ok += rec.n == 2 && rec.scale[0] == scale && rec.scale[1] == 1 && !rec.final[0] && rec.final[1] &&
                            rec.img[1] && !memcmp(rec.img[1], ref, img_bytes(W, H));
                if (rec.n == 2 && rec.img[0]) {
                    float within;
                    long unfilled;
                    preview_check(rec.img[0], ref, W, H, scale, &within, &unfilled);
                    preview_ok += unfilled == 0 && within >= 0.97f;
                    /* lc_render at that pixel scale is the same pass */
                    lc_render_desc dn = d;
                    dn.pixel_scale = scale;
                    preview_ok += lc_render(dev, &dn, ref, NULL) == LC_OK && !memcmp(ref, rec.img[0], img_bytes(W, H));
                }
                passes_free(&rec);
                /* navigation quality: one pass, lc_render's with the same desc */
                lc_render_desc dn = d;
                dn.pixel_scale = 3, dn.step_scale = 2.0f;
                job = NULL;
                st = lc_render(dev, &dn, ref, NULL);
                if (st == LC_OK) st = lc_render_begin(dev, &dn, &(lc_job_desc){.on_pass = on_pass, .user = &rec}, img, &job);
                if (st == LC_OK) st = lc_job_wait(job, -1.0, NULL);
                lc_job_destroy(job);
                nav_ok += st == LC_OK && rec.n == 1 && rec.scale[0] == 3 && rec.final[0] && !memcmp(img, ref, img_bytes(W, H));
                passes_free(&rec);
            }
    CHECK(same == runs, "%s: %d of %d jobs (3 kinds x 4 modes x eye outside/inside) equal lc_render byte for byte%s", tn,
          same, runs, bad);
    CHECK(shape_ok == runs, "%s: %d of %d jobs called on_pass for the preview (scale 2/4/8) then the final image", tn,
          shape_ok, runs);
    CHECK(preview_ok == 2 * runs,
          "%s: %d of %d previews fill their blocks, match the full image at (s i, s j) (97%% within 0.02) and equal "
          "lc_render at that pixel_scale",
          tn, preview_ok, 2 * runs);
    CHECK(nav_ok == runs, "%s: %d of %d navigation jobs (pixel_scale 3, step_scale 2) are one pass equal to lc_render",
          tn, nav_ok, runs);
    lc_device_destroy(dev);
}

typedef struct at_fraction {
    float at;
    lc_job **job;
    atomic_int armed;
} at_fraction;

static void cancel_at(void *user, float f)
{
    at_fraction *a = user;
    if (f >= a->at && atomic_load(&a->armed)) lc_job_cancel(*a->job);
}

static uint32_t rng = 99u;
static double urand(void)
{
    rng = rng * 1664525u + 1013904223u;
    return (double)(rng >> 8) / 16777216.0;
}

/* 200 cancels at random points of a frame; every 10th trial, and after the
 * last, the device renders the exact image again. */
static void cancels(const scenes3 *s, int trials, float *ref[3], float *img)
{
    lc_device *dev = NULL;
    if (lc_device_create(&(lc_device_desc){.threads = 2}, &dev) != LC_OK) {
        CHECK(0, "device: %s", lc_last_error());
        return;
    }
    double frame[3];
    for (int k = 0; k < 3; k++) {
        lc_render_desc d = scene_desc(s, k, LC_MODE_DVR, 0, BW, BH);
        lc_render_stats st;
        CHECK(lc_render(dev, &d, ref[k], &st) == LC_OK && scenes3_nontrivial(ref[k], BW, BH), "%s reference %dx%d: %.1f ms",
              s->name[k], BW, BH, 1e3 * st.seconds);
        frame[k] = st.seconds;
    }
    int cancelled = 0, finished_exact = 0, wrong = 0, after_ok = 0, after_runs = 0, by_fraction = 0;
    for (int i = 0; i < trials; i++) {
        int k = i % 3;
        lc_render_desc d = scene_desc(s, k, LC_MODE_DVR, 0, BW, BH);
        lc_job *job = NULL;
        at_fraction a = {(float)urand(), &job, 0};
        int frac = i % 2 == 0;
        if (frac) d.progress = cancel_at, d.progress_user = &a;
        lc_status st = lc_render_begin(dev, &d, NULL, img, &job);
        if (st != LC_OK) {
            wrong++;
            continue;
        }
        if (frac) atomic_store(&a.armed, 1);
        else sleep_us((long)(urand() * 1.2 * frame[k] * 1e6));
        if (!frac) lc_job_cancel(job);
        st = lc_job_wait(job, -1.0, NULL);
        lc_job_progress p;
        lc_job_get_progress(job, &p);
        lc_job_destroy(job);
        if (st == LC_CANCELLED && p.state == LC_JOB_CANCELLED) cancelled++, by_fraction += frac;
        else if (st == LC_OK && p.state == LC_JOB_DONE && !memcmp(img, ref[k], img_bytes(BW, BH))) finished_exact++;
        else wrong++;
        if (i % 10 == 9 || i == trials - 1) {
            lc_render_desc d2 = scene_desc(s, k, LC_MODE_DVR, 0, BW, BH);
            after_runs++;
            after_ok += lc_render(dev, &d2, img, NULL) == LC_OK && !memcmp(img, ref[k], img_bytes(BW, BH));
        }
    }
    CHECK(wrong == 0 && cancelled + finished_exact == trials,
          "%d cancels at random points: %d cancelled (%d from the progress callback), %d had finished with the exact "
          "image, %d wrong",
          trials, cancelled, by_fraction, finished_exact, wrong);
    /* a fraction drawn below 1 is reached before the last tile: those must all cancel (a few fractions may
       land past the preview while worker 0 sees only its own tiles, so at least 80%) */
    CHECK(by_fraction >= (trials / 2) * 8 / 10, "cancels from the progress callback took effect (%d of %d)", by_fraction,
          trials / 2);
    CHECK(after_ok == after_runs, "the device renders exactly after cancels (%d of %d)", after_ok, after_runs);
    lc_device_destroy(dev);
}

static int cancel_after(void *user)
{
    atomic_int *n = user;
    return atomic_fetch_add(n, 1) >= 5;
}

/* desc->cancel stops a synchronous lc_render. */
static void sync_cancel(const scenes3 *s, const float *ref, float *img)
{
    lc_device *dev = NULL;
    lc_device_create(&(lc_device_desc){.threads = 2}, &dev);
    lc_render_desc d = scene_desc(s, 0, LC_MODE_DVR, 0, BW, BH);
    atomic_int asked = 0;
    d.cancel = cancel_after, d.cancel_user = &asked;
    lc_status st = lc_render(dev, &d, img, NULL);
    CHECK(st == LC_CANCELLED && strstr(lc_last_error(), "cancel") && strstr(lc_device_last_error(dev), "cancel"),
          "desc->cancel stops lc_render: %s (%s), the device's message says so", lc_status_string(st), lc_last_error());
    d.cancel = NULL;
    CHECK(lc_render(dev, &d, img, NULL) == LC_OK && !memcmp(img, ref, img_bytes(BW, BH)),
          "the next lc_render on the device is exact");
    lc_device_destroy(dev);
}

/* Three jobs begun at once on one device (the first cancelled), each with
 * its own camera; a job destroyed while running and one while queued. */
static void overlaps(const scenes3 *s, float *ref[3])
{
    lc_device *dev = NULL;
    lc_device_create(&(lc_device_desc){.threads = 2}, &dev);
    float *out[3], *want[3];
    lc_job *job[3] = {NULL, NULL, NULL};
    int ok = 1;
    for (int i = 0; i < 3; i++) {
        out[i] = malloc(img_bytes(BW, BH));
        want[i] = malloc(img_bytes(BW, BH));
        lc_render_desc d = scene_desc(s, i, LC_MODE_DVR, 0, BW, BH);
        d.camera.eye.x += 0.3f * (float)i;
        ok &= lc_render(dev, &d, want[i], NULL) == LC_OK;
    }
    for (int i = 0; i < 3; i++) {
        lc_render_desc d = scene_desc(s, i, LC_MODE_DVR, 0, BW, BH);
        d.camera.eye.x += 0.3f * (float)i;
        ok &= lc_render_begin(dev, &d, NULL, out[i], &job[i]) == LC_OK;
    }
    lc_job_cancel(job[0]);
    lc_status st0 = lc_job_wait(job[0], -1.0, NULL);
    int same = 0;
    for (int i = 1; i < 3; i++) same += lc_job_wait(job[i], -1.0, NULL) == LC_OK && !memcmp(out[i], want[i], img_bytes(BW, BH));
    CHECK(ok && (st0 == LC_CANCELLED || (st0 == LC_OK && !memcmp(out[0], want[0], img_bytes(BW, BH)))) && same == 2,
          "three overlapping jobs on one device: the cancelled one %s, the other two exact (%d of 2)",
          lc_status_string(st0), same);
    CHECK(memcmp(want[1], want[2], img_bytes(BW, BH)) != 0 && memcmp(want[1], ref[1], img_bytes(BW, BH)) != 0,
          "control: the jobs' cameras give different images (a mix-up would show)");
    for (int i = 0; i < 3; i++) lc_job_destroy(job[i]);
    /* destroyed while running, and a second one while queued behind it */
    lc_render_desc d = scene_desc(s, 0, LC_MODE_DVR, 0, 4 * BW, 4 * BH);
    float *big = malloc(img_bytes(4 * BW, 4 * BH)), *big2 = malloc(img_bytes(4 * BW, 4 * BH));
    lc_job *a = NULL, *b = NULL;
    ok = big && big2 && lc_render_begin(dev, &d, NULL, big, &a) == LC_OK && lc_render_begin(dev, &d, NULL, big2, &b) == LC_OK;
    lc_job_progress pa;
    lc_status wa = ok ? lc_job_wait(a, 0.0, NULL) : LC_OK;
    lc_job_get_progress(a, &pa);
    struct timespec c0, c1;
    clock_gettime(CLOCK_MONOTONIC, &c0);
    lc_job_destroy(b);
    sleep_us(2000);
    lc_job_destroy(a);
    clock_gettime(CLOCK_MONOTONIC, &c1);
    double t0 = (double)c0.tv_sec + 1e-9 * (double)c0.tv_nsec, t1 = (double)c1.tv_sec + 1e-9 * (double)c1.tv_nsec;
    CHECK(ok && wa == LC_TIMEOUT && (pa.state == LC_JOB_QUEUED || pa.state == LC_JOB_RUNNING) && pa.npasses == 2,
          "a running job: wait(0) times out (%s), state %d, %d passes", lc_status_string(wa), (int)pa.state, pa.npasses);
    CHECK(t1 - t0 < 5.0, "two jobs destroyed while queued and running, in %.1f ms", 1e3 * (t1 - t0));
    lc_render_desc d1 = scene_desc(s, 1, LC_MODE_DVR, 0, BW, BH);
    CHECK(lc_render(dev, &d1, out[0], NULL) == LC_OK && !memcmp(out[0], ref[1], img_bytes(BW, BH)),
          "the device renders exactly after destroyed jobs");
    free(big), free(big2);
    for (int i = 0; i < 3; i++) free(out[i]), free(want[i]);
    lc_device_destroy(dev);
}

static void progress_and_errors(const scenes3 *s, float *img)
{
    lc_device *dev = NULL;
    lc_device_create(&(lc_device_desc){.threads = 2}, &dev);
    lc_render_desc d = scene_desc(s, 0, LC_MODE_DVR, 0, BW, BH);
    lc_job *job = NULL;
    lc_render_stats st;
    lc_job_progress p;
    lc_status w = LC_ERROR_INTERNAL;
    if (lc_render_begin(dev, &d, NULL, img, &job) == LC_OK) w = lc_job_wait(job, 30.0, &st);
    lc_job_get_progress(job, &p);
    CHECK(w == LC_OK && p.state == LC_JOB_DONE && p.pass == 2 && p.npasses == 2 && p.scale == 1 && p.fraction == 1.0f &&
              st.rays >= (uint64_t)BW * BH && st.seconds > 0.0,
          "a finished job: state done, pass 2 of 2, scale 1, fraction 1, stats (%llu rays for %d pixels)",
          (unsigned long long)st.rays, BW * BH);
    lc_job_destroy(job);
    job = (lc_job *)1;
    lc_render_desc bad = d;
    bad.pixel_scale = 17;
    CHECK(lc_render_begin(dev, &bad, NULL, img, &job) == LC_ERROR_INVALID_ARGUMENT && job == NULL &&
              strstr(lc_last_error(), "pixel_scale"),
          "pixel_scale 17: %s", lc_last_error());
    bad = d, bad.step_scale = 0.5f;
    CHECK(lc_render(dev, &bad, img, NULL) == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "step_scale"),
          "step_scale 0.5: %s", lc_last_error());
    CHECK(lc_render_begin(dev, &d, &(lc_job_desc){.preview_scale = 3}, img, &job) == LC_ERROR_INVALID_ARGUMENT &&
              strstr(lc_last_error(), "preview_scale"),
          "preview_scale 3: %s", lc_last_error());
    bad = d, bad.dt = -1.0f;
    CHECK(lc_render_begin(dev, &bad, NULL, img, &job) == LC_ERROR_INVALID_ARGUMENT && job == NULL &&
              strstr(lc_last_error(), "dt"),
          "a bad desc fails in lc_render_begin, nothing started: %s", lc_last_error());
    CHECK(lc_render_begin(dev, &d, NULL, NULL, &job) == LC_ERROR_INVALID_ARGUMENT, "rgba NULL: %s", lc_last_error());
    CHECK(lc_job_wait(NULL, 0.0, NULL) == LC_ERROR_INVALID_ARGUMENT && lc_job_get_progress(NULL, &p) == LC_ERROR_INVALID_ARGUMENT,
          "NULL job: %s", lc_last_error());
    lc_job_cancel(NULL);
    lc_job_destroy(NULL);
    CHECK(!strcmp(lc_status_string(LC_CANCELLED), "cancelled") && !strcmp(lc_status_string(LC_TIMEOUT), "timed out"),
          "status strings");
    lc_device_destroy(dev);
}

int main(int argc, char **argv)
{
    int trials = argc > 1 ? atoi(argv[1]) : 200;
    lc_device *owner = NULL;
    scenes3 *s = malloc(sizeof *s);
    float *ref = malloc(img_bytes(BW, BH)), *img = malloc(img_bytes(4 * BW, 4 * BH));
    float *refs[3] = {malloc(img_bytes(BW, BH)), malloc(img_bytes(BW, BH)), malloc(img_bytes(BW, BH))};
    if (!s || !ref || !img || !refs[0] || !refs[1] || !refs[2] ||
        lc_device_create(&(lc_device_desc){.target = LC_TARGET_SCALAR, .threads = 1}, &owner) ||
        scenes3_create(owner, s) != 0) {
        printf("FAIL setup: %s\n", lc_last_error());
        return 1;
    }
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        if (usable((lc_target)t)) identity((lc_target)t, s, ref, img);
        else
            printf("skip %s: %s\n", lc_target_name((lc_target)t),
                   lc_target_compiled((lc_target)t) ? "this CPU cannot run it" : "not compiled in");
    }
    cancels(s, trials, refs, img);
    sync_cancel(s, refs[0], img);
    overlaps(s, refs);
    progress_and_errors(s, img);
    scenes3_destroy(s);
    lc_device_destroy(owner);
    for (int k = 0; k < 3; k++) free(refs[k]);
    free(s), free(ref), free(img);
    return check_summary("render_job");
}
