/* Structured-grid integration shared by the BVH and brute-force kernels
 * (Knoll et al. 2011 §6): packlets of lane-width rays, samples on SPEC.md's
 * lattice t_k = k dt (independent of BVH and bricks, so both methods take the
 * same samples), trilinear reconstruction (eq. 8) with the analytic gradient
 * from the same weights (eq. 9), classification through the frame's TF table
 * or the pre-integrated table (eq. 4), then the mode's consumer (mode.h). */
#ifndef LC_GRID_COMMON_H
#define LC_GRID_COMMON_H

#include "mode.h"
#include "shared/kgrid.h"
#include "shared/ktable.h"

/* Stage profile (bench only, docs/bench/grid.md "Stage profile"): the
 * benchmark compiles these kernels again with GRID_PROF set to a cumulative
 * set of stages replaced by cheap stand-ins that keep the data flow (so the
 * compiler cannot drop what remains) and the samples taken (frames run with
 * no early termination). The shipped kernels have GRID_PROF = 0: every test is
 * a compile-time constant and folds away. */
#ifndef GRID_PROF
#define GRID_PROF 0
#endif
enum {
    GP_FETCH = 1,   /* voxel loads -> arithmetic on the element index */
    GP_INTERP = 2,  /* cell, offsets, trilinear weights, gradient -> a linear function of position */
    GP_CLASS = 4,   /* TF / pre-integrated table lookups -> rgb = v, tau = v */
    GP_SHADE = 8,   /* shading -> nothing */
    GP_BLEND = 16,  /* exp and front-to-back compositing -> masked sums */
    GP_SAMPLE = 32, /* the whole per-sample loop -> nothing (only its bookkeeping) */
    GP_NOSTOP = 64  /* every profile variant: no early termination, so all take the same samples */
};

/* Lanes still below alpha_stop (all of them in profile variants). */
static inline vmask grid_below_stop(vfloat a, vfloat astop)
{
    if (GRID_PROF & GP_NOSTOP) return vi_eq(vi_set1(0), vi_set1(0));
    return vf_lt(a, astop);
}

/* One packlet: LC_W rays in SOA form, their colour and lattice progress.
 * knext: next lattice index still to integrate (the BVH visits leaves front
 * to back, so a sample on a face shared by two leaves is taken once);
 * klast: last index inside the grid's domain. */
typedef struct gpk {
    vray ray;
    vfloat ix, iy, iz; /* 1 / direction, zero components replaced by 1e-30 */
    vcolor c;
    vint knext, klast;
    vint px, py;
    vfloat prev;  /* pre-integration: normalised value of sample kprev */
    vint kprev;
    vmask live;   /* lanes with samples left and A < alpha_stop */
    vint pa, pb;  /* BVH: pending run of samples not yet integrated (empty: pa > pb) */
} gpk;

/* Lattice parameter of index k: dt (k + rda k (k - 1) / 2) (differential
 * sampling: the step from k to k+1 is dt (1 + rda k)). */
static inline vfloat grid_t_of_k(const lc_kgrid *g, float dt, vint k)
{
    vfloat kf = vi_to_vf(k);
    if (g->rda == 0.0f) return vf_mul(kf, vf_set1(dt));
    vfloat q = vf_mul(vf_mul(kf, vf_sub(kf, vf_set1(1.0f))), vf_set1(0.5f * g->rda));
    return vf_mul(vf_add(kf, q), vf_set1(dt));
}

