/* Data-parallel rendering in one process (host/mpi/dp.h): the compositing
 * schedule over P = 1..64 virtual ranks against sequential "over" and
 * nearest depth; the kd-tree's balance and cells; and every kind rendered
 * region by region and composited against the one render (SPEC.md
 * "Regions"): summed per-region sample counts equal the single count,
 * mip/iso/slice to the bit, dvr within float round-off of the "over" with
 * alpha_stop = 1 and within SPEC.md's 1 - alpha_stop with the default. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "host/mpi/dp.h"
#include "imgcmp.h"
#include "dp_scene.h"
#include "modes_scene.h"

static uint32_t rs = 12345u;
static uint32_t urand(void) { return rs = rs * 1103515245u + 12345u, rs >> 8; }
static float frand(void) { return (float)(urand() & 0xffff) / 65535.0f; }

/* ---------------------------------------------------------------- schedule */

static void random_image(lci_cimage *img, int w, int h, int op)
{
    img->w = w, img->h = h;
    img->rgba = calloc((size_t)w * (size_t)h * 4, sizeof(float));
    img->depth = op == LCI_COMP_DEPTH ? malloc(sizeof(float) * (size_t)w * (size_t)h) : NULL;
    for (int i = 0; op == LCI_COMP_DEPTH && i < w * h; i++) img->depth[i] = INFINITY;
    int x0 = (int)(urand() % (unsigned)w), y0 = (int)(urand() % (unsigned)h);
    int x1 = x0 + (int)(urand() % (unsigned)(w - x0 + 1)), y1 = y0 + (int)(urand() % (unsigned)(h - y0 + 1));
    if (urand() % 4 == 0) x0 = 0, y0 = 0, x1 = w, y1 = h;
    for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++) {
            float *c = img->rgba + ((size_t)y * (size_t)w + (size_t)x) * 4;
            if (urand() % 5 == 0) continue; /* holes inside the rect */
            float a = frand();
            c[0] = a * frand(), c[1] = a * frand(), c[2] = a * frand(), c[3] = a;
            if (op == LCI_COMP_DEPTH) img->depth[(size_t)y * (size_t)w + (size_t)x] = (float)(urand() % 16); /* ties */
        }
    lci_cimage_rect(img, op);
}

static void test_schedule(lc_device *dev)
{
    static const int sizes[][2] = {{1, 1}, {7, 5}, {16, 9}, {13, 64}, {3, 2}};
    int bad_over = 0, bad_depth = 0, runs = 0;
    double worst = 0.0;
    for (int P = 1; P <= 64; P++) {
        for (int si = 0; si < 5; si++) {
            for (int op = 0; op < 2; op++) {
                int w = sizes[si][0], h = sizes[si][1];
                lci_cimage *imgs = calloc((size_t)P, sizeof *imgs);
                for (int p = 0; p < P; p++) random_image(&imgs[p], w, h, op);
                /* the reference: sequential front to back over positions 0 .. P-1 */
                size_t np = (size_t)w * (size_t)h;
                float *want = calloc(np * 4, sizeof(float)), *wd = malloc(np * sizeof(float));
                for (size_t i = 0; i < np; i++) wd[i] = INFINITY;
                for (int p = 0; p < P; p++)
                    for (size_t i = 0; i < np; i++) {
                        const float *c = imgs[p].rgba + 4 * i;
                        if (op == LCI_COMP_OVER) {
                            float k = 1.0f - want[4 * i + 3];
                            for (int ch = 0; ch < 4; ch++) want[4 * i + ch] += k * c[ch];
                        } else if (imgs[p].depth[i] < wd[i]) {
                            wd[i] = imgs[p].depth[i];
                            memcpy(want + 4 * i, c, sizeof(float) * 4);
                        }
                    }
                float *got = malloc(np * 4 * sizeof(float)), *gd = malloc(np * sizeof(float));
                lci_dp_composite_local(dev, P, imgs, op, got, op == LCI_COMP_DEPTH ? gd : NULL, NULL, NULL);
                for (size_t i = 0; i < np * 4; i++) {
                    double e = fabs((double)got[i] - (double)want[i]);
                    if (op == LCI_COMP_OVER) {
                        if (e > worst) worst = e;
                        if (!(e <= 1e-5)) bad_over++;
                    } else if (got[i] != want[i]) {
                        bad_depth++;
                    }
                }
                for (size_t i = 0; op == LCI_COMP_DEPTH && i < np; i++)
                    if (gd[i] != wd[i]) bad_depth++;
                runs++;
                for (int p = 0; p < P; p++) free(imgs[p].rgba), free(imgs[p].depth);
                free(imgs), free(want), free(wd), free(got), free(gd);
            }
        }
    }
    CHECK(bad_over == 0, "schedule: over of P = 1..64 random images (%d runs) = sequential over, worst |diff| %.2g <= 1e-5 (%d off)",
          runs, worst, bad_over);
    CHECK(bad_depth == 0, "schedule: nearest depth of P = 1..64 random images = sequential, to the bit (%d off)", bad_depth);
}

