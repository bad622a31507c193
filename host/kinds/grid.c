/* Structured grids (Knoll et al. 2011): the lc_grid object (voxels in the
 * caller's linear array or our 4^3-bricked copy behind offset tables, §6.1),
 * its implicit min-max BVH (bvh/grid_bvh.c), and its row of kind operations. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "host/kinds/grid.h"

#define GATHER_PAD 64
/* Owned uint8 grids up to lci_grid_pairs_max voxels keep the y-pair-packed
 * copy (lc_kgrid.pairs) in place of the voxels: 2 bytes a voxel instead of 1
 * (the kernels sample only the copy). Measured at 1024^2, avx512, 2
 * threads (docs/bench/grid.md "The uint8 copies"): 512^3 1.2-1.3x less CPU per
 * frame with it; since the software-pipelined sample loop also 768^3 and
 * 896^3 (1.2-1.4x) and 1024^3 (1.14-1.38x; before the pipelining, at
 * 63f139c, 1024^3 was 1.07-1.25x slower with it). The bound is 1024^3
 * voxels (a 2 GiB copy): beyond it the copy's int32 element offsets
 * (kgrid.h) come near 2^31, and larger volumes keep only the bricks. */
int64_t lci_grid_pairs_max = (int64_t)1 << 30; /* tests lower it (tests/test_grid_nopairs.c) */
/* ... and up to lci_grid_quads_max voxels the copy is z-paired too (4 bytes a
 * voxel, lc_kgrid.pair_quads): one 64-bit gather lane per sample instead of
 * two 32-bit ones (docs/bench/grid.md "The uint8 copies"). */
int64_t lci_grid_quads_max = (int64_t)1 << 25; /* tests change it (tests/test_grid_quads.c) */
/* nodes per axis: every index up to size - 2 is exact in float32 */
#define MAX_AXIS (1 << 24)

int lci_value_size(lc_value_type t)
{
    switch (t) {
    case LC_VALUE_UINT8: return 1;
    case LC_VALUE_UINT16:
    case LC_VALUE_INT16: return 2;
    case LC_VALUE_FLOAT32: return 4;
    default: return 0;
    }
}

static const char *type_name(lc_value_type t)
{
    switch (t) {
    case LC_VALUE_UINT8: return "uint8";
    case LC_VALUE_UINT16: return "uint16";
    case LC_VALUE_INT16: return "int16";
    case LC_VALUE_FLOAT32: return "float32";
    default: return "unknown";
    }
}

static int kval(lc_value_type t)
{
    return t == LC_VALUE_UINT8 ? LC_KVAL_U8 : t == LC_VALUE_UINT16 ? LC_KVAL_U16 : t == LC_VALUE_INT16 ? LC_KVAL_I16 : LC_KVAL_F32;
}


static void destroy(lc_volume *v);


/* What create decides from a valid desc. */
typedef struct shape {
    int es;             /* bytes per value */
    int64_t count;      /* values */
    int32_t n[3];
    lc_vec3 sp;         /* spacing, defaults filled in */
    int L;              /* BVH leaf side */
    lc_grid_layout layout;
    int borrow;
} shape;

