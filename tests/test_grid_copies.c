/* The voxel copies an owned uint8 grid samples (host/kinds/grid.c, kgrid.h),
 * two grids of the same volume side by side, one test per pair:
 * - nopairs (issue 9): no copy (above lci_grid_pairs_max,
 *   lowered here), sampled from the bricked or linear voxels, against the
 *   y-pair copy (2 bytes a voxel);
 * - quads (issue 9): the z-paired copy (pair_quads, 4 bytes a voxel, one
 *   64-bit gather lane per sample; up to lci_grid_quads_max) against the
 *   y-pair copy.
 * Per target: the first grid against the reference core (tests/ref) at
 * SPEC.md tolerances and the two grids' images equal (BVH with heuristics
 * off and on, brute force, post-classified and pre-integrated), camera
 * outside, inside and on an axis-aligned view, odd sizes, both layouts, and
 * a volume large enough for the huge-page voxel allocation, and rows wide
 * enough for the pair copy's padded strides. A reference of a
 * perturbed volume must fail the same comparison (the test can fail).
 * usage: test_grid_copies nopairs|quads [OUTDIR]   (diff images of failures go to OUTDIR) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/kinds/grid.h"

#include "check.h"
#include "imgcmp.h"
#include "ref/ref_core.h"
#include "ref/ref_fields.h"
#include "gscene.h"

extern int64_t lci_grid_pairs_max, lci_grid_quads_max; /* host/kinds/grid.c */

enum { W = 41, H = 37 };

static const char *diff_dir;

/* the pair of grids compared: [0] against the reference, [1] beside it */
typedef struct variant {
    const char *name, *label[2];
    int64_t pairs_max[2], quads_max[2]; /* the bounds each grid is created under */
} variant;
static const variant variants[] = {
    {"nopairs", {"nopairs", "pairs"}, {1000, (int64_t)1 << 40}, {0, 0}},
    {"quads", {"quads", "pairs"}, {(int64_t)1 << 40, (int64_t)1 << 40}, {(int64_t)1 << 40, 0}},
};
static const variant *var;
static imgcmp_worst w_ref = IMGCMP_WORST_INIT, w_same = IMGCMP_WORST_INIT, w_heur = IMGCMP_WORST_INIT,
                    w_pre = IMGCMP_WORST_INIT;

/* two soft blobs and a shell in [0, 255], 0 (air) below 12 */
static uint8_t field(double x, double y, double z)
{
    double a = exp(-((x - 0.35) * (x - 0.35) + (y - 0.4) * (y - 0.4) + (z - 0.5) * (z - 0.5)) / 0.02);
    double b = exp(-((x - 0.65) * (x - 0.65) + (y - 0.6) * (y - 0.6) + (z - 0.45) * (z - 0.45)) / 0.01);
    double r = sqrt((x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5) + (z - 0.5) * (z - 0.5));
    double shell = r > 0.38 && r < 0.45 ? 0.5 + 0.3 * sin(20 * x) * cos(17 * y) : 0;
    double v = fmax(fmax(a, b), shell) * 255.0;
    return v < 12 ? 0 : (uint8_t)lround(v);
}

typedef struct vol {
    int n[3];
    uint8_t *data;
    double *ref;
} vol;

static void vol_make(vol *v, int nx, int ny, int nz)
{
    v->n[0] = nx, v->n[1] = ny, v->n[2] = nz;
    size_t n = (size_t)nx * ny * nz;
    v->data = malloc(n);
    v->ref = malloc(n * sizeof(double));
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++) {
                size_t id = ((size_t)k * ny + j) * nx + i;
                v->data[id] = field((double)i / (nx - 1), (double)j / (ny - 1), (double)k / (nz - 1));
                v->ref[id] = v->data[id];
            }
}

static void render(lc_device *dev, lc_volume *g, const lc_tf *tf, const gview *vw, lc_method m, int heur, int preint,
                   float *out)
{
    lc_render_desc d = gscene_desc(g, tf, vw, W, H, m, 0, 255);
    lc_grid_params gp = {0};
    if (!heur) gp = (lc_grid_params){.delta_c = -1, .delta_p = -1, .delta_sv = -1};
    gp.preintegrated = preint;
    CHECK_QUIET(lc_grid_set_params(g, &gp) == LC_OK, "lc_grid_set_params: %s", lc_last_error());
    CHECK_QUIET(lc_render(dev, &d, out, NULL) == LC_OK, "render: %s", lc_last_error());
}

