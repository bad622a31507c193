/* What both particle methods share (Knoll et al. 2014): the Gaussian and its
 * support test with one arithmetic (so coherent and direct differ only by
 * summation order), the ray-centre distance, the grown node boxes, opaque
 * spheres (§5.2), and the per-vector ray setup and finish. Included by
 * kernels/particles.c and kernels/particles_coherent.c. */
#ifndef LC_PARTICLES_COMMON_H
#define LC_PARTICLES_COMMON_H

#include <math.h>
#include "mode.h"
#include "shared/kparticles.h"
#include "shared/ktable.h"
#include "kernels.h"
#include "particles_sph.h"

/* Offset of p from particle centre c and the truncation test d2 < R2 = (sigma r)^2. */
static inline vfloat sample_d2(vfloat px, vfloat py, vfloat pz, float cx, float cy, float cz, float r2s, vmask m,
                               vmask *inside, vfloat *ex, vfloat *ey, vfloat *ez)
{
    *ex = vf_sub(px, vf_set1(cx));
    *ey = vf_sub(py, vf_set1(cy));
    *ez = vf_sub(pz, vf_set1(cz));
    vfloat d2 = vf_madd(*ex, *ex, vf_madd(*ey, *ey, vf_mul(*ez, *ez))); /* the same bits on every target */
    *inside = vm_and(m, vf_lt(d2, vf_set1(r2s)));
    return d2;
}

/* kappa k_i exp(-d2 / (2 r_i^2)) (paper eq. 2), zero outside the support. */
static inline vfloat gaussian(vfloat d2, float nir, float kk, vmask inside)
{
    return vf_select(inside, vf_mul(vf_set1(kk), vf_exp(vf_mul(d2, vf_set1(nir)))), vf_zero());
}

/* Squared distance of a centre from a ray: |oc - tc d|^2 with tc = oc.d. Not
 * |oc|^2 - tc^2, which cancels catastrophically for a distant eye (|oc|^2 ~ 1e4
 * against R^2 ~ 1) and wrongly drops rays that do pass within the support. */
static inline vfloat perp2(vfloat ocx, vfloat ocy, vfloat ocz, vfloat dx, vfloat dy, vfloat dz, vfloat tc)
{
    vfloat qx = vf_nmadd(tc, dx, ocx), qy = vf_nmadd(tc, dy, ocy), qz = vf_nmadd(tc, dz, ocz);
    return vf_madd(qx, qx, vf_madd(qy, qy, vf_mul(qz, qz)));
}

/* The Gaussian along a ray without exp per sample (SPEC.md "Fields"): with
 * u = t - tc and d2 = d_perp^2, g(u) = kk exp(nir (d2 + u^2)) steps by
 * g(u + dt) = g(u) q(u), q(u + dt) = q(u) c, c = exp(2 nir dt^2). Each run
 * of PG_ANCHOR samples starts from a direct evaluation of g and q (two exps)
 * and c is rounded once from double, so a term drifts by at most ~PG_ANCHOR
 * roundings of q and PG_ANCHOR^2 / 2 of c: measured up to 5.2e-6 relative
 * (tests/test_particles_recurrence.c checks 1e-5 on every target). */
#define PG_ANCHOR 8

typedef struct pgauss_consts {
    float nir, kk, nirdt, dt;
    vfloat c;
} pgauss_consts;

/* c = exp(2 nir dt^2), rounded once from double (kparticles.h). */
static inline float pgauss_c(float nir, float dt) { return lc_kparticles_ratio(nir, dt); }

static inline pgauss_consts pgauss_consts_make(float nir, float kk, float dt, float c)
{
    pgauss_consts gc;
    gc.nir = nir, gc.kk = kk, gc.nirdt = nir * dt, gc.dt = dt;
    gc.c = vf_set1(c);
    return gc;
}

