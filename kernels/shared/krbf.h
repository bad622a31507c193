/* The RBF set as kernels read it (Jang et al. 2004, eqs. 2-3): the flat
 * binary BVH of the particle builder over the RBF centres, with a per-node
 * largest support R so a node's box grows by it at traversal time, and
 * structure-of-arrays RBF data in leaf order. One field. */
#ifndef LC_KRBF_H
#define LC_KRBF_H

#include <stdint.h>
#include "kparticles.h" /* lc_kpnode: the same node layout and builder */
#include "koctree.h"    /* lc_kcell: the optional octree (accel = octree) */

typedef struct lc_krbf {
    const lc_kpnode *nodes;  /* nodes[0] is the root; NULL when no RBF is kept */
    const float *node_rmax;  /* per node: largest support R_i below it */
    const float *cx, *cy, *cz; /* centres mu_i */
    const float *r2;         /* R_i^2: the term counts where |x - mu_i|^2 < R_i^2 */
    const float *nis;        /* -1 / (2 s_i^2) */
    const float *w;          /* weights w_i */
    int64_t count;
    int32_t nnodes;
    int32_t depth;           /* longest root-to-leaf path; stacks hold depth + 4 entries */
    float bias;              /* w0 */
    int32_t empty;           /* 1: the clip box is empty, no ray samples */
    float lo[4], hi[4];      /* lattice clip box: the domain or the union of the supports */
    /* the octree (LC_KMETHOD_CELLS and point sampling when built; NULL otherwise) */
    const lc_kcell *cells;   /* cells[0] is the root */
    const int32_t *cell_list; /* RBF indices per leaf, ascending */
    const float *cell_corr;  /* significant mode: LC_KCORR floats per cell; NULL: exact lists */
    int32_t ncells;
    int32_t pad;
} lc_krbf;
_Static_assert(sizeof(lc_krbf) == 8 * 8 + 8 + 8 + 8 + 32 + 3 * 8 + 8, "lc_krbf layout");

#endif
