/* Owned linear voxels (uint16, int16, float32) pad rows of 1 KiB
 * and more and planes of 4 KiB and more to an odd number of 64-byte lines
 * (host/kinds/grid_layout.c lci_grid_padded_strides, the pair copy's rule), and every reader
 * honours the strides: the kernels (dvr, BVH and brute force, mip, iso,
 * lc_volume_sample) and lc_grid_histogram. Per value type, a 601 x 23 x 19
 * volume (rows of 1202 or 2404 bytes: padded) owned and linear, against the
 * reference core (tests/ref) at SPEC.md tolerances and against the same array
 * borrowed (used in place, unpadded): images equal bit for bit, histograms
 * and samples equal; a 300-wide uint16 volume (600-byte rows) keeps its
 * rows and pads its planes. On every target. A reference of a perturbed volume must fail.
 * usage: test_grid_padded [OUTDIR]   (diff images of failures go to OUTDIR) */
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

enum { W = 41, H = 37 };

static const char *diff_dir;
static imgcmp_worst w_ref = IMGCMP_WORST_INIT, w_same = IMGCMP_WORST_INIT;

/* two soft blobs and a shell in [0, 1], 0 (air) below 12/255 */
static double field(double x, double y, double z)
{
    double a = exp(-((x - 0.35) * (x - 0.35) + (y - 0.4) * (y - 0.4) + (z - 0.5) * (z - 0.5)) / 0.02);
    double b = exp(-((x - 0.65) * (x - 0.65) + (y - 0.6) * (y - 0.6) + (z - 0.45) * (z - 0.45)) / 0.01);
    double r = sqrt((x - 0.5) * (x - 0.5) + (y - 0.5) * (y - 0.5) + (z - 0.5) * (z - 0.5));
    double shell = r > 0.38 && r < 0.45 ? 0.5 + 0.3 * sin(20 * x) * cos(17 * y) : 0;
    double v = fmax(fmax(a, b), shell);
    return v < 12.0 / 255 ? 0 : v;
}

typedef struct vol {
    int n[3];
    lc_value_type type;
    double lo, hi; /* the TF's range: the type's image of [0, 1] */
    void *data;
    double *ref;
} vol;

static void vol_make(vol *v, int nx, int ny, int nz, lc_value_type t)
{
    v->n[0] = nx, v->n[1] = ny, v->n[2] = nz, v->type = t;
    v->lo = t == LC_VALUE_INT16 ? -32768 : 0;
    v->hi = t == LC_VALUE_FLOAT32 ? 1 : v->lo + 65535;
    size_t n = (size_t)nx * ny * nz;
    v->data = malloc(n * (size_t)lci_value_size(t));
    v->ref = malloc(n * sizeof(double));
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++) {
                size_t id = ((size_t)k * ny + j) * nx + i;
                double f = field((double)i / (nx - 1), (double)j / (ny - 1), (double)k / (nz - 1));
                long q = lround(f * 65535);
                if (t == LC_VALUE_UINT16)
                    ((uint16_t *)v->data)[id] = (uint16_t)q, v->ref[id] = (double)q;
                else if (t == LC_VALUE_INT16)
                    ((int16_t *)v->data)[id] = (int16_t)(q - 32768), v->ref[id] = (double)(q - 32768);
                else
                    ((float *)v->data)[id] = (float)f, v->ref[id] = (float)f;
            }
}

static const char *type_label(const vol *v)
{
    return v->type == LC_VALUE_UINT16 ? "uint16" : v->type == LC_VALUE_INT16 ? "int16" : "float32";
}

/* mode: 0 dvr, 1 mip, 2 iso at 40% of the range */
static void render(lc_device *dev, lc_volume *g, const lc_tf *tf, const vol *v, const gview *vw, lc_method m, int mode,
                   float *out)
{
    lc_render_desc d = gscene_desc(g, tf, vw, W, H, m, v->lo, v->hi);
    d.mode = mode == 1 ? LC_MODE_MIP : mode == 2 ? LC_MODE_ISO : LC_MODE_DVR;
    d.iso = (float)(v->lo + 0.4 * (v->hi - v->lo));
    lc_grid_params gp = {.delta_c = -1, .delta_p = -1, .delta_sv = -1};
    CHECK_QUIET(lc_grid_set_params(g, &gp) == LC_OK, "lc_grid_set_params: %s", lc_last_error());
    CHECK_QUIET(lc_render(dev, &d, out, NULL) == LC_OK, "render: %s", lc_last_error());
}

static void ref_image(const vol *v, const double *values, const gview *vw, float *out)
{
    gscene_ref(v->n, values, v->lo, v->hi, vw, W, H, out);
}

static int cmp(const char *label, const float *got, const float *want, imgcmp_worst *w)
{
    imgcmp_result r;
    int rc = imgcmp_check_ex(label, got, want, W, H, 0, 0, diff_dir, 1, &r);
    if (rc >= 0 && w) imgcmp_worst_add(w, &r);
    if (rc != 0) printf("%s: max %.3f/255 psnr %.1f\n", label, r.max_diff_255, r.psnr_db);
    return rc;
}