static void ref_image(const vol *v, const gview *vw, float *out) { gscene_ref(v->n, v->ref, 0, 255, vw, W, H, out); }

static int cmp(const char *label, const float *got, const float *want, double max_255, double min_psnr, imgcmp_worst *w)
{
    imgcmp_result r;
    int rc = imgcmp_check_ex(label, got, want, W, H, max_255, min_psnr, diff_dir, 1, &r);
    if (rc >= 0 && w) imgcmp_worst_add(w, &r);
    if (rc != 0) printf("%s: max %.3f/255 psnr %.1f\n", label, r.max_diff_255, r.psnr_db);
    return rc;
}

typedef struct grids {
    lc_volume *g[2][2]; /* [variant's grid][layout: 0 bricked, 1 linear] */
} grids;

/* One volume under every target: the variant's two grids of each layout,
 * against the reference and one another. */
static void check_volume(const vol *v, const gview *views, int nviews, int show)
{
    float *a = malloc(sizeof(float) * W * H * 4), *b = malloc(sizeof(float) * W * H * 4),
          *r = malloc(sizeof(float) * W * H * 4);
    float *refs = malloc(sizeof(float) * W * H * 4 * (size_t)nviews);
    for (int e = 0; e < nviews; e++) {
        ref_image(v, &views[e], refs + (size_t)e * W * H * 4);
        double amax = 0;
        for (int i = 0; i < W * H; i++)
            amax = fmax(amax, refs[(size_t)e * W * H * 4 + 4 * i + 3]);
        CHECK_QUIET(amax > 0.3, "view %d: reference image nearly empty (max alpha %g)", e, amax);
    }
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        if (!lc_target_compiled((lc_target)t) || !lc_target_supported((lc_target)t)) continue;
        const char *tn = lc_target_name((lc_target)t);
        lc_device *dev = NULL;
        if (lc_device_create(&(lc_device_desc){.target = (lc_target)t, .threads = 2}, &dev) != LC_OK) continue;
        lc_tf_field tff = {.color = gscene_color, .ncolor = 3, .opacity = gscene_opacity, .nopacity = 4};
        lc_tf *tf = NULL;
        CHECK_QUIET(lc_tf_create(dev, &tff, 1, &tf) == LC_OK, "tf: %s", lc_last_error());
        grids gs;
        uint64_t bytes[2][2];
        for (int c = 0; c < 2; c++)
            for (int lay = 0; lay < 2; lay++) {
                lci_grid_pairs_max = var->pairs_max[c];
                lci_grid_quads_max = var->quads_max[c];
                lc_grid_desc gd = {.size = {v->n[0], v->n[1], v->n[2]},
                                   .type = LC_VALUE_UINT8,
                                   .data = v->data,
                                   .layout = lay ? LC_LAYOUT_LINEAR : LC_LAYOUT_BRICKED};
                gs.g[c][lay] = NULL;
                CHECK_QUIET(lc_grid_create(dev, &gd, &gs.g[c][lay]) == LC_OK, "create: %s", lc_last_error());
                lc_grid_info in = {0};
                if (gs.g[c][lay]) lc_grid_get_info(gs.g[c][lay], &in);
                bytes[c][lay] = in.layout_bytes;
                if (gs.g[c][lay])
                    CHECK_QUIET(((const grid *)gs.g[c][lay])->kg.pair_quads == (var->quads_max[c] > 0),
                                "%s: quad copy %s", tn, var->quads_max[c] > 0 ? "absent" : "present");
            }
        lci_grid_pairs_max = (int64_t)1 << 30;
        lci_grid_quads_max = (int64_t)1 << 25;
        uint64_t count = (uint64_t)v->n[0] * v->n[1] * v->n[2];
        uint64_t tables = sizeof(int32_t) * ((uint64_t)v->n[0] + v->n[1] + v->n[2]);
        for (int c = 0; c < 2; c++)
            for (int lay = 0; lay < 2; lay++) {
                /* a copy replaces the voxels: its bytes (and 64 of padding) and the offset tables only */
                uint64_t per = var->quads_max[c] ? 4 : var->pairs_max[c] > (int64_t)count ? 2 : 0;
                lc_grid_info in = {0};
                if (gs.g[c][lay]) lc_grid_get_info(gs.g[c][lay], &in);
                CHECK_QUIET(in.copy_voxel_bytes == (int)per, "%s layout %d: %s reports a copy of %d bytes a voxel", tn,
                            lay, var->label[c], in.copy_voxel_bytes);
                /* the pair copy's rows and planes padded to an odd number of 64-byte
                   lines from 1 KiB and 4 KiB (host/kinds/grid_layout.c lci_grid_padded_strides); the quad copy unpadded */
                uint64_t elems = count;
                if (per == 2 && gs.g[c][lay]) {
                    const lc_kgrid *kg = &((const grid *)gs.g[c][lay])->kg;
                    int64_t ys = kg->pair_ystride, zs = kg->pair_zstride;
                    int rows_ok = v->n[0] * 2 >= 1024 ? ys >= v->n[0] && ys * 2 % 64 == 0 && (ys * 2 / 64) % 2 == 1
                                                      : ys == v->n[0];
                    int planes_ok = ys * v->n[1] * 2 >= 4096
                                        ? zs >= ys * v->n[1] && zs * 2 % 64 == 0 && (zs * 2 / 64) % 2 == 1
                                        : zs == ys * v->n[1];
                    CHECK_QUIET(rows_ok && planes_ok, "%s layout %d: pair copy strides %lld / %lld for %dx%d voxels",
                                tn, lay, (long long)ys, (long long)zs, v->n[0], v->n[1]);
                    elems = (uint64_t)zs * (uint64_t)v->n[2];
                }
                int ok = per ? bytes[c][lay] == tables + per * elems + 64 : bytes[c][lay] >= tables + count;
                CHECK_QUIET(ok, "%s layout %d: %s holds %llu bytes (%llu voxels)", tn, lay, var->label[c],
                            (unsigned long long)bytes[c][lay], (unsigned long long)count);
            }
        /* the histogram (lc_tf_auto's input) reads the copy where there is one */
        for (int lay = 0; lay < 2; lay++) {
            if (!gs.g[0][lay] || !gs.g[1][lay]) continue;
            uint64_t h0[64], h1[64], sum = 0;
            CHECK_QUIET(lc_grid_histogram(gs.g[0][lay], 64, h0) == LC_OK &&
                            lc_grid_histogram(gs.g[1][lay], 64, h1) == LC_OK,
                        "histogram: %s", lc_last_error());
            for (int i = 0; i < 64; i++)
                sum += h0[i];
            CHECK_QUIET(sum == count && memcmp(h0, h1, sizeof h0) == 0, "%s layout %d: %s and %s histograms differ", tn,
                        lay, var->label[0], var->label[1]);
        }
        for (int e = 0; e < nviews; e++) {
            const float *ref = refs + (size_t)e * W * H * 4;
            char label[160];
            for (int lay = 0; lay < 2; lay++) {
                if (!gs.g[0][lay] || !gs.g[1][lay]) continue;
                for (int m = 0; m < 2; m++) {
                    lc_method meth = m ? LC_METHOD_BRUTE : LC_METHOD_BVH;
                    const char *mn = m ? "brute" : "bvh";
                    render(dev, gs.g[0][lay], tf, &views[e], meth, 0, 0, a);
                    render(dev, gs.g[1][lay], tf, &views[e], meth, 0, 0, b);
                    snprintf(label, sizeof label, "%s_view%d_layout%d_%s_%s-ref", tn, e, lay, mn, var->label[0]);
                    CHECK_QUIET(cmp(label, a, ref, 0, 0, &w_ref) == 0, "%s", label);
                    snprintf(label, sizeof label, "%s_view%d_layout%d_%s_%s-%s", tn, e, lay, mn, var->label[0],
                             var->label[1]);
                    CHECK_QUIET(cmp(label, a, b, 0, 0, &w_same) == 0, "%s", label);
                    /* pre-integrated: both grids alike (the reference has no table) */
                    render(dev, gs.g[0][lay], tf, &views[e], meth, 0, 1, a);
                    render(dev, gs.g[1][lay], tf, &views[e], meth, 0, 1, b);
                    snprintf(label, sizeof label, "%s_view%d_layout%d_%s_preint_%s-%s", tn, e, lay, mn, var->label[0],
                             var->label[1]);
                    CHECK_QUIET(cmp(label, a, b, 0, 0, &w_pre) == 0, "%s", label);
                }
                /* the BVH with its default heuristics: test_grid's bound */
                render(dev, gs.g[0][lay], tf, &views[e], LC_METHOD_BVH, 1, 0, a);
                snprintf(label, sizeof label, "%s_view%d_layout%d_bvh-heuristics_%s-ref", tn, e, lay, var->label[0]);
                CHECK_QUIET(cmp(label, a, ref, IMGCMP_NO_MAX_BOUND, 40.0, &w_heur) == 0, "%s", label);
            }
        }
        if (show && gs.g[0][0]) {
            /* the comparison can fail: the same render against the reference of a
               perturbed volume (one block of voxels 40 higher) */
            vol p = *v;
            size_t n = (size_t)v->n[0] * v->n[1] * v->n[2];
            p.ref = malloc(n * sizeof(double));
            memcpy(p.ref, v->ref, n * sizeof(double));
            for (int k = v->n[2] / 3; k < v->n[2] / 2; k++)
                for (int j = v->n[1] / 3; j < 2 * v->n[1] / 3; j++)
                    for (int i = v->n[0] / 4; i < 3 * v->n[0] / 4; i++)
                        p.ref[((size_t)k * v->n[1] + j) * v->n[0] + i] += 40;
            ref_image(&p, &views[0], r);
            render(dev, gs.g[0][0], tf, &views[0], LC_METHOD_BVH, 0, 0, a);
            imgcmp_result res;
            int rc = imgcmp_check_ex("self-check_perturbed", a, r, W, H, 0, 0, NULL, 1, &res);
            CHECK(rc == 1, "%s: a perturbed volume's reference fails the comparison (max %.3f/255)", tn,
                  res.max_diff_255);
            free(p.ref);
        }
        for (int c = 0; c < 2; c++)
            for (int lay = 0; lay < 2; lay++)
                lc_volume_destroy(gs.g[c][lay]);
        lc_tf_destroy(tf);
        lc_device_destroy(dev);
    }
    free(a), free(b), free(r), free(refs);
}

