/* AVX-512 (F/DQ/BW/VL) backend at eight lanes: __m256 vectors with the
 * AVX-512VL encodings and masks in k registers (__mmask8). It exists so lane
 * width and instruction set can be studied apart: same width as avx2, same
 * ISA as avx512 (native masked loads/stores/gathers, rcp14/rsqrt14,
 * roundscale, compares into masks, blends by mask). */
#ifndef LC_LANE_AVX512_8_H
#define LC_LANE_AVX512_8_H

#include <immintrin.h>

#define LC_W 8
#define LC_TARGET_NAME "avx512_8"
#define LC_KFN(name) name##_avx512_8

typedef __m256 vfloat;
typedef __m256i vint;
typedef __mmask8 vmask;

static inline vfloat vf_set1(float a) { return _mm256_set1_ps(a); }
static inline vfloat vf_zero(void) { return _mm256_setzero_ps(); }
static inline vfloat vf_iota(void) { return _mm256_setr_ps(0, 1, 2, 3, 4, 5, 6, 7); }
static inline vint vi_set1(int32_t a) { return _mm256_set1_epi32(a); }
static inline vint vi_iota(void) { return _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7); }

static inline vfloat vf_load(const float *p) { return _mm256_loadu_ps(p); }
static inline void vf_store(float *p, vfloat v) { _mm256_storeu_ps(p, v); }
static inline vint vi_load(const int32_t *p) { return _mm256_loadu_si256((const __m256i *)p); }
static inline void vi_store(int32_t *p, vint v) { _mm256_storeu_si256((__m256i *)p, v); }
static inline float vf_lane(vfloat v, int i) { float t[8]; _mm256_storeu_ps(t, v); return t[i]; }
static inline int32_t vi_lane(vint v, int i) { int32_t t[8]; _mm256_storeu_si256((__m256i *)t, v); return t[i]; }
/* EVEX masked moves suppress faults on inactive lanes */
static inline vfloat vf_load_masked(vmask m, const float *p, vfloat fallback)
{
    return _mm256_mask_loadu_ps(fallback, m, p);
}
static inline void vf_store_masked(vmask m, float *p, vfloat v) { _mm256_mask_storeu_ps(p, m, v); }
/* Unmasked gathers go through the EVEX form with a full mask (the AVX2 form
 * would be the VEX instruction, i.e. the avx2 target's code); the zero source
 * breaks the dependency on the destination register. */
static inline vfloat vf_gather(const float *base, vint idx)
{
    return _mm256_mmask_i32gather_ps(_mm256_setzero_ps(), (__mmask8)0xff, idx, base, 4);
}
static inline vfloat vf_gather_masked(vmask m, const float *base, vint idx, vfloat fallback)
{
    return _mm256_mmask_i32gather_ps(fallback, m, idx, base, 4);
}
static inline vint vi_gather(const int32_t *base, vint idx)
{
    return _mm256_mmask_i32gather_epi32(_mm256_setzero_si256(), (__mmask8)0xff, idx, (const void *)base, 4);
}

