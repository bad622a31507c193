/* Particle parts for data-parallel rendering (host/mpi/pwindow.c,
 * partition.c) in one process: for P = 1..4 regions, each region's part
 * holds the particles whose support (grown by two steps) reaches its cell,
 * made the whole set to the frame (lci_dp_particles_create with the whole
 * set's extremes); with canonical_order (whole set and parts) the regions
 * rendered from the parts and composited equal the same regions rendered
 * from the whole set bit for bit (memcmp; dvr, mip, iso, slice; Gaussian
 * with varying radii, an SPH kernel and the normalised interpolant through
 * the direct method; views from outside, eye inside the data, orthographic,
 * along an axis, and along and across the root's split plane from either
 * side), and with Embree's build (canonical_order 0) some differ in their
 * bits (each part's BVH sums a sample's particles in another order: the
 * check can fail). With the ghosts cut (margin 0; the Gaussian
 * also 0.4 of the reach) the dvr image differs by more than an 8-bit step. The distributed selection (lci_kd_build_dist) gives the
 * splits of the sort (lci_kd_build). A set of 2 particles over 4 regions
 * (regions owning none, holding only ghosts); a part renders only under a region, and a larger
 * sigma or longer step than its ghosts serve is refused. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "host/mpi/dp.h"
#include "imgcmp.h"
#include "dp_scene.h"

enum { W = 40, H = 30, NMAX = 600 };

static uint32_t rng = 12345u;
static float urand(void)
{
    rng = rng * 1664525u + 1013904223u;
    return (float)(rng >> 8) / 16777216.0f;
}

typedef struct set {
    size_t n;
    float xyz[3 * NMAX], r[NMAX], k[NMAX], w[NMAX];
    uint8_t f[NMAX];
} set;

static void make_set(set *s, size_t n)
{
    s->n = n;
    for (size_t i = 0; i < n; i++) {
        /* clustered towards one corner: the kd splits are not the box's halves */
        for (int a = 0; a < 3; a++) s->xyz[3 * i + a] = 1.6f * urand() * urand() - 0.8f;
        s->r[i] = 0.06f + 0.1f * urand();
        s->k[i] = 0.5f + urand();
        s->w[i] = 0.2f + urand(); /* m_i / rho_i of the normalised interpolant */
        s->f[i] = (uint8_t)(i % 2);
    }
}

static lc_particles_desc desc_of(const set *s, lc_kernel kernel)
{
    return (lc_particles_desc){.count = s->n, .positions = s->xyz, .radii = s->r, .values = s->k, .fields = s->f,
                               .nfields = 2, .params = {.kernel = kernel}, .canonical_order = 1};
}

/* The P parts of the whole set for a step dt, ghosts reaching margin times as far. */
static int make_parts(lc_device *dev, const lc_particles_desc *whole_desc, const lc_volume *whole, int P, float dt,
                      float margin, lc_volume **parts, size_t *held)
{
    lci_kdtree t;
    lc_render_desc d = {.volume = whole, .width = W, .height = H};
    if (lci_dp_partition(dev, &d, P, &t) != LC_OK) return -1;
    lci_particles_global g;
    lci_particles_extremes(whole, &g);
    lc_particles_info pi;
    lc_particles_get_info(whole, &pi);
    float support = pi.params.kernel == LC_KERNEL_GAUSSIAN ? pi.params.sigma : 1.0f;
    int ok = 1;
    for (int r = 0; r < P && ok; r++) {
        lc_particles_desc cut;
        lci_dp_ppart pp = {.parts = P, .part = r, .support = support, .dt = dt};
        ok = lci_dp_particles_cut(dev, whole_desc, &t, r, support, dt, margin, &cut) == LC_OK &&
             lci_kd_copy(dev, &t, &pp.tree) == LC_OK;
        if (!ok) break;
        held[r] = cut.count;
        ok = lci_dp_particles_create(dev, &cut, &g, &pp, &parts[r]) == LC_OK;
        lci_dp_particles_free(&cut);
    }
    lci_kd_release(&t);
    if (!ok) CHECK(0, "P=%d parts: %s", P, lc_device_last_error(dev));
    return ok ? 0 : -1;
}

/* The views: dp_views, then four about the root split plane of P regions
 * (eye on the plane looking along it, from either end; eye on either side
 * looking across it). */
