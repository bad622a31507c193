/* Render modes as per-sample consumers (STYLE.md "A mode is a per-sample
 * consumer"). Every kind and method hands its field samples here, so the
 * rule that turns samples into a pixel exists once:
 *   dvr (SPEC.md "Sampling and integration"): classify through the field's
 *   TF, shade (SPEC.md "Shading"), blend front to back.
 *   mip (SPEC.md "Other modes"): keep the largest normalised value along
 *   the ray; mode_finish maps it through its field's colour map.
 * The ray's state is its vcolor: dvr accumulates (C, A) in it; mip keeps
 * (max v, field of the max, seen, 0) until mode_finish, with A = 0 so early
 * termination never stops a mip ray. Kernels call mode_finish once per ray
 * before writing the pixel.
 * Traversals ask mode_node_matters whether a subtree can change a pixel; the
 * kind states what it knows of the node's values. iso, MIP and slice add a
 * case to each function here (docs/DEVELOPERS.md "A new render mode"). */
#ifndef LC_MODE_H
#define LC_MODE_H

#include "dvr.h"

/* A sample's gradient (world units), for shading. */
typedef struct vgrad {
    vfloat x, y, z;
} vgrad;

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

/* One sample of field fi with value phi on the lanes in m, in mode `mode`
 * (f->mode; hot loops pass it as a constant so each mode gets its own loop). */
static inline __attribute__((always_inline)) void mode_sample_as(const lc_kframe *f, int mode, int fi, vcolor *c,
                                                                 vmask m, vfloat phi, const vgrad *grad,
                                                                 const vray *ray, const vfloat *step_scale)
{
    if (mode == LC_KMODE_MIP) {
        mip_sample(f, fi, c, m, phi);
        return;
    }
    vfloat r, g, b, tau;
    dvr_classify(&f->tf[fi], phi, &r, &g, &b, &tau);
    mode_sample_rgbt(f, fi, c, m, r, g, b, tau, grad, ray, step_scale);
}

/* One sample of field fi with value phi on the lanes in m. */
static inline void mode_sample(const lc_kframe *f, int fi, vcolor *c, vmask m, vfloat phi, const vgrad *grad,
                               const vray *ray, const vfloat *step_scale)
{
    mode_sample_as(f, f->mode, fi, c, m, phi, grad, ray, step_scale);
}

/* The ray's final colour: mip maps its maximum through the colour map of
 * the field that reached it (opaque where the ray took a sample). */
static inline void mode_finish(const lc_kframe *f, vcolor *c)
{
    if (f->mode != LC_KMODE_MIP) return;
    vmask seen = vf_gt(c->b, vf_zero());
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
 * field) cannot beat the maximum every live ray already has. */
static inline int mode_node_matters(const lc_kframe *f, const mnode *n)
{
    switch (f->mode) {
    case LC_KMODE_MIP:
        return !n->bounds_field || (n->vmax - f->tf[0].lo) * f->tf[0].inv_range > n->floor;
    case LC_KMODE_DVR:
    default:
        return !n->transparent;
    }
}

#endif
