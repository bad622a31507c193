/* Prototypes of this target's kernel entry points (suffixed by LC_KFN), seen
 * by the kernel sources and kernels/ktable.c only. */
#ifndef LC_KERNELS_H
#define LC_KERNELS_H

#include "lane/lane.h"
#include "shared/ktable.h"

void LC_KFN(lc_lane_apply)(const lc_lane_args *args);

void LC_KFN(particles_coherent)(const struct lc_kparticles *s, const lc_kframe *f, const lc_ktile *t,
                                lc_kscratch *scratch, lc_kstats *st);
void LC_KFN(particles_direct)(const struct lc_kparticles *s, const lc_kframe *f, const lc_ktile *t,
                              lc_kscratch *scratch, lc_kstats *st);
uint64_t LC_KFN(particles_scratch_bytes)(const struct lc_kparticles *s, const lc_kframe *f);
void LC_KFN(particles_sample)(const struct lc_kparticles *s, const float *xyz, int64_t n, float *phi, float *grad,
                              int32_t *stack);

void LC_KFN(grid_bvh)(const struct lc_kgrid *g, const lc_kframe *f, const lc_ktile *t, lc_kscratch *scratch,
                      lc_kstats *st);
void LC_KFN(grid_brute)(const struct lc_kgrid *g, const lc_kframe *f, const lc_ktile *t, lc_kscratch *scratch,
                        lc_kstats *st);
uint64_t LC_KFN(grid_scratch_bytes)(const struct lc_kgrid *g, const lc_kframe *f);

#endif
