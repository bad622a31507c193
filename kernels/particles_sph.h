/* The SPH kernels in the lane vocabulary (SPEC.md "SPH kernels and
 * projections"): the one place every particle kernel path (the direct
 * method's gather and the probes in particles_common.h, the coherent
 * deposits in particles_walk.h) evaluates them. Support radius H (u = d / H),
 * W(d, H) = norm / H^3 f(u), f = 0 for u >= 1; the host's double copies of the
 * same polynomials (host/sph/sph_kernel.c) serve its tables and conversions,
 * and tests/test_sph_render.c checks these against the reference written from
 * SPEC.md. The kernel ids are kparticles.h's LC_KSPH_*. */
#ifndef LC_PARTICLES_SPH_H
#define LC_PARTICLES_SPH_H

#include "lane/lane.h"
#include "shared/kparticles.h"

static inline vfloat sph_p2(vfloat x) { return vf_mul(x, x); }
static inline vfloat sph_p4(vfloat x) { return sph_p2(sph_p2(x)); }

/* f(u) of kernel `kernel` at u in [0, 1] (callers clamp), and *gu = f'(u) / u
 * (the gradient is norm / H^5 * gu * (x - x_i)). The B-splines' truncated
 * powers (each term where its base is positive) give the value; their inner
 * pieces' derivatives are expanded so f'(u) / u stays exact at u -> 0. */