/* Binary swap's traffic: each rank sends S (1 - 1/P) in the swap rounds
 * (S = 16 W H bytes) plus its 1/P share to the root; fold partners send S. */
static void test_bytes(lc_device *dev)
{
    const int w = 64, h = 64;
    for (int P = 2; P <= 8; P++) {
        lci_cimage *imgs = calloc((size_t)P, sizeof *imgs);
        for (int p = 0; p < P; p++) {
            imgs[p].w = w, imgs[p].h = h;
            imgs[p].rgba = malloc(sizeof(float) * 4 * w * h);
            for (int i = 0; i < 4 * w * h; i++) imgs[p].rgba[i] = 0.25f;
            lci_cimage_rect(&imgs[p], LCI_COMP_OVER);
        }
        uint64_t bytes[8], msgs[8];
        float *out = malloc(sizeof(float) * 4 * w * h);
        lci_dp_composite_local(dev, P, imgs, LCI_COMP_OVER, out, NULL, bytes, msgs);
        int P2 = P >= 8 ? 8 : P >= 4 ? 4 : 2;
        double S = 16.0 * w * h, worst = 0.0;
        for (int p = 0; p < P; p++) {
            /* swap rounds + gather (not from position 0): S (1 - 1/P2) + S / P2 */
            int folded_out = p < 2 * (P - P2) && (p & 1);
            double want = folded_out ? S : S * (1.0 - 1.0 / P2) + (p ? S / P2 : 0.0);
            double r = (double)bytes[p] / want;
            if (r > worst) worst = r;
        }
        CHECK(worst >= 1.0 && worst <= 1.01, "bytes P=%d: the most a rank sends / binary swap's S(1-1/P)+S/P = %.4f (headers only)", P, worst);
        for (int p = 0; p < P; p++) free(imgs[p].rgba);
        free(imgs), free(out);
    }
}

/* ---------------------------------------------------------------- partition */

