/* The rank-K dot product of a projection's pixels (project.c): one source
 * compiled twice, for the baseline and for AVX2 + FMA (GCC's target
 * attribute; the compiler vectorises the 8-wide block), picked by the
 * device's target so that --target scalar keeps the baseline code. Plain C:
 * no vector types leave this file. */
#include "host/sph/project.h"

#define DOT_BODY                                                                                                       \
    int i = 0;                                                                                                         \
    for (; i + 8 <= n; i += 8) {                                                                                       \
        float acc[8] = {0};                                                                                            \
        for (int k = 0; k < K; k++) {                                                                                  \
            const float *c = col + (size_t)k * stride + i;                                                             \
            float r = row[k];                                                                                          \
            for (int l = 0; l < 8; l++) acc[l] += r * c[l];                                                            \
        }                                                                                                              \
        for (int l = 0; l < 8; l++) out[i + l] = acc[l];                                                               \
    }                                                                                                                  \
    for (; i < n; i++) {                                                                                               \
        float acc = 0.0f;                                                                                              \
        for (int k = 0; k < K; k++) acc += row[k] * col[(size_t)k * stride + i];                                       \
        out[i] = acc;                                                                                                  \
    }

static void dot_base(int K, const float *row, const float *col, size_t stride, int n, float *out) { DOT_BODY }

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2,fma"))) static void dot_avx2(int K, const float *row, const float *col, size_t stride,
                                                          int n, float *out)
{
    DOT_BODY
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
