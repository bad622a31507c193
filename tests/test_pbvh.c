/* The particle BVH builders (bvh/particle_bvh.c, bvh/particle_bvh_sah.c):
 * every builder on every input below must give a tree the kernels can walk:
 * every particle exactly once in leaf order, leaves of 1..leaf_size, node
 * boxes containing their particles' centres (so the box grown by
 * sigma * rmax contains every support, for any sigma), rmax at least every
 * radius below, children after their parent and siblings adjacent, the
 * reported depth at least the real one, at most 2n - 1 nodes. Inputs:
 * uniform and clustered sets with mixed radii, all particles at one point,
 * one particle, particles on a plane, on a line, coordinates and radii up to
 * the 1e18 particles.c admits, centres a few subnormals apart, 2^20 + 3
 * particles (32-bit sized loops). check() is shown to fail on corrupted
 * trees first. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "bvh/embree.h"
#include "bvh/particle_bvh.h"

static int failures;
#define FAIL(...) (fprintf(stderr, __VA_ARGS__), fputc('\n', stderr), failures++)

typedef struct set {
    const char *name;
    size_t n;
    float *xyz, *r;
    float r_all;
} set;

/* Why the tree is broken, or NULL. */
static const char *check(const lci_pbvh *b, const set *s, int leaf_size, char *why, size_t len)
{
    size_t n = s->n;
    if (b->nnodes < 1 || (size_t)b->nnodes > 2 * n - 1) return snprintf(why, len, "%d nodes for %zu particles", b->nnodes, n), why;
    /* order is freed by particles.c after reordering; the builders return it */
    if (!b->order || !b->nodes || !b->rmax) return "missing arrays";
    unsigned char *seen = calloc(n, 1), *leaf_seen = calloc(n, 1);
    int32_t *depth = calloc((size_t)b->nnodes, sizeof *depth), *parent = malloc((size_t)b->nnodes * sizeof *parent);
    const char *bad = NULL;
    for (size_t j = 0; j < n && !bad; j++) {
        uint32_t i = b->order[j];
        if (i >= n) bad = "order entry out of range";
        else if (seen[i]++) snprintf(why, len, "particle %u twice in leaf order", i), bad = why;
    }
    for (int32_t k = 0; k < b->nnodes; k++) parent[k] = -1;
    for (int32_t k = 0; k < b->nnodes && !bad; k++) {
        const lc_kpnode *o = &b->nodes[k];
        if (o->count < 0) snprintf(why, len, "node %d: count %d", k, o->count), bad = why;
        else if (o->count == 0) { /* inner */
            if (o->first <= k || o->first + 1 >= b->nnodes)
                snprintf(why, len, "node %d: children at %d of %d nodes", k, o->first, b->nnodes), bad = why;
            for (int c = 0; c < 2 && !bad; c++) {
                int32_t ch = o->first + c;
                if (parent[ch] >= 0) snprintf(why, len, "node %d has two parents", ch), bad = why;
                parent[ch] = k;
                depth[ch] = depth[k] + 1;
                const lc_kpnode *q = &b->nodes[ch];
                for (int a = 0; a < 3 && !bad; a++)
                    if (q->lo[a] < o->lo[a] || q->hi[a] > o->hi[a])
                        snprintf(why, len, "node %d's box does not contain child %d's", k, ch), bad = why;
                if (!bad && b->rmax[ch] > b->rmax[k]) snprintf(why, len, "node %d: rmax below child %d's", k, ch), bad = why;
            }
        } else { /* leaf */
            if (o->count > leaf_size) snprintf(why, len, "leaf %d holds %d > %d", k, o->count, leaf_size), bad = why;
            else if (o->first < 0 || (size_t)o->first + (size_t)o->count > n)
                snprintf(why, len, "leaf %d: range %d+%d of %zu", k, o->first, o->count, n), bad = why;
            for (int32_t j = o->first; j < o->first + o->count && !bad; j++) {
                if (leaf_seen[j]++) snprintf(why, len, "leaf-order slot %d in two leaves", j), bad = why;
                uint32_t i = b->order[j];
                float ri = s->r ? s->r[i] : s->r_all;
                for (int a = 0; a < 3 && !bad; a++) {
                    float c = s->xyz[3 * (size_t)i + (size_t)a];
                    if (c < o->lo[a] || c > o->hi[a])
                        snprintf(why, len, "leaf %d: particle %u's centre outside the box", k, i), bad = why;
                }
                if (!bad && !(ri <= b->rmax[k])) snprintf(why, len, "leaf %d: radius of %u above rmax", k, i), bad = why;
            }
            if (!bad && depth[k] > b->depth) snprintf(why, len, "leaf %d at depth %d > reported %d", k, depth[k], b->depth), bad = why;
        }
    }
    for (int32_t k = 1; k < b->nnodes && !bad; k++)
        if (parent[k] < 0) snprintf(why, len, "node %d unreachable", k), bad = why;
    for (size_t j = 0; j < n && !bad; j++)
        if (!leaf_seen[j]) snprintf(why, len, "leaf-order slot %zu in no leaf", j), bad = why;
    free(seen), free(leaf_seen), free(depth), free(parent);
    return bad;
}

