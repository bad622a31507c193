/* Structured grids inside the host: the object and the pre-integrated table
 * (host/kinds/grid_preint.c). */
#ifndef LC_HOST_GRID_H
#define LC_HOST_GRID_H

#include <pthread.h>
#include "host/api/vcache.h"
#include "host/kinds/kind.h"
#include "bvh/grid_bvh.h"
#include "kernels/shared/kgrid.h"

typedef struct grid {
    lc_volume base;       /* first: the kind-neutral handle */
    lc_grid_info info;
    void *owned;          /* owned voxels (padded for wide gathers), or NULL if borrowed or a copy replaces them */
    void *pairs;          /* y-pair-packed (or with quads y- and z-paired) uint8 voxels (lc_kgrid.pairs), or NULL */
    int quads;            /* pairs is the z-paired uint32 layout (lc_kgrid.pair_quads) */
    size_t pair_bytes;    /* its allocation */
    int32_t *offsets;     /* xoff | yoff | zoff */
    lci_grid_bvh bvh;
    lc_kgrid kg;          /* template: per-frame fields filled by prepare */
    /* the per-frame tables of the last frame (host/kinds/grid_tables.c) */
    pthread_mutex_t tables_mu;
    int tables_mu_init;
    lci_vcache_entry *tables; /* an lci_grid_tables (host/api/vcache.h) */
    int windowed;         /* 1: holds a part of a larger grid (window) */
    struct lci_grid_window *window;
} grid;

/* kernels index voxels with int32 element offsets */
#define LCI_GRID_MAX_ELEMENTS ((int64_t)INT32_MAX - 64)

/* Voxel storage (host/kinds/grid_layout.c): the offset tables of n[0] x
 * n[1] x n[2] voxels in 4^3 bricks (elements: the array's length) or linear
 * with strides ys, zs; zeroed storage freed with lci_aligned_free; the uint8
 * copies of src (y-paired uint16, or y- and z-paired uint32 quads) at
 * strides ys, zs; the padded strides of a linear array of es-byte elements. */
void lci_grid_brick_tables(const int32_t n[3], const int32_t len[3], int32_t *xo, int32_t *yo, int32_t *zo,
                           int64_t *elements);
void lci_grid_linear_tables(const int32_t n[3], int64_t ys, int64_t zs, int32_t *xo, int32_t *yo, int32_t *zo);
void *lci_grid_voxel_alloc(size_t bytes);
void lci_grid_build_pairs(const uint8_t *src, const int32_t n[3], int64_t ys, int64_t zs, uint16_t *pairs);
void lci_grid_build_quads(const uint8_t *src, const int32_t n[3], int64_t ys, int64_t zs, uint32_t *quads);
void lci_grid_padded_strides(const int32_t n[3], int es, int64_t *ys, int64_t *zs);

/* A part of a grid held by one rank of a data-parallel render (host/mpi/):
 * the nodes from `start`, as many as the desc's size, of a grid of `full`
 * nodes. The volume is the whole grid to everything outside (info, bounds,
 * the BVH over the whole grid built from `bmin`/`bmax`, the brick ranges of
 * lci_grid_bvh_ranges united over all parts, value range, lattice); samples
 * are clamped to the cells held (lc_kgrid.cell_lo/hi); lc_grid_histogram
 * counts the nodes [own0, own1) (the parts' own ranges tile the grid) and
 * sums the parts' counts with `reduce` when set (collective: every part
 * calls it). */
typedef struct lci_grid_window {
    int32_t full[3], start[3];
    int32_t count[3];     /* nodes held (set by lci_grid_create_window from the desc) */
    int32_t own0[3], own1[3];
    const float *bmin, *bmax;
    lc_status (*reduce)(void *user, uint64_t *counts, int n);
    void *user;
    void (*user_free)(void *user); /* called on user when the volume goes */
    int part, parts;      /* which part of how many (the region it renders) */
} lci_grid_window;

/* Creates the part of a grid: d gives the held nodes (size, data) and the
 * whole grid's type, spacing, origin, brick and layout; w the rest (copied;
 * bmin/bmax are read here only; the volume owns user once this succeeds). */
lc_status lci_grid_create_window(lc_device *dev, const lc_grid_desc *d, const lci_grid_window *w, lc_volume **out);
/* The window of a grid volume: 1 and *w, or 0 for a whole grid. */
int lci_grid_window_of(const lc_volume *v, lci_grid_window *w);

/* The pre-integrated table, its one-step opacity and (with_nodes) the
 * per-node TF bits for frame f under k's parameters (host/kinds/grid_tables.c):
 * the volume's cached entry when its key matches, else a new one that
 * replaces it. The caller holds a reference (NULL: out of memory) until
 * lci_grid_tables_release; lci_grid_tables_fill points k's preint
 * and node_tf_bits at it (the one-step opacity only feeds the node bits). */
typedef struct lci_grid_tables lci_grid_tables;
lci_grid_tables *lci_grid_tables_get(grid *g, const lc_kgrid *k, const lc_kframe *f, int with_nodes);
void lci_grid_tables_fill(const lci_grid_tables *t, lc_kgrid *k);
void lci_grid_tables_release(lci_grid_tables *t);

/* Fills the LC_PREINT_N^2 x (r, g, b, tau_mean) table (eq. 4) from a kernel
 * TF table of LC_TF_TABLE_SIZE x (r, g, b, tau), integrating its piecewise
 * linear interpolant exactly: tau_mean(a, b) = mean of tau over the values
 * from a to b; rgb = tau-weighted mean colour (emission without
 * self-attenuation across one segment). */
void lci_grid_preint(const float *rgbt, float *table);

int lci_value_size(lc_value_type t); /* bytes, 0 if unknown */

#endif
