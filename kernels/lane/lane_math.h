/* Math built once over the lane vocabulary, identical on every target. */
#ifndef LC_LANE_MATH_H
#define LC_LANE_MATH_H

static inline vfloat vf_clamp(vfloat x, vfloat lo, vfloat hi) { return vf_min(vf_max(x, lo), hi); }
/* a * b + c, a * b - c and c - a * b rounded twice on every target (never
 * fused): the geometry that decides whether a sample lies inside a truncated
 * support (ray directions, sample positions, squared distances) must give
 * the same bits on every target, or a sample at the cut keeps a term on one
 * target and drops it on another (a jump of exp(-sigma^2 / 2) of a peak). */
static inline vfloat vf_madd(vfloat a, vfloat b, vfloat c) { return vf_add(vf_mul(a, b), c); }
static inline vfloat vf_msub(vfloat a, vfloat b, vfloat c) { return vf_sub(vf_mul(a, b), c); }
static inline vfloat vf_nmadd(vfloat a, vfloat b, vfloat c) { return vf_sub(c, vf_mul(a, b)); }
static inline vfloat vf_lerp(vfloat a, vfloat b, vfloat w) { return vf_fma(w, vf_sub(b, a), a); }

/* One Newton-Raphson step on the hardware estimate: relative error ~1e-7 on
 * AVX-512 (14-bit seed), ~5e-7 on SSE/AVX (12-bit seed). */
static inline vfloat vf_rcp(vfloat a)
{
    vfloat r = vf_rcp_approx(a);
    return vf_mul(r, vf_fnma(a, r, vf_set1(2.0f)));
}
static inline vfloat vf_rsqrt(vfloat a)
{
    vfloat r = vf_rsqrt_approx(a);
    vfloat hr = vf_mul(vf_set1(0.5f), r);
    vfloat arr = vf_mul(vf_mul(a, r), r);
    return vf_mul(hr, vf_sub(vf_set1(3.0f), arr));
}

/* p 2^n for integral n in [-126, 127] (2^n a normal float): the exact
 * product rounded once. Built here from 2^n's exponent field and a multiply;
 * a backend with a direct instruction defines LC_LANE_SCALE2 and its own
 * (avx512: vscalefps, the same bits; tests/test_lane.c checks every target
 * against ldexp). */
#ifndef LC_LANE_SCALE2
static inline vfloat vf_scale2(vfloat p, vfloat n)
{
    return vf_mul(p, vi_as_vf(vi_sll(vi_add(vf_to_vi(n), vi_set1(127)), 23)));
}
#endif

/* exp(x): Cephes-style range reduction x = n ln2 + r, |r| <= ln2/2, a degree-6
 * polynomial for e^r, times 2^n (vf_scale2). The argument is
 * clamped to [-87.3, 88.37]: below that the result would be denormal, which
 * both loses precision and slows SIMD code (NOTES.md); above 88.37,
 * n = floor(x log2(e) + 0.5) reaches 128 and n + 127 is the exponent field of
 * infinity, so exp(88.5) came out as inf instead of 2.7e38. Larger arguments
 * saturate at exp(88.37) ~ 2.4e38. Measured relative error below 1.5e-7 over
 * the range (lane conformance test checks 1e-6). */
static inline vfloat vf_exp(vfloat x)
{
    x = vf_clamp(x, vf_set1(-87.3f), vf_set1(88.37f));
    vfloat fx = vf_floor(vf_fma(x, vf_set1(1.44269504088896341f), vf_set1(0.5f)));
    vfloat r = vf_fnma(fx, vf_set1(0.693359375f), x);
    r = vf_fnma(fx, vf_set1(-2.12194440e-4f), r);
    vfloat p = vf_set1(1.9875691500e-4f);
    p = vf_fma(p, r, vf_set1(1.3981999507e-3f));
    p = vf_fma(p, r, vf_set1(8.3334519073e-3f));
    p = vf_fma(p, r, vf_set1(4.1665795894e-2f));
    p = vf_fma(p, r, vf_set1(1.6666665459e-1f));
    p = vf_fma(p, r, vf_set1(5.0000001201e-1f));
    vfloat r2 = vf_mul(r, r);
    p = vf_fma(p, r2, vf_add(r, vf_set1(1.0f)));
    return vf_scale2(p, fx); /* fx in [-126, 127] after the clamp */
}

/* x^p for a small non-negative integer p, by repeated squaring (Phong). */
static inline vfloat vf_powi(vfloat x, int p)
{
    vfloat r = vf_set1(1.0f);
    while (p > 0) {
        if (p & 1) r = vf_mul(r, x);
        x = vf_mul(x, x);
        p >>= 1;
    }
    return r;
}

static inline float vf_reduce_min_masked(vmask m, vfloat v) { return vf_reduce_min(vf_select(m, v, vf_set1(__builtin_inff()))); }
static inline float vf_reduce_max_masked(vmask m, vfloat v) { return vf_reduce_max(vf_select(m, v, vf_set1(-__builtin_inff()))); }
static inline float vf_reduce_add_masked(vmask m, vfloat v) { return vf_reduce_add(vf_select(m, v, vf_zero())); }

#endif
