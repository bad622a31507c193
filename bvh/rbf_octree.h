/* The adaptive octree of an RBF set (Jang et al. 2004, §5), flattened into
 * lc_kcell arrays (bvh/rbf_octree.c). Includes nothing from host/. */
#ifndef LC_RBF_OCTREE_H
#define LC_RBF_OCTREE_H

#include <stddef.h>
#include <stdint.h>
#include "kernels/shared/koctree.h"

/* The RBFs in the order the kernels index them (leaf order), and the box
 * rays sample. */
typedef struct lci_octree_in {
    const float *cx, *cy, *cz; /* centres */
    const float *R;            /* supports R_i (eq. 3) */
    const float *w, *nis;      /* weights, -1 / (2 s_i^2) */
    size_t n;
    float lo[3], hi[3];        /* the root: the lattice clip box */
    int cell_max;              /* stop below this many RBFs per cell (1..) */
    int significant;           /* 1: leaves keep their cell_max most significant RBFs */
} lci_octree_in;

typedef struct lci_octree {
    lc_kcell *cells;
    int32_t *list;
    float *corr;       /* significant: LC_KCORR floats per cell; else NULL */
    int32_t ncells, nleaves, depth;
    int64_t nlist;     /* list entries */
    int64_t truncated; /* significant: list entries dropped from leaves */
    int32_t max_leaf;  /* the longest leaf list */
    double err_bound;  /* significant: the largest truncation bound of a leaf (see .c) */
} lci_octree;

/* Largest number of list entries a build may make (int32 offsets). */
#define LCI_OCTREE_MAX_LIST ((int64_t)1 << 30)

/* Builds the octree. Returns 0, or -1 with a message in err (out of memory,
 * or the lists would exceed LCI_OCTREE_MAX_LIST entries). */
int lci_octree_build(const lci_octree_in *in, lci_octree *out, char *err, size_t errlen);
void lci_octree_free(lci_octree *o);
size_t lci_octree_bytes(const lci_octree *o);

#endif