/* Checks a desc (one message naming what is wrong) and fills the shape. */
static lc_status validate(lc_device *dev, const lc_grid_desc *d, const char *name, shape *sh)
{
    lc_status s = LC_OK;
    const void *src = d->data;
    int es = lci_value_size(d->type);
    if (!es) {
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: value type %d is not uint8, uint16, int16 or float32", name,
                      (int)d->type);
        return s;
    }
    int64_t count = 1;
    for (int a = 0; a < 3; a++) {
        if (d->size[a] < 2) {
            s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: size %d x %d x %d: every size must be at least 2 nodes",
                          name, d->size[0], d->size[1], d->size[2]);
            return s;
        }
        /* the kernels locate samples in float32 node coordinates: past 2^24
         * nodes an axis has cells float cannot address, and the clamp of the
         * cell index to size - 2 rounds up to size - 1, so the +1 neighbour
         * of the last cell would be read one row, plane or element past the
         * array (found with a borrowed array ending at a guard page) */
        if (d->size[a] > MAX_AXIS) {
            s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                          "%s: size %d x %d x %d: at most %d nodes per axis (float32 sample coordinates)", name,
                          d->size[0], d->size[1], d->size[2], MAX_AXIS);
            return s;
        }
        if (count > LCI_GRID_MAX_ELEMENTS / d->size[a]) {
            s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                          "%s: size %d x %d x %d has more than 2^31 values (the kernels index voxels with 32 bits)",
                          name, d->size[0], d->size[1], d->size[2]);
            return s;
        }
        count *= d->size[a];
    }
    lc_vec3 sp = d->spacing;
    if (sp.x == 0.0f && sp.y == 0.0f && sp.z == 0.0f) sp = (lc_vec3){1.0f, 1.0f, 1.0f};
    if (!(sp.x > 0.0f && sp.y > 0.0f && sp.z > 0.0f && isfinite(sp.x) && isfinite(sp.y) && isfinite(sp.z))) {
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: spacing (%g, %g, %g): each must be finite and > 0", name,
                      (double)sp.x, (double)sp.y, (double)sp.z);
        return s;
    }
    if (!(isfinite(d->origin.x) && isfinite(d->origin.y) && isfinite(d->origin.z))) {
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: origin must be finite", name);
        return s;
    }
    int L = d->brick;
    int32_t n[3] = {d->size[0], d->size[1], d->size[2]};
    if (L == 0) L = lci_grid_bvh_default_brick(n);
    if (L != 1 && L != 2 && L != 4 && L != 8 && L != 16) {
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: brick %d, expected 1, 2, 4, 8 or 16", name, d->brick);
        return s;
    }
    lc_grid_layout layout = d->layout;
    int borrow = d->borrow != 0;
    /* default: linear for borrowed arrays (used in place) and for narrow
     * values (uint8, uint16, int16), whose linear layout fetches a cell's x
     * neighbours with one gather per pair (4 gathers a sample instead of 8):
     * 1.23-1.46x less CPU per frame than bricked on uint16 volumes (headsq,
     * proc256u16, proc512u16) in every view direction, 1.0-1.1x at 768^3
     * (docs/bench/grid.md "Layouts"); float32 stays bricked. (uint8 grids up
     * to lci_grid_pairs_max voxels sample their copy, whatever the layout.) */
    if (layout == LC_LAYOUT_DEFAULT)
        layout = borrow || d->type != LC_VALUE_FLOAT32 ? LC_LAYOUT_LINEAR : LC_LAYOUT_BRICKED;
    if (layout != LC_LAYOUT_LINEAR && layout != LC_LAYOUT_BRICKED) {
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: layout %d is not linear or bricked", name, (int)layout);
        return s;
    }
    if (borrow && layout == LC_LAYOUT_BRICKED) {
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: a borrowed array is used in place, so it cannot be bricked",
                      name);
        return s;
    }
    if (d->type == LC_VALUE_FLOAT32) {
        const float *f = src;
        for (int64_t i = 0; i < count; i++)
            if (!isfinite(f[i])) {
                s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: value %lld is not finite", name, (long long)i);
                return s;
            }
    }
    sh->es = es, sh->count = count, sh->sp = sp, sh->L = L, sh->layout = layout, sh->borrow = borrow;
    memcpy(sh->n, n, sizeof n);
    return LC_OK;
}


/* A window's own checks: inside the whole grid, starting on a brick row
 * (4 | start), the whole grid within the kernels' limits, owned (not borrowed). */
