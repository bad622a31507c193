/* Iso and slice through the mode seam (kernels/mode.h), every kind, method
 * and target this CPU runs:
 * (a) hit points: one particle and one RBF (Gaussians) and a grid of the
 *     distance from a point (radial) have spherical iso-surfaces of known
 *     radius R; every hit, read back through lci_render's depth (the kernels'
 *     own hit t), lies within 1e-3 of R, rays passing well inside hit and rays
 *     passing outside miss;
 * (b) images of the shared scene (modes_scene.h) against the reference core
 *     (tests/ref) at SPEC.md's tolerances, and their depths against the
 *     reference's; a wrong iso value and a moved plane must fail;
 * (c) the grid BVH's iso culling is exact: BVH and brute-force images
 *     bit-identical (small bricks, differential sampling), with fewer
 *     samples taken;
 * (d) bad parameters refused, naming the member. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "host/internal.h" /* lci_render: each pixel's iso hit or plane point distance */
#include "imgcmp.h"
#include "modes_scene.h"
#include "ref/ref_core.h"
#include "ref/ref_fields.h"

static const char *target_name;

/* ---------------------------------------------------------------- (a) spheres */

enum { SW = 40, SH = 36, SG = 101 };
static const double sc[3] = {0.13, -0.07, 0.05}; /* the spheres' centre */

static const ref_camera sphere_cam = {REF_PERSPECTIVE, {0.4, 0.3, 5.0}, {0.13, -0.07, 0.05}, {0, 1, 0}, 32.0, 0.0};

/* Iso of v at value iso, method m: hits within 1e-3 of radius R around sc;
 * every ray passing at b < sqrt(R^2 - dt^2) from the centre (a chord longer
 * than 2 dt: a lattice sample inside) hits, no ray at b > R + 1e-3 does. */
static void check_sphere(lc_device *dev, const char *kind, const lc_volume *v, const lc_tf *tf, lc_method m,
                         const char *method, float iso, float dt, double R)
{
    static float rgba[4 * SW * SH], depth[SW * SH];
    lc_render_desc d = {0};
    d.width = SW, d.height = SH;
    const ref_camera *c = &sphere_cam;
    d.camera = (lc_camera){LC_PERSPECTIVE,
                           {(float)c->eye[0], (float)c->eye[1], (float)c->eye[2]},
                           {(float)c->at[0], (float)c->at[1], (float)c->at[2]},
                           {0, 1, 0},
                           (float)c->fovy,
                           0.0f};
    d.mode = LC_MODE_ISO, d.iso = iso, d.tf = tf, d.volume = v, d.method = m, d.dt = dt;
    d.shading = LC_SHADE_DIFFUSE;
    lc_status s = lci_render(dev, &d, rgba, depth, NULL);
    double worst = 0.0;
    int hits = 0, missed = 0, stray = 0, opaque = 1;
    for (int py = 0; py < SH && s == LC_OK; py++)
        for (int px = 0; px < SW; px++) {
            double o[3], dir[3], e[3];
            ref_camera_ray(c, SW, SH, px, py, o, dir);
            for (int a = 0; a < 3; a++) e[a] = sc[a] - o[a];
            double tc = e[0] * dir[0] + e[1] * dir[1] + e[2] * dir[2];
            double b = sqrt(fmax(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] - tc * tc, 0.0));
            float t = depth[py * SW + px];
            int hit = isfinite(t);
            opaque &= rgba[4 * (py * SW + px) + 3] == (hit ? 1.0f : 0.0f);
            if (hit) {
                double r2 = 0.0;
                for (int a = 0; a < 3; a++) r2 += (o[a] + t * dir[a] - sc[a]) * (o[a] + t * dir[a] - sc[a]);
                worst = fmax(worst, fabs(sqrt(r2) - R));
                hits++;
                stray += b > R + 1e-3;
            } else {
                missed += b < sqrt(R * R - (double)dt * dt);
            }
        }
    CHECK(s == LC_OK && hits > SW * SH / 8 && worst < 1e-3 && missed == 0 && stray == 0 && opaque,
          "sphere-%s-%s-%s: %d hits, | |x - c| - R | <= %.2e (R %.5f), %d rays inside missed, %d outside hit%s",
          kind, target_name, method, hits, worst, R, missed, stray, opaque ? "" : ", alpha not 1 at hits / 0 else");
}