/* First and last lattice index in [t0, t1] (empty: kf > kl). */
static inline void grid_lattice(const lc_kgrid *g, float dt, vfloat t0, vfloat t1, vint *kf, vint *kl)
{
    if (g->rda == 0.0f) {
        dvr_lattice(t0, t1, dt, kf, kl);
        return;
    }
    /* invert t = dt (k + a k (k-1)/2) for k >= 0: a/2 k^2 + (1 - a/2) k - t/dt = 0 */
    vmask hit = vf_le(t0, t1);
    float a = g->rda, b = 1.0f - 0.5f * a;
    vfloat x0 = vf_div(t0, vf_set1(dt)), x1 = vf_div(t1, vf_set1(dt));
    vfloat r0 = vf_div(vf_sub(vf_sqrt(vf_fma(x0, vf_set1(2.0f * a), vf_set1(b * b))), vf_set1(b)), vf_set1(a));
    vfloat r1 = vf_div(vf_sub(vf_sqrt(vf_fma(x1, vf_set1(2.0f * a), vf_set1(b * b))), vf_set1(b)), vf_set1(a));
    vint k0 = vf_to_vi(vf_min(vf_max(vf_floor(r0), vf_zero()), vf_set1(LC_KLATTICE_MAX)));
    vint k1 = vf_to_vi(vf_min(vf_max(vf_floor(r1), vf_zero()), vf_set1(LC_KLATTICE_MAX)));
    /* fix round-off exactly against grid_t_of_k, the definition */
    for (int it = 0; it < 2; it++) {
        k0 = vi_select(vf_lt(grid_t_of_k(g, dt, k0), t0), vi_add(k0, vi_set1(1)), k0);
        vint km = vi_max(vi_sub(k0, vi_set1(1)), vi_set1(0));
        k0 = vi_select(vm_and(vi_gt(k0, vi_set1(0)), vf_ge(grid_t_of_k(g, dt, km), t0)), km, k0);
        k1 = vi_select(vf_gt(grid_t_of_k(g, dt, k1), t1), vi_sub(k1, vi_set1(1)), k1);
        vint kp = vi_add(k1, vi_set1(1));
        k1 = vi_select(vf_le(grid_t_of_k(g, dt, kp), t1), kp, k1);
    }
    *kf = vi_select(hit, k0, vi_set1(1));
    *kl = vi_select(hit, k1, vi_set1(0));
}

/* Slab test against a box with the packlet's inverse directions, t >= 0. */
static inline void grid_box_t(const gpk *p, const float lo[3], const float hi[3], vfloat *t0, vfloat *t1)
{
    dvr_slab(p->ray.ox, p->ray.oy, p->ray.oz, p->ix, p->iy, p->iz, lo, hi, 0.0f, t0, t1);
    *t0 = vf_max(*t0, vf_zero());
}

/* Rays of a packlet at pixel block (x, y); lanes outside the tile are dead.
 * Always inlined: with four callers GCC called it out of line, once per
 * packlet, and brute-force avx2 dvr frames were 3% slower. */
static inline __attribute__((always_inline)) void grid_packlet_init(const lc_kgrid *g, const lc_kframe *f,
                                                                    const lc_ktile *t, int x, int y, gpk *p)
{
    dvr_packet_pixels(x, y, &p->px, &p->py);
    p->ray = dvr_camera_rays(&f->cam, p->px, p->py);
    p->ix = dvr_inv_dir(p->ray.dx);
    p->iy = dvr_inv_dir(p->ray.dy);
    p->iz = dvr_inv_dir(p->ray.dz);
    vfloat t0, t1;
    dvr_clip_box(&p->ray, g->lo, g->hi, &t0, &t1);
    grid_lattice(g, f->dt, t0, t1, &p->knext, &p->klast);
    dvr_region(f, &p->ray, mode_pairs(f), &p->knext, &p->klast);
    vmask in = vm_and(vi_lt(p->px, vi_set1(t->x1)), vi_lt(p->py, vi_set1(t->y1)));
    p->c = dvr_start(t, x, y); /* zero unless the tile carries (C, A) in */
    /* a carried-in ray may have stopped already */
    p->live = vm_and(vm_and(in, vm_not(vi_gt(p->knext, p->klast))), grid_below_stop(p->c.a, vf_set1(f->alpha_stop)));
    p->prev = vf_zero();
    p->kprev = vi_set1(-2);
    p->pa = vi_set1(1);
    p->pb = vi_set1(0);
}

#include "grid_fetch.h"

