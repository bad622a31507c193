/* The SPH kernel shapes (host/sph/sph_kernel.c) against the formulas:
 * each integrates to 1 over space (Simpson, 4 pi H^3 int u^2 norm f du),
 * vanishes at u = 1, has the derivative of finite differences, and the
 * line-of-sight column through the centre matches the closed forms
 * F(0) = 3 / (2 pi h^2) for M4 (h = H / 2) and 7 / (4 pi h^2) for Wendland C2
 * in the same h (issue 27); names round-trip through lc_kernel_from_name. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "check.h"
#include "host/sph/sph_kernel.h"


/* Simpson's rule of g on [a, b] with n (even) intervals. */
static double simpson(double (*g)(const lci_sph_kernel *, double), const lci_sph_kernel *k, double a, double b, int n)
{
    double h = (b - a) / n, s = g(k, a) + g(k, b);
    for (int i = 1; i < n; i++) s += (i % 2 ? 4.0 : 2.0) * g(k, a + i * h);
    return s * h / 3.0;
}
static double shell(const lci_sph_kernel *k, double u) { return 4.0 * M_PI * u * u * k->norm * k->f(u); }
static double line(const lci_sph_kernel *k, double u) { return 2.0 * k->norm * k->f(u); }

int main(void)
{
    for (int i = LC_KERNEL_M4; i <= LC_KERNEL_WENDLAND_C6; i++) {
        const lci_sph_kernel *k = lci_sph_kernel_get((lc_kernel)i);
        CHECK_QUIET(k != NULL, "kernel %d missing", i);
        if (!k) continue;
        /* piecewise kernels have breaks at multiples of 0.1 (M4 0.5, M5 0.2/0.6, M6 1/3, 2/3): integrate per piece */
        const double br[] = {0.0, 0.2, 1.0 / 3.0, 0.5, 0.6, 2.0 / 3.0, 1.0};
        double mass = 0.0;
        for (int b = 0; b + 1 < 7; b++) mass += simpson(shell, k, br[b], br[b + 1], 2000);
        CHECK_QUIET(fabs(mass - 1.0) < 1e-10, "%s: integral of W = %.12f", k->name, mass);
        CHECK_QUIET(k->f(1.0) == 0.0 && k->f(1.5) == 0.0 && k->f(-0.1) == 0.0, "%s: not zero outside [0, 1)", k->name);
        CHECK_QUIET(fabs(k->f(1.0 - 1e-6)) < 1e-12, "%s: f not continuous at u = 1", k->name);
        CHECK_QUIET(k->f(0.0) > 0.0, "%s: f(0) = %g", k->name, k->f(0.0));
        for (double u = 0.013; u < 1.0; u += 0.0371) {
            double e = 1e-6, fd = (k->f(u + e) - k->f(u - e)) / (2.0 * e);
            CHECK_QUIET(fabs(fd - k->df(u)) < 1e-6 * (1.0 + fabs(fd)), "%s: df(%g) = %g, finite difference %g", k->name, u,
                  k->df(u), fd);
        }
        lc_kernel back;
        CHECK_QUIET(lc_kernel_from_name(k->name, &back) == LC_OK && back == (lc_kernel)i, "%s: name round trip", k->name);
        CHECK_QUIET(strcmp(lc_kernel_name((lc_kernel)i), k->name) == 0, "%s: lc_kernel_name", k->name);
        CHECK_QUIET(k->swift_gamma > 1.5 && k->swift_gamma < 2.5, "%s: gamma %g", k->name, k->swift_gamma);
    }
    /* column through the centre, H = 1: M4's h = 1/2, C2's "same convention" h = H / 2 */
    const lci_sph_kernel *m4 = lci_sph_kernel_get(LC_KERNEL_M4), *c2 = lci_sph_kernel_get(LC_KERNEL_WENDLAND_C2);
    double f4 = simpson(line, m4, 0.0, 0.5, 2000) + simpson(line, m4, 0.5, 1.0, 2000);
    double h = 0.5;
    CHECK_QUIET(fabs(f4 - 3.0 / (2.0 * M_PI * h * h)) < 1e-10, "M4 F(0) = %.12f, expected %.12f", f4, 3.0 / (2.0 * M_PI * h * h));
    double fc2 = simpson(line, c2, 0.0, 1.0, 4000);
    CHECK_QUIET(fabs(fc2 - 7.0 / (4.0 * M_PI * h * h)) < 1e-10, "C2 F(0) = %.12f, expected %.12f", fc2,
          7.0 / (4.0 * M_PI * h * h));
    lc_kernel k;
    CHECK_QUIET(lc_kernel_from_name("gaussian", &k) == LC_OK && k == LC_KERNEL_GAUSSIAN, "gaussian by name");
    CHECK_QUIET(lc_kernel_from_name("cubic", &k) == LC_ERROR_INVALID_ARGUMENT, "unknown name accepted");
    CHECK_QUIET(lc_kernel_name((lc_kernel)7) == NULL && lci_sph_kernel_get(LC_KERNEL_GAUSSIAN) == NULL, "range");
    return check_summary("sph_kernel");
}
