/* Ray generation, classification, shading and front-to-back blending shared
 * by every ray-casting kernel (particles, grids, RBF sets), straight from
 * SPEC.md. Include after lane/lane.h in a kernel translation unit. */
#ifndef LC_DVR_H
#define LC_DVR_H

#include "lane/lane.h"
#include "shared/kframe.h"
#include "dvr_rows.h"

typedef struct vray {
    vfloat ox, oy, oz;
    vfloat dx, dy, dz;
} vray;

/* The rays of pixels (px, py), SPEC.md "Camera and rays". */
static inline vray dvr_camera_rays(const lc_kcamera *c, vint px, vint py)
{
    vfloat u = vf_msub(vf_add(vi_to_vf(px), vf_set1(0.5f)), vf_set1(2.0f / (float)c->width), vf_set1(1.0f));
    vfloat v = vf_nmadd(vf_add(vi_to_vf(py), vf_set1(0.5f)), vf_set1(2.0f / (float)c->height), vf_set1(1.0f));
    vray r;
    if (c->ortho) {
        r.ox = vf_madd(u, vf_set1(c->right[0]), vf_madd(v, vf_set1(c->up[0]), vf_set1(c->eye[0])));
        r.oy = vf_madd(u, vf_set1(c->right[1]), vf_madd(v, vf_set1(c->up[1]), vf_set1(c->eye[1])));
        r.oz = vf_madd(u, vf_set1(c->right[2]), vf_madd(v, vf_set1(c->up[2]), vf_set1(c->eye[2])));
        r.dx = vf_set1(c->forward[0]);
        r.dy = vf_set1(c->forward[1]);
        r.dz = vf_set1(c->forward[2]);
    } else {
        vfloat dx = vf_madd(u, vf_set1(c->right[0]), vf_madd(v, vf_set1(c->up[0]), vf_set1(c->forward[0])));
        vfloat dy = vf_madd(u, vf_set1(c->right[1]), vf_madd(v, vf_set1(c->up[1]), vf_set1(c->forward[1])));
        vfloat dz = vf_madd(u, vf_set1(c->right[2]), vf_madd(v, vf_set1(c->up[2]), vf_set1(c->forward[2])));
        /* unfused products and exact division rather than rsqrt: directions must
           agree across targets to the bit (vf_madd) */
        vfloat inv = vf_div(vf_set1(1.0f), vf_sqrt(vf_madd(dx, dx, vf_madd(dy, dy, vf_mul(dz, dz)))));
        r.ox = vf_set1(c->eye[0]);
        r.oy = vf_set1(c->eye[1]);
        r.oz = vf_set1(c->eye[2]);
        r.dx = vf_mul(dx, inv);
        r.dy = vf_mul(dy, inv);
        r.dz = vf_mul(dz, inv);
    }
    return r;
}

/* 1/d with zero (and tiny) components replaced by 1e-30, so slab tests never
 * form 0 * inf = NaN for axis-aligned rays whose origin lies on a slab plane. */
static inline vfloat dvr_inv_dir(vfloat d)
{
    vfloat tiny = vf_set1(1e-30f);
    d = vf_select(vf_lt(vf_abs(d), tiny), tiny, d);
    return vf_div(vf_set1(1.0f), d);
}

/* Slab test with inverse directions against a box grown by g on every side:
 * entry tn and exit tf (tn > tf: miss). Not clipped to t >= 0. */
static inline void dvr_slab(vfloat ox, vfloat oy, vfloat oz, vfloat ix, vfloat iy, vfloat iz, const float lo[3],
                            const float hi[3], float g, vfloat *tn, vfloat *tf)
{
    vfloat ax = vf_mul(vf_sub(vf_set1(lo[0] - g), ox), ix), bx = vf_mul(vf_sub(vf_set1(hi[0] + g), ox), ix);
    vfloat ay = vf_mul(vf_sub(vf_set1(lo[1] - g), oy), iy), by = vf_mul(vf_sub(vf_set1(hi[1] + g), oy), iy);
    vfloat az = vf_mul(vf_sub(vf_set1(lo[2] - g), oz), iz), bz = vf_mul(vf_sub(vf_set1(hi[2] + g), oz), iz);
    *tn = vf_max(vf_max(vf_min(ax, bx), vf_min(ay, by)), vf_min(az, bz));
    *tf = vf_min(vf_min(vf_max(ax, bx), vf_max(ay, by)), vf_max(az, bz));
}