/* strides the rule gives: odd whole lines from 1 KiB rows and 4 KiB planes, else unpadded */
static int strides_ok(const lc_kgrid *k, int es, int padded)
{
    int64_t ys = k->ystride, zs = k->zstride, nx = k->size[0], ny = k->size[1];
    if (!padded) return ys == nx && zs == nx * ny;
    int rows = nx * es >= 1024 ? ys >= nx && ys * es % 64 == 0 && (ys * es / 64) % 2 == 1 : ys == nx;
    int planes = ys * ny * es >= 4096 ? zs >= ys * ny && zs * es % 64 == 0 && (zs * es / 64) % 2 == 1 : zs == ys * ny;
    return rows && planes;
}

static void check_volume(const vol *v, const gview *views, int nviews, int show)
{
    size_t img = (size_t)W * H * 4, count = (size_t)v->n[0] * v->n[1] * v->n[2];
    int es = lci_value_size(v->type);
    float *a = malloc(sizeof(float) * img), *b = malloc(sizeof(float) * img), *r = malloc(sizeof(float) * img);
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        if (!lc_target_compiled((lc_target)t) || !lc_target_supported((lc_target)t)) continue;
        const char *tn = lc_target_name((lc_target)t);
        lc_device *dev = NULL;
        if (lc_device_create(&(lc_device_desc){.target = (lc_target)t, .threads = 2}, &dev) != LC_OK) continue;
        lc_tf_field tff = {.color = gscene_color, .ncolor = 3, .opacity = gscene_opacity, .nopacity = 4};
        lc_tf *tf = NULL;
        CHECK_QUIET(lc_tf_create(dev, &tff, 1, &tf) == LC_OK, "tf: %s", lc_last_error());
        lc_volume *g[2] = {NULL, NULL}; /* [0] owned linear (padded), [1] borrowed (the caller's strides) */
        for (int c = 0; c < 2; c++) {
            lc_grid_desc gd = {.size = {v->n[0], v->n[1], v->n[2]},
                               .type = v->type,
                               .data = v->data,
                               .layout = LC_LAYOUT_LINEAR,
                               .borrow = c};
            CHECK_QUIET(lc_grid_create(dev, &gd, &g[c]) == LC_OK, "create: %s", lc_last_error());
        }
        if (!g[0] || !g[1]) goto next;
        const lc_kgrid *k0 = &((const grid *)g[0])->kg, *k1 = &((const grid *)g[1])->kg;
        CHECK_QUIET(strides_ok(k0, es, 1) && strides_ok(k1, es, 0),
                    "%s: strides %d / %d owned, %d / %d borrowed for %dx%d", tn, k0->ystride, k0->zstride, k1->ystride,
                    k1->zstride, v->n[0], v->n[1]);
        lc_grid_info in = {0};
        lc_grid_get_info(g[0], &in);
        uint64_t tables = sizeof(int32_t) * ((uint64_t)v->n[0] + v->n[1] + v->n[2]);
        CHECK_QUIET(in.layout_bytes == tables + (uint64_t)es * (uint64_t)k0->zstride * (uint64_t)v->n[2] + 64 &&
                        in.layout_overhead_bytes == in.layout_bytes - in.data_bytes,
                    "%s: layout_bytes %llu for strides %d / %d", tn, (unsigned long long)in.layout_bytes, k0->ystride,
                    k0->zstride);
        /* histogram (lc_tf_auto's input) */
        uint64_t h0[97], h1[97], sum = 0;
        CHECK_QUIET(lc_grid_histogram(g[0], 97, h0) == LC_OK && lc_grid_histogram(g[1], 97, h1) == LC_OK,
                    "histogram: %s", lc_last_error());
        for (int i = 0; i < 97; i++)
            sum += h0[i];
        CHECK_QUIET(sum == count && !memcmp(h0, h1, sizeof h0), "%s: owned and borrowed histograms differ", tn);
        /* lc_volume_sample at every node of a few rows and planes, and between nodes */
        enum { NP = 4096 };
        float *pts = malloc(sizeof(float) * 3 * NP), *s0 = malloc(sizeof(float) * 2 * NP), *s1 = s0 + NP;
        float *gr0 = malloc(sizeof(float) * 6 * NP), *gr1 = gr0 + 3 * NP;
        uint32_t lcg = 7u;
        int bad = 0;
        for (int p = 0; p < NP; p++) {
            int node = p < NP / 2;
            for (int ax = 0; ax < 3; ax++) {
                lcg = lcg * 1664525u + 1013904223u;
                double u = (double)(lcg >> 8) / 16777216.0 * (v->n[ax] - 1);
                pts[3 * p + ax] = (float)(node ? floor(u) : u);
            }
        }
        CHECK_QUIET(lc_volume_sample(dev, g[0], NP, pts, s0, gr0) == LC_OK &&
                        lc_volume_sample(dev, g[1], NP, pts, s1, gr1) == LC_OK,
                    "lc_volume_sample: %s", lc_last_error());
        for (int p = 0; p < NP; p++) {
            int node = p < NP / 2;
            size_t id = ((size_t)pts[3 * p + 2] * v->n[1] + (size_t)pts[3 * p + 1]) * v->n[0] + (size_t)pts[3 * p];
            if (s0[p] != s1[p] || memcmp(gr0 + 3 * p, gr1 + 3 * p, 3 * sizeof(float)) ||
                (node && s0[p] != (float)v->ref[id]))
                bad++;
        }
        CHECK_QUIET(!bad, "%s: %d of %d samples differ between owned and borrowed (or from the voxel)", tn, bad, NP);
        free(pts), free(s0), free(gr0);
        for (int e = 0; e < nviews; e++) {
            char label[160];
            ref_image(v, v->ref, &views[e], r);
            for (int m = 0; m < 2; m++) {
                lc_method meth = m ? LC_METHOD_BRUTE : LC_METHOD_BVH;
                const char *mn = m ? "brute" : "bvh";
                for (int mode = 0; mode < 3; mode++) {
                    render(dev, g[0], tf, v, &views[e], meth, mode, a);
                    render(dev, g[1], tf, v, &views[e], meth, mode, b);
                    if (mode == 0) {
                        snprintf(label, sizeof label, "padded_%s_%s_view%d_%s-ref", tn, type_label(v), e, mn);
                        CHECK_QUIET(cmp(label, a, r, &w_ref) == 0, "%s", label);
                    }
                    snprintf(label, sizeof label, "padded_%s_%s_view%d_%s_mode%d_owned-borrowed", tn, type_label(v), e,
                             mn, mode);
                    imgcmp_result res;
                    int rc = imgcmp_check_ex(label, a, b, W, H, 0, 0, diff_dir, 1, &res);
                    if (rc >= 0) imgcmp_worst_add(&w_same, &res);
                    CHECK_QUIET(rc == 0 && !memcmp(a, b, sizeof(float) * img), "%s: not the same bits (max %.3f/255)",
                                label, res.max_diff_255);
                }
            }
        }
        if (show) {
            /* the comparison can fail: the reference of a perturbed volume */
            double *pr = malloc(count * sizeof(double));
            memcpy(pr, v->ref, count * sizeof(double));
            for (int kk = v->n[2] / 3; kk < v->n[2] / 2; kk++)
                for (int j = v->n[1] / 3; j < 2 * v->n[1] / 3; j++)
                    for (int i = v->n[0] / 4; i < 3 * v->n[0] / 4; i++)
                        pr[((size_t)kk * v->n[1] + j) * v->n[0] + i] += 0.15 * (v->hi - v->lo);
            ref_image(v, pr, &views[0], r);
            render(dev, g[0], tf, v, &views[0], LC_METHOD_BVH, 0, a);
            imgcmp_result res;
            CHECK(imgcmp_check_ex("self-check_perturbed", a, r, W, H, 0, 0, NULL, 1, &res) == 1,
                  "%s: a perturbed volume's reference fails the comparison (max %.3f/255)", tn, res.max_diff_255);
            free(pr);
        }
    next:
        lc_volume_destroy(g[0]);
        lc_volume_destroy(g[1]);
        lc_tf_destroy(tf);
        lc_device_destroy(dev);
    }
    free(a), free(b), free(r);
}

