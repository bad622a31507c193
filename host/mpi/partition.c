/* The kd-tree of a data-parallel render (dp.h): recursive bisection of the
 * data's box balanced by points or voxels, and the regions' visibility
 * order from the camera (SPEC.md "Regions"). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "host/mpi/dp.h"

typedef struct kd_build {
    lci_kdtree *t;
    const float *xyz[3];
    uint32_t *idx;      /* point indices, reordered in place per node */
    float *key;         /* scratch: the coordinates being split */
    int cells[3];
    double origin[3], cellw[3]; /* grid cells: the plane of cell boundary c on axis a */
    const lci_kd_peers *peers; /* points spread over holders (NULL: one holder) */
    uint32_t *ukey;     /* scratch for the distributed selection */
    int failed;
} kd_build;

static uint64_t kd_sum1(kd_build *k, uint64_t v)
{
    if (k->peers && k->peers->sum(k->peers->user, &v, 1) != LC_OK) k->failed = 1;
    return v;
}

/* A float's bits as an unsigned key in the floats' order (-0 just below +0). */
static uint32_t fkey(float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    return u & 0x80000000u ? ~u : u | 0x80000000u;
}

static float fkey_value(uint32_t u)
{
    u = u & 0x80000000u ? u & 0x7fffffffu : ~u;
    float f;
    memcpy(&f, &u, 4);
    return f;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* The m-th smallest coordinate (0-based) of the points of idx[i0 .. i1) over
 * every holder: the smallest key with at least m + 1 keys at or below it,
 * found by bisection of the 32-bit key range, one summed count a step; the
 * value of one of the points, the same float the one-holder sort gives. */
static float dist_select(kd_build *k, int axis, size_t i0, size_t i1, uint64_t m)
{
    size_t cnt = i1 - i0;
    for (size_t i = i0; i < i1; i++) k->ukey[i - i0] = fkey(k->xyz[axis][k->idx[i]]);
    if (cnt > 1) qsort(k->ukey, cnt, sizeof(uint32_t), cmp_u32);
    uint64_t lo = 0, hi = UINT32_MAX;
    while (lo < hi) {
        uint64_t mid = lo + (hi - lo) / 2;
        size_t a = 0, b = cnt; /* local keys <= mid: upper bound */
        while (a < b) {
            size_t c = a + (b - a) / 2;
            if ((uint64_t)k->ukey[c] <= mid) a = c + 1;
            else b = c;
        }
        if (kd_sum1(k, (uint64_t)a) >= m + 1) hi = mid;
        else lo = mid + 1;
    }
    return fkey_value((uint32_t)lo);
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* Builds the subtree of `nl` regions from leaf id `leaf0` over box b (cell
 * ranges c0..c1 for grids, points idx[i0 .. i1)); returns its node. */
static int build_node(kd_build *k, lc_box3 b, const int c0[3], const int c1[3], size_t i0, size_t i1, int nl,
                      int leaf0)
{
    lci_kdtree *t = k->t;
    int id = t->nnodes++;
    lci_kd_node *n = &t->node[id];
    if (nl == 1) {
        n->axis = -1, n->leaf = leaf0, n->child[0] = n->child[1] = -1, n->split = 0.0f;
        t->box[leaf0] = b;
        if (k->xyz[0]) t->weight[leaf0] = kd_sum1(k, (uint64_t)(i1 - i0));
        else t->weight[leaf0] = (uint64_t)(c1[0] - c0[0]) * (uint64_t)(c1[1] - c0[1]) * (uint64_t)(c1[2] - c0[2]);
        if (t->crange)
            for (int a = 0; a < 3; a++) t->crange[6 * leaf0 + a] = c0[a], t->crange[6 * leaf0 + 3 + a] = c1[a];
        return id;
    }
    float lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
    int axis = 0;
    for (int a = 1; a < 3; a++)
        if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
    int nleft = nl / 2;
    float split;
    size_t im = i0;
    int cl[3] = {c0[0], c0[1], c0[2]}, cr[3] = {c1[0], c1[1], c1[2]};
    if (k->xyz[0]) {
        uint64_t cnt = kd_sum1(k, (uint64_t)(i1 - i0)), m = (uint64_t)((double)cnt * nleft / nl);
        if (cnt == 0) {
            split = lo[axis] + (hi[axis] - lo[axis]) * (float)nleft / (float)nl;
        } else if (k->peers) {
            split = dist_select(k, axis, i0, i1, m);
            if (split > hi[axis]) split = hi[axis];
            if (split < lo[axis]) split = lo[axis];
        } else {
            for (size_t i = i0; i < i1; i++) k->key[i - i0] = k->xyz[axis][k->idx[i]];
            qsort(k->key, cnt, sizeof(float), cmp_float);
            split = m < cnt ? k->key[m] : nextafterf(k->key[cnt - 1], INFINITY);
            if (split > hi[axis]) split = hi[axis];
            if (split < lo[axis]) split = lo[axis];
        }
        /* points with x < split go left */
        size_t j = i0;
        for (size_t i = i0; i < i1; i++) {
            if (k->xyz[axis][k->idx[i]] < split) {
                uint32_t tmp = k->idx[i];
                k->idx[i] = k->idx[j];
                k->idx[j++] = tmp;
            }
        }
        im = j;
    } else {
        int w = c1[axis] - c0[axis];
        int c = c0[axis] + (int)lround((double)w * nleft / nl);
        split = (float)(k->origin[axis] + (double)c * k->cellw[axis]);
        if (c == k->cells[axis]) split = hi[axis]; /* the last plane is the box's own float */
        if (split > hi[axis]) split = hi[axis];
        if (split < lo[axis]) split = lo[axis];
        cl[axis] = c, cr[axis] = c;
    }
    n->axis = axis, n->leaf = -1, n->split = split;
    lc_box3 bl = b, br = b;
    float *bh = axis == 0 ? &bl.hi.x : axis == 1 ? &bl.hi.y : &bl.hi.z;
    float *bo = axis == 0 ? &br.lo.x : axis == 1 ? &br.lo.y : &br.lo.z;
    *bh = split, *bo = split;
    int left = build_node(k, bl, c0, cr, i0, im, nleft, leaf0);
    int right = build_node(k, br, cl, c1, im, i1, nl - nleft, leaf0 + nleft);
    t->node[id].child[0] = left, t->node[id].child[1] = right;
    return id;
}

/* Each region's cell: the splits of its ancestors, -+inf elsewhere. */
static void cells_of(lci_kdtree *t, int id, lc_kregion c)
{
    const lci_kd_node *n = &t->node[id];
    if (n->leaf >= 0) {
        t->cell[n->leaf] = c;
        return;
    }
    lc_kregion l = c, r = c;
    l.hi[n->axis] = n->split;
    r.lo[n->axis] = n->split;
    cells_of(t, n->child[0], l);
    cells_of(t, n->child[1], r);
}

/* The tree's arrays and the build's scratch (n points; ukey when distributed). */
static lc_status kd_alloc(lc_device *dev, int nleaves, size_t n, const float *x, kd_build *k, lci_kdtree *out)
{
    out->nleaves = nleaves;
    out->node = calloc((size_t)(2 * nleaves - 1), sizeof *out->node);
    out->cell = calloc((size_t)nleaves, sizeof *out->cell);
    out->box = calloc((size_t)nleaves, sizeof *out->box);
    out->weight = calloc((size_t)nleaves, sizeof *out->weight);
    if (!x) out->crange = calloc((size_t)nleaves * 6, sizeof *out->crange);
    if (x && n > 0) {
        k->idx = malloc(n * sizeof *k->idx);
        k->key = malloc(n * sizeof *k->key);
        if (k->peers) k->ukey = malloc(n * sizeof *k->ukey);
    }
    if (!out->node || !out->cell || !out->box || !out->weight || (!x && !out->crange) ||
        (x && n > 0 && (!k->idx || !k->key || (k->peers && !k->ukey))) || lci_test_fault("kd"))
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "kd-tree: out of memory for %d regions and %zu points", nleaves,
                         n);
    return LC_OK;
}

static lc_status kd_build_any(lc_device *dev, const lc_box3 *bounds, int nleaves, size_t n, const float *x,
                              const float *y, const float *z, const int cells[3], const lci_kd_peers *peers,
                              lci_kdtree *out)
{
    memset(out, 0, sizeof *out);
    if (nleaves < 1 || nleaves > 65536)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "kd-tree: %d regions, expected 1 to 65536", nleaves);
    kd_build k;
    memset(&k, 0, sizeof k);
    k.t = out;
    k.peers = peers;
    lc_status s = x && n > UINT32_MAX
                      ? lci_error(dev, LC_ERROR_UNSUPPORTED, "kd-tree: %zu points, at most %u", n, UINT32_MAX)
                      : kd_alloc(dev, nleaves, n, x, &k, out);
    /* every holder takes each sum of the build or none does */
    if (peers && peers->agree) s = peers->agree(dev, peers->user, s);
    if (s != LC_OK) {
        free(k.idx), free(k.key), free(k.ukey);
        lci_kd_release(out);
        return s;
    }
    int c0[3] = {0, 0, 0}, c1[3] = {0, 0, 0};
    if (x) {
        k.xyz[0] = x, k.xyz[1] = y, k.xyz[2] = z;
        for (size_t i = 0; i < n; i++) k.idx[i] = (uint32_t)i;
    } else {
        const float lo[3] = {bounds->lo.x, bounds->lo.y, bounds->lo.z}, hi[3] = {bounds->hi.x, bounds->hi.y, bounds->hi.z};
        for (int a = 0; a < 3; a++) {
            k.cells[a] = cells && cells[a] > 0 ? cells[a] : 1;
            k.origin[a] = lo[a];
            k.cellw[a] = ((double)hi[a] - (double)lo[a]) / k.cells[a];
            c1[a] = k.cells[a];
        }
    }
    build_node(&k, *bounds, c0, c1, 0, x ? n : 0, nleaves, 0);
    lc_kregion all;
    for (int a = 0; a < 4; a++) all.lo[a] = -INFINITY, all.hi[a] = INFINITY;
    cells_of(out, 0, all);
    free(k.idx);
    free(k.key);
    free(k.ukey);
    if (k.failed) {
        lci_kd_release(out);
        return lci_error(dev, LC_ERROR_INTERNAL, "kd-tree: summing the counts over the ranks failed");
    }
    return LC_OK;
}

