/* The kernel table: one instance per compiled target (kernels/ktable.c is
 * compiled once per target and defines lc_ktable_<target>). The host picks one
 * at device creation and calls only through it. No vector type appears here. */
#ifndef LC_KTABLE_H
#define LC_KTABLE_H

#include <stdint.h>
#include "lane_ops.h"
#include "kframe.h"

struct lc_kparticles;
struct lc_kgrid;

typedef void (*lc_particles_tile_fn)(const struct lc_kparticles *scene, const lc_kframe *frame,
                                     const lc_ktile *tile, lc_kscratch *scratch, lc_kstats *stats);
typedef void (*lc_grid_tile_fn)(const struct lc_kgrid *scene, const lc_kframe *frame,
                                const lc_ktile *tile, lc_kscratch *scratch, lc_kstats *stats);

typedef struct lc_ktable {
    const char *name;
    int32_t lanes;
    void (*lane_apply)(const lc_lane_args *args);
    /* particle path (Knoll 2014) */
    lc_particles_tile_fn particles_coherent;
    lc_particles_tile_fn particles_direct;
    uint64_t (*particles_scratch_bytes)(const struct lc_kparticles *scene, const lc_kframe *frame);
    /* fields and gradients at points; stack holds depth + 2 ints */
    void (*particles_sample)(const struct lc_kparticles *scene, const float *xyz, int64_t n, float *phi, float *grad,
                             int32_t *stack);
    /* structured grid path (Knoll 2011) */
    lc_grid_tile_fn grid_bvh;
    lc_grid_tile_fn grid_brute;
    uint64_t (*grid_scratch_bytes)(const struct lc_kgrid *scene, const lc_kframe *frame);
} lc_ktable;

#define LC_DECLARE_KTABLE(t) extern const lc_ktable lc_ktable_##t;
LC_DECLARE_KTABLE(scalar)
LC_DECLARE_KTABLE(sse4)
LC_DECLARE_KTABLE(avx2)
LC_DECLARE_KTABLE(avx512)
LC_DECLARE_KTABLE(avx512_8)

#endif