int main(int argc, char **argv)
{
    diff_dir = argc > 1 ? argv[1] : NULL;
    setvbuf(stdout, NULL, _IOLBF, 0);
    /* rows of 1202 (uint16, int16) and 2404 bytes (float32): rows and planes padded */
    gview vw[2] = {{{250, 60, 75}, {230, 11, 9}, 2}, {{212, 9.5, 10.2}, {260, 11, 9}, 1}};
    const lc_value_type types[3] = {LC_VALUE_UINT16, LC_VALUE_INT16, LC_VALUE_FLOAT32};
    for (int t = 0; t < 3; t++) {
        vol v;
        vol_make(&v, 601, 23, 19, types[t]);
        check_volume(&v, vw, 2, t == 0);
        free(v.data), free(v.ref);
    }
    /* 600-byte rows: unpadded rows, padded planes */
    vol s;
    vol_make(&s, 300, 29, 17, LC_VALUE_UINT16);
    gview vs[1] = {{{330, 60, 60}, {150, 14, 8}, 2}};
    check_volume(&s, vs, 1, 0);
    free(s.data), free(s.ref);
    imgcmp_worst_print("padded owned linear vs reference (heuristics off)", &w_ref);
    imgcmp_worst_print("padded owned vs borrowed (dvr, mip, iso)", &w_same);
    printf("%s: %d failure(s)\n", check_failures ? "FAIL" : "ok", check_failures);
    return check_failures ? 1 : 0;
}
