/* SSE4.2 backend: four lanes in __m128. Masks are all-ones/all-zeros lanes in
 * an __m128. SSE has no gather or masked load: those are per-lane loads that
 * never touch memory of inactive lanes. */
#ifndef LC_LANE_SSE4_H
#define LC_LANE_SSE4_H

#include <smmintrin.h>
#include <nmmintrin.h>

#define LC_W 4
#define LC_TARGET_NAME "sse4"
#define LC_KFN(name) name##_sse4

typedef __m128 vfloat;
typedef __m128i vint;
typedef __m128 vmask;

static inline vfloat vf_set1(float a) { return _mm_set1_ps(a); }
static inline vfloat vf_zero(void) { return _mm_setzero_ps(); }
static inline vfloat vf_iota(void) { return _mm_setr_ps(0, 1, 2, 3); }
static inline vint vi_set1(int32_t a) { return _mm_set1_epi32(a); }
static inline vint vi_iota(void) { return _mm_setr_epi32(0, 1, 2, 3); }

static inline vfloat vf_load(const float *p) { return _mm_loadu_ps(p); }
static inline void vf_store(float *p, vfloat v) { _mm_storeu_ps(p, v); }
static inline vint vi_load(const int32_t *p) { return _mm_loadu_si128((const __m128i *)p); }
static inline void vi_store(int32_t *p, vint v) { _mm_storeu_si128((__m128i *)p, v); }
static inline float vf_lane(vfloat v, int i) { float t[4]; _mm_storeu_ps(t, v); return t[i]; }
static inline int32_t vi_lane(vint v, int i) { int32_t t[4]; _mm_storeu_si128((__m128i *)t, v); return t[i]; }
static inline uint32_t vm_bits(vmask m) { return (uint32_t)_mm_movemask_ps(m); }
static inline vfloat vf_load_masked(vmask m, const float *p, vfloat fallback)
{
    float t[4];
    uint32_t b = vm_bits(m);
    _mm_storeu_ps(t, fallback);
    for (int i = 0; i < 4; i++)
        if (b & (1u << i)) t[i] = p[i];
    return _mm_loadu_ps(t);
}
static inline void vf_store_masked(vmask m, float *p, vfloat v)
{
    float t[4];
    uint32_t b = vm_bits(m);
    _mm_storeu_ps(t, v);
    for (int i = 0; i < 4; i++)
        if (b & (1u << i)) p[i] = t[i];
}
static inline vfloat vf_gather(const float *base, vint idx)
{
    return _mm_setr_ps(base[_mm_extract_epi32(idx, 0)], base[_mm_extract_epi32(idx, 1)],
                       base[_mm_extract_epi32(idx, 2)], base[_mm_extract_epi32(idx, 3)]);
}
static inline vfloat vf_gather_masked(vmask m, const float *base, vint idx, vfloat fallback)
{
    float t[4];
    int32_t ix[4];
    uint32_t b = vm_bits(m);
    _mm_storeu_ps(t, fallback);
    _mm_storeu_si128((__m128i *)ix, idx);
    for (int i = 0; i < 4; i++)
        if (b & (1u << i)) t[i] = base[ix[i]];
    return _mm_loadu_ps(t);
}
static inline vint vi_gather(const int32_t *base, vint idx)
{
    return _mm_setr_epi32(base[_mm_extract_epi32(idx, 0)], base[_mm_extract_epi32(idx, 1)],
                          base[_mm_extract_epi32(idx, 2)], base[_mm_extract_epi32(idx, 3)]);
}