static lc_status check_window(lc_device *dev, const lc_grid_desc *d, const lci_grid_window *w, const char *name)
{
    int64_t full = 1;
    for (int a = 0; a < 3; a++) {
        if (w->full[a] < 2 || w->full[a] > MAX_AXIS || w->start[a] < 0 || w->start[a] % 4 ||
            w->start[a] + d->size[a] > w->full[a] || w->own0[a] < w->start[a] || w->own1[a] > w->start[a] + d->size[a] ||
            w->own0[a] > w->own1[a])
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                             "%s: axis %c: nodes %d .. %d (owning %d .. %d) are not a window of a grid of %d nodes", name,
                             "xyz"[a], w->start[a], w->start[a] + d->size[a] - 1, w->own0[a], w->own1[a] - 1, w->full[a]);
        full *= w->full[a];
    }
    if (full > LCI_GRID_MAX_ELEMENTS)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: the whole grid %d x %d x %d has more than 2^31 values", name,
                         w->full[0], w->full[1], w->full[2]);
    if (d->borrow) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: a window of a grid is copied, not borrowed", name);
    if (!w->bmin || !w->bmax) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: a window needs the brick ranges", name);
    return LC_OK;
}

static lc_status create_grid(lc_device *dev, const lc_grid_desc *desc, const lci_grid_window *w, lc_volume **out)
{
    lc_grid_desc dw;
    const lc_grid_desc *d = desc;
    const char *name = w ? "lci_grid_create_window" : "lc_grid_create";
    lc_status s = LC_OK;
    if (w) { /* the whole grid's leaf side, so its BVH is the whole grid's */
        dw = *desc;
        if (!dw.brick) dw.brick = lci_grid_bvh_default_brick(w->full);
        d = &dw;
        s = check_window(dev, d, w, name);
    }
    shape sh;
    memset(&sh, 0, sizeof sh);
    if (s == LC_OK) s = validate(dev, d, name, &sh);
    if (s != LC_OK) return s;
    grid *g = NULL;
    const void *src = d->data;
    int es = sh.es, L = sh.L, borrow = sh.borrow;
    int64_t count = sh.count;
    int32_t n[3] = {sh.n[0], sh.n[1], sh.n[2]};
    /* nf: the whole grid's nodes; s0: the first node held (0 0 0 unless a window) */
    int32_t nf[3] = {n[0], n[1], n[2]}, s0[3] = {0, 0, 0};
    int64_t count_full = count;
    if (w) {
        memcpy(nf, w->full, sizeof nf), memcpy(s0, w->start, sizeof s0);
        count_full = (int64_t)nf[0] * nf[1] * nf[2];
    }
    lc_vec3 sp = sh.sp;
    lc_grid_layout layout = sh.layout;
    g = calloc(1, sizeof *g);
    if (!g) goto oom;
    if (w) {
        g->window = malloc(sizeof *g->window);
        if (!g->window) goto oom;
        *g->window = *w;
        g->window->bmin = g->window->bmax = NULL;
        memcpy(g->window->count, n, sizeof n);
        g->windowed = 1;
    }
    g->base.ops = &lci_grid_ops;
    g->base.device = dev;
    g->info.params = d->params;
    if (pthread_mutex_init(&g->tables_mu, NULL) != 0) goto oom;
    g->tables_mu_init = 1;
    g->offsets = malloc(sizeof(int32_t) * ((size_t)nf[0] + (size_t)nf[1] + (size_t)nf[2]));
    if (!g->offsets) goto oom;
    int32_t *xo = g->offsets, *yo = xo + nf[0], *zo = yo + nf[1];
    /* owned uint8: a packed copy the kernels sample (2 or 4 bytes a voxel)
     * instead of the voxels; the kernels then never read the voxels, nor
     * does the host after the BVH build (lc_grid_histogram reads the copy) */
    int copy = 0;
    if (!borrow && d->type == LC_VALUE_UINT8)
        copy = count_full <= lci_grid_quads_max ? 2 : count_full <= lci_grid_pairs_max; /* a window samples as the whole */
    /* owned linear voxels (uint16, int16, float32 asked linear, uint8 past
     * the copies): rows and planes padded like the pair copy's; the kernels
     * read them through lc_kgrid.ystride / zstride, lc_grid_histogram through
     * the offset tables; borrowed arrays keep the caller's strides */
    int64_t ys = n[0], zs = (int64_t)n[0] * n[1];
    if (layout == LC_LAYOUT_LINEAR && !borrow && !copy) lci_grid_padded_strides(n, es, &ys, &zs);
    int64_t elements = zs * n[2];
    if (layout == LC_LAYOUT_BRICKED) lci_grid_brick_tables(n, nf, xo, yo, zo, &elements);
    else lci_grid_linear_tables(nf, ys, zs, xo, yo, zo);
    /* a window's element (i, j, k) of the whole grid's indices lies at
     * xo[i] + yo[j] + zo[k] - shift of what it holds; the kernels compute the
     * same offsets and read through data pointers moved back by shift */
    int64_t shift = (int64_t)xo[s0[0]] + yo[s0[1]] + zo[s0[2]];
    if (elements + shift > LCI_GRID_MAX_ELEMENTS) {
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: the bricked copy would exceed 2^31 values; use a linear layout",
                      name);
        goto fail;
    }
    const void *data = copy ? NULL : src;
    if (!borrow && !copy) {
        g->owned = lci_grid_voxel_alloc((size_t)elements * (size_t)es + GATHER_PAD);
        if (!g->owned) goto oom;
        const unsigned char *s8 = src;
        unsigned char *d8 = g->owned;
        for (int32_t k = 0; k < n[2]; k++)
            for (int32_t j = 0; j < n[1]; j++) {
                const unsigned char *row = s8 + ((size_t)k * (size_t)n[1] + (size_t)j) * (size_t)n[0] * (size_t)es;
                int64_t base = (int64_t)yo[s0[1] + j] + zo[s0[2] + k] - shift;
                const int32_t *xw = xo + s0[0];
                if (layout == LC_LAYOUT_LINEAR) { /* a row is contiguous; the padding stays zero */
                    memcpy(d8 + (size_t)(base + xw[0]) * (size_t)es, row, (size_t)n[0] * (size_t)es);
                    continue;
                }
                int32_t i = 0;
                for (; i + 4 <= n[0]; i += 4) /* a brick row holds 4 consecutive x */
                    memcpy(d8 + (size_t)(base + xw[i]) * (size_t)es, row + (size_t)i * (size_t)es, 4 * (size_t)es);
                for (; i < n[0]; i++)
                    memcpy(d8 + (size_t)(base + xw[i]) * (size_t)es, row + (size_t)i * (size_t)es, (size_t)es);
            }
        data = (const char *)g->owned - shift * es;
    }
    int64_t pys = n[0], pzs = (int64_t)n[0] * n[1];
    if (copy) {
        if (copy == 1) lci_grid_padded_strides(n, 2, &pys, &pzs);
        g->pair_bytes = (size_t)(pzs * n[2]) * (copy == 2 ? 4 : 2) + GATHER_PAD;
        g->pairs = lci_grid_voxel_alloc(g->pair_bytes);
        if (!g->pairs) goto oom;
        g->quads = copy == 2;
        if (copy == 2) lci_grid_build_quads(src, n, pys, pzs, g->pairs);
        else lci_grid_build_pairs(src, n, pys, pzs, g->pairs);
    }
    int64_t pshift = s0[0] + s0[1] * pys + s0[2] * pzs; /* the copy's element of node s0 */
    if (copy && pzs * n[2] + pshift > LCI_GRID_MAX_ELEMENTS) {
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: the window's sampling copy would exceed 2^31 values", name);
        goto fail;
    }
    float origin[3] = {d->origin.x, d->origin.y, d->origin.z}, spacing[3] = {sp.x, sp.y, sp.z};
    double t0 = lci_now();
    int brc = w ? lci_grid_bvh_from_ranges(w->bmin, w->bmax, nf, origin, spacing, L, &g->bvh)
                : lci_grid_bvh_build(src, kval(d->type), n, origin, spacing, L, &g->bvh);
    if (brc != 0) goto oom;
    g->bvh.seconds = lci_now() - t0;
    lc_kgrid *k = &g->kg;
    k->data = data;
    k->xoff = xo, k->yoff = yo, k->zoff = zo;
    for (int a = 0; a < 3; a++) {
        k->size[a] = nf[a];
        k->origin[a] = origin[a];
        k->spacing[a] = spacing[a];
        k->inv_spacing[a] = 1.0f / spacing[a];
        k->lo[a] = origin[a];
        k->hi[a] = origin[a] + (float)(nf[a] - 1) * spacing[a];
        k->cell_lo[a] = (float)s0[a];
        k->cell_hi[a] = (float)(s0[a] + n[a] - 2);
    }
    k->type = kval(d->type);
    k->bricked = layout == LC_LAYOUT_BRICKED;
    k->ystride = k->bricked ? 64 * ((n[0] + 3) / 4) : (int32_t)ys;
    k->zstride = k->bricked ? 64 * ((n[0] + 3) / 4) * ((n[1] + 3) / 4) : (int32_t)zs;
    k->pairs = g->pairs ? (const char *)g->pairs - pshift * (copy == 2 ? 4 : 2) : NULL;
    k->pair_quads = g->quads;
    k->pair_ystride = (int32_t)pys;
    k->pair_zstride = (int32_t)pzs;
    k->wide_safe = borrow ? (d->type == LC_VALUE_UINT8 ? count - 3 : count - 1) : INT64_MAX;
    k->nodes = g->bvh.nodes;
    k->nnodes = g->bvh.nnodes;
    k->depth = g->bvh.depth;
    float dx = k->hi[0] - k->lo[0], dy = k->hi[1] - k->lo[1], dz = k->hi[2] - k->lo[2];
    k->diag_volume = sqrtf(dx * dx + dy * dy + dz * dz);
    lc_grid_info *in = &g->info;
    for (int a = 0; a < 3; a++) in->size[a] = nf[a];
    in->type = d->type;
    in->spacing = sp;
    in->origin = d->origin;
    in->bounds.lo = (lc_vec3){k->lo[0], k->lo[1], k->lo[2]};
    in->bounds.hi = (lc_vec3){k->hi[0], k->hi[1], k->hi[2]};
    in->value_min = g->bvh.nodes[0].vmin;
    in->value_max = g->bvh.nodes[0].vmax;
    in->layout = layout;
    in->borrowed = borrow;
    in->data_bytes = (uint64_t)count * (uint64_t)es;
    uint64_t tables = sizeof(int32_t) * ((uint64_t)n[0] + (uint64_t)n[1] + (uint64_t)n[2]);
    in->layout_bytes = (borrow || copy ? 0 : (uint64_t)elements * (uint64_t)es + GATHER_PAD) + tables +
                       (uint64_t)g->pair_bytes;
    in->layout_overhead_bytes = borrow ? tables : in->layout_bytes - in->data_bytes;
    in->brick = L;
    in->copy_voxel_bytes = copy == 2 ? 4 : copy ? 2 : 0;
    in->bvh_nodes = (uint64_t)g->bvh.nnodes;
    in->bvh_leaves = (uint64_t)g->bvh.nleaves;
    in->bvh_bytes = g->bvh.bytes;
    in->bvh_depth = g->bvh.depth;
    in->bvh_build_seconds = g->bvh.seconds;
    if (g->bvh.depth > LC_KGRID_MAX_DEPTH) {
        s = lci_error(dev, LC_ERROR_INTERNAL, "%s: BVH depth %d exceeds the traversal stack", name, g->bvh.depth);
        goto fail;
    }
    lci_log(dev, LC_LOG_INFO, "%s: %dx%dx%d %s, %s (+%llu bytes), BVH L=%d: %d nodes, %llu bytes, depth %d, %.3f s",
            name, n[0], n[1], n[2], type_name(d->type),
            copy == 2 ? "z-paired sampling copy" : copy ? "y-paired sampling copy"
            : layout == LC_LAYOUT_BRICKED ? "bricked layout" : "linear layout",
            (unsigned long long)in->layout_overhead_bytes, L, g->bvh.nnodes, (unsigned long long)g->bvh.bytes,
            g->bvh.depth, g->bvh.seconds);
    *out = &g->base;
    return LC_OK;
