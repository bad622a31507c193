/* The RBF term shared by the RBF set kernels (kernels/rbf.c: BVH and brute
 * force; kernels/rbf_octree.c: the octree), so every method sums a term with
 * the same arithmetic and they agree to the bit on the same terms in the same
 * order. Jang et al. 2004, eqs. 2-3. */
#ifndef LC_RBF_COMMON_H
#define LC_RBF_COMMON_H

#include "mode.h"
#include "shared/krbf.h"

/* Boxes grow a little more than R so float round-off in the box test never
 * drops a sample inside a support (the exact test is d2 < R^2 in term()). */
static inline float grow(float r) { return r * 1.0001f + 1e-6f; }

/* Term i at the points p on the lanes in m: adds w_i exp(d2 nis_i) to *phi
 * and, with grad, its gradient -(p - mu_i) / s_i^2 phi_i to g*. Returns the
 * lanes inside the support. */
static inline vmask term(const lc_krbf *s, int32_t i, vfloat px, vfloat py, vfloat pz, vmask m, int grad, vfloat *phi,
                         vfloat *gx, vfloat *gy, vfloat *gz)
{
    vfloat ex = vf_sub(px, vf_set1(s->cx[i])), ey = vf_sub(py, vf_set1(s->cy[i])), ez = vf_sub(pz, vf_set1(s->cz[i]));
    vfloat d2 = vf_fma(ex, ex, vf_fma(ey, ey, vf_mul(ez, ez)));
    vmask in = vm_and(m, vf_lt(d2, vf_set1(s->r2[i])));
    if (vm_none(in)) return in;
    float nis = s->nis[i];
    vfloat p = vf_select(in, vf_mul(vf_set1(s->w[i]), vf_exp(vf_mul(d2, vf_set1(nis)))), vf_zero());
    *phi = vf_add(*phi, p);
    if (grad) {
        vfloat gp = vf_mul(p, vf_set1(2.0f * nis));
        *gx = vf_fma(ex, gp, *gx);
        *gy = vf_fma(ey, gp, *gy);
        *gz = vf_fma(ez, gp, *gz);
    }
    return in;
}

#endif