static inline vfloat vf_add(vfloat a, vfloat b) { return _mm256_add_ps(a, b); }
static inline vfloat vf_sub(vfloat a, vfloat b) { return _mm256_sub_ps(a, b); }
static inline vfloat vf_mul(vfloat a, vfloat b) { return _mm256_mul_ps(a, b); }
static inline vfloat vf_div(vfloat a, vfloat b) { return _mm256_div_ps(a, b); }
static inline vfloat vf_neg(vfloat a)
{
    return _mm256_castsi256_ps(_mm256_xor_si256(_mm256_castps_si256(a), _mm256_set1_epi32((int)0x80000000u)));
}
static inline vfloat vf_abs(vfloat a)
{
    return _mm256_castsi256_ps(_mm256_and_si256(_mm256_castps_si256(a), _mm256_set1_epi32(0x7fffffff)));
}
static inline vfloat vf_min(vfloat a, vfloat b) { return _mm256_min_ps(a, b); }
static inline vfloat vf_max(vfloat a, vfloat b) { return _mm256_max_ps(a, b); }
static inline vfloat vf_sqrt(vfloat a) { return _mm256_sqrt_ps(a); }
static inline vfloat vf_fma(vfloat a, vfloat b, vfloat c) { return _mm256_fmadd_ps(a, b, c); }
static inline vfloat vf_fms(vfloat a, vfloat b, vfloat c) { return _mm256_fmsub_ps(a, b, c); }
static inline vfloat vf_fnma(vfloat a, vfloat b, vfloat c) { return _mm256_fnmadd_ps(a, b, c); }
static inline vfloat vf_rcp_approx(vfloat a) { return _mm256_rcp14_ps(a); }
static inline vfloat vf_rsqrt_approx(vfloat a) { return _mm256_rsqrt14_ps(a); }
static inline vfloat vf_floor(vfloat a) { return _mm256_roundscale_ps(a, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC); }
static inline vint vf_to_vi(vfloat a) { return _mm256_cvttps_epi32(a); }
static inline vfloat vi_to_vf(vint a) { return _mm256_cvtepi32_ps(a); }
static inline vint vf_as_vi(vfloat a) { return _mm256_castps_si256(a); }
static inline vfloat vi_as_vf(vint a) { return _mm256_castsi256_ps(a); }

static inline vint vi_add(vint a, vint b) { return _mm256_add_epi32(a, b); }
static inline vint vi_sub(vint a, vint b) { return _mm256_sub_epi32(a, b); }
static inline vint vi_mul(vint a, vint b) { return _mm256_mullo_epi32(a, b); }
static inline vint vi_min(vint a, vint b) { return _mm256_min_epi32(a, b); }
static inline vint vi_max(vint a, vint b) { return _mm256_max_epi32(a, b); }
static inline vint vi_and(vint a, vint b) { return _mm256_and_si256(a, b); }
static inline vint vi_or(vint a, vint b) { return _mm256_or_si256(a, b); }
#define vi_sll(a, n) _mm256_slli_epi32((a), (n))
#define vi_srl(a, n) _mm256_srli_epi32((a), (n))

static inline vmask vf_lt(vfloat a, vfloat b) { return _mm256_cmp_ps_mask(a, b, _CMP_LT_OQ); }
static inline vmask vf_le(vfloat a, vfloat b) { return _mm256_cmp_ps_mask(a, b, _CMP_LE_OQ); }
static inline vmask vf_gt(vfloat a, vfloat b) { return _mm256_cmp_ps_mask(a, b, _CMP_GT_OQ); }
static inline vmask vf_ge(vfloat a, vfloat b) { return _mm256_cmp_ps_mask(a, b, _CMP_GE_OQ); }
static inline vmask vf_eq(vfloat a, vfloat b) { return _mm256_cmp_ps_mask(a, b, _CMP_EQ_OQ); }
static inline vmask vf_ne(vfloat a, vfloat b) { return _mm256_cmp_ps_mask(a, b, _CMP_NEQ_UQ); }
static inline vmask vi_lt(vint a, vint b) { return _mm256_cmplt_epi32_mask(a, b); }
static inline vmask vi_gt(vint a, vint b) { return _mm256_cmpgt_epi32_mask(a, b); }
static inline vmask vi_eq(vint a, vint b) { return _mm256_cmpeq_epi32_mask(a, b); }
static inline vfloat vf_select(vmask m, vfloat t, vfloat f) { return _mm256_mask_blend_ps(m, f, t); }
static inline vint vi_select(vmask m, vint t, vint f) { return _mm256_mask_blend_epi32(m, f, t); }