int main(int argc, char **argv)
{
    for (size_t i = 0; i < sizeof variants / sizeof variants[0]; i++)
        if (argc > 1 && !strcmp(argv[1], variants[i].name)) var = &variants[i];
    if (!var) {
        fprintf(stderr, "usage: test_grid_copies nopairs|quads [OUTDIR]\n");
        return 2;
    }
    diff_dir = argc > 2 ? argv[2] : NULL;
    setvbuf(stdout, NULL, _IOLBF, 0);
    CHECK(lci_grid_quads_max == (int64_t)1 << 25 && lci_grid_pairs_max == (int64_t)1 << 30,
          "default copy bounds: quads up to 2^25 voxels (%lld), pairs up to 2^30 (%lld)", (long long)lci_grid_quads_max,
          (long long)lci_grid_pairs_max);
    /* odd sizes: outside, inside the volume, and an axis-aligned view down z */
    vol s;
    vol_make(&s, 37, 29, 41);
    gview vs[3] = {
        {{48, 42.5, 86}, {18, 14, 20}, 2}, {{20.3, 16.1, 14.7}, {18, 14, 20}, 1}, {{18, 14, 95}, {18, 14, 20}, 0}};
    check_volume(&s, vs, 3, 1);
    free(s.data), free(s.ref);
    /* 4 MiB of voxels and more: the huge-page allocation */
    vol b;
    vol_make(&b, 131, 127, 133);
    gview vb[2] = {{{170, 150, 300}, {65, 63, 66}, 2}, {{65, 63, 320}, {65, 63, 66}, 0}};
    check_volume(&b, vb, 2, 0);
    free(b.data), free(b.ref);
    /* rows of 1 KiB and more: the pair copy pads its rows and planes (padded_strides) */
    vol wd;
    vol_make(&wd, 601, 23, 19);
    gview vw[2] = {{{250, 60, 75}, {230, 11, 9}, 2}, {{212, 9.5, 10.2}, {260, 11, 9}, 1}};
    check_volume(&wd, vw, 2, 0);
    free(wd.data), free(wd.ref);
    char what[160];
    snprintf(what, sizeof what, "%s vs reference (heuristics off)", var->label[0]);
    imgcmp_worst_print(what, &w_ref);
    snprintf(what, sizeof what, "%s vs %s (heuristics off)", var->label[0], var->label[1]);
    imgcmp_worst_print(what, &w_same);
    snprintf(what, sizeof what, "pre-integrated, %s vs %s", var->label[0], var->label[1]);
    imgcmp_worst_print(what, &w_pre);
    snprintf(what, sizeof what, "%s, bvh with heuristics vs reference (PSNR >= 40 only)", var->label[0]);
    imgcmp_worst_print(what, &w_heur);
    printf("%s: %d failure(s)\n", check_failures ? "FAIL" : "ok", check_failures);
    return check_failures ? 1 : 0;
}
