/* Plain structs the structured-grid kernels read (Knoll et al. 2011): the
 * voxels behind per-axis offset tables (§6.1), the implicit min-max BVH
 * (§5.1) and the pre-integrated transfer function (eq. 4). Built by
 * host/grid.c and bvh/grid_bvh.c; fixed-width types, sizes asserted. */
#ifndef LC_KGRID_H
#define LC_KGRID_H

#include <stdint.h>

enum { LC_KVAL_U8 = 1, LC_KVAL_U16 = 2, LC_KVAL_I16 = 3, LC_KVAL_F32 = 4 };

/* Side of the pre-integrated table: PREINT_N x PREINT_N entries over pairs of
 * quantised normalised values (256 levels: exact for 8-bit data over [0, 255]). */
#define LC_PREINT_N 256

/* A node of the implicit min-max BVH. Children of an inner node are
 * child and child + 1 (child == 0: leaf brick). Boxes are world boxes between
 * grid nodes; vmin/vmax cover every voxel of the trilinear stencil of any
 * point in the box (the +1 neighbours of §5.1). */
typedef struct lc_kgrid_node {
    float lo[3];
    float hi[3];
    float vmin, vmax;
    int32_t child;
    int32_t axis; /* split axis of an inner node (child boxes meet on it) */
} lc_kgrid_node;
_Static_assert(sizeof(lc_kgrid_node) == 40, "lc_kgrid_node layout");

typedef struct lc_kgrid {
    /* voxels: value at node (i, j, k) is data[xoff[i] + yoff[j] + zoff[k]]
     * (element index). The tables express either the linear layout or 4^3
     * bricks (§6.1) without the kernels knowing which. */
    const void *data;
    const int32_t *xoff, *yoff, *zoff;
    int32_t size[3];
    int32_t type;     /* LC_KVAL_* */
    /* the same offsets computed arithmetically (kernels: no table gathers):
     * bricked: (i/4)*64 + i%4 + (j/4)*ystride + (j%4)*4 + (k/4)*zstride + (k%4)*16
     * linear:  i + j*ystride + k*zstride */
    int32_t bricked;
    int32_t ystride, zstride;
    float prune_footprint; /* prune nodes narrower than this many packet footprints at
                            * LC_KGRID_PRUNE_ROWS image rows, at least LC_KGRID_PRUNE_MIN
                            * at the frame's rows (0: off) */
    float origin[4];
    float spacing[4];
    float inv_spacing[4];
    float lo[4], hi[4]; /* domain: first to last node */
    /* element index below which an SIMD narrow gather (vi_gather_u8/u16,
     * reads up to 3 bytes past) stays inside the allocation; at or above it
     * the kernels load lane by lane. */
    int64_t wide_safe;
    /* BVH */
    const lc_kgrid_node *nodes;
    int32_t nnodes;
    int32_t depth;   /* longest root-to-leaf path in nodes */
    /* pre-integrated TF of field 0 (LC_PREINT_N^2 x (r, g, b, tau_mean)) */
    const float *preint;
    /* per-frame options */
    int32_t use_preint; /* classify with the pre-integrated table */
    int32_t bvh_flags;  /* LC_KGRID_CULL / PRUNE / CONST bits */
    float delta_c, delta_p, delta_sv;
    float rda;          /* differential sampling: step k -> k+1 is dt (1 + rda k) */
    float diag_volume;  /* |D_volume| of eq. 6 */
    int32_t run_max;    /* BVH: longest run of lattice samples deferred before integrating */
    /* y-pair-packed copy of uint8 voxels (NULL: none), built when the grid owns
     * its voxels and has at most 2^30 of them (host/kinds/grid.c
     * lci_grid_pairs_max): pairs[i + j pair_ystride + k pair_zstride]
     * = v(i, j, k) | v(i, min(j + 1, ny - 1), k) << 8 (the 2-byte copy pads rows
     * of 1 KiB or more and planes of 4 KiB or more to an odd number of 64-byte
     * lines, grid_layout.c lci_grid_padded_strides; the 4-byte one is unpadded: pair_ystride = nx,
     * pair_zstride = nx ny), so one 32-bit load at
     * element e (byte 2e) holds v(i, j), v(i, j+1), v(i+1, j), v(i+1, j+1)
     * of plane k: two loads per trilinear sample instead of eight.
     * With pair_quads set (smaller volumes, lci_grid_quads_max) the copy is
     * z-paired too, one uint32 per voxel at the same linear index e:
     * pairs32[e] = v(i, j, k) | v(i, j1, k) << 8 | v(i, j, k1) << 16 |
     * v(i, j1, k1) << 24 with j1 = min(j + 1, ny - 1), k1 = min(k + 1, nz - 1),
     * so one 64-bit load at e (byte 4e) holds the whole 2x2x2 stencil:
     * two 8-lane qword gathers per 16 samples instead of two 16-lane dword
     * gathers (a gather costs about one load per lane on Zen 4). */
    const void *pairs;
    int32_t pair_ystride, pair_zstride;
    /* per frame, one byte per BVH node: the node's TF test bits
     * LC_KGRID_NODE_EMPTY / CONST / DENSE (below), which the host computes
     * from the pre-integrated table (eqs. 5-7). The traversal reads a byte per
     * child (nnodes bytes, which stay in cache) instead of each child's node
     * and the 1 MiB pre-integrated table (cache misses: ~15% of a BVH frame). */
    const uint8_t *node_tf_bits;
    int32_t pair_quads; /* pairs holds the z-paired uint32 layout (above) */
    int32_t pad_;
    /* the cells a sample's stencil is clamped to, per axis: 0 .. size - 2, or
     * for a part of a grid held by one rank (host/mpi/, lci_grid_create_window)
     * the cells of the nodes it holds, so that no lane (active or not) reads
     * outside them; the same floats as before for a whole grid */
    float cell_lo[4], cell_hi[4];
} lc_kgrid;
_Static_assert(sizeof(lc_kgrid) == 8 * 4 + 16 + 16 + 5 * 16 + 8 + 8 + 8 + 8 + 3 * 4 + 12 + 24 + 8 + 8 + 32, "lc_kgrid layout");

