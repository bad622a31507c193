/* lanecast bench --roofline: this machine's ceilings per target, one thread.
 * Each kernel is compiled for its target with a function attribute (the
 * tool itself is baseline x86-64; a kernel only runs when the CPU supports
 * its target), with GCC vector types of the target's width:
 * - FMA peak: 12 independent multiply-add chains (one FMA instruction where
 *   the target has FMA, i.e. avx2/avx512*; mul + add on scalar and sse4, as
 *   the library's kernels for those targets do), 2 FLOPs per lane per step.
 * - Gaussian ceiling: sums of Gaussians at independent sample points with a
 *   degree-6 polynomial exp (the shape of the particle and RBF kernels'
 *   inner loop, without traversal): evaluations per second, L1-resident.
 * - Gather vs scalar loads: floats fetched per second at random int32
 *   indices from a 16 KiB (L1) and a 16 MiB (memory) table, with the target's
 *   gather (avx2, avx512_8: 8 lanes; avx512: 16) and with scalar loads.
 * - Grid ceiling: trilinear samples streamed along parallel rays (a packet:
 *   one row of lanes half a voxel apart, steps of half a voxel, the grids'
 *   default dt) through the grid kernels' uint8 z-paired quad copy (kgrid.h
 *   pair_quads: two 32-bit loads per sample, x and x + 1), 7 lerps, summed:
 *   the fetch and interpolation every grid sample pays, without traversal,
 *   classification, shading or blending, so a frame's samples per second
 *   stay below it. A 40^3 volume (256 KiB, cache-resident) and a 320^3 one
 *   (125 MiB); the ceiling is the faster.
 * Every rate is the best pass of several within the time given: on a shared
 * machine the best pass is the closest to what the core can do. */
#include <immintrin.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "bench_common.h"

static volatile float roof_m = 0.9999f, roof_c = 1e-4f; /* not constants: nothing folds */
#define NOVEC __attribute__((optimize("no-tree-vectorize", "no-tree-slp-vectorize"), noinline))

