/* The voxel fetch of the structured-grid kernels (grid_common.h includes it
 * after the packlet type): a sample's 2x2x2 stencil from whichever layout or
 * copy the grid has (bricked or linear voxels of any value type, the uint8
 * y-pair copy, the z-paired quad copy; kgrid.h), its trilinear value (eq. 8)
 * and analytic gradient (eq. 9), and the software prefetch of the copies'
 * lines ahead of the sample loop. */
#ifndef LC_GRID_FETCH_H
#define LC_GRID_FETCH_H

/* Per-lane element loads for narrow gathers near the end of borrowed data. */
static inline vint grid_load_lanes(const lc_kgrid *g, vint idx)
{
    int32_t ix[LC_W], v[LC_W];
    vi_store(ix, idx);
    for (int l = 0; l < LC_W; l++)
        v[l] = g->type == LC_KVAL_U8 ? ((const uint8_t *)g->data)[ix[l]] : ((const uint16_t *)g->data)[ix[l]];
    return vi_load(v);
}

/* Voxel values at element indices idx (any lane value must be valid). */
static inline vfloat grid_fetch(const lc_kgrid *g, vint idx)
{
    if (GRID_PROF & GP_FETCH) return vi_to_vf(vi_and(idx, vi_set1(0xff)));
    switch (g->type) {
    case LC_KVAL_F32:
        return vf_gather((const float *)g->data, idx);
    case LC_KVAL_U8:
    case LC_KVAL_U16:
    case LC_KVAL_I16: {
        vint v;
        if (g->wide_safe <= INT32_MAX && vm_any(vi_gt(idx, vi_set1((int32_t)(g->wide_safe - 1)))))
            v = grid_load_lanes(g, idx);
        else if (g->type == LC_KVAL_U8) v = vi_gather_u8((const uint8_t *)g->data, idx);
        else v = vi_gather_u16((const uint16_t *)g->data, idx);
        if (g->type == LC_KVAL_I16) /* sign-extend: offset binary, then subtract the offset */
            v = vi_sub(vi_and(vi_add(v, vi_set1(0x8000)), vi_set1(0xffff)), vi_set1(0x8000));
        return vi_to_vf(v);
    }
    default:
        return vf_zero();
    }
}

static inline vint grid_sext16(vint v) { return vi_sub(vi_and(vi_add(v, vi_set1(0x8000)), vi_set1(0xffff)), vi_set1(0x8000)); }

/* The z-paired copy (kgrid.h pair_quads): d0 = pairs32[e], d1 = pairs32[e + 1]
 * per lane, i.e. the 2x2 (j, k) voxels of columns i and i + 1. Where the
 * target has 64-bit gathers, one 8-byte load per lane and two dword
 * permutes; elsewhere two dword gathers. */
static inline __attribute__((always_inline)) void grid_fetch_quads(const uint32_t *q, vint e, vint *d0, vint *d1)
{
#if defined(LC_TARGET_AVX512) && LC_W == 16
    __m512i a = _mm512_i32gather_epi64(_mm512_castsi512_si256(e), (const void *)q, 4);
    __m512i b = _mm512_i32gather_epi64(_mm512_extracti32x8_epi32(e, 1), (const void *)q, 4);
    const __m512i ev = _mm512_setr_epi32(0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 20, 22, 24, 26, 28, 30);
    const __m512i od = _mm512_setr_epi32(1, 3, 5, 7, 9, 11, 13, 15, 17, 19, 21, 23, 25, 27, 29, 31);
    *d0 = _mm512_permutex2var_epi32(a, ev, b);
    *d1 = _mm512_permutex2var_epi32(a, od, b);
#elif (defined(LC_TARGET_AVX2) || defined(LC_TARGET_AVX512_8)) && LC_W == 8
    __m256i a = _mm256_i32gather_epi64((const long long *)(const void *)q, _mm256_castsi256_si128(e), 4);
    __m256i b = _mm256_i32gather_epi64((const long long *)(const void *)q, _mm256_extracti128_si256(e, 1), 4);
    /* per 128-bit half: a's then b's even (odd) dwords; then the halves' qwords in order */
    __m256 lo = _mm256_shuffle_ps(_mm256_castsi256_ps(a), _mm256_castsi256_ps(b), 0x88);
    __m256 hi = _mm256_shuffle_ps(_mm256_castsi256_ps(a), _mm256_castsi256_ps(b), 0xdd);
    *d0 = _mm256_permute4x64_epi64(_mm256_castps_si256(lo), 0xd8);
    *d1 = _mm256_permute4x64_epi64(_mm256_castps_si256(hi), 0xd8);
#else
    *d0 = vi_gather((const int32_t *)(const void *)q, e);
    *d1 = vi_gather((const int32_t *)(const void *)q, vi_add(e, vi_set1(1)));
#endif
}