/* The post-classified dvr sample's first half, taken before the loop
 * fetches the next stencil (grid_run): the trilinear value, whether any lane
 * in m is visible (the TF not exactly transparent there), and where the
 * frame shades, the gradient: taken whether or not a lane is visible, as a
 * branch on visibility cost more than the 15 operations it saved (embryo
 * Phong 1.02-1.06x without it, docs/bench/grid.md "Value, visibility and
 * gradient before the next fetch"). After it only phi and
 * the gradient of this stencil stay live while the next one is fetched and
 * this sample classified (4 registers instead of the 8 voxel values and 3
 * weights: the Phong loop spilled the colour and the stencils). */
typedef struct gdvr {
    vfloat phi, gx, gy, gz;
    int visible;
} gdvr;

static inline __attribute__((always_inline)) void grid_dvr_pre(const lc_kgrid *g, const lc_kframe *f, int shade,
                                                               vmask m, const gcell *cell, gdvr *s)
{
    s->phi = grid_cell_value(cell);
    /* every lane at a value where the TF is exactly transparent: nothing to
     * add (a = 0), the sample is skipped */
    s->visible = (GRID_PROF & GP_CLASS) || vm_any(dvr_visible(&f->tf[0], m, s->phi));
    s->gx = s->gy = s->gz = vf_zero();
    if (shade) grid_cell_grad(g, cell, &s->gx, &s->gy, &s->gz);
}

/* The post-classified dvr sample (rda off), second half: classify through
 * the step table, shade only where some lane is visible (a > 0) with the
 * gradient grid_dvr_pre took, blend premultiplied: C += (1 - A) (a rgb),
 * A += (1 - A) a. GRID_PROF stand-ins as in grid_prof_consume. */
static inline __attribute__((always_inline)) void grid_dvr_step(const lc_kframe *f, int shade, gpk *p, vmask m,
                                                                const gdvr *s)
{
    const lc_ktf *tf = &f->tf[0];
    vfloat pr, pg, pb, a, phi = s->phi;
    if (!s->visible) return;
    if (GRID_PROF & GP_CLASS) {
        pr = pg = pb = phi;
        a = vf_mul(phi, vf_set1(1e-3f));
    } else {
        dvr_classify_step(tf, phi, &pr, &pg, &pb, &a);
    }
    if (shade && vm_any(vm_and(m, vf_gt(a, vf_zero())))) {
        if (GRID_PROF & GP_SHADE) pr = vf_add(pr, s->gx), pg = vf_add(pg, s->gy), pb = vf_add(pb, s->gz);
        else dvr_shade_pm(f, tf->grad_eps, &p->ray, s->gx, s->gy, s->gz, a, &pr, &pg, &pb);
    }
    if (GRID_PROF & GP_BLEND) {
        p->c.r = vf_add(p->c.r, vf_select(m, pr, vf_zero()));
        p->c.g = vf_add(p->c.g, vf_select(m, pg, vf_zero()));
        p->c.b = vf_add(p->c.b, vf_select(m, pb, vf_zero()));
        p->c.a = vf_add(p->c.a, vf_select(m, a, vf_zero()));
        return;
    }
    dvr_blend_pm(&p->c, m, pr, pg, pb, a);
}

/* Pre-integrated classification (eq. 4) of the segment from the previous
 * sample's normalised value to this one: emission-weighted colour and the
 * mean extinction over the segment. */
static inline void grid_classify_preint(const lc_kgrid *g, vfloat va, vfloat vb, vfloat *r, vfloat *gg, vfloat *b,
                                        vfloat *tau)
{
    float s = (float)(LC_PREINT_N - 1);
    vint qa = vf_to_vi(vf_add(vf_mul(vf_clamp(va, vf_zero(), vf_set1(1.0f)), vf_set1(s)), vf_set1(0.5f)));
    vint qb = vf_to_vi(vf_add(vf_mul(vf_clamp(vb, vf_zero(), vf_set1(1.0f)), vf_set1(s)), vf_set1(0.5f)));
    vint i = vi_sll(vi_add(vi_mul(qa, vi_set1(LC_PREINT_N)), qb), 2);
    *r = vf_gather(g->preint, i);
    *gg = vf_gather(g->preint + 1, i);
    *b = vf_gather(g->preint + 2, i);
    *tau = vf_gather(g->preint + 3, i);
}