/* g and q at offset u from the centre's foot tc (lanes outside m: g = 0). */
static inline void pgauss_anchor(const pgauss_consts *gc, vfloat d2, vfloat u, vmask m, vfloat *g, vfloat *q)
{
    vfloat a = vf_madd(u, u, d2);
    *g = vf_select(m, vf_mul(vf_set1(gc->kk), vf_exp(vf_mul(a, vf_set1(gc->nir)))), vf_zero());
    *q = vf_exp(vf_mul(vf_set1(gc->nirdt), vf_fma(u, vf_set1(2.0f), vf_set1(gc->dt))));
}

static inline void pgauss_step(const pgauss_consts *gc, vfloat *g, vfloat *q)
{
    *g = vf_mul(*g, *q);
    *q = vf_mul(*q, gc->c);
}

/* Test hook (tests/test_particles_recurrence.c): the Gaussian at lattice
 * samples ka..kb of LC_W rays (perpendicular distances d2[l], centre feet
 * tc[l]), stepped as deposit steps it with a direct anchor every `period`
 * samples (0: PG_ANCHOR), into out[(k - ka) * LC_W + l]. Returns the period. */
int LC_KFN(lc_pgauss_probe)(const float *d2, const float *tc, float nir, float kk, float dt, int ka, int kb,
                            int period, float *out);

/* Boxes grow a little more than sigma * rmax so float round-off in the slab
 * test never drops a sample that lies within the truncation radius. */
static inline float grow(float sigma_r) { return sigma_r * 1.0001f + 1e-6f; }

/* Transparent-space skipping (issue 8): can no particle below node n change
 * a dvr sample? The host marks such nodes per frame (host/kinds/particles.c
 * clear_nodes): every field present below the node is bounded by |kappa|
 * times its node bound at every sample the node's particles reach, and the
 * frame's TF is fully transparent up to that value. Samples there are
 * transparent whatever else is added to them, so skipping changes no pixel. */
static inline int node_clear(const lc_kparticles *s, int32_t n) { return s->node_clear && s->node_clear[n]; }

/* Do samples that no particle reached (they hold exactly s->bias) blend to
 * exactly nothing in this frame, so a method may skip them? bias 0: the
 * frame's zero_transparent (tau(0) = 0, dvr); otherwise what the host found
 * for tau(bias) (kparticles.h). */
static inline int skip_base(const lc_kparticles *s, const lc_kframe *f)
{
    return s->bias == 0.0f ? f->zero_transparent : s->bias_clear;
}

/* Every field (and, with grad, its gradient) at the points p of the lanes in m,
 * through the BVH: the direct method's per-sample gather, starting from the
 * bias (0 for particles). Returns whether any particle contributed. sph (a
 * constant): s->kernel is an SPH kernel (particles_sph.h), else the Gaussian. */