lc_status lci_kd_build(lc_device *dev, const lc_box3 *bounds, int nleaves, size_t n, const float *x, const float *y,
                       const float *z, const int cells[3], lci_kdtree *out)
{
    return kd_build_any(dev, bounds, nleaves, n, x, y, z, cells, NULL, out);
}

lc_status lci_kd_build_dist(lc_device *dev, const lc_box3 *bounds, int nleaves, size_t n, const float *x,
                            const float *y, const float *z, const lci_kd_peers *peers, lci_kdtree *out)
{
    static const float none = 0.0f; /* a holder of no points still takes every step */
    lc_status s = !x && n > 0 ? lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "kd-tree: %zu points without coordinates", n)
                              : LC_OK;
    if (s != LC_OK) {
        memset(out, 0, sizeof *out);
        return peers->agree ? peers->agree(dev, peers->user, s) : s;
    }
    if (!x) x = y = z = &none;
    return kd_build_any(dev, bounds, nleaves, n, x, y, z, NULL, peers, out);
}

int lci_test_fault(const char *point)
{
    const char *e = getenv("LANECAST_TEST_FAULT");
    size_t k = strlen(point);
    for (const char *p = e ? strstr(e, point) : NULL; p; p = strstr(p + 1, point))
        if ((p == e || p[-1] == ',') && (p[k] == 0 || p[k] == ',')) return 1;
    return 0;
}

