/* Render modes as per-sample consumers (STYLE.md "A mode is a per-sample
 * consumer"). Every kind and method hands its field samples here, so the
 * rule that turns samples into a pixel exists once:
 *   dvr (SPEC.md "Sampling and integration"): classify through the field's
 *   TF, shade (SPEC.md "Shading"), blend front to back.
 *   mip (SPEC.md "Other modes"): keep the largest normalised value along
 *   the ray; mode_finish maps it through its field's colour map.
 *   iso (SPEC.md "Other modes"): watch consecutive lattice samples of field
 *   f->field for a change of side (phi >= iso or not), bisect the first such
 *   step to 1e-4 dt through the kind's probe; mode_finish shades the hit.
 *   slice (SPEC.md "Other modes"): no lattice; mode_slice finds the nearest
 *   plane inside the data's box, mode_finish samples and colours it.
 * The ray's state is its vcolor: dvr accumulates (C, A) in it; mip keeps
 * (max v, field of the max, seen, 0) until mode_finish, with A = 0 so early
 * termination never stops a mip ray; iso keeps (previous phi, its t, its
 * lattice index + 1, 0) until it hits, then (t of the hit, 0, 0, 1), and
 * slice (t of the plane point, 0, 0, 1), so early termination stops the
 * ray. Kernels call mode_finish once per ray before writing the pixel with
 * mode_store.
 * Modes that sample off the lattice (iso's bisection and normal, slice) ask
 * the kind for the field at any point through an mprobe: the kind's own
 * point evaluation (particles: the BVH gather, grids: the trilinear sample,
 * RBF sets: the gather of their method).
 * Traversals ask mode_node_matters whether a subtree can change a pixel; the
 * kind states what it knows of the node's values (docs/DEVELOPERS.md "A new
 * render mode"). */
#ifndef LC_MODE_H
#define LC_MODE_H

#include <math.h>
#include "dvr.h"

/* A sample's gradient (world units), for shading. */
typedef struct vgrad {
    vfloat x, y, z;
} vgrad;

/* A kind's point evaluation: field fi at (x, y, z) on the lanes in m (the
 * other lanes hold finite points and get any value), and its gradient into
 * *g when g is not NULL. ctx is the kind's (its scene, a traversal stack,
 * its counters). */
typedef vfloat (*mprobe_fn)(const void *ctx, int fi, vfloat x, vfloat y, vfloat z, vmask m, vgrad *g);
typedef struct mprobe {
    mprobe_fn fn;
    const void *ctx;
} mprobe;

/* Does the frame need each lattice sample's gradient? Only dvr shades
 * samples; iso takes its one gradient at the hit through the probe. */
static inline int mode_needs_grad(const lc_kframe *f) { return f->mode == LC_KMODE_DVR && f->shade != LC_KSHADE_NONE; }

/* Does the mode walk the lattice? slice takes one sample per ray instead. */
static inline int mode_lattice(const lc_kframe *f) { return f->mode != LC_KMODE_SLICE; }

/* Does the mode look at pairs of consecutive lattice samples (iso)? A
 * traversal that skips stretches of samples by node values must then also
 * take, for every node it keeps, the lattice sample just before and just
 * after the ray's samples in that node (grid_bvh.c integrate_node). */
static inline int mode_pairs(const lc_kframe *f) { return f->mode == LC_KMODE_ISO; }

/* One sample of field fi, already classified to (r, g, b, tau), on the lanes
 * in m: shaded when grad is given (and the frame shades), tau scaled by
 * *step_scale when given (a step other than dt: differential sampling,
 * constant runs), then blended into c. */
static inline void mode_sample_rgbt(const lc_kframe *f, int fi, vcolor *c, vmask m, vfloat r, vfloat g, vfloat b,
                                    vfloat tau, const vgrad *grad, const vray *ray, const vfloat *step_scale)
{
    if (grad) dvr_shade(f, f->tf[fi].grad_eps, ray, grad->x, grad->y, grad->z, &r, &g, &b);
    if (step_scale) tau = vf_mul(tau, *step_scale);
    dvr_blend(c, m, r, g, b, tau, f->dt);
}

