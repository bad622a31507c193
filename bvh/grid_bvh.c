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

size_t lci_grid_bvh_bricks(const int32_t size[3], int L)
{
    size_t n = 1;
    for (int a = 0; a < 3; a++) n *= (size_t)((size[a] - 1 + L - 1) / L);
    return n;
}

void lci_grid_bvh_ranges_init(size_t nbricks, float *bmin, float *bmax)
{
    for (size_t i = 0; i < nbricks; i++) bmin[i] = FLT_MAX, bmax[i] = -FLT_MAX;
}

int lci_grid_bvh_ranges(const void *data, int type, const int32_t start[3], const int32_t count[3],
                        const int32_t size[3], int L, float *bmin, float *bmax)
{
    int32_t nb[3];
    for (int a = 0; a < 3; a++) nb[a] = (size[a] - 1 + L - 1) / L;
    void (*row_minmax)(const void *, int64_t, int64_t, float *, float *) =
        type == LC_KVAL_U8 ? row_minmax_uint8_t : type == LC_KVAL_U16 ? row_minmax_uint16_t
        : type == LC_KVAL_I16 ? row_minmax_int16_t : row_minmax_float;
    size_t esize = type == LC_KVAL_U8 ? 1 : type == LC_KVAL_F32 ? 4 : 2;
    float *rmn = malloc((size_t)nb[0] * sizeof(float)), *rmx = malloc((size_t)nb[0] * sizeof(float));
    if (!rmn || !rmx) {
        free(rmn), free(rmx);
        return -1;
    }
    /* the bricks the held x nodes reach: a brick's nodes are a L .. a L + L */
    int32_t xs = start[0], xe = start[0] + count[0] - 1; /* first and last node held */
    int32_t a0 = xs / L - (xs % L == 0 && xs > 0), a1 = xe / L < nb[0] ? xe / L : nb[0] - 1;
    /* each row of x is scanned once; a node on a brick face belongs to the
     * bricks on both sides (the +1 stencil) */
    for (int32_t kw = 0; kw < count[2]; kw++) {
        int32_t k = start[2] + kw, zb[2], nz = 0;
        if (k / L < nb[2]) zb[nz++] = k / L;
        if (k % L == 0 && k > 0) zb[nz++] = k / L - 1;
        for (int32_t jw = 0; jw < count[1]; jw++) {
            int32_t j = start[1] + jw, yb[2], ny = 0;
            if (j / L < nb[1]) yb[ny++] = j / L;
            if (j % L == 0 && j > 0) yb[ny++] = j / L - 1;
            const unsigned char *row =
                (const unsigned char *)data + ((size_t)kw * (size_t)count[1] + (size_t)jw) * (size_t)count[0] * esize;
            for (int32_t a = a0; a <= a1; a++) {
                int64_t x0 = (int64_t)a * L, x1 = x0 + L < size[0] - 1 ? x0 + L : size[0] - 1;
                if (x0 < xs) x0 = xs;
                if (x1 > xe) x1 = xe;
                row_minmax(row, x0 - xs, x1 - xs, &rmn[a], &rmx[a]);
            }
            for (int zi = 0; zi < nz; zi++)
                for (int yi = 0; yi < ny; yi++) {
                    size_t base = ((size_t)zb[zi] * (size_t)nb[1] + (size_t)yb[yi]) * (size_t)nb[0];
                    for (int32_t a = a0; a <= a1; a++) {
                        if (rmn[a] < bmin[base + a]) bmin[base + a] = rmn[a];
                        if (rmx[a] > bmax[base + a]) bmax[base + a] = rmx[a];
                    }
                }
        }
    }
    free(rmn), free(rmx);
    return 0;
}

int lci_grid_bvh_from_ranges(const float *bmin, const float *bmax, const int32_t size[3], const float origin[3],
                             const float spacing[3], int L, lci_grid_bvh *out)
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
    size_t nbricks = lci_grid_bvh_bricks(size, L);
    lc_kgrid_node *nodes = calloc(2 * nbricks - 1, sizeof *nodes);
    if (!nodes) return -1;
    b.nodes = nodes;
    b.bmin = bmin;
    b.bmax = bmax;
    b.used = 1;
    int32_t r0[3] = {0, 0, 0};
    build_node(&b, 0, r0, b.nb, 1);
    out->nodes = nodes;
    out->nnodes = b.used;
    out->nleaves = (int32_t)nbricks;
    out->depth = b.depth;
    out->brick = L;
    out->bytes = (uint64_t)b.used * sizeof *nodes;
    return 0;
}

int lci_grid_bvh_build(const void *data, int type, const int32_t size[3], const float origin[3], const float spacing[3],
                       int L, lci_grid_bvh *out)
{
    memset(out, 0, sizeof *out);
    size_t nbricks = lci_grid_bvh_bricks(size, L);
    float *bmin = malloc(nbricks * sizeof(float)), *bmax = malloc(nbricks * sizeof(float));
    const int32_t zero[3] = {0, 0, 0};
    int rc = bmin && bmax ? 0 : -1;
    if (rc == 0) {
        lci_grid_bvh_ranges_init(nbricks, bmin, bmax);
        rc = lci_grid_bvh_ranges(data, type, zero, size, size, L, bmin, bmax);
    }
    if (rc == 0) rc = lci_grid_bvh_from_ranges(bmin, bmax, size, origin, spacing, L, out);
    free(bmin), free(bmax);
    return rc;
}

void lci_grid_bvh_free(lci_grid_bvh *bvh)
{
    if (!bvh) return;
    free(bvh->nodes);
    memset(bvh, 0, sizeof *bvh);
}