static void run_spheres(lc_device *dev)
{
    /* one particle, r 0.8: exp(-d^2 / (2 r^2)) = 0.5 at R = r sqrt(2 ln 2) (inside sigma r = 1.6) */
    const float pc[3] = {(float)sc[0], (float)sc[1], (float)sc[2]}, pr = 0.8f;
    lc_volume *pv = NULL, *gv = NULL, *rv = NULL;
    lc_particles_desc pd = {.count = 1, .positions = pc, .radii = &pr};
    CHECK(lc_particles_create(dev, &pd, &pv) == LC_OK, "sphere: particle");
    /* one RBF, s 0.7, w 1 over w0 0.1: 0.1 + exp(-d^2 / (2 s^2)) = 0.6 at R = s sqrt(2 ln 2) */
    const float rs = 0.7f, rw = 1.0f;
    lc_rbf_desc rd = {.count = 1, .centres = pc, .widths = &rs, .weights = &rw, .bias = 0.1f};
    CHECK(lc_rbf_create(dev, &rd, &rv) == LC_OK, "sphere: rbf");
    /* the distance from sc on a 101^3 grid over [-2, 2]^3 (h 0.04): its trilinear interpolant
       is within h^2 / 8 * (2 / R) = 4e-4 of the distance near R = 1 */
    static float dist[SG * SG * SG];
    for (int k = 0; k < SG; k++)
        for (int j = 0; j < SG; j++)
            for (int i = 0; i < SG; i++) {
                double x = -2.0 + 0.04 * i - sc[0], y = -2.0 + 0.04 * j - sc[1], z = -2.0 + 0.04 * k - sc[2];
                dist[((size_t)k * SG + j) * SG + i] = (float)sqrt(x * x + y * y + z * z);
            }
    lc_grid_desc gd = {.size = {SG, SG, SG}, .type = LC_VALUE_FLOAT32, .data = dist,
                       .spacing = {0.04f, 0.04f, 0.04f}, .origin = {-2.0f, -2.0f, -2.0f}};
    CHECK(lc_grid_create(dev, &gd, &gv) == LC_OK, "sphere: grid");
    lc_tf *tf = NULL;
    lc_tf_field tff = {col0, 3, opa, 2, 1, {0.0f, 4.0f}};
    lc_tf_create(dev, &tff, 1, &tf);
    if (pv && rv && gv && tf) {
        check_sphere(dev, "particle", pv, tf, LC_METHOD_COHERENT, "coherent", 0.5f, 0.1f, 0.8 * sqrt(2.0 * log(2.0)));
        check_sphere(dev, "particle", pv, tf, LC_METHOD_DIRECT, "direct", 0.5f, 0.1f, 0.8 * sqrt(2.0 * log(2.0)));
        check_sphere(dev, "rbf", rv, tf, LC_METHOD_BVH, "bvh", 0.6f, 0.1f, 0.7 * sqrt(2.0 * log(2.0)));
        check_sphere(dev, "rbf", rv, tf, LC_METHOD_BRUTE, "brute", 0.6f, 0.1f, 0.7 * sqrt(2.0 * log(2.0)));
        check_sphere(dev, "rbf", rv, tf, LC_METHOD_DEFAULT, "octree", 0.6f, 0.1f, 0.7 * sqrt(2.0 * log(2.0)));
        check_sphere(dev, "grid", gv, tf, LC_METHOD_BVH, "bvh", 1.0f, 0.03f, 1.0);
        check_sphere(dev, "grid", gv, tf, LC_METHOD_BRUTE, "brute", 1.0f, 0.03f, 1.0);
    }
    lc_tf_destroy(tf);
    lc_volume_destroy(pv);
    lc_volume_destroy(rv);
    lc_volume_destroy(gv);
}

/* ---------------------------------------------------------------- (b) scene images */

#define SPHERE_SCALE 0.35
#define DT 0.07

/* Three planes through the data, seen at different angles. */
static const double planes[3][6] = {
    {0.2, 0.1, 0.3, 0.3, 0.2, 1.0}, {-0.4, 0.0, 0.0, 1.0, 0.1, -0.2}, {0.0, -0.6, 0.0, 0.0, 1.0, 0.4}};