/* Rays against a box, t clipped to [0, inf). Lanes that miss get t0 > t1. */
static inline void dvr_clip_box(const vray *r, const float lo[3], const float hi[3], vfloat *t0, vfloat *t1)
{
    vfloat n, f;
    dvr_slab(r->ox, r->oy, r->oz, dvr_inv_dir(r->dx), dvr_inv_dir(r->dy), dvr_inv_dir(r->dz), lo, hi, 0.0f, &n, &f);
    n = vf_max(n, vf_zero());
    /* belt and braces: a NaN must never open the interval */
    vmask ok = vm_and(vf_eq(n, n), vf_eq(f, f));
    *t0 = vf_select(ok, n, vf_set1(1.0f));
    *t1 = vf_select(ok, f, vf_set1(-1.0f));
}

/* First and last lattice index k (t_k = k dt) inside [t0, t1]; empty if kf > kl.
 * Division (not a reciprocal) so every target picks the same k. */
static inline void dvr_lattice(vfloat t0, vfloat t1, float dt, vint *kf, vint *kl)
{
    vmask hit = vf_le(t0, t1);
    vfloat a = vf_floor(vf_div(t0, vf_set1(dt)));
    a = vf_select(vf_lt(vf_mul(a, vf_set1(dt)), t0), vf_add(a, vf_set1(1.0f)), a); /* ceil */
    vfloat b = vf_floor(vf_div(t1, vf_set1(dt)));
    /* clamped on both sides before the conversion: a missed ray's slab times may be
       +-1e30 (axis-parallel orthographic rays), which no int holds (UB on the scalar target) */
    a = vf_max(vf_min(a, vf_set1(LC_KLATTICE_MAX)), vf_set1(-LC_KLATTICE_MAX));
    b = vf_max(vf_min(b, vf_set1(LC_KLATTICE_MAX)), vf_set1(-LC_KLATTICE_MAX));
    *kf = vi_select(hit, vf_to_vi(a), vi_set1(1));
    *kl = vi_select(hit, vf_to_vi(b), vi_set1(0));
}

/* The first lattice index k with k dt >= t (t may be +-inf), clamped to
 * [-1, LC_KLATTICE_MAX + 2]; both regions beside a split plane call it on
 * the same t, so they agree on the sample where one ends and the next begins. */
static inline vint dvr_region_k(vfloat t, float dt)
{
    vfloat x = vf_min(vf_max(vf_div(t, vf_set1(dt)), vf_set1(-1.0f)), vf_set1(LC_KLATTICE_MAX + 1.0f));
    vfloat a = vf_floor(x);
    a = vf_select(vf_lt(vf_mul(a, vf_set1(dt)), t), vf_add(a, vf_set1(1.0f)), a);
    return vf_to_vi(a);
}

/* The ray's part inside the frame's region (SPEC.md "Regions"): the
 * half-open interval [t_in, t_out) of its slab test against the region's
 * cell. Returns t_in and t_out (unclipped; t_in >= t_out: none). */
static inline void dvr_region_t(const lc_kframe *f, const vray *r, vfloat *tin, vfloat *tout)
{
    dvr_slab(r->ox, r->oy, r->oz, dvr_inv_dir(r->dx), dvr_inv_dir(r->dy), dvr_inv_dir(r->dz), f->region.lo,
             f->region.hi, 0.0f, tin, tout);
}

/* Narrows a ray's lattice range [kf, kl] (inside the data's box) to the
 * samples k dt in [t_in, t_out) of the frame's region; nothing without one.
 * iso also keeps the sample before the region's first (`pairs`), so the
 * region owning sample k sees the step from k - 1 to k: every step of the
 * ray belongs to exactly one region. */
