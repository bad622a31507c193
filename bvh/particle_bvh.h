/* The particle BVH as flat lc_kpnode arrays: the canonical build
 * (bvh/particle_bvh_canon.c) by default, Embree's rtcBuildBVH (MEDIUM) when
 * a set asks for it, the own binned SAH builder (bvh/particle_bvh_sah.c)
 * for A/B runs (bvh/particle_bvh.c). */
#ifndef LC_PARTICLE_BVH_H
#define LC_PARTICLE_BVH_H

#include <stddef.h>
#include <stdint.h>
#include "kernels/shared/kparticles.h"

typedef struct lci_pbvh {
    lc_kpnode *nodes;
    float *rmax;
    int32_t nnodes;
    int32_t depth;
    uint32_t *order; /* order[j] = original index of the j-th particle in leaf order */
} lci_pbvh;

typedef enum lci_pbvh_builder {
    LCI_PBVH_DEFAULT,    /* LCI_PBVH_EMBREE, or LANECAST_PBVH_BUILDER's choice (A/B runs) */
    LCI_PBVH_EMBREE,     /* Embree's binned SAH (RTC_BUILD_QUALITY_MEDIUM) over all particles at once */
    LCI_PBVH_SAH,        /* the own binned SAH builder (bvh/particle_bvh_sah.c) */
} lci_pbvh_builder;

/* Builds over n particles (positions xyz interleaved, radii r, or r_all for
 * every particle when r is NULL). leaf_size in 1..32. Returns 0 on success,
 * else writes a message into err. */
int lci_pbvh_build(void *embree_device, const float *xyz, const float *r, float r_all, size_t n, int leaf_size,
                   lci_pbvh *out, char *err, size_t errlen);
/* The own builder (bvh/particle_bvh_sah.c): binned SAH straight into the
 * flat layout, 16 bytes per particle of scratch; threads >= 2 builds the
 * root's two subtrees on two threads. Called by lci_pbvh_build_ex, which
 * checks the arguments and handles n = 0. */
int lci_pbvh_build_sah(const float *xyz, const float *r, float r_all, size_t n, int leaf_size, int threads,
                       lci_pbvh *out, char *err, size_t errlen);
/* As lci_pbvh_build with a builder. embree_device may be NULL for LCI_PBVH_SAH. */
/* The sizes every builder takes (n particles in int32 node indices, leaves
 * of 1 to 32): 0, or -1 with the message in err. */
int lci_pbvh_check_size(size_t n, int leaf_size, char *err, size_t errlen);
int lci_pbvh_build_ex(void *embree_device, const float *xyz, const float *r, float r_all, size_t n, int leaf_size,
                      lci_pbvh_builder builder, lci_pbvh *out, char *err, size_t errlen);
/* What orders the canonical BVH (bvh/particle_bvh_canon.c): the box of the
 * centres' Morton code (lo[a] <= hi[a]; every holder of the set passes the same
 * box), then per particle up to LCI_PBVH_TIES floats and a byte that break
 * ties after the centre and radius (NULL: none), indexed by src[j] for the
 * j-th particle (src NULL: by j). */
#define LCI_PBVH_TIES 3
typedef struct lci_pbvh_keys {
    float lo[3], hi[3];
    const float *tie[LCI_PBVH_TIES];
    const uint8_t *tag;
    const size_t *src;
} lci_pbvh_keys;

/* Leaves in the canonical order of keys (a pure function of each particle's
 * data and the box), split by the Morton codes: a sample's terms add in
 * that order in every set holding them (data-parallel parts equal the whole
 * set bit for bit). Returns 0, else writes a message into err. */
int lci_pbvh_build_canonical(const float *xyz, const float *r, float r_all, size_t n, int leaf_size,
                             const lci_pbvh_keys *keys, lci_pbvh *out, char *err, size_t errlen);
/* 1 when a set's canonical_order (lc_particles_desc, lc_rbf_desc: 1 or -1,
 * 0 the default) means the canonical build: 1, or 0 unless
 * LANECAST_PBVH_BUILDER names embree or sah (A/B runs: lanecast bench
 * --builders). Else lci_pbvh_build (Embree's, or the variable's builder). */
int lci_pbvh_canonical(int canonical_order);
void lci_pbvh_free(lci_pbvh *b);

#endif
