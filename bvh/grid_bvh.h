/* The implicit min-max BVH of a structured grid (Knoll et al. 2011 §5.1),
 * built once per grid with baseline flags; kernels read the flat node array. */
#ifndef LC_BVH_GRID_BVH_H
#define LC_BVH_GRID_BVH_H

#include <stddef.h>
#include <stdint.h>
#include "kernels/shared/kgrid.h"

typedef struct lci_grid_bvh {
    lc_kgrid_node *nodes; /* nnodes, root at 0, children adjacent */
    int32_t nnodes, nleaves, depth, brick;
    double seconds; /* set by the caller, which times the build */
    uint64_t bytes;
} lci_grid_bvh;

/* Builds from linear voxels (x fastest) of LC_KVAL_* type. L: leaf side.
 * Returns 0, or -1 when out of memory (out is then empty). */
int lci_grid_bvh_build(const void *data, int type, const int32_t size[3], const float origin[3], const float spacing[3],
                       int L, lci_grid_bvh *out);
void lci_grid_bvh_free(lci_grid_bvh *bvh);

/* The same build in two steps, for a grid held in parts (host/mpi/): the
 * min/max of each leaf brick (lci_grid_bvh_bricks of them, x fastest),
 * accumulated from the count[0] x count[1] x count[2] nodes from node
 * `start` of a grid of `size` nodes (linear, x fastest) into bmin/bmax
 * (set to +-FLT_MAX by lci_grid_bvh_ranges_init); the union of the parts'
 * ranges (min of bmin, max of bmax) is the whole grid's. Then the tree from
 * those ranges: the nodes lci_grid_bvh_build gives the whole grid. 0 or -1
 * (out of memory). */
size_t lci_grid_bvh_bricks(const int32_t size[3], int L);
void lci_grid_bvh_ranges_init(size_t nbricks, float *bmin, float *bmax);
int lci_grid_bvh_ranges(const void *data, int type, const int32_t start[3], const int32_t count[3],
                        const int32_t size[3], int L, float *bmin, float *bmax);
int lci_grid_bvh_from_ranges(const float *bmin, const float *bmax, const int32_t size[3], const float origin[3],
                             const float spacing[3], int L, lci_grid_bvh *out);
/* The default leaf side for a grid size: 4 up to 256^3-ish, 8 up to 1024^3,
 * 16 beyond (keeps the node array near 1/10 of the voxel bytes or less). */
int lci_grid_bvh_default_brick(const int32_t size[3]);

#endif