/* Values at idx and idx + 1 of a linear grid: owned (padded) u8/u16/i16, or
 * float32 (owned or borrowed: idx + 1 is the cell's other x corner, inside
 * the array), whose two floats are one 8-byte load per lane where the target
 * has 64-bit gathers (grid_fetch_quads). */
static inline void grid_fetch_pair(const lc_kgrid *g, vint idx, vfloat *a, vfloat *b)
{
    vint lo, hi;
    if (GRID_PROF & GP_FETCH) {
        *a = vi_to_vf(vi_and(idx, vi_set1(0xff)));
        *b = vi_to_vf(vi_and(vi_add(idx, vi_set1(1)), vi_set1(0xff)));
        return;
    }
    if (g->type == LC_KVAL_F32) {
        grid_fetch_quads((const uint32_t *)g->data, idx, &lo, &hi);
        *a = vi_as_vf(lo);
        *b = vi_as_vf(hi);
        return;
    }
    if (g->type == LC_KVAL_U8) {
        vint w = vi_gather_u8pair((const uint8_t *)g->data, idx);
        lo = vi_and(w, vi_set1(0xff));
        hi = vi_srl(w, 8);
    } else {
        vint w = vi_gather_u16pair((const uint16_t *)g->data, idx);
        lo = vi_and(w, vi_set1(0xffff));
        hi = vi_srl(w, 16);
        if (g->type == LC_KVAL_I16) lo = grid_sext16(lo), hi = grid_sext16(hi);
    }
    *a = vi_to_vf(lo);
    *b = vi_to_vf(hi);
}

/* A sample's trilinear stencil: the 8 voxel values of its cell
 * (v[0..7] = v000, v100, v010, v110, v001, v101, v011, v111) and the weights
 * (eq. 8). Profile variants with GP_INTERP keep u = (ux, uy, uz) in w*. */
typedef struct gcell {
    vfloat v[8];
    vfloat wx, wy, wz;
} gcell;

#if defined(LC_TARGET_AVX512) && LC_W == 16
/* The quad copy's stencil on 16 lanes (AVX-512) for volumes of at most 2^24
 * voxels: the element index i + j Y + k Z taken in float with two FMAs (every
 * product and partial sum is an integer below 2^24, so exact, and one
 * conversion instead of three, no vpmulld), and the bytes of the two
 * gathered words zero-extended with one vpshufb each instead of a shift and
 * a mask. Same voxel values, same bytes as grid_cell's general path
 * (docs/bench/grid.md "The uint8 copies": avx512 close 0.99-1.05x alone, within
 * the run-to-run spread; tests: test_grid_copies' quad copy, test_grid). */
static inline __attribute__((always_inline)) void grid_cell_quads16(const lc_kgrid *g, vfloat fx0, vfloat fy0,
                                                                     vfloat fz0, gcell *c)
{
    vfloat ef = vf_fma(fz0, vf_set1((float)g->pair_zstride), vf_fma(fy0, vf_set1((float)g->pair_ystride), fx0));
    vint w0, w1;
    grid_fetch_quads(g->pairs, vf_to_vi(ef), &w0, &w1);
    /* vpshufb indexes bytes within each 128-bit block: dword p's byte n is 4 p + n */
    const __m512i b1 = _mm512_broadcast_i32x4(_mm_setr_epi32((int)0x80808001u, (int)0x80808005u, (int)0x80808009u,
                                                            (int)0x8080800du));
    const __m512i b2 = _mm512_add_epi32(b1, _mm512_set1_epi32(1));
    vint ff = vi_set1(0xff);
    c->v[0] = vi_to_vf(vi_and(w0, ff)), c->v[2] = vi_to_vf(_mm512_shuffle_epi8(w0, b1));
    c->v[4] = vi_to_vf(_mm512_shuffle_epi8(w0, b2)), c->v[6] = vi_to_vf(vi_srl(w0, 24));
    c->v[1] = vi_to_vf(vi_and(w1, ff)), c->v[3] = vi_to_vf(_mm512_shuffle_epi8(w1, b1));
    c->v[5] = vi_to_vf(_mm512_shuffle_epi8(w1, b2)), c->v[7] = vi_to_vf(vi_srl(w1, 24));
}
#endif

