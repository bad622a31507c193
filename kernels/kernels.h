/* Prototypes of this target's kernel entry points (suffixed by LC_KFN), seen
 * by the kernel sources and kernels/ktable.c only. */
#ifndef LC_KERNELS_H
#define LC_KERNELS_H

#include "lane/lane.h"
#include "shared/ktable.h"

void LC_KFN(lc_lane_apply)(const lc_lane_args *args);

/* each kind's sub-table, defined in its kernel file */
extern const lc_kkind LC_KFN(lc_kkind_particles);
extern const lc_kkind LC_KFN(lc_kkind_grid);
extern const lc_kkind LC_KFN(lc_kkind_rbf);

/* the coherent particle method lives in its own file; the sub-table is in particles.c */
void LC_KFN(particles_coherent)(const void *scene, const lc_kframe *f, const lc_ktile *t, lc_kscratch *scratch,
                                lc_kstats *st);
uint64_t LC_KFN(particles_coherent_scratch_bytes)(const void *scene, const lc_kframe *f);

/* the grid methods live in two files; the sub-table is in grid_bvh.c */
void LC_KFN(grid_brute)(const void *scene, const lc_kframe *f, const lc_ktile *t, lc_kscratch *scratch, lc_kstats *st);

/* the RBF octree method (rbf_octree.c); the sub-table is in rbf.c */
struct lc_krbf;
void LC_KFN(rbf_octree)(const void *scene, const lc_kframe *f, const lc_ktile *t, lc_kscratch *scratch, lc_kstats *st);
uint64_t LC_KFN(rbf_octree_scratch_bytes)(const void *scene, const lc_kframe *f);
void LC_KFN(rbf_octree_sample)(const struct lc_krbf *s, const float *xyz, int64_t n, float *phi, float *grad);

/* particles deposited to grid nodes (resample.c) */
struct lc_kresample;
struct lc_kresample_brick;
void LC_KFN(lc_resample_brick)(const struct lc_kresample *s, struct lc_kresample_brick *b);

#endif
