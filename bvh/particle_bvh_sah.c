/* The particle BVH's own builder: top-down binned SAH over the centres,
 * written straight into the flat lc_kpnode layout (no intermediate tree, no
 * 32-byte build primitives). Why: Embree's builder needs its primitive array
 * (32 B per particle) and a pointer tree beside the flat copy; this one needs
 * 16 B per particle (centre and radius, partitioned in place with the order
 * array the caller gets anyway) plus the final nodes (docs/bench/particles.md,
 * "Build peak").
 *
 * Cost model as the Embree build it replaces (RTC_BUILD_QUALITY_MEDIUM,
 * traversal cost 1, intersection cost 0.5, leaves of 1..leaf_size): a node
 * becomes a leaf when it holds at most leaf_size particles and
 * 0.5 n A(node) <= A(node) + 0.5 (nL A(L) + nR A(R)), with A the half
 * surface of a box. Boxes are the centre bounds grown by 2 rmax (the box the
 * kernels test at the default sigma 2), so the cost sees what the traversal
 * tests. Per axis min(32, 4 + n / 20) bins over the node's centre bounds
 * (Embree's count), the bins spanning 1/0.99 of the bounds as Embree's do:
 * with bins ending exactly at the bounds, uniform data splits exactly at the
 * centre of the root box, the plane a camera aimed at the data's centre
 * looks along, and a close view of 10M uniform particles then tests 47%
 * more nodes (0.29 s against 0.26 s CPU per frame; docs/bench/particles.md). Where no split
 * separates the centres (all in one bin on every axis) or below depth 64,
 * nodes split at the object median of their longest axis (quickselect), so
 * depth <= 64 + log2(n) + 1 whatever the input. With threads >= 2 the
 * root's two subtrees build on two threads (build_two); the tree is the same. */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "particle_bvh.h"

#define BINS 32
#define MEDIAN_DEPTH 64
#define STACK (MEDIAN_DEPTH + 40)
#define TRAV_COST 1.0
#define ISECT_COST 0.5
#define GROW 2.0f /* boxes for the cost: centre bounds grown by GROW * rmax */

typedef struct pt {
    float c[3], r;
} pt;

typedef struct cbox { /* centre bounds and largest radius of a set */
    float lo[3], hi[3], rmax;
    uint32_t n;
} cbox;

typedef struct task {
    uint32_t first, count;
    int32_t slot, depth;
    cbox b;
} task;

static void cbox_empty(cbox *b)
{
    for (int a = 0; a < 3; a++) b->lo[a] = 1e30f, b->hi[a] = -1e30f;
    b->rmax = 0.0f;
    b->n = 0;
}

static void cbox_add_pt(cbox *b, const pt *p)
{
    for (int a = 0; a < 3; a++) {
        b->lo[a] = p->c[a] < b->lo[a] ? p->c[a] : b->lo[a];
        b->hi[a] = p->c[a] > b->hi[a] ? p->c[a] : b->hi[a];
    }
    b->rmax = p->r > b->rmax ? p->r : b->rmax;
    b->n++;
}

static void cbox_merge(cbox *b, const cbox *o)
{
    for (int a = 0; a < 3; a++) {
        b->lo[a] = o->lo[a] < b->lo[a] ? o->lo[a] : b->lo[a];
        b->hi[a] = o->hi[a] > b->hi[a] ? o->hi[a] : b->hi[a];
    }
    b->rmax = o->rmax > b->rmax ? o->rmax : b->rmax;
    b->n += o->n;
}

/* Half surface of the box the cost model uses (double: no overflow at the
 * largest coordinates particles.c admits). */
static double half_area(const cbox *b)
{
    double g = 2.0 * (double)(GROW * b->rmax), d[3];
    for (int a = 0; a < 3; a++) d[a] = (double)b->hi[a] - (double)b->lo[a] + g;
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
}