static void test_partition(lc_device *dev)
{
    enum { N = 2000 };
    float *x = malloc(sizeof(float) * N * 3), *y = x + N, *z = y + N;
    for (int i = 0; i < N; i++) x[i] = 4 * frand() - 1, y[i] = frand(), z[i] = 2 * frand();
    lc_box3 b = {{-1, 0, 0}, {3, 1, 2}};
    int bad_cells = 0, bad_weight = 0;
    for (int P = 1; P <= 13; P++) {
        lci_kdtree t;
        if (lci_kd_build(dev, &b, P, N, x, y, z, NULL, &t) != LC_OK) {
            CHECK(0, "kd build P=%d: %s", P, lc_device_last_error(dev));
            continue;
        }
        uint64_t sum = 0;
        for (int l = 0; l < P; l++) {
            sum += t.weight[l];
            if (fabs((double)t.weight[l] - (double)N / P) > 8.0) bad_weight++;
        }
        if (sum != N) bad_weight++;
        for (int i = 0; i < N; i++) {
            int in = 0;
            for (int l = 0; l < P; l++) {
                const lc_kregion *c = &t.cell[l];
                float p[3] = {x[i], y[i], z[i]};
                int k = 1;
                for (int a = 0; a < 3; a++) k &= c->lo[a] <= p[a] && p[a] < c->hi[a];
                in += k;
            }
            if (in != 1) bad_cells++;
        }
        lci_kd_release(&t);
    }
    CHECK(bad_weight == 0, "kd-tree P = 1..13 over 2000 points: each region within 8 of N/P, all counted (%d off)", bad_weight);
    CHECK(bad_cells == 0, "kd-tree cells: every point in exactly one half-open cell (%d off)", bad_cells);
    lci_kdtree t;
    int cells[3] = {16, 12, 10};
    lci_kd_build(dev, &b, 6, 0, NULL, NULL, NULL, cells, &t);
    uint64_t sum = 0, mx = 0;
    for (int l = 0; l < 6; l++) sum += t.weight[l], mx = t.weight[l] > mx ? t.weight[l] : mx;
    CHECK(sum == 16 * 12 * 10 && mx <= 16 * 12 * 10 / 6 + 16 * 12, "kd-tree of a 16x12x10-cell grid in 6: %llu cells, largest %llu",
          (unsigned long long)sum, (unsigned long long)mx);
    lci_kd_release(&t);
    free(x);
}

/* ---------------------------------------------------------------- renders */

/* One kind, mode and view: the single render against P-region renders. */
static void compare(lc_device *dev, const char *kind, const lc_volume *v, const lc_tf *tf, lc_mode mode, int vi,
                    float alpha_stop, int w, int h, float iso)
{
    lc_render_desc d = dp_desc(v, tf, mode, vi, alpha_stop, w, h, iso);
    size_t np = (size_t)w * (size_t)h;
    float *want = malloc(sizeof(float) * 4 * np), *got = malloc(sizeof(float) * 4 * np);
    lc_render_stats st1;
    if (lc_render(dev, &d, want, &st1) != LC_OK) {
        CHECK(0, "%s %s: %s", kind, dp_mode_names[mode], lc_device_last_error(dev));
        free(want), free(got);
        return;
    }
    static const int Ps[] = {2, 3, 4, 7};
    for (int pi = 0; pi < 4; pi++) {
        int P = Ps[pi];
        uint64_t samples[8];
        lc_render_stats st;
        lc_status s = lci_dp_render_local(dev, &d, P, got, &st, samples);
        char label[160];
        snprintf(label, sizeof label, "%s-%s-%s-a%g-P%d-%dx%d", kind, dp_mode_names[mode], dp_view_names[vi],
                 (double)alpha_stop, P, w, h);
        if (s != LC_OK) {
            CHECK(0, "%s: %s", label, lc_device_last_error(dev));
            continue;
        }
        dp_check_image(label, got, want, &d);
        if (mode == LC_MODE_DVR) { /* the chain: the same bits without early termination */
            uint64_t cs[8];
            s = lci_dp_render_chain(dev, &d, P, pi % 2 ? 1 : 5, got, NULL, cs); /* one band or five of 6-7 rows */
            CHECK_QUIET(s == LC_OK, "%s chain: %s", label, lc_device_last_error(dev));
            if (s == LC_OK) { /* early termination too: a carried-in ray stops where one render's does */
                double e = 0.0;
                for (size_t i = 0; i < 4 * np; i++) e = fmax(e, fabs((double)got[i] - (double)want[i]));
                CHECK_QUIET(!memcmp(got, want, sizeof(float) * 4 * np), "%s chain: not one render's bits (max |diff| %.3g)",
                            label, e);
                uint64_t sum = 0;
                for (int p = 0; p < P; p++) sum += cs[p];
                CHECK_QUIET(sum == st1.samples, "%s chain: summed region samples %llu != one render's %llu", label,
                            (unsigned long long)sum, (unsigned long long)st1.samples);
            }
        }
        if ((mode == LC_MODE_DVR || mode == LC_MODE_MIP) && alpha_stop == 1.0f) { /* early termination stops rays per region */
            uint64_t sum = 0;
            for (int p = 0; p < P; p++) sum += samples[p];
            CHECK_QUIET(sum == st1.samples, "%s: summed region samples %llu != one render's %llu", label,
                        (unsigned long long)sum, (unsigned long long)st1.samples);
        }
    }
    free(want), free(got);
}