static inline __attribute__((always_inline)) int gather_fields_as(const lc_kparticles *s, vfloat px, vfloat py,
                                                                  vfloat pz, vmask m, int grad, int skip,
                                                                  int32_t *stack, vfloat *phi, vfloat *gx,
                                                                  vfloat *gy, vfloat *gz, lc_kstats *st, int sph,
                                                                  int norm)
{
    /* norm (a constant, SPH only): the denominators sum kappa kn_i W and their gradients */
    vfloat den[LC_KMAX_FIELDS], dx[LC_KMAX_FIELDS], dy[LC_KMAX_FIELDS], dz[LC_KMAX_FIELDS];
    for (int fi = 0; fi < s->nfields; fi++) phi[fi] = vf_set1(s->bias), gx[fi] = gy[fi] = gz[fi] = vf_zero();
    if (norm)
        for (int fi = 0; fi < s->nfields; fi++) den[fi] = dx[fi] = dy[fi] = dz[fi] = vf_zero();
    if (s->nnodes == 0) return 0;
    int sp = 0, found = 0;
    uint64_t nodes = 0, leaves = 0, evals = 0;
    stack[sp++] = 0;
    while (sp > 0) {
        int32_t n = stack[--sp];
        const lc_kpnode *node = &s->nodes[n];
        float g = grow(s->sigma * s->node_rmax[n]);
        nodes++;
        if (skip && node_clear(s, n)) continue; /* dvr samples only: transparent whatever it adds */
        vmask in = vm_and(m, vm_and(vm_and(vf_ge(px, vf_set1(node->lo[0] - g)), vf_le(px, vf_set1(node->hi[0] + g))),
                                    vm_and(vm_and(vf_ge(py, vf_set1(node->lo[1] - g)), vf_le(py, vf_set1(node->hi[1] + g))),
                                           vm_and(vf_ge(pz, vf_set1(node->lo[2] - g)), vf_le(pz, vf_set1(node->hi[2] + g))))));
        if (vm_none(in)) continue;
        if (node->count == 0) {
            stack[sp++] = node->first + 1;
            stack[sp++] = node->first;
            continue;
        }
        leaves++;
        for (int32_t i = node->first; i < node->first + node->count; i++) {
            float rs = s->sigma * s->r[i];
            vmask inside;
            vfloat ex, ey, ez;
            vfloat d2 = sample_d2(px, py, pz, s->px[i], s->py[i], s->pz[i], rs * rs, in, &inside, &ex, &ey, &ez);
            if (vm_none(inside)) continue;
            found = 1;
            evals += (uint64_t)vm_popcnt(inside);
            int fi = s->field[i];
            vfloat p, gp = vf_zero();
            if (sph && norm) { /* one shape evaluation, two amplitudes */
                sph_consts sc = sph_consts_make(s->r[i], s->kappa * s->kn[i], s->knorm);
                vfloat gq = vf_zero(), q = sph_term(s->kernel, &sc, d2, inside, grad ? &gq : NULL);
                float a = s->kn[i] != 0.0f ? s->k[i] / s->kn[i] : 0.0f; /* A_i */
                p = vf_mul(q, vf_set1(a)), gp = vf_mul(gq, vf_set1(a));
                den[fi] = vf_add(den[fi], q);
                if (grad) {
                    dx[fi] = vf_fma(ex, gq, dx[fi]);
                    dy[fi] = vf_fma(ey, gq, dy[fi]);
                    dz[fi] = vf_fma(ez, gq, dz[fi]);
                }
            } else if (sph) {
                sph_consts sc = sph_consts_make(s->r[i], s->kappa * s->k[i], s->knorm);
                p = sph_term(s->kernel, &sc, d2, inside, grad ? &gp : NULL);
            } else {
                p = gaussian(d2, s->neg_inv_2r2[i], s->kappa * s->k[i], inside);
                gp = vf_mul(p, vf_set1(2.0f * s->neg_inv_2r2[i])); /* grad phi_i = -(p - c) / r^2 phi_i */
            }
            phi[fi] = vf_add(phi[fi], p);
            if (grad) {
                gx[fi] = vf_fma(ex, gp, gx[fi]);
                gy[fi] = vf_fma(ey, gp, gy[fi]);
                gz[fi] = vf_fma(ez, gp, gz[fi]);
            }
        }
    }
    if (st) st->nodes += nodes, st->leaves += leaves, st->kernel_evals += evals;
    if (norm) /* A = N / D, grad A = (grad N - A grad D) / D; 0 where D = 0 */
        for (int fi = 0; fi < s->nfields; fi++) {
            vmask pos = vf_gt(den[fi], vf_zero());
            vfloat inv = vf_div(vf_set1(1.0f), vf_select(pos, den[fi], vf_set1(1.0f)));
            vfloat a = vf_select(pos, vf_mul(phi[fi], inv), vf_zero());
            phi[fi] = a;
            if (grad) {
                gx[fi] = vf_select(pos, vf_mul(vf_nmadd(a, dx[fi], gx[fi]), inv), vf_zero());
                gy[fi] = vf_select(pos, vf_mul(vf_nmadd(a, dy[fi], gy[fi]), inv), vf_zero());
                gz[fi] = vf_select(pos, vf_mul(vf_nmadd(a, dz[fi], gz[fi]), inv), vf_zero());
            }
        }
    return found;
}

/* gather_fields_as for the SPH kernels, out of line (the Gaussian's callers
 * compile as they did). */