/* One kind's case: its iso value and field, and the references. */
typedef struct kcase {
    const char *name;
    int field;
    float iso;
    float range[2]; /* 0, 0: the TF's */
    double eye_z;
    int spheres; /* particles with opaque spheres */
    float want_iso[4 * W * H], want_slice[4 * W * H];
    double depth_iso[W * H], depth_slice[W * H], margin_iso[W * H], margin_slice[W * H];
} kcase;

static ref_params ref_view(const ref_tf *tf, const kcase *k, ref_mode mode)
{
    ref_params p = {0};
    p.width = W, p.height = H;
    p.camera = (ref_camera){REF_PERSPECTIVE, {0.7, 0.9, k->eye_z}, {0.05, 0.1, 0.0}, {0, 1, 0}, 38.0, 0.0};
    p.mode = mode;
    p.tf = tf;
    p.dt = DT;
    p.alpha_stop = 1.0;
    p.shading = REF_SHADE_PHONG;
    p.iso = k->iso;
    p.field = k->field;
    memcpy(p.planes, planes, sizeof planes);
    p.nplanes = 3;
    return p;
}

static lc_render_desc lib_view(const lc_volume *v, const lc_tf *tf, const kcase *k, lc_mode mode)
{
    lc_render_desc d = {0};
    d.width = W, d.height = H;
    d.camera = (lc_camera){LC_PERSPECTIVE, {0.7f, 0.9f, (float)k->eye_z}, {0.05f, 0.1f, 0.0f}, {0, 1, 0}, 38.0f, 0.0f};
    d.mode = mode;
    d.tf = tf;
    d.volume = v;
    d.dt = (float)DT;
    d.alpha_stop = 1.0f;
    d.shading = LC_SHADE_PHONG;
    d.iso = k->iso;
    d.field = k->field;
    d.range[0] = k->range[0], d.range[1] = k->range[1];
    for (int i = 0; i < 3; i++)
        d.planes[i] = (lc_plane){{(float)planes[i][0], (float)planes[i][1], (float)planes[i][2]},
                                 {(float)planes[i][3], (float)planes[i][4], (float)planes[i][5]}};
    d.nplanes = 3;
    return d;
}

static imgcmp_worst worst_img = IMGCMP_WORST_INIT;
static double worst_depth;

/* The library's image and depth against the reference's: SPEC.md's image
 * tolerances, and hit distances within 2e-4 dt plus float round-off of t
 * (the reference's hit is within 1e-4 dt of the crossing, the library's too,
 * up to its float evaluation). */
static void compare(const char *label, const float *img, const float *depth, const float *want,
                    const double *want_depth)
{
    imgcmp_result r;
    int bad = imgcmp_check_ex(label, img, want, W, H, 0, 0, NULL, 1, &r);
    imgcmp_worst_add(&worst_img, &r);
    int dbad = 0;
    double dmax = 0.0;
    for (int i = 0; i < W * H; i++) {
        if (isfinite(depth[i]) != isfinite(want_depth[i])) {
            dbad++;
            continue;
        }
        if (!isfinite(depth[i])) continue;
        double e = fabs(depth[i] - want_depth[i]);
        dmax = fmax(dmax, e);
        dbad += e > 2e-4 * DT + 4e-7 * want_depth[i];
    }
    worst_depth = fmax(worst_depth, dmax);
    CHECK_QUIET(bad == 0 && dbad == 0, "%s: image max %.3f/255, PSNR %.1f dB; %d depths off (max %.2e)", label,
                r.max_diff_255, r.psnr_db, dbad, dmax);
}