/* The grid's point evaluation for the modes (mode.h mprobe): the trilinear
 * value (eq. 8) and gradient (eq. 9) of the one field, counted as voxel
 * samples on the lanes in m. */
typedef struct gprobe {
    const lc_kgrid *g;
    lc_kstats *st;
} gprobe;

static inline vfloat grid_probe(const void *ctx, int fi, vfloat x, vfloat y, vfloat z, vmask m, vgrad *gr)
{
    const gprobe *p = ctx;
    (void)fi;
    vfloat gx, gy, gz;
    vfloat v = grid_sample(p->g, x, y, z, gr != NULL, &gx, &gy, &gz);
    if (gr) gr->x = gx, gr->y = gy, gr->z = gz;
    p->st->kernel_evals += (uint64_t)vm_popcnt(m);
    return v;
}

/* Hands one sample (index k at t) to the mode: phi, or when pre-integrated
 * (eq. 4) its segment's classification rgbt; shaded when the frame shades,
 * with this sample's step dt (1 + rda k) under differential sampling. */
static inline __attribute__((always_inline)) void grid_consume(const lc_kgrid *g, const lc_kframe *f, int mode, gpk *p,
                                                               vmask m, vint k, vfloat t, vfloat phi,
                                                               const vfloat *rgbt, vfloat gx, vfloat gy, vfloat gz,
                                                               lc_kstats *st)
{
    vgrad gr = {gx, gy, gz};
    const vgrad *grad = f->shade != LC_KSHADE_NONE ? &gr : NULL;
    const gprobe pc = {g, st};
    const mprobe probe = {grid_probe, &pc};
    if (g->rda != 0.0f) {
        vfloat scale = vf_fma(vi_to_vf(k), vf_set1(g->rda), vf_set1(1.0f));
        if (rgbt) mode_sample_rgbt(f, 0, &p->c, m, rgbt[0], rgbt[1], rgbt[2], rgbt[3], grad, &p->ray, &scale);
        else mode_sample_as(f, mode, 0, &p->c, m, phi, grad, &p->ray, &scale, k, t, &probe);
    } else {
        if (rgbt) mode_sample_rgbt(f, 0, &p->c, m, rgbt[0], rgbt[1], rgbt[2], rgbt[3], grad, &p->ray, NULL);
        else mode_sample_as(f, mode, 0, &p->c, m, phi, grad, &p->ray, NULL, k, t, &probe);
    }
}

/* Stage-profile stand-ins (GRID_PROF, bench only) for classification,
 * shading and blending, each replaced as its bit says. */
static inline void grid_prof_consume(const lc_kgrid *g, const lc_kframe *f, gpk *p, vmask m, vint k, vfloat phi,
                                     vfloat gx, vfloat gy, vfloat gz)
{
    const lc_ktf *tf = &f->tf[0];
    const int shade = f->shade != LC_KSHADE_NONE;
    vfloat r, gg, b, tau;
    if (GRID_PROF & GP_CLASS) {
        r = gg = b = phi;
        tau = vf_mul(phi, vf_set1(1e-3f));
    } else {
        dvr_classify(tf, phi, &r, &gg, &b, &tau);
    }
    if (shade && !(GRID_PROF & GP_SHADE)) dvr_shade(f, tf->grad_eps, &p->ray, gx, gy, gz, &r, &gg, &b);
    if (shade && (GRID_PROF & GP_SHADE)) r = vf_add(r, gx), gg = vf_add(gg, gy), b = vf_add(b, gz);
    if (g->rda != 0.0f) tau = vf_mul(tau, vf_fma(vi_to_vf(k), vf_set1(g->rda), vf_set1(1.0f)));
    if (GRID_PROF & GP_BLEND) {
        p->c.r = vf_add(p->c.r, vf_select(m, r, vf_zero()));
        p->c.g = vf_add(p->c.g, vf_select(m, gg, vf_zero()));
        p->c.b = vf_add(p->c.b, vf_select(m, b, vf_zero()));
        p->c.a = vf_add(p->c.a, vf_select(m, tau, vf_zero()));
    } else {
        dvr_blend(&p->c, m, r, gg, b, tau, f->dt);
    }
}