static __attribute__((noinline, unused)) int gather_fields_sph(const lc_kparticles *s, vfloat px, vfloat py,
                                                               vfloat pz, vmask m, int grad, int skip,
                                                               int32_t *stack, vfloat *phi, vfloat *gx, vfloat *gy,
                                                               vfloat *gz, lc_kstats *st)
{
    return gather_fields_as(s, px, py, pz, m, grad, skip, stack, phi, gx, gy, gz, st, 1, 0);
}

/* The normalised SPH interpolant (s->normalise), out of line too; no node
 * is skipped (the host marks none: a weighted mean is not bounded by the
 * node sums). */
static __attribute__((noinline, unused)) int gather_fields_norm(const lc_kparticles *s, vfloat px, vfloat py,
                                                                vfloat pz, vmask m, int grad, int32_t *stack,
                                                                vfloat *phi, vfloat *gx, vfloat *gy, vfloat *gz,
                                                                lc_kstats *st)
{
    return gather_fields_as(s, px, py, pz, m, grad, 0, stack, phi, gx, gy, gz, st, 1, 1);
}

static inline int gather_fields(const lc_kparticles *s, vfloat px, vfloat py, vfloat pz, vmask m, int grad,
                                int skip, int32_t *stack, vfloat *phi, vfloat *gx, vfloat *gy, vfloat *gz, lc_kstats *st)
{
    if (s->kernel != LC_KSPH_GAUSSIAN) {
        if (s->normalise) return gather_fields_norm(s, px, py, pz, m, grad, stack, phi, gx, gy, gz, st);
        return gather_fields_sph(s, px, py, pz, m, grad, skip, stack, phi, gx, gy, gz, st);
    }
    return gather_fields_as(s, px, py, pz, m, grad, skip, stack, phi, gx, gy, gz, st, 0, 0);
}

/* The particles' point evaluation for the modes (mode.h mprobe): field fi
 * through gather_fields. */
typedef struct pprobe {
    const lc_kparticles *s;
    int32_t *stack;
    lc_kstats *st;
} pprobe;

static inline vfloat particles_probe(const void *ctx, int fi, vfloat x, vfloat y, vfloat z, vmask m, vgrad *g)
{
    const pprobe *p = ctx;
    vfloat phi[LC_KMAX_FIELDS], gx[LC_KMAX_FIELDS], gy[LC_KMAX_FIELDS], gz[LC_KMAX_FIELDS];
    gather_fields(p->s, x, y, z, m, g != NULL, 0, p->stack, phi, gx, gy, gz, p->st);
    if (g) g->x = gx[fi], g->y = gy[fi], g->z = gz[fi];
    return phi[fi];
}

/* Opaque spheres (paper §5.2): nearest hit of radius scale * r_i through the
 * same BVH, shaded with the particle's TF colour and the headlight. */