enum { NVIEWS = DP_NVIEWS + 4 };
static const char *const view_names[NVIEWS] = {"outside", "eye-inside", "ortho", "axis",
                                               "along-split", "along-split-back", "across-split-lo", "across-split-hi"};

static lc_camera view_of(lc_device *dev, const lc_volume *whole, int P, int vi)
{
    if (vi < DP_NVIEWS) return dp_views[vi];
    lci_kdtree t;
    lc_render_desc d = {.volume = whole, .width = W, .height = H};
    int axis = 0;
    float split = 0.0f;
    if (P > 1 && lci_dp_partition(dev, &d, P, &t) == LC_OK) {
        axis = t.node[0].axis, split = t.node[0].split;
        lci_kd_release(&t);
    }
    int other = (axis + 1) % 3;
    lc_camera c = {LC_PERSPECTIVE, {0.05f, 0.1f, 0.02f}, {0.05f, 0.1f, 0.02f}, {0, 0, 0}, 50.0f, 0.0f};
    float *eye = &c.eye.x, *at = &c.at.x, *up = &c.up.x;
    up[(axis + 2) % 3] = 1.0f;
    eye[axis] = at[axis] = split;
    if (vi < DP_NVIEWS + 2) { /* on the plane */
        eye[other] = vi == DP_NVIEWS ? 3.0f : -3.0f;
    } else { /* beside it, looking across */
        eye[axis] = split + (vi == DP_NVIEWS + 2 ? -2.5f : 2.5f);
        eye[other] += 0.4f;
    }
    return c;
}

/* Regions of the parts composited against the whole set's regions: max
 * |diff|; check: they must be the same bits. bits_differ counts the images
 * whose bits differ. */
static int bits_differ;

static double region_diff(lc_device *dev, const lc_volume *whole, lc_volume *const *parts, int P, const lc_tf *tf,
                          lc_mode mode, int vi, float dt, int check, const char *label)
{
    lc_render_desc d = dp_desc(whole, tf, mode, 0, 1.0f, W, H, 0.5f);
    d.camera = view_of(dev, whole, P, vi);
    d.dt = dt;
    size_t np = (size_t)W * H;
    float *want = malloc(sizeof(float) * 4 * np), *got = malloc(sizeof(float) * 4 * np);
    lc_status s = lci_dp_render_local(dev, &d, P, want, NULL, NULL);
    if (s == LC_OK) s = dp_render_parts(dev, &d, parts, P, got);
    double e = -1.0;
    CHECK_QUIET(s == LC_OK, "%s: %s", label, lc_device_last_error(dev));
    if (s == LC_OK) {
        e = 0.0;
        for (size_t i = 0; i < 4 * np; i++) e = fmax(e, fabs((double)got[i] - (double)want[i]));
        if (check)
            CHECK_QUIET(!memcmp(got, want, sizeof(float) * 4 * np),
                        "%s: not the whole set's regions to the bit (max |diff| %.3g)", label, e);
        bits_differ += memcmp(got, want, sizeof(float) * 4 * np) != 0;
    }
    free(want), free(got);
    return e;
}

static void destroy_parts(lc_volume **parts, int P)
{
    for (int r = 0; r < P; r++) lc_volume_destroy(parts[r]), parts[r] = NULL;
}

/* lci_kd_build_dist with one holder (the sum is the count itself) against lci_kd_build. */
static lc_status sum_one(void *user, uint64_t *v, int n)
{
    (void)user, (void)v, (void)n;
    return LC_OK;
}

static void check_selection(lc_device *dev, const set *s)
{
    float *x = malloc(4 * s->n), *y = malloc(4 * s->n), *z = malloc(4 * s->n);
    for (size_t i = 0; i < s->n; i++) x[i] = s->xyz[3 * i], y[i] = s->xyz[3 * i + 1], z[i] = s->xyz[3 * i + 2];
    x[3] = -0.0f, x[4] = 0.0f, y[5] = y[6]; /* signed zeros and ties */
    lc_box3 b = {{-1, -1, -1}, {1, 1, 1}};
    const lci_kd_peers one = {sum_one, NULL, NULL};
    int same = 1;
    for (int P = 1; P <= 64; P = P < 8 ? P + 1 : 2 * P) {
        lci_kdtree a, d;
        if (lci_kd_build(dev, &b, P, s->n, x, y, z, NULL, &a) != LC_OK ||
            lci_kd_build_dist(dev, &b, P, s->n, x, y, z, &one, &d) != LC_OK) {
            same = 0;
            break;
        }
        for (int i = 0; i < a.nnodes; i++)
            same &= a.node[i].axis == d.node[i].axis && a.node[i].split == d.node[i].split;
        same &= !memcmp(a.weight, d.weight, sizeof(uint64_t) * (size_t)P);
        lci_kd_release(&a), lci_kd_release(&d);
    }
    CHECK(same, "distributed selection: the splits and weights of the sort for P = 1..8, 16, 32, 64");
    free(x), free(y), free(z);
}

