/* The rank-K dot product of a projection's pixels (project.c): one source
 * compiled twice, for the baseline and for AVX2 + FMA (GCC's target
 * attribute; the compiler vectorises the 8-wide block), picked by the
 * device's target so that --target scalar keeps the baseline code. Plain C:
 * no vector types leave this file. */
#include "host/sph/column.h"
#include "host/sph/project.h"

/* Four terms per pass over the row (contiguous in i, so GCC vectorises the
 * i loop at the target's width); the sum of a pixel keeps the order of k. */
#define DOT_BODY                                                                                                       \
    for (int i = 0; i < n; i++) out[i] = 0.0f;                                                                         \
    int k = 0;                                                                                                         \
    for (; k + 4 <= K; k += 4) {                                                                                       \
        const float *c0 = col + (size_t)k * stride, *c1 = c0 + stride, *c2 = c1 + stride, *c3 = c2 + stride;           \
        float r0 = row[k], r1 = row[k + 1], r2 = row[k + 2], r3 = row[k + 3];                                          \
        for (int i = 0; i < n; i++) out[i] += r0 * c0[i] + r1 * c1[i] + r2 * c2[i] + r3 * c3[i];                       \
    }                                                                                                                  \
    for (; k < K; k++) {                                                                                               \
        const float *c0 = col + (size_t)k * stride;                                                                    \
        float r0 = row[k];                                                                                             \
        for (int i = 0; i < n; i++) out[i] += r0 * c0[i];                                                              \
    }

static void dot_base(int K, const float *row, const float *col, size_t stride, int n, float *out) { DOT_BODY }
static void cum_base(const lci_column *c, double u, double *out) { lci_column_cumulative_inline(c, u, out); }

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2,fma"))) static void dot_avx2(int K, const float *row, const float *col, size_t stride,
                                                          int n, float *out)
{
    DOT_BODY
}
__attribute__((target("avx2,fma"))) static void cum_avx2(const lci_column *c, double u, double *out)
{
    lci_column_cumulative_inline(c, u, out);
}
#endif

lci_dot_fn lci_project_dot(lc_target target)
{
#if defined(__x86_64__) && defined(__GNUC__)
    if (target == LC_TARGET_AVX2 || target == LC_TARGET_AVX512 || target == LC_TARGET_AVX512_8) return dot_avx2;
#endif
    (void)target;
    return dot_base;
}

lci_cum_fn lci_project_cum(lc_target target)
{
#if defined(__x86_64__) && defined(__GNUC__)
    if (target == LC_TARGET_AVX2 || target == LC_TARGET_AVX512 || target == LC_TARGET_AVX512_8) return cum_avx2;
#endif
    (void)target;
    return cum_base;
}
