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
        float r = 0;                                                                                      \
        for (int i = 0; i < N; i++) r += total[i];                                                        \
        return r;                                                                                         \
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
                "\"gather_over_scalar_mem\": %.3f, \"loadavg\": %.2f, %s}\n",
                lc_target_name((lc_target)t), lc_target_lanes((lc_target)t), r->fma_gflops[t], r->gauss_per_s[t],
                r->gather_l1[t], r->gather_mem[t], r->scalar_l1, r->scalar_mem,
                r->scalar_l1 > 0 ? r->gather_l1[t] / r->scalar_l1 : 0, r->scalar_mem > 0 ? r->gather_mem[t] / r->scalar_mem : 0,
                bench_loadavg(), machine_json);
    }
    fflush(f);
}