/* One lattice sample k at t, its stencil fetched, handed to the mode: the
 * general path (mip, iso, pre-integrated dvr, rda, profile stand-ins). */
static inline __attribute__((always_inline)) void grid_sample_consume(const lc_kgrid *g, const lc_kframe *f, int mode,
                                                                      int shade, gpk *p, vmask m, vint k, vfloat t,
                                                                      const gcell *cell, lc_kstats *st)
{
    const lc_ktf *tf = &f->tf[0];
    vfloat gx = vf_zero(), gy = vf_zero(), gz = vf_zero();
    if (shade) grid_cell_grad(g, cell, &gx, &gy, &gz);
    vfloat phi = grid_cell_value(cell);
    if (GRID_PROF & (GP_CLASS | GP_SHADE | GP_BLEND)) {
        grid_prof_consume(g, f, p, m, k, phi, gx, gy, gz);
    } else if (g->use_preint && mode == LC_KMODE_DVR) {
        vfloat v = vf_mul(vf_sub(phi, vf_set1(tf->lo)), vf_set1(tf->inv_range));
        vfloat va = vf_select(vi_eq(p->kprev, vi_sub(k, vi_set1(1))), p->prev, v);
        vfloat rgbt[4];
        grid_classify_preint(g, va, v, &rgbt[0], &rgbt[1], &rgbt[2], &rgbt[3]);
        p->prev = vf_select(m, v, p->prev);
        p->kprev = vi_select(m, k, p->kprev);
        grid_consume(g, f, mode, p, m, k, t, phi, rgbt, gx, gy, gz, st);
    } else {
        grid_consume(g, f, mode, p, m, k, t, phi, NULL, gx, gy, gz, st);
    }
}

/* The software-pipelined loop over samples k.. of the lanes in m (stopping
 * at kb and alpha_stop): the next sample's stencil (its gathers) is fetched
 * before this sample is classified, shaded and blended, so the loads'
 * latency overlaps that work (any lattice index gives a valid stencil:
 * grid_cell clamps). Same arithmetic, same bytes. Returns the lane samples. */
static inline __attribute__((always_inline)) uint64_t grid_run(const lc_kgrid *g, const lc_kframe *f, int mode,
                                                               int fast, int shade, gpk *p, vmask m, vint k, vint kb,
                                                               lc_kstats *st)
{
    const float dt = f->dt;
    vfloat astop = vf_set1(f->alpha_stop);
    uint64_t n = 0;
    vfloat t = grid_t_of_k(g, dt, k);
    gcell cell;
    grid_cell(g, vf_fma(t, p->ray.dx, p->ray.ox), vf_fma(t, p->ray.dy, p->ray.oy), vf_fma(t, p->ray.dz, p->ray.oz),
              &cell);
    /* the copies' prefetch every other sample: a ray crosses a plane every
       step or two (measured for the quad copy: 1.01-1.08x over every sample,
       4 interleaved runs; for the pair copy with every lane, 1.03-1.08x;
       docs/bench/grid.md "Software prefetch"); in every mode (mip and iso on proc1024
       medium: 1.33x and 1.26x), but not in the profile's stand-in variants */
    unsigned it = 0;
    for (;;) {
        vint kn = vi_add(k, vi_set1(1));
        vfloat tn = grid_t_of_k(g, dt, kn);
        if ((fast || !GRID_PROF) && GRID_PF && g->pairs && (it++ & 1))
            grid_prefetch_pairs(g, p, vf_add(tn, vf_set1((GRID_PF - 1) * dt)));
        gdvr s;
        if (fast) grid_dvr_pre(g, f, shade, m, &cell, &s);
        /* the next stencil only when some lane has a next sample: a run's
           last fetch was otherwise wasted (1 of the ~20-35 a run takes at
           1024^2; docs/bench/grid.md "The run's last fetch skipped") */
        vmask mn = vm_and(m, vm_not(vi_gt(kn, kb)));
        gcell next;
        if (vm_any(mn))
            grid_cell(g, vf_fma(tn, p->ray.dx, p->ray.ox), vf_fma(tn, p->ray.dy, p->ray.oy),
                      vf_fma(tn, p->ray.dz, p->ray.oz), &next);
        else
            next = cell; /* unused: the loop ends below */
        if (fast) grid_dvr_step(f, shade, p, m, &s);
        else grid_sample_consume(g, f, mode, shade, p, m, k, t, &cell, st);
        n += (uint64_t)vm_popcnt(m);
        k = kn, t = tn;
        m = vm_and(mn, grid_below_stop(p->c.a, astop));
        if (!vm_any(m)) break;
        cell = next;
    }
    return n;
}

