/* Structured grids inside the host: the object, the loader's entry into it,
 * the pre-integrated table (host/grid_preint.c). */
#ifndef LC_HOST_GRID_H
#define LC_HOST_GRID_H

#include "scene.h"
#include "../bvh/grid_bvh.h"
#include "../kernels/shared/kgrid.h"

struct lc_grid {
    lc_device *dev;
    lc_grid_info info;
    void *owned;          /* owned voxels (padded for wide gathers), or NULL if borrowed */
    int32_t *offsets;     /* xoff | yoff | zoff */
    lci_grid_bvh bvh;
    lc_kgrid kg;          /* template: per-frame fields filled by lci_grid_prepare */
};

/* lc_grid_create with an option to take ownership of a malloc'd linear
 * buffer (the loader's), freed here on success or failure. */
lc_status lci_grid_create(lc_device *dev, const lc_grid_desc *desc, void *take, const char *name, lc_grid **out);

/* Fills the LC_PREINT_N^2 x (r, g, b, tau_mean) table (eq. 4) from a kernel
 * TF table of LC_TF_TABLE_SIZE x (r, g, b, tau), integrating its piecewise
 * linear interpolant exactly: tau_mean(a, b) = mean of tau over the values
 * from a to b; rgb = tau-weighted mean colour (emission without
 * self-attenuation across one segment). */
void lci_grid_preint(const float *rgbt, float *table);

int lci_value_size(lc_value_type t); /* bytes, 0 if unknown */

#endif
