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


/* One packet of rays of the tile at pixel block (x, y): the rays, their
 * overlap [ta, tb] with the set's box (ta > tb on lanes without one), their
 * lattice range [kf, kl] there, and whether any lane has samples (0: the
 * caller stores the empty colour and moves on). Shared by the BVH gather and
 * the octree. */
static inline int rbf_packet_setup(const lc_krbf *s, const lc_kframe *f, const lc_ktile *t, int x, int y, vint *px,
                                   vint *py, vray *r, vfloat *ta, vfloat *tb, vint *kf, vint *kl, lc_kstats *st)
{
    dvr_packet_pixels(x, y, px, py);
    vmask valid = vm_and(vi_lt(*px, vi_set1(t->x1)), vi_lt(*py, vi_set1(t->y1)));
    *r = dvr_camera_rays(&f->cam, *px, *py);
    vfloat t0, t1;
    dvr_clip_box(r, s->lo, s->hi, &t0, &t1);
    valid = vm_and(valid, vf_le(t0, t1));
    if (s->empty || vm_none(valid)) return 0;
    st->rays += (uint64_t)vm_popcnt(valid);
    *ta = vf_select(valid, t0, vf_set1(1.0f));
    *tb = vf_select(valid, t1, vf_set1(-1.0f));
    dvr_lattice(*ta, *tb, f->dt, kf, kl);
    return 1;
}

#endif
