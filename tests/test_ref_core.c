/* Self-test of the reference core (ref/ref_core.h, ref/ref_fields.h) and the
 * image comparer (imgcmp.h): closed forms computed here, independently of
 * the code under test, and failures that must be reported as failures. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "imgcmp.h"
#include "ref/ref_core.h"
#include "ref/ref_fields.h"

static int near(double a, double b, double tol) { return fabs(a - b) <= tol * (1.0 + fabs(b)); }

/* ---------------------------------------------------------------- (a) fields */

static void test_particle_field(void)
{
    const double pos[] = {0.0, 0.0, 0.0, 1.0, 0.5, -0.5, 3.0, 0.0, 0.0};
    const double rad[] = {1.0, 0.5, 0.25}, val[] = {2.0, -1.0, 4.0};
    const int fid[] = {0, 0, 1};
    ref_particle_set ps = {3, pos, rad, val, fid, 2, 2.0, 1.5};
    ref_source src;
    CHECK(ref_particles_source(&ps, &src) == 0 && src.nfields == 2, "particles: source");
    CHECK(src.lo[0] == -2.0 && src.hi[0] == 5.0 && src.lo[1] == -2.0 && src.hi[2] == 2.0,
          "particles: box = centre bounds grown by sigma * max r");
    const double x[3] = {0.6, 0.2, -0.1};
    double phi[2], grad[2][3];
    ref_particles_eval(&ps, x, phi, grad);
    /* closed form: both field-0 particles are within 2 r; particle 2 is 2.4 away > 2 * 0.25 */
    double e0[3] = {0.6, 0.2, -0.1}, e1[3] = {-0.4, -0.3, 0.4};
    double d0 = 0.36 + 0.04 + 0.01, d1 = 0.16 + 0.09 + 0.16;
    double p0 = 1.5 * 2.0 * exp(-d0 / 2.0), p1 = 1.5 * -1.0 * exp(-d1 / (2.0 * 0.25));
    CHECK(near(phi[0], p0 + p1, 1e-14) && phi[1] == 0.0, "particles: phi %.15g (closed form %.15g), field 1 %g",
          phi[0], p0 + p1, phi[1]);
    int gok = 1;
    for (int a = 0; a < 3; a++) gok &= near(grad[0][a], -e0[a] * p0 - e1[a] / 0.25 * p1, 1e-13);
    CHECK(gok, "particles: gradient = -sum (x - x_i) / r_i^2 phi_i");
    /* gradient against central differences */
    double h = 1e-6, fd[3];
    for (int a = 0; a < 3; a++) {
        double xp[3] = {x[0], x[1], x[2]}, xm[3] = {x[0], x[1], x[2]}, pp[2], pm[2];
        xp[a] += h, xm[a] -= h;
        ref_particles_eval(&ps, xp, pp, NULL);
        ref_particles_eval(&ps, xm, pm, NULL);
        fd[a] = (pp[0] - pm[0]) / (2 * h);
    }
    CHECK(near(fd[0], grad[0][0], 1e-7) && near(fd[1], grad[0][1], 1e-7) && near(fd[2], grad[0][2], 1e-7),
          "particles: gradient matches central differences");
    /* truncation at sigma r: just inside counts, just outside does not */
    const double xin[3] = {3.0 + 0.4999, 0, 0}, xout[3] = {3.0 + 0.5001, 0, 0};
    double pin[2], pout[2];
    ref_particles_eval(&ps, xin, pin, NULL);
    ref_particles_eval(&ps, xout, pout, NULL);
    CHECK(near(pin[1], 1.5 * 4.0 * exp(-0.4999 * 0.4999 / (2 * 0.0625)), 1e-14) && pout[1] == 0.0,
          "particles: cut at sigma r (in %g, out %g)", pin[1], pout[1]);
}

static double lin(const double x[3]) { return 1.5 + 0.3 * x[0] - 2.0 * x[1] + 0.7 * x[2]; }
static double tri(const double x[3]) { return x[0] * x[1] * x[2]; }