static inline void dvr_region(const lc_kframe *f, const vray *r, int pairs, vint *kf, vint *kl)
{
    if (!f->has_region) return;
    vfloat tin, tout;
    dvr_region_t(f, r, &tin, &tout);
    vint a = dvr_region_k(tin, f->dt), b = vi_sub(dvr_region_k(tout, f->dt), vi_set1(1));
    vint ap = pairs ? vi_sub(a, vi_set1(1)) : a;
    /* an empty part stays empty when iso widens it */
    vmask none = vi_gt(a, b);
    *kf = vi_select(none, vi_set1(1), vi_max(*kf, ap));
    *kl = vi_select(none, vi_set1(0), vi_min(*kl, b));
}

/* slice: the plane points the region takes are those with t in [t_in,
 * t_out): raises *t0 to t_in and lowers *tmax (a strict bound) to t_out. */
static inline void dvr_region_slice(const lc_kframe *f, const vray *r, vfloat *t0, vfloat *tmax)
{
    if (!f->has_region) return;
    vfloat tin, tout;
    dvr_region_t(f, r, &tin, &tout);
    *t0 = vf_max(*t0, tin);
    *tmax = vf_min(*tmax, tout);
}

/* The normalised value v = (phi - lo) / (hi - lo), unclamped. */
static inline vfloat dvr_normalise(const lc_ktf *tf, vfloat phi)
{
    return vf_mul(vf_sub(phi, vf_set1(tf->lo)), vf_set1(tf->inv_range));
}

/* Transfer function lookup at normalised value v (clamped to [0, 1]). */
static inline void dvr_classify_v(const lc_ktf *tf, vfloat v, vfloat *r, vfloat *g, vfloat *b, vfloat *tau)
{
    v = vf_clamp(v, vf_zero(), vf_set1(1.0f));
    vfloat x = vf_mul(v, vf_set1((float)(LC_TF_TABLE_SIZE - 1)));
    vfloat xf = vf_min(vf_floor(x), vf_set1((float)(LC_TF_TABLE_SIZE - 2)));
    vfloat w = vf_sub(x, xf);
    vint i = vi_sll(vf_to_vi(xf), 2);
    const float *t = tf->rgbt;
    vfloat r0 = vf_gather(t, i), g0 = vf_gather(t + 1, i), b0 = vf_gather(t + 2, i), a0 = vf_gather(t + 3, i);
    vfloat r1 = vf_gather(t + 4, i), g1 = vf_gather(t + 5, i), b1 = vf_gather(t + 6, i), a1 = vf_gather(t + 7, i);
    *r = vf_lerp(r0, r1, w);
    *g = vf_lerp(g0, g1, w);
    *b = vf_lerp(b0, b1, w);
    *tau = vf_lerp(a0, a1, w);
}

/* Transfer function lookup: rgb and extinction tau at value phi. */
static inline void dvr_classify(const lc_ktf *tf, vfloat phi, vfloat *r, vfloat *g, vfloat *b, vfloat *tau)
{
    dvr_classify_v(tf, dvr_normalise(tf, phi), r, g, b, tau);
}

/* SPEC.md "Shading": headlight, n = -grad/|grad|, l = -dir, h = normalize(l - dir).
 * With a headlight h = l, so |n.h| = |n.l|. Unshaded where |grad| < grad_eps:
 * returns the lit lanes (none: *k and *spec unset), the diffuse factor
 * k = ka + kd |n.l| and the specular term ks |n.h|^p (0 unless phong). */
static inline __attribute__((always_inline)) vmask dvr_light(const lc_kframe *f, float grad_eps, const vray *ray, vfloat gx, vfloat gy, vfloat gz,
                                                              vfloat *k, vfloat *spec)
{
    vfloat g2 = vf_fma(gx, gx, vf_fma(gy, gy, vf_mul(gz, gz)));
    vfloat glen = vf_sqrt(g2);
    vmask lit = vf_ge(glen, vf_set1(grad_eps));
    if (vm_none(lit)) return lit;
    /* n.l = (-grad/|grad|) . (-dir) = grad.dir / |grad| */
    vfloat ndl = vf_abs(vf_div(vf_fma(gx, ray->dx, vf_fma(gy, ray->dy, vf_mul(gz, ray->dz))), vf_max(glen, vf_set1(1e-30f))));
    *k = vf_fma(vf_set1(f->kd), ndl, vf_set1(f->ka));
    *spec = vf_zero();
    if (f->shade == LC_KSHADE_PHONG) *spec = vf_mul(vf_set1(f->ks), vf_powi(ndl, f->phong_exp));
    return lit;
}

