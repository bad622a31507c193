/* RBF sets through the adaptive octree (Jang 2004 §5, accel = octree): on
 * every supported target, images of dense and sparse scenes (both signs, a
 * bias with a domain, shading, MIP, cell_max from 1 to beyond the longest
 * list) against the independent reference core at SPEC.md tolerances and bit
 * for bit against the BVH method (same terms, same order); a perturbed weight
 * that must fail the comparison; lc_volume_sample against the reference
 * evaluator and bit for bit against a BVH set, also far outside the data; the
 * n-most-significant approximation's error measured against its stored bound;
 * bad options refused. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "imgcmp.h"
#include "lanecast/lanecast.h"

#define W 64
#define H 48
#include "rbf_scene.h"

static const char *outdir = ".";
static lc_target targets[LC_TARGET_COUNT];
static int ntargets;
static double worst_255, worst_psnr = INFINITY;

enum { NSCENES = 7 };

static void make_scenes(scene *sc)
{
    memset(sc, 0, sizeof *sc * NSCENES);
    sc[0].name = "dense_clustered";
    fill(&sc[0], 300, 1, 0.08f, 0.3f, -0.4f, 0.6f, 11u, 0.2f);
    sc[0].range[0] = -1.0f, sc[0].range[1] = 2.0f, sc[0].dt = 0.02f, sc[0].cell_max = 8;
    sc[1] = sc[0], sc[1].name = "dense_phong_cell1", sc[1].shade = LC_SHADE_PHONG, sc[1].cell_max = 1;
    sc[2].name = "sparse_uniform";
    fill(&sc[2], 40, 0, 0.2f, 0.6f, -1.0f, 1.5f, 7u, 0.2f);
    sc[2].range[0] = -1.0f, sc[2].range[1] = 2.0f, sc[2].dt = 0.05f, sc[2].cell_max = 4;
    sc[3] = sc[2], sc[3].name = "sparse_bias_domain_diffuse", sc[3].bias = 0.25f, sc[3].shade = LC_SHADE_DIFFUSE;
    sc[3].domain = (lc_box3){{-2.5f, -1.8f, -2.2f}, {2.2f, 2.4f, 1.9f}};
    sc[4] = sc[0], sc[4].name = "dense_one_cell", sc[4].cell_max = LC_RBF_MAX_CELL; /* the root is the only leaf */
    sc[5] = sc[2], sc[5].name = "sparse_mip", sc[5].mode = LC_MODE_MIP, sc[5].cell_max = 2;
    sc[6] = sc[0], sc[6].name = "dense_bias_domain_phong", sc[6].bias = -0.2f, sc[6].shade = LC_SHADE_PHONG;
    sc[6].domain = (lc_box3){{-1.5f, -1.2f, -1.0f}, {1.4f, 1.9f, 1.5f}}, sc[6].cell_max = 16;
}

/* ---------------------------------------------------------------- images */

