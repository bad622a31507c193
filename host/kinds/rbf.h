/* RBF sets inside the host: the object (host/kinds/rbf.c: creation, info,
 * frames and the kind's row) and its build (host/kinds/rbf_build.c:
 * validation, the supports of eq. 3, the BVH and octree, the value range). */
#ifndef LC_HOST_RBF_H
#define LC_HOST_RBF_H

#include "host/kinds/kind.h"
#include "bvh/particle_bvh.h"
#include "bvh/rbf_octree.h"

typedef struct rbf {
    lc_volume base; /* first: the kind-neutral handle */
    lc_rbf_info info;
    lci_pbvh bvh;
    lci_octree oct; /* accel = octree */
    float *cx, *cy, *cz, *r2, *nis, *w, *R; /* leaf order */
    float peak[2]; /* the field's range at the centres (with the bias): the default TF range */
    /* the coherent method's particle view (kparticles.h): per node the sum of
       |w_i| below it (node_ksum), and an upper bound of the field (bias
       included) at every point the node's terms reach (node_hi, range_bound),
       which decides the transparent nodes of a dvr frame; field ids, all 0 */
    float *node_wsum, *node_hi;
    uint8_t *field0;
    size_t global_count; /* a part of a data-parallel load: the whole set's count (lci_rbf_set_global) */
    void *part;          /* and what host/mpi/ keeps with it */
    void (*part_free)(void *);
} rbf;

/* 1 when all six bounds are 0 (no domain given). */
int lci_rbf_box_is_zero(const lc_box3 *b);
/* LC_RBF_ACCEL_DEFAULT resolved (lanecast.h). */
lc_rbf_accel lci_rbf_resolve_accel(const lc_rbf_desc *d);
/* The descriptor's scalar checks (one message naming what is wrong); the
 * per-RBF ones follow in lci_rbf_keep's caller. */
lc_status lci_rbf_check_desc(lc_device *dev, const lc_rbf_desc *d);
/* The default eps: 1e-4 of the strongest weight. */
float lci_rbf_pick_eps(const lc_rbf_desc *d);
/* Copies the kept RBFs (|w| > eps) into xyz / R (supports) in input order,
 * src[j] = their input index; *sb = the union of the supports. Returns how
 * many were kept. */
size_t lci_rbf_keep(const lc_rbf_desc *d, float eps, float *xyz, float *R, size_t *src, lc_box3 *sb);
/* The BVH over the n kept supports, the leaf-ordered arrays, the range
 * bound and the octree when p->info.accel asks for it. */
lc_status lci_rbf_build(lc_device *dev, rbf *p, const lc_rbf_desc *d, const float *xyz, const float *R,
                        const size_t *src, size_t n);

#endif
