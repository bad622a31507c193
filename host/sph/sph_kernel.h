/* The SPH kernels as dimensionless shapes (host side, double precision).
 *
 * One convention everywhere in lanecast: H is the kernel's support radius
 * (GADGET's and yt's HSML), u = r / H, and
 *     W(r, H) = norm / H^3 * f(u),   f(u) = 0 for u >= 1,
 * normalised in 3-D (integral of W over space = 1). The kernels' own
 * conventions (M4 with h = H/2, M5 h = H/2.5, M6 h = H/3; Wendland with h = H)
 * are converted into this one here. Kernel code evaluates the same
 * polynomials in its own lane vocabulary; these are the host's copies for
 * tables (column kernels, projections) and for the formats' h -> H
 * conversion. LC_KERNEL_GAUSSIAN has no compact support and is not an SPH
 * kernel here: its entries are NULL / 0. */
#ifndef LC_SPH_KERNEL_H
#define LC_SPH_KERNEL_H

#include "lanecast/lanecast.h"

typedef struct lci_sph_kernel {
    const char *name;   /* lc_kernel_name */
    double norm;        /* 3-D normalisation in units of 1 / H^3 */
    double swift_gamma; /* H / h for SWIFT's (Dehnen & Aly 2012) h: H = gamma h */
    double (*f)(double u);  /* shape on [0, 1], 0 beyond */
    double (*df)(double u); /* its derivative in u, 0 beyond */
} lci_sph_kernel;

/* NULL for LC_KERNEL_GAUSSIAN and out-of-range values. */
const lci_sph_kernel *lci_sph_kernel_get(lc_kernel kernel);

#endif