static void test_grid_field(void)
{
    enum { NX = 4, NY = 5, NZ = 6 };
    static double vl[NX * NY * NZ], vt[NX * NY * NZ];
    ref_grid_field gl = {{NX, NY, NZ}, {-1.0, 2.0, 3.0}, {0.5, 0.25, 2.0}, vl}, gt = gl;
    gt.values = vt;
    for (int k = 0; k < NZ; k++)
        for (int j = 0; j < NY; j++)
            for (int i = 0; i < NX; i++) {
                double x[3] = {-1.0 + 0.5 * i, 2.0 + 0.25 * j, 3.0 + 2.0 * k};
                vl[(k * NY + j) * NX + i] = lin(x);
                vt[(k * NY + j) * NX + i] = tri(x);
            }
    ref_source src;
    CHECK(ref_grid_source(&gl, &src) == 0 && src.lo[0] == -1.0 && src.hi[0] == 0.5 && src.hi[1] == 3.0 &&
              src.hi[2] == 13.0,
          "grid: box = first to last node");
    srand(7);
    double el = 0, egl = 0, et = 0, egt = 0;
    for (int n = 0; n < 2000; n++) {
        double x[3], phi, g[1][3];
        for (int a = 0; a < 3; a++) x[a] = src.lo[a] + (src.hi[a] - src.lo[a]) * rand() / (double)RAND_MAX;
        ref_grid_eval(&gl, x, &phi, g);
        el = fmax(el, fabs(phi - lin(x)));
        egl = fmax(egl, fmax(fabs(g[0][0] - 0.3), fmax(fabs(g[0][1] + 2.0), fabs(g[0][2] - 0.7))));
        /* x y z is trilinear too: exact value and gradient (y z, x z, x y) */
        ref_grid_eval(&gt, x, &phi, g);
        et = fmax(et, fabs(phi - tri(x)));
        egt = fmax(egt, fmax(fabs(g[0][0] - x[1] * x[2]), fmax(fabs(g[0][1] - x[0] * x[2]), fabs(g[0][2] - x[0] * x[1]))));
    }
    CHECK(el < 1e-12 && egl < 1e-12, "grid: linear field exact (value err %.2g, gradient err %.2g vs slope)", el, egl);
    CHECK(et < 1e-11 && egt < 1e-11, "grid: x y z exact (value err %.2g, gradient err %.2g)", et, egt);
    /* corners (the last node is inside) */
    double phi, c[3] = {0.5, 3.0, 13.0};
    double g[1][3];
    ref_grid_eval(&gl, c, &phi, g);
    CHECK(near(phi, lin(c), 1e-14) && near(g[0][0], 0.3, 1e-14) && near(g[0][1], -2.0, 1e-14) &&
              near(g[0][2], 0.7, 1e-14),
          "grid: last node %g = %g, gradient the slope", phi, lin(c));
}

static void test_rbf_field(void)
{
    const double mu[] = {1.0, 0.0, 0.0}, s[] = {1.5}, w[] = {-2.0};
    ref_rbf_set set = {1, mu, s, w, 0.5, 1e-3};
    ref_source src;
    double R = 1.5 * sqrt(2.0 * log(2000.0));
    CHECK(ref_rbf_source(&set, &src) == 0 && near(src.hi[0], 1.0 + R, 1e-14) && near(src.lo[2], -R, 1e-14),
          "rbf: box = support sphere, R = s sqrt(2 ln(|w| / eps)) = %g", R);
    double x[3] = {1.3, -0.4, 0.2}, phi, g[1][3];
    ref_rbf_eval(&set, x, &phi, g);
    double e2 = 0.09 + 0.16 + 0.04, ph = -2.0 * exp(-e2 / (2 * 2.25));
    CHECK(near(phi, 0.5 + ph, 1e-14) && near(g[0][0], -0.3 / 2.25 * ph, 1e-13) && near(g[0][1], 0.4 / 2.25 * ph, 1e-13),
          "rbf: value %.15g = w0 + w exp(...) %.15g, gradient", phi, 0.5 + ph);
    double xin[3] = {1.0 + R * (1 - 1e-9), 0, 0}, xout[3] = {1.0 + R * (1 + 1e-9), 0, 0}, pin, pout;
    ref_rbf_eval(&set, xin, &pin, NULL);
    ref_rbf_eval(&set, xout, &pout, NULL);
    CHECK(near(pin, 0.5 - 1e-3, 1e-6) && pout == 0.5, "rbf: term is eps at R (in %.9g, out %.9g)", pin, pout);
}

/* ---------------------------------------------------------------- (b) renders */

typedef struct konst {
    double v[2];
} konst;

static void const_eval(const void *user, const double p[3], double *phi, double (*grad)[3])
{
    const konst *k = user;
    (void)p;
    for (int f = 0; f < 2; f++) {
        phi[f] = k->v[f];
        if (grad) grad[f][0] = grad[f][1] = grad[f][2] = 0.0;
    }
}

static const double red[] = {0.0, 0.9, 0.3, 0.1}, green[] = {0.0, 0.0, 1.0, 0.0};
static const double tau_c[] = {0.0, 1.7}, tau_c2[] = {0.0, 0.6};

/* Eye on +z looking at the origin; a 5 x 5 image, so pixel (2, 2) looks straight down -z. */
static ref_params base_params(const ref_tf *tf)
{
    ref_params p = {0};
    p.width = p.height = 5;
    p.camera = (ref_camera){REF_PERSPECTIVE, {0, 0, 10}, {0, 0, 0}, {0, 0, 0}, 30.0, 0.0};
    p.tf = tf;
    p.dt = 0.35;
    p.alpha_stop = 1.0;
    return p;
}

