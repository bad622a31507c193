/* The canonical particle BVH (lci_pbvh_build_canonical): leaves in one order
 * fixed by each particle's own data, so that every traversal, which visits
 * leaves first child first and so in array (leaf) order, adds a sample's
 * terms in the same order in any set that holds them. A data-parallel part
 * (a region's owners and ghosts) then sums each sample exactly as the whole
 * set does: the terms it lacks are those whose support misses its region,
 * and the ones it adds beyond them are exact zeros there (a sum starts at
 * +0 or the bias and never becomes -0, so x + 0 = x).
 *
 * The order: a 63-bit Morton code of the centre over a box every holder of
 * the set agrees on (the whole set's centre bounds, or the RBF domain), ties
 * broken by the float bits of the centre, radius and the caller's extra
 * values, so only particles with identical data keep an arbitrary order
 * among themselves, and those add identical terms. The tree splits the
 * sorted array where the highest differing bit of the codes changes (the
 * Morton grid's spatial median; Karras 2012), in the middle of runs of one
 * code, down to leaves of at most leaf_size. Siblings are adjacent, the
 * first child holds the lower codes. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "particle_bvh.h"

#define MORTON_BITS 21

typedef struct ckey {
    uint64_t code;
    uint32_t id;
    uint32_t pad_;
} ckey;

typedef struct cctx {
    const float *xyz, *r;
    float r_all;
    const lci_pbvh_keys *keys;
} cctx;

static uint64_t spread3(uint32_t v)
{
    uint64_t x = v & 0x1fffffu;
    x = (x | x << 32) & 0x1f00000000ffffull;
    x = (x | x << 16) & 0x1f0000ff0000ffull;
    x = (x | x << 8) & 0x100f00f00f00f00full;
    x = (x | x << 4) & 0x10c30c30c30c30c3ull;
    x = (x | x << 2) & 0x1249249249249249ull;
    return x;
}

/* The cell of v on an axis of the box [lo, hi] (double arithmetic on the
 * same floats gives every holder the same cell). */
static uint32_t cell(float v, float lo, float hi)
{
    double e = (double)hi - (double)lo;
    if (!(e > 0.0)) return 0;
    double c = ((double)v - (double)lo) / e * (double)(1u << MORTON_BITS);
    if (!(c > 0.0)) return 0; /* also NaN */
    if (c >= (double)((1u << MORTON_BITS) - 1)) return (1u << MORTON_BITS) - 1;
    return (uint32_t)c;
}

static uint32_t fbits(float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    return u;
}

/* The tie order: centre, radius, then the caller's values, by their bits. */
static int tie_cmp(const cctx *c, uint32_t a, uint32_t b)
{
    for (int k = 0; k < 3; k++) {
        uint32_t x = fbits(c->xyz[3 * (size_t)a + (size_t)k]), y = fbits(c->xyz[3 * (size_t)b + (size_t)k]);
        if (x != y) return x < y ? -1 : 1;
    }
    if (c->r) {
        uint32_t x = fbits(c->r[a]), y = fbits(c->r[b]);
        if (x != y) return x < y ? -1 : 1;
    }
    const lci_pbvh_keys *q = c->keys;
    size_t ia = q->src ? q->src[a] : a, ib = q->src ? q->src[b] : b;
    for (int k = 0; k < LCI_PBVH_TIES; k++) {
        if (!q->tie[k]) continue;
        uint32_t x = fbits(q->tie[k][ia]), y = fbits(q->tie[k][ib]);
        if (x != y) return x < y ? -1 : 1;
    }
    if (q->tag && q->tag[ia] != q->tag[ib]) return q->tag[ia] < q->tag[ib] ? -1 : 1;
    return 0;
}

/* Insertion sort of a run of equal codes by the tie order (runs are a few
 * particles; a long run, e.g. particles at one point, sorts by merging). */
static void sort_run(const cctx *c, ckey *k, ckey *tmp, size_t n)
{
    if (n < 2) return;
    if (n <= 32) {
        for (size_t i = 1; i < n; i++) {
            ckey v = k[i];
            size_t j = i;
            while (j > 0 && tie_cmp(c, k[j - 1].id, v.id) > 0) k[j] = k[j - 1], j--;
            k[j] = v;
        }
        return;
    }
    size_t h = n / 2;
    sort_run(c, k, tmp, h);
    sort_run(c, k + h, tmp, n - h);
    size_t i = 0, j = h, o = 0;
    while (i < h && j < n) tmp[o++] = tie_cmp(c, k[j].id, k[i].id) < 0 ? k[j++] : k[i++];
    while (i < h) tmp[o++] = k[i++];
    while (j < n) tmp[o++] = k[j++];
    memcpy(k, tmp, n * sizeof *k);
}

/* LSD radix sort by code (16-bit digits; digits equal in every key skipped),
 * stable, then each run of equal codes by the tie order. */
