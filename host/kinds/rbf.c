/* RBF sets (Jang et al. 2004): validation, the truncation supports of eq. 3,
 * the BVH over the supports (the particle builder, radius = R_i), a
 * conservative value range, and the per-frame kernel scene: lc_krbf for the
 * BVH gather, brute force and the octree (kernels/rbf*.c), or the particle
 * view lc_kparticles for the coherent method, which runs the particle kind's
 * coherent kernel (kparticles.h says how a term maps onto a particle). Render
 * only: no encoder. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/kinds/kind.h"
#include "host/api/tf.h"
#include "host/kinds/particles_frame.h"
#include "bvh/particle_bvh.h"
#include "bvh/rbf_octree.h"
#include "kernels/shared/krbf.h"
#include "kernels/shared/ktable.h"

typedef struct rbf {
    lc_volume base; /* first: the kind-neutral handle */
    lc_rbf_info info;
    lci_pbvh bvh;
    lci_octree oct; /* accel = octree */
    float *cx, *cy, *cz, *r2, *nis, *w, *R; /* leaf order */
    float peak[2]; /* the field's range at the centres (with the bias): the default TF range */
    /* the coherent method's particle view (kparticles.h): per node the sum of
       |w_i| below it (node_ksum), and an upper bound of the field (bias
       included) at every point the node's terms reach (node_hi, range_bound),
       which decides the transparent nodes of a dvr frame; field ids, all 0 */
    float *node_wsum, *node_hi;
    uint8_t *field0;
} rbf;

static void destroy(lc_volume *v)
{
    rbf *p = (rbf *)v;
    if (!p) return;
    lci_pbvh_free(&p->bvh);
    lci_octree_free(&p->oct);
    free(p->cx), free(p->cy), free(p->cz), free(p->r2), free(p->nis), free(p->w), free(p->R);
    free(p->node_wsum), free(p->node_hi), free(p->field0);
    free(p);
}

lc_status lc_rbf_get_info(const lc_volume *v, lc_rbf_info *out)
{
    const rbf *p = lci_volume_as(v, LC_KIND_RBF, "lc_rbf_get_info");
    if (!p) return LC_ERROR_INVALID_ARGUMENT;
    if (!out) return lci_error(v->device, LC_ERROR_INVALID_ARGUMENT, "lc_rbf_get_info: out is NULL");
    *out = p->info;
    return LC_OK;
}

/* Centres, widths and the domain are bounded so that every extent the BVH
 * and octree builders and the kernels form (a support is at most ~14 widths
 * for any float weight and eps, max - min of centres +- supports) stays far
 * from float overflow: Embree's binning asserts (aborts) on infinite extents,
 * as for particles (host/kinds/particles.c). */
#define MAX_COORD 1e18f
#define MAX_WIDTH 1e16f

/* Why RBF i is invalid, or NULL. */
static const char *invalid(const lc_rbf_desc *d, size_t i)
{
    const float *c = d->centres + 3 * i;
    if (!isfinite(c[0]) || !isfinite(c[1]) || !isfinite(c[2])) return "non-finite centre";
    if (fabsf(c[0]) > MAX_COORD || fabsf(c[1]) > MAX_COORD || fabsf(c[2]) > MAX_COORD)
        return "a centre coordinate beyond +-1e18";
    if (!(d->widths[i] > 0.0f) || !isfinite(d->widths[i])) return "width not finite and > 0";
    if (d->widths[i] > MAX_WIDTH) return "width beyond 1e16";
    if (!isfinite(d->weights[i])) return "non-finite weight";
    return NULL;
}

static int box_is_zero(const lc_box3 *b)
{
    return b->lo.x == 0.0f && b->lo.y == 0.0f && b->lo.z == 0.0f && b->hi.x == 0.0f && b->hi.y == 0.0f &&
           b->hi.z == 0.0f;
}

/* LC_RBF_ACCEL_DEFAULT: the fastest on the measured sets (docs/bench/rbf.md),
 * the coherent method; the octree when an octree option (cell_max,
 * significant) asks for one. */
static lc_rbf_accel resolve_accel(const lc_rbf_desc *d)
{
    if (d->accel != LC_RBF_ACCEL_DEFAULT) return d->accel;
    return d->cell_max || d->significant ? LC_RBF_ACCEL_OCTREE : LC_RBF_ACCEL_COHERENT;
}

