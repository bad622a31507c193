/* The reference of the projection tests (tests/test_sph_project*.c), written
 * from the formulas of SPEC.md "SPH kernels and projections", never from the
 * library's tables: the kernel shapes in the support-radius convention, their
 * line-of-sight column F(b) and a pixel's average of it by nested
 * Gauss-Legendre quadrature split at every radius where the integrand is not
 * smooth (the Gaussian: its cube-cut separable form, products of erf
 * differences). Call gl_init() first. */
#ifndef LC_TEST_SPH_PROJECT_REF_H
#define LC_TEST_SPH_PROJECT_REF_H

#include <math.h>
#include <stdio.h>
#include "lanecast/lanecast.h"

/* ---------------------------------------------------------------- kernel shapes (SPEC.md) */

static inline double pos(double x) { return x > 0.0 ? x : 0.0; }
static inline double p3(double x) { return x * x * x; }
static inline double p4(double x) { return x * x * x * x; }
static inline double p5(double x) { return x * x * x * x * x; }
/* w(u) in the support-radius convention, normalised in 3-D */
static inline double shape(lc_kernel k, double u)
{
    if (u >= 1.0) return 0.0;
    switch (k) {
    case LC_KERNEL_M4: return 8.0 / M_PI * (u <= 0.5 ? 1 - 6 * u * u + 6 * u * u * u : 2 * p3(1 - u));
    case LC_KERNEL_M5: {
        double q = 2.5 * u;
        return 15.625 / (20 * M_PI) * (p4(pos(2.5 - q)) - 5 * p4(pos(1.5 - q)) + 10 * p4(pos(0.5 - q)));
    }
    case LC_KERNEL_M6: {
        double q = 3 * u;
        return 27.0 / (120 * M_PI) * (p5(pos(3 - q)) - 6 * p5(pos(2 - q)) + 15 * p5(pos(1 - q)));
    }
    case LC_KERNEL_WENDLAND_C2: return 21 / (2 * M_PI) * p4(1 - u) * (1 + 4 * u);
    case LC_KERNEL_WENDLAND_C4: return 495 / (32 * M_PI) * p3(1 - u) * p3(1 - u) * (1 + 6 * u + 35 * u * u / 3);
    case LC_KERNEL_WENDLAND_C6: return 1365 / (64 * M_PI) * p4(1 - u) * p4(1 - u) * (1 + 8 * u + 25 * u * u + 32 * u * u * u);
    default: return 0.0;
    }
}
static inline int kinks(lc_kernel k, double *r)
{
    if (k == LC_KERNEL_M4) return r[0] = 0.5, 1;
    if (k == LC_KERNEL_M5) return r[0] = 0.2, r[1] = 0.6, 2;
    if (k == LC_KERNEL_M6) return r[0] = 1.0 / 3, r[1] = 2.0 / 3, 2;
    return 0;
}

/* Gauss-Legendre nodes on [0, 1] */
#define NG 20
static double gx[NG], gw[NG];
static inline void gl_init(void)
{
    for (int i = 0; i < NG; i++) {
        double z = cos(M_PI * (i + 0.75) / (NG + 0.5)), dp = 1;
        for (int it = 0; it < 100; it++) {
            double p0 = 1, p1 = z;
            for (int k = 2; k <= NG; k++) {
                double p2 = ((2.0 * k - 1) * z * p1 - (k - 1.0) * p0) / k;
                p0 = p1, p1 = p2;
            }
            dp = NG * (z * p1 - p0) / (z * z - 1);
            double d = p1 / dp;
            z -= d;
            if (fabs(d) < 1e-16) break;
        }
        gx[i] = 0.5 * (1 - z), gw[i] = 1 / ((1 - z * z) * dp * dp);
    }
}
/* int_a^b g over pieces split at the sorted cuts inside (a, b), each piece in `panels` parts */
typedef double (*fn1)(const void *ctx, double x);
static inline double integrate(fn1 g, const void *ctx, double a, double b, const double *cuts, int nc, int panels)
{
    double pts[16];
    int n = 0;
    pts[n++] = a;
    for (int i = 0; i < nc; i++)
        if (cuts[i] > a && cuts[i] < b) pts[n++] = cuts[i];
    pts[n++] = b;
    for (int i = 1; i < n; i++) /* sort */
        for (int j = i; j > 0 && pts[j] < pts[j - 1]; j--) {
            double t = pts[j];
            pts[j] = pts[j - 1], pts[j - 1] = t;
        }
    double sum = 0;
    for (int p = 0; p + 1 < n; p++)
        for (int q = 0; q < panels; q++) {
            double lo = pts[p] + (pts[p + 1] - pts[p]) * q / panels, h = (pts[p + 1] - pts[p]) / panels, s = 0;
            for (int i = 0; i < NG; i++) s += gw[i] * g(ctx, lo + h * gx[i]);
            sum += h * s;
        }
    return sum;
}

