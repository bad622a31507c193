/* Implicit min-max BVH over leaf bricks of L^3 cells (Knoll et al. 2011
 * §5.1). Leaf min/max cover the brick's nodes plus the forward neighbours
 * (L + 1 per axis): every voxel of the trilinear stencil of any point inside
 * the leaf box. The tree is a top-down median split of the brick list along
 * the axis of largest spatial extent; on a full regular array of bricks the
 * sorted-centroid median is the middle brick index, so no sort is needed.
 * Inner min/max are the union of the children's. */
#include "grid_bvh.h"
#include <float.h>
#include <stdlib.h>
#include <string.h>

int lci_grid_bvh_default_brick(const int32_t size[3])
{
    double n = (double)size[0] * (double)size[1] * (double)size[2];
    if (n <= 300.0 * 300.0 * 300.0) return 4;
    if (n < 1000.0 * 1000.0 * 1000.0) return 8;
    return 16;
}

#define ROW_MINMAX(T)                                                                                                  \
    static void row_minmax_##T(const void *row, int64_t a, int64_t b, float *mn, float *mx)                          \
    {                                                                                                                  \
        const T *r = (const T *)row;                                                                                   \
        T lo = r[a], hi = r[a];                                                                                        \
        for (int64_t i = a + 1; i <= b; i++) {                                                                         \
            lo = r[i] < lo ? r[i] : lo;                                                                                \
            hi = r[i] > hi ? r[i] : hi;                                                                                \
        }                                                                                                              \
        *mn = (float)lo;                                                                                               \
        *mx = (float)hi;                                                                                               \
    }
ROW_MINMAX(uint8_t)
ROW_MINMAX(uint16_t)
ROW_MINMAX(int16_t)
ROW_MINMAX(float)

typedef struct build {
    lc_kgrid_node *nodes;
    int32_t used, depth;
    const float *bmin, *bmax;
    int32_t nb[3];
    int L;
    int32_t size[3];
    float origin[3], spacing[3];
} build;

static float node_coord(const build *b, int axis, int64_t brick_index)
{
    int64_t n = brick_index * b->L;
    if (n > b->size[axis] - 1) n = b->size[axis] - 1;
    return b->origin[axis] + (float)n * b->spacing[axis];
}

/* Fills node `id` for bricks [r0, r1) per axis. */
static void build_node(build *b, int32_t id, const int32_t r0[3], const int32_t r1[3], int depth)
{
    lc_kgrid_node *n = &b->nodes[id];
    for (int a = 0; a < 3; a++) {
        n->lo[a] = node_coord(b, a, r0[a]);
        n->hi[a] = node_coord(b, a, r1[a]);
    }
    if (depth > b->depth) b->depth = depth;
    int axis = -1;
    float ext = -1.0f;
    for (int a = 0; a < 3; a++)
        if (r1[a] - r0[a] > 1 && n->hi[a] - n->lo[a] > ext) ext = n->hi[a] - n->lo[a], axis = a;
    if (axis < 0) { /* one brick: a leaf */
        size_t i = ((size_t)r0[2] * (size_t)b->nb[1] + (size_t)r0[1]) * (size_t)b->nb[0] + (size_t)r0[0];
        n->vmin = b->bmin[i];
        n->vmax = b->bmax[i];
        n->child = 0;
        n->axis = 0;
        return;
    }
    int32_t c = b->used;
    b->used += 2;
    n->child = c;
    n->axis = axis;
    int32_t mid = r0[axis] + (r1[axis] - r0[axis]) / 2;
    int32_t a1[3] = {r1[0], r1[1], r1[2]}, b0[3] = {r0[0], r0[1], r0[2]};
    a1[axis] = mid;
    b0[axis] = mid;
    build_node(b, c, r0, a1, depth + 1);
    build_node(b, c + 1, b0, r1, depth + 1);
    n = &b->nodes[id];
    n->vmin = b->nodes[c].vmin < b->nodes[c + 1].vmin ? b->nodes[c].vmin : b->nodes[c + 1].vmin;
    n->vmax = b->nodes[c].vmax > b->nodes[c + 1].vmax ? b->nodes[c].vmax : b->nodes[c + 1].vmax;
}