/* One FMA-peak kernel and one Gaussian kernel per width (N lanes). */
#define ROOF_KERNELS(SUF, N, TGT)                                                                         \
    typedef float vf_##SUF __attribute__((vector_size(4 * (N))));                                        \
    typedef int32_t vi_##SUF __attribute__((vector_size(4 * (N))));                                      \
    __attribute__((target(TGT))) static inline float hsum_##SUF(vf_##SUF v)                               \
    {                                                                                                     \
        float r = 0;                                                                                      \
        for (int i = 0; i < N; i++) r += v[i];                                                            \
        return r;                                                                                         \
    }                                                                                                     \
    __attribute__((target(TGT))) NOVEC static float fma_##SUF(long iters)                                 \
    {                                                                                                     \
        vf_##SUF a[12], m, c;                                                                             \
        for (int i = 0; i < N; i++) m[i] = roof_m, c[i] = roof_c;                                             \
        for (int k = 0; k < 12; k++) a[k] = c * (float)(k + 1);                                           \
        for (long it = 0; it < iters; it++) {                                                             \
            for (int k = 0; k < 12; k++) a[k] = a[k] * m + c;                                             \
        }                                                                                                 \
        vf_##SUF s = a[0];                                                                                \
        for (int k = 1; k < 12; k++) s += a[k];                                                           \
        float r = 0;                                                                                      \
        for (int i = 0; i < N; i++) r += s[i];                                                            \
        return r;                                                                                         \
    }                                                                                                     \
    __attribute__((target(TGT))) NOVEC static float gauss_##SUF(const float *pts, int nvec, const float *g, \
                                                               int ng)                                    \
    {                                                                                                     \
        const vf_##SUF lo = (vf_##SUF){0} - 87.0f, magic = (vf_##SUF){0} + 12582912.0f;                   \
        vf_##SUF total = {0};                                                                             \
        for (int v = 0; v < nvec; v++) {                                                                  \
            vf_##SUF px, py, pz, acc = {0};                                                               \
            memcpy(&px, pts + (size_t)(3 * v + 0) * (N), sizeof px);                                      \
            memcpy(&py, pts + (size_t)(3 * v + 1) * (N), sizeof py);                                      \
            memcpy(&pz, pts + (size_t)(3 * v + 2) * (N), sizeof pz);                                      \
            for (int j = 0; j < ng; j++) {                                                                \
                vf_##SUF dx = px - g[4 * j], dy = py - g[4 * j + 1], dz = pz - g[4 * j + 2];              \
                vf_##SUF x = (dx * dx + dy * dy + dz * dz) * -g[4 * j + 3];                               \
                vi_##SUF below = x < lo;                                                                  \
                x = (vf_##SUF)(((vi_##SUF)x & ~below) | ((vi_##SUF)lo & below));                         \
                vf_##SUF t = x * 1.44269504f + magic, n = t - magic;                                      \
                vf_##SUF r = x - n * 0.693145752f - n * 1.42860677e-6f;                                   \
                vf_##SUF p = r * (1.0f / 720) + (1.0f / 120);                                             \
                p = p * r + (1.0f / 24), p = p * r + (1.0f / 6), p = p * r + 0.5f;                        \
                p = p * r + 1.0f, p = p * r + 1.0f;                                                       \
                acc += (vf_##SUF)((vi_##SUF)p + (((vi_##SUF)t - (vi_##SUF)magic) << 23));                 \
            }                                                                                             \
            total += acc;                                                                                 \
        }                                                                                                 \
        return hsum_##SUF(total);                                                                         \
    }

/* scalar: plain floats (1-lane vector types go through memory) */
NOVEC static float fma_scalar(long iters)
{
    float a[12], m = roof_m, c = roof_c;
    for (int k = 0; k < 12; k++) a[k] = c * (float)(k + 1);
    for (long it = 0; it < iters; it++) {
        a[0] = a[0] * m + c, a[1] = a[1] * m + c, a[2] = a[2] * m + c, a[3] = a[3] * m + c;
        a[4] = a[4] * m + c, a[5] = a[5] * m + c, a[6] = a[6] * m + c, a[7] = a[7] * m + c;
        a[8] = a[8] * m + c, a[9] = a[9] * m + c, a[10] = a[10] * m + c, a[11] = a[11] * m + c;
    }
    float r = 0;
    for (int k = 0; k < 12; k++) r += a[k];
    return r;
}

NOVEC static float gauss_scalar(const float *pts, int n, const float *g, int ng)
{
    float total = 0;
    for (int v = 0; v < n; v++) {
        float px = pts[3 * v], py = pts[3 * v + 1], pz = pts[3 * v + 2], acc = 0;
        for (int j = 0; j < ng; j++) {
            float dx = px - g[4 * j], dy = py - g[4 * j + 1], dz = pz - g[4 * j + 2];
            float x = (dx * dx + dy * dy + dz * dz) * -g[4 * j + 3];
            x = x < -87.0f ? -87.0f : x;
            float t = x * 1.44269504f + 12582912.0f, nn = t - 12582912.0f;
            float r = x - nn * 0.693145752f - nn * 1.42860677e-6f;
            float p = r * (1.0f / 720) + (1.0f / 120);
            p = p * r + (1.0f / 24), p = p * r + (1.0f / 6), p = p * r + 0.5f;
            p = p * r + 1.0f, p = p * r + 1.0f;
            int32_t pi, ti, mi;
            float magic = 12582912.0f;
            memcpy(&pi, &p, 4), memcpy(&ti, &t, 4), memcpy(&mi, &magic, 4);
            pi += (int32_t)((uint32_t)(ti - mi) << 23);
            memcpy(&p, &pi, 4);
            acc += p;
        }
        total += acc;
    }
    return total;
}
ROOF_KERNELS(sse4, 4, "sse4.2")
ROOF_KERNELS(avx2, 8, "avx2,fma")
ROOF_KERNELS(avx512_8, 8, "avx512f,avx512vl,avx2,fma")
ROOF_KERNELS(avx512, 16, "avx512f,avx512vl,avx2,fma")


/* One grid-stream kernel per width: packets of N parallel rays, each
 * packet's start (3 N floats, lanes along x) and step count given; q is the
 * quad copy of an n^3 uint8 volume (q[e] = v(i,j,k) | v(i,j+1,k) << 8 |
 * v(i,j,k+1) << 16 | v(i,j+1,k+1) << 24 at e = i + j n + k n^2). */
#define GRID_KERNEL(SUF, N, TGT, GATHER)                                                                       \
    __attribute__((target(TGT))) NOVEC static float gstream_##SUF(const uint32_t *q, int n, const float *start, \
                                                                 const int *steps, int npk, const float *dir)   \
    {                                                                                                          \
        vf_##SUF total = {0};                                                                                  \
        const vi_##SUF ff = (vi_##SUF){0} + 255, nn = (vi_##SUF){0} + n, nn2 = (vi_##SUF){0} + n * n;          \
        for (int p = 0; p < npk; p++) {                                                                        \
            vf_##SUF x, y, z, acc = {0};                                                                       \
            memcpy(&x, start + (size_t)(3 * p + 0) * (N), sizeof x);                                           \
            memcpy(&y, start + (size_t)(3 * p + 1) * (N), sizeof y);                                           \
            memcpy(&z, start + (size_t)(3 * p + 2) * (N), sizeof z);                                           \
            for (int k = 0; k < steps[p]; k++) {                                                               \
                vi_##SUF ix = __builtin_convertvector(x, vi_##SUF), iy = __builtin_convertvector(y, vi_##SUF); \
                vi_##SUF iz = __builtin_convertvector(z, vi_##SUF);                                            \
                vf_##SUF ux = x - __builtin_convertvector(ix, vf_##SUF);                                       \
                vf_##SUF uy = y - __builtin_convertvector(iy, vf_##SUF);                                       \
                vf_##SUF uz = z - __builtin_convertvector(iz, vf_##SUF);                                       \
                vi_##SUF e = ix + iy * nn + iz * nn2, w0, w1;                                                  \
                GATHER(w0, q, e);                                                                              \
                GATHER(w1, q, e + 1);                                                                          \
                vf_##SUF a0 = __builtin_convertvector(w0 & ff, vf_##SUF);                                      \
                vf_##SUF a1 = __builtin_convertvector((w0 >> 8) & ff, vf_##SUF);                               \
                vf_##SUF a2 = __builtin_convertvector((w0 >> 16) & ff, vf_##SUF);                              \
                vf_##SUF a3 = __builtin_convertvector((w0 >> 24) & ff, vf_##SUF);                              \
                vf_##SUF b0 = __builtin_convertvector(w1 & ff, vf_##SUF);                                      \
                vf_##SUF b1 = __builtin_convertvector((w1 >> 8) & ff, vf_##SUF);                               \
                vf_##SUF b2 = __builtin_convertvector((w1 >> 16) & ff, vf_##SUF);                              \
                vf_##SUF b3 = __builtin_convertvector((w1 >> 24) & ff, vf_##SUF);                              \
                vf_##SUF c0 = a0 + (b0 - a0) * ux, c1 = a1 + (b1 - a1) * ux;                                   \
                vf_##SUF c2 = a2 + (b2 - a2) * ux, c3 = a3 + (b3 - a3) * ux;                                   \
                vf_##SUF d0 = c0 + (c1 - c0) * uy, d1 = c2 + (c3 - c2) * uy;                                   \
                acc += d0 + (d1 - d0) * uz;                                                                    \
                x += dir[0], y += dir[1], z += dir[2];                                                         \
            }                                                                                                  \
            total += acc;                                                                                      \
        }                                                                                                      \
        return hsum_##SUF(total);                                                                              \
    }

#define GATHER_LANES(out, q, e) \
    for (int l_ = 0; l_ < (int)(sizeof(e) / 4); l_++) (out)[l_] = (int32_t)(q)[(e)[l_]]
#define GATHER_AVX2(out, q, e) (out) = (vi_avx2)_mm256_i32gather_epi32((const int *)(const void *)(q), (__m256i)(e), 4)
#define GATHER_AVX512_8(out, q, e) \
    (out) = (vi_avx512_8)_mm256_mmask_i32gather_epi32(_mm256_setzero_si256(), 0xff, (__m256i)(e), (q), 4)
#define GATHER_AVX512(out, q, e) (out) = (vi_avx512)_mm512_i32gather_epi32((__m512i)(e), (const void *)(q), 4)
GRID_KERNEL(sse4, 4, "sse4.2", GATHER_LANES)
GRID_KERNEL(avx2, 8, "avx2,fma", GATHER_AVX2)
GRID_KERNEL(avx512_8, 8, "avx512f,avx512vl,avx2,fma", GATHER_AVX512_8)
GRID_KERNEL(avx512, 16, "avx512f,avx512vl,avx2,fma", GATHER_AVX512)

NOVEC static float gstream_scalar(const uint32_t *q, int n, const float *start, const int *steps, int npk,
                                  const float *dir)
{
    float total = 0;
    for (int p = 0; p < npk; p++) {
        float x = start[3 * p], y = start[3 * p + 1], z = start[3 * p + 2];
        for (int k = 0; k < steps[p]; k++) {
            int ix = (int)x, iy = (int)y, iz = (int)z;
            float ux = x - (float)ix, uy = y - (float)iy, uz = z - (float)iz;
            uint32_t w0 = q[ix + iy * n + iz * n * n], w1 = q[ix + 1 + iy * n + iz * n * n];
            float a[4], b[4];
            for (int c = 0; c < 4; c++) a[c] = (float)((w0 >> (8 * c)) & 255), b[c] = (float)((w1 >> (8 * c)) & 255);
            float c0 = a[0] + (b[0] - a[0]) * ux, c1 = a[1] + (b[1] - a[1]) * ux;
            float c2 = a[2] + (b[2] - a[2]) * ux, c3 = a[3] + (b[3] - a[3]) * ux;
            float d0 = c0 + (c1 - c0) * uy, d1 = c2 + (c3 - c2) * uy;
            total += d0 + (d1 - d0) * uz;
            x += dir[0], y += dir[1], z += dir[2];
        }
    }
    return total;
}

NOVEC static float loads_scalar(const float *table, const int32_t *idx, long n)
{
    float a0 = 0, a1 = 0, a2 = 0, a3 = 0;
    for (long i = 0; i + 3 < n; i += 4)
        a0 += table[idx[i]], a1 += table[idx[i + 1]], a2 += table[idx[i + 2]], a3 += table[idx[i + 3]];
    return a0 + a1 + a2 + a3;
}

__attribute__((target("avx2,fma"))) NOVEC static float gather_avx2(const float *table, const int32_t *idx, long n)
{
    __m256 a = _mm256_setzero_ps(), b = _mm256_setzero_ps();
    for (long i = 0; i + 15 < n; i += 16) {
        a = _mm256_add_ps(a, _mm256_i32gather_ps(table, _mm256_loadu_si256((const __m256i *)(idx + i)), 4));
        b = _mm256_add_ps(b, _mm256_i32gather_ps(table, _mm256_loadu_si256((const __m256i *)(idx + i + 8)), 4));
    }
    float o[8];
    _mm256_storeu_ps(o, _mm256_add_ps(a, b));
    return o[0] + o[1] + o[2] + o[3] + o[4] + o[5] + o[6] + o[7];
}

__attribute__((target("avx512f,avx512vl,avx2,fma"))) NOVEC static float gather_avx512_8(const float *table,
                                                                                      const int32_t *idx, long n)
{
    __m256 a = _mm256_setzero_ps(), b = _mm256_setzero_ps();
    for (long i = 0; i + 15 < n; i += 16) {
        a = _mm256_add_ps(a, _mm256_mmask_i32gather_ps(a, 0xff, _mm256_loadu_si256((const __m256i *)(idx + i)), table, 4));
        b = _mm256_add_ps(b, _mm256_mmask_i32gather_ps(b, 0xff, _mm256_loadu_si256((const __m256i *)(idx + i + 8)), table, 4));
    }
    float o[8];
    _mm256_storeu_ps(o, _mm256_add_ps(a, b));
    return o[0] + o[1] + o[2] + o[3] + o[4] + o[5] + o[6] + o[7];
}

__attribute__((target("avx512f,avx512vl,avx2,fma"))) NOVEC static float gather_avx512(const float *table,
                                                                                    const int32_t *idx, long n)
{
    __m512 a = _mm512_setzero_ps(), b = _mm512_setzero_ps();
    for (long i = 0; i + 31 < n; i += 32) {
        a = _mm512_add_ps(a, _mm512_i32gather_ps(_mm512_loadu_si512(idx + i), table, 4));
        b = _mm512_add_ps(b, _mm512_i32gather_ps(_mm512_loadu_si512(idx + i + 16), table, 4));
    }
    return _mm512_reduce_add_ps(_mm512_add_ps(a, b));
}

static volatile float sink;

double bench_fma_width_ratio(const bench_roof *r)
{
    return r->fma_gflops[LC_TARGET_AVX2] > 0 && r->fma_gflops[LC_TARGET_AVX512] > 0
               ? r->fma_gflops[LC_TARGET_AVX512] / r->fma_gflops[LC_TARGET_AVX2]
               : 0;
}

/* Best rate (units per second) of passes of fn over `seconds`. */
#define BEST_RATE(out, units, seconds, call)                        \
    do {                                                            \
        double t_end_ = bench_now() + (seconds), best_ = 0;         \
        int passes_ = 0;                                            \
        while (passes_ < 3 || bench_now() < t_end_) {               \
            double t0_ = bench_now();                               \
            sink = (call);                                          \
            double dt_ = bench_now() - t0_;                         \
            if (dt_ > 0 && (units) / dt_ > best_) best_ = (units) / dt_; \
            if (++passes_ > 1000) break;                            \
        }                                                           \
        (out) = best_;                                              \
    } while (0)

static int runs(lc_target t) { return lc_target_compiled(t) && lc_target_supported(t); }

static void measure_gauss(bench_roof *r, double seconds)
{
    enum { NG = 256, NPTS = 1024 };
    static float g[4 * NG], pts[3 * NPTS];
    uint32_t s = 12345;
    for (int i = 0; i < 4 * NG; i++) s = s * 1664525u + 1013904223u, g[i] = (float)(s >> 8) / 16777216.0f;
    for (int i = 0; i < NG; i++) g[4 * i + 3] = 4.0f + 8.0f * g[4 * i + 3]; /* 1 / (2 r^2) */
    for (int i = 0; i < 3 * NPTS; i++) s = s * 1664525u + 1013904223u, pts[i] = (float)(s >> 8) / 16777216.0f;
    double evals = (double)NPTS * NG;
    if (runs(LC_TARGET_SCALAR)) BEST_RATE(r->gauss_per_s[LC_TARGET_SCALAR], evals, seconds, gauss_scalar(pts, NPTS, g, NG));
    if (runs(LC_TARGET_SSE4)) BEST_RATE(r->gauss_per_s[LC_TARGET_SSE4], evals, seconds, gauss_sse4(pts, NPTS / 4, g, NG));
    if (runs(LC_TARGET_AVX2)) BEST_RATE(r->gauss_per_s[LC_TARGET_AVX2], evals, seconds, gauss_avx2(pts, NPTS / 8, g, NG));
    if (runs(LC_TARGET_AVX512_8))
        BEST_RATE(r->gauss_per_s[LC_TARGET_AVX512_8], evals, seconds, gauss_avx512_8(pts, NPTS / 8, g, NG));
    if (runs(LC_TARGET_AVX512))
        BEST_RATE(r->gauss_per_s[LC_TARGET_AVX512], evals, seconds, gauss_avx512(pts, NPTS / 16, g, NG));
}

static void measure_loads(bench_roof *r, double seconds)
{
    const long nidx = 1 << 20;
    const size_t big = (size_t)4 << 20; /* floats: 16 MiB, as in ../shared/NOTES.md */
    float *table = malloc(sizeof(float) * big);
    int32_t *idx = malloc(sizeof(int32_t) * (size_t)nidx);
    if (!table || !idx) {
        free(table), free(idx);
        return;
    }
    for (size_t i = 0; i < big; i++) table[i] = (float)(i & 1023) * 1e-3f;
    for (int pass = 0; pass < 2; pass++) {
        uint32_t mask = pass ? (uint32_t)(big - 1) : 4095u, s = 777;
        for (long i = 0; i < nidx; i++) s = s * 1664525u + 1013904223u, idx[i] = (int32_t)((s >> 4) & mask);
        double *g = pass ? r->gather_mem : r->gather_l1, sc = 0, n = (double)nidx;
        BEST_RATE(sc, n, seconds, loads_scalar(table, idx, nidx));
        *(pass ? &r->scalar_mem : &r->scalar_l1) = sc;
        g[LC_TARGET_SCALAR] = g[LC_TARGET_SSE4] = sc; /* no gather instruction: scalar loads */
        if (runs(LC_TARGET_AVX2)) BEST_RATE(g[LC_TARGET_AVX2], n, seconds, gather_avx2(table, idx, nidx));
        if (runs(LC_TARGET_AVX512_8)) BEST_RATE(g[LC_TARGET_AVX512_8], n, seconds, gather_avx512_8(table, idx, nidx));
        if (runs(LC_TARGET_AVX512)) BEST_RATE(g[LC_TARGET_AVX512], n, seconds, gather_avx512(table, idx, nidx));
    }
    free(table);
    free(idx);
}


/* Rays of the grid ceiling in an n^3 volume: NPK packets of `lanes` rays
 * (a row, half a voxel apart) starting at z = 1 at pseudo-random x, y, going
 * (0.48, 0.36, 0.8) half a voxel a step while every lane's cell stays inside. */
static double grid_rate(lc_target t, int lanes, const uint32_t *q, int n, double seconds)
{
    enum { NPK = 256 };
    static float start[3 * 16 * NPK];
    static int steps[NPK];
    const float dir[3] = {0.24f, 0.18f, 0.4f};
    uint32_t s = 4242;
    double samples = 0;
    for (int p = 0; p < NPK; p++) {
        s = s * 1664525u + 1013904223u;
        float x0 = 1.0f + (float)(s >> 8) / 16777216.0f * (0.3f * (float)n);
        s = s * 1664525u + 1013904223u;
        float y0 = 1.0f + (float)(s >> 8) / 16777216.0f * (0.3f * (float)n);
        for (int l = 0; l < lanes; l++) {
            float *o = t == LC_TARGET_SCALAR ? start + 3 * (p * lanes + l) : start + (size_t)3 * lanes * p + l;
            int stride = t == LC_TARGET_SCALAR ? 1 : lanes;
            o[0] = x0 + 0.5f * (float)l, o[stride] = y0, o[2 * stride] = 1.0f;
        }
        /* the last lane is the furthest in x: every coordinate below n - 2 */
        float xe = x0 + 0.5f * (float)(lanes - 1), lim = (float)n - 2.01f;
        float kx = (lim - xe) / dir[0], ky = (lim - y0) / dir[1], kz = (lim - 1.0f) / dir[2];
        float k = kx < ky ? kx : ky;
        steps[p] = (int)(k < kz ? k : kz);
        samples += (double)steps[p] * lanes;
    }
    double rate = 0;
    int npk = t == LC_TARGET_SCALAR ? NPK * lanes : NPK;
    if (t == LC_TARGET_SCALAR) { /* one ray per "packet": expand the step counts */
        static int st1[16 * NPK];
        for (int p = 0; p < NPK * lanes; p++) st1[p] = steps[p / lanes];
        BEST_RATE(rate, samples, seconds, gstream_scalar(q, n, start, st1, npk, dir));
    } else if (t == LC_TARGET_SSE4) BEST_RATE(rate, samples, seconds, gstream_sse4(q, n, start, steps, npk, dir));
    else if (t == LC_TARGET_AVX2) BEST_RATE(rate, samples, seconds, gstream_avx2(q, n, start, steps, npk, dir));
    else if (t == LC_TARGET_AVX512_8) BEST_RATE(rate, samples, seconds, gstream_avx512_8(q, n, start, steps, npk, dir));
    else if (t == LC_TARGET_AVX512) BEST_RATE(rate, samples, seconds, gstream_avx512(q, n, start, steps, npk, dir));
    return rate;
}

static void measure_grid(bench_roof *r, double seconds)
{
    for (int pass = 0; pass < 2; pass++) {
        int n = pass ? 320 : 40;
        size_t count = (size_t)n * n * n;
        uint32_t *q = malloc(sizeof(uint32_t) * count);
        if (!q) return;
        uint32_t s = 99;
        for (size_t i = 0; i < count; i++) s = s * 1664525u + 1013904223u, q[i] = s;
        for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++)
            if (runs((lc_target)t)) {
                int lanes = t == LC_TARGET_SCALAR ? 8 : lc_target_lanes((lc_target)t);
                (pass ? r->grid_mem : r->grid_cache)[t] = grid_rate((lc_target)t, lanes, q, n, seconds);
            }
        free(q);
    }
}