/* The descriptor's scalar checks; the per-RBF ones follow in create. */
static lc_status check_desc(lc_device *dev, const lc_rbf_desc *d)
{
    const char *fn = "lc_rbf_create";
    if (d->count > 0 && (!d->centres || !d->widths || !d->weights))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: %zu RBFs but centres, widths or weights is NULL", fn,
                         d->count);
    if (d->count > (size_t)INT32_MAX / 2)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: %zu RBFs, at most %d", fn, d->count, INT32_MAX / 2);
    if (d->leaf_size < 0 || d->leaf_size > 32)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: leaf_size = %d, expected 0 (default) or 1 to 32", fn,
                         d->leaf_size);
    if (!isfinite(d->bias))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: bias = %g, expected a finite value", fn, (double)d->bias);
    if ((int)d->accel < 0 || (int)d->accel > LC_RBF_ACCEL_COHERENT)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "%s: accel = %d, expected 0 (default), %d (bvh), %d (octree) or %d (coherent)", fn,
                         (int)d->accel, LC_RBF_ACCEL_BVH, LC_RBF_ACCEL_OCTREE, LC_RBF_ACCEL_COHERENT);
    if (d->cell_max < 0 || d->cell_max > LC_RBF_MAX_CELL)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: cell_max = %d, expected 0 (default) or 1 to %d", fn,
                         d->cell_max, LC_RBF_MAX_CELL);
    if (d->significant != 0 && d->significant != 1)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: significant = %d, expected 0 or 1", fn, d->significant);
    if (d->significant && resolve_accel(d) != LC_RBF_ACCEL_OCTREE)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "%s: significant = 1 keeps the most significant RBFs of octree cells; it needs accel = octree",
                         fn);
    if (!(d->eps >= 0.0f) || !isfinite(d->eps))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: eps = %g, expected 0 (default) or a finite value > 0",
                         fn, (double)d->eps);
    const lc_box3 *b = &d->domain;
    if (!box_is_zero(b)) {
        const float v[6] = {b->lo.x, b->lo.y, b->lo.z, b->hi.x, b->hi.y, b->hi.z};
        int ok = 1;
        for (int k = 0; k < 6; k++) ok &= isfinite(v[k]) && fabsf(v[k]) <= MAX_COORD;
        if (!ok || !(v[0] < v[3] && v[1] < v[4] && v[2] < v[5]))
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                             "%s: domain (%g,%g,%g)-(%g,%g,%g): expected lo < hi on every axis within +-1e18, or "
                             "all zero",
                             fn,
                             (double)v[0], (double)v[1], (double)v[2], (double)v[3], (double)v[4], (double)v[5]);
    }
    size_t bad = 0, first = 0;
    const char *why = NULL;
    for (size_t i = 0; i < d->count; i++) {
        const char *w = invalid(d, i);
        if (w && !bad++) first = i, why = w;
    }
    if (bad)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: %zu of %zu RBFs are invalid; the first is RBF %zu (%s)", fn,
                         bad, d->count, first, why);
    return LC_OK;
}

/* The default eps (lanecast.h): 1e-4 of the strongest weight. */
static float pick_eps(const lc_rbf_desc *d)
{
    if (d->eps > 0.0f) return d->eps;
    float m = 0.0f;
    for (size_t i = 0; i < d->count; i++) m = fmaxf(m, fabsf(d->weights[i]));
    /* all weights zero: nothing has support either way; a subnormal largest
       weight would make 1e-4 m underflow to 0 and every support infinite
       (Embree's binning aborted: fuzz_rbf_binary), so eps stays > 0 */
    return m > 0.0f ? fmaxf(1e-4f * m, FLT_TRUE_MIN) : 1.0f;
}

/* Eq. 3 in double, so the support and the box agree with a double reference
 * to float rounding: R_i = s_i sqrt(2 ln(|w_i| / eps)), 0 when |w_i| <= eps. */
static double support(float s, float w, float eps)
{
    double q = fabs((double)w) / (double)eps;
    return q > 1.0 ? (double)s * sqrt(2.0 * log(q)) : 0.0;
}