static void test_kinds(lc_device *dev)
{
    static scene sc;
    make_scene(&sc);
    lc_tf_field tff[2] = {{col0, 3, opa, 2, 1, {0.0f, 1.0f}}, {col1, 2, opa, 2, 1, {0.0f, 1.0f}}};
    lc_tf *tf2 = NULL, *tf1 = NULL;
    lc_tf_create(dev, tff, 2, &tf2);
    lc_tf_create(dev, tff, 1, &tf1);
    lc_volume *pv = NULL, *gv = NULL, *rv = NULL;
    lc_particles_desc pd = {.count = NP, .positions = sc.pos, .radii = sc.rad, .fields = sc.field, .nfields = 2};
    lc_grid_desc gd = {.size = {GX, GY, GZ}, .type = LC_VALUE_FLOAT32, .data = sc.grid,
                       .spacing = {0.25f, 0.25f, 0.25f}, .origin = {-2.0f, -1.5f, -1.25f}};
    lc_rbf_desc rd = {.count = NR, .centres = sc.rc, .widths = sc.rs, .weights = sc.rw, .bias = RBF_BIAS,
                      .eps = RBF_EPS, .domain = rbf_domain};
    CHECK(lc_particles_create(dev, &pd, &pv) == LC_OK && lc_grid_create(dev, &gd, &gv) == LC_OK &&
              lc_rbf_create(dev, &rd, &rv) == LC_OK, "volumes");
    int before = check_failures;
    static const lc_mode modes[] = {LC_MODE_DVR, LC_MODE_MIP, LC_MODE_ISO, LC_MODE_SLICE};
    for (int mi = 0; mi < 4; mi++)
        for (int vi = 0; vi < DP_NVIEWS; vi++) {
            compare(dev, "particles", pv, tf2, modes[mi], vi, 1.0f, 40, 32, 0.3f);
            compare(dev, "grid", gv, tf1, modes[mi], vi, 1.0f, 40, 32, 0.45f);
            compare(dev, "rbf", rv, tf1, modes[mi], vi, 1.0f, 40, 32, 0.3f);
        }
    CHECK(check_failures == before, "particles, grid, rbf x dvr/mip/iso/slice x 4 views x P = 2,3,4,7 (alpha_stop 1): "
                                    "regions composited = one render");
    before = check_failures;
    for (int vi = 0; vi < DP_NVIEWS; vi++) {
        compare(dev, "particles", pv, tf2, LC_MODE_DVR, vi, 0.97f, 40, 32, 0.0f);
        compare(dev, "grid", gv, tf1, LC_MODE_DVR, vi, 0.97f, 40, 32, 0.0f);
        compare(dev, "rbf", rv, tf1, LC_MODE_DVR, vi, 0.97f, 40, 32, 0.0f);
        /* rays that stop inside a region in front: the chain must not take one more sample behind */
        compare(dev, "particles", pv, tf2, LC_MODE_DVR, vi, 0.2f, 40, 32, 0.0f);
        compare(dev, "grid", gv, tf1, LC_MODE_DVR, vi, 0.2f, 40, 32, 0.0f);
        compare(dev, "rbf", rv, tf1, LC_MODE_DVR, vi, 0.2f, 40, 32, 0.0f);
        compare(dev, "grid", gv, tf1, LC_MODE_DVR, vi, 1.0f, 1, 1, 0.0f);
        compare(dev, "grid", gv, tf1, LC_MODE_DVR, vi, 1.0f, 13, 7, 0.0f);
    }
    CHECK(check_failures == before, "alpha_stop 0.97 and 0.2 within 1 - alpha_stop (the chain: the same bits); 1x1 and 13x7 images");
    lc_volume_destroy(pv), lc_volume_destroy(gv), lc_volume_destroy(rv);
    lc_tf_destroy(tf1), lc_tf_destroy(tf2);
}