static inline __attribute__((always_inline)) void trace_spheres(const lc_kparticles *s, const lc_kframe *f,
                                                                const vray *ray, vmask valid, int32_t *stack,
                                                                vfloat *thit, vcolor *surf, lc_kstats *st)
{
    vfloat inf = vf_set1(3.0e38f);
    vfloat best = inf, nx = vf_zero(), ny = vf_zero(), nz = vf_zero(), sr = vf_zero(), sg = vf_zero(), sb = vf_zero();
    vfloat ix = dvr_inv_dir(ray->dx), iy = dvr_inv_dir(ray->dy), iz = dvr_inv_dir(ray->dz);
    float scale = s->sphere_scale;
    int sp = 0;
    stack[sp++] = 0;
    while (sp > 0) {
        int32_t n = stack[--sp];
        const lc_kpnode *node = &s->nodes[n];
        vfloat tn, tf;
        dvr_slab(ray->ox, ray->oy, ray->oz, ix, iy, iz, node->lo, node->hi, grow(scale * s->node_rmax[n]), &tn, &tf);
        vmask hit = vm_and(valid, vm_and(vf_le(vf_max(tn, vf_zero()), tf), vf_lt(tn, best)));
        st->nodes++;
        if (vm_none(hit)) continue;
        if (node->count == 0) {
            stack[sp++] = node->first;
            stack[sp++] = node->first + 1;
            continue;
        }
        st->leaves++;
        for (int32_t i = node->first; i < node->first + node->count; i++) {
            float rr = scale * s->r[i];
            vfloat ocx = vf_sub(vf_set1(s->px[i]), ray->ox), ocy = vf_sub(vf_set1(s->py[i]), ray->oy),
                   ocz = vf_sub(vf_set1(s->pz[i]), ray->oz);
            vfloat tc = vf_madd(ocx, ray->dx, vf_madd(ocy, ray->dy, vf_mul(ocz, ray->dz)));
            vfloat d2 = perp2(ocx, ocy, ocz, ray->dx, ray->dy, ray->dz, tc);
            vfloat h2 = vf_sub(vf_set1(rr * rr), d2);
            vmask m = vm_and(hit, vf_ge(h2, vf_zero()));
            if (vm_none(m)) continue;
            vfloat h = vf_sqrt(vf_max(h2, vf_zero()));
            vfloat t = vf_sub(tc, h);
            t = vf_select(vf_gt(t, vf_zero()), t, vf_add(tc, h)); /* eye inside: the far side */
            m = vm_and(m, vm_and(vf_gt(t, vf_zero()), vf_lt(t, best)));
            if (vm_none(m)) continue;
            best = vf_select(m, t, best);
            vfloat inv = vf_set1(1.0f / rr);
            nx = vf_select(m, vf_mul(vf_fms(ray->dx, t, ocx), inv), nx);
            ny = vf_select(m, vf_mul(vf_fms(ray->dy, t, ocy), inv), ny);
            nz = vf_select(m, vf_mul(vf_fms(ray->dz, t, ocz), inv), nz);
            vfloat r, g, b, tau;
            dvr_classify(&f->tf[s->field[i]], vf_set1(s->kappa * s->k[i]), &r, &g, &b, &tau);
            sr = vf_select(m, r, sr), sg = vf_select(m, g, sg), sb = vf_select(m, b, sb);
        }
    }
    vmask hit = vf_lt(best, inf);
    /* diffuse (+ specular for phong) with the headlight: n.l = -n.dir */
    vfloat ndl = vf_abs(vf_fma(nx, ray->dx, vf_fma(ny, ray->dy, vf_mul(nz, ray->dz))));
    vfloat k = vf_fma(vf_set1(f->kd), ndl, vf_set1(f->ka));
    vfloat spec = f->shade == LC_KSHADE_PHONG ? vf_mul(vf_set1(f->ks), vf_powi(ndl, f->phong_exp)) : vf_zero();
    surf->r = vf_select(hit, vf_fma(sr, k, spec), vf_zero());
    surf->g = vf_select(hit, vf_fma(sg, k, spec), vf_zero());
    surf->b = vf_select(hit, vf_fma(sb, k, spec), vf_zero());
    surf->a = vf_select(hit, vf_set1(1.0f), vf_zero());
    *thit = best;
}

/* Rays, lattice range and (with spheres) the opaque hit for one vector of the
 * group: the ray, its lattice range [kf, kl] (empty for rays outside the tile
 * or the data) and the surface colour to composite behind the volume. */