/* Integrates lattice samples ka..kb (per lane) of the live lanes of p, front
 * to back, stopping lanes at alpha_stop. Both methods go through here. */
static inline __attribute__((always_inline)) void grid_integrate_as(const lc_kgrid *g, const lc_kframe *f, int mode,
                                                                    gpk *p, vint ka, vint kb, lc_kstats *st)
{
    const int shade = mode == LC_KMODE_DVR && f->shade != LC_KSHADE_NONE; /* mode_needs_grad */
    vfloat astop = vf_set1(f->alpha_stop);
    /* post-classified dvr without differential sampling: the step table */
    const int fast = mode == LC_KMODE_DVR && !g->use_preint && g->rda == 0.0f && f->tf[0].cls;
    vmask start = vm_and(p->live, vm_not(vi_gt(ka, kb)));
    vmask m = start;
    uint64_t n = 0;
    if (GRID_PROF & GP_SAMPLE) m = vm_and(m, vm_not(m));
    if (vm_any(m)) {
        if (fast) {
            /* on a local copy of the packlet: no store in the loop can then
               alias its colour and rays (nor the frame's and grid's fields),
               so they stay in registers instead of being stored and reloaded
               every sample */
            gpk q = *p;
            n = grid_run(g, f, mode, 1, shade, &q, m, ka, kb, st);
            p->c = q.c;
        } else {
            n = grid_run(g, f, mode, 0, shade, p, m, ka, kb, st);
        }
    }
    st->samples += n;
    st->kernel_evals += n;
    p->knext = vi_select(start, vi_max(p->knext, vi_add(kb, vi_set1(1))), p->knext);
    p->live = vm_and(p->live, vm_and(vm_not(vi_gt(p->knext, p->klast)), grid_below_stop(p->c.a, astop)));
}

/* The sample loop specialised per mode (the mode is the same for a frame). */
static inline void grid_integrate(const lc_kgrid *g, const lc_kframe *f, gpk *p, vint ka, vint kb, lc_kstats *st)
{
    if (f->mode == LC_KMODE_MIP) grid_integrate_as(g, f, LC_KMODE_MIP, p, ka, kb, st);
    else if (f->mode == LC_KMODE_ISO) grid_integrate_as(g, f, LC_KMODE_ISO, p, ka, kb, st);
    else grid_integrate_as(g, f, LC_KMODE_DVR, p, ka, kb, st);
}

/* Constant subvolume (eq. 7): samples ka..kb all take the value phi, unshaded,
 * blended in closed form: n samples of opacity a give 1 - (1 - a)^n, i.e.
 * 1 - exp(-tau * (t_{kb+1} - t_ka)). */
static inline void grid_integrate_const(const lc_kgrid *g, const lc_kframe *f, gpk *p, vint ka, vint kb, float phi,
                                        lc_kstats *st)
{
    vmask m = vm_and(p->live, vm_not(vi_gt(ka, kb)));
    if (vm_none(m)) return;
    vint kend = vi_add(kb, vi_set1(1));
    vfloat len = vf_sub(grid_t_of_k(g, f->dt, kend), grid_t_of_k(g, f->dt, ka));
    /* one sample whose step is the run's length: a = 1 - exp(-tau len) */
    vfloat scale = vf_div(len, vf_set1(f->dt));
    /* dvr and mip only (node_constant): iso needs every sample, slice none */
    mode_sample(f, 0, &p->c, m, vf_set1(phi), NULL, &p->ray, &scale, ka, vf_zero(), NULL);
    st->samples += (uint64_t)vm_popcnt(m);
    p->knext = vi_select(m, vi_max(p->knext, kend), p->knext);
    p->kprev = vi_select(m, vi_set1(-2), p->kprev);
    p->live = vm_and(p->live, vm_and(vm_not(vi_gt(p->knext, p->klast)), grid_below_stop(p->c.a, vf_set1(f->alpha_stop))));
}