static int sort_keys(const cctx *c, ckey *k, ckey *tmp, size_t n)
{
    static const int digits = 4;
    size_t *cnt = malloc(sizeof(size_t) * 65536);
    if (!cnt) return -1;
    uint64_t all_and = ~(uint64_t)0, all_or = 0;
    for (size_t i = 0; i < n; i++) all_and &= k[i].code, all_or |= k[i].code;
    for (int d = 0; d < digits; d++) {
        int sh = 16 * d;
        if ((((all_and ^ all_or) >> sh) & 0xffffu) == 0) continue;
        memset(cnt, 0, sizeof(size_t) * 65536);
        for (size_t i = 0; i < n; i++) cnt[(k[i].code >> sh) & 0xffffu]++;
        size_t s = 0;
        for (size_t b = 0; b < 65536; b++) {
            size_t t = cnt[b];
            cnt[b] = s, s += t;
        }
        for (size_t i = 0; i < n; i++) tmp[cnt[(k[i].code >> sh) & 0xffffu]++] = k[i];
        memcpy(k, tmp, n * sizeof *k);
    }
    free(cnt);
    for (size_t i = 0; i < n;) {
        size_t j = i + 1;
        while (j < n && k[j].code == k[i].code) j++;
        sort_run(c, k + i, tmp, j - i);
        i = j;
    }
    return 0;
}

typedef struct tctx {
    lci_pbvh *b;
    const cctx *c;
    const ckey *k;
    int leaf_size;
    int32_t next_node;
    int32_t depth;
} tctx;

/* Node `slot` over the sorted keys [lo, hi). */
static void build(tctx *t, int32_t slot, size_t lo, size_t hi, int32_t depth)
{
    if (depth > t->depth) t->depth = depth;
    lc_kpnode *o = &t->b->nodes[slot];
    if (hi - lo <= (size_t)t->leaf_size) {
        float bl[3] = {1e30f, 1e30f, 1e30f}, bh[3] = {-1e30f, -1e30f, -1e30f}, rm = 0.0f;
        o->first = (int32_t)lo, o->count = (int32_t)(hi - lo);
        for (size_t j = lo; j < hi; j++) {
            uint32_t id = t->k[j].id;
            t->b->order[j] = id;
            for (int a = 0; a < 3; a++) {
                float v = t->c->xyz[3 * (size_t)id + (size_t)a];
                bl[a] = v < bl[a] ? v : bl[a];
                bh[a] = v > bh[a] ? v : bh[a];
            }
            float ri = t->c->r ? t->c->r[id] : t->c->r_all;
            rm = ri > rm ? ri : rm;
        }
        memcpy(o->lo, bl, sizeof bl), memcpy(o->hi, bh, sizeof bh);
        t->b->rmax[slot] = rm;
        return;
    }
    uint64_t a = t->k[lo].code, z = t->k[hi - 1].code;
    size_t m = lo + (hi - lo) / 2;
    if (a != z) { /* the first key with the highest differing bit set */
        int bit = 63 - __builtin_clzll(a ^ z);
        size_t l = lo, h = hi - 1; /* k[l] has it clear, k[h] set */
        while (h - l > 1) {
            size_t q = l + (h - l) / 2;
            if ((t->k[q].code >> bit) & 1u) h = q;
            else l = q;
        }
        m = h;
    }
    int32_t first = t->next_node;
    t->next_node += 2;
    o->first = first, o->count = 0;
    build(t, first, lo, m, depth + 1);
    build(t, first + 1, m, hi, depth + 1);
    const lc_kpnode *l = &t->b->nodes[first], *r = &t->b->nodes[first + 1];
    for (int x = 0; x < 3; x++) {
        o->lo[x] = l->lo[x] < r->lo[x] ? l->lo[x] : r->lo[x];
        o->hi[x] = l->hi[x] > r->hi[x] ? l->hi[x] : r->hi[x];
    }
    float ra = t->b->rmax[first], rb = t->b->rmax[first + 1];
    t->b->rmax[slot] = ra > rb ? ra : rb;
}

int lci_pbvh_build_canonical(const float *xyz, const float *r, float r_all, size_t n, int leaf_size,
                             const lci_pbvh_keys *keys, lci_pbvh *out, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    if (n == 0) return 0;
    if (lci_pbvh_check_size(n, leaf_size, err, errlen)) return -1;
    size_t cap = 2 * n - 1;
    ckey *k = malloc(n * sizeof *k), *tmp = malloc(n * sizeof *tmp);
    out->nodes = malloc(cap * sizeof *out->nodes);
    out->rmax = malloc(cap * sizeof *out->rmax);
    out->order = malloc(n * sizeof *out->order);
    if (!k || !tmp || !out->nodes || !out->rmax || !out->order) {
        free(k), free(tmp);
        lci_pbvh_free(out);
        snprintf(err, errlen, "out of memory for the canonical BVH of %zu particles", n);
        return -1;
    }
    cctx c = {xyz, r, r_all, keys};
    for (size_t i = 0; i < n; i++) {
        const float *p = xyz + 3 * i;
        k[i].code = spread3(cell(p[0], keys->lo[0], keys->hi[0])) << 2 |
                    spread3(cell(p[1], keys->lo[1], keys->hi[1])) << 1 | spread3(cell(p[2], keys->lo[2], keys->hi[2]));
        k[i].id = (uint32_t)i, k[i].pad_ = 0;
    }
    int rc = sort_keys(&c, k, tmp, n);
    free(tmp);
    if (rc != 0) {
        free(k);
        lci_pbvh_free(out);
        snprintf(err, errlen, "out of memory sorting %zu particles", n);
        return -1;
    }
    tctx t = {out, &c, k, leaf_size, 1, 0};
    build(&t, 0, 0, n, 0);
    free(k);
    out->nnodes = t.next_node;
    out->depth = t.depth;
    return 0;
}
