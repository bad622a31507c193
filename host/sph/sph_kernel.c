/* SPH kernel shapes in the support-radius convention (sph_kernel.h).
 * Normalisations: M4 1/(pi h^3), M5 1/(20 pi h^3), M6 1/(120 pi h^3)
 * (Monaghan 1985; Price 2012), Wendland C2 21/(2 pi H^3), C4 495/(32 pi H^3),
 * C6 1365/(64 pi H^3) (Dehnen & Aly 2012); tests/test_sph_kernel.c
 * integrates each to 1. */
#include <math.h>
#include <stddef.h>
#include <string.h>
#include "host/sph/sph_kernel.h"

static double pos(double x) { return x > 0.0 ? x : 0.0; }
static double p3(double x) { return x * x * x; }
static double p4(double x) { return x * x * x * x; }
static double p5(double x) { return x * x * x * x * x; }

/* M4 with q = 2u: 1 - 1.5 q^2 + 0.75 q^3 (q < 1), 0.25 (2 - q)^3 (q < 2). */
static double m4(double u)
{
    if (u >= 1.0 || u < 0.0) return 0.0;
    return u < 0.5 ? 1.0 - 6.0 * u * u + 6.0 * u * u * u : 2.0 * p3(1.0 - u);
}
static double m4d(double u)
{
    if (u >= 1.0 || u < 0.0) return 0.0;
    return u < 0.5 ? -12.0 * u + 18.0 * u * u : -6.0 * (1.0 - u) * (1.0 - u);
}
/* M5 with q = 2.5u: (2.5-q)^4 - 5 (1.5-q)^4 + 10 (0.5-q)^4, each term where positive. */
static double m5(double u)
{
    if (u >= 1.0 || u < 0.0) return 0.0;
    double q = 2.5 * u;
    return p4(pos(2.5 - q)) - 5.0 * p4(pos(1.5 - q)) + 10.0 * p4(pos(0.5 - q));
}
static double m5d(double u)
{
    if (u >= 1.0 || u < 0.0) return 0.0;
    double q = 2.5 * u;
    return -2.5 * 4.0 * (p3(pos(2.5 - q)) - 5.0 * p3(pos(1.5 - q)) + 10.0 * p3(pos(0.5 - q)));
}
/* M6 with q = 3u: (3-q)^5 - 6 (2-q)^5 + 15 (1-q)^5, each term where positive. */
static double m6(double u)
{
    if (u >= 1.0 || u < 0.0) return 0.0;
    double q = 3.0 * u;
    return p5(pos(3.0 - q)) - 6.0 * p5(pos(2.0 - q)) + 15.0 * p5(pos(1.0 - q));
}
static double m6d(double u)
{
    if (u >= 1.0 || u < 0.0) return 0.0;
    double q = 3.0 * u;
    return -3.0 * 5.0 * (p4(pos(3.0 - q)) - 6.0 * p4(pos(2.0 - q)) + 15.0 * p4(pos(1.0 - q)));
}
/* Wendland C2: (1-u)^4 (1 + 4u). */
static double c2(double u) { return u >= 1.0 || u < 0.0 ? 0.0 : p4(1.0 - u) * (1.0 + 4.0 * u); }
static double c2d(double u) { return u >= 1.0 || u < 0.0 ? 0.0 : -20.0 * u * p3(1.0 - u); }
/* Wendland C4: (1-u)^6 (1 + 6u + 35/3 u^2). */
static double c4(double u)
{
    if (u >= 1.0 || u < 0.0) return 0.0;
    double t = 1.0 - u;
    return p3(t) * p3(t) * (1.0 + 6.0 * u + 35.0 / 3.0 * u * u);
}
static double c4d(double u)
{
    if (u >= 1.0 || u < 0.0) return 0.0;
    double t = 1.0 - u;
    return -56.0 / 3.0 * u * (1.0 + 5.0 * u) * p5(t);
}
/* Wendland C6: (1-u)^8 (1 + 8u + 25u^2 + 32u^3). */
static double c6(double u)
{
    if (u >= 1.0 || u < 0.0) return 0.0;
    double t = p4(1.0 - u);
    return t * t * (1.0 + 8.0 * u + 25.0 * u * u + 32.0 * u * u * u);
}
static double c6d(double u)
{
    if (u >= 1.0 || u < 0.0) return 0.0;
    double t = 1.0 - u;
    return -22.0 * u * (1.0 + 7.0 * u + 16.0 * u * u) * p4(t) * p3(t);
}

static const lci_sph_kernel kernels[] = {
    [LC_KERNEL_M4] = {"m4", 8.0 / M_PI, 1.825742, m4, m4d},
    [LC_KERNEL_M5] = {"m5", 15.625 / (20.0 * M_PI), 2.018932, m5, m5d},
    [LC_KERNEL_M6] = {"m6", 27.0 / (120.0 * M_PI), 2.195775, m6, m6d},
    [LC_KERNEL_WENDLAND_C2] = {"wendland-c2", 21.0 / (2.0 * M_PI), 1.936492, c2, c2d},
    [LC_KERNEL_WENDLAND_C4] = {"wendland-c4", 495.0 / (32.0 * M_PI), 2.207940, c4, c4d},
    [LC_KERNEL_WENDLAND_C6] = {"wendland-c6", 1365.0 / (64.0 * M_PI), 2.449490, c6, c6d},
};

const lci_sph_kernel *lci_sph_kernel_get(lc_kernel kernel)
{
    if (kernel <= LC_KERNEL_GAUSSIAN || kernel > LC_KERNEL_WENDLAND_C6) return NULL;
    return &kernels[kernel];
}

const char *lc_kernel_name(lc_kernel kernel)
{
    if (kernel == LC_KERNEL_GAUSSIAN) return "gaussian";
    const lci_sph_kernel *k = lci_sph_kernel_get(kernel);
    return k ? k->name : NULL;
}

lc_status lc_kernel_from_name(const char *name, lc_kernel *out)
{
    if (!name || !out) return LC_ERROR_INVALID_ARGUMENT;
    for (int k = LC_KERNEL_GAUSSIAN; k <= LC_KERNEL_WENDLAND_C6; k++) {
        const char *n = lc_kernel_name((lc_kernel)k);
        if (n && strcmp(n, name) == 0) {
            *out = (lc_kernel)k;
            return LC_OK;
        }
    }
    return LC_ERROR_INVALID_ARGUMENT;
}