/* The normalised SPH interpolant (params.normalise, norm_weights m_i / rho_i
 * carried into each part): the parts' regions equal the whole set's in
 * every mode and view, and a part's default range is the whole set's (the
 * A_i = k_i / w_i over every part). */
static void check_normalised(lc_device *dev, const set *s, const float *col, const float *op)
{
    lc_particles_desc wd = desc_of(s, LC_KERNEL_M4);
    wd.norm_weights = s->w, wd.params.normalise = 1;
    lc_volume *whole = NULL;
    if (lc_particles_create(dev, &wd, &whole) != LC_OK) {
        CHECK(0, "normalised set: %s", lc_device_last_error(dev));
        return;
    }
    lc_volume_info vi;
    lc_volume_get_info(whole, &vi);
    lc_tf_field tff[2] = {{col, 3, op, 3, 1, {vi.range[0], vi.range[1]}}, {col, 3, op, 3, 1, {vi.range[0], vi.range[1]}}};
    lc_tf *tf = NULL;
    lc_tf_create(dev, tff, 2, &tf);
    int before = check_failures;
    for (int P = 1; P <= 4; P++) {
        lc_volume *parts[4] = {0};
        size_t held[4] = {0};
        if (make_parts(dev, &wd, whole, P, 0.02f, 1.0f, parts, held) != 0) continue;
        for (int r = 0; r < P; r++) {
            lc_volume_info pv;
            lc_volume_get_info(parts[r], &pv);
            CHECK_QUIET(pv.range[0] == vi.range[0] && pv.range[1] == vi.range[1],
                        "normalised P=%d part %d: range [%g, %g], the whole set's [%g, %g]", P, r,
                        (double)pv.range[0], (double)pv.range[1], (double)vi.range[0], (double)vi.range[1]);
        }
        static const lc_mode modes[] = {LC_MODE_DVR, LC_MODE_MIP, LC_MODE_ISO, LC_MODE_SLICE};
        for (int m = 0; m < 4; m++)
            for (int v = 0; v < NVIEWS; v++) {
                char label[96];
                snprintf(label, sizeof label, "m4 normalised %s %s P=%d", dp_mode_names[m], view_names[v], P);
                region_diff(dev, whole, parts, P, tf, modes[m], v, 0.02f, 1, label);
            }
        destroy_parts(parts, P);
    }
    CHECK(check_failures == before,
          "m4 normalised: the parts of P = 1..4 carry the norm weights and render the whole set's regions "
          "(dvr, mip, iso, slice; 8 views) with its range, bit for bit");
    lc_tf_destroy(tf);
    lc_volume_destroy(whole);
}

/* Embree's build (canonical_order -1) for the whole set and its parts: some
 * regions' sums add their terms in another order, so some images differ in
 * their bits from the whole set's (what the bit-for-bit checks above would
 * catch), within float rounding (1e-5). */