static void run_images(lc_device *dev, const scene *s, kcase *kc)
{
    lc_tf_field tff[2] = {{col0, 3, opa, 2, 1, {0.0f, 1.0f}}, {col1, 2, opa, 2, 1, {0.0f, 1.0f}}};
    lc_tf *tf2 = NULL, *tf1 = NULL;
    lc_tf_create(dev, tff, 2, &tf2);
    lc_tf_create(dev, tff, 1, &tf1);
    lc_volume *vol[4] = {NULL, NULL, NULL, NULL};
    lc_particles_desc pd = {.count = NP, .positions = s->pos, .radii = s->rad, .fields = s->field, .nfields = 2};
    lc_particles_create(dev, &pd, &vol[0]);
    pd.params.sphere_scale = (float)SPHERE_SCALE;
    lc_particles_create(dev, &pd, &vol[1]);
    lc_grid_desc gd = {.size = {GX, GY, GZ}, .type = LC_VALUE_FLOAT32, .data = s->grid,
                       .spacing = {0.25f, 0.25f, 0.25f}, .origin = {-2.0f, -1.5f, -1.25f}};
    lc_grid_create(dev, &gd, &vol[2]);
    lc_rbf_desc rd = {.count = NR, .centres = s->rc, .widths = s->rs, .weights = s->rw, .bias = RBF_BIAS,
                      .eps = RBF_EPS, .domain = rbf_domain};
    lc_rbf_create(dev, &rd, &vol[3]);
    /* RBF sets (k = 3) also through their default method: the octree (lc_rbf_desc.accel 0) */
    static const lc_method pm[] = {LC_METHOD_COHERENT, LC_METHOD_DIRECT},
                           gm[] = {LC_METHOD_BVH, LC_METHOD_BRUTE, LC_METHOD_DEFAULT};
    static const char *const pn[] = {"coherent", "direct"}, *const gn[] = {"bvh", "brute", "octree"};
    static float img[4 * W * H], depth[W * H];
    char label[96];
    for (int k = 0; k < 4; k++) {
        CHECK_QUIET(vol[k] != NULL, "%s: %s: %s", target_name, kc[k].name, lc_last_error());
        if (!vol[k]) continue;
        for (int m = 0; m < (k == 3 ? 3 : 2); m++) {
            for (int mode = 0; mode < 2; mode++) {
                lc_render_desc d = lib_view(vol[k], k < 2 ? tf2 : tf1, &kc[k], mode ? LC_MODE_SLICE : LC_MODE_ISO);
                d.method = k < 2 ? pm[m] : gm[m];
                snprintf(label, sizeof label, "%s-%s-%s-%s", mode ? "slice" : "iso", kc[k].name, target_name,
                         k < 2 ? pn[m] : gn[m]);
                lc_status st = lci_render(dev, &d, img, depth, NULL);
                CHECK_QUIET(st == LC_OK, "%s: %s", label, lc_last_error());
                if (st != LC_OK) continue;
                compare(label, img, depth, mode ? kc[k].want_slice : kc[k].want_iso,
                        mode ? kc[k].depth_slice : kc[k].depth_iso);
            }
        }
    }
    for (int k = 0; k < 4; k++) lc_volume_destroy(vol[k]);
    lc_tf_destroy(tf1);
    lc_tf_destroy(tf2);
}

/* The references of the four cases, and a wrong iso value and a moved plane
 * that must fail against them. */
