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


/* The start of a packet of rays at pixel block (x, y) for both RBF methods
 * (the BVH gather and the octree), in mode `mode` (f->mode, a constant): the
 * rays and their lattice range [kf, kl] inside the set's box. Returns 0
 * when the packet is finished here: no ray meets the box (the empty colour
 * is stored), or slice (its one sample per ray taken through the method's
 * probe and stored); 1 when the caller walks the lattice. */
static inline __attribute__((always_inline)) int rbf_packet_begin(const lc_krbf *s, const lc_kframe *f, int mode,
                                                                  const lc_ktile *t, int x, int y, const mprobe *probe,
                                                                  vint *px, vint *py, vray *r, vint *kf, vint *kl,
                                                                  vcolor *col, lc_kstats *st)
{
    dvr_packet_pixels(x, y, px, py);
    vmask valid = vm_and(vi_lt(*px, vi_set1(t->x1)), vi_lt(*py, vi_set1(t->y1)));
    *r = dvr_camera_rays(&f->cam, *px, *py);
    vfloat t0, t1;
    dvr_clip_box(r, s->lo, s->hi, &t0, &t1);
    valid = vm_and(valid, vf_le(t0, t1));
    if (s->empty || vm_none(valid)) {
        mode_store_as(t, mode, *px, *py, col, vf_set1(INFINITY));
        return 0;
    }
    st->rays += (uint64_t)vm_popcnt(valid);
    vfloat ta = vf_select(valid, t0, vf_set1(1.0f)), tb = vf_select(valid, t1, vf_set1(-1.0f));
    if (mode == LC_KMODE_SLICE) { /* no lattice: one sample per ray, in mode_finish */
        vfloat tmax = vf_set1(INFINITY);
        dvr_region_slice(f, r, &ta, &tmax);
        mode_slice(f, r, ta, tb, tmax, col);
        st->samples += (uint64_t)vm_popcnt(vf_gt(col->a, vf_zero()));
        mode_store_as(t, mode, *px, *py, col, mode_finish_as(f, mode, col, r, probe));
        return 0;
    }
    dvr_lattice(ta, tb, f->dt, kf, kl);
    dvr_region(f, r, mode == LC_KMODE_ISO, kf, kl);
    return 1;
}

#endif