/* mip: the running maximum of the normalised value over the lanes in m. */
static inline void mip_sample(const lc_kframe *f, int fi, vcolor *c, vmask m, vfloat phi)
{
    vfloat v = dvr_normalise(&f->tf[fi], phi);
    vmask seen = vf_gt(c->b, vf_zero());
    vmask better = vm_and(m, vm_or(vm_not(seen), vf_gt(v, c->r)));
    c->r = vf_select(better, v, c->r);
    c->g = vf_select(better, vf_set1((float)fi), c->g);
    c->b = vf_select(m, vf_set1(1.0f), c->b);
}

/* The point at t on each lane's ray (iso, slice). */
static inline void mode_point(const vray *ray, vfloat t, vfloat *x, vfloat *y, vfloat *z)
{
    *x = vf_fma(t, ray->dx, ray->ox);
    *y = vf_fma(t, ray->dy, ray->oy);
    *z = vf_fma(t, ray->dz, ray->oz);
}

/* iso: [ta, tb] holds a change of side on the lanes in m (in_a: the side at
 * ta is phi >= iso). Halves it, keeping the change inside, until it is at
 * most 1e-4 dt wide (or float cannot split it further), and returns its end
 * on the phi >= iso side: within 1e-4 dt of the crossing, and on the same
 * side of it whatever the rounding (so the normal there does not depend on
 * which half a rounding picked where the field jumps, as at a truncated
 * Gaussian's support). */
static inline vfloat iso_refine(const lc_kframe *f, int fi, const vray *ray, vfloat ta, vfloat tb, vmask in_a, vmask m,
                                const mprobe *probe)
{
    vfloat tol = vf_set1(1e-4f * f->dt), iso = vf_set1(f->iso);
    vmask act = vm_and(m, vf_gt(vf_sub(tb, ta), tol));
    while (vm_any(act)) {
        vfloat mid = vf_mul(vf_add(ta, tb), vf_set1(0.5f));
        act = vm_and(act, vm_and(vf_gt(mid, ta), vf_lt(mid, tb)));
        if (vm_none(act)) break;
        vfloat x, y, z;
        mode_point(ray, vf_select(act, mid, tb), &x, &y, &z);
        vfloat phi = probe->fn(probe->ctx, fi, x, y, z, act, NULL);
        vmask same = vm_not(vm_xor(vf_ge(phi, iso), in_a));
        ta = vf_select(vm_and(act, same), mid, ta);
        tb = vf_select(vm_andnot(act, same), mid, tb);
        act = vm_and(act, vf_gt(vf_sub(tb, ta), tol));
    }
    return vf_select(in_a, ta, tb);
}

/* iso: sample k (at t, value phi of field fi) on the lanes in m. A lane
 * whose previous sample was k - 1 and lies on the other side of the iso
 * value has found its first crossing: it is refined and the lane stops
 * (A = 1); the others remember this sample. */
static inline void iso_sample(const lc_kframe *f, int fi, vcolor *c, vmask m, vfloat phi, vint k, vfloat t,
                              const vray *ray, const mprobe *probe)
{
    if (fi != f->field) return;
    m = vm_and(m, vf_eq(c->a, vf_zero()));
    vfloat iso = vf_set1(f->iso);
    vmask in_prev = vf_ge(c->r, iso);
    /* b holds the previous sample's index + 1: it is k - 1 when b == k */
    vmask pair = vm_and(m, vf_eq(c->b, vi_to_vf(k)));
    vmask cross = vm_and(pair, vm_xor(in_prev, vf_ge(phi, iso)));
    vmask keep = vm_andnot(m, cross);
    if (vm_any(cross)) {
        vfloat th = iso_refine(f, fi, ray, c->g, t, in_prev, cross, probe);
        c->r = vf_select(cross, th, c->r);
        c->g = vf_select(cross, vf_zero(), c->g);
        c->b = vf_select(cross, vf_zero(), c->b);
        c->a = vf_select(cross, vf_set1(1.0f), c->a);
    }
    c->r = vf_select(keep, phi, c->r);
    c->g = vf_select(keep, t, c->g);
    c->b = vf_select(keep, vi_to_vf(vi_add(k, vi_set1(1))), c->b);
}