/* A constant-density grid (brute force: one sample per lattice point) and a
 * dense particle set: no sample counted twice or lost at region borders. */
static void test_counts(lc_device *dev)
{
    enum { N = 9 };
    static float ones[N * N * N];
    for (int i = 0; i < N * N * N; i++) ones[i] = 1.0f;
    lc_grid_desc gd = {.size = {N, N, N}, .type = LC_VALUE_FLOAT32, .data = ones, .spacing = {0.5f, 0.5f, 0.5f},
                       .origin = {-2.0f, -2.0f, -2.0f}};
    lc_volume *gv = NULL;
    lc_grid_create(dev, &gd, &gv);
    static const float col[] = {0.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f, 1.0f};
    static const float op[] = {0.0f, 0.5f, 1.0f, 0.5f};
    lc_tf_field f = {col, 2, op, 2, 1, {0.0f, 2.0f}};
    lc_tf *tf = NULL;
    lc_tf_create(dev, &f, 1, &tf);
    int before = check_failures;
    for (int vi = 0; vi < DP_NVIEWS; vi++) {
        lc_render_desc d = {0};
        d.width = 24, d.height = 20, d.volume = gv, d.tf = tf, d.dt = 0.1f, d.alpha_stop = 1.0f;
        d.method = LC_METHOD_BRUTE;
        d.camera = dp_views[vi];
        float *img = malloc(sizeof(float) * 4 * 24 * 20);
        lc_render_stats st1, st;
        lc_render(dev, &d, img, &st1);
        for (int P = 2; P <= 9; P++) {
            uint64_t samples[9], sum = 0;
            lci_dp_render_local(dev, &d, P, img, &st, samples);
            for (int p = 0; p < P; p++) sum += samples[p];
            CHECK_QUIET(sum == st1.samples && st1.samples > 0, "constant grid %s P=%d: %llu samples in regions, %llu in one",
                        dp_view_names[vi], P, (unsigned long long)sum, (unsigned long long)st1.samples);
        }
        free(img);
    }
    CHECK(check_failures == before, "constant-density grid, 4 views, P = 2..9: summed region samples = one render's");
    lc_volume_destroy(gv);
    lc_tf_destroy(tf);
}

int main(void)
{
    lc_device *dev;
    if (lc_device_create(&(lc_device_desc){.threads = 2}, &dev) != LC_OK) {
        printf("device: %s\n", lc_last_error());
        return 1;
    }
    /* the scene's double copies serve the reference core, not this test */
    to_double(col0, dcol0, 12), to_double(col1, dcol1, 8), to_double(opa, dopa, 4);
    test_schedule(dev);
    test_bytes(dev);
    test_partition(dev);
    test_counts(dev);
    test_kinds(dev);
    lc_device_destroy(dev);
    /* the kinds' region and chain renders on every other target this CPU runs (the carry-in is per target) */
    lc_device_desc dd = {.threads = 2};
    lc_device_create(&dd, &dev);
    lc_target best = LC_TARGET_AUTO;
    lc_device_target(dev, &best);
    lc_device_destroy(dev);
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        if (t == (int)best || !lc_target_compiled((lc_target)t) || !lc_target_supported((lc_target)t)) continue;
        dd.target = (lc_target)t;
        if (lc_device_create(&dd, &dev) != LC_OK) continue;
        int before = check_failures;
        test_kinds(dev);
        CHECK(check_failures == before, "target %s: the kinds' regions and chains", lc_target_name((lc_target)t));
        lc_device_destroy(dev);
    }
    return check_summary("test_dp");
}