void bench_roof_measure(bench_roof *r, double seconds)
{
    memset(r, 0, sizeof *r);
    const long it = 200000;
    const double fl = 2.0 * 12 * (double)it;
    if (runs(LC_TARGET_SCALAR)) BEST_RATE(r->fma_gflops[LC_TARGET_SCALAR], fl * 1e-9, seconds, fma_scalar(it));
    if (runs(LC_TARGET_SSE4)) BEST_RATE(r->fma_gflops[LC_TARGET_SSE4], 4 * fl * 1e-9, seconds, fma_sse4(it));
    if (runs(LC_TARGET_AVX2)) BEST_RATE(r->fma_gflops[LC_TARGET_AVX2], 8 * fl * 1e-9, seconds, fma_avx2(it));
    if (runs(LC_TARGET_AVX512_8)) BEST_RATE(r->fma_gflops[LC_TARGET_AVX512_8], 8 * fl * 1e-9, seconds, fma_avx512_8(it));
    if (runs(LC_TARGET_AVX512)) BEST_RATE(r->fma_gflops[LC_TARGET_AVX512], 16 * fl * 1e-9, seconds, fma_avx512(it));
    measure_gauss(r, seconds);
    measure_loads(r, seconds);
    measure_grid(r, seconds);
    r->measured = 1;
}