int lci_grid_bvh_build(const void *data, int type, const int32_t size[3], const float origin[3], const float spacing[3],
                       int L, lci_grid_bvh *out)
{
    memset(out, 0, sizeof *out);
    build b;
    memset(&b, 0, sizeof b);
    b.L = L;
    for (int a = 0; a < 3; a++) {
        b.size[a] = size[a];
        b.origin[a] = origin[a];
        b.spacing[a] = spacing[a];
        b.nb[a] = (size[a] - 1 + L - 1) / L;
    }
    size_t nbricks = (size_t)b.nb[0] * (size_t)b.nb[1] * (size_t)b.nb[2];
    float *bmin = malloc(nbricks * sizeof(float)), *bmax = malloc(nbricks * sizeof(float));
    lc_kgrid_node *nodes = calloc(2 * nbricks - 1, sizeof *nodes);
    if (!bmin || !bmax || !nodes) {
        free(bmin), free(bmax), free(nodes);
        return -1;
    }
    for (size_t i = 0; i < nbricks; i++) bmin[i] = FLT_MAX, bmax[i] = -FLT_MAX;
    void (*row_minmax)(const void *, int64_t, int64_t, float *, float *) =
        type == LC_KVAL_U8 ? row_minmax_uint8_t : type == LC_KVAL_U16 ? row_minmax_uint16_t
        : type == LC_KVAL_I16 ? row_minmax_int16_t : row_minmax_float;
    size_t esize = type == LC_KVAL_U8 ? 1 : type == LC_KVAL_F32 ? 4 : 2;
    float *rmn = malloc((size_t)b.nb[0] * sizeof(float)), *rmx = malloc((size_t)b.nb[0] * sizeof(float));
    if (!rmn || !rmx) {
        free(bmin), free(bmax), free(nodes), free(rmn), free(rmx);
        return -1;
    }
    /* each row of x is scanned once; a node on a brick face belongs to the
     * bricks on both sides (the +1 stencil) */
    for (int32_t k = 0; k < size[2]; k++) {
        int32_t zb[2], nz = 0;
        if (k / L < b.nb[2]) zb[nz++] = k / L;
        if (k % L == 0 && k > 0) zb[nz++] = k / L - 1;
        for (int32_t j = 0; j < size[1]; j++) {
            int32_t yb[2], ny = 0;
            if (j / L < b.nb[1]) yb[ny++] = j / L;
            if (j % L == 0 && j > 0) yb[ny++] = j / L - 1;
            const unsigned char *row = (const unsigned char *)data + ((size_t)k * (size_t)size[1] + (size_t)j) * (size_t)size[0] * esize;
            for (int32_t a = 0; a < b.nb[0]; a++) {
                int64_t x0 = (int64_t)a * L, x1 = x0 + L < size[0] - 1 ? x0 + L : size[0] - 1;
                row_minmax(row, x0, x1, &rmn[a], &rmx[a]);
            }
            for (int zi = 0; zi < nz; zi++)
                for (int yi = 0; yi < ny; yi++) {
                    size_t base = ((size_t)zb[zi] * (size_t)b.nb[1] + (size_t)yb[yi]) * (size_t)b.nb[0];
                    for (int32_t a = 0; a < b.nb[0]; a++) {
                        if (rmn[a] < bmin[base + a]) bmin[base + a] = rmn[a];
                        if (rmx[a] > bmax[base + a]) bmax[base + a] = rmx[a];
                    }
                }
        }
    }
    free(rmn), free(rmx);
    b.nodes = nodes;
    b.bmin = bmin;
    b.bmax = bmax;
    b.used = 1;
    int32_t r0[3] = {0, 0, 0};
    build_node(&b, 0, r0, b.nb, 1);
    free(bmin), free(bmax);
    out->nodes = nodes;
    out->nnodes = b.used;
    out->nleaves = (int32_t)nbricks;
    out->depth = b.depth;
    out->brick = L;
    out->bytes = (uint64_t)b.used * sizeof *nodes;
    return 0;
}

void lci_grid_bvh_free(lci_grid_bvh *bvh)
{
    if (!bvh) return;
    free(bvh->nodes);
    memset(bvh, 0, sizeof *bvh);
}