enum { LC_KGRID_CULL = 1, LC_KGRID_PRUNE = 2, LC_KGRID_CONST = 4 };

/* image height at which prune_footprint counts packet footprints, and the
 * fewest footprints at the frame's own height (kernels/grid_bvh.c traverse) */
#define LC_KGRID_PRUNE_ROWS 512
#define LC_KGRID_PRUNE_MIN 2.0f

/* lc_kgrid.node_tf_bits, per node and frame:
 * EMPTY: eq. 5, skipped as transparent (pre-integrated mean extinction over
 *   the range exactly 0, or with culling on an opacity over one step <= delta_c);
 * CONST: eq. 7's TF test over [vmin, vmax] passes (with LC_KGRID_CONST; the
 *   kernel adds the mode and shading conditions);
 * DENSE: eq. 6's opacity test passes, rho diag_volume > delta_p |box|
 *   (with LC_KGRID_PRUNE; the kernel adds the footprint test). */
enum { LC_KGRID_NODE_EMPTY = 1, LC_KGRID_NODE_CONST = 2, LC_KGRID_NODE_DENSE = 4 };

/* |box| of eq. 6, the same float expression on host and kernels */
static inline float lc_kgrid_node_diag(const lc_kgrid_node *n)
{
    float dx = n->hi[0] - n->lo[0], dy = n->hi[1] - n->lo[1], dz = n->hi[2] - n->lo[2];
    return __builtin_sqrtf(dx * dx + dy * dy + dz * dz);
}

/* A node's value range [vmin, vmax] as indices into the pre-integrated table
 * of a TF over [lo, lo + 1 / inv_range]: quantised bounds, widened by one
 * level so the table covers every value the trilinear interpolant can take. */
static inline void lc_kgrid_node_quant(float vmin, float vmax, float lo, float inv_range, int *qlo, int *qhi)
{
    float s = (float)(LC_PREINT_N - 1);
    float a = (vmin - lo) * inv_range * s, b = (vmax - lo) * inv_range * s;
    a = __builtin_floorf(a - 1e-3f), b = __builtin_ceilf(b + 1e-3f);
    a = a < 0.0f ? 0.0f : a > s ? s : a;
    b = b < 0.0f ? 0.0f : b > s ? s : b;
    *qlo = (int)a, *qhi = (int)b;
}

/* Traversal stack bound: the median split halves the brick count per level,
 * so depth <= 3 * log2(max bricks per axis) + 1 < 64 for sizes below 2^20. */
#define LC_KGRID_MAX_DEPTH 64

#endif