static inline void setup_vector(const lc_kparticles *s, const lc_kframe *f, const lc_ktile *t, int x, int y,
                                int32_t *stack, vray *ray, vint *kf, vint *kl, vcolor *surf, lc_kstats *st)
{
    vint px, py;
    dvr_packet_pixels(x, y, &px, &py);
    vmask valid = vm_and(vi_lt(px, vi_set1(t->x1)), vi_lt(py, vi_set1(t->y1)));
    *ray = dvr_camera_rays(&f->cam, px, py);
    vfloat t0, t1;
    dvr_clip_box(ray, s->lo, s->hi, &t0, &t1);
    valid = vm_and(valid, vf_le(t0, t1));
    dvr_lattice(vf_select(valid, t0, vf_set1(1.0f)), vf_select(valid, t1, vf_set1(-1.0f)), f->dt, kf, kl);
    dvr_region(f, ray, mode_pairs(f), kf, kl);
    surf->r = surf->g = surf->b = surf->a = vf_zero();
    if (s->sphere_scale > 0.0f && s->nnodes > 0 && vm_any(valid)) {
        vfloat thit;
        trace_spheres(s, f, ray, valid, stack, &thit, surf, st);
        /* only samples strictly in front of the surface: k dt < t_hit */
        vfloat kh = vf_floor(vf_div(thit, vf_set1(f->dt)));
        kh = vf_select(vf_lt(vf_mul(kh, vf_set1(f->dt)), thit), kh, vf_sub(kh, vf_set1(1.0f)));
        vmask h = vf_gt(surf->a, vf_zero());
        *kl = vi_select(h, vi_min(*kl, vf_to_vi(vf_min(kh, vf_set1(LC_KLATTICE_MAX)))), *kl);
    }
    st->rays += (uint64_t)vm_popcnt(valid);
}

/* Finishes the rays in mode `mode` (f->mode, a constant: see mode_finish_as),
 * composites the opaque surface behind them and writes the pixels. */
static inline __attribute__((always_inline)) void finish_vector(const lc_kframe *f, int mode, const lc_ktile *t, int x,
                                                                int y, vcolor *c, const vcolor *surf, const vray *ray,
                                                                const mprobe *probe)
{
    vint px, py;
    dvr_packet_pixels(x, y, &px, &py);
    vfloat depth = mode_finish_as(f, mode, c, ray, probe);
    vfloat w = vf_sub(vf_set1(1.0f), c->a);
    c->r = vf_fma(w, surf->r, c->r);
    c->g = vf_fma(w, surf->g, c->g);
    c->b = vf_fma(w, surf->b, c->b);
    c->a = vf_fma(w, surf->a, c->a);
    mode_store_as(t, mode, px, py, c, depth);
}

/* slice, for both methods (one sample per ray, no lattice): the planes
 * inside the particles' box and in front of the opaque spheres. Out of line,
 * so the tile functions' dvr code stays as it was. */
static __attribute__((noinline, unused)) void particles_slice_tile(const lc_kparticles *s, const lc_kframe *f,
                                                                   const lc_ktile *t, int32_t *stack, lc_kstats *st)
{
    const pprobe pc = {s, stack, st};
    const mprobe probe = {particles_probe, &pc};
    for (int y = t->y0; y < t->y1; y += DVR_PH) {
        if (lc_ktile_stopped(t)) return;
        for (int x = t->x0; x < t->x1; x += DVR_PW) {
            vint px, py;
            dvr_packet_pixels(x, y, &px, &py);
            vray ray = dvr_camera_rays(&f->cam, px, py);
            vcolor col = {vf_zero(), vf_zero(), vf_zero(), vf_zero()};
            vcolor surf = col;
            vmask valid = vm_and(vi_lt(px, vi_set1(t->x1)), vi_lt(py, vi_set1(t->y1)));
            vfloat t0, t1, thit = vf_set1(INFINITY);
            dvr_clip_box(&ray, s->lo, s->hi, &t0, &t1);
            valid = vm_and(valid, vf_le(t0, t1));
            if (s->nnodes > 0 && vm_any(valid)) {
                st->rays += (uint64_t)vm_popcnt(valid);
                if (s->sphere_scale > 0.0f) trace_spheres(s, f, &ray, valid, stack, &thit, &surf, st);
                dvr_region_slice(f, &ray, &t0, &thit);
                mode_slice(f, &ray, vf_select(valid, t0, vf_set1(1.0f)), vf_select(valid, t1, vf_set1(-1.0f)), thit,
                           &col);
                st->samples += (uint64_t)vm_popcnt(vf_gt(col.a, vf_zero()));
            }
            finish_vector(f, LC_KMODE_SLICE, t, x, y, &col, &surf, &ray, &probe);
        }
    }
}

#endif