void bench_roof_print(FILE *f, const bench_roof *r, const char *machine_json)
{
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        if (!runs((lc_target)t)) continue;
        fprintf(f,
                "{\"record\": \"roofline\", \"target\": \"%s\", \"lanes\": %d, \"threads\": 1, \"fma_gflops\": %.4g, "
                "\"gauss_per_s\": %.4g, \"gather_l1_per_s\": %.4g, \"gather_mem_per_s\": %.4g, "
                "\"scalar_load_l1_per_s\": %.4g, \"scalar_load_mem_per_s\": %.4g, \"gather_over_scalar_l1\": %.3f, "
                "\"gather_over_scalar_mem\": %.3f, \"grid_cache_samples_per_s\": %.4g, \"grid_mem_samples_per_s\": %.4g, "
                "\"fma_width_ratio\": %.3f, \"loadavg\": %.2f, %s}\n",
                lc_target_name((lc_target)t), lc_target_lanes((lc_target)t), r->fma_gflops[t], r->gauss_per_s[t],
                r->gather_l1[t], r->gather_mem[t], r->scalar_l1, r->scalar_mem,
                r->scalar_l1 > 0 ? r->gather_l1[t] / r->scalar_l1 : 0, r->scalar_mem > 0 ? r->gather_mem[t] / r->scalar_mem : 0,
                r->grid_cache[t], r->grid_mem[t], bench_fma_width_ratio(r), bench_loadavg(), machine_json);
    }
    fflush(f);
}