/* One sample of field fi with value phi on the lanes in m, in mode `mode`
 * (f->mode; hot loops pass it as a constant so each mode gets its own loop);
 * dvr samples a step of dt through the TF's step table (dvr_classify_step),
 * other steps (step_scale) through the TF and exp:
 * lattice index k at t on the ray (iso pairs consecutive samples), probe the
 * kind's point evaluation (iso refines through it). dvr and mip use neither. */
static inline __attribute__((always_inline)) void mode_sample_as(const lc_kframe *f, int mode, int fi, vcolor *c,
                                                                 vmask m, vfloat phi, const vgrad *grad,
                                                                 const vray *ray, const vfloat *step_scale, vint k,
                                                                 vfloat t, const mprobe *probe)
{
    if (mode == LC_KMODE_MIP) {
        mip_sample(f, fi, c, m, phi);
        return;
    }
    if (mode == LC_KMODE_ISO) {
        iso_sample(f, fi, c, m, phi, k, t, ray, probe);
        return;
    }
    const lc_ktf *tf = &f->tf[fi];
    if (!step_scale && tf->cls) {
        /* a step of dt: the frame's step table, premultiplied, no exp; nothing
           to add where every lane is exactly transparent */
        if (vm_none(dvr_visible(tf, m, phi))) return;
        vfloat pr, pg, pb, a;
        dvr_classify_step(tf, phi, &pr, &pg, &pb, &a);
        if (grad) dvr_shade_pm(f, tf->grad_eps, ray, grad->x, grad->y, grad->z, a, &pr, &pg, &pb);
        dvr_blend_pm(c, m, pr, pg, pb, a);
        return;
    }
    vfloat r, g, b, tau;
    dvr_classify(tf, phi, &r, &g, &b, &tau);
    mode_sample_rgbt(f, fi, c, m, r, g, b, tau, grad, ray, step_scale);
}

/* One sample of field fi with value phi on the lanes in m. */
static inline void mode_sample(const lc_kframe *f, int fi, vcolor *c, vmask m, vfloat phi, const vgrad *grad,
                               const vray *ray, const vfloat *step_scale, vint k, vfloat t, const mprobe *probe)
{
    mode_sample_as(f, f->mode, fi, c, m, phi, grad, ray, step_scale, k, t, probe);
}

/* slice: the nearest plane each ray meets at t in [t0, t1] (the ray's overlap
 * with the data's box, t0 >= 0; t0 > t1: none) and before tmax (an opaque
 * surface in front; +inf: none). Those lanes become opaque with the plane
 * point's t, which mode_finish samples; the others stay transparent. */
static inline void mode_slice(const lc_kframe *f, const vray *ray, vfloat t0, vfloat t1, vfloat tmax, vcolor *c)
{
    vfloat best = vf_set1(INFINITY);
    vmask hit = vm_false();
    for (int i = 0; i < f->nplanes; i++) {
        const lc_kplane *p = &f->planes[i];
        vfloat dn = vf_fma(ray->dx, vf_set1(p->normal[0]),
                           vf_fma(ray->dy, vf_set1(p->normal[1]), vf_mul(ray->dz, vf_set1(p->normal[2]))));
        vfloat ex = vf_sub(vf_set1(p->point[0]), ray->ox), ey = vf_sub(vf_set1(p->point[1]), ray->oy),
               ez = vf_sub(vf_set1(p->point[2]), ray->oz);
        vfloat pn =
            vf_fma(ex, vf_set1(p->normal[0]), vf_fma(ey, vf_set1(p->normal[1]), vf_mul(ez, vf_set1(p->normal[2]))));
        /* parallel rays divide by zero: +-inf or NaN, which no test below passes */
        vfloat tp = vf_div(pn, dn);
        vmask ok = vm_and(vm_and(vf_ge(tp, t0), vf_le(tp, t1)), vm_and(vf_lt(tp, tmax), vf_lt(tp, best)));
        best = vf_select(ok, tp, best);
        hit = vm_or(hit, ok);
    }
    c->r = vf_select(hit, best, vf_zero());
    c->g = c->b = vf_zero();
    c->a = vf_select(hit, vf_set1(1.0f), vf_zero());
}