static void test_images(void)
{
    printf("-- images: the octree on every target against the reference core and the BVH\n");
    static scene sc[NSCENES];
    make_scenes(sc);
    float *want = malloc(sizeof(float) * 4 * W * H), *got = malloc(sizeof(float) * 4 * W * H);
    float *bvh = malloc(sizeof(float) * 4 * W * H);
    for (int i = 0; i < NSCENES; i++) {
        for (int ti = 0; ti < ntargets; ti++) {
            lc_device_desc dd = {.target = targets[ti], .threads = 2};
            lc_device *dev = NULL;
            lc_volume *v = NULL;
            lc_rbf_desc d = desc_of(&sc[i], LC_RBF_ACCEL_OCTREE, 0);
            lc_rbf_info info;
            if (lc_device_create(&dd, &dev) != LC_OK || lc_rbf_create(dev, &d, &v) != LC_OK ||
                lc_rbf_get_info(v, &info) != LC_OK) {
                CHECK(0, "%s: create on %s: %s", sc[i].name, lc_target_name(targets[ti]), lc_last_error());
                lc_device_destroy(dev);
                continue;
            }
            if (ti == 0) {
                double amax = 0.0;
                int rc = ref_image(&sc[i], info.eps, want);
                for (int p = 0; p < W * H; p++) amax = fmax(amax, want[4 * p + 3]);
                CHECK(rc == 0 && amax > 0.2 && info.accel == LC_RBF_ACCEL_OCTREE && info.truncated == 0,
                      "%s: reference image (alpha max %.2f); octree %d cells, %d leaves, depth %d, longest list %zu "
                      "of %zu RBFs",
                      sc[i].name, amax, info.octree_cells, info.octree_leaves, info.octree_depth,
                      info.octree_max_list, info.count);
            }
            char label[128];
            snprintf(label, sizeof label, "rbf_octree_%s_%s", sc[i].name, lc_target_name(targets[ti]));
            lc_render_stats st, sb;
            if (render(dev, v, &sc[i], LC_METHOD_DEFAULT, got, &st) || render(dev, v, &sc[i], LC_METHOD_BVH, bvh, &sb)) {
                CHECK(0, "%s: lc_render: %s", label, lc_last_error());
            } else {
                imgcmp_result r;
                imgcmp_stats(got, want, W, H, 2.0, &r);
                worst_255 = fmax(worst_255, r.max_diff_255), worst_psnr = fmin(worst_psnr, r.psnr_db);
                CHECK(imgcmp_check(label, got, want, W, H, 0, 0, outdir) == 0,
                      "%s (%llu gaussians, %llu cells entered; bvh %llu gaussians)", label,
                      (unsigned long long)st.kernel_evals, (unsigned long long)st.leaves,
                      (unsigned long long)sb.kernel_evals);
                CHECK(!memcmp(got, bvh, sizeof(float) * 4 * W * H), "%s: bit-identical to the BVH method", label);
            }
            lc_volume_destroy(v);
            lc_device_destroy(dev);
        }
    }
    /* the comparison can fail: the strongest weight 10% off, through the octree */
    lc_device *dev = NULL;
    lc_device_create(NULL, &dev);
    int strongest = 0;
    for (int i = 1; i < sc[2].n; i++) strongest = fabsf(sc[2].w[i]) > fabsf(sc[2].w[strongest]) ? i : strongest;
    scene bad = sc[2];
    bad.w[strongest] *= 1.1f;
    lc_rbf_info info;
    lc_volume *v = NULL;
    lc_rbf_desc d = desc_of(&sc[2], LC_RBF_ACCEL_OCTREE, 0), db = desc_of(&bad, LC_RBF_ACCEL_OCTREE, 0);
    lc_rbf_create(dev, &d, &v);
    lc_rbf_get_info(v, &info);
    lc_volume_destroy(v);
    ref_image(&sc[2], info.eps, want);
    db.eps = info.eps;
    int failed = lc_rbf_create(dev, &db, &v) == LC_OK && render(dev, v, &bad, LC_METHOD_DEFAULT, got, NULL) == 0 &&
                 imgcmp_check("rbf_octree_expected_fail_perturbed_weight", got, want, W, H, 0, 0, NULL) == 1;
    CHECK(failed, "a weight perturbed by 10%% fails the image comparison (the FAIL line above is expected)");
    lc_volume_destroy(v);
    lc_device_destroy(dev);
    free(want), free(got), free(bvh);
}

/* ---------------------------------------------------------------- sampling */

enum { NP = 800 };
static float pts[3 * NP];

/* Points near centres, anywhere in [-4, 4]^3 and far outside the data. */
static void make_points(const scene *s)
{
    seed = 5u;
    for (int i = 0; i < NP; i++)
        for (int k = 0; k < 3; k++)
            pts[3 * i + k] = i < s->n ? s->c[3 * i + k] + rnd(-0.1f, 0.1f) : i < NP - 40 ? rnd(-4.0f, 4.0f)
                                                                                        : rnd(-40.0f, 40.0f);
}