/* The bin of coordinate c; the same expression bins and partitions. */
static inline int bin_of(float c, float lo, float scale, int nbins)
{
    float f = (c - lo) * scale;
    int k = f > 0.0f ? (int)f : 0;
    return k < nbins ? k : nbins - 1;
}

typedef struct split {
    int axis, bin; /* particles with bin_of(c[axis]) < bin go left */
    int nbins;
    double cost;   /* nL A(L) + nR A(R) */
    cbox left, right;
} split;

/* The best binned SAH split of p[0..n), or axis -1 when no bin boundary
 * separates the centres. */
static split best_split(const pt *p, uint32_t n, const cbox *b, float scale[3])
{
    cbox bins[3][BINS];
    /* fewer bins for small nodes, as Embree's binning: most nodes are small */
    int nb = 4 + (int)(n / 20);
    nb = nb < BINS ? nb : BINS;
    for (int a = 0; a < 3; a++) {
        float ext = b->hi[a] - b->lo[a];
        scale[a] = ext > 0.0f ? (float)nb * 0.99f / ext : 0.0f;
        if (!(scale[a] < 1e30f)) scale[a] = 0.0f; /* a subnormal extent: no binning on this axis */
        for (int k = 0; k < nb; k++) cbox_empty(&bins[a][k]);
    }
    for (uint32_t i = 0; i < n; i++)
        for (int a = 0; a < 3; a++)
            if (scale[a] > 0.0f) cbox_add_pt(&bins[a][bin_of(p[i].c[a], b->lo[a], scale[a], nb)], &p[i]);
    split best = {.axis = -1, .nbins = nb};
    for (int a = 0; a < 3; a++) {
        if (!(scale[a] > 0.0f)) continue;
        cbox right[BINS], acc;
        cbox_empty(&acc);
        for (int k = nb - 1; k >= 0; k--) cbox_merge(&acc, &bins[a][k]), right[k] = acc;
        cbox_empty(&acc);
        for (int k = 1; k < nb; k++) {
            cbox_merge(&acc, &bins[a][k - 1]);
            if (!acc.n || !right[k].n) continue;
            double c = (double)acc.n * half_area(&acc) + (double)right[k].n * half_area(&right[k]);
            if (best.axis < 0 || c < best.cost) best = (split){a, k, nb, c, acc, right[k]};
        }
    }
    return best;
}

static void swap_pt(pt *p, uint32_t *id, int64_t i, int64_t j)
{
    pt t = p[i];
    p[i] = p[j], p[j] = t;
    uint32_t u = id[i];
    id[i] = id[j], id[j] = u;
}

/* Puts the k-th smallest centre along axis a at k, smaller ones before it
 * (Hoare partitions: equal keys split evenly, so all-equal input is linear). */
static void select_nth(pt *p, uint32_t *id, int64_t lo, int64_t hi, int64_t k, int a)
{
    while (hi > lo) {
        float x = p[lo].c[a], y = p[lo + (hi - lo) / 2].c[a], z = p[hi].c[a];
        float piv = x < y ? (y < z ? y : (x < z ? z : x)) : (x < z ? x : (y < z ? z : y));
        int64_t i = lo, j = hi;
        while (i <= j) {
            while (p[i].c[a] < piv) i++;
            while (p[j].c[a] > piv) j--;
            if (i <= j) swap_pt(p, id, i++, j--);
        }
        if (k <= j) hi = j;
        else if (k >= i) lo = i;
        else return;
    }
}

/* Median split of t along its longest centre axis: the children's bounds. */
static void median_split(pt *p, uint32_t *id, const task *t, cbox *l, cbox *r)
{
    int a = 0;
    for (int q = 1; q < 3; q++)
        if (t->b.hi[q] - t->b.lo[q] > t->b.hi[a] - t->b.lo[a]) a = q;
    uint32_t nl = t->count / 2;
    if (t->b.hi[a] > t->b.lo[a]) select_nth(p + t->first, id + t->first, 0, (int64_t)t->count - 1, nl, a);
    cbox_empty(l), cbox_empty(r);
    for (uint32_t i = 0; i < t->count; i++) cbox_add_pt(i < nl ? l : r, &p[t->first + i]);
}