/* The stencil at world positions (x, y, z). Always inlined (see grid_sample). */
static inline __attribute__((always_inline)) void grid_cell(const lc_kgrid *g, vfloat x, vfloat y, vfloat z, gcell *c)
{
    vfloat ux = vf_mul(vf_sub(x, vf_set1(g->origin[0])), vf_set1(g->inv_spacing[0]));
    vfloat uy = vf_mul(vf_sub(y, vf_set1(g->origin[1])), vf_set1(g->inv_spacing[1]));
    vfloat uz = vf_mul(vf_sub(z, vf_set1(g->origin[2])), vf_set1(g->inv_spacing[2]));
    if (GRID_PROF & GP_INTERP) {
        c->wx = ux, c->wy = uy, c->wz = uz;
        return;
    }
    vfloat fx0 = vf_clamp(vf_floor(ux), vf_set1(g->cell_lo[0]), vf_set1(g->cell_hi[0]));
    vfloat fy0 = vf_clamp(vf_floor(uy), vf_set1(g->cell_lo[1]), vf_set1(g->cell_hi[1]));
    vfloat fz0 = vf_clamp(vf_floor(uz), vf_set1(g->cell_lo[2]), vf_set1(g->cell_hi[2]));
    c->wx = vf_clamp(vf_sub(ux, fx0), vf_zero(), vf_set1(1.0f));
    c->wy = vf_clamp(vf_sub(uy, fy0), vf_zero(), vf_set1(1.0f));
    c->wz = vf_clamp(vf_sub(uz, fz0), vf_zero(), vf_set1(1.0f));
#if defined(LC_TARGET_AVX512) && LC_W == 16
    if (g->pair_quads && !(GRID_PROF & GP_FETCH) && (int64_t)g->pair_zstride * g->size[2] <= (1 << 24)) {
        grid_cell_quads16(g, fx0, fy0, fz0, c);
        return;
    }
#endif
    vint i = vf_to_vi(fx0), j = vf_to_vi(fy0), k = vf_to_vi(fz0);
    if (g->pairs) {
        /* y-pair-packed uint8 (kgrid.h): one 32-bit load per z plane holds the
         * plane's 2x2 voxels, bytes (i, j), (i, j+1), (i+1, j), (i+1, j+1) */
        vint e = vi_add(i, vi_add(vi_mul(j, vi_set1(g->pair_ystride)), vi_mul(k, vi_set1(g->pair_zstride))));
        vint w0, w1;
        vint ff = vi_set1(0xff);
        if (g->pair_quads && !(GRID_PROF & GP_FETCH)) {
            /* z-paired: d0 holds column i's bytes (j, k), (j+1, k), (j, k+1), (j+1, k+1), d1 column i+1's */
            grid_fetch_quads(g->pairs, e, &w0, &w1);
            c->v[0] = vi_to_vf(vi_and(w0, ff)), c->v[2] = vi_to_vf(vi_and(vi_srl(w0, 8), ff));
            c->v[4] = vi_to_vf(vi_and(vi_srl(w0, 16), ff)), c->v[6] = vi_to_vf(vi_srl(w0, 24));
            c->v[1] = vi_to_vf(vi_and(w1, ff)), c->v[3] = vi_to_vf(vi_and(vi_srl(w1, 8), ff));
            c->v[5] = vi_to_vf(vi_and(vi_srl(w1, 16), ff)), c->v[7] = vi_to_vf(vi_srl(w1, 24));
            return;
        }
        if (GRID_PROF & GP_FETCH) {
            w0 = vi_and(e, vi_set1(0x7f7f7f7f));
            w1 = vi_and(vi_add(e, vi_set1(1)), vi_set1(0x7f7f7f7f));
        } else {
            w0 = vi_gather_u16pair(g->pairs, e);
            w1 = vi_gather_u16pair(g->pairs, vi_add(e, vi_set1(g->pair_zstride)));
        }
        c->v[0] = vi_to_vf(vi_and(w0, ff)), c->v[2] = vi_to_vf(vi_and(vi_srl(w0, 8), ff));
        c->v[1] = vi_to_vf(vi_and(vi_srl(w0, 16), ff)), c->v[3] = vi_to_vf(vi_srl(w0, 24));
        c->v[4] = vi_to_vf(vi_and(w1, ff)), c->v[6] = vi_to_vf(vi_and(vi_srl(w1, 8), ff));
        c->v[5] = vi_to_vf(vi_and(vi_srl(w1, 16), ff)), c->v[7] = vi_to_vf(vi_srl(w1, 24));
        return;
    }
    /* voxel offsets (§6.1's tables, computed: cheaper than six gathers) */
    vint x0, x1, y0, y1, z0, z1;
    if (g->bricked) {
        vint three = vi_set1(3), i3 = vi_and(i, three), j3 = vi_and(j, three), k3 = vi_and(k, three);
        x0 = vi_add(vi_sll(vi_srl(i, 2), 6), i3);
        y0 = vi_add(vi_mul(vi_srl(j, 2), vi_set1(g->ystride)), vi_sll(j3, 2));
        z0 = vi_add(vi_mul(vi_srl(k, 2), vi_set1(g->zstride)), vi_sll(k3, 4));
        /* the +1 neighbour is in the same brick unless the index is 3 mod 4 */
        x1 = vi_add(x0, vi_select(vi_eq(i3, three), vi_set1(61), vi_set1(1)));
        y1 = vi_add(y0, vi_select(vi_eq(j3, three), vi_set1(g->ystride - 12), vi_set1(4)));
        z1 = vi_add(z0, vi_select(vi_eq(k3, three), vi_set1(g->zstride - 48), vi_set1(16)));
    } else {
        x0 = i;
        x1 = vi_add(i, vi_set1(1));
        y0 = vi_mul(j, vi_set1(g->ystride));
        y1 = vi_add(y0, vi_set1(g->ystride));
        z0 = vi_mul(k, vi_set1(g->zstride));
        z1 = vi_add(z0, vi_set1(g->zstride));
    }
    vint yz00 = vi_add(y0, z0), yz10 = vi_add(y1, z0), yz01 = vi_add(y0, z1), yz11 = vi_add(y1, z1);
    vfloat *v = c->v;
    if (!g->bricked && (g->type == LC_KVAL_F32 || g->wide_safe > INT32_MAX)) {
        /* linear voxels: x neighbours are adjacent, one gather per pair */
        grid_fetch_pair(g, vi_add(x0, yz00), &v[0], &v[1]);
        grid_fetch_pair(g, vi_add(x0, yz10), &v[2], &v[3]);
        grid_fetch_pair(g, vi_add(x0, yz01), &v[4], &v[5]);
        grid_fetch_pair(g, vi_add(x0, yz11), &v[6], &v[7]);
    } else {
        v[0] = grid_fetch(g, vi_add(x0, yz00)), v[1] = grid_fetch(g, vi_add(x1, yz00));
        v[2] = grid_fetch(g, vi_add(x0, yz10)), v[3] = grid_fetch(g, vi_add(x1, yz10));
        v[4] = grid_fetch(g, vi_add(x0, yz01)), v[5] = grid_fetch(g, vi_add(x1, yz01));
        v[6] = grid_fetch(g, vi_add(x0, yz11)), v[7] = grid_fetch(g, vi_add(x1, yz11));
    }
}