oom:
    s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for a %d x %d x %d grid", name, d->size[0], d->size[1],
                  d->size[2]);
fail:
    if (g && g->window) g->window->user_free = NULL; /* the caller keeps user on failure */
    destroy(g ? &g->base : NULL);
    return s;
}

lc_status lc_grid_create(lc_device *dev, const lc_grid_desc *desc, lc_volume **out)
{
    if (out) *out = NULL;
    if (!dev) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_grid_create: device is NULL");
    if (!desc || !out || !desc->data)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_grid_create: desc, data and out must not be NULL");
    return create_grid(dev, desc, NULL, out);
}

static lc_status create(lc_device *dev, const void *desc, lc_volume **out) { return create_grid(dev, desc, NULL, out); }

lc_status lci_grid_create_window(lc_device *dev, const lc_grid_desc *desc, const lci_grid_window *w, lc_volume **out)
{
    *out = NULL;
    if (!desc || !desc->data || !w)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lci_grid_create_window: desc, data and window must not be NULL");
    return create_grid(dev, desc, w, out);
}

int lci_grid_window_of(const lc_volume *v, lci_grid_window *w)
{
    if (!v || lc_volume_kind(v) != LC_KIND_GRID) return 0;
    const grid *g = (const grid *)v;
    if (!g->windowed) return 0;
    if (w) *w = *g->window;
    return 1;
}