/* iso and slice (mode_finish): the hit's colour and distance. Out of line:
 * it runs once per ray and would only grow the kernels' tile functions. */
static __attribute__((noinline, unused)) vfloat mode_finish_hit(const lc_kframe *f, vcolor *c, const vray *ray,
                                                                const mprobe *probe)
{
    const int fi = f->field;
    const lc_ktf *tf = &f->tf[fi];
    vmask hit = vf_gt(c->a, vf_zero());
    vfloat th = vf_select(hit, c->r, vf_zero());
    vfloat r = vf_zero(), g = vf_zero(), b = vf_zero(), tau;
    if (vm_any(hit)) {
        vfloat x, y, z;
        mode_point(ray, th, &x, &y, &z);
        if (f->mode == LC_KMODE_SLICE) {
            dvr_classify(tf, probe->fn(probe->ctx, fi, x, y, z, hit, NULL), &r, &g, &b, &tau);
        } else {
            dvr_classify(tf, vf_set1(f->iso), &r, &g, &b, &tau);
            if (f->shade != LC_KSHADE_NONE) {
                vgrad gr;
                probe->fn(probe->ctx, fi, x, y, z, hit, &gr);
                dvr_shade(f, tf->grad_eps, ray, gr.x, gr.y, gr.z, &r, &g, &b);
            }
        }
    }
    c->r = vf_select(hit, r, vf_zero());
    c->g = vf_select(hit, g, vf_zero());
    c->b = vf_select(hit, b, vf_zero());
    c->a = vf_select(hit, vf_set1(1.0f), vf_zero());
    return vf_select(hit, th, vf_set1(INFINITY));
}

/* The ray's final colour, and the distance of the point it shows (iso,
 * slice; minus the maximum normalised value in mip; +inf in dvr and where
 * nothing is shown), in mode
 * `mode` (f->mode; a constant where a kernel specialises its tile function
 * per mode, so the dvr code holds nothing of the other modes):
 *   mip maps its maximum through the colour map of the field that reached it
 *   (opaque where the ray took a sample);
 *   iso colours the hit with the TF's colour at the iso value, shaded with
 *   the gradient there (one probe);
 *   slice samples the plane point (one probe) through the colour map. */
static inline __attribute__((always_inline)) vfloat mode_finish_as(const lc_kframe *f, int mode, vcolor *c,
                                                                   const vray *ray, const mprobe *probe)
{
    vfloat inf = vf_set1(INFINITY);
    if (mode == LC_KMODE_ISO || mode == LC_KMODE_SLICE) return mode_finish_hit(f, c, ray, probe);
    if (mode != LC_KMODE_MIP) return inf;
    vmask seen = vf_gt(c->b, vf_zero());
    /* the depth of a mip pixel is minus its maximum, so regions composite
       by nearest depth (SPEC.md "Regions") */
    vfloat depth = vf_select(seen, vf_sub(vf_zero(), c->r), inf);
    vfloat r = vf_zero(), g = vf_zero(), b = vf_zero();
    for (int fi = 0; fi < f->nfields; fi++) {
        vmask m = vm_and(seen, vf_eq(c->g, vf_set1((float)fi)));
        if (vm_none(m)) continue;
        vfloat cr, cg, cb, tau;
        dvr_classify_v(&f->tf[fi], c->r, &cr, &cg, &cb, &tau);
        r = vf_select(m, cr, r), g = vf_select(m, cg, g), b = vf_select(m, cb, b);
    }
    c->r = r, c->g = g, c->b = b;
    c->a = vf_select(seen, vf_set1(1.0f), vf_zero());
    return depth;
}