static int sample(const scene *s, lc_target t, int significant, int cell_max, lc_rbf_accel a, float *val, float *grad,
                  lc_rbf_info *info)
{
    lc_device_desc dd = {.target = t, .threads = 1};
    lc_device *dev = NULL;
    lc_volume *v = NULL;
    lc_rbf_desc d = desc_of(s, a, significant);
    if (cell_max) d.cell_max = cell_max;
    int ok = lc_device_create(&dd, &dev) == LC_OK && lc_rbf_create(dev, &d, &v) == LC_OK &&
             lc_rbf_get_info(v, info) == LC_OK && lc_volume_sample(dev, v, NP, pts, val, grad) == LC_OK;
    if (!ok) CHECK(0, "sample %s on %s: %s", s->name, lc_target_name(t), lc_last_error());
    lc_volume_destroy(v), lc_device_destroy(dev);
    return ok ? 0 : -1;
}

/* Exact lists: the octree's samples equal a BVH set's to the bit, and the
 * reference evaluator's within 1e-5 (|w0| + sum |w|) (as tests/test_rbf.c,
 * skipping points within 1e-4 R of a support's edge). */
static void test_sample(void)
{
    printf("-- lc_volume_sample through the octree\n");
    static scene sc[NSCENES];
    make_scenes(sc);
    static float vo[NP], go[3 * NP], vb[NP], gb[3 * NP];
    const int which[] = {0, 1, 3};
    for (int wi = 0; wi < 3; wi++) {
        const scene *s = &sc[which[wi]];
        make_points(s);
        static double c[3 * MAXN], sw[MAXN], w[MAXN];
        double sumw = fabs(s->bias);
        for (int i = 0; i < 3 * s->n; i++) c[i] = s->c[i];
        for (int i = 0; i < s->n; i++) sw[i] = s->s[i], w[i] = s->w[i], sumw += fabs(w[i]);
        for (int ti = 0; ti < ntargets; ti++) {
            lc_rbf_info io, ib;
            if (sample(s, targets[ti], 0, 0, LC_RBF_ACCEL_OCTREE, vo, go, &io) ||
                sample(s, targets[ti], 0, 0, LC_RBF_ACCEL_BVH, vb, gb, &ib))
                continue;
            CHECK(!memcmp(vo, vb, sizeof vo) && !memcmp(go, gb, sizeof go),
                  "%s on %s: octree samples and gradients bit-identical to the BVH's", s->name,
                  lc_target_name(targets[ti]));
            ref_rbf_set set = {(size_t)s->n, c, sw, w, s->bias, io.eps};
            double worst = 0.0;
            for (int i = 0; i < NP; i++) {
                const double p[3] = {pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]};
                int edge = 0;
                for (int j = 0; j < s->n && !edge; j++) {
                    double R = ref_rbf_support(sw[j], w[j], io.eps);
                    double e = sqrt(pow(p[0] - c[3 * j], 2) + pow(p[1] - c[3 * j + 1], 2) + pow(p[2] - c[3 * j + 2], 2));
                    edge = R > 0.0 && fabs(e - R) < 1e-4 * R;
                }
                if (edge) continue;
                double phi, g[3];
                ref_rbf_eval(&set, p, &phi, &g);
                worst = fmax(worst, fabs(vo[i] - phi) / sumw);
            }
            CHECK(worst < 1e-5, "%s on %s: octree samples within %.2g (|w0| + sum |w|) of the reference (< 1e-5)",
                  s->name, lc_target_name(targets[ti]), worst);
        }
    }
}

/* ---------------------------------------------------------------- significant */

/* The n-most-significant lists with corner errors: the measured error
 * |f - f_exact| at points inside the data stays within the stored bound (plus
 * float summation, 1e-5 (|w0| + sum |w|)); it is reported relative to the
 * weight scale; a cell_max beyond the longest list truncates nothing and
 * renders bit-identical to the exact octree. */
