/* The adaptive octree of an RBF set (Jang et al. 2004, §5) as kernels read
 * it: a flat cell array whose inner cells split at a point chosen from the
 * RBF centres (non-uniform subdivision; the 8 children are adjacent, octant
 * bit 0 = x >= split.x, bit 1 = y, bit 2 = z) and whose leaves hold a range
 * of an index list naming the RBFs whose support reaches the cell, in
 * ascending (BVH leaf) order. Built by bvh/rbf_octree.c. */
#ifndef LC_KOCTREE_H
#define LC_KOCTREE_H

#include <stdint.h>

typedef struct lc_kcell {
    /* leaf: the region the descent assigns to it, [lo, hi) per axis, with the
       faces on the root's boundary at -inf / +inf, so a point's leaf found by
       descent always passes this test and the test never disagrees with it */
    float lo[3];
    int32_t child;   /* inner: index of the first of its 8 children; leaf: -1 */
    float hi[3];
    int32_t first;   /* leaf: first entry of its list */
    float split[3];  /* inner: the split point */
    int32_t count;   /* leaf: entries in its list */
} lc_kcell;
_Static_assert(sizeof(lc_kcell) == 48, "lc_kcell layout");

/* Significant mode: per cell LC_KCORR floats: the finite box's lo (3), its
   inverse extent (3), 2 unused, then the truncation error (the sum of the
   dropped terms) at the 8 corners, corner c at x = bit 0, y = bit 1, z = bit 2. */
#define LC_KCORR 16

#endif
