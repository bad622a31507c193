/* RBF sets (Jang et al. 2004): creation (the build, from validation to the
 * BVH, octree and value range, is host/kinds/rbf_build.c), info, the
 * default TF range from the field at the centres, and the per-frame kernel scene: lc_krbf for the
 * BVH gather, brute force and the octree (kernels/rbf*.c), or the particle
 * view lc_kparticles for the coherent method, which runs the particle kind's
 * coherent kernel (kparticles.h says how a term maps onto a particle). Render
 * only: no encoder. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/kinds/rbf.h"
#include "host/api/tf.h"
#include "host/kinds/particles_frame.h"
#include "bvh/particle_bvh.h"
#include "bvh/rbf_octree.h"
#include "kernels/shared/krbf.h"
#include "kernels/shared/ktable.h"

static void destroy(lc_volume *v)
{
    rbf *p = (rbf *)v;
    if (!p) return;
    lci_pbvh_free(&p->bvh);
    lci_octree_free(&p->oct);
    free(p->cx), free(p->cy), free(p->cz), free(p->r2), free(p->nis), free(p->w), free(p->R);
    free(p->node_wsum), free(p->node_hi), free(p->field0);
    if (p->part_free) p->part_free(p->part);
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
    lc_status s = lci_rbf_check_desc(dev, d);
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
    in->eps = lci_rbf_pick_eps(d);
    in->leaf_size = d->leaf_size ? d->leaf_size : 4;
    in->accel = lci_rbf_resolve_accel(d);
    if (in->accel == LC_RBF_ACCEL_OCTREE) in->cell_max = d->cell_max ? d->cell_max : 32, in->significant = d->significant;
    double t0 = lci_now();
    size_t n = lci_rbf_keep(d, in->eps, xyz, R, src, &in->support_bounds);
    in->count = n;
    in->dropped = d->count - n;
    in->bounds = lci_rbf_box_is_zero(&d->domain) ? in->support_bounds : d->domain;
    s = lci_rbf_build(dev, p, d, xyz, R, src, n);
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
static int is_empty(const rbf *p) { return p->info.count == 0 && lci_rbf_box_is_zero(&p->info.bounds); }

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
    out->default_dt = p->info.count || p->global_count ? 0.25f * p->info.min_width : diag > 0.0f ? diag / 256.0f : 1.0f;
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
    if (p->part && !frame->has_region)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "lc_render: these %zu RBFs are one rank's part of %zu (lc_mpi_volume_load): render them with "
                         "lc_mpi_render",
                         p->info.count, p->global_count);
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
    if (!strcmp(o->key, "canonical_order")) return lci_option_order(dev, file, o, &d->canonical_order);
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
    .option_keys = "leaf_size eps domain accel cell_max significant canonical_order",
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

void lci_rbf_global_of(const lc_volume *v, lci_rbf_global *g)
{
    const rbf *p = (const rbf *)v;
    g->count = p->info.count;
    g->peak[0] = p->peak[0], g->peak[1] = p->peak[1];
    g->min_width = p->info.min_width, g->max_width = p->info.max_width, g->max_support = p->info.max_support;
    g->range[0] = p->info.range[0], g->range[1] = p->info.range[1];
}

void lci_rbf_set_global(lc_volume *v, const lci_rbf_global *g, void *part, void (*part_free)(void *))
{
    rbf *p = (rbf *)v;
    p->global_count = g->count;
    p->peak[0] = g->peak[0], p->peak[1] = g->peak[1];
    p->info.min_width = g->min_width, p->info.max_width = g->max_width, p->info.max_support = g->max_support;
    p->info.range[0] = g->range[0], p->info.range[1] = g->range[1];
    if (p->part_free) p->part_free(p->part);
    p->part = part, p->part_free = part_free;
}

void *lci_rbf_part(const lc_volume *v) { return lc_volume_kind(v) == LC_KIND_RBF ? ((const rbf *)v)->part : NULL; }