static void test_significant(void)
{
    printf("-- the n most significant RBFs per cell, corner errors interpolated\n");
    static scene sc[NSCENES];
    make_scenes(sc);
    const scene *s = &sc[0];
    make_points(s);
    static float ve[NP], vs[NP], g[3 * NP];
    double sumw = 0.0, maxw = 0.0;
    for (int i = 0; i < s->n; i++) sumw += fabs(s->w[i]), maxw = fmax(maxw, fabs(s->w[i]));
    lc_rbf_info ie, is;
    const int ns[] = {2, 4, 8, 16, 32};
    for (int ti = 0; ti < ntargets; ti++) {
        if (sample(s, targets[ti], 0, 4, LC_RBF_ACCEL_OCTREE, ve, g, &ie)) continue;
        for (int k = 0; k < 5; k++) {
            if (sample(s, targets[ti], 1, ns[k], LC_RBF_ACCEL_OCTREE, vs, g, &is)) continue;
            double worst = 0.0, mean = 0.0;
            for (int i = 0; i < NP; i++) worst = fmax(worst, fabs(vs[i] - ve[i])), mean += fabs(vs[i] - ve[i]) / NP;
            int print = ti == 0 || worst > is.truncation_bound + 1e-5 * sumw;
            if (print)
                CHECK(worst <= is.truncation_bound + 1e-5 * sumw && (is.truncated > 0) == (is.truncation_bound > 0.0),
                      "significant n = %d on %s: %zu of %zu list entries dropped; error max %.3g mean %.3g (max |w| "
                      "%.2g) within the bound %.3g",
                      ns[k], lc_target_name(targets[ti]), is.truncated, is.truncated + is.octree_refs, worst, mean,
                      maxw, is.truncation_bound);
        }
    }
    /* nothing to drop: the exact lists, bit for bit */
    lc_device *dev = NULL;
    lc_volume *a = NULL, *b = NULL;
    lc_device_create(NULL, &dev);
    lc_rbf_desc da = desc_of(s, LC_RBF_ACCEL_OCTREE, 0), db = desc_of(s, LC_RBF_ACCEL_OCTREE, 1);
    da.cell_max = db.cell_max = LC_RBF_MAX_CELL;
    float *ia = malloc(sizeof(float) * 4 * W * H), *ib = malloc(sizeof(float) * 4 * W * H);
    int ok = lc_rbf_create(dev, &da, &a) == LC_OK && lc_rbf_create(dev, &db, &b) == LC_OK &&
             lc_rbf_get_info(b, &is) == LC_OK && render(dev, a, s, LC_METHOD_DEFAULT, ia, NULL) == 0 &&
             render(dev, b, s, LC_METHOD_DEFAULT, ib, NULL) == 0;
    CHECK(ok && is.truncated == 0 && is.truncation_bound == 0.0 && !memcmp(ia, ib, sizeof(float) * 4 * W * H),
          "significant with cell_max beyond every list: nothing dropped, bit-identical to exact");
    /* and with truncation the image differs from the exact one (the mode does something), reported */
    lc_volume_destroy(b), b = NULL;
    db.cell_max = 4;
    float *want = malloc(sizeof(float) * 4 * W * H);
    lc_rbf_info ia_info;
    lc_rbf_get_info(a, &ia_info);
    ok = lc_rbf_create(dev, &db, &b) == LC_OK && render(dev, b, s, LC_METHOD_DEFAULT, ib, NULL) == 0 &&
         ref_image(s, ia_info.eps, want) == 0;
    imgcmp_result r = {0};
    if (ok) imgcmp_stats(ib, want, W, H, 2.0, &r);
    CHECK(ok && r.max_diff_255 > 0.0, "significant n = 4 image against the reference: max %.2f/255, PSNR %.1f dB",
          r.max_diff_255, r.psnr_db);
    lc_volume_destroy(a), lc_volume_destroy(b), lc_device_destroy(dev);
    free(ia), free(ib), free(want);
}

/* ---------------------------------------------------------------- options */