static uint64_t rs = 0x9e3779b97f4a7c15ull;
static float urand(void)
{
    rs ^= rs << 13, rs ^= rs >> 7, rs ^= rs << 17;
    return (float)(rs >> 40) / 16777216.0f;
}

/* kind: 0 uniform, 1 clustered (8 tight clusters + background), 2 one point,
 * 3 plane z = 5, 4 line along x, 5 the extremes particles.c admits (coordinates
 * and radii up to 1e18), 6 centres a few subnormals apart (bin scales overflow) */
static set make(const char *name, size_t n, int kind, int radii)
{
    set s = {name, n, malloc(3 * n * sizeof(float)), radii ? malloc(n * sizeof(float)) : NULL, 0.75f};
    if (!s.xyz || (radii && !s.r)) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    for (size_t i = 0; i < n; i++) {
        float *p = s.xyz + 3 * i;
        for (int a = 0; a < 3; a++) p[a] = 100.0f * urand();
        if (kind == 1 && i % 10) {
            int c = (int)(i % 8);
            for (int a = 0; a < 3; a++) p[a] = 10.0f + 10.0f * (float)c + 0.3f * (urand() - 0.5f);
        }
        if (kind == 2) p[0] = 3.0f, p[1] = -2.0f, p[2] = 7.0f;
        if (kind == 3) p[2] = 5.0f;
        if (kind == 4) p[1] = p[2] = 1.0f;
        if (kind == 5)
            for (int a = 0; a < 3; a++) p[a] = (i % 3 == 0 ? 1e18f : 1e16f) * (2.0f * urand() - 1.0f);
        if (kind == 6)
            for (int a = 0; a < 3; a++) p[a] = 1e-45f * (float)(int)(4.0f * urand());
        if (radii) s.r[i] = kind == 5 ? (i % 5 == 0 ? 1e18f : 1e10f * urand() + 1.0f) : 0.2f + 2.0f * urand() * urand();
    }
    return s;
}

static const char *const bnames[] = {"default", "embree", "sah"};

static void run(void *dev, const set *s, lci_pbvh_builder bld, int leaf)
{
    lci_pbvh b;
    char err[256], why[256];
    if (lci_pbvh_build_ex(dev, s->xyz, s->r, s->r_all, s->n, leaf, bld, &b, err, sizeof err) != 0) {
        FAIL("%s, %s, leaf %d: build failed: %s", s->name, bnames[bld], leaf, err);
        return;
    }
    const char *bad = check(&b, s, leaf, why, sizeof why);
    if (bad) FAIL("%s, %s, leaf %d: %s", s->name, bnames[bld], leaf, bad);
    lci_pbvh_free(&b);
}