static inline vfloat vf_add(vfloat a, vfloat b) { return _mm_add_ps(a, b); }
static inline vfloat vf_sub(vfloat a, vfloat b) { return _mm_sub_ps(a, b); }
static inline vfloat vf_mul(vfloat a, vfloat b) { return _mm_mul_ps(a, b); }
static inline vfloat vf_div(vfloat a, vfloat b) { return _mm_div_ps(a, b); }
static inline vfloat vf_neg(vfloat a) { return _mm_xor_ps(a, _mm_set1_ps(-0.0f)); }
static inline vfloat vf_abs(vfloat a) { return _mm_andnot_ps(_mm_set1_ps(-0.0f), a); }
static inline vfloat vf_min(vfloat a, vfloat b) { return _mm_min_ps(a, b); }
static inline vfloat vf_max(vfloat a, vfloat b) { return _mm_max_ps(a, b); }
static inline vfloat vf_sqrt(vfloat a) { return _mm_sqrt_ps(a); }
/* SSE4.2 has no FMA unit: these round twice (within SPEC tolerances). */
static inline vfloat vf_fma(vfloat a, vfloat b, vfloat c) { return _mm_add_ps(_mm_mul_ps(a, b), c); }
static inline vfloat vf_fms(vfloat a, vfloat b, vfloat c) { return _mm_sub_ps(_mm_mul_ps(a, b), c); }
static inline vfloat vf_fnma(vfloat a, vfloat b, vfloat c) { return _mm_sub_ps(c, _mm_mul_ps(a, b)); }
static inline vfloat vf_rcp_approx(vfloat a) { return _mm_rcp_ps(a); }
static inline vfloat vf_rsqrt_approx(vfloat a) { return _mm_rsqrt_ps(a); }
static inline vfloat vf_floor(vfloat a) { return _mm_floor_ps(a); }
static inline vint vf_to_vi(vfloat a) { return _mm_cvttps_epi32(a); }
static inline vfloat vi_to_vf(vint a) { return _mm_cvtepi32_ps(a); }
static inline vint vf_as_vi(vfloat a) { return _mm_castps_si128(a); }
static inline vfloat vi_as_vf(vint a) { return _mm_castsi128_ps(a); }

static inline vint vi_add(vint a, vint b) { return _mm_add_epi32(a, b); }
static inline vint vi_sub(vint a, vint b) { return _mm_sub_epi32(a, b); }
static inline vint vi_mul(vint a, vint b) { return _mm_mullo_epi32(a, b); }
static inline vint vi_min(vint a, vint b) { return _mm_min_epi32(a, b); }
static inline vint vi_max(vint a, vint b) { return _mm_max_epi32(a, b); }
static inline vint vi_and(vint a, vint b) { return _mm_and_si128(a, b); }
static inline vint vi_or(vint a, vint b) { return _mm_or_si128(a, b); }
#define vi_sll(a, n) _mm_slli_epi32((a), (n))
#define vi_srl(a, n) _mm_srli_epi32((a), (n))

static inline vmask vf_lt(vfloat a, vfloat b) { return _mm_cmplt_ps(a, b); }
static inline vmask vf_le(vfloat a, vfloat b) { return _mm_cmple_ps(a, b); }
static inline vmask vf_gt(vfloat a, vfloat b) { return _mm_cmpgt_ps(a, b); }
static inline vmask vf_ge(vfloat a, vfloat b) { return _mm_cmpge_ps(a, b); }
static inline vmask vf_eq(vfloat a, vfloat b) { return _mm_cmpeq_ps(a, b); }
static inline vmask vf_ne(vfloat a, vfloat b) { return _mm_cmpneq_ps(a, b); }
static inline vmask vi_lt(vint a, vint b) { return _mm_castsi128_ps(_mm_cmplt_epi32(a, b)); }
static inline vmask vi_gt(vint a, vint b) { return _mm_castsi128_ps(_mm_cmpgt_epi32(a, b)); }
static inline vmask vi_eq(vint a, vint b) { return _mm_castsi128_ps(_mm_cmpeq_epi32(a, b)); }
static inline vfloat vf_select(vmask m, vfloat t, vfloat f) { return _mm_blendv_ps(f, t, m); }
static inline vint vi_select(vmask m, vint t, vint f)
{
    return _mm_castps_si128(_mm_blendv_ps(_mm_castsi128_ps(f), _mm_castsi128_ps(t), m));
}