static void test_options(lc_device *dev)
{
    printf("-- bad octree options refused, good ones taken from a file load\n");
    float c[3] = {0, 0, 0}, s[1] = {1}, w[1] = {1};
    lc_volume *v = NULL;
    lc_rbf_desc d = {.count = 1, .centres = c, .widths = s, .weights = w, .accel = (lc_rbf_accel)4};
    CHECK(lc_rbf_create(dev, &d, &v) == LC_ERROR_INVALID_ARGUMENT && !v && strstr(lc_last_error(), "accel = 4"),
          "accel 4: %s", lc_last_error());
    d.accel = LC_RBF_ACCEL_OCTREE, d.cell_max = -1;
    CHECK(lc_rbf_create(dev, &d, &v) == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "cell_max = -1"),
          "cell_max -1: %s", lc_last_error());
    d.cell_max = LC_RBF_MAX_CELL + 1;
    CHECK(lc_rbf_create(dev, &d, &v) == LC_ERROR_INVALID_ARGUMENT, "cell_max %d: %s", LC_RBF_MAX_CELL + 1,
          lc_last_error());
    d.cell_max = 0, d.significant = 2;
    CHECK(lc_rbf_create(dev, &d, &v) == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "significant = 2"),
          "significant 2: %s", lc_last_error());
    d.accel = LC_RBF_ACCEL_BVH, d.significant = 1;
    CHECK(lc_rbf_create(dev, &d, &v) == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "needs accel = octree"),
          "significant without the octree: %s", lc_last_error());
    d.accel = LC_RBF_ACCEL_DEFAULT, d.significant = 0;
    lc_rbf_info in;
    CHECK(lc_rbf_create(dev, &d, &v) == LC_OK && lc_rbf_get_info(v, &in) == LC_OK &&
              (in.accel == LC_RBF_ACCEL_BVH || in.accel == LC_RBF_ACCEL_OCTREE || in.accel == LC_RBF_ACCEL_COHERENT) &&
              (in.accel == LC_RBF_ACCEL_OCTREE) == (in.octree_cells > 0),
          "the default accel resolves to %s",
          in.accel == LC_RBF_ACCEL_OCTREE ? "octree" : in.accel == LC_RBF_ACCEL_BVH ? "bvh" : "coherent");
    lc_volume_destroy(v), v = NULL;
    /* file options */
    char p[512];
    snprintf(p, sizeof p, "%s/octree_opts.rbf", outdir);
    FILE *f = fopen(p, "w");
    if (f) fputs("lanecast-rbf 1\nbias 0\ncount 2\n0 0 0 1 1\n1 0 0 0.5 -1\n", f), fclose(f);
    lc_option good[] = {{"accel", "octree"}, {"cell_max", "1"}, {"significant", "1"}};
    lc_load_desc ld = {.options = good, .noptions = 3};
    CHECK(f && lc_volume_load(dev, p, &ld, &v) == LC_OK && lc_rbf_get_info(v, &in) == LC_OK &&
              in.accel == LC_RBF_ACCEL_OCTREE && in.cell_max == 1 && in.significant == 1 && in.octree_cells >= 1,
          "accel=octree cell_max=1 significant=1 from a load: %d cells, %zu dropped, bound %.3g", in.octree_cells,
          in.truncated, in.truncation_bound);
    lc_volume_destroy(v), v = NULL;
    const lc_option bad[][1] = {{{"accel", "kdtree"}}, {{"cell_max", "0"}}, {{"significant", "yes"}}};
    const char *expect[] = {"expected coherent, bvh or octree", "cell_max", "significant"};
    for (int i = 0; i < 3; i++) {
        lc_load_desc lb = {.options = bad[i], .noptions = 1};
        lc_status st = lc_volume_load(dev, p, &lb, &v);
        const char *msg = lc_last_error();
        CHECK(st == LC_ERROR_INVALID_ARGUMENT && !v && strstr(msg, expect[i]) && !strchr(msg, '\n'), "%s=%s: %s",
              bad[i][0].key, bad[i][0].value, msg);
        lc_volume_destroy(v), v = NULL;
    }
}

int main(int argc, char **argv)
{
    if (argc > 1) outdir = argv[1];
    for (lc_target t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        if (!lc_target_compiled(t)) printf("skip target %s: not compiled in\n", lc_target_name(t));
        else if (!lc_target_supported(t)) printf("skip target %s: this CPU cannot run it\n", lc_target_name(t));
        else targets[ntargets++] = t;
    }
    lc_device *dev = NULL;
    if (lc_device_create(NULL, &dev) != LC_OK) return 1;
    test_options(dev);
    lc_device_destroy(dev);
    test_sample();
    test_significant();
    test_images();
    printf("worst octree image difference over all targets and scenes: %.3f/255, PSNR %.1f dB\n", worst_255,
           worst_psnr);
    return check_summary("test_rbf_octree");
}
