/* Column kernels and their separable cumulative tables (issue 27).
 *
 * A particle of support S (H for the SPH kernels, sigma r for the Gaussian)
 * and amount m projects to the surface density m / S^2 g(x / S, y / S) with
 *     g(u, v) = F(sqrt(u^2 + v^2)),  F(b) = norm * int f(sqrt(b^2 + z^2)) dz
 * over the chord (F = 0 for b >= 1), normalised so the integral of g over the
 * plane is 1. A pixel's exact average is the integral of g over the pixel's
 * rectangle [u0, u1] x [v0, v1], the difference of four values of the
 * cumulative table Q(u, v) = int_0^u int_0^v g. Q is kept in separable
 * (eigen) form: g(u, v) = sum_k mu_k phi_k(|u|) phi_k(|v|) (Nystrom on
 * Gauss-Legendre nodes, Jacobi rotations), so
 *     Q(u1..u0, v1..v0) = sum_k mu_k [A_k(u1) - A_k(u0)] [A_k(v1) - A_k(v0)],
 * A_k(u) = int_0^u phi_k (odd in u), tabulated with phi_k on LCI_COL_NT + 1
 * nodes of [0, 1] for cubic Hermite lookups in double (kernels/sph_project.c
 * does the lookups and the pixels, once per target). The four-lookup
 * difference then factorises into one 1-D difference per pixel column and
 * row of a particle's footprint and a rank-K dot product per pixel. mu_0
 * carries the truncated components' mass, so a particle's pixels sum to m to
 * rounding at any S / pixel.
 *
 * The Gaussian (LC_KERNEL_GAUSSIAN) is the 3-D Gaussian of standard
 * deviation r cut at +-LCI_COL_GAUSS r on each axis (a cube, where it is
 * below 4e-6 of its peak) and normalised to unit mass inside it: it stays
 * separable, so its pixel averages are exact products of erf differences
 * (rank 1) and its partial columns in a slab are its column times the mass
 * fraction inside the slab. The ray casters' sigma truncation is a speed
 * device of theirs and does not apply. Tables are built once per kernel and
 * kept for the process. */
#ifndef LC_SPH_COLUMN_H
#define LC_SPH_COLUMN_H

#include "lanecast/lanecast.h"
#include "kernels/sph_project.h"

#define LCI_COL_NT 1024   /* nodes - 1 on [0, 1] where A_k and phi_k are computed */
#ifndef LCI_COL_NK
#define LCI_COL_NK 256    /* nodes - 1 of the lookup tables (every LCI_COL_NT / LCI_COL_NK-th node) */
#endif
#define LCI_COL_KMAX 48   /* largest rank kept */
#define LCI_COL_NQ 4096   /* entries - 1 of the centre-sampling table over q = b^2 */
#define LCI_COL_NZ 256    /* slab tables: nodes - 1 per axis */
#define LCI_COL_GAUSS 5.0 /* the Gaussian's support in standard deviations */

typedef struct lci_column {
    lc_kernel kernel;
    double norm;          /* 3-D normalisation of the shape in units of 1 / S^3 */
    double f0;            /* F(0): the peak of the column in units of 1 / S^2 */
    int rank;             /* K terms kept */
    double err;           /* largest |g - g_K| over a check grid, relative to F(0) */
    double mu[LCI_COL_KMAX];
    double *tab;          /* (LCI_COL_NK + 1) nodes x 2 kpad: A_k(u_j) (k < kpad, 0 beyond rank), then phi_k(u_j) / LCI_COL_NK */
    double *marg;         /* (LCI_COL_NK + 1) x 2: M(u_j) = int_0^u_j int_-1^1 g = 2 sum_k mu_k A_k(1) A_k(u_j), M' / LCI_COL_NK */
    lc_kproj_table kt;    /* the kernels' view of tab, mu and marg (kernels/sph_project.h) */
    float *fq;            /* F at q = b^2 = i / LCI_COL_NQ, i = 0 .. LCI_COL_NQ + 1 (the last two 0) */
    /* slabs: the partial column T(b, s) = norm int_0^{s c(b)} f(sqrt(b^2 + z^2)) dz
       (c(b) = sqrt(1 - b^2)) on (LCI_COL_NZ + 1)^2 nodes of b, s in [0, 1], and the
       mass fraction below height z, mz(z) for z in [-1, 1] on 2 LCI_COL_NZ + 1 nodes */
    float *slab;          /* NULL for the Gaussian (separable in z) */
    double *mz;
} lci_column;

/* The support S of a particle of radius r: r for the SPH kernels (r = H),
 * LCI_COL_GAUSS r for the Gaussian (r its standard deviation). */
static inline double lci_column_support(lc_kernel kernel, double r)
{
    return kernel == LC_KERNEL_GAUSSIAN ? LCI_COL_GAUSS * r : r;
}

/* The tables of a kernel, built on first use and kept; thread-safe. NULL
 * when out of memory (message on dev). */
const lci_column *lci_column_get(lc_device *dev, lc_kernel kernel);

/* F(b) in units of 1 / S^2 (0 for b >= 1) from the centre-sampling table
 * (linear in b^2; q = b^2). */
static inline float lci_column_fq(const lci_column *c, float q)
{
    if (!(q < 1.0f)) return 0.0f;
    float x = q * (float)LCI_COL_NQ;
    int i = (int)x;
    float t = x - (float)i;
    return c->fq[i] + t * (c->fq[i + 1] - c->fq[i]);
}


/* The mass fraction of the kernel between heights z0 < z1 (units of S). */
double lci_column_slab_mass(const lci_column *c, double z0, double z1);
/* The partial column between heights z0 < z1 at impact parameter b (units
 * of S), in units of 1 / S^2. */
float lci_column_partial(const lci_column *c, float b, float z0, float z1);

/* F(b) computed by quadrature (no table), for checks. */
double lci_column_exact(const lci_column *c, double b);

#endif