typedef struct col_ctx {
    lc_kernel k;
    double b;
} col_ctx;
static inline double col_integrand(const void *c, double z)
{
    const col_ctx *cc = c;
    return shape(cc->k, sqrt(cc->b * cc->b + z * z));
}
/* F(b) = 2 int_0^sqrt(1 - b^2) w(sqrt(b^2 + z^2)) dz, in units of 1 / H^2 */
static inline double column_ref(lc_kernel k, double b)
{
    if (b >= 1) return 0;
    double r[2], cuts[2];
    int nk = kinks(k, r), nc = 0;
    for (int i = 0; i < nk; i++)
        if (r[i] > b) cuts[nc++] = sqrt(r[i] * r[i] - b * b);
    col_ctx c = {k, b};
    return 2 * integrate(col_integrand, &c, 0, sqrt(1 - b * b), cuts, nc, 1);
}

/* ---------------------------------------------------------------- pixel averages */

typedef struct pix_ctx {
    lc_kernel k;
    double y;         /* inner: fixed y (units of H) */
    double x0, x1;    /* inner range */
} pix_ctx;
static inline double inner(const void *c, double x)
{
    const pix_ctx *p = c;
    return column_ref(p->k, sqrt(x * x + p->y * p->y));
}
static inline double outer(const void *c, double y)
{
    const pix_ctx *p0 = c;
    pix_ctx p = *p0;
    p.y = y;
    double r[3], cuts[7];
    int nk = kinks(p.k, r), nc = 0;
    r[nk++] = 1.0;
    cuts[nc++] = 0.0; /* the centre: odd powers of u (M4, Wendland) make F(b) not smooth at b = 0 */
    for (int i = 0; i < nk; i++)
        if (r[i] > fabs(y)) {
            double x = sqrt(r[i] * r[i] - y * y);
            cuts[nc++] = x, cuts[nc++] = -x;
        }
    return integrate(inner, &p, p.x0, p.x1, cuts, nc, 1);
}
/* int over [x0, x1] x [y0, y1] of F(sqrt(x^2 + y^2)) (units of H) */
static inline double pixel_ref(lc_kernel k, double x0, double x1, double y0, double y1)
{
    x0 = fmax(x0, -1), x1 = fmin(x1, 1), y0 = fmax(y0, -1), y1 = fmin(y1, 1);
    if (x0 >= x1 || y0 >= y1) return 0;
    if (k == LC_KERNEL_GAUSSIAN) { /* cube-cut at 5 sigma: S = 5 r, u = x / S */
        double e = erf(5 / sqrt(2.0));
        return (erf(5 * x1 / sqrt(2.0)) - erf(5 * x0 / sqrt(2.0))) * (erf(5 * y1 / sqrt(2.0)) - erf(5 * y0 / sqrt(2.0))) /
               (4 * e * e);
    }
    double r[3], cuts[7];
    int nk = kinks(k, r), nc = 0;
    r[nk++] = 1.0;
    cuts[nc++] = 0.0;
    for (int i = 0; i < nk; i++) cuts[nc++] = r[i], cuts[nc++] = -r[i];
    pix_ctx p = {k, 0, x0, x1};
    return integrate(outer, &p, y0, y1, cuts, nc, 1);
}

/* ---------------------------------------------------------------- views and helpers */

/* A view down -z of the square [-half, half]^2 around the origin, N pixels a side. */
static inline lc_project_desc view(int N, double half, lc_project_sample s)
{
    lc_project_desc d = {.width = N, .height = N, .sample = s};
    d.camera = (lc_camera){LC_ORTHOGRAPHIC, {0, 0, 100}, {0, 0, 0}, {0, 1, 0}, 0, (float)(2 * half)};
    return d;
}

static inline double map_mass(const float *map, int N, double pix)
{
    double s = 0;
    for (int i = 0; i < N * N; i++) s += map[i];
    return s * pix * pix;
}

static const lc_kernel all_kernels[7] = {LC_KERNEL_M4, LC_KERNEL_M5, LC_KERNEL_M6, LC_KERNEL_WENDLAND_C2,
                                        LC_KERNEL_WENDLAND_C4, LC_KERNEL_WENDLAND_C6, LC_KERNEL_GAUSSIAN};

static inline double urand(unsigned *s)
{
    *s = *s * 1664525u + 1013904223u;
    return (*s >> 8) / 16777216.0;
}

static inline const char *dev_target_name(const lc_device *d)
{
    lc_target t = LC_TARGET_AUTO;
    lc_device_target(d, &t);
    return lc_target_name(t);
}

/* Devices of every target this machine runs, first the default one (def);
 * the others print why they are skipped. Returns how many. */
static inline int open_targets(lc_device *def, int threads, lc_device **out)
{
    lc_target td = LC_TARGET_AUTO;
    lc_device_target(def, &td);
    int n = 0;
    out[n++] = def;
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        if (t == (int)td) continue;
        if (!lc_target_compiled((lc_target)t) || !lc_target_supported((lc_target)t)) {
            printf("     skip %s: not compiled or not supported by this CPU\n", lc_target_name((lc_target)t));
            continue;
        }
        lc_device_desc dd = {.target = (lc_target)t, .threads = threads};
        if (lc_device_create(&dd, &out[n]) == LC_OK) n++;
        else printf("     device %s: %s\n", lc_target_name((lc_target)t), lc_last_error());
    }
    return n;
}

#endif