/* slice (no lattice): the packlet's rays against the planes inside the
 * domain; mode_finish samples the plane points. */
static inline void grid_slice(const lc_kgrid *g, const lc_kframe *f, const lc_ktile *t, gpk *p, lc_kstats *st)
{
    vfloat t0, t1;
    dvr_clip_box(&p->ray, g->lo, g->hi, &t0, &t1);
    vmask in = vm_and(vi_lt(p->px, vi_set1(t->x1)), vi_lt(p->py, vi_set1(t->y1)));
    vfloat tmax = vf_set1(INFINITY);
    dvr_region_slice(f, &p->ray, &t0, &tmax);
    mode_slice(f, &p->ray, vf_select(in, t0, vf_set1(1.0f)), vf_select(in, t1, vf_set1(-1.0f)), tmax, &p->c);
    st->samples += (uint64_t)vm_popcnt(vf_gt(p->c.a, vf_zero()));
}

/* Finishes the packlet's rays in the mode and writes the lanes inside the tile. */
static inline void grid_finish_store(const lc_kgrid *g, const lc_kframe *f, const lc_ktile *t, gpk *p, lc_kstats *st)
{
    const gprobe pc = {g, st};
    const mprobe probe = {grid_probe, &pc};
    vfloat depth = mode_finish(f, &p->c, &p->ray, &probe);
    if (f->mode != LC_KMODE_DVR) mode_store(t, f, p->px, p->py, &p->c, depth);
    else dvr_store(t, p->px, p->py, &p->c);
}

/* Rows per step of the BVH's traversal group (grid_group_side). */
#define GRID_GROUP_ROWS 256

/* Side in rays of the group of rays the BVH traverses together: the frame's
 * packet side times one per GRID_GROUP_ROWS image rows (1 to 4), at most 32
 * (or the packet side if larger); packet 1 (lane-width packlets) stays 1.
 * The images do not depend on it: which nodes are leaves depends on the
 * node and on the frame's packet side only (footprint pruning, traverse),
 * and every ray takes the lattice samples of the leaves it crosses, in
 * order. Measured (docs/bench/grid.md "Traversal groups of up to 32x32 rays"): at 1024^2, 16x16 groups
 * take 3.4x fewer node visits than 8x8 and 1.08-1.15x less CPU per frame, 32x32
 * another 1-5 %; at 512^2 16x16 1.00-1.15x; at 256^2 mixed (0.9-1.1x). */
static inline int grid_group_side(const lc_kframe *f)
{
    int p = f->packet;
    if (p <= 1) return p;
    int k = f->cam.height / GRID_GROUP_ROWS;
    k = k < 1 ? 1 : k > 4 ? 4 : k;
    int cap = p > 32 ? p : 32;
    return p * k < cap ? p * k : cap;
}

/* Side of the ray packets (in rays) the BVH traverses for this target and
 * frame: packet 1 means one lane-width packlet; otherwise a multiple of the
 * packlet's block. */
static inline void grid_packet_dims(const lc_kframe *f, int *pw, int *ph)
{
    int p = grid_group_side(f);
    p = p <= 1 ? 0 : p;
    if (p == 0) {
        *pw = DVR_PW;
        *ph = DVR_PH;
        return;
    }
    *pw = (p + DVR_PW - 1) / DVR_PW * DVR_PW;
    *ph = (p + DVR_PH - 1) / DVR_PH * DVR_PH;
}

static inline uint64_t grid_scratch(const lc_kframe *f)
{
    int pw, ph;
    grid_packet_dims(f, &pw, &ph);
    return (uint64_t)(pw / DVR_PW) * (uint64_t)(ph / DVR_PH) * sizeof(gpk) + 64;
}

#endif
