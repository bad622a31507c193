/* The RBF set scenes of tests/test_rbf.c and tests/test_rbf_octree.c: random
 * sets (fixed seeds), one transfer function and camera, the reference image
 * through the independent reference core (tests/ref) and the library image,
 * so both tests build their scenes and compare them the same way. Include
 * once per test, after defining W and H (image size). */
#ifndef LC_TEST_RBF_SCENE_H
#define LC_TEST_RBF_SCENE_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "lanecast/lanecast.h"
#include "ref/ref_core.h"
#include "ref/ref_fields.h"

#define MAXN 400

typedef struct scene {
    const char *name;
    int n;
    float c[3 * MAXN], s[MAXN], w[MAXN];
    float bias, eps, dt;
    lc_box3 domain;
    int leaf, cell_max;
    lc_shading shade;
    lc_mode mode;
    float range[2];
    float iso;                /* iso: the iso value */
    int nplanes;              /* slice: planes[0 .. nplanes - 1], point and normal */
    float planes[2][6];
    const float *opacity;     /* the TF's opacity points [v, tau], nopacity of them; NULL: tf_opacity */
    int nopacity;
} scene;

static uint32_t seed;
static float rnd(float a, float b) { return a + (b - a) * (float)((seed = seed * 1664525u + 1013904223u) >> 8) / 16777216.0f; }

/* n RBFs: uniform in [-2, 2]^3, or (clustered) around 3 centres with spread
 * 0.5; widths s0..s1 (several sizes), weights w0..w1 (both signs), a weight
 * below 0.05 in magnitude replaced by wfloor so every term shows. */
static void fill(scene *sc, int n, int clustered, float s0, float s1, float w0, float w1, uint32_t sd, float wfloor)
{
    seed = sd;
    sc->n = n;
    const float cl[3][3] = {{-1.0f, -0.5f, 0.3f}, {0.9f, 0.6f, -0.4f}, {0.2f, 1.2f, 0.8f}};
    for (int i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++) sc->c[3 * i + k] = clustered ? cl[i % 3][k] + rnd(-0.5f, 0.5f) : rnd(-2.0f, 2.0f);
        sc->s[i] = rnd(s0, s1);
        sc->w[i] = rnd(w0, w1);
        if (fabsf(sc->w[i]) < 0.05f) sc->w[i] = wfloor;
    }
}

static lc_rbf_desc desc_of(const scene *sc, lc_rbf_accel a, int significant)
{
    lc_rbf_desc d = {.count = (size_t)sc->n, .centres = sc->c, .widths = sc->s, .weights = sc->w, .bias = sc->bias,
                     .eps = sc->eps, .domain = sc->domain, .leaf_size = sc->leaf, .accel = a,
                     .cell_max = a == LC_RBF_ACCEL_OCTREE ? sc->cell_max : 0, .significant = significant};
    return d;
}

/* The TF of every image: a heat ramp; opaque for negative values (v < 0.3),
 * faint near the bias values of the scenes, dense at the top. The faint part
 * keeps one lattice sample more or less at a box face (float against double
 * entry points) below 2/255. */
static const float tf_color[] = {0.0f, 0.1f, 0.2f, 0.9f, 0.4f, 0.8f, 0.2f, 0.1f, 1.0f, 1.0f, 0.95f, 0.6f};
static const float tf_opacity[] = {0.0f, 1.5f, 0.3f, 0.0f, 0.5f, 0.1f, 1.0f, 3.0f};
static const lc_camera cam = {LC_PERSPECTIVE, {0.7f, 1.1f, 9.0f}, {0.1f, -0.2f, 0.0f}, {0, 1, 0}, 40.0f, 0.0f};

static const float *opacity_of(const scene *sc) { return sc->opacity ? sc->opacity : tf_opacity; }
static int nopacity_of(const scene *sc) { return sc->opacity ? sc->nopacity : 4; }