static void test_constant_box(void)
{
    konst k = {{0.5, 0.5}};
    ref_tf tf[2] = {{0, 1, red, 1, tau_c, 1}, {0, 1, green, 1, tau_c2, 1}};
    ref_source src = {const_eval, &k, 1, {-1, -1, -1}, {1, 1, 1}};
    ref_params p = base_params(tf);
    double out[4];
    /* t in [9, 11]: k dt with k = 26 .. 31 (9 / 0.35 = 25.7, 11 / 0.35 = 31.4), 6 samples */
    int n = 0;
    for (int i = 0; i < 100; i++) n += i * 0.35 >= 9.0 && i * 0.35 <= 11.0;
    double A = 1.0 - exp(-1.7 * n * 0.35);
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && n == 6 && near(out[3], A, 1e-14),
          "box: A %.15g = 1 - exp(-tau n dt) %.15g, n = %d", out[3], A, n);
    CHECK(near(out[0], 0.9 * A, 1e-14) && near(out[1], 0.3 * A, 1e-14) && near(out[2], 0.1 * A, 1e-14),
          "box: C = rgb A (premultiplied)");
    p.shading = REF_SHADE_PHONG;
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && near(out[0], 0.9 * A, 1e-14),
          "box: zero gradient is not shaded");
    p.shading = REF_SHADE_NONE;
    /* early termination: stops at the first sample with A >= 0.7 */
    p.alpha_stop = 0.7;
    int m = 1;
    while (1.0 - exp(-1.7 * m * 0.35) < 0.7) m++;
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && near(out[3], 1.0 - exp(-1.7 * m * 0.35), 1e-14),
          "box: alpha_stop 0.7 stops after %d samples (A %.6f)", m, out[3]);
    p.alpha_stop = 1.0;
    /* differential sampling: t_k = dt (k + rda k (k-1) / 2), extinction over the step dt (1 + rda k) */
    p.rda = 0.01;
    double tsum = 0.0;
    n = 0;
    for (int i = 0; i < 100; i++) {
        double t = 0.35 * (i + 0.01 * i * (i - 1) / 2.0);
        if (t >= 9.0 && t <= 11.0) tsum += 0.35 * (1.0 + 0.01 * i), n++;
    }
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && n > 0 && near(out[3], 1.0 - exp(-1.7 * tsum), 1e-14),
          "box: rda 0.01, %d samples, A %.15g = %.15g", n, out[3], 1.0 - exp(-1.7 * tsum));
    p.rda = 0.0;
    /* two fields: A = 1 - exp(-(tau0 + tau1) n dt) whatever the order */
    src.nfields = 2;
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && near(out[3], 1.0 - exp(-(1.7 + 0.6) * 6 * 0.35), 1e-14),
          "box: two fields, A %.15g", out[3]);
    double a0 = 1.0 - exp(-1.7 * 0.35), a1 = 1.0 - exp(-0.6 * 0.35), Ag = 0.0, R = 0.0, G = 0.0;
    for (int i = 0; i < 6; i++) { /* field 0 (rgb 0.9 0.3 0.1) first, then field 1 (green) */
        R += (1.0 - Ag) * a0 * 0.9, G += (1.0 - Ag) * a0 * 0.3, Ag += (1.0 - Ag) * a0;
        G += (1.0 - Ag) * a1, Ag += (1.0 - Ag) * a1;
    }
    CHECK(near(out[0], R, 1e-14) && near(out[1], G, 1e-14), "box: fields blended in field order (r %.12g, g %.12g)",
          out[0], out[1]);
    /* eye inside the box: t clipped to 0, samples k = 0 .. 4 */
    double t0 = -1, t1 = -1, o[3] = {0, 0, 0.5}, d[3] = {0, 0, -1};
    CHECK(ref_ray_box(o, d, src.lo, src.hi, &t0, &t1) && t0 == 0.0 && t1 == 1.5, "box: clipped to t >= 0");
    p.camera.eye[2] = 0.5;
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && near(out[3], 1.0 - exp(-(1.7 + 0.6) * 5 * 0.35), 1e-14),
          "box: eye inside, 5 samples from the eye, A %.15g", out[3]);
    p.camera.eye[2] = 10.0;
    /* a corner ray misses the box: nothing */
    float img[5 * 5 * 4];
    CHECK(ref_render_f(&src, &p, img) == 0 && img[3] == 0.0f && img[4 * 12 + 3] > 0.0f, "box: corner misses");
    p.mode = (ref_mode)9;
    CHECK(ref_render_f(&src, &p, img) == -1, "box: unknown mode refused");
    /* MIP: field 1's normalised 0.6 beats field 0's 0.3, so field 1's colour, opaque;
       a ray that misses stays empty */
    konst k2 = {{0.3, 0.6}};
    src.user = &k2;
    p.mode = REF_MODE_MIP;
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && out[0] == 0.0 && out[1] == 1.0 && out[3] == 1.0,
          "mip: the larger normalised field wins (%g %g %g %g)", out[0], out[1], out[2], out[3]);
    k2.v[0] = 0.9;
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && near(out[0], 0.9, 1e-15) && out[3] == 1.0,
          "mip: field 0 wins when larger");
    CHECK(ref_render_f(&src, &p, img) == 0 && img[3] == 0.0f && img[4 * 12 + 3] == 1.0f, "mip: corner misses");
}

