/* The kernel table: one instance per compiled target (kernels/ktable.c is
 * compiled once per target and defines lc_ktable_<target>). The host picks one
 * at device creation and calls only through it. No vector type appears here. */
#ifndef LC_KTABLE_H
#define LC_KTABLE_H

#include <stdint.h>
#include "lane_ops.h"
#include "kframe.h"

/* Renders one tile of a prepared kind scene (lc_kparticles, lc_kgrid, ...). */
typedef void (*lc_ktile_fn)(const void *scene, const lc_kframe *frame, const lc_ktile *tile, lc_kscratch *scratch,
                            lc_kstats *stats);

/* A kind's methods: the accelerated one (particles: coherent packets, grids:
 * the min-max BVH, RBF sets: per-sample gather through the BVH) and the
 * baseline (particles: per-sample gather, grids and RBF sets: brute force). The host maps lc_method onto these.
 * CELLS: a kind's second accelerated method over a spatial subdivision (RBF
 * sets: the octree of Jang 2004 §5, when the volume built one); NULL in the
 * kinds without one. */
/* COHERENT: a kind's coherent buffered method when that is not its FAST one
 * (RBF sets: the particle kind's coherent kernel over the set's lc_kparticles
 * view, kparticles.h); NULL in the other kinds. */
enum { LC_KMETHOD_FAST = 0, LC_KMETHOD_BASE = 1, LC_KMETHOD_CELLS = 2, LC_KMETHOD_COHERENT = 3, LC_KMETHOD_COUNT = 4 };

/* One data kind's kernels on this target. */
typedef struct lc_kkind {
    lc_ktile_fn render[LC_KMETHOD_COUNT];
    /* per-worker scratch bytes render[method] needs for this scene and frame */
    uint64_t (*scratch_bytes[LC_KMETHOD_COUNT])(const void *scene, const lc_kframe *frame);
    /* every field and its gradient at n points: phi[i * nf + f], grad[3 (i * nf + f) + c]
       (grad may be NULL); scratch of sample_scratch_bytes */
    void (*sample)(const void *scene, const float *xyz, int64_t n, float *phi, float *grad, void *scratch);
    uint64_t (*sample_scratch_bytes)(const void *scene);
} lc_kkind;

/* Rows of lc_ktable.kind, one per data kind. */
enum { LC_KKIND_PARTICLES = 0, LC_KKIND_GRID = 1, LC_KKIND_RBF = 2, LC_KKIND_COUNT = 3 };

struct lc_kresample;
struct lc_kresample_brick;

typedef struct lc_ktable {
    const char *name;
    int32_t lanes;
    void (*lane_apply)(const lc_lane_args *args);
    const lc_kkind *kind[LC_KKIND_COUNT];
    /* particles deposited to one brick of grid nodes (kernels/resample.c, kresample.h) */
    void (*resample_brick)(const struct lc_kresample *s, struct lc_kresample_brick *b);
} lc_ktable;

#define LC_DECLARE_KTABLE(t) extern const lc_ktable lc_ktable_##t;
LC_DECLARE_KTABLE(scalar)
LC_DECLARE_KTABLE(sse4)
LC_DECLARE_KTABLE(avx2)
LC_DECLARE_KTABLE(avx512)
LC_DECLARE_KTABLE(avx512_8)

#endif