static void destroy(lc_volume *v)
{
    grid *g = (grid *)v;
    if (!g) return;
    lci_vcache_release(g->tables);
    if (g->tables_mu_init) pthread_mutex_destroy(&g->tables_mu);
    lci_grid_bvh_free(&g->bvh);
    lci_aligned_free(g->owned);
    lci_aligned_free(g->pairs);
    free(g->offsets);
    if (g->window && g->window->user_free) g->window->user_free(g->window->user);
    free(g->window);
    free(g);
}

lc_status lc_grid_get_info(const lc_volume *v, lc_grid_info *out)
{
    const grid *g = lci_volume_as(v, LC_KIND_GRID, "lc_grid_get_info");
    if (!g) return LC_ERROR_INVALID_ARGUMENT;
    if (!out) return lci_error(v->device, LC_ERROR_INVALID_ARGUMENT, "lc_grid_get_info: out is NULL");
    *out = g->info;
    return LC_OK;
}

static lc_status check_params(lc_device *dev, const char *fn, const lc_grid_params *p)
{
    if (!(isfinite(p->rda) && p->rda >= 0.0f && p->rda <= 1.0f))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: rda = %g, expected 0 (off) to 1", fn, (double)p->rda);
    if (!isfinite(p->delta_c) || !isfinite(p->delta_p) || !isfinite(p->delta_sv))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: grid heuristics delta_c, delta_p, delta_sv must be finite",
                         fn);
    return LC_OK;
}