/* A ramp grid phi = z or phi = x: constant gradient for the shading rules. */
static void test_shading(void)
{
    static double vz[8], vx[8];
    for (int i = 0; i < 8; i++) vz[i] = (i >> 2) & 1, vx[i] = i & 1;
    ref_grid_field gz = {{2, 2, 2}, {-1, -1, -1}, {2, 2, 2}, vz}, gx = gz;
    gx.values = vx;
    ref_tf tf[1] = {{0, 1, red, 1, tau_c, 1}};
    ref_params p = base_params(tf);
    ref_source src;
    double out[4], A = 1.0 - exp(-1.7 * 6 * 0.35);
    ref_grid_source(&gz, &src);
    p.shading = REF_SHADE_PHONG; /* n parallel to the view: (ka + kd) rgb + ks */
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && near(out[0], (0.9 + 0.4) * A, 1e-13) &&
              near(out[3], A, 1e-14),
          "shade: phong, n.l = 1: r %.12g = %.12g", out[0], (0.9 + 0.4) * A);
    ref_grid_source(&gx, &src);
    p.shading = REF_SHADE_DIFFUSE; /* n perpendicular: ka rgb */
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && near(out[1], 0.2 * 0.3 * A, 1e-13),
          "shade: diffuse, n.l = 0: g %.12g = %.12g", out[1], 0.2 * 0.3 * A);
    p.ka = 0.5, p.kd = 0.1, p.ks = 0.0, p.p = 1.0;
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && near(out[1], 0.5 * 0.3 * A, 1e-13), "shade: custom ka");
    p.ka = p.kd = p.ks = p.p = 0.0;
    /* |grad| below 1e-6 (hi - lo) / dt = 2.86e-6: unshaded; above: shaded */
    for (int i = 0; i < 8; i++) vx[i] = 1e-6 * (i & 1);
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && near(out[1], 0.3 * A, 1e-13),
          "shade: |grad| 5e-7 below the threshold: unshaded");
    for (int i = 0; i < 8; i++) vx[i] = 1.2e-5 * (i & 1);
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && near(out[1], 0.2 * 0.3 * A, 1e-13),
          "shade: |grad| 6e-6 above the threshold: shaded");
    /* oblique gradient (1, 0, 1): |n.l| = |n.h| = 1/sqrt 2; phong (ka + kd / sqrt 2) rgb + ks 2^-8 */
    for (int i = 0; i < 8; i++) vx[i] = (i & 1) + ((i >> 2) & 1);
    p.shading = REF_SHADE_PHONG;
    double want = (0.9 * (0.2 + 0.8 / sqrt(2.0)) + 0.4 / 256.0) * A;
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && near(out[0], want, 1e-13),
          "shade: phong oblique, r %.12g = %.12g", out[0], want);
}

/* iso and slice on the ramp phi = (z + 1) / 2 over [-1, 1]^3, seen from
 * (0, 0, 10): the centre pixel's ray is t = 10 - z, the colour ramp shows v. */