/* Moves the particles of bins < s.bin to the front of the task's range. */
static void partition(pt *p, uint32_t *id, const task *t, const split *s, const float scale[3])
{
    int a = s->axis;
    float lo = t->b.lo[a], sc = scale[a];
    int64_t i = t->first, j = (int64_t)t->first + t->count - 1;
    while (i <= j) {
        if (bin_of(p[i].c[a], lo, sc, s->nbins) < s->bin) i++;
        else swap_pt(p, id, i, j--);
    }
}

static void write_node(lci_pbvh *o, const task *t, int32_t first, int32_t count)
{
    lc_kpnode *n = &o->nodes[t->slot];
    memcpy(n->lo, t->b.lo, sizeof n->lo);
    memcpy(n->hi, t->b.hi, sizeof n->hi);
    n->first = first;
    n->count = count;
    o->rmax[t->slot] = t->b.rmax;
}

typedef struct bctx {
    pt *p;
    lci_pbvh *out;
    int leaf_size;
} bctx;

/* Makes t a leaf (returns 0) or splits it into *l and *r, its children in
 * slots child and child + 1 (returns 1). */
static int split_task(const bctx *c, const task *t, int32_t child, task *l, task *r)
{
    if (t->count == 1) {
        write_node(c->out, t, (int32_t)t->first, 1);
        return 0;
    }
    cbox lb, rb;
    split s = {.axis = -1};
    float scale[3] = {0};
    if (t->depth < MEDIAN_DEPTH) s = best_split(c->p + t->first, t->count, &t->b, scale);
    if (t->count <= (uint32_t)c->leaf_size) {
        double a = half_area(&t->b);
        if (s.axis < 0 || ISECT_COST * t->count * a <= TRAV_COST * a + ISECT_COST * s.cost) {
            write_node(c->out, t, (int32_t)t->first, (int32_t)t->count);
            return 0;
        }
    }
    if (s.axis >= 0) {
        partition(c->p, c->out->order, t, &s, scale);
        lb = s.left, rb = s.right;
    } else
        median_split(c->p, c->out->order, t, &lb, &rb);
    write_node(c->out, t, child, 0);
    *l = (task){t->first, lb.n, child, t->depth + 1, lb};
    *r = (task){t->first + lb.n, rb.n, child + 1, t->depth + 1, rb};
    return 1;
}

/* The subtree under root (its slot already chosen), new nodes from slot
 * `next` on, depth-first with siblings adjacent. */
typedef struct subtree {
    const bctx *c;
    task root;
    int32_t next, depth; /* in: first free slot; out: one past the last slot used, deepest node */
    int ok;
} subtree;

static void *build_subtree(void *arg)
{
    subtree *st = arg;
    task stack[STACK];
    int sp = 0;
    stack[sp++] = st->root;
    st->ok = 1;
    while (sp > 0) {
        task t = stack[--sp], l, r;
        st->depth = t.depth > st->depth ? t.depth : st->depth;
        if (!split_task(st->c, &t, st->next, &l, &r)) continue;
        if (sp + 2 > STACK) { /* cannot happen: depth <= MEDIAN_DEPTH + 32 */
            st->ok = 0;
            break;
        }
        st->next += 2;
        stack[sp++] = r; /* the left child is popped next */
        stack[sp++] = l;
    }
    return NULL;
}

/* Two threads: the root's left subtree from slot 3 on, its right one from
 * slot 1 + 2 nL on (past the most nodes the left one can need, 2 nL - 2);
 * close_gap then moves the right one's nodes down. Untouched gap pages never
 * become resident. Returns 0, or -1 when no thread could start (the caller
 * builds serially). */