static void make_references(scene *s, kcase *kc)
{
    to_double(col0, dcol0, 12), to_double(col1, dcol1, 8), to_double(opa, dopa, 4);
    static ref_tf rtf[2], rtf_r;
    rtf[0] = (ref_tf){0, 1, dcol0, 3, dopa, 2};
    rtf[1] = (ref_tf){0, 1, dcol1, 2, dopa, 2};
    rtf_r = rtf[0];
    rtf_r.lo = -0.5, rtf_r.hi = 1.2;
    static ref_particle_set ps;
    ps = (ref_particle_set){NP, s->dpos, s->drad, NULL, s->dfield, 2, 0, 0};
    static ref_sphere_set ss;
    ss = (ref_sphere_set){&ps, SPHERE_SCALE};
    static ref_grid_field gf;
    gf = (ref_grid_field){{GX, GY, GZ}, {-2.0, -1.5, -1.25}, {0.25, 0.25, 0.25}, s->dgrid};
    static ref_rbf_set rs;
    rs = (ref_rbf_set){NR, s->drc, s->drs, s->drw, RBF_BIAS, RBF_EPS};
    ref_source src[4];
    ref_particles_source(&ps, &src[0]);
    src[1] = src[0];
    ref_grid_source(&gf, &src[2]);
    ref_rbf_source(&rs, &src[3]);
    for (int a = 0; a < 3; a++) src[3].lo[a] = (&rbf_domain.lo.x)[a], src[3].hi[a] = (&rbf_domain.hi.x)[a];
    const ref_tf *tfs[4] = {rtf, rtf, rtf, &rtf_r};
    for (int k = 0; k < 4; k++) {
        ref_params p = ref_view(tfs[k], &kc[k], REF_MODE_ISO);
        if (kc[k].spheres) p.surface = ref_particles_spheres, p.surface_user = &ss;
        CHECK(ref_render_f(&src[k], &p, kc[k].want_iso) == 0 &&
                  ref_render_depth(&src[k], &p, kc[k].depth_iso, kc[k].margin_iso) == 0,
              "reference: iso %s", kc[k].name);
        p.mode = REF_MODE_SLICE;
        CHECK(ref_render_f(&src[k], &p, kc[k].want_slice) == 0 &&
                  ref_render_depth(&src[k], &p, kc[k].depth_slice, kc[k].margin_slice) == 0,
              "reference: slice %s", kc[k].name);
        int hits_iso = 0, hits_slice = 0;
        double mi = INFINITY, ms = INFINITY;
        for (int i = 0; i < W * H; i++) {
            hits_iso += isfinite(kc[k].depth_iso[i]), hits_slice += isfinite(kc[k].depth_slice[i]);
            mi = fmin(mi, kc[k].margin_iso[i]), ms = fmin(ms, kc[k].margin_slice[i]);
        }
        /* every image shows something and misses something, so both sides are compared; and no
           pixel is a knife edge that float round-off may tip (a lattice sample within 1e-6 of the iso
           value, a plane point within 1e-5 of the box's side), so every pixel is compared */
        CHECK(hits_iso > W * H / 20 && hits_iso < W * H && hits_slice > W * H / 20 && hits_slice < W * H &&
                  mi > 1e-6 && ms > 1e-5,
              "reference %s: iso hits %d, slice hits %d of %d pixels; closest calls: |phi - iso| %.2e at a "
              "lattice sample, a plane point %.2e from the box's side",
              kc[k].name, hits_iso, hits_slice, W * H, mi, ms);
    }
    /* the comparison bites: iso 2% off, a plane moved by 0.05 */
    static float wrong[4 * W * H];
    kcase kw = kc[2];
    kw.iso *= 1.02f;
    ref_params p = ref_view(rtf, &kw, REF_MODE_ISO);
    ref_render_f(&src[2], &p, wrong);
    CHECK(imgcmp_check("iso-wrong-value", wrong, kc[2].want_iso, W, H, 0, 0, NULL) != 0,
          "a 2%% wrong iso value is caught");
    p.mode = REF_MODE_SLICE;
    p.iso = kc[2].iso;
    p.planes[1][0] += 0.05;
    ref_render_f(&src[2], &p, wrong);
    CHECK(imgcmp_check("slice-moved-plane", wrong, kc[2].want_slice, W, H, 0, 0, NULL) != 0, "a moved plane is caught");
}

/* ---------------------------------------------------------------- (c) culling */

enum { CX = 56, CY = 48, CZ = 40 };

static float cull_v[CX * CY * CZ];
static double cull_dv[CX * CY * CZ];
static float cull_want[4 * 64 * 48];
static const ref_camera cull_cam = {REF_PERSPECTIVE, {1.2, 0.8, 3.5}, {0.0, 0.0, 0.0}, {0, 1, 0}, 40.0, 0.0};

/* A lumpy field, and the reference image of one culling case (rda 0.02, iso
 * 0.45) with no knife-edge pixel. */
static void make_culling(void)
{
    for (int k = 0; k < CZ; k++)
        for (int j = 0; j < CY; j++)
            for (int i = 0; i < CX; i++) {
                double x = i / (CX - 1.0), y = j / (CY - 1.0), z = k / (CZ - 1.0);
                double f = exp(-((x - 0.4) * (x - 0.4) + (y - 0.5) * (y - 0.5) + (z - 0.5) * (z - 0.5)) * 18.0) +
                           0.25 * sin(17.0 * x) * sin(13.0 * y + 1.0) * sin(11.0 * z + 2.0);
                size_t o = ((size_t)k * CY + j) * CX + i;
                cull_v[o] = (float)f;
                cull_dv[o] = cull_v[o];
            }
    static double dcol[12], dop[4];
    to_double(col0, dcol, 12), to_double(opa, dop, 4);
    ref_tf tf = {-0.3, 1.2, dcol, 3, dop, 2};
    ref_grid_field gf = {{CX, CY, CZ}, {-1.4, -1.2, -1.0}, {0.05, 0.05, 0.05}, cull_dv};
    ref_source src;
    ref_grid_source(&gf, &src);
    ref_params p = {0};
    p.width = 64, p.height = 48, p.camera = cull_cam, p.mode = REF_MODE_ISO, p.tf = &tf, p.dt = 0.02;
    p.alpha_stop = 1.0, p.shading = REF_SHADE_PHONG, p.iso = 0.45, p.rda = 0.02;
    static double depth[64 * 48], margin[64 * 48];
    double mi = INFINITY;
    CHECK(ref_render_f(&src, &p, cull_want) == 0 && ref_render_depth(&src, &p, depth, margin) == 0,
          "reference: culling grid, iso 0.45, rda 0.02");
    for (int i = 0; i < 64 * 48; i++) mi = fmin(mi, margin[i]);
    CHECK(mi > 1e-6, "reference culling grid: closest call |phi - iso| %.2e at a lattice sample", mi);
}