static inline vmask vm_true(void) { return _mm_castsi128_ps(_mm_set1_epi32(-1)); }
static inline vmask vm_false(void) { return _mm_setzero_ps(); }
static inline vmask vm_first_n(int n) { return vi_lt(vi_iota(), vi_set1(n)); }
static inline vmask vm_and(vmask a, vmask b) { return _mm_and_ps(a, b); }
static inline vmask vm_or(vmask a, vmask b) { return _mm_or_ps(a, b); }
static inline vmask vm_xor(vmask a, vmask b) { return _mm_xor_ps(a, b); }
static inline vmask vm_andnot(vmask a, vmask b) { return _mm_andnot_ps(b, a); }
static inline vmask vm_not(vmask a) { return _mm_xor_ps(a, vm_true()); }
static inline vmask vm_from_bits(uint32_t b)
{
    const __m128i bit = _mm_setr_epi32(1, 2, 4, 8);
    return _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32((int)b), bit), bit));
}
static inline int vm_any(vmask m) { return _mm_movemask_ps(m) != 0; }
static inline int vm_all(vmask m) { return _mm_movemask_ps(m) == 0xf; }
static inline int vm_none(vmask m) { return _mm_movemask_ps(m) == 0; }
static inline int vm_popcnt(vmask m) { return __builtin_popcount((unsigned)_mm_movemask_ps(m)); }
static inline int vm_first(vmask m)
{
    unsigned b = (unsigned)_mm_movemask_ps(m);
    return b ? __builtin_ctz(b) : -1;
}

static inline float vf_reduce_add(vfloat a)
{
    __m128 s = _mm_add_ps(a, _mm_movehl_ps(a, a));
    s = _mm_add_ss(s, _mm_shuffle_ps(s, s, 1));
    return _mm_cvtss_f32(s);
}
static inline float vf_reduce_min(vfloat a)
{
    __m128 s = _mm_min_ps(a, _mm_movehl_ps(a, a));
    s = _mm_min_ss(s, _mm_shuffle_ps(s, s, 1));
    return _mm_cvtss_f32(s);
}
static inline float vf_reduce_max(vfloat a)
{
    __m128 s = _mm_max_ps(a, _mm_movehl_ps(a, a));
    s = _mm_max_ss(s, _mm_shuffle_ps(s, s, 1));
    return _mm_cvtss_f32(s);
}

/* Zero-extended narrow gathers (voxels); per-lane loads of exactly one element. */
static inline vint vi_gather_u8(const uint8_t *base, vint idx)
{
    return _mm_setr_epi32(base[_mm_extract_epi32(idx, 0)], base[_mm_extract_epi32(idx, 1)],
                          base[_mm_extract_epi32(idx, 2)], base[_mm_extract_epi32(idx, 3)]);
}
static inline vint vi_gather_u16(const uint16_t *base, vint idx)
{
    return _mm_setr_epi32(base[_mm_extract_epi32(idx, 0)], base[_mm_extract_epi32(idx, 1)],
                          base[_mm_extract_epi32(idx, 2)], base[_mm_extract_epi32(idx, 3)]);
}

/* Pairs of horizontally adjacent voxels: base[idx] | base[idx + 1] << 8 (16). */
static inline vint vi_gather_u8pair(const uint8_t *base, vint idx)
{
    int32_t ix[4], v[4];
    _mm_storeu_si128((__m128i *)ix, idx);
    for (int l = 0; l < 4; l++) v[l] = base[ix[l]] | base[ix[l] + 1] << 8;
    return _mm_loadu_si128((const __m128i *)v);
}
static inline vint vi_gather_u16pair(const uint16_t *base, vint idx)
{
    int32_t ix[4], v[4];
    _mm_storeu_si128((__m128i *)ix, idx);
    for (int l = 0; l < 4; l++) v[l] = (int32_t)((uint32_t)base[ix[l]] | (uint32_t)base[ix[l] + 1] << 16);
    return _mm_loadu_si128((const __m128i *)v);
}

#endif