lc_status lci_kd_copy(lc_device *dev, const lci_kdtree *t, lci_kdtree *out)
{
    memset(out, 0, sizeof *out);
    size_t L = (size_t)t->nleaves, N = (size_t)t->nnodes;
    out->nleaves = t->nleaves, out->nnodes = t->nnodes;
    out->node = malloc(N * sizeof *out->node);
    out->cell = malloc(L * sizeof *out->cell);
    out->box = malloc(L * sizeof *out->box);
    out->weight = malloc(L * sizeof *out->weight);
    if (t->crange) out->crange = malloc(6 * L * sizeof *out->crange);
    if (!out->node || !out->cell || !out->box || !out->weight || (t->crange && !out->crange)) {
        lci_kd_release(out);
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "kd-tree: out of memory for a copy");
    }
    memcpy(out->node, t->node, N * sizeof *out->node);
    memcpy(out->cell, t->cell, L * sizeof *out->cell);
    memcpy(out->box, t->box, L * sizeof *out->box);
    memcpy(out->weight, t->weight, L * sizeof *out->weight);
    if (t->crange) memcpy(out->crange, t->crange, 6 * L * sizeof *out->crange);
    return LC_OK;
}

void lci_kd_release(lci_kdtree *t)
{
    free(t->node);
    free(t->cell);
    free(t->box);
    free(t->weight);
    free(t->crange);
    memset(t, 0, sizeof *t);
}

/* Front to back below node id: perspective rays start at the eye, so the
 * side of each split holding the eye comes first along every ray; parallel
 * (orthographic) rays meet the low side first when they travel up the axis. */
static void order_node(const lci_kdtree *t, int id, const lc_kcamera *cam, int *order, int *n)
{
    const lci_kd_node *nd = &t->node[id];
    if (nd->leaf >= 0) {
        order[(*n)++] = nd->leaf;
        return;
    }
    int near = cam->ortho ? (cam->forward[nd->axis] >= 0.0f ? 0 : 1) : (cam->eye[nd->axis] < nd->split ? 0 : 1);
    order_node(t, nd->child[near], cam, order, n);
    order_node(t, nd->child[1 - near], cam, order, n);
}

void lci_kd_order(const lci_kdtree *t, const lc_kcamera *cam, int *order)
{
    int n = 0;
    order_node(t, 0, cam, order, &n);
}
