/* AVX-512 (F/DQ/BW/VL) backend: sixteen lanes in __m512; masks live in k
 * registers (__mmask16), so masked loads, stores and gathers are native. */
#ifndef LC_LANE_AVX512_H
#define LC_LANE_AVX512_H

#include <immintrin.h>

#define LC_W 16
#define LC_TARGET_NAME "avx512"
#define LC_KFN(name) name##_avx512

typedef __m512 vfloat;
typedef __m512i vint;
typedef __mmask16 vmask;

static inline vfloat vf_set1(float a) { return _mm512_set1_ps(a); }
static inline vfloat vf_zero(void) { return _mm512_setzero_ps(); }
static inline vfloat vf_iota(void) { return _mm512_setr_ps(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15); }
static inline vint vi_set1(int32_t a) { return _mm512_set1_epi32(a); }
static inline vint vi_iota(void) { return _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15); }

static inline vfloat vf_load(const float *p) { return _mm512_loadu_ps(p); }
static inline void vf_store(float *p, vfloat v) { _mm512_storeu_ps(p, v); }
static inline vint vi_load(const int32_t *p) { return _mm512_loadu_si512((const void *)p); }
static inline void vi_store(int32_t *p, vint v) { _mm512_storeu_si512((void *)p, v); }
static inline float vf_lane(vfloat v, int i) { float t[16]; _mm512_storeu_ps(t, v); return t[i]; }
static inline int32_t vi_lane(vint v, int i) { int32_t t[16]; _mm512_storeu_si512((void *)t, v); return t[i]; }
static inline vfloat vf_load_masked(vmask m, const float *p, vfloat fallback) { return _mm512_mask_loadu_ps(fallback, m, p); }
static inline void vf_store_masked(vmask m, float *p, vfloat v) { _mm512_mask_storeu_ps(p, m, v); }
static inline vfloat vf_gather(const float *base, vint idx) { return _mm512_i32gather_ps(idx, base, 4); }
static inline vfloat vf_gather_masked(vmask m, const float *base, vint idx, vfloat fallback)
{
    return _mm512_mask_i32gather_ps(fallback, m, idx, base, 4);
}
static inline vint vi_gather(const int32_t *base, vint idx) { return _mm512_i32gather_epi32(idx, (const void *)base, 4); }

static inline vfloat vf_add(vfloat a, vfloat b) { return _mm512_add_ps(a, b); }
static inline vfloat vf_sub(vfloat a, vfloat b) { return _mm512_sub_ps(a, b); }
static inline vfloat vf_mul(vfloat a, vfloat b) { return _mm512_mul_ps(a, b); }
static inline vfloat vf_div(vfloat a, vfloat b) { return _mm512_div_ps(a, b); }
static inline vfloat vf_neg(vfloat a) { return _mm512_castsi512_ps(_mm512_xor_si512(_mm512_castps_si512(a), _mm512_set1_epi32((int)0x80000000u))); }
static inline vfloat vf_abs(vfloat a) { return _mm512_castsi512_ps(_mm512_and_si512(_mm512_castps_si512(a), _mm512_set1_epi32(0x7fffffff))); }
static inline vfloat vf_min(vfloat a, vfloat b) { return _mm512_min_ps(a, b); }
static inline vfloat vf_max(vfloat a, vfloat b) { return _mm512_max_ps(a, b); }
static inline vfloat vf_sqrt(vfloat a) { return _mm512_sqrt_ps(a); }
static inline vfloat vf_fma(vfloat a, vfloat b, vfloat c) { return _mm512_fmadd_ps(a, b, c); }
static inline vfloat vf_fms(vfloat a, vfloat b, vfloat c) { return _mm512_fmsub_ps(a, b, c); }
static inline vfloat vf_fnma(vfloat a, vfloat b, vfloat c) { return _mm512_fnmadd_ps(a, b, c); }
static inline vfloat vf_rcp_approx(vfloat a) { return _mm512_rcp14_ps(a); }
/* lane_math.h's p 2^n in one instruction (the same bits; 3 of exp's 18
 * operations fewer: particle anchors, commits 48c4dd2, fa5e54b). Not on avx512_8, where
 * the ymm form made 1tw7 frames 5-10% slower. */
#define LC_LANE_SCALE2 1
static inline vfloat vf_scale2(vfloat p, vfloat n) { return _mm512_scalef_ps(p, n); }
static inline vfloat vf_rsqrt_approx(vfloat a) { return _mm512_rsqrt14_ps(a); }
static inline vfloat vf_floor(vfloat a) { return _mm512_roundscale_ps(a, _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC); }
static inline vint vf_to_vi(vfloat a) { return _mm512_cvttps_epi32(a); }
static inline vfloat vi_to_vf(vint a) { return _mm512_cvtepi32_ps(a); }
static inline vint vf_as_vi(vfloat a) { return _mm512_castps_si512(a); }
static inline vfloat vi_as_vf(vint a) { return _mm512_castsi512_ps(a); }

