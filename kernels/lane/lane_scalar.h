/* Scalar backend: one lane. The reference every SIMD backend is tested against. */
#ifndef LC_LANE_SCALAR_H
#define LC_LANE_SCALAR_H

#include <math.h>
#include <string.h>

#define LC_W 1
#define LC_TARGET_NAME "scalar"
#define LC_KFN(name) name##_scalar

typedef float vfloat;
typedef int32_t vint;
typedef uint32_t vmask; /* 0 or 1 */

/* construction */
static inline vfloat vf_set1(float a) { return a; }
static inline vfloat vf_zero(void) { return 0.0f; }
static inline vfloat vf_iota(void) { return 0.0f; }
static inline vint vi_set1(int32_t a) { return a; }
static inline vint vi_iota(void) { return 0; }

/* memory */
static inline vfloat vf_load(const float *p) { return *p; }
static inline void vf_store(float *p, vfloat v) { *p = v; }
static inline vint vi_load(const int32_t *p) { return *p; }
static inline void vi_store(int32_t *p, vint v) { *p = v; }
static inline vfloat vf_load_masked(vmask m, const float *p, vfloat fallback) { return m ? *p : fallback; }
static inline void vf_store_masked(vmask m, float *p, vfloat v) { if (m) *p = v; }
static inline vfloat vf_gather(const float *base, vint idx) { return base[idx]; }
static inline vfloat vf_gather_masked(vmask m, const float *base, vint idx, vfloat fallback) { return m ? base[idx] : fallback; }
static inline vint vi_gather(const int32_t *base, vint idx) { return base[idx]; }
static inline float vf_lane(vfloat v, int i) { (void)i; return v; }
static inline int32_t vi_lane(vint v, int i) { (void)i; return v; }

/* float arithmetic */
static inline vfloat vf_add(vfloat a, vfloat b) { return a + b; }
static inline vfloat vf_sub(vfloat a, vfloat b) { return a - b; }
static inline vfloat vf_mul(vfloat a, vfloat b) { return a * b; }
static inline vfloat vf_div(vfloat a, vfloat b) { return a / b; }
static inline vfloat vf_neg(vfloat a) { return -a; }
static inline vfloat vf_abs(vfloat a) { return fabsf(a); }
static inline vfloat vf_min(vfloat a, vfloat b) { return a < b ? a : b; }
static inline vfloat vf_max(vfloat a, vfloat b) { return a > b ? a : b; }
static inline vfloat vf_sqrt(vfloat a) { return sqrtf(a); }
/* Baseline x86-64 has no FMA instruction (fmaf would be a libm call): the
 * scalar target rounds twice, like SSE4. */
static inline vfloat vf_fma(vfloat a, vfloat b, vfloat c) { return a * b + c; }
static inline vfloat vf_fms(vfloat a, vfloat b, vfloat c) { return a * b - c; }
static inline vfloat vf_fnma(vfloat a, vfloat b, vfloat c) { return c - a * b; }
static inline vfloat vf_rcp_approx(vfloat a) { return 1.0f / a; }
static inline vfloat vf_rsqrt_approx(vfloat a) { return 1.0f / sqrtf(a); }
static inline vfloat vf_floor(vfloat a) { return floorf(a); }
static inline vint vf_to_vi(vfloat a) { return (int32_t)a; } /* truncation */
static inline vfloat vi_to_vf(vint a) { return (float)a; }
static inline vint vf_as_vi(vfloat a) { vint r; memcpy(&r, &a, 4); return r; }
static inline vfloat vi_as_vf(vint a) { vfloat r; memcpy(&r, &a, 4); return r; }

/* int arithmetic */
static inline vint vi_add(vint a, vint b) { return (int32_t)((uint32_t)a + (uint32_t)b); }
static inline vint vi_sub(vint a, vint b) { return (int32_t)((uint32_t)a - (uint32_t)b); }
static inline vint vi_mul(vint a, vint b) { return (int32_t)((uint32_t)a * (uint32_t)b); }
static inline vint vi_min(vint a, vint b) { return a < b ? a : b; }
static inline vint vi_max(vint a, vint b) { return a > b ? a : b; }
static inline vint vi_and(vint a, vint b) { return a & b; }
static inline vint vi_or(vint a, vint b) { return a | b; }
#define vi_sll(a, n) ((int32_t)((uint32_t)(a) << (n)))
#define vi_srl(a, n) ((int32_t)((uint32_t)(a) >> (n)))

/* comparisons */
static inline vmask vf_lt(vfloat a, vfloat b) { return a < b; }
static inline vmask vf_le(vfloat a, vfloat b) { return a <= b; }
static inline vmask vf_gt(vfloat a, vfloat b) { return a > b; }
static inline vmask vf_ge(vfloat a, vfloat b) { return a >= b; }
static inline vmask vf_eq(vfloat a, vfloat b) { return a == b; }
static inline vmask vf_ne(vfloat a, vfloat b) { return a != b; }
static inline vmask vi_lt(vint a, vint b) { return a < b; }
static inline vmask vi_gt(vint a, vint b) { return a > b; }
static inline vmask vi_eq(vint a, vint b) { return a == b; }
static inline vfloat vf_select(vmask m, vfloat t, vfloat f) { return m ? t : f; }
static inline vint vi_select(vmask m, vint t, vint f) { return m ? t : f; }

/* masks */
static inline vmask vm_true(void) { return 1; }
static inline vmask vm_false(void) { return 0; }
static inline vmask vm_first_n(int n) { return n > 0; }
static inline vmask vm_and(vmask a, vmask b) { return a & b; }
static inline vmask vm_or(vmask a, vmask b) { return a | b; }
static inline vmask vm_xor(vmask a, vmask b) { return a ^ b; }
static inline vmask vm_andnot(vmask a, vmask b) { return a & !b; } /* a and not b */
static inline vmask vm_not(vmask a) { return !a; }
static inline uint32_t vm_bits(vmask m) { return m; }
static inline vmask vm_from_bits(uint32_t b) { return b & 1u; }
static inline int vm_any(vmask m) { return m != 0; }
static inline int vm_all(vmask m) { return m != 0; }
static inline int vm_none(vmask m) { return m == 0; }
static inline int vm_popcnt(vmask m) { return (int)m; }
static inline int vm_first(vmask m) { return m ? 0 : -1; }

/* horizontal reductions */
static inline float vf_reduce_add(vfloat a) { return a; }
static inline float vf_reduce_min(vfloat a) { return a; }
static inline float vf_reduce_max(vfloat a) { return a; }

static inline vint vi_gather_u8(const uint8_t *base, vint idx) { return base[idx]; }
static inline vint vi_gather_u16(const uint16_t *base, vint idx) { return base[idx]; }

/* Pairs of horizontally adjacent voxels: base[idx] | base[idx + 1] << 8 (16). */
static inline vint vi_gather_u8pair(const uint8_t *base, vint idx) { return base[idx] | base[idx + 1] << 8; }
static inline vint vi_gather_u16pair(const uint16_t *base, vint idx) { return (int32_t)((uint32_t)base[idx] | (uint32_t)base[idx + 1] << 16); }

#endif
