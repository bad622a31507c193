/* Voxel storage of the structured grids (host/kinds/grid.c creates them):
 * the per-axis offset tables of the 4^3-bricked and the linear layouts
 * (Knoll 2011 §6.1), the zeroed, huge-page-advised voxel arrays, and the
 * uint8 copies the kernels sample instead of the voxels (lc_kgrid.pairs:
 * y-paired, or y- and z-paired quads) with their padded strides. */
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include "host/kinds/grid.h"

/* 4^3 bricks: element (i, j, k) at brick (i/4, j/4, k/4) * 64 + (k%4)*16 + (j%4)*4 + i%4,
 * bricks counted from the n nodes held; tables for len nodes (n, or the
 * whole grid's for a window) */
void lci_grid_brick_tables(const int32_t n[3], const int32_t len[3], int32_t *xo, int32_t *yo, int32_t *zo,
                           int64_t *elements)
{
    int32_t nb[3];
    for (int a = 0; a < 3; a++) nb[a] = (n[a] + 3) / 4;
    for (int32_t i = 0; i < len[0]; i++) xo[i] = (i >> 2) * 64 + (i & 3);
    for (int32_t j = 0; j < len[1]; j++) yo[j] = (j >> 2) * 64 * nb[0] + (j & 3) * 4;
    for (int32_t k = 0; k < len[2]; k++) zo[k] = (k >> 2) * 64 * nb[0] * nb[1] + (k & 3) * 16;
    *elements = (int64_t)nb[0] * nb[1] * nb[2] * 64;
}

/* linear: element (i, j, k) at i + j ys + k zs (strides from padded_strides) */
void lci_grid_linear_tables(const int32_t n[3], int64_t ys, int64_t zs, int32_t *xo, int32_t *yo, int32_t *zo)
{
    for (int32_t i = 0; i < n[0]; i++) xo[i] = i;
    for (int32_t j = 0; j < n[1]; j++) yo[j] = (int32_t)(j * ys);
    for (int32_t k = 0; k < n[2]; k++) zo[k] = (int32_t)(k * zs);
}

/* Zeroed voxel storage, freed with lci_aligned_free. Arrays of 4 MiB or more
 * are 2 MiB aligned and asked to be backed by transparent huge pages before
 * they are touched: rays cross a z plane every step or two (a plane of the
 * linear pair copy is 2 MiB at 1024^2), so with 4 KiB pages nearly every
 * sample missed the TLB (proc1024 medium: 25% more CPU per frame with the
 * pair copy than without, before; see docs/bench/grid.md "Transparent huge
 * pages"). */
void *lci_grid_voxel_alloc(size_t bytes)
{
    const size_t huge = (size_t)2 << 20;
    if (bytes < 2 * huge) {
        void *s = lci_aligned_alloc(64, bytes);
        if (s) memset(s, 0, bytes); /* the copies' padding is zero */
        return s;
    }
    void *p = NULL;
    if (posix_memalign(&p, huge, bytes) != 0) return NULL;
#ifdef MADV_HUGEPAGE
    (void)madvise(p, bytes, MADV_HUGEPAGE); /* advice only: 4 KiB pages if refused */
#endif
    memset(p, 0, bytes);
    return p;
}

/* pairs[e] = v(i, j, k) | v(i, min(j + 1, ny - 1), k) << 8 at the linear
 * index e of (i, j, k) (lc_kgrid.pairs); padding zeroed. */
void lci_grid_build_pairs(const uint8_t *src, const int32_t n[3], int64_t ys, int64_t zs, uint16_t *pairs)
{
    for (int32_t k = 0; k < n[2]; k++)
        for (int32_t j = 0; j < n[1]; j++) {
            size_t e = ((size_t)k * (size_t)n[1] + (size_t)j) * (size_t)n[0];
            size_t o = (size_t)k * (size_t)zs + (size_t)j * (size_t)ys;
            const uint8_t *r0 = src + e, *r1 = j + 1 < n[1] ? r0 + n[0] : r0;
            for (int32_t i = 0; i < n[0]; i++) pairs[o + (size_t)i] = (uint16_t)(r0[i] | r1[i] << 8);
        }
}

/* quads[e] = v(i, j, k) | v(i, j1, k) << 8 | v(i, j, k1) << 16 | v(i, j1, k1) << 24
 * with j1 = min(j + 1, ny - 1), k1 = min(k + 1, nz - 1) at the linear index e
 * of (i, j, k) (lc_kgrid.pair_quads); padding zeroed. */
void lci_grid_build_quads(const uint8_t *src, const int32_t n[3], int64_t ys, int64_t zs, uint32_t *quads)
{
    size_t plane = (size_t)n[0] * (size_t)n[1];
    for (int32_t k = 0; k < n[2]; k++)
        for (int32_t j = 0; j < n[1]; j++) {
            size_t e = (size_t)k * plane + (size_t)j * (size_t)n[0];
            size_t o = (size_t)k * (size_t)zs + (size_t)j * (size_t)ys;
            const uint8_t *r0 = src + e, *r1 = j + 1 < n[1] ? r0 + n[0] : r0;
            const uint8_t *r2 = k + 1 < n[2] ? r0 + plane : r0, *r3 = k + 1 < n[2] ? r1 + plane : r1;
            for (int32_t i = 0; i < n[0]; i++)
                quads[o + (size_t)i] = (uint32_t)r0[i] | (uint32_t)r1[i] << 8 | (uint32_t)r2[i] << 16 | (uint32_t)r3[i] << 24;
        }
}

/* The row and plane strides, in elements of es bytes, of a linear array the
 * kernels read through lc_kgrid strides: the 2-byte pair copy and owned
 * linear voxels (uint16 and int16 by default, float32 asked linear, uint8
 * past the copies); not the quad copy (padding it measured no gain), not
 * bricks (a 1024-wide float32 grid measured no cost),
 * not borrowed arrays (the caller's). Rows of at least 1 KiB and planes of
 * at least 4 KiB are padded to an odd number of 64-byte lines: with
 * power-of-two strides (1024 wide: rows of 2 or 4 KiB, planes of 2 or 4 MiB)
 * every line a ray's stencil needs at one x maps to one or two of the L1's 64
 * sets (and the planes to one of the L2's), so lines evicted each other
 * before the gathers read them. Measured (docs/bench/grid.md "Padded
 * strides", CPU a frame): the pair copy at proc1024 medium 1.20-1.28x, far 1.5x;
 * proc1024u16 1.27-1.30x; 1024^3 float32 linear 1.16-1.38x. Costs at most 2
 * lines a row and a plane, i.e. at most 12 % (rows just over 1 KiB; 1024
 * wide +3 % at 2 bytes, +1.6 % at 4); where the padded array would pass
 * LCI_GRID_MAX_ELEMENTS (int32 element offsets) the strides stay unpadded. (Named
 * pair_strides until d2f841d, when it served the pair copy alone.) */
void lci_grid_padded_strides(const int32_t n[3], int es, int64_t *ys, int64_t *zs)
{
    const int64_t line = 64 / es;
    int64_t y = n[0];
    if (y * es >= 1024) {
        y = (y + line - 1) / line * line;
        if ((y / line) % 2 == 0) y += line;
    }
    int64_t z = y * n[1];
    if (z * es >= 4096) {
        z = (z + line - 1) / line * line;
        if ((z / line) % 2 == 0) z += line;
    }
    if (z * n[2] > LCI_GRID_MAX_ELEMENTS) y = n[0], z = (int64_t)n[0] * n[1];
    *ys = y, *zs = z;
}