static void test_iso_slice(void)
{
    static double vz[8];
    for (int i = 0; i < 8; i++) vz[i] = (i >> 2) & 1;
    ref_grid_field gz = {{2, 2, 2}, {-1, -1, -1}, {2, 2, 2}, vz};
    static const double ramp[] = {0, 0, 0, 1, 1, 1, 0, 0};
    ref_tf tf[1] = {{0, 1, ramp, 2, tau_c, 1}};
    ref_params p = base_params(tf);
    ref_source src;
    ref_grid_source(&gz, &src);
    double out[4], depth[25], margin[25];
    /* iso 0.3: z = -0.4, t = 10.4; the ray starts inside (phi 1 >= 0.3) and leaves at the hit,
       which is the bracket's inside end: at most 1e-4 dt before 10.4 */
    p.mode = REF_MODE_ISO, p.iso = 0.3;
    CHECK(ref_render_depth(&src, &p, depth, margin) == 0 && depth[12] <= 10.4 + 1e-12 &&
              depth[12] >= 10.4 - 1e-4 * 0.35 && near(margin[12], 0.05, 1e-9),
          "iso: hit at t %.9f (10.4 - 1e-4 dt <= t <= 10.4); margin %.9g = |phi - iso| at t 10.5, the closest "
          "lattice sample",
          depth[12], margin[12]);
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && near(out[0], 0.3, 1e-14) && near(out[2], 0.7, 1e-14) &&
              out[3] == 1.0,
          "iso: opaque, the colour at the iso value (%g %g %g %g)", out[0], out[1], out[2], out[3]);
    p.shading = REF_SHADE_PHONG; /* gradient (0, 0, 0.5) along the view: (ka + kd) rgb + ks */
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && near(out[0], 0.3 + 0.4, 1e-13) &&
              near(out[2], 0.7 + 0.4, 1e-13),
          "iso: shaded with the gradient at the hit (r %.12g)", out[0]);
    p.shading = REF_SHADE_NONE;
    p.iso = 1.5; /* never reached: transparent, no depth */
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && out[3] == 0.0 && out[0] == 0.0, "iso: no crossing, no hit");
    CHECK(ref_render_depth(&src, &p, depth, NULL) == 0 && isinf(depth[12]), "iso: no crossing, depth inf");
    p.iso = NAN;
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == -1, "iso: NaN refused");
    p.iso = 0.3, p.field = 1;
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == -1, "iso: field 1 of 1 refused");
    p.field = 0;
    /* slice: z = 0.2 (phi 0.6) behind z = 0.5 (phi 0.75, t = 9.5); a plane outside the box and one
       parallel to the centre ray are never shown there */
    p.mode = REF_MODE_SLICE;
    double planes[4][6] = {{0, 0, 0.2, 0, 0, 1}, {0, 0, 2, 0, 0, 1}, {0, 0, 0.5, 0, 0, -3}, {0.1, 0, 0, 1, 0, 0}};
    memcpy(p.planes, planes, sizeof planes);
    p.nplanes = 1;
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && near(out[0], 0.6, 1e-14) && out[3] == 1.0,
          "slice: the field on the plane (%g)", out[0]);
    p.nplanes = 4;
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && near(out[0], 0.75, 1e-14) && out[3] == 1.0 &&
              ref_render_depth(&src, &p, depth, margin) == 0 && near(depth[12], 9.5, 1e-14),
          "slice: the nearest plane in the box wins (%g at t %g)", out[0], depth[12]);
    p.shading = REF_SHADE_PHONG;
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && near(out[0], 0.75, 1e-14), "slice: unshaded");
    p.shading = REF_SHADE_NONE;
    p.nplanes = 1, p.planes[0][2] = 1.5; /* outside the box */
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && out[3] == 0.0, "slice: a plane outside the box shows nothing");
    p.nplanes = 0;
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == -1, "slice: no plane refused");
    p.nplanes = 1, p.planes[0][3] = p.planes[0][4] = p.planes[0][5] = 0.0;
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == -1, "slice: zero normal refused");
}