/* The reference image of a scene (terms cut at eps), the support box or the
 * domain as clip box, in the scene's mode (dvr, mip, iso, slice); with depth
 * not NULL also ref_render_depth's depth and margin (iso, slice); 0 ok. */
static int ref_image_depth(const scene *sc, float eps, float *img, double *depth, double *margin)
{
    static double c[3 * MAXN], s[MAXN], w[MAXN];
    for (int i = 0; i < 3 * sc->n; i++) c[i] = sc->c[i];
    for (int i = 0; i < sc->n; i++) s[i] = sc->s[i], w[i] = sc->w[i];
    ref_rbf_set set = {(size_t)sc->n, c, s, w, sc->bias, eps};
    ref_source src;
    if (ref_rbf_source(&set, &src)) return -1;
    const lc_box3 *d = &sc->domain;
    if (d->lo.x != 0 || d->hi.x != 0) {
        const double lo[3] = {d->lo.x, d->lo.y, d->lo.z}, hi[3] = {d->hi.x, d->hi.y, d->hi.z};
        memcpy(src.lo, lo, sizeof lo), memcpy(src.hi, hi, sizeof hi);
    }
    double col[12], op[16];
    for (int i = 0; i < 12; i++) col[i] = tf_color[i];
    for (int i = 0; i < 2 * nopacity_of(sc); i++) op[i] = opacity_of(sc)[i];
    ref_tf tf = {sc->range[0], sc->range[1], col, 3, op, nopacity_of(sc)};
    static const ref_mode modes[] = {[LC_MODE_DVR] = REF_MODE_DVR, [LC_MODE_MIP] = REF_MODE_MIP,
                                     [LC_MODE_ISO] = REF_MODE_ISO, [LC_MODE_SLICE] = REF_MODE_SLICE};
    ref_params p = {.width = W, .height = H, .tf = &tf, .dt = sc->dt, .alpha_stop = 1.0,
                    .shading = (ref_shading)sc->shade, .mode = modes[sc->mode], .iso = sc->iso,
                    .nplanes = sc->nplanes};
    for (int i = 0; i < sc->nplanes; i++)
        for (int k = 0; k < 6; k++) p.planes[i][k] = sc->planes[i][k];
    p.camera.projection = REF_PERSPECTIVE;
    for (int k = 0; k < 3; k++) {
        p.camera.eye[k] = (&cam.eye.x)[k], p.camera.at[k] = (&cam.at.x)[k], p.camera.up[k] = (&cam.up.x)[k];
    }
    p.camera.fovy = cam.fovy;
    if (depth && ref_render_depth(&src, &p, depth, margin)) return -1;
    return ref_render_f(&src, &p, img);
}

static int ref_image(const scene *sc, float eps, float *img) { return ref_image_depth(sc, eps, img, NULL, NULL); }

/* Renders a scene on dev with method m; 0 ok. */
static int render(lc_device *dev, const lc_volume *v, const scene *sc, lc_method m, float *img, lc_render_stats *st)
{
    lc_tf_field f = {tf_color, 3, opacity_of(sc), nopacity_of(sc), 1, {sc->range[0], sc->range[1]}};
    lc_tf *tf = NULL;
    if (lc_tf_create(dev, &f, 1, &tf) != LC_OK) return -1;
    lc_render_desc rd = {.width = W, .height = H, .camera = cam, .tf = tf, .volume = v, .dt = sc->dt,
                         .alpha_stop = 1.0f, .shading = sc->shade, .method = m, .mode = sc->mode,
                         .iso = sc->iso, .nplanes = sc->nplanes};
    for (int i = 0; i < sc->nplanes; i++)
        rd.planes[i] = (lc_plane){{sc->planes[i][0], sc->planes[i][1], sc->planes[i][2]},
                                  {sc->planes[i][3], sc->planes[i][4], sc->planes[i][5]}};
    lc_status s = lc_render(dev, &rd, img, st);
    lc_tf_destroy(tf);
    return s == LC_OK ? 0 : -1;
}

#endif