/* Iso of a lumpy field on a grid with small bricks: the BVH culls nodes
 * whose range misses the iso value, yet its images equal brute force's bit
 * for bit (also with differential sampling, where steps vary), and the
 * reference's where it has one. */
static void run_culling(lc_device *dev)
{
    const float *v = cull_v;
    lc_tf *tf = NULL;
    lc_tf_field tff = {col0, 3, opa, 2, 1, {-0.3f, 1.2f}};
    lc_tf_create(dev, &tff, 1, &tf);
    static float a[4 * 64 * 48], b[4 * 64 * 48];
    static const int bricks[] = {1, 2};
    static const float rdas[] = {0.0f, 0.02f}, isos[] = {0.45f, 0.1f};
    for (int bi = 0; bi < 2; bi++) {
        lc_volume *g = NULL;
        lc_grid_desc gd = {.size = {CX, CY, CZ}, .type = LC_VALUE_FLOAT32, .data = v, .spacing = {0.05f, 0.05f, 0.05f},
                           .origin = {-1.4f, -1.2f, -1.0f}, .brick = bricks[bi]};
        if (lc_grid_create(dev, &gd, &g) != LC_OK) {
            CHECK(0, "culling: grid: %s", lc_last_error());
            continue;
        }
        for (int ri = 0; ri < 2; ri++)
            for (int ii = 0; ii < 2; ii++) {
                lc_grid_params gp = {.rda = rdas[ri]};
                lc_grid_set_params(g, &gp);
                lc_render_desc d = {0};
                d.width = 64, d.height = 48;
                d.camera = (lc_camera){LC_PERSPECTIVE, {1.2f, 0.8f, 3.5f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 40.0f, 0.0f};
                d.mode = LC_MODE_ISO, d.iso = isos[ii], d.tf = tf, d.volume = g, d.shading = LC_SHADE_PHONG;
                d.dt = ri ? 0.02f : 0.06f; /* steps longer than a voxel: some pass nodes between samples */
                lc_render_stats sa, sb;
                d.method = LC_METHOD_BVH;
                lc_status s1 = lc_render(dev, &d, a, &sa);
                d.method = LC_METHOD_BRUTE;
                lc_status s2 = lc_render(dev, &d, b, &sb);
                int hits = 0;
                for (int i = 0; i < 64 * 48; i++) hits += a[4 * i + 3] == 1.0f;
                CHECK(s1 == LC_OK && s2 == LC_OK && !memcmp(a, b, sizeof a) && sa.samples < sb.samples && hits > 200,
                      "culling-%s: brick %d, rda %g, iso %g: bvh = brute bit for bit (%d hits), samples %llu < %llu",
                      target_name, bricks[bi], (double)rdas[ri], (double)isos[ii], hits,
                      (unsigned long long)sa.samples, (unsigned long long)sb.samples);
                if (ri == 1 && ii == 0) {
                    char label[64];
                    snprintf(label, sizeof label, "iso-culling-rda-%s-brick%d", target_name, bricks[bi]);
                    imgcmp_result r;
                    CHECK_QUIET(imgcmp_check_ex(label, b, cull_want, 64, 48, 0, 0, NULL, 1, &r) == 0,
                                "%s: brute against the reference: max %.3f/255", label, r.max_diff_255);
                    imgcmp_worst_add(&worst_img, &r);
                }
            }
        lc_volume_destroy(g);
    }
    lc_tf_destroy(tf);
}

/* ---------------------------------------------------------------- (d) bad parameters */

static void expect_refused(lc_device *dev, const lc_render_desc *d, const char *what, const char *word)
{
    static float img[4 * 8 * 8];
    lc_status s = lc_render(dev, d, img, NULL);
    CHECK(s == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), word), "refused: %s (%s)", what, lc_last_error());
}