/* Orthographic view of one particle: A = 1 - exp(-sum tau(phi(t_k)) dt), with a linear TF. */
static void test_particle_render(void)
{
    const double pos[] = {0, 0, 0}, rad[] = {1.0};
    ref_particle_set ps = {1, pos, rad, NULL, NULL, 0, 0.0, 0.0};
    const double col[] = {0, 1, 0, 0, 1, 0, 0, 1}, op[] = {0, 0, 1, 2};
    ref_tf tf[1] = {{0, 1, col, 2, op, 2}};
    ref_source src;
    ref_particles_source(&ps, &src);
    ref_params p = {0};
    p.width = p.height = 1;
    p.camera = (ref_camera){REF_ORTHOGRAPHIC, {0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 0.0, 4.0};
    p.tf = tf, p.dt = 0.1, p.alpha_stop = 1.0;
    double C[3] = {0, 0, 0}, A = 0.0, out[4];
    for (int k = 0; k < 200; k++) {
        double t = 0.1 * k, z = 5.0 - t;
        if (t < 3.0 || t > 7.0 || fabs(z) >= 2.0) continue;
        double v = exp(-z * z / 2.0), a = 1.0 - exp(-2.0 * v * 0.1);
        C[0] += (1 - A) * a * (1 - v), C[2] += (1 - A) * a * v, A += (1 - A) * a;
    }
    CHECK(ref_render_pixel(&src, &p, 0, 0, out) == 0 && near(out[3], A, 1e-13) && near(out[0], C[0], 1e-13) &&
              near(out[2], C[2], 1e-13) && out[1] == 0.0,
          "particle: orthographic ray through the centre, A %.12g = %.12g", out[3], A);
}

static void test_tf(void)
{
    const double col[] = {0.25, 1, 0, 0, 0.5, 0, 1, 0, 0.5, 0, 0, 1}, op[] = {0.5, 3.0};
    ref_tf tf = {1.0, 3.0, col, 3, op, 1};
    double rgb[3], tau;
    ref_tf_eval(&tf, 1.75, rgb, &tau); /* v 0.375: half way from 0.25 to 0.5 */
    CHECK(rgb[0] == 0.5 && rgb[1] == 0.5 && tau == 3.0, "tf: interpolation");
    ref_tf_eval(&tf, -5.0, rgb, &tau);
    CHECK(rgb[0] == 1.0 && rgb[1] == 0.0, "tf: clamped below");
    ref_tf_eval(&tf, 2.0, rgb, &tau); /* v 0.5 exactly: the step to blue */
    CHECK(rgb[2] == 1.0 && rgb[1] == 0.0, "tf: step at repeated v takes the upper point");
    /* v itself is clamped to [0, 1] before the points are looked up */
    const double op2[] = {0.0, 0.0, 2.0, 2.0};
    ref_tf tf2 = {0.0, 1.0, col, 3, op2, 2};
    ref_tf_eval(&tf2, 1.5, rgb, &tau);
    CHECK(tau == 1.0, "tf: v clamped to 1 (tau %g)", tau);
    ref_tf_eval(&tf, NAN, rgb, &tau);
    CHECK(isnan(rgb[0]) && isnan(tau), "tf: NaN stays NaN");
}

/* ---------------------------------------------------------------- (c) imgcmp */

static void test_imgcmp(const char *dir)
{
    enum { W = 8, H = 6, N = W * H * 4 };
    static float a[N], b[N];
    imgcmp_result r;
    for (int i = 0; i < N; i++) a[i] = b[i] = (float)((i * 37 % 101) / 101.0);
    CHECK(imgcmp_check("identical", a, b, W, H, 0, 0, dir) == 0, "imgcmp: identical images pass");
    CHECK(imgcmp_stats(a, b, W, H, 2.0, &r) == 0 && isinf(r.psnr_db) && r.max_diff_255 == 0.0, "imgcmp: PSNR inf");
    b[4 * (2 * W + 3) + 1] += 1.0f / 255.0f;
    CHECK(imgcmp_check("one-255", a, b, W, H, 0, 0, dir) == 0, "imgcmp: 1/255 on one pixel passes");
    b[4 * (2 * W + 3) + 1] += 2.0f / 255.0f;
    CHECK(imgcmp_check("three-255", a, b, W, H, 0, 0, dir) == 1, "imgcmp: 3/255 fails");
    CHECK(imgcmp_stats(a, b, W, H, 2.0, &r) == 0 && r.worst_x == 3 && r.worst_y == 2 && r.worst_channel == 1 &&
              r.ndiff == 1 && near(r.max_diff_255, 3.0, 1e-4),
          "imgcmp: worst pixel (%d,%d) ch %d, %.4f/255", r.worst_x, r.worst_y, r.worst_channel, r.max_diff_255);
    memcpy(b, a, sizeof a);
    for (int i = 0; i < N; i++) b[i] += 1.0f / 255.0f;
    CHECK(imgcmp_check("all-one-255", a, b, W, H, 0, 0, NULL) == 1, "imgcmp: 1/255 everywhere is 48 dB: fails");
    memcpy(b, a, sizeof a);
    b[4 * (5 * W + 7) + 3] = NAN;
    CHECK(imgcmp_check("one-nan", a, b, W, H, 0, 0, dir) == 1, "imgcmp: one NaN pixel in want fails");
    CHECK(imgcmp_stats(a, b, W, H, 2.0, &r) == 0 && r.nonfinite == 1 && r.bad_x == 7 && r.bad_y == 5 &&
              r.bad_in_want && r.bad_channel == 3,
          "imgcmp: NaN located");
    CHECK(r.max_diff_255 == 0.0 && isinf(r.psnr_db), "imgcmp: NaN pixel left out of max and PSNR");
    CHECK(imgcmp_check("one-nan-got", b, a, W, H, 0, 0, NULL) == 1, "imgcmp: one NaN pixel in got fails");
    b[4 * (5 * W + 7) + 3] = a[4 * (5 * W + 7) + 3];
    b[0] = INFINITY;
    CHECK(imgcmp_check("inf", b, a, W, H, 0, 0, NULL) == 1, "imgcmp: Inf fails");
    b[0] = -INFINITY;
    CHECK(imgcmp_check("neg-inf", b, a, W, H, 0, 0, NULL) == 1, "imgcmp: -Inf fails");
    for (int i = 0; i < N; i++) a[i] = b[i] = NAN;
    CHECK(imgcmp_check("all-nan", a, b, W, H, 0, 0, dir) == 1, "imgcmp: all-NaN images fail");
    CHECK(imgcmp_stats(a, b, W, H, 2.0, &r) == 0 && r.nonfinite == 2 * N, "imgcmp: %ld non-finite", r.nonfinite);
    CHECK(imgcmp_check("bad", a, b, 0, H, 0, 0, NULL) == -1, "imgcmp: bad size refused");
    if (dir) {
        char path[512];
        snprintf(path, sizeof path, "%s/three-255.diff.ppm", dir);
        FILE *f = fopen(path, "rb");
        char magic[3] = {0};
        int w = 0, h = 0;
        CHECK(f && fscanf(f, "%2s %d %d", magic, &w, &h) == 3 && !strcmp(magic, "P6") && w == 3 * W && h == H,
              "imgcmp: diff image %s written (%dx%d)", path, w, h);
        if (f) fclose(f);
        const char *names[] = {"three-255", "one-nan", "all-nan"};
        for (int i = 0; i < 3; i++) {
            snprintf(path, sizeof path, "%s/%s.diff.ppm", dir, names[i]);
            remove(path);
        }
        snprintf(path, sizeof path, "%s/identical.diff.ppm", dir);
        f = fopen(path, "rb");
        CHECK(f == NULL, "imgcmp: no diff image for a pass");
        if (f) fclose(f);
    }
}

/* ---------------------------------------------------------------- (d) camera */

static void test_camera(void)
{
    ref_camera cam = {REF_PERSPECTIVE, {1, 2, 3}, {-2, 0.5, 7}, {0, 0, 0}, 45.0, 0.0};
    double o[3], d[3], f[3] = {-3, -1.5, 4}, fl = sqrt(9 + 2.25 + 16);
    CHECK(ref_camera_ray(&cam, 101, 101, 50, 50, o, d) == 0 && near(d[0], f[0] / fl, 1e-15) &&
              near(d[1], f[1] / fl, 1e-15) && near(d[2], f[2] / fl, 1e-15) && o[0] == 1 && o[2] == 3,
          "camera: centre pixel ray points at 'at'");
    /* eye on +z looking at the origin, up +y, fovy 90, 3 x 3: pixel (1, 0) is v = 2/3 up, (2, 1) u = 2/3 right (+x) */
    ref_camera c2 = {REF_PERSPECTIVE, {0, 0, 5}, {0, 0, 0}, {0, 0, 0}, 90.0, 0.0};
    double n = sqrt(1 + 4.0 / 9.0);
    ref_camera_ray(&c2, 3, 3, 1, 0, o, d);
    CHECK(near(d[1], 2.0 / 3.0 / n, 1e-15) && near(d[2], -1.0 / n, 1e-15) && fabs(d[0]) < 1e-16,
          "camera: row 0 is the top, default up +y");
    ref_camera_ray(&c2, 3, 3, 2, 1, o, d);
    CHECK(near(d[0], 2.0 / 3.0 / n, 1e-15), "camera: right = forward x up is +x");
    ref_camera_ray(&c2, 6, 3, 5, 1, o, d); /* aspect 2: u = (11/6 - 1) * 2 = 5/3 */
    CHECK(near(d[0] / -d[2], 5.0 / 3.0, 1e-14), "camera: u scales with W / H");
    ref_camera c3 = {REF_ORTHOGRAPHIC, {0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 0.0, 4.0};
    ref_camera_ray(&c3, 4, 4, 0, 0, o, d);
    CHECK(d[2] == -1.0 && near(o[0], -1.5, 1e-15) && near(o[1], 1.5, 1e-15) && o[2] == 5.0,
          "camera: orthographic origin on the image plane, direction forward");
    CHECK(ref_camera_ray(&(ref_camera){REF_PERSPECTIVE, {0, 0, 0}, {0, 0, 0}, {0}, 45, 0}, 4, 4, 0, 0, o, d) == -1 &&
              ref_camera_ray(&(ref_camera){REF_PERSPECTIVE, {0, 0, 0}, {0, 1, 0}, {0}, 45, 0}, 4, 4, 0, 0, o, d) == -1,
          "camera: eye = at and up parallel to forward refused");
    long k0, k1;
    CHECK(ref_lattice_range(0.35 * 3, 0.35 * 7, 0.35, 0.0, &k0, &k1) == 5 && k0 == 3 && k1 == 7,
          "lattice: samples on both ends included");
}

/* ---------------------------------------------------------------- (d) surfaces, budgets, spheres */

typedef struct wall {
    double t, rgb[3];
} wall;

static int wall_hit(const void *user, const ref_params *p, const double o[3], const double d[3], double *t, double rgb[3])
{
    const wall *w = user;
    (void)p, (void)o, (void)d;
    *t = w->t;
    for (int a = 0; a < 3; a++) rgb[a] = w->rgb[a];
    return 1;
}

static void test_surface(void)
{
    konst k = {{0.5, 0.5}};
    ref_tf tf[2] = {{0, 1, red, 1, tau_c, 1}, {0, 1, green, 1, tau_c2, 1}};
    ref_source src = {const_eval, &k, 1, {-1, -1, -1}, {1, 1, 1}};
    ref_params p = base_params(tf);
    /* box t in [9, 11], lattice k = 26 .. 31; a wall at t = 10 keeps k dt < 10: k = 26 .. 28 */
    wall w = {10.0, {0.2, 0.4, 0.6}};
    p.surface = wall_hit, p.surface_user = &w;
    double out[4], A = 1.0 - exp(-1.7 * 3 * 0.35);
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && near(out[3], 1.0, 1e-15) &&
              near(out[0], 0.9 * A + (1 - A) * 0.2, 1e-14) && near(out[2], 0.1 * A + (1 - A) * 0.6, 1e-14),
          "surface: samples strictly in front (3), then the surface behind them, A = 1");
    w.t = 0.35 * 27; /* a sample exactly at the surface is not taken */
    A = 1.0 - exp(-1.7 * 1 * 0.35);
    CHECK(ref_render_pixel(&src, &p, 2, 2, out) == 0 && near(out[0], 0.9 * A + (1 - A) * 0.2, 1e-14),
          "surface: t_k = t_hit excluded");
}

static void test_budget_spheres(void)
{
    const double pos[] = {0.0, 0.0, 0.0, 0.3, 0.0, 0.0}, rad[] = {0.5, 0.25}, val[] = {2.0, -1.0};
    ref_particle_set ps = {2, pos, rad, val, NULL, 1, 2.0, 1.0};
    const double x[3] = {0.1, 0.2, 0.0};
    double phi[1], as[1], gas[1], psn[1], gps[1];
    int cut;
    ref_particles_eval(&ps, x, phi, NULL);
    ref_particles_budget(&ps, x, as, gas, psn, gps, &cut);
    double p0 = 2.0 * exp(-0.05 / 0.5), p1 = -1.0 * exp(-0.08 / 0.125);
    CHECK(near(as[0], fabs(p0) + fabs(p1), 1e-14) && near(phi[0], p0 + p1, 1e-14) && !cut,
          "budget: sum |phi_i| %.15g = %.15g", as[0], fabs(p0) + fabs(p1));
    CHECK(near(gas[0], fabs(p0) * sqrt(0.05) / 0.25 + fabs(p1) * sqrt(0.08) / 0.0625, 1e-14) &&
              near(psn[0], fabs(p0) * sqrt(0.05) / 0.25 * 0.3 + fabs(p1) * sqrt(0.08) / 0.0625 * 0.6, 1e-14),
          "budget: gradient sum and position sensitivity");
    const double xe[3] = {1.0 + 1e-7, 0.0, 0.0}; /* at the first particle's cut-off sigma r = 1 */
    ref_particles_budget(&ps, xe, as, gas, psn, gps, &cut);
    CHECK(cut, "budget: a point at the cut-off is flagged");
    /* spheres of radius 2 r_i seen down -z, orthographic: the centre pixel hits particle 0's sphere at t = 5 - 1 */
    static const double col[] = {0.0, 0.2, 0.4, 0.6, 1.0, 1.0, 1.0, 1.0}, tau0[] = {0.0, 0.0};
    ref_tf tf = {0.0, 4.0, col, 2, tau0, 1};
    ref_sphere_set ss = {&ps, 2.0};
    ref_params p = {0};
    p.width = p.height = 5, p.tf = &tf, p.dt = 0.1, p.alpha_stop = 1.0, p.shading = REF_SHADE_NONE;
    p.camera = (ref_camera){REF_ORTHOGRAPHIC, {0, 0, 5}, {0, 0, 0}, {0, 0, 0}, 0.0, 0.1};
    double o[3], d[3], t, rgb[3], out[4];
    ref_camera_ray(&p.camera, 5, 5, 2, 2, o, d);
    /* value kappa k = 2 -> v = 0.5: rgb (0.6, 0.7, 0.8); n.d = 1 at the pole; lit even unshaded: ka + kd = 1 */
    int hit = ref_particles_spheres(&ss, &p, o, d, &t, rgb);
    CHECK(hit && near(t, 4.0, 1e-12) && near(rgb[0], 0.6, 1e-12) && near(rgb[2], 0.8, 1e-12),
          "spheres: hit t %.6g, rgb %.4g %.4g %.4g", t, rgb[0], rgb[1], rgb[2]);
    p.shading = REF_SHADE_PHONG; /* + ks |n.h|^p = 0.4 */
    ref_particles_spheres(&ss, &p, o, d, &t, rgb);
    CHECK(near(rgb[0], 1.0, 1e-12), "spheres: phong adds ks at the pole (%g)", rgb[0]);
    ref_source src;
    p.surface = ref_particles_spheres, p.surface_user = &ss;
    CHECK(ref_particles_source(&ps, &src) == 0 && ref_render_pixel(&src, &p, 2, 2, out) == 0 && out[3] == 1.0 &&
              near(out[0], 1.0, 1e-12), "spheres: a transparent volume in front of the sphere leaves its colour");
    p.camera.eye[1] = 3.0, p.camera.at[1] = 3.0; /* misses every sphere */
    CHECK(ref_particles_spheres(&ss, &p, p.camera.eye, d, &t, rgb) == 0, "spheres: a miss");
}

int main(void)
{
    char dir[] = "/tmp/ref_core_XXXXXX";
    const char *d = mkdtemp(dir);
    test_particle_field();
    test_grid_field();
    test_rbf_field();
    test_tf();
    test_constant_box();
    test_shading();
    test_particle_render();
    test_iso_slice();
    test_imgcmp(d);
    test_camera();
    test_surface();
    test_budget_spheres();
    if (d) rmdir(d);
    return check_summary("ref_core");
}