static inline vmask vm_true(void) { return (vmask)0xff; }
static inline vmask vm_false(void) { return (vmask)0; }
static inline vmask vm_first_n(int n) { return n >= 8 ? (vmask)0xff : n <= 0 ? (vmask)0 : (vmask)((1u << n) - 1u); }
static inline vmask vm_and(vmask a, vmask b) { return (vmask)(a & b); }
static inline vmask vm_or(vmask a, vmask b) { return (vmask)(a | b); }
static inline vmask vm_xor(vmask a, vmask b) { return (vmask)(a ^ b); }
static inline vmask vm_andnot(vmask a, vmask b) { return (vmask)(a & ~b); }
static inline vmask vm_not(vmask a) { return (vmask)~a; }
static inline uint32_t vm_bits(vmask m) { return (uint32_t)m; }
static inline vmask vm_from_bits(uint32_t b) { return (vmask)(b & 0xffu); }
static inline int vm_any(vmask m) { return m != 0; }
static inline int vm_all(vmask m) { return m == 0xff; }
static inline int vm_none(vmask m) { return m == 0; }
static inline int vm_popcnt(vmask m) { return __builtin_popcount((unsigned)m); }
static inline int vm_first(vmask m) { return m ? __builtin_ctz((unsigned)m) : -1; }

/* No 256-bit reduce intrinsics for floats: halves, as in lane_avx2.h (same
 * summation order, so avx2 and avx512_8 agree bit for bit). */
static inline float vf_reduce_add(vfloat a)
{
    __m128 s = _mm_add_ps(_mm256_castps256_ps128(a), _mm256_extractf128_ps(a, 1));
    s = _mm_add_ps(s, _mm_movehl_ps(s, s));
    s = _mm_add_ss(s, _mm_shuffle_ps(s, s, 1));
    return _mm_cvtss_f32(s);
}
static inline float vf_reduce_min(vfloat a)
{
    __m128 s = _mm_min_ps(_mm256_castps256_ps128(a), _mm256_extractf128_ps(a, 1));
    s = _mm_min_ps(s, _mm_movehl_ps(s, s));
    s = _mm_min_ss(s, _mm_shuffle_ps(s, s, 1));
    return _mm_cvtss_f32(s);
}
static inline float vf_reduce_max(vfloat a)
{
    __m128 s = _mm_max_ps(_mm256_castps256_ps128(a), _mm256_extractf128_ps(a, 1));
    s = _mm_max_ps(s, _mm_movehl_ps(s, s));
    s = _mm_max_ss(s, _mm_shuffle_ps(s, s, 1));
    return _mm_cvtss_f32(s);
}

/* Zero-extended narrow gathers (voxels): a 32-bit gather at byte scale 1 or 2
 * and a mask, so each lane reads up to 3 (u8) or 2 (u16) bytes past its
 * element: callers keep that much readable memory after the last one. */
static inline vint vi_gather_u8(const uint8_t *base, vint idx)
{
    vint v = _mm256_mmask_i32gather_epi32(_mm256_setzero_si256(), (__mmask8)0xff, idx, (const void *)base, 1);
    return _mm256_and_si256(v, _mm256_set1_epi32(0xff));
}
static inline vint vi_gather_u16(const uint16_t *base, vint idx)
{
    vint v = _mm256_mmask_i32gather_epi32(_mm256_setzero_si256(), (__mmask8)0xff, idx, (const void *)base, 2);
    return _mm256_and_si256(v, _mm256_set1_epi32(0xffff));
}

/* Pairs of horizontally adjacent voxels: base[idx] | base[idx + 1] << 8 (16);
 * one 32-bit gather, reading up to 2 bytes past the pair (u8). */
static inline vint vi_gather_u8pair(const uint8_t *base, vint idx)
{
    vint v = _mm256_mmask_i32gather_epi32(_mm256_setzero_si256(), (__mmask8)0xff, idx, (const void *)base, 1);
    return _mm256_and_si256(v, _mm256_set1_epi32(0xffff));
}
static inline vint vi_gather_u16pair(const uint16_t *base, vint idx)
{
    return _mm256_mmask_i32gather_epi32(_mm256_setzero_si256(), (__mmask8)0xff, idx, (const void *)base, 2);
}

#endif
