/* The particle scene as kernels read it (Knoll 2014): a flat binary BVH whose
 * node boxes bound the particle centres, a per-node maximum radius so the box
 * grows by sigma * rmax at traversal time (sigma and kappa change without a
 * rebuild, paper §5.3), a per-node value bound for the mode's culling test, and structure-of-arrays particle data in leaf order. */
#ifndef LC_KPARTICLES_H
#define LC_KPARTICLES_H

#include <stdint.h>
#include "kframe.h"

/* Inner node: count == 0, children at first and first + 1.
 * Leaf: count >= 1 particles starting at first. */
typedef struct lc_kpnode {
    float lo[3];
    int32_t first;
    float hi[3];
    int32_t count;
} lc_kpnode;
_Static_assert(sizeof(lc_kpnode) == 32, "lc_kpnode layout");

typedef struct lc_kparticles {
    const lc_kpnode *nodes; /* nodes[0] is the root; NULL when empty */
    const float *node_rmax; /* per node: largest radius below it */
    const float *node_ksum; /* per node: sum of |k_i| below it, so |kappa| * node_ksum bounds the
                               node's own contribution to any field (others add to it) */
    const uint8_t *node_clear; /* dvr, this frame: 1 where no particle below the node can change a
                                  sample (host/kinds/particles.c clear_nodes); NULL = none */
    const float *px, *py, *pz;
    const float *r;
    const float *neg_inv_2r2; /* -1 / (2 r^2) */
    const float *k;           /* value k_i */
    const uint8_t *field;     /* field id */
    int64_t count;
    int32_t nnodes;
    int32_t depth;         /* longest root-to-leaf path; traversal stacks hold depth + 2 entries */
    int32_t nfields;
    int32_t buffer_k;      /* coherent: samples per ray per pass and field */
    float sigma, kappa;
    float sphere_scale;    /* > 0: opaque spheres of radius sphere_scale * r_i */
    float max_radius;
    float lo[4], hi[4];    /* centre bounds grown by max(sigma, sphere_scale) * max radius */
    float clear_below[LC_KMAX_FIELDS]; /* dvr: field values at or below this are fully transparent
                                          in this frame's TF (-inf: skip nothing) */
} lc_kparticles;
_Static_assert(sizeof(lc_kparticles) == 11 * 8 + 8 + 4 * 8 + 32 + 4 * LC_KMAX_FIELDS, "lc_kparticles layout");

#endif
