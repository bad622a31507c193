/* The exact pixel averages of projections (host/sph/project.c), compiled
 * once per target from kernels/sph_project.c (meson's kernel_sources).
 *
 * A particle of support s pixels at (X, Y) (pixel units, y down) puts into
 * pixel (i, j) its amount times
 *     sum_k mu_k [A_k(u_{i+1}) - A_k(u_i)] [A_k(v_{j+1}) - A_k(v_j)],
 * u_i = (i - X) / s, v_j = (j - Y) / s, the separable cumulative table of its
 * column kernel (host/sph/column.h). Per particle and band of rows the kernel
 * looks A_k up once per pixel column edge and row edge (cubic Hermite in
 * double, vectorised over k), keeps the differences as a K x columns and a
 * rows x K float matrix, and forms their product in register blocks of 4 rows
 * by two lane vectors of columns (a small matrix product). Every product is
 * rounded and then added in the order of k (vf_madd, never fused), so every
 * target gives the same bits. Footprints of at most 2 x 2 pixels take a
 * short path with the same value in double: the marginal M(u) = int_0^u
 * int_{-1}^1 g (one lookup) and, across a pixel corner, the quadrant
 * integral 1/4 + M(a) / 2 + M(b) / 2 + sum_k mu_k A_k(a) A_k(b); a support
 * inside one pixel puts its whole amount there. No vector type leaves the
 * kernel file: this header is plain C. */
#ifndef LC_KERNELS_SPH_PROJECT_H
#define LC_KERNELS_SPH_PROJECT_H

#include <stddef.h>
#include <stdint.h>

#define LC_KPROJ_KPAD 8   /* ranks padded to a multiple of this (zeros beyond the rank) */
#define LC_KPROJ_MR 4     /* rows per register block */
#define LC_KPROJ_CPAD 48  /* columns of padding after a particle's last (two 16-lane vectors and more) */

#define LC_KPROJ_LEVELS 6 /* lower ranks for small supports (lc_kproj_table.lev_*) */

/* The separable table of one kernel (built by host/sph/column.c). */
typedef struct lc_kproj_table {
    int32_t rank, kpad, nt;  /* K terms, K rounded up to LC_KPROJ_KPAD, nodes - 1 on [0, 1] */
    const double *tab;       /* (nt + 1) nodes x 2 kpad: A_k(j / nt) for k < kpad, then phi_k(j / nt) / nt */
    const double *mu;        /* kpad eigenvalues (mu_0 carries the truncated terms' mass; 0 beyond rank) */
    const double *marg;      /* (nt + 1) x 2: M(j / nt), M'(j / nt) / nt */
    /* A support of s pixels with s <= lev_smax[l] (the first such l < nlev) may
     * take the first lev_k[l] terms (a multiple of LC_KPROJ_KPAD) with mu_0 =
     * lev_mu0[l]: pixel-wide differences of the higher A_k are below the
     * table's tolerance there (host/sph/column.c levels), and mu_0 carries
     * their mass, so the map keeps its mass. */
    int32_t nlev;
    int32_t lev_k[LC_KPROJ_LEVELS];
    double lev_smax[LC_KPROJ_LEVELS], lev_mu0[LC_KPROJ_LEVELS];
} lc_kproj_table;

/* One band of rows of the image and its accumulators. */
typedef struct lc_kproj_band {
    int32_t W, H;        /* the image */
    int32_t b0, b1;      /* rows [b0, b1) */
    int32_t disk;        /* 1: the support is a disk (SPH kernels); 0: a square (the Gaussian) */
    int32_t weighted;    /* den is accumulated too */
    double *num, *den;   /* (b1 - b0) x W, row-major */
    void *scratch;       /* lc_kproj_scratch_bytes, 64-byte aligned */
} lc_kproj_band;

/* A particle: centre (pixels), support (pixels), amounts per pixel area. */
typedef struct lc_kproj_particle {
    double X, Y, s, a, w;
} lc_kproj_particle;

/* Scratch bytes of one worker for images W wide and bands of `rows` rows. */
static inline size_t lc_kproj_scratch_bytes(int W, int rows, int kpad)
{
    size_t w = (size_t)W + LC_KPROJ_CPAD, k = (size_t)kpad, r = (size_t)rows + LC_KPROJ_MR;
    size_t b = sizeof(float) * (k * w + r * k + LC_KPROJ_MR * 32) + sizeof(double) * 2 * k + sizeof(int32_t) * 2 * r;
    return (b + 64 * 8 + 63) & ~(size_t)63;
}

/* Deposits particle p's exact pixel averages over the band's rows; returns
 * the pixels written. */
typedef uint64_t (*lc_kproj_deposit_fn)(const lc_kproj_table *t, const lc_kproj_band *b, const lc_kproj_particle *p);

typedef struct lc_kproj {
    const char *target;
    lc_kproj_deposit_fn deposit;
} lc_kproj;

#define LC_DECLARE_KPROJ(t) extern const lc_kproj lc_kproj_##t;
LC_DECLARE_KPROJ(scalar)
LC_DECLARE_KPROJ(sse4)
LC_DECLARE_KPROJ(avx2)
LC_DECLARE_KPROJ(avx512)
LC_DECLARE_KPROJ(avx512_8)

#endif