/* Squared distance from point c to the box [lo, hi]. */
static double box_d2(const float c[3], const float lo[3], const float hi[3])
{
    double d2 = 0.0;
    for (int k = 0; k < 3; k++) {
        double e = c[k] < lo[k] ? (double)lo[k] - c[k] : c[k] > hi[k] ? (double)c[k] - hi[k] : 0.0;
        d2 += e * e;
    }
    return d2;
}

/* A support grown so float round-off never leaves out a term the kernels
 * count (they test d^2 < R^2 in float), as the particle kind's grow_support. */
static double grow_support(float R) { return (double)R * 1.001 + 1e-6; }

/* The default range (lanecast.h, lc_rbf_info.range). A point x inside the
 * support of a term of leaf L lies in L's centre box grown by L's largest R,
 * and every term contributing at x has a support reaching x, hence that box:
 * so f(x) - w0 lies between the negative and the positive weight sums over
 * the supports reaching the grown box of any leaf. Outside all supports
 * f = w0. One BVH query per leaf.
 * The same query gives node_hi for the coherent method's transparent-space
 * skipping (prepare_coherent): w0 plus the positive weight sum over the
 * supports, grown by grow_support, reaching the leaf's box grown likewise,
 * bounds every partial sum of the terms at any sample a leaf term reaches;
 * an inner node takes the larger of its children's. */
static lc_status range_bound(lc_device *dev, rbf *p, float out[2])
{
    double lo = p->info.bias, hi = p->info.bias;
    int32_t nn = p->bvh.nnodes;
    p->node_hi = malloc(sizeof(float) * (size_t)(nn > 0 ? nn : 1));
    p->node_wsum = malloc(sizeof(float) * (size_t)(nn > 0 ? nn : 1));
    if (!p->node_hi || !p->node_wsum) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_create: out of memory");
    int32_t *stack = malloc(sizeof(int32_t) * (size_t)(p->bvh.depth + 4));
    if (!stack) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_create: out of memory");
    for (int32_t l = 0; l < p->bvh.nnodes; l++) {
        const lc_kpnode *leaf = &p->bvh.nodes[l];
        if (leaf->count == 0) continue;
        float g = p->bvh.rmax[l], blo[3], bhi[3], glo[3], ghi[3], gg = (float)grow_support(g);
        for (int k = 0; k < 3; k++) blo[k] = leaf->lo[k] - g, bhi[k] = leaf->hi[k] + g;
        for (int k = 0; k < 3; k++) glo[k] = leaf->lo[k] - gg, ghi[k] = leaf->hi[k] + gg;
        double pos = 0.0, neg = 0.0, gpos = 0.0;
        int sp = 0;
        stack[sp++] = 0;
        while (sp > 0) {
            const int32_t n = stack[--sp];
            const lc_kpnode *node = &p->bvh.nodes[n];
            float r = (float)grow_support(p->bvh.rmax[n]), nlo[3], nhi[3];
            int overlap = 1;
            for (int k = 0; k < 3; k++) {
                nlo[k] = node->lo[k] - r, nhi[k] = node->hi[k] + r;
                overlap &= nlo[k] <= ghi[k] && nhi[k] >= glo[k];
            }
            if (!overlap) continue;
            if (node->count == 0) {
                stack[sp++] = node->first, stack[sp++] = node->first + 1;
                continue;
            }
            for (int32_t j = node->first; j < node->first + node->count; j++) {
                const float c[3] = {p->cx[j], p->cy[j], p->cz[j]};
                const double Rg = grow_support(p->R[j]);
                if (p->w[j] > 0.0f && box_d2(c, glo, ghi) <= Rg * Rg) gpos += p->w[j];
                if (box_d2(c, blo, bhi) > (double)p->R[j] * p->R[j]) continue;
                pos += p->w[j] > 0.0f ? p->w[j] : 0.0;
                neg += p->w[j] < 0.0f ? p->w[j] : 0.0;
            }
        }
        hi = fmax(hi, (double)p->info.bias + pos);
        lo = fmin(lo, (double)p->info.bias + neg);
        /* rounded up well past the kernels' float sums */
        double h = (double)p->info.bias + gpos;
        p->node_hi[l] = (float)(h + 1e-5 * (fabs(h) + gpos) + 1e-30);
    }
    free(stack);
    /* children follow their parent in the flat array: one backward sweep */
    for (int32_t n = nn - 1; n >= 0; n--) {
        const lc_kpnode *node = &p->bvh.nodes[n];
        double ws = 0.0;
        if (node->count == 0) {
            p->node_hi[n] = fmaxf(p->node_hi[node->first], p->node_hi[node->first + 1]);
            ws = (double)p->node_wsum[node->first] + p->node_wsum[node->first + 1];
        } else {
            for (int32_t j = node->first; j < node->first + node->count; j++) ws += fabs((double)p->w[j]);
        }
        p->node_wsum[n] = (float)ws * (1.0f + 1e-6f);
    }
    /* a hair wider: the kernels sum in float */
    double pad = 1e-6 * (fabs(lo) + fabs(hi));
    out[0] = (float)(lo - pad), out[1] = (float)(hi + pad);
    return LC_OK;
}