static inline vfloat mode_finish(const lc_kframe *f, vcolor *c, const vray *ray, const mprobe *probe)
{
    if (f->mode == LC_KMODE_MIP) return mode_finish_as(f, LC_KMODE_MIP, c, ray, probe);
    if (f->mode == LC_KMODE_ISO || f->mode == LC_KMODE_SLICE) return mode_finish_hit(f, c, ray, probe);
    return mode_finish_as(f, LC_KMODE_DVR, c, ray, probe);
}

/* The depth of the lanes inside the tile (the test hook; out of line, as it
 * only runs for tests). */
static __attribute__((noinline, unused)) void mode_store_depth(const lc_ktile *t, vint px, vint py, vfloat depth)
{
    for (int l = 0; l < LC_W; l++) {
        int x = vi_lane(px, l), y = vi_lane(py, l);
        if (x >= t->x1 || y >= t->y1) continue;
        t->depth[(size_t)y * (size_t)t->stride + (size_t)x] = vf_lane(depth, l);
    }
}

/* Writes the lanes inside the tile: premultiplied (C, A) and, in iso and
 * slice when the tile asks for it (a test hook), the depth mode_finish
 * returned. mode as for mode_finish_as. */
static inline __attribute__((always_inline)) void mode_store_as(const lc_ktile *t, int mode, vint px, vint py,
                                                                const vcolor *c, vfloat depth)
{
    dvr_store(t, px, py, c);
    if (mode != LC_KMODE_DVR && t->depth) mode_store_depth(t, px, py, depth);
}

static inline void mode_store(const lc_ktile *t, const lc_kframe *f, vint px, vint py, const vcolor *c, vfloat depth)
{
    dvr_store(t, px, py, c);
    if (f->mode != LC_KMODE_DVR && t->depth) mode_store_depth(t, px, py, depth);
}

/* What a kind knows of a BVH node's values under the current parameters. */
typedef struct mnode {
    float vmin, vmax;  /* bounds of the values samples inside the node can take */
    int32_t bounds_field; /* 1: [vmin, vmax] bounds the field itself (grids); 0: only this
                             node's additive contribution (particles: others add to it) */
    int32_t transparent;  /* dvr: the kind's TF test found every value in range fully
                             transparent (or below its culling threshold) */
    float floor;          /* mip: the smallest current maximum (normalised, field 0) of the
                             packet's live rays; -inf while any has none */
} mnode;

/* Can the samples inside a node change a pixel? dvr: unless the kind found
 * them transparent. mip: unless the node's values (when they bound the
 * field) cannot beat the maximum every live ray already has. iso: unless
 * they bound the field and the iso value lies outside them (widened by
 * 1e-6 of their magnitude, more than the float round-off of a trilinear
 * sample); the traversal then also takes the samples around each kept node
 * (mode_pairs), which makes the culling exact: a step between two lattice
 * samples that changes side holds a point at the iso value (the field is
 * continuous along it), that point lies in a node whose range holds the
 * value, and the step overlaps that node, so both its samples are taken. */
static inline int mode_node_matters(const lc_kframe *f, const mnode *n)
{
    switch (f->mode) {
    case LC_KMODE_MIP:
        return !n->bounds_field || (n->vmax - f->tf[0].lo) * f->tf[0].inv_range > n->floor;
    case LC_KMODE_ISO: {
        float slack = 1e-6f * fmaxf(fabsf(n->vmin), fabsf(n->vmax));
        return !n->bounds_field || (f->iso >= n->vmin - slack && f->iso <= n->vmax + slack);
    }
    case LC_KMODE_DVR:
    default:
        return !n->transparent;
    }
}

#endif