/* Shades a sample's colour in place: rgb k + spec on the lit lanes. */
static inline void dvr_shade(const lc_kframe *f, float grad_eps, const vray *ray, vfloat gx, vfloat gy, vfloat gz, vfloat *r,
                             vfloat *g, vfloat *b)
{
    if (f->shade == LC_KSHADE_NONE) return;
    vfloat k, spec;
    vmask lit = dvr_light(f, grad_eps, ray, gx, gy, gz, &k, &spec);
    if (vm_none(lit)) return;
    *r = vf_select(lit, vf_fma(*r, k, spec), *r);
    *g = vf_select(lit, vf_fma(*g, k, spec), *g);
    *b = vf_select(lit, vf_fma(*b, k, spec), *b);
}

typedef struct vcolor {
    vfloat r, g, b, a;
} vcolor;

/* SPEC.md: a = 1 - exp(-tau dt); C += (1 - A) a rgb; A += (1 - A) a, for the
 * lanes in m. */
static inline void dvr_blend(vcolor *c, vmask m, vfloat r, vfloat g, vfloat b, vfloat tau, float dt)
{
    vfloat a = vf_sub(vf_set1(1.0f), vf_exp(vf_mul(tau, vf_set1(-dt))));
    vfloat w = vf_mul(vf_sub(vf_set1(1.0f), c->a), a);
    w = vf_select(m, w, vf_zero());
    c->r = vf_fma(w, r, c->r);
    c->g = vf_fma(w, g, c->g);
    c->b = vf_fma(w, b, c->b);
    c->a = vf_add(c->a, w);
}

/* Classification for one step dt through the TF's step table (kframe.h
 * lc_ktf cls): opacity a and premultiplied colour (a r, a g, a b),
 * interpolated linearly between the entries like dvr_classify_v, with no exp
 * per sample; one 32-byte row load per lane (dvr_rows.h) instead of 8
 * gathers. It differs from a = 1 - exp(-tau dt) of the interpolated tau by
 * the interpolation of a instead of tau (tests/test_grid.c: <= 2e-4 on a
 * steep TF). */
static inline __attribute__((always_inline)) void dvr_classify_step(const lc_ktf *tf, vfloat phi, vfloat *pr,
                                                                    vfloat *pg, vfloat *pb, vfloat *a)
{
    vfloat v = vf_clamp(dvr_normalise(tf, phi), vf_zero(), vf_set1(1.0f));
    vfloat x = vf_mul(v, vf_set1((float)(LC_TF_TABLE_SIZE - 1)));
    vfloat xf = vf_min(vf_floor(x), vf_set1((float)(LC_TF_TABLE_SIZE - 2)));
    vfloat w = vf_sub(x, xf);
    vfloat e[8];
    dvr_rows8(tf->cls, vi_sll(vf_to_vi(xf), 2), e);
    *pr = vf_lerp(e[0], e[4], w);
    *pg = vf_lerp(e[1], e[5], w);
    *pb = vf_lerp(e[2], e[6], w);
    *a = vf_lerp(e[3], e[7], w);
}

/* Does any lane in m hold a value where the TF is not exactly transparent?
 * (Where none does, a step-table sample adds exactly nothing.) */
static inline vmask dvr_visible(const lc_ktf *tf, vmask m, vfloat phi)
{
    return vm_and(m, vf_gt(dvr_normalise(tf, phi), vf_set1(tf->cls_vzero)));
}

/* SPEC.md "Shading" on a premultiplied sample (a r, a g, a b) of opacity a:
 * rgb k + spec premultiplies to (a rgb) k + a spec. Same formulas as
 * dvr_shade. */
static inline __attribute__((always_inline)) void dvr_shade_pm(const lc_kframe *f, float grad_eps, const vray *ray,
                                                               vfloat gx, vfloat gy, vfloat gz, vfloat a, vfloat *r,
                                                               vfloat *g, vfloat *b)
{
    vfloat k, spec;
    vmask lit = dvr_light(f, grad_eps, ray, gx, gy, gz, &k, &spec);
    if (vm_none(lit)) return;
    vfloat as = vf_mul(a, spec);
    *r = vf_select(lit, vf_fma(*r, k, as), *r);
    *g = vf_select(lit, vf_fma(*g, k, as), *g);
    *b = vf_select(lit, vf_fma(*b, k, as), *b);
}