static void check_embree_order(lc_device *dev, const set *s, const float *col, const float *op)
{
    lc_particles_desc wd = desc_of(s, LC_KERNEL_GAUSSIAN);
    wd.canonical_order = -1;
    lc_volume *whole = NULL;
    if (lc_particles_create(dev, &wd, &whole) != LC_OK) {
        CHECK(0, "embree-ordered set: %s", lc_device_last_error(dev));
        return;
    }
    lc_volume_info vi;
    lc_volume_get_info(whole, &vi);
    lc_tf_field tff[2] = {{col, 3, op, 3, 1, {vi.range[0], vi.range[1]}}, {col, 3, op, 3, 1, {vi.range[0], vi.range[1]}}};
    lc_tf *tf = NULL;
    lc_tf_create(dev, tff, 2, &tf);
    int cases = 0, before = bits_differ;
    double worst = 0.0;
    for (int P = 2; P <= 4; P++) {
        lc_volume *parts[4] = {0};
        size_t held[4] = {0};
        if (make_parts(dev, &wd, whole, P, 0.02f, 1.0f, parts, held) != 0) continue;
        for (int m = 0; m < 4; m++)
            for (int v = 0; v < NVIEWS; v++, cases++)
                worst = fmax(worst, region_diff(dev, whole, parts, P, tf, (lc_mode)m, v, 0.02f, 0, "embree order"));
        destroy_parts(parts, P);
    }
    CHECK(bits_differ > before && worst < 1e-5,
          "Embree's build: %d of %d images of P = 2..4 differ in their bits from the whole set's regions "
          "(max |diff| %.3g: rounding), so the checks above can fail",
          bits_differ - before, cases, worst);
    lc_tf_destroy(tf);
    lc_volume_destroy(whole);
}