static inline vint vi_add(vint a, vint b) { return _mm512_add_epi32(a, b); }
static inline vint vi_sub(vint a, vint b) { return _mm512_sub_epi32(a, b); }
static inline vint vi_mul(vint a, vint b) { return _mm512_mullo_epi32(a, b); }
static inline vint vi_min(vint a, vint b) { return _mm512_min_epi32(a, b); }
static inline vint vi_max(vint a, vint b) { return _mm512_max_epi32(a, b); }
static inline vint vi_and(vint a, vint b) { return _mm512_and_si512(a, b); }
static inline vint vi_or(vint a, vint b) { return _mm512_or_si512(a, b); }
#define vi_sll(a, n) _mm512_slli_epi32((a), (n))
#define vi_srl(a, n) _mm512_srli_epi32((a), (n))

static inline vmask vf_lt(vfloat a, vfloat b) { return _mm512_cmp_ps_mask(a, b, _CMP_LT_OQ); }
static inline vmask vf_le(vfloat a, vfloat b) { return _mm512_cmp_ps_mask(a, b, _CMP_LE_OQ); }
static inline vmask vf_gt(vfloat a, vfloat b) { return _mm512_cmp_ps_mask(a, b, _CMP_GT_OQ); }
static inline vmask vf_ge(vfloat a, vfloat b) { return _mm512_cmp_ps_mask(a, b, _CMP_GE_OQ); }
static inline vmask vf_eq(vfloat a, vfloat b) { return _mm512_cmp_ps_mask(a, b, _CMP_EQ_OQ); }
static inline vmask vf_ne(vfloat a, vfloat b) { return _mm512_cmp_ps_mask(a, b, _CMP_NEQ_UQ); }
static inline vmask vi_lt(vint a, vint b) { return _mm512_cmplt_epi32_mask(a, b); }
static inline vmask vi_gt(vint a, vint b) { return _mm512_cmpgt_epi32_mask(a, b); }
static inline vmask vi_eq(vint a, vint b) { return _mm512_cmpeq_epi32_mask(a, b); }
static inline vfloat vf_select(vmask m, vfloat t, vfloat f) { return _mm512_mask_blend_ps(m, f, t); }
static inline vint vi_select(vmask m, vint t, vint f) { return _mm512_mask_blend_epi32(m, f, t); }

static inline vmask vm_true(void) { return (vmask)0xffff; }
static inline vmask vm_false(void) { return (vmask)0; }
static inline vmask vm_first_n(int n) { return n >= 16 ? (vmask)0xffff : n <= 0 ? (vmask)0 : (vmask)((1u << n) - 1u); }
static inline vmask vm_and(vmask a, vmask b) { return (vmask)(a & b); }
static inline vmask vm_or(vmask a, vmask b) { return (vmask)(a | b); }
static inline vmask vm_xor(vmask a, vmask b) { return (vmask)(a ^ b); }
static inline vmask vm_andnot(vmask a, vmask b) { return (vmask)(a & ~b); }
static inline vmask vm_not(vmask a) { return (vmask)~a; }
static inline uint32_t vm_bits(vmask m) { return (uint32_t)m; }
static inline vmask vm_from_bits(uint32_t b) { return (vmask)(b & 0xffffu); }
static inline int vm_any(vmask m) { return m != 0; }
static inline int vm_all(vmask m) { return m == 0xffff; }
static inline int vm_none(vmask m) { return m == 0; }
static inline int vm_popcnt(vmask m) { return __builtin_popcount((unsigned)m); }
static inline int vm_first(vmask m) { return m ? __builtin_ctz((unsigned)m) : -1; }

static inline float vf_reduce_add(vfloat a) { return _mm512_reduce_add_ps(a); }
static inline float vf_reduce_min(vfloat a) { return _mm512_reduce_min_ps(a); }
static inline float vf_reduce_max(vfloat a) { return _mm512_reduce_max_ps(a); }

/* Zero-extended narrow gathers (voxels): a 32-bit gather at byte scale 1 or 2
 * and a mask, so each lane reads up to 3 (u8) or 2 (u16) bytes past its
 * element: callers keep that much readable memory after the last one. */
static inline vint vi_gather_u8(const uint8_t *base, vint idx)
{
    return _mm512_and_si512(_mm512_i32gather_epi32(idx, (const void *)base, 1), _mm512_set1_epi32(0xff));
}
static inline vint vi_gather_u16(const uint16_t *base, vint idx)
{
    return _mm512_and_si512(_mm512_i32gather_epi32(idx, (const void *)base, 2), _mm512_set1_epi32(0xffff));
}

/* Pairs of horizontally adjacent voxels: base[idx] | base[idx + 1] << 8 (16);
 * one 32-bit gather, reading up to 2 bytes past the pair (u8). */
static inline vint vi_gather_u8pair(const uint8_t *base, vint idx)
{
    return _mm512_and_si512(_mm512_i32gather_epi32(idx, (const void *)base, 1), _mm512_set1_epi32(0xffff));
}
static inline vint vi_gather_u16pair(const uint16_t *base, vint idx)
{
    return _mm512_i32gather_epi32(idx, (const void *)base, 2);
}

#endif