/* SPEC.md's blend of a premultiplied sample on the lanes in m:
 * C += (1 - A) (a rgb), A += (1 - A) a. */
static inline void dvr_blend_pm(vcolor *c, vmask m, vfloat pr, vfloat pg, vfloat pb, vfloat a)
{
    vfloat w = vf_select(m, vf_sub(vf_set1(1.0f), c->a), vf_zero());
    c->r = vf_fma(w, pr, c->r);
    c->g = vf_fma(w, pg, c->g);
    c->b = vf_fma(w, pb, c->b);
    c->a = vf_fma(w, a, c->a);
}

/* Pixel coordinates of lane-width packets: lanes laid out as a small 2D block
 * (1x1, 2x2, 4x2, 4x4) so a packet's rays stay coherent. */
#if LC_W == 1
#define DVR_PW 1
#define DVR_PH 1
#elif LC_W == 4
#define DVR_PW 2
#define DVR_PH 2
#elif LC_W == 8
#define DVR_PW 4
#define DVR_PH 2
#else
#define DVR_PW 4
#define DVR_PH 4
#endif

static inline void dvr_packet_pixels(int x, int y, vint *px, vint *py)
{
    vint lane = vi_iota();
    *px = vi_add(vi_set1(x), vi_and(lane, vi_set1(DVR_PW - 1)));
#if DVR_PW == 1
    *py = vi_set1(y);
#elif DVR_PW == 2
    *py = vi_add(vi_set1(y), vi_srl(lane, 1));
#else
    *py = vi_add(vi_set1(y), vi_srl(lane, 2));
#endif
}

/* The (C, A) the rays of the packet at pixel block (x, y) start from:
 * zero, or with t->carry what the tile holds there (lc_ktile). Lanes
 * outside the tile start at zero and are never stored. */
static inline vcolor dvr_start(const lc_ktile *t, int x, int y)
{
    vcolor c = {vf_zero(), vf_zero(), vf_zero(), vf_zero()};
    if (!t->carry) return c;
    float v[4][LC_W];
    for (int l = 0; l < LC_W; l++) {
        int px = x + l % DVR_PW, py = y + l / DVR_PW; /* dvr_packet_pixels */
        if (px >= t->x1 || py >= t->y1) {
            v[0][l] = v[1][l] = v[2][l] = v[3][l] = 0.0f;
            continue;
        }
        const float *o = t->rgba + ((size_t)py * (size_t)t->stride + (size_t)px) * 4;
        for (int j = 0; j < 4; j++) v[j][l] = o[j];
    }
    c.r = vf_load(v[0]), c.g = vf_load(v[1]), c.b = vf_load(v[2]), c.a = vf_load(v[3]);
    return c;
}

/* Writes premultiplied (C, A) of the lanes inside the tile, lane by lane. */
static inline void dvr_store_lanes(const lc_ktile *t, vint px, vint py, const vcolor *c)
{
    for (int l = 0; l < LC_W; l++) {
        int x = vi_lane(px, l), y = vi_lane(py, l);
        if (x >= t->x1 || y >= t->y1) continue;
        float *o = t->rgba + ((size_t)y * (size_t)t->stride + (size_t)x) * 4;
        o[0] = vf_lane(c->r, l);
        o[1] = vf_lane(c->g, l);
        o[2] = vf_lane(c->b, l);
        o[3] = vf_lane(c->a, l);
    }
}

/* Writes premultiplied (C, A) of the lanes inside the tile; px, py as
 * dvr_packet_pixels gives them (every kind's packets). Where the packet's
 * block lies inside the tile, lane l is pixel (x + l % DVR_PW, y + l /
 * DVR_PW), so a 4x4 transpose of (r, g, b, a) per 128-bit part gives each
 * row's DVR_PW = 4 pixels as 16 consecutive floats: whole-row vector stores.
 * The lane-by-lane store (dvr_store_lanes) was ~20 % of grid_bvh's own time
 * on a 1024^2 embryo medium frame (64 lane extractions and scalar stores per
 * packet, stalled on the image's lines). Same bytes. */
