/* Render modes as per-sample consumers (STYLE.md "A mode is a per-sample
 * consumer"). Every kind and method hands its field samples here, so the
 * rule that turns samples into a pixel exists once:
 *   dvr (SPEC.md "Sampling and integration"): classify through the field's
 *   TF, shade (SPEC.md "Shading"), blend front to back.
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

/* One sample of field fi with value phi on the lanes in m. */
static inline void mode_sample(const lc_kframe *f, int fi, vcolor *c, vmask m, vfloat phi, const vgrad *grad,
                               const vray *ray, const vfloat *step_scale)
{
    vfloat r, g, b, tau;
    dvr_classify(&f->tf[fi], phi, &r, &g, &b, &tau);
    mode_sample_rgbt(f, fi, c, m, r, g, b, tau, grad, ray, step_scale);
}

/* What a kind knows of a BVH node's values under the current parameters. */
typedef struct mnode {
    float vmin, vmax;  /* bounds of the values samples inside the node can take */
    int32_t bounds_field; /* 1: [vmin, vmax] bounds the field itself (grids); 0: only this
                             node's additive contribution (particles: others add to it) */
    int32_t transparent;  /* dvr: the kind's TF test found every value in range fully
                             transparent (or below its culling threshold) */
} mnode;

/* Can the samples inside a node change a pixel? dvr: unless the kind found
 * them transparent. */
static inline int mode_node_matters(const lc_kframe *f, const mnode *n)
{
    switch (f->mode) {
    case LC_KMODE_DVR:
    default:
        return !n->transparent;
    }
}

#endif
