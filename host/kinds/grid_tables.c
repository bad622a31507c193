/* A grid's per-frame tables (Knoll et al. 2011): the pre-integrated TF
 * (eq. 4), its opacity over one step, and the BVH's per-node TF bits (eqs.
 * 5-7, kgrid.h node_tf_bits), kept per volume while what they depend on is
 * unchanged. Building them is serial work inside the frame (~2-6 % of a
 * 1024^2 medium frame: the 65536-entry table, 65536 expf and a pass over
 * every node); a camera move with the same TF, step and parameters reuses
 * them.
 *
 * Key: the TF's kernel table of field 0 (rgbt, bitwise) and its range, dt,
 * the grid parameters that enter (cull/prune/const flags and deltas), and
 * which node bits were computed (mode dvr or not, unshaded or not, with or
 * without the node pass). The voxels and the BVH never change after
 * creation, so they need no key; lc_grid_set_params changes the key.
 *
 * The entry lives in the volume's cache slot (host/api/vcache.h: mutex,
 * reference counts, never written after it is published). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "host/kinds/grid.h"

struct lci_grid_tables {
    lci_vcache_entry head; /* first (vcache.h) */
    /* key */
    float rgbt[LC_TF_TABLE_SIZE * 4];
    float tf_lo, tf_inv_range, dt;
    float delta_c, delta_p, delta_sv;
    int32_t bvh_flags;
    int32_t node_pass; /* 0: no node bits; else 1 + dvr + 2 * unshaded */
    /* values, 64-byte aligned after the header */
    float *table; /* LC_PREINT_N^2 x (r, g, b, tau_mean) */
    float *alpha; /* LC_PREINT_N^2: 1 - exp(-tau_mean dt) */
    uint8_t *bits; /* nnodes (node_pass != 0) */
};

/* The frame's per-node TF tests (kgrid.h LC_KGRID_NODE_*), the formulas the
 * BVH kernel used per visit (eqs. 5-7) on the pre-integrated table and its
 * one-step opacity alpha. Only the bits the kernel can read are computed: a
 * dvr traversal never visits an EMPTY node, and reads CONST only on unshaded
 * dvr frames. */
static void node_flags(const lc_kgrid *k, const lc_kframe *f, const float *table, const float *alpha, uint8_t *out)
{
    const lc_ktf *tf = &f->tf[0];
    const int dvr = f->mode == LC_KMODE_DVR;
    const int want_const = (k->bvh_flags & LC_KGRID_CONST) && dvr && f->shade == LC_KSHADE_NONE;
    const int want_dense = (k->bvh_flags & LC_KGRID_PRUNE) != 0;
    for (int32_t i = 0; i < k->nnodes; i++) {
        const lc_kgrid_node *n = &k->nodes[i];
        int qa, qb;
        lc_kgrid_node_quant(n->vmin, n->vmax, tf->lo, tf->inv_range, &qa, &qb);
        size_t q = (size_t)qa * LC_PREINT_N + (size_t)qb;
        uint8_t fl = 0;
        if (table[4 * q + 3] == 0.0f || ((k->bvh_flags & LC_KGRID_CULL) && alpha[q] <= k->delta_c)) {
            fl = LC_KGRID_NODE_EMPTY;
            if (dvr) {
                out[i] = fl;
                continue;
            }
        }
        if (want_dense && alpha[q] * k->diag_volume > k->delta_p * lc_kgrid_node_diag(n)) fl |= LC_KGRID_NODE_DENSE;
        if (want_const && n->vmin != n->vmax) {
            /* eq. 7 with the colour condition (kernels/grid_bvh.c node_constant) */
            size_t ql = (size_t)qa * LC_PREINT_N + (size_t)qa, qh = (size_t)qb * LC_PREINT_N + (size_t)qb;
            float r = alpha[q], rl = alpha[ql], rh = alpha[qh];
            const float *cl = table + 4 * ql, *ch = table + 4 * qh;
            float dc = fmaxf(fmaxf(fabsf(cl[0] - ch[0]), fabsf(cl[1] - ch[1])), fabsf(cl[2] - ch[2]));
            if (fmaxf(fabsf(r - rl), fabsf(r - rh)) < k->delta_sv && dc * r < k->delta_sv) fl |= LC_KGRID_NODE_CONST;
        }
        out[i] = fl;
    }
}