lc_status lc_grid_set_params(lc_volume *v, const lc_grid_params *params)
{
    grid *g = lci_volume_as(v, LC_KIND_GRID, "lc_grid_set_params");
    if (!g) return LC_ERROR_INVALID_ARGUMENT;
    lc_grid_params p = params ? *params : (lc_grid_params){0};
    lc_status s = check_params(v->device, "lc_grid_set_params", &p);
    if (s == LC_OK) g->info.params = p;
    return s;
}

static lc_status frame_info(lc_device *dev, const lc_volume *v, lci_frame_info *out)
{
    (void)dev;
    const grid *g = (const grid *)v;
    out->bounds = g->info.bounds;
    float sp = fminf(g->info.spacing.x, fminf(g->info.spacing.y, g->info.spacing.z));
    out->default_dt = 0.5f * sp;
    out->default_range[0] = g->info.value_min;
    out->default_range[1] = g->info.value_max > g->info.value_min ? g->info.value_max : g->info.value_min + 1.0f;
    out->nfields = 1;
    return LC_OK;
}

static float param(float v, float def) { return v == 0.0f ? def : v; }

/* A grid's frame: its kernel scene and a reference to the tables it reads. */
typedef struct prep_block {
    lc_kgrid k;
    lci_grid_tables *t;
} prep_block;