int main(void)
{
    lc_device *dev;
    lc_device_create(&(lc_device_desc){.threads = 2}, &dev);
    static set s, tiny;
    make_set(&s, 500);
    make_set(&tiny, 2); /* far apart and small: regions reached by neither */
    const float two[6] = {-0.7f, -0.6f, -0.5f, 0.7f, 0.6f, 0.5f};
    memcpy(tiny.xyz, two, sizeof two), tiny.r[0] = tiny.r[1] = 0.05f;
    check_selection(dev, &s);
    static const float col[] = {0.0f, 0.1f, 0.2f, 0.9f, 0.5f, 1.0f, 0.4f, 0.1f, 1.0f, 1.0f, 1.0f, 0.8f};
    static const float op[] = {0.0f, 0.0f, 0.2f, 1.0f, 1.0f, 4.0f};
    static const lc_kernel kernels[] = {LC_KERNEL_GAUSSIAN, LC_KERNEL_WENDLAND_C2};
    for (int kc = 0; kc < 2; kc++) {
        lc_particles_desc wd = desc_of(&s, kernels[kc]);
        lc_volume *whole = NULL;
        if (lc_particles_create(dev, &wd, &whole) != LC_OK) {
            CHECK(0, "whole set: %s", lc_device_last_error(dev));
            continue;
        }
        lc_volume_info vi;
        lc_volume_get_info(whole, &vi);
        lc_tf_field tff[2] = {{col, 3, op, 3, 1, {vi.range[0], vi.range[1]}}, {col, 3, op, 3, 1, {vi.range[0], vi.range[1]}}};
        lc_tf *tf = NULL;
        lc_tf_create(dev, tff, 2, &tf);
        const float dt = 0.02f;
        int before = check_failures;
        for (int P = 1; P <= 4; P++) {
            lc_volume *parts[4] = {0};
            size_t held[4] = {0};
            if (make_parts(dev, &wd, whole, P, dt, 1.0f, parts, held) != 0) continue;
            for (int r = 0; P > 1 && r < P; r++)
                CHECK_QUIET(held[r] < s.n, "P=%d: part %d holds %zu of %zu particles", P, r, held[r], s.n);
            lc_volume_info pv;
            lc_volume_get_info(parts[P - 1], &pv);
            CHECK_QUIET(!memcmp(&pv.bounds, &vi.bounds, sizeof pv.bounds) && pv.range[0] == vi.range[0] &&
                            pv.range[1] == vi.range[1] && pv.nfields == vi.nfields,
                        "P=%d: a part's bounds, range or fields differ from the whole set's", P);
            static const lc_mode modes[] = {LC_MODE_DVR, LC_MODE_MIP, LC_MODE_ISO, LC_MODE_SLICE};
            for (int m = 0; m < 4; m++)
                for (int v = 0; v < NVIEWS; v++) {
                    char label[96];
                    snprintf(label, sizeof label, "%s %s %s P=%d", kc ? "wendland-c2" : "gaussian", dp_mode_names[m],
                             view_names[v], P);
                    region_diff(dev, whole, parts, P, tf, modes[m], v, dt, 1, label);
                }
            destroy_parts(parts, P);
            if (P < 2) continue;
            /* without ghosts, or with too short a reach, a boundary shows */
            static const float margins[] = {0.0f, 0.4f};
            for (int g = 0; g < (kc ? 1 : 2); g++) {
                if (make_parts(dev, &wd, whole, P, dt, margins[g], parts, held) != 0) continue;
                double e = region_diff(dev, whole, parts, P, tf, LC_MODE_DVR, 0, dt, 0, "cut ghosts");
                CHECK_QUIET(e > 1.0 / 255.0, "%s P=%d ghost margin %g: max |diff| %.3g, expected a seam",
                            kc ? "wendland-c2" : "gaussian", P, (double)margins[g], e);
                destroy_parts(parts, P);
            }
        }
        CHECK(check_failures == before,
              "%s: parts of P = 1..4 regions hold fewer particles, report the whole set, and render its regions "
              "bit for bit (dvr, mip, iso, slice; 8 views); a ghost margin of 0 (Gaussian: and 0.4) shows seams",
              kc ? "wendland-c2" : "gaussian");
        if (kc == 0) {
            lc_volume *parts[4] = {0};
            size_t held[4] = {0};
            if (make_parts(dev, &wd, whole, 2, dt, 1.0f, parts, held) == 0) {
                lc_render_desc d = dp_desc(parts[0], tf, LC_MODE_DVR, 0, 1.0f, 8, 8, 0.0f);
                d.dt = dt;
                float img[4 * 64];
                lc_status st = lc_render(dev, &d, img, NULL);
                CHECK(st == LC_ERROR_INVALID_ARGUMENT && strstr(lc_device_last_error(dev), "lc_mpi_render"),
                      "lc_render of a part is refused: %s", lc_device_last_error(dev));
                lci_kdtree t;
                lci_cimage im;
                lci_dp_partition(dev, &d, 2, &t);
                d.dt = 0.05f;
                st = lci_dp_render_region(dev, &d, &t, 0, &im, NULL);
                CHECK(st == LC_ERROR_INVALID_ARGUMENT && strstr(lc_device_last_error(dev), "longer"),
                      "a step longer than the ghosts serve is refused: %s", lc_device_last_error(dev));
                d.dt = dt;
                lc_particles_set_params(parts[0], &(lc_particle_params){.sigma = 3.0f});
                st = lci_dp_render_region(dev, &d, &t, 0, &im, NULL);
                CHECK(st == LC_ERROR_INVALID_ARGUMENT && strstr(lc_device_last_error(dev), "support"),
                      "a larger sigma than the ghosts serve is refused: %s", lc_device_last_error(dev));
                lci_kd_release(&t);
                destroy_parts(parts, 2);
            }
        }
        lc_tf_destroy(tf);
        lc_volume_destroy(whole);
    }
    check_normalised(dev, &s, col, op);
    check_embree_order(dev, &s, col, op);
    /* more regions than particles: regions owning none */
    lc_particles_desc td = desc_of(&tiny, LC_KERNEL_GAUSSIAN);
    lc_volume *whole = NULL, *parts[4] = {0};
    size_t held[4] = {0};
    if (lc_particles_create(dev, &td, &whole) == LC_OK && make_parts(dev, &td, whole, 4, 0.02f, 1.0f, parts, held) == 0) {
        lc_volume_info vi;
        lc_volume_get_info(whole, &vi);
        lc_tf_field tff[2] = {{col, 3, op, 3, 1, {vi.range[0], vi.range[1]}}, {col, 3, op, 3, 1, {vi.range[0], vi.range[1]}}};
        lc_tf *tf = NULL;
        lc_tf_create(dev, tff, 2, &tf);
        int before = check_failures, empty = 0;
        lci_kdtree t;
        lc_render_desc pd = {.volume = parts[0]};
        if (lci_dp_partition(dev, &pd, 4, &t) == LC_OK) {
            for (int r = 0; r < 4; r++) empty += t.weight[r] == 0;
            lci_kd_release(&t);
        }
        for (int m = 0; m < 4; m++) region_diff(dev, whole, parts, 4, tf, (lc_mode)m, 0, 0.02f, 1, "2 particles, P=4");
        CHECK(check_failures == before && empty > 0,
              "2 particles over 4 regions (%d own none): the whole set's image in every mode", empty);
        lc_tf_destroy(tf);
        destroy_parts(parts, 4);
    } else
        CHECK(0, "2 particles: %s", lc_device_last_error(dev));
    lc_volume_destroy(whole);
    lc_device_destroy(dev);
    return check_summary("test_dp_particles");
}