static void run_refusals(lc_device *dev)
{
    const float pos[6] = {0, 0, 0, 1, 0, 0}, rad[2] = {0.5f, 0.5f};
    const uint8_t fld[2] = {0, 1};
    lc_volume *v = NULL;
    lc_particles_desc pd = {.count = 2, .positions = pos, .radii = rad, .fields = fld, .nfields = 2};
    if (lc_particles_create(dev, &pd, &v) != LC_OK) {
        CHECK(0, "refusals: particles: %s", lc_last_error());
        return;
    }
    lc_render_desc d = {0};
    d.width = d.height = 8;
    d.volume = v;
    d.mode = LC_MODE_ISO;
    d.iso = NAN;
    expect_refused(dev, &d, "iso NaN", "iso");
    d.iso = INFINITY;
    expect_refused(dev, &d, "iso inf", "iso");
    d.iso = 0.5f, d.field = 2;
    expect_refused(dev, &d, "iso field 2 of 2", "field");
    d.field = -1;
    expect_refused(dev, &d, "iso field -1", "field");
    d.field = 1;
    static float img[4 * 8 * 8];
    CHECK(lc_render(dev, &d, img, NULL) == LC_OK, "iso field 1 of 2 renders");
    d.mode = LC_MODE_SLICE;
    expect_refused(dev, &d, "slice without planes", "nplanes");
    d.nplanes = LC_MAX_PLANES + 1;
    expect_refused(dev, &d, "slice with 5 planes", "nplanes");
    d.nplanes = 2;
    d.planes[0] = (lc_plane){{0, 0, 0}, {0, 0, 1}};
    d.planes[1] = (lc_plane){{0, 0, 0}, {0, 0, 0}};
    expect_refused(dev, &d, "slice with a zero normal", "planes[1].normal");
    d.planes[1] = (lc_plane){{0, 0, 0}, {NAN, 0, 1}};
    expect_refused(dev, &d, "slice with a NaN normal", "planes[1].normal");
    d.planes[1] = (lc_plane){{0, INFINITY, 0}, {0, 1, 0}};
    expect_refused(dev, &d, "slice with an infinite point", "planes[1].point");
    d.planes[1] = (lc_plane){{0, 0, 0}, {1e-30f, 0, 0}};
    CHECK(lc_render(dev, &d, img, NULL) == LC_OK, "slice with a tiny (non-zero) normal renders");
    d.field = 2;
    expect_refused(dev, &d, "slice field 2 of 2", "field");
    d.field = 0;
    d.mode = (lc_mode)4;
    expect_refused(dev, &d, "mode 4", "mode");
    lc_volume_destroy(v);
}

int main(void)
{
    static scene s;
    make_scene(&s);
    static kcase kc[4] = {{.name = "particles", .field = 1, .iso = 0.45f, .eye_z = 9.0},
                          {.name = "particles-spheres", .field = 0, .iso = 0.3f, .eye_z = 9.0, .spheres = 1},
                          {.name = "grid", .field = 0, .iso = 0.5f, .eye_z = 8.0},
                          {.name = "rbf", .field = 0, .iso = 0.3f, .range = {-0.5f, 1.2f}, .eye_z = 8.0}};
    make_references(&s, kc);
    make_culling();
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        target_name = lc_target_name((lc_target)t);
        if (!lc_target_compiled((lc_target)t) || !lc_target_supported((lc_target)t)) {
            printf("skip %s: not compiled or not supported by this CPU\n", target_name);
            continue;
        }
        lc_device *dev;
        if (lc_device_create(&(lc_device_desc){.target = (lc_target)t, .threads = 2}, &dev) != LC_OK) {
            CHECK(0, "%s: device: %s", target_name, lc_last_error());
            continue;
        }
        run_spheres(dev);
        run_images(dev, &s, kc);
        run_culling(dev);
        if (t == LC_TARGET_SCALAR) run_refusals(dev);
        lc_device_destroy(dev);
    }
    imgcmp_worst_print("iso and slice images", &worst_img);
    printf("worst depth difference %.2e (dt %g)\n", worst_depth, DT);
    return check_summary("modes_iso");
}
