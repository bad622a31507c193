/* Particles deposited to a grid (lc_particles_resample, host/resample/): the
 * kernel's view of the particles and the grid, and one brick of work. The
 * field is the particle renderer's (SPEC.md "Fields", "SPH kernels and
 * projections"; kernels/particles_common.h, particles_sph.h): the Gaussian
 * kappa k_i exp(-d^2 / (2 r_i^2)) for d^2 < (sigma r_i)^2, or an SPH kernel
 * kappa k_i norm / H_i^3 f(d / H_i) with H_i = r_i, at every node
 * origin + (i, j, k) * spacing. Plain fixed-width types, shared with the host. */
#ifndef LC_KRESAMPLE_H
#define LC_KRESAMPLE_H

#include <stdint.h>

typedef struct lc_kresample {
    const float *px, *py, *pz, *r, *k; /* particles (the set's leaf order) */
    float *values;                      /* size[0] * size[1] * size[2] nodes, x fastest */
    int64_t size[3];
    float origin[3], spacing[3];
    float sigma, kappa, knorm; /* knorm: the SPH kernel's normalisation (kparticles.h) */
    int32_t kernel;            /* LC_KSPH_* (kparticles.h) */
} lc_kresample;
_Static_assert(sizeof(lc_kresample) == 6 * 8 + 3 * 8 + 6 * 4 + 4 * 4, "lc_kresample layout");

/* The nodes [lo, hi) per axis of one brick and the particles that reach it
 * (ascending indices, so every node sums its terms in the particles' order
 * whatever thread runs the brick). The kernel adds into values, which the
 * host cleared; scratch holds lc_kresample_scratch_floats(side) floats for a
 * brick of at most `side` nodes per axis. */
typedef struct lc_kresample_brick {
    int32_t lo[3], hi[3];
    const uint32_t *list;
    int64_t n;
    float *scratch;
    uint64_t evals; /* out: node-particle terms added */
} lc_kresample_brick;
_Static_assert(sizeof(lc_kresample_brick) == 24 + 8 + 8 + 8 + 8, "lc_kresample_brick layout");

/* Six rows (x, y, z squared offsets and Gaussian factors) of side nodes plus
 * two vectors of padding each (16 lanes at most). */
static inline uint64_t lc_kresample_scratch_floats(int side) { return 6 * ((uint64_t)side + 32); }

/* The nodes [*i0, *i1] of one axis (origin o, spacing sp, nodes [lo, hi))
 * that a support of radius R about c can reach: 0 if none. One definition for
 * the host's binning and the kernel's rows; generous by up to a node (the
 * kernel's d^2 < R^2 test decides), and safe for far-away particles. */
static inline int lc_kresample_range(float o, float sp, int64_t lo, int64_t hi, float c, float R, int64_t *i0,
                                     int64_t *i1)
{
    double a = ((double)c - (double)R - (double)o) / (double)sp, b = ((double)c + (double)R - (double)o) / (double)sp;
    if (!(b >= (double)lo - 1.0) || !(a <= (double)hi)) return 0;
    int64_t l = a <= (double)lo ? lo : (int64_t)a;      /* a > lo >= 0 here: truncation is floor */
    int64_t h = b >= (double)hi ? hi - 1 : (int64_t)b + 1; /* a ceiling, or one past an integer b */
    if (h > hi - 1) h = hi - 1;
    *i0 = l, *i1 = h;
    return l <= h;
}

#endif