/* Trilinear value (eq. 8) of a stencil. */
static inline __attribute__((always_inline)) vfloat grid_cell_value(const gcell *c)
{
    if (GRID_PROF & GP_INTERP) return vf_add(c->wx, vf_add(c->wy, c->wz));
    const vfloat *v = c->v;
    vfloat c00 = vf_lerp(v[0], v[1], c->wx), c10 = vf_lerp(v[2], v[3], c->wx);
    vfloat c01 = vf_lerp(v[4], v[5], c->wx), c11 = vf_lerp(v[6], v[7], c->wx);
    vfloat c0 = vf_lerp(c00, c10, c->wy), c1 = vf_lerp(c01, c11, c->wy);
    return vf_lerp(c0, c1, c->wz);
}

/* The analytic gradient (eq. 9) of the same interpolant, world units: each
 * partial derivative is the bilinear interpolant of the differences along
 * its axis, with the other two weights. */
static inline __attribute__((always_inline)) void grid_cell_grad(const lc_kgrid *g, const gcell *c, vfloat *gx, vfloat *gy,
                                                                 vfloat *gz)
{
    if (GRID_PROF & GP_INTERP) {
        *gx = c->wx, *gy = c->wy, *gz = c->wz;
        return;
    }
    const vfloat *v = c->v;
    vfloat c00 = vf_lerp(v[0], v[1], c->wx), c10 = vf_lerp(v[2], v[3], c->wx);
    vfloat c01 = vf_lerp(v[4], v[5], c->wx), c11 = vf_lerp(v[6], v[7], c->wx);
    vfloat c0 = vf_lerp(c00, c10, c->wy), c1 = vf_lerp(c01, c11, c->wy);
    vfloat dx00 = vf_sub(v[1], v[0]), dx10 = vf_sub(v[3], v[2]), dx01 = vf_sub(v[5], v[4]), dx11 = vf_sub(v[7], v[6]);
    vfloat ddx = vf_lerp(vf_lerp(dx00, dx10, c->wy), vf_lerp(dx01, dx11, c->wy), c->wz);
    vfloat ddy = vf_lerp(vf_sub(c10, c00), vf_sub(c11, c01), c->wz);
    vfloat ddz = vf_sub(c1, c0);
    *gx = vf_mul(ddx, vf_set1(g->inv_spacing[0]));
    *gy = vf_mul(ddy, vf_set1(g->inv_spacing[1]));
    *gz = vf_mul(ddz, vf_set1(g->inv_spacing[2]));
}