static int build_two(const bctx *c, const task *root, subtree *left, subtree *right)
{
    task l, r;
    if (!split_task(c, root, 1, &l, &r)) {
        *left = (subtree){c, *root, 1, 0, 1}, *right = (subtree){c, *root, 0, 0, 1};
        return 0;
    }
    *left = (subtree){c, l, 3, 1, 0};
    *right = (subtree){c, r, (int32_t)(1 + 2 * l.count), 1, 0};
    pthread_t th;
    if (pthread_create(&th, NULL, build_subtree, right) != 0) return -1;
    build_subtree(left);
    pthread_join(th, NULL);
    return 0;
}

/* After build_two (and after the scratch is freed: the moved block is
 * briefly resident twice): the right subtree's nodes follow the left's. */
static void close_gap(lci_pbvh *o, subtree *left, const subtree *right)
{
    if (right->next == 0) return; /* the root was a leaf */
    int32_t base = (int32_t)(1 + 2 * (size_t)(right->root.first)); /* right->root.first = nL */
    int32_t shift = base - left->next, count = right->next - base;
    memmove(o->nodes + left->next, o->nodes + base, (size_t)count * sizeof *o->nodes);
    memmove(o->rmax + left->next, o->rmax + base, (size_t)count * sizeof *o->rmax);
    for (int32_t k = left->next; k < left->next + count; k++)
        if (o->nodes[k].count == 0) o->nodes[k].first -= shift;
    if (o->nodes[2].count == 0) o->nodes[2].first -= shift;
    left->next += count;
    left->depth = left->depth > right->depth ? left->depth : right->depth;
    left->ok = left->ok && right->ok;
}

int lci_pbvh_build_sah(const float *xyz, const float *r, float r_all, size_t n, int leaf_size, int threads,
                       lci_pbvh *out, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out); /* n >= 1 and leaf_size in 1..32: lci_pbvh_build_ex checked */
    size_t cap = 2 * n - 1; /* a binary tree over n leaves' worth of particles */
    pt *p = malloc(n * sizeof *p);
    out->order = malloc(n * sizeof *out->order);
    out->nodes = malloc(cap * sizeof *out->nodes);
    out->rmax = malloc(cap * sizeof *out->rmax);
    if (!p || !out->order || !out->nodes || !out->rmax) {
        free(p);
        lci_pbvh_free(out);
        snprintf(err, errlen, "out of memory for the BVH of %zu particles", n);
        return -1;
    }
    task root = {.first = 0, .count = (uint32_t)n, .slot = 0, .depth = 0};
    cbox_empty(&root.b);
    for (size_t i = 0; i < n; i++) {
        p[i] = (pt){{xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]}, r ? r[i] : r_all};
        out->order[i] = (uint32_t)i;
        cbox_add_pt(&root.b, &p[i]);
    }
    bctx c = {p, out, leaf_size};
    subtree all = {&c, root, 1, 0, 0}, right = {&c, root, 0, 0, 1};
    /* two threads pay from ~64k particles on (thread start-up ~50 us) */
    if (threads < 2 || n < (1u << 16) || build_two(&c, &root, &all, &right) != 0) {
        all = (subtree){&c, root, 1, 0, 0};
        right.next = 0;
        build_subtree(&all);
    }
    free(p);
    close_gap(out, &all, &right);
    if (!all.ok) {
        lci_pbvh_free(out);
        snprintf(err, errlen, "BVH deeper than %d levels", STACK);
        return -1;
    }
    out->nnodes = all.next;
    out->depth = all.depth;
    lc_kpnode *nn = realloc(out->nodes, (size_t)all.next * sizeof *nn);
    float *rm = realloc(out->rmax, (size_t)all.next * sizeof *rm);
    out->nodes = nn ? nn : out->nodes; /* shrinking: keeping the larger block is no error */
    out->rmax = rm ? rm : out->rmax;
    return 0;
}