static void prep_release(void *owned)
{
    prep_block *pb = owned;
    if (!pb) return;
    lci_grid_tables_release(pb->t);
    free(pb);
}

static lc_status prepare(lc_device *dev, const lc_volume *v, const lc_render_desc *desc, const lc_kframe *frame,
                         lci_prepared *out)
{
    const grid *g = (const grid *)v;
    const lc_grid_params *p = &g->info.params;
    lc_method m = desc->method;
    if (m != LC_METHOD_DEFAULT && m != LC_METHOD_BVH && m != LC_METHOD_BRUTE)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "grids render with method bvh or brute, not %d", (int)m);
    lc_status s = check_params(dev, "lc_render", p);
    if (s == LC_OK && g->windowed && !frame->has_region)
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                      "lc_render: this grid holds region %d's part of a %d x %d x %d grid (lc_mpi_volume_load): render it "
                      "with lc_mpi_render",
                      g->window->part, g->window->full[0], g->window->full[1], g->window->full[2]);
    if (s != LC_OK) return s;
    prep_block *pb = malloc(sizeof *pb);
    if (!pb) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_render: out of memory for the grid's frame");
    lc_kgrid *k = &pb->k;
    *k = g->kg;
    k->run_max = 48;
    /* nodes narrower than three packet footprints at 512 rows (at least two
     * at the frame's rows) are leaves (exact; docs/bench/grid.md "Footprint
     * pruning by node size": 3 best of 1-3 at 512^2, 6 of 2-12 at 1024^2, i.e. the same
     * node size; at 256^2 two of the frame's footprints) */
    k->prune_footprint = 3.0f;
    k->use_preint = p->preintegrated != 0;
    k->rda = p->rda;
    k->delta_c = param(p->delta_c, 1e-3f);
    k->delta_p = param(p->delta_p, 1.5f);
    k->delta_sv = param(p->delta_sv, 1e-4f);
    k->bvh_flags = (k->delta_c >= 0.0f ? LC_KGRID_CULL : 0) | (k->delta_p >= 0.0f ? LC_KGRID_PRUNE : 0) |
                   (k->delta_sv >= 0.0f ? LC_KGRID_CONST : 0);
    /* the pre-integrated table and eqs. 5-7 per node for this frame (kgrid.h
     * node_tf_bits; brute force reads no node bits), cached on the volume
     * while the TF, dt and parameters stay the same (grid_tables.c). The
     * cache is the volume's internal state behind its own lock. */
    pb->t = lci_grid_tables_get((grid *)g, k, frame, m != LC_METHOD_BRUTE);
    if (!pb->t) {
        free(pb);
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_render: out of memory for the pre-integrated table");
    }
    lci_grid_tables_fill(pb->t, k);
    int km = m == LC_METHOD_BRUTE ? LC_KMETHOD_BASE : LC_KMETHOD_FAST;
    const lc_kkind *kk = dev->kt->kind[LC_KKIND_GRID];
    out->tile = kk->render[km];
    out->kscene = k;
    out->scratch_bytes = kk->scratch_bytes[km](k, frame);
    out->owned = pb;
    out->release = prep_release;
    return LC_OK;
}