static inline __attribute__((always_inline)) void dvr_store(const lc_ktile *t, vint px, vint py, const vcolor *c)
{
#if defined(LC_TARGET_AVX512) && LC_W == 16 && DVR_PW == 4 && DVR_PH == 4
    int x = vi_lane(px, 0), y = vi_lane(py, 0);
    if (x + DVR_PW <= t->x1 && y + DVR_PH <= t->y1) {
        __m512 t0 = _mm512_unpacklo_ps(c->r, c->g), t1 = _mm512_unpackhi_ps(c->r, c->g);
        __m512 t2 = _mm512_unpacklo_ps(c->b, c->a), t3 = _mm512_unpackhi_ps(c->b, c->a);
        /* per 128-bit part j (row j): u_k = pixel k's (r, g, b, a) */
        __m512 u0 = _mm512_castpd_ps(_mm512_unpacklo_pd(_mm512_castps_pd(t0), _mm512_castps_pd(t2)));
        __m512 u1 = _mm512_castpd_ps(_mm512_unpackhi_pd(_mm512_castps_pd(t0), _mm512_castps_pd(t2)));
        __m512 u2 = _mm512_castpd_ps(_mm512_unpacklo_pd(_mm512_castps_pd(t1), _mm512_castps_pd(t3)));
        __m512 u3 = _mm512_castpd_ps(_mm512_unpackhi_pd(_mm512_castps_pd(t1), _mm512_castps_pd(t3)));
        __m512 s0 = _mm512_shuffle_f32x4(u0, u1, 0x44), s1 = _mm512_shuffle_f32x4(u0, u1, 0xee);
        __m512 s2 = _mm512_shuffle_f32x4(u2, u3, 0x44), s3 = _mm512_shuffle_f32x4(u2, u3, 0xee);
        float *o = t->rgba + ((size_t)y * (size_t)t->stride + (size_t)x) * 4;
        size_t row = (size_t)t->stride * 4;
        _mm512_storeu_ps(o, _mm512_shuffle_f32x4(s0, s2, 0x88));
        _mm512_storeu_ps(o + row, _mm512_shuffle_f32x4(s0, s2, 0xdd));
        _mm512_storeu_ps(o + 2 * row, _mm512_shuffle_f32x4(s1, s3, 0x88));
        _mm512_storeu_ps(o + 3 * row, _mm512_shuffle_f32x4(s1, s3, 0xdd));
        return;
    }
#elif (defined(LC_TARGET_AVX2) || defined(LC_TARGET_AVX512_8)) && LC_W == 8 && DVR_PW == 4 && DVR_PH == 2
    int x = vi_lane(px, 0), y = vi_lane(py, 0);
    if (x + DVR_PW <= t->x1 && y + DVR_PH <= t->y1) {
        __m256 t0 = _mm256_unpacklo_ps(c->r, c->g), t1 = _mm256_unpackhi_ps(c->r, c->g);
        __m256 t2 = _mm256_unpacklo_ps(c->b, c->a), t3 = _mm256_unpackhi_ps(c->b, c->a);
        /* per 128-bit half j (row j): u_k = pixel k's (r, g, b, a) */
        __m256 u0 = _mm256_shuffle_ps(t0, t2, 0x44), u1 = _mm256_shuffle_ps(t0, t2, 0xee);
        __m256 u2 = _mm256_shuffle_ps(t1, t3, 0x44), u3 = _mm256_shuffle_ps(t1, t3, 0xee);
        float *o = t->rgba + ((size_t)y * (size_t)t->stride + (size_t)x) * 4;
        size_t row = (size_t)t->stride * 4;
        _mm256_storeu_ps(o, _mm256_permute2f128_ps(u0, u1, 0x20));
        _mm256_storeu_ps(o + 8, _mm256_permute2f128_ps(u2, u3, 0x20));
        _mm256_storeu_ps(o + row, _mm256_permute2f128_ps(u0, u1, 0x31));
        _mm256_storeu_ps(o + row + 8, _mm256_permute2f128_ps(u2, u3, 0x31));
        return;
    }
#endif
    dvr_store_lanes(t, px, py, c);
}


#endif