static int node_pass_of(const lc_kframe *f, int with_nodes)
{
    if (!with_nodes) return 0;
    return 1 + (f->mode == LC_KMODE_DVR) + 2 * (f->shade == LC_KSHADE_NONE);
}

/* Does entry t hold the tables frame f needs under k's parameters? An entry
 * with node bits also serves a frame that needs none (brute force). */
static int matches(const lci_grid_tables *t, const lc_kgrid *k, const lc_kframe *f, int with_nodes)
{
    const lc_ktf *tf = &f->tf[0];
    if (t->tf_lo != tf->lo || t->tf_inv_range != tf->inv_range || t->dt != f->dt) return 0;
    if (t->bvh_flags != k->bvh_flags || t->delta_c != k->delta_c || t->delta_p != k->delta_p ||
        t->delta_sv != k->delta_sv)
        return 0;
    int np = node_pass_of(f, with_nodes);
    if (np != 0 && t->node_pass != np) return 0;
    return memcmp(t->rgbt, tf->rgbt, sizeof t->rgbt) == 0;
}

/* what a frame asks the cache for */
typedef struct tables_key {
    const lc_kgrid *k;
    const lc_kframe *f;
    int with_nodes;
} tables_key;

static int matches_key(const lci_vcache_entry *e, const void *key)
{
    const tables_key *q = key;
    return matches((const lci_grid_tables *)e, q->k, q->f, q->with_nodes);
}

static lci_vcache_entry *build(const void *key)
{
    const tables_key *q = key;
    const lc_kgrid *k = q->k;
    const lc_kframe *f = q->f;
    const int with_nodes = q->with_nodes;
    size_t head = (sizeof(lci_grid_tables) + 63) & ~(size_t)63;
    size_t nbits = with_nodes ? (size_t)k->nnodes : 0;
    size_t bytes = head + sizeof(float) * (size_t)LC_PREINT_N * LC_PREINT_N * 5 + nbits;
    unsigned char *mem = lci_aligned_alloc(64, bytes);
    if (!mem) return NULL;
    lci_grid_tables *t = (lci_grid_tables *)mem;
    const lc_ktf *tf = &f->tf[0];
    memcpy(t->rgbt, tf->rgbt, sizeof t->rgbt);
    t->tf_lo = tf->lo, t->tf_inv_range = tf->inv_range, t->dt = f->dt;
    t->delta_c = k->delta_c, t->delta_p = k->delta_p, t->delta_sv = k->delta_sv;
    t->bvh_flags = k->bvh_flags;
    t->node_pass = node_pass_of(f, with_nodes);
    t->table = (float *)(mem + head);
    lci_grid_preint(tf->rgbt, t->table);
    t->alpha = t->table + (size_t)LC_PREINT_N * LC_PREINT_N * 4;
    for (size_t i = 0; i < (size_t)LC_PREINT_N * LC_PREINT_N; i++) t->alpha[i] = 1.0f - expf(-t->table[4 * i + 3] * f->dt);
    t->bits = with_nodes ? (uint8_t *)(t->alpha + (size_t)LC_PREINT_N * LC_PREINT_N) : NULL;
    if (with_nodes) node_flags(k, f, t->table, t->alpha, t->bits);
    return &t->head;
}

void lci_grid_tables_release(lci_grid_tables *t) { lci_vcache_release(t ? &t->head : NULL); }

lci_grid_tables *lci_grid_tables_get(grid *g, const lc_kgrid *k, const lc_kframe *f, int with_nodes)
{
    tables_key key = {k, f, with_nodes};
    return (lci_grid_tables *)lci_vcache_get(&g->tables_mu, &g->tables, matches_key, build, &key);
}

void lci_grid_tables_fill(const lci_grid_tables *t, lc_kgrid *k)
{
    k->preint = t->table;
    k->node_tf_bits = t->bits;
}