static lc_status sample_scene(lc_device *dev, const lc_volume *v, void **ks, uint64_t *scratch_bytes)
{
    lc_kgrid *k = lci_aligned_alloc(64, sizeof *k);
    if (!k) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_volume_sample: out of memory");
    *k = ((const grid *)v)->kg;
    *ks = k;
    *scratch_bytes = dev->kt->kind[LC_KKIND_GRID]->sample_scratch_bytes(k);
    return LC_OK;
}

/* Build options a file load may carry (lc_load_desc), applied to the desc. */
static lc_status set_option(lc_device *dev, void *desc, const lc_option *o, const char *file)
{
    lc_grid_desc *d = desc;
    if (!strcmp(o->key, "brick")) return lci_option_int(dev, file, o, 1, 16, &d->brick);
    if (!strcmp(o->key, "layout")) {
        if (!strcmp(o->value, "linear")) d->layout = LC_LAYOUT_LINEAR;
        else if (!strcmp(o->value, "bricked")) d->layout = LC_LAYOUT_BRICKED;
        else
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: option layout = '%s', expected linear or bricked",
                             file, o->value);
        return LC_OK;
    }
    return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: option '%s' does not apply to grids", file, o->key);
}

const lci_kind_ops lci_grid_ops = {
    .kind = LC_KIND_GRID,
    .name = "grid",
    .krow = LC_KKIND_GRID,
    .option_keys = "brick layout",
    .create = create,
    .set_option = set_option,
    .destroy = destroy,
    .frame_info = frame_info,
    .prepare = prepare,
    .sample_scene = sample_scene,
};

/* ---- histogram (lc_tf_auto's input) */

lc_status lc_grid_histogram(const lc_volume *v, int nbins, uint64_t *counts)
{
    const grid *g = lci_volume_as(v, LC_KIND_GRID, "lc_grid_histogram");
    if (!g) return LC_ERROR_INVALID_ARGUMENT;
    if (!counts || nbins < 1 || nbins > (1 << 24))
        return lci_error(v->device, LC_ERROR_INVALID_ARGUMENT,
                         "lc_grid_histogram: %d bins (expected 1 to 2^24) or counts is NULL", nbins);
    memset(counts, 0, sizeof *counts * (size_t)nbins);
    const lc_kgrid *k = &g->kg;
    double lo = g->info.value_min, hi = g->info.value_max;
    double scale = hi > lo ? nbins / (hi - lo) : 0.0;
    /* a window counts its own nodes (the parts' own ranges tile the grid) */
    int32_t o0[3] = {0, 0, 0}, o1[3] = {k->size[0], k->size[1], k->size[2]};
    if (g->windowed) memcpy(o0, g->window->own0, sizeof o0), memcpy(o1, g->window->own1, sizeof o1);
    for (int32_t z = o0[2]; z < o1[2]; z++)
        for (int32_t y = o0[1]; y < o1[1]; y++)
            for (int32_t x = o0[0]; x < o1[0]; x++) {
                int64_t e = (int64_t)k->xoff[x] + k->yoff[y] + k->zoff[z];
                int64_t el = x + (int64_t)y * k->pair_ystride + (int64_t)z * k->pair_zstride; /* the copy's */
                double val;
                if (k->pairs) /* the copy's low byte is the voxel (kgrid.h) */
                    val = k->pair_quads ? ((const uint32_t *)k->pairs)[el] & 0xff : ((const uint16_t *)k->pairs)[el] & 0xff;
                else switch (k->type) {
                case LC_KVAL_U8: val = ((const uint8_t *)k->data)[e]; break;
                case LC_KVAL_U16: val = ((const uint16_t *)k->data)[e]; break;
                case LC_KVAL_I16: val = ((const int16_t *)k->data)[e]; break;
                default: val = ((const float *)k->data)[e]; break;
                }
                long b = (long)((val - lo) * scale);
                counts[b < 0 ? 0 : b >= nbins ? nbins - 1 : b]++;
            }
    if (g->windowed && g->window->reduce) return g->window->reduce(g->window->user, counts, nbins);
    return LC_OK;
}
