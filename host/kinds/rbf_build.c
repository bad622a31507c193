/* The build of an RBF set (Jang et al. 2004; host/kinds/rbf.c creates it):
 * descriptor checks, the truncation supports of eq. 3, the BVH over the
 * supports (the particle builder, radius = R_i), the leaf-ordered arrays, a
 * conservative value range, and the adaptive octree when asked for. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/kinds/rbf.h"
#include "host/api/tf.h"

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

int lci_rbf_box_is_zero(const lc_box3 *b)
{
    return b->lo.x == 0.0f && b->lo.y == 0.0f && b->lo.z == 0.0f && b->hi.x == 0.0f && b->hi.y == 0.0f &&
           b->hi.z == 0.0f;
}

/* LC_RBF_ACCEL_DEFAULT: the fastest on the measured sets (docs/bench/rbf.md),
 * the coherent method; the octree when an octree option (cell_max,
 * significant) asks for one. */
lc_rbf_accel lci_rbf_resolve_accel(const lc_rbf_desc *d)
{
    if (d->accel != LC_RBF_ACCEL_DEFAULT) return d->accel;
    return d->cell_max || d->significant ? LC_RBF_ACCEL_OCTREE : LC_RBF_ACCEL_COHERENT;
}

/* The descriptor's scalar checks; the per-RBF ones follow in create. */
lc_status lci_rbf_check_desc(lc_device *dev, const lc_rbf_desc *d)
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
    if (d->significant && lci_rbf_resolve_accel(d) != LC_RBF_ACCEL_OCTREE)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "%s: significant = 1 keeps the most significant RBFs of octree cells; it needs accel = octree",
                         fn);
    if (!(d->eps >= 0.0f) || !isfinite(d->eps))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: eps = %g, expected 0 (default) or a finite value > 0",
                         fn, (double)d->eps);
    const lc_box3 *b = &d->domain;
    if (!lci_rbf_box_is_zero(b)) {
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
float lci_rbf_pick_eps(const lc_rbf_desc *d)
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
size_t lci_rbf_keep(const lc_rbf_desc *d, float eps, float *xyz, float *R, size_t *src, lc_box3 *sb)
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
lc_status lci_rbf_build(lc_device *dev, rbf *p, const lc_rbf_desc *d, const float *xyz, const float *R,
                       const size_t *src, size_t n)
{
    lc_rbf_info *in = &p->info;
    char err[256];
    if (n > 0) {
        void *e = lci_embree_device(dev);
        if (!e) return LC_ERROR_INTERNAL;
        /* canonical: ordered over the domain (a part's is the whole set's), ties by width and weight */
        const lc_box3 *b = &in->bounds;
        lci_pbvh_keys q = {{b->lo.x, b->lo.y, b->lo.z}, {b->hi.x, b->hi.y, b->hi.z}, {d->widths, d->weights, NULL},
                           NULL, src};
        int canon = lci_pbvh_canonical(d->canonical_order);
        if (canon ? lci_pbvh_build_canonical(xyz, R, 0.0f, n, in->leaf_size, &q, &p->bvh, err, sizeof err)
                  : lci_pbvh_build(e, xyz, R, 0.0f, n, in->leaf_size, &p->bvh, err, sizeof err))
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