/* Copies the kept RBFs (|w| > eps) into xyz/R in input order. */
static size_t keep(const lc_rbf_desc *d, float eps, float *xyz, float *R, size_t *src, lc_box3 *sb)
{
    size_t n = 0;
    *sb = (lc_box3){{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
    for (size_t i = 0; i < d->count; i++) {
        double r = support(d->widths[i], d->weights[i], eps);
        if (!(r > 0.0)) continue;
        const float *c = d->centres + 3 * i;
        memcpy(xyz + 3 * n, c, sizeof(float) * 3);
        R[n] = (float)r;
        src[n++] = i;
        sb->lo.x = fminf(sb->lo.x, (float)(c[0] - r)), sb->hi.x = fmaxf(sb->hi.x, (float)(c[0] + r));
        sb->lo.y = fminf(sb->lo.y, (float)(c[1] - r)), sb->hi.y = fmaxf(sb->hi.y, (float)(c[1] + r));
        sb->lo.z = fminf(sb->lo.z, (float)(c[2] - r)), sb->hi.z = fmaxf(sb->hi.z, (float)(c[2] + r));
    }
    if (n == 0) *sb = (lc_box3){{0, 0, 0}, {0, 0, 0}};
    return n;
}

/* The octree over the kept RBFs (leaf order). Its root holds the clip box
 * and every support, so lc_volume_sample anywhere finds a leaf whose list
 * has every term reaching the point; grown a little for round-off. */
static lc_status build_octree(lc_device *dev, rbf *p, size_t n)
{
    lc_rbf_info *in = &p->info;
    double t0 = lci_now();
    lci_octree_in oi = {p->cx, p->cy, p->cz, p->R, p->w, p->nis, n, {0}, {0}, in->cell_max, in->significant};
    const lc_box3 *a = &in->bounds, *b = &in->support_bounds;
    const float alo[3] = {a->lo.x, a->lo.y, a->lo.z}, ahi[3] = {a->hi.x, a->hi.y, a->hi.z};
    const float blo[3] = {b->lo.x, b->lo.y, b->lo.z}, bhi[3] = {b->hi.x, b->hi.y, b->hi.z};
    for (int k = 0; k < 3; k++) {
        float lo = n ? fminf(alo[k], blo[k]) : alo[k], hi = n ? fmaxf(ahi[k], bhi[k]) : ahi[k];
        float g = 1e-4f * (hi - lo) + 1e-6f * (fabsf(lo) + fabsf(hi)) + 1e-30f;
        oi.lo[k] = lo - g, oi.hi[k] = hi + g;
    }
    char err[256];
    if (lci_octree_build(&oi, &p->oct, err, sizeof err) != 0)
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_create: octree build failed: %s", err);
    in->octree_cells = p->oct.ncells, in->octree_leaves = p->oct.nleaves, in->octree_depth = p->oct.depth;
    in->octree_refs = (size_t)p->oct.nlist, in->octree_max_list = (size_t)p->oct.max_leaf;
    in->octree_bytes = lci_octree_bytes(&p->oct);
    in->truncated = (size_t)p->oct.truncated, in->truncation_bound = p->oct.err_bound;
    in->octree_seconds = lci_now() - t0;
    return LC_OK;
}

/* BVH over the kept supports, leaf-ordered arrays, the range bound, the
 * octree when asked for. */
static lc_status build(lc_device *dev, rbf *p, const lc_rbf_desc *d, const float *xyz, const float *R,
                       const size_t *src, size_t n)
{
    lc_rbf_info *in = &p->info;
    char err[256];
    if (n > 0) {
        void *e = lci_embree_device(dev);
        if (!e) return LC_ERROR_INTERNAL;
        if (lci_pbvh_build(e, xyz, R, 0.0f, n, in->leaf_size, &p->bvh, err, sizeof err) != 0)
            return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_create: BVH build failed: %s", err);
    }
    size_t m = n ? n : 1;
    float **arr[] = {&p->cx, &p->cy, &p->cz, &p->r2, &p->nis, &p->w, &p->R};
    for (size_t a = 0; a < sizeof arr / sizeof arr[0]; a++)
        if (!(*arr[a] = malloc(sizeof(float) * m)))
            return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_create: out of memory for %zu RBFs", n);
    if (!(p->field0 = calloc(m, 1)))
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_create: out of memory for %zu RBFs", n);
    in->min_width = n ? INFINITY : 0.0f;
    for (size_t j = 0; j < n; j++) {
        uint32_t o = p->bvh.order[j];
        size_t i = src[o];
        float s = d->widths[i];
        p->cx[j] = xyz[3 * o], p->cy[j] = xyz[3 * o + 1], p->cz[j] = xyz[3 * o + 2];
        p->R[j] = R[o];
        p->r2[j] = R[o] * R[o];
        p->nis[j] = -1.0f / (2.0f * s * s);
        p->w[j] = d->weights[i];
        in->min_width = fminf(in->min_width, s);
        in->max_width = fmaxf(in->max_width, s);
        in->max_support = fmaxf(in->max_support, R[o]);
    }
    if (p->bvh.order) free(p->bvh.order), p->bvh.order = NULL;
    lc_status s = range_bound(dev, p, in->range);
    if (s != LC_OK || in->accel != LC_RBF_ACCEL_OCTREE) return s;
    s = build_octree(dev, p, n);
    if (s != LC_OK && d->accel == LC_RBF_ACCEL_DEFAULT) {
        /* the default never fails where the BVH alone would not: the BVH it is */
        lci_log(dev, LC_LOG_WARNING, "rbf: %s; rendering through the BVH instead", lc_last_error());
        lci_octree_free(&p->oct);
        in->accel = LC_RBF_ACCEL_BVH, in->cell_max = 0, in->significant = 0;
        s = LC_OK;
    }
    return s;
}

/* The field's extremes are near the centres: its values there (at most 4096
 * centres, evenly strided) and the bias give the default TF range, far
 * tighter than the bound in info.range, which adds every overlapping weight. */
static void peaks(lc_device *dev, rbf *p)
{
    p->peak[0] = p->peak[1] = p->info.bias;
    size_t n = p->info.count, m = n < 4096 ? n : 4096;
    float *xyz = m ? malloc(sizeof(float) * 3 * m) : NULL, *v = m ? malloc(sizeof(float) * m) : NULL;
    if (!xyz || !v) {
        free(xyz), free(v);
        return; /* the bias alone: the bound is used (frame_info) */
    }
    for (size_t i = 0; i < m; i++) {
        size_t j = i * n / m;
        xyz[3 * i] = p->cx[j], xyz[3 * i + 1] = p->cy[j], xyz[3 * i + 2] = p->cz[j];
    }
    if (lc_volume_sample(dev, &p->base, m, xyz, v, NULL) == LC_OK)
        for (size_t i = 0; i < m; i++) p->peak[0] = fminf(p->peak[0], v[i]), p->peak[1] = fmaxf(p->peak[1], v[i]);
    free(xyz), free(v);
}

static lc_status create(lc_device *dev, const void *desc, lc_volume **out)
{
    const lc_rbf_desc *d = desc;
    *out = NULL;
    lc_status s = check_desc(dev, d);
    if (s != LC_OK) return s;
    rbf *p = calloc(1, sizeof *p);
    size_t m = d->count ? d->count : 1;
    float *xyz = malloc(sizeof(float) * 3 * m), *R = malloc(sizeof(float) * m);
    size_t *src = malloc(sizeof(size_t) * m);
    if (!p || !xyz || !R || !src) {
        free(p), free(xyz), free(R), free(src);
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_create: out of memory for %zu RBFs", d->count);
    }
    p->base.ops = &lci_rbf_ops;
    p->base.device = dev;
    lc_rbf_info *in = &p->info;
    in->bias = d->bias;
    in->eps = pick_eps(d);
    in->leaf_size = d->leaf_size ? d->leaf_size : 4;
    in->accel = resolve_accel(d);
    if (in->accel == LC_RBF_ACCEL_OCTREE) in->cell_max = d->cell_max ? d->cell_max : 32, in->significant = d->significant;
    double t0 = lci_now();
    size_t n = keep(d, in->eps, xyz, R, src, &in->support_bounds);
    in->count = n;
    in->dropped = d->count - n;
    in->bounds = box_is_zero(&d->domain) ? in->support_bounds : d->domain;
    s = build(dev, p, d, xyz, R, src, n);
    free(xyz), free(R), free(src);
    if (s != LC_OK) {
        destroy(&p->base);
        return s;
    }
    in->build_seconds = lci_now() - t0;
    in->bvh_nodes = p->bvh.nnodes;
    in->bvh_depth = p->bvh.depth;
    in->bvh_bytes = (size_t)p->bvh.nnodes * (sizeof(lc_kpnode) + sizeof(float));
    in->data_bytes = n * 7 * sizeof(float);
    lci_log(dev, LC_LOG_INFO, "rbf: %zu RBFs (%zu without support at eps %g), BVH %d nodes depth %d, range %g..%g, %.3f s",
            n, in->dropped, (double)in->eps, in->bvh_nodes, in->bvh_depth, (double)in->range[0],
            (double)in->range[1], in->build_seconds);
    if (in->accel == LC_RBF_ACCEL_OCTREE)
        lci_log(dev, LC_LOG_INFO, "rbf: octree %d cells (%d leaves) depth %d, %zu list entries (longest %zu), %.3f s",
                in->octree_cells, in->octree_leaves, in->octree_depth, in->octree_refs, in->octree_max_list,
                in->octree_seconds);
    peaks(dev, p);
    *out = &p->base;
    return LC_OK;
}

lc_status lc_rbf_create(lc_device *dev, const lc_rbf_desc *desc, lc_volume **out)
{
    if (!dev) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_rbf_create: device is NULL");
    if (!out) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_rbf_create: out is NULL");
    *out = NULL;
    if (!desc) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_rbf_create: desc is NULL");
    return create(dev, desc, out);
}

/* No kept RBF and no domain: nothing to sample. */
static int is_empty(const rbf *p) { return p->info.count == 0 && box_is_zero(&p->info.bounds); }

static lc_status frame_info(lc_device *dev, const lc_volume *v, lci_frame_info *out)
{
    (void)dev;
    const rbf *p = (const rbf *)v;
    const lc_box3 *b = &p->info.bounds;
    out->bounds = *b;
    /* a quarter of the smallest width resolves every Gaussian (as particles); no RBF:
       the constant bias needs no resolution, 1/256 of the domain's diagonal */
    float dx = b->hi.x - b->lo.x, dy = b->hi.y - b->lo.y, dz = b->hi.z - b->lo.z;
    float diag = sqrtf(dx * dx + dy * dy + dz * dz);
    out->default_dt = p->info.count ? 0.25f * p->info.min_width : diag > 0.0f ? diag / 256.0f : 1.0f;
    /* the TF maps from the bias, the set's background (an encoded volume's empty
       space), to the largest value at the centres, so the background is
       transparent by default; a set of only negative terms maps from its
       smallest value to the bias */
    float w0 = p->info.bias;
    out->default_range[0] = p->peak[1] > w0 ? w0 : p->peak[0];
    out->default_range[1] = p->peak[1] > w0 ? p->peak[1] : w0;
    if (!(out->default_range[1] > out->default_range[0])) out->default_range[1] = out->default_range[0] + 1.0f;
    out->nfields = 1;
    return LC_OK;
}

static lc_krbf *kscene(lc_device *dev, const rbf *p)
{
    lc_krbf *k = lci_aligned_alloc(64, sizeof *k);
    if (!k) {
        lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "out of memory for the RBF scene");
        return NULL;
    }
    k->nodes = p->bvh.nodes;
    k->node_rmax = p->bvh.rmax;
    k->cx = p->cx, k->cy = p->cy, k->cz = p->cz;
    k->r2 = p->r2, k->nis = p->nis, k->w = p->w;
    k->count = (int64_t)p->info.count;
    k->nnodes = p->bvh.nnodes;
    k->depth = p->bvh.depth;
    k->bias = p->info.bias;
    k->empty = is_empty(p);
    const lc_box3 *b = &p->info.bounds;
    k->lo[0] = b->lo.x, k->lo[1] = b->lo.y, k->lo[2] = b->lo.z;
    k->hi[0] = b->hi.x, k->hi[1] = b->hi.y, k->hi[2] = b->hi.z;
    k->cells = p->oct.cells, k->cell_list = p->oct.list, k->cell_corr = p->oct.corr;
    k->ncells = p->oct.ncells;
    return k;
}

/* The coherent method: the set as the particle kind's kernel reads it
 * (kparticles.h), rendered by that kind's coherent kernel. A dvr frame also
 * gets transparent-space skipping: the TF's transparent values (at or below
 * clear_below) and the nodes whose bound node_hi lies there, exactly as for
 * particles but with the bias inside the bound, and the bias itself when it
 * is transparent (bias_clear). */
static lc_status prepare_coherent(lc_device *dev, const rbf *p, const lc_kframe *frame, lci_prepared *out)
{
    const int nn = p->bvh.nnodes, dvr = frame->mode == LC_KMODE_DVR;
    size_t head = (sizeof(lc_kparticles) + 63) & ~(size_t)63;
    lc_kparticles *k = lci_aligned_alloc(64, head + (dvr ? (size_t)nn : 0));
    if (!k) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_render: out of memory for the RBF scene");
    memset(k, 0, sizeof *k);
    k->nodes = p->bvh.nodes;
    k->node_rmax = p->bvh.rmax; /* the largest R below each node: sigma = 1 */
    k->node_ksum = p->node_wsum;
    k->px = p->cx, k->py = p->cy, k->pz = p->cz;
    k->r = p->R;              /* support test d^2 < R^2 */
    k->neg_inv_2r2 = p->nis;  /* -1 / (2 s^2) */
    k->k = p->w;
    k->field = p->field0;
    k->count = (int64_t)p->info.count;
    k->nnodes = nn;
    k->depth = p->bvh.depth;
    k->nfields = 1;
    k->buffer_k = 128; /* the particle kind's capacity for one field, the pass length adapted per group */
    k->buffer_adapt = 1;
    k->sigma = 1.0f, k->kappa = 1.0f;
    k->max_radius = p->info.max_support;
    const lc_box3 *b = &p->info.bounds; /* the domain: the lattice clip box of every method */
    k->lo[0] = b->lo.x, k->lo[1] = b->lo.y, k->lo[2] = b->lo.z;
    k->hi[0] = b->hi.x, k->hi[1] = b->hi.y, k->hi[2] = b->hi.z;
    k->bias = p->info.bias;
    /* LANECAST_PARTICLE_CONE=0 turns off the particle kernel's per-vector cone
       pre-test here as for particles (tests, A/B runs): the same image, bit for bit */
    k->cone_off = lci_pcone_off();
    if (dvr) {
        float cb = lci_tf_clear_below(&frame->tf[0]);
        k->bias_clear = k->bias <= cb;
        uint8_t *flags = (uint8_t *)k + head;
        long n_clear = 0;
        for (int32_t n = 0; n < nn; n++) {
            flags[n] = (uint8_t)(p->node_hi[n] <= cb);
            n_clear += flags[n];
        }
        k->node_clear = n_clear ? flags : NULL;
    }
    const lc_kkind *kk = dev->kt->kind[LC_KKIND_RBF];
    out->tile = kk->render[LC_KMETHOD_COHERENT];
    out->kscene = k;
    out->scratch_bytes = kk->scratch_bytes[LC_KMETHOD_COHERENT](k, frame);
    out->owned = k; /* freed with free(): posix_memalign memory */
    return LC_OK;
}

static lc_status prepare(lc_device *dev, const lc_volume *v, const lc_render_desc *d, const lc_kframe *frame,
                         lci_prepared *out)
{
    static const char *const names[] = {"default", "coherent", "direct", "bvh", "brute"};
    lc_method m = d->method;
    if (m != LC_METHOD_DEFAULT && m != LC_METHOD_COHERENT && m != LC_METHOD_BVH && m != LC_METHOD_BRUTE)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "method %s does not apply to RBF sets (coherent, bvh or brute)",
                         (int)m >= 0 && (int)m < 5 ? names[m] : "(unknown)");
    const rbf *p = (const rbf *)v;
    if (m == LC_METHOD_DEFAULT && p->info.accel == LC_RBF_ACCEL_COHERENT) m = LC_METHOD_COHERENT;
    /* no term: the field is w0 on the domain, which the particle kernel (it
       renders nothing without a node) leaves to the BVH method */
    if (m == LC_METHOD_COHERENT && p->info.count > 0) return prepare_coherent(dev, p, frame, out);
    if (m == LC_METHOD_COHERENT) m = LC_METHOD_BVH;
    lc_krbf *k = kscene(dev, p);
    if (!k) return LC_ERROR_OUT_OF_MEMORY;
    /* DEFAULT: the set's accel; BVH and BRUTE on any set (the BVH is always built) */
    int km = m == LC_METHOD_BRUTE                                                ? LC_KMETHOD_BASE
             : m == LC_METHOD_DEFAULT && p->info.accel == LC_RBF_ACCEL_OCTREE ? LC_KMETHOD_CELLS
                                                                              : LC_KMETHOD_FAST;
    const lc_kkind *kk = dev->kt->kind[LC_KKIND_RBF];
    out->tile = kk->render[km];
    out->kscene = k;
    out->scratch_bytes = kk->scratch_bytes[km](k, frame);
    out->owned = k; /* freed with free(): posix_memalign memory */
    return LC_OK;
}