static inline vfloat sph_shape(int kernel, vfloat u, vfloat *gu)
{
    const vfloat one = vf_set1(1.0f), zero = vf_zero();
    vfloat t = vf_sub(one, u), f, g;
    switch (kernel) {
    case LC_KSPH_M4: { /* 1 - 6u^2 + 6u^3 (u < 1/2), 2 (1 - u)^3 */
        vmask in = vf_lt(u, vf_set1(0.5f));
        vfloat t2 = sph_p2(t);
        f = vf_select(in, vf_nmadd(vf_mul(vf_set1(6.0f), sph_p2(u)), t, one), vf_mul(vf_set1(2.0f), vf_mul(t2, t)));
        g = vf_select(in, vf_fma(vf_set1(18.0f), u, vf_set1(-12.0f)),
                      vf_div(vf_mul(vf_set1(-6.0f), t2), vf_max(u, vf_set1(0.5f))));
        break;
    }
    case LC_KSPH_M5: { /* q = 2.5u: (2.5 - q)^4 - 5 (1.5 - q)^4 + 10 (0.5 - q)^4 */
        vfloat q = vf_mul(vf_set1(2.5f), u);
        vfloat a = vf_sub(vf_set1(2.5f), q), b = vf_max(vf_sub(vf_set1(1.5f), q), zero);
        vfloat c = vf_max(vf_sub(vf_set1(0.5f), q), zero);
        f = vf_fma(vf_set1(10.0f), sph_p4(c), vf_fma(vf_set1(-5.0f), sph_p4(b), sph_p4(a)));
        /* f'(u) = -10 (a^3 - 5 b^3 + 10 c^3); for q < 1/2, f = 14.375 - 15 q^2 + 6 q^4, so
           f'(u) / u = 6.25 (-30 + 24 q^2) */
        vfloat d = vf_fma(vf_set1(10.0f), vf_mul(sph_p2(c), c),
                          vf_fma(vf_set1(-5.0f), vf_mul(sph_p2(b), b), vf_mul(sph_p2(a), a)));
        vfloat outer = vf_div(vf_mul(vf_set1(-10.0f), d), vf_max(u, vf_set1(0.2f)));
        vfloat inner = vf_mul(vf_set1(6.25f), vf_fma(vf_set1(24.0f), sph_p2(q), vf_set1(-30.0f)));
        g = vf_select(vf_lt(q, vf_set1(0.5f)), inner, outer);
        break;
    }
    case LC_KSPH_M6: { /* q = 3u: (3 - q)^5 - 6 (2 - q)^5 + 15 (1 - q)^5 */
        vfloat q = vf_mul(vf_set1(3.0f), u);
        vfloat a = vf_sub(vf_set1(3.0f), q), b = vf_max(vf_sub(vf_set1(2.0f), q), zero);
        vfloat c = vf_max(vf_sub(one, q), zero);
        vfloat a4 = sph_p4(a), b4 = sph_p4(b), c4 = sph_p4(c);
        f = vf_fma(vf_set1(15.0f), vf_mul(c4, c), vf_fma(vf_set1(-6.0f), vf_mul(b4, b), vf_mul(a4, a)));
        /* f'(u) = -15 (a^4 - 6 b^4 + 15 c^4); for q < 1 the bracket is 24q - 24q^3 + 10q^4, so
           f'(u) / u = 9 (-120 + 120 q^2 - 50 q^3) */
        vfloat d = vf_fma(vf_set1(15.0f), c4, vf_fma(vf_set1(-6.0f), b4, a4));
        vfloat outer = vf_div(vf_mul(vf_set1(-15.0f), d), vf_max(u, vf_set1(1.0f / 3.0f)));
        vfloat q2 = sph_p2(q);
        vfloat inner = vf_mul(vf_set1(9.0f), vf_fma(q2, vf_fma(vf_set1(-50.0f), q, vf_set1(120.0f)), vf_set1(-120.0f)));
        g = vf_select(vf_lt(q, one), inner, outer);
        break;
    }
    case LC_KSPH_C2: { /* (1 - u)^4 (1 + 4u); f' / u = -20 (1 - u)^3 */
        vfloat t3 = vf_mul(sph_p2(t), t);
        f = vf_mul(vf_mul(t3, t), vf_fma(vf_set1(4.0f), u, one));
        g = vf_mul(vf_set1(-20.0f), t3);
        break;
    }
    case LC_KSPH_C4: { /* (1 - u)^6 (1 + 6u + 35/3 u^2); f' / u = -56/3 (1 + 5u) (1 - u)^5 */
        vfloat t5 = vf_mul(sph_p4(t), t);
        f = vf_mul(vf_mul(t5, t), vf_fma(u, vf_fma(vf_set1(35.0f / 3.0f), u, vf_set1(6.0f)), one));
        g = vf_mul(vf_set1(-56.0f / 3.0f), vf_mul(vf_fma(vf_set1(5.0f), u, one), t5));
        break;
    }
    default: { /* C6: (1 - u)^8 (1 + 8u + 25u^2 + 32u^3); f' / u = -22 (1 + 7u + 16u^2) (1 - u)^7 */
        vfloat t4 = sph_p4(t), t7 = vf_mul(vf_mul(t4, sph_p2(t)), t);
        vfloat poly = vf_fma(u, vf_fma(u, vf_fma(vf_set1(32.0f), u, vf_set1(25.0f)), vf_set1(8.0f)), one);
        f = vf_mul(sph_p2(t4), poly);
        g = vf_mul(vf_set1(-22.0f), vf_mul(vf_fma(u, vf_fma(vf_set1(16.0f), u, vf_set1(7.0f)), one), t7));
        break;
    }
    }
    *gu = g;
    return f;
}

/* One particle's SPH constants: 1 / H^2 and the amplitude kappa k_i norm / H^3
 * (norm the kernel's 3-D normalisation, lc_kparticles.knorm), computed the same
 * way wherever a term is evaluated, so both methods take the same terms. */
typedef struct sph_consts {
    float ih2, amp;
} sph_consts;

static inline sph_consts sph_consts_make(float H, float kk, float knorm)
{
    float ih = 1.0f / H;
    sph_consts c;
    c.ih2 = ih * ih;
    c.amp = kk * knorm * ih * c.ih2;
    return c;
}

/* The term amp f(u) at squared distances d2 on the lanes in m (zero elsewhere)
 * and, when gs is not NULL, the gradient's scale: grad = *gs * (x - x_i). */
static inline vfloat sph_term(int kernel, const sph_consts *c, vfloat d2, vmask m, vfloat *gs)
{
    vfloat u = vf_min(vf_sqrt(vf_mul(d2, vf_set1(c->ih2))), vf_set1(1.0f));
    vfloat gu;
    vfloat f = sph_shape(kernel, u, &gu);
    if (gs) *gs = vf_select(m, vf_mul(vf_set1(c->amp * c->ih2), gu), vf_zero());
    return vf_select(m, vf_mul(vf_set1(c->amp), f), vf_zero());
}

#endif