/* Trilinear value (eq. 8) at world positions, and if want_grad the analytic
 * gradient of the same interpolant (eq. 9) in world units. Always inlined:
 * with iso's loop and probe as further callers GCC stopped inlining it into
 * the dvr sample loop, which made avx512 frames 2-3% slower. */
static inline __attribute__((always_inline)) vfloat grid_sample(const lc_kgrid *g, vfloat x, vfloat y, vfloat z, int want_grad, vfloat *gx, vfloat *gy,
                                 vfloat *gz)
{
    gcell c;
    grid_cell(g, x, y, z, &c);
    if (want_grad) grid_cell_grad(g, &c, gx, gy, gz);
    return grid_cell_value(&c);
}

/* Samples ahead of the one being integrated whose pair-copy lines the
 * fast dvr loop prefetches (0: none). Measured (docs/bench/grid.md "Software
 * prefetch", commit 63f139c): proc512 1024^2 1.14-1.24x less CPU per frame, 256^3
 * volumes 0-5%; prefetching the bricked layout the same way did not pay. */
#ifndef GRID_PF
#define GRID_PF 8
#endif

/* Software prefetch of the copy's lines a sample at t needs: rays cross a
 * plane every step or two, and the hardware prefetchers do not follow
 * gathers. The quad copy: one line per lane holds both planes; the
 * packlet's four corner lanes (its rays are coherent). The pair copy: both
 * z-plane lines of every lane. A 4x4 packlet's lanes span up to four pair
 * rows, and with the corners alone the middle rows' misses stalled the
 * gathers: every lane made proc1024 medium 1.3-1.4x and proc512 1.1-1.2x
 * faster (docs/bench/grid.md "Software prefetch"). */
static inline __attribute__((always_inline)) void grid_prefetch_pairs(const lc_kgrid *g, const gpk *p, vfloat t)
{
    vfloat ux = vf_mul(vf_sub(vf_fma(t, p->ray.dx, p->ray.ox), vf_set1(g->origin[0])), vf_set1(g->inv_spacing[0]));
    vfloat uy = vf_mul(vf_sub(vf_fma(t, p->ray.dy, p->ray.oy), vf_set1(g->origin[1])), vf_set1(g->inv_spacing[1]));
    vfloat uz = vf_mul(vf_sub(vf_fma(t, p->ray.dz, p->ray.oz), vf_set1(g->origin[2])), vf_set1(g->inv_spacing[2]));
    /* clamped like grid_cell (a prefetch never faults, but stay inside) */
    vint i = vf_to_vi(vf_clamp(ux, vf_set1(g->cell_lo[0]), vf_set1(g->cell_hi[0])));
    vint j = vf_to_vi(vf_clamp(uy, vf_set1(g->cell_lo[1]), vf_set1(g->cell_hi[1])));
    vint k = vf_to_vi(vf_clamp(uz, vf_set1(g->cell_lo[2]), vf_set1(g->cell_hi[2])));
    vint e = vi_add(i, vi_add(vi_mul(j, vi_set1(g->pair_ystride)), vi_mul(k, vi_set1(g->pair_zstride))));
    int32_t ev[LC_W];
    vi_store(ev, e);
    if (g->pair_quads) {
        /* one line per lane holds both planes */
        const uint32_t *q = g->pairs;
        __builtin_prefetch(q + ev[0]);
        __builtin_prefetch(q + ev[LC_W - 1]);
        if (LC_W == 16) { /* the 4x4 block's other two corners: 1.00-1.04x (commit e8fa572) */
            __builtin_prefetch(q + ev[3]);
            __builtin_prefetch(q + ev[12]);
        }
        return;
    }
    const uint16_t *b = g->pairs;
    for (int l = 0; l < LC_W; l++) { /* unrolled; a prefetch per lane costs less than the misses it hides */
        __builtin_prefetch(b + ev[l]);
        __builtin_prefetch(b + ev[l] + g->pair_zstride);
    }
}

#endif