static lc_status sample_scene(lc_device *dev, const lc_volume *v, void **ks, uint64_t *scratch_bytes)
{
    lc_krbf *k = kscene(dev, (const rbf *)v);
    if (!k) return LC_ERROR_OUT_OF_MEMORY;
    *ks = k;
    *scratch_bytes = dev->kt->kind[LC_KKIND_RBF]->sample_scratch_bytes(k);
    return LC_OK;
}

/* Build options a file load may carry (lc_load_desc), applied to the desc. */
static lc_status set_option(lc_device *dev, void *desc, const lc_option *o, const char *file)
{
    lc_rbf_desc *d = desc;
    if (!strcmp(o->key, "leaf_size")) return lci_option_int(dev, file, o, 1, 32, &d->leaf_size);
    if (!strcmp(o->key, "eps")) return lci_option_float(dev, file, o, 0.0f, 1e30f, &d->eps);
    if (!strcmp(o->key, "cell_max")) return lci_option_int(dev, file, o, 1, LC_RBF_MAX_CELL, &d->cell_max);
    if (!strcmp(o->key, "significant")) return lci_option_int(dev, file, o, 0, 1, &d->significant);
    if (!strcmp(o->key, "accel")) {
        if (!strcmp(o->value, "bvh")) d->accel = LC_RBF_ACCEL_BVH;
        else if (!strcmp(o->value, "octree")) d->accel = LC_RBF_ACCEL_OCTREE;
        else if (!strcmp(o->value, "coherent")) d->accel = LC_RBF_ACCEL_COHERENT;
        else
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: accel = '%s', expected coherent, bvh or octree",
                             file, o->value);
        return LC_OK;
    }
    if (!strcmp(o->key, "domain")) {
        float v[6];
        lc_status s = lci_option_floats(dev, file, o, 6, v);
        if (s == LC_OK) d->domain = (lc_box3){{v[0], v[1], v[2]}, {v[3], v[4], v[5]}};
        return s;
    }
    return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: option '%s' does not apply to RBF sets", file, o->key);
}

const lci_kind_ops lci_rbf_ops = {
    .kind = LC_KIND_RBF,
    .name = "rbf",
    .krow = LC_KKIND_RBF,
    .option_keys = "leaf_size eps domain accel cell_max significant",
    .create = create,
    .set_option = set_option,
    .destroy = destroy,
    .frame_info = frame_info,
    .prepare = prepare,
    .sample_scene = sample_scene,
};

lc_status lci_rbf_centres(const lc_volume *v, size_t *n, const float **x, const float **y, const float **z)
{
    const rbf *p = lci_volume_as(v, LC_KIND_RBF, "lci_rbf_centres");
    if (!p) return LC_ERROR_INVALID_ARGUMENT;
    *n = p->info.count, *x = p->cx, *y = p->cy, *z = p->cz;
    return LC_OK;
}