/* check() must reject trees broken in each way it looks for. */
static void check_can_fail(void *dev)
{
    set s = make("corruption", 5000, 0, 1);
    const char *what[] = {"duplicate particle", "shrunk leaf box", "small rmax", "oversized leaf", "child before parent",
                          "shallow depth"};
    for (int w = 0; w < 6; w++) {
        lci_pbvh b;
        char err[256], why[256];
        if (lci_pbvh_build_ex(dev, s.xyz, s.r, 0, s.n, 4, LCI_PBVH_SAH, &b, err, sizeof err) != 0) {
            FAIL("corruption base build: %s", err);
            break;
        }
        int32_t leaf = -1, inner = 0;
        for (int32_t k = 0; k < b.nnodes && leaf < 0; k++)
            if (b.nodes[k].count >= 2) leaf = k;
        if (w == 0) b.order[1] = b.order[0];
        if (w == 1) b.nodes[leaf].hi[0] = b.nodes[leaf].lo[0] - 1.0f;
        if (w == 2) b.rmax[leaf] = 0.0f;
        if (w == 3) b.nodes[leaf].count = 9;
        if (w == 4) b.nodes[inner].first = 0;
        if (w == 5) b.depth = 1;
        if (!check(&b, &s, 4, why, sizeof why)) FAIL("check() accepted a tree with a %s", what[w]);
        lci_pbvh_free(&b);
    }
    free(s.xyz), free(s.r);
}

int main(void)
{
    char err[256];
    void *dev = lci_embree_new(2, NULL, NULL, err, sizeof err);
    if (!dev) {
        fprintf(stderr, "%s\n", err);
        return 1;
    }
    check_can_fail(dev);
    set sets[] = {make("uniform 20000", 20000, 0, 1), make("clustered 20000", 20000, 1, 1),
                  make("one point 5000", 5000, 2, 1), make("one point, one radius 3000", 3000, 2, 0),
                  make("plane 20000", 20000, 3, 1),   make("line 20000", 20000, 4, 0),
                  make("1 particle", 1, 0, 1),        make("2 particles", 2, 0, 0),
                  make("33 particles", 33, 1, 1),     make("coordinates and radii to 1e18", 5000, 5, 1),
                  make("subnormal spread", 5000, 6, 0)};
    int nsets = (int)(sizeof sets / sizeof sets[0]);
    for (int i = 0; i < nsets; i++)
        for (int bld = LCI_PBVH_EMBREE; bld <= LCI_PBVH_SAH; bld++)
            for (int l = 0; l < 4; l++)
                run(dev, &sets[i], (lci_pbvh_builder)bld, (int[]){1, 4, 16, 32}[l]);
    /* past 2^20: 32-bit sized loops */
    set big = make("2^20 + 3 uniform", (1u << 20) + 3, 0, 1), same = make("2^20 + 3 at one point", (1u << 20) + 3, 2, 0);
    for (int bld = LCI_PBVH_EMBREE; bld <= LCI_PBVH_SAH; bld++) {
        run(dev, &big, (lci_pbvh_builder)bld, 4);
        run(dev, &same, (lci_pbvh_builder)bld, 4);
    }
    for (int i = 0; i < nsets; i++) free(sets[i].xyz), free(sets[i].r);
    free(big.xyz), free(big.r), free(same.xyz);
    /* bad arguments are refused with a message, not a crash */
    lci_pbvh b;
    err[0] = 0;
    if (lci_pbvh_build_ex(dev, (float[3]){0, 0, 0}, NULL, 1.0f, 1, 33, LCI_PBVH_SAH, &b, err, sizeof err) == 0 ||
        !err[0])
        FAIL("leaf size 33 accepted");
    lci_embree_free(dev);
    if (failures) fprintf(stderr, "%d failures\n", failures);
    else printf("particle BVH builders: all trees valid\n");
    return failures ? 1 : 0;
}
