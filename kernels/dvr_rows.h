/* Row gathers for table lookups (the TF step table, kframe.h lc_ktf cls):
 * out[c] lane l = base[idx_l + c] for c = 0..7, i.e. 8 consecutive floats
 * per lane. On Zen 4 a zmm gather
 * costs about 16 scalar loads (../shared/NOTES.md "This CPU's ceilings"), so
 * the 8 gathers a lerped RGBA table lookup needs (two entries x four
 * channels) cost ~150 cycles per 16 lanes; one 32-byte load per lane and an
 * 8x8 transpose in registers cost ~16 loads and ~32 shuffles. The rows must
 * be readable (8 floats from every idx). */
#ifndef LC_DVR_ROWS_H
#define LC_DVR_ROWS_H

#include "lane/lane.h"

#if defined(LC_TARGET_AVX2) || defined(LC_TARGET_AVX512_8) || defined(LC_TARGET_AVX512)
#include <immintrin.h>
/* 8x8 transpose of ymm rows r[0..7] (row l = lane l) into columns. */
static inline __attribute__((always_inline)) void dvr_transpose8(__m256 r[8])
{
    __m256 t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpackhi_ps(r[0], r[1]);
    __m256 t2 = _mm256_unpacklo_ps(r[2], r[3]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
    __m256 t4 = _mm256_unpacklo_ps(r[4], r[5]), t5 = _mm256_unpackhi_ps(r[4], r[5]);
    __m256 t6 = _mm256_unpacklo_ps(r[6], r[7]), t7 = _mm256_unpackhi_ps(r[6], r[7]);
    __m256 s0 = _mm256_shuffle_ps(t0, t2, 0x44), s1 = _mm256_shuffle_ps(t0, t2, 0xee);
    __m256 s2 = _mm256_shuffle_ps(t1, t3, 0x44), s3 = _mm256_shuffle_ps(t1, t3, 0xee);
    __m256 s4 = _mm256_shuffle_ps(t4, t6, 0x44), s5 = _mm256_shuffle_ps(t4, t6, 0xee);
    __m256 s6 = _mm256_shuffle_ps(t5, t7, 0x44), s7 = _mm256_shuffle_ps(t5, t7, 0xee);
    r[0] = _mm256_permute2f128_ps(s0, s4, 0x20);
    r[1] = _mm256_permute2f128_ps(s1, s5, 0x20);
    r[2] = _mm256_permute2f128_ps(s2, s6, 0x20);
    r[3] = _mm256_permute2f128_ps(s3, s7, 0x20);
    r[4] = _mm256_permute2f128_ps(s0, s4, 0x31);
    r[5] = _mm256_permute2f128_ps(s1, s5, 0x31);
    r[6] = _mm256_permute2f128_ps(s2, s6, 0x31);
    r[7] = _mm256_permute2f128_ps(s3, s7, 0x31);
}
#endif

static inline __attribute__((always_inline)) void dvr_rows8(const float *base, vint idx, vfloat out[8])
{
#if defined(LC_TARGET_AVX2) || defined(LC_TARGET_AVX512_8)
    int32_t ix[8];
    vi_store(ix, idx);
    __m256 r[8];
    for (int l = 0; l < 8; l++) r[l] = _mm256_loadu_ps(base + ix[l]);
    dvr_transpose8(r);
    for (int c = 0; c < 8; c++) out[c] = r[c];
#elif defined(LC_TARGET_AVX512)
    int32_t ix[16];
    vi_store(ix, idx);
    /* row l in the low half and row l + 8 in the high half of r[l]: the
     * in-lane unpacks and shuffles transpose both halves at once, and one
     * two-source permute per column joins the 128-bit blocks (24 shuffles
     * instead of two 8x8 transposes' 48 and 8 inserts) */
    __m512 r[8];
    for (int l = 0; l < 8; l++)
        r[l] = _mm512_insertf32x8(_mm512_castps256_ps512(_mm256_loadu_ps(base + ix[l])),
                                  _mm256_loadu_ps(base + ix[l + 8]), 1);
    __m512 t0 = _mm512_unpacklo_ps(r[0], r[1]), t1 = _mm512_unpackhi_ps(r[0], r[1]);
    __m512 t2 = _mm512_unpacklo_ps(r[2], r[3]), t3 = _mm512_unpackhi_ps(r[2], r[3]);
    __m512 t4 = _mm512_unpacklo_ps(r[4], r[5]), t5 = _mm512_unpackhi_ps(r[4], r[5]);
    __m512 t6 = _mm512_unpacklo_ps(r[6], r[7]), t7 = _mm512_unpackhi_ps(r[6], r[7]);
    __m512 s0 = _mm512_shuffle_ps(t0, t2, 0x44), s1 = _mm512_shuffle_ps(t0, t2, 0xee);
    __m512 s2 = _mm512_shuffle_ps(t1, t3, 0x44), s3 = _mm512_shuffle_ps(t1, t3, 0xee);
    __m512 s4 = _mm512_shuffle_ps(t4, t6, 0x44), s5 = _mm512_shuffle_ps(t4, t6, 0xee);
    __m512 s6 = _mm512_shuffle_ps(t5, t7, 0x44), s7 = _mm512_shuffle_ps(t5, t7, 0xee);
    /* block b of s holds lanes 4 (b & 1) .. +3 of rows 0-3 (s0-s3) or 4-7
     * (s4-s7) for the low (b < 2) or high half: column c < 4 takes the even
     * blocks, c >= 4 the odd ones, in lane order */
    const __m512i lo = _mm512_setr_epi32(0, 1, 2, 3, 16, 17, 18, 19, 8, 9, 10, 11, 24, 25, 26, 27);
    const __m512i hi = _mm512_setr_epi32(4, 5, 6, 7, 20, 21, 22, 23, 12, 13, 14, 15, 28, 29, 30, 31);
    out[0] = _mm512_permutex2var_ps(s0, lo, s4);
    out[1] = _mm512_permutex2var_ps(s1, lo, s5);
    out[2] = _mm512_permutex2var_ps(s2, lo, s6);
    out[3] = _mm512_permutex2var_ps(s3, lo, s7);
    out[4] = _mm512_permutex2var_ps(s0, hi, s4);
    out[5] = _mm512_permutex2var_ps(s1, hi, s5);
    out[6] = _mm512_permutex2var_ps(s2, hi, s6);
    out[7] = _mm512_permutex2var_ps(s3, hi, s7);
#else
    int32_t ix[LC_W];
    float col[8][LC_W];
    vi_store(ix, idx);
    for (int l = 0; l < LC_W; l++)
        for (int c = 0; c < 8; c++) col[c][l] = base[ix[l] + c];
    for (int c = 0; c < 8; c++) out[c] = vf_load(col[c]);
#endif
}

#endif
