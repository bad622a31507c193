/* Particle BVH builds. The default is Embree's rtcBuildBVH with
 * RTC_BUILD_QUALITY_MEDIUM (binned SAH, binary, leaves of at most leaf_size
 * particles): the project's stated builder, and within the build-peak budget
 * of issue 8. The own binned SAH builder (bvh/particle_bvh_sah.c) stays for
 * A/B runs (LANECAST_PBVH_BUILDER, lanecast bench --builders); Embree LOW and
 * chunked Embree builds were measured and removed (docs/bench/particles.md
 * "Build peak" and its ledger). Embree's tree is flattened depth-first with
 * siblings adjacent. Embree runs the callbacks on several TBB threads: nodes
 * come from rtcThreadLocalAlloc and the callbacks only write their own node.
 * Node boxes and rmax are recomputed from the centres after the build (the
 * builder's boxes include the radius and some builders set them before
 * children exist). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <embree3/rtcore.h>
#include <embree3/rtcore_builder.h>
#include "particle_bvh.h"
#include "embree.h"

typedef struct bnode {
    int leaf;
    int count;              /* leaf */
    struct bnode *child[2]; /* inner */
    unsigned ids[];         /* leaf */
} bnode;

static void *create_node(RTCThreadLocalAllocator alloc, unsigned int nchildren, void *user)
{
    (void)nchildren, (void)user;
    bnode *n = rtcThreadLocalAlloc(alloc, sizeof(bnode), 16);
    n->leaf = 0;
    n->count = 0;
    n->child[0] = n->child[1] = NULL;
    return n;
}

static void set_children(void *node, void **children, unsigned int nchildren, void *user)
{
    (void)user;
    bnode *n = node;
    for (unsigned i = 0; i < nchildren && i < 2; i++) n->child[i] = children[i];
}

static void set_bounds(void *node, const struct RTCBounds **bounds, unsigned int nchildren, void *user)
{
    (void)node, (void)bounds, (void)nchildren, (void)user; /* recomputed after the build */
}

static void *create_leaf(RTCThreadLocalAllocator alloc, const struct RTCBuildPrimitive *prims, size_t n, void *user)
{
    (void)user;
    bnode *l = rtcThreadLocalAlloc(alloc, sizeof(bnode) + n * sizeof(unsigned), 16);
    l->leaf = 1;
    l->count = (int)n;
    l->child[0] = l->child[1] = NULL;
    for (size_t i = 0; i < n; i++) l->ids[i] = prims[i].primID; /* prims is only valid during the call */
    return l;
}

typedef struct flat_ctx {
    lci_pbvh *b;
    const float *xyz, *r;
    float r_all;
    int32_t next_node;
    int32_t next_prim;
    int32_t depth;
} flat_ctx;

/* Fills node slot `slot` from n; returns 0 or -1 on a malformed tree. */
static int flatten(flat_ctx *c, const bnode *n, int32_t slot, int32_t depth)
{
    if (depth > c->depth) c->depth = depth;
    if (depth > 100000) return -1;
    lc_kpnode *o = &c->b->nodes[slot];
    if (n->leaf) {
        float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f}, rm = 0.0f;
        o->first = c->next_prim;
        o->count = n->count;
        for (int i = 0; i < n->count; i++) {
            unsigned id = n->ids[i];
            c->b->order[c->next_prim++] = id;
            for (int k = 0; k < 3; k++) {
                float v = c->xyz[3 * (size_t)id + (size_t)k];
                lo[k] = v < lo[k] ? v : lo[k];
                hi[k] = v > hi[k] ? v : hi[k];
            }
            float ri = c->r ? c->r[id] : c->r_all;
            rm = ri > rm ? ri : rm;
        }
        memcpy(o->lo, lo, sizeof lo);
        memcpy(o->hi, hi, sizeof hi);
        c->b->rmax[slot] = rm;
        return 0;
    }
    if (!n->child[0] || !n->child[1]) return -1;
    int32_t first = c->next_node;
    c->next_node += 2;
    o->first = first;
    o->count = 0;
    for (int i = 0; i < 2; i++)
        if (flatten(c, n->child[i], first + i, depth + 1) != 0) return -1;
    lc_kpnode *a = &c->b->nodes[first], *b = &c->b->nodes[first + 1];
    for (int k = 0; k < 3; k++) {
        o->lo[k] = a->lo[k] < b->lo[k] ? a->lo[k] : b->lo[k];
        o->hi[k] = a->hi[k] > b->hi[k] ? a->hi[k] : b->hi[k];
    }
    float ra = c->b->rmax[first], rb = c->b->rmax[first + 1];
    c->b->rmax[slot] = ra > rb ? ra : rb;
    return 0;
}

void lci_pbvh_free(lci_pbvh *b)
{
    if (!b) return;
    free(b->nodes);
    free(b->rmax);
    free(b->order);
    memset(b, 0, sizeof *b);
}

/* Embree's build (MEDIUM) over the particles ids[0..m) (NULL: 0..m-1),
 * flattened into c's arrays with its root at `slot` and depth counted from
 * `depth`. */
static int build_part(RTCDevice dev, flat_ctx *c, const uint32_t *ids, size_t m, int leaf_size, int32_t slot,
                      int32_t depth, char *err, size_t errlen)
{
    struct RTCBuildPrimitive *prims = NULL;
    if (posix_memalign((void **)&prims, 32, m * sizeof *prims) != 0) {
        snprintf(err, errlen, "out of memory for %zu build primitives", m);
        return -1;
    }
    for (size_t j = 0; j < m; j++) {
        size_t i = ids ? ids[j] : j;
        const float *p = c->xyz + 3 * i;
        float ri = c->r ? c->r[i] : c->r_all;
        prims[j].lower_x = p[0] - ri;
        prims[j].lower_y = p[1] - ri;
        prims[j].lower_z = p[2] - ri;
        prims[j].upper_x = p[0] + ri;
        prims[j].upper_y = p[1] + ri;
        prims[j].upper_z = p[2] + ri;
        prims[j].geomID = 0;
        prims[j].primID = (unsigned)i;
    }
    RTCBVH bvh = rtcNewBVH(dev);
    if (!bvh) {
        free(prims);
        snprintf(err, errlen, "Embree: rtcNewBVH failed (error %d)", (int)rtcGetDeviceError(dev));
        return -1;
    }
    struct RTCBuildArguments a = rtcDefaultBuildArguments();
    a.byteSize = sizeof a;
    a.buildFlags = RTC_BUILD_FLAG_NONE;
    a.buildQuality = RTC_BUILD_QUALITY_MEDIUM;
    a.maxBranchingFactor = 2;
    a.maxDepth = 1024; /* clustered data needs more than the default 32 (NOTES.md) */
    a.sahBlockSize = 1;
    a.minLeafSize = 1;
    a.maxLeafSize = (unsigned)leaf_size;
    a.traversalCost = 1.0f;
    a.intersectionCost = 0.5f; /* fuller leaves: half the nodes of 1.0 (1M particles: 0.73M vs 1.41M) */
    a.bvh = bvh;
    a.primitives = prims;
    a.primitiveCount = m;
    a.primitiveArrayCapacity = m;
    a.createNode = create_node;
    a.setNodeChildren = set_children;
    a.setNodeBounds = set_bounds;
    a.createLeaf = create_leaf;
    a.splitPrimitive = NULL;
    a.buildProgress = NULL;
    a.userPtr = NULL;
    bnode *root = rtcBuildBVH(&a);
    free(prims);
    int rc = 0;
    int32_t first_prim = c->next_prim;
    if (!root) {
        snprintf(err, errlen, "Embree: rtcBuildBVH failed (error %d)", (int)rtcGetDeviceError(dev));
        rc = -1;
    } else if (flatten(c, root, slot, depth) != 0 || (size_t)(c->next_prim - first_prim) != m) {
        snprintf(err, errlen, "Embree returned a malformed tree (%d of %zu particles in leaves)",
                 c->next_prim - first_prim, m);
        rc = -1;
    }
    rtcReleaseBVH(bvh);
    return rc;
}

/* LANECAST_PBVH_BUILDER (embree, sah) overrides the default for A/B runs
 * (lanecast bench --builders). */
static lci_pbvh_builder env_builder(lci_pbvh_builder b)
{
    const char *e = getenv("LANECAST_PBVH_BUILDER");
    if (!e) return b;
    return !strcmp(e, "embree") ? LCI_PBVH_EMBREE : !strcmp(e, "sah") ? LCI_PBVH_SAH : b;
}

int lci_pbvh_canonical(int canonical_order)
{
    if (canonical_order != 0) return canonical_order > 0;
    const char *e = getenv("LANECAST_PBVH_BUILDER");
    return !(e && (!strcmp(e, "embree") || !strcmp(e, "sah")));
}

int lci_pbvh_check_size(size_t n, int leaf_size, char *err, size_t errlen)
{
    if (n > (size_t)INT32_MAX / 2 || leaf_size < 1 || leaf_size > 32) {
        snprintf(err, errlen, "%zu particles with leaves of %d: at most %d particles, leaves of 1 to 32", n, leaf_size,
                 INT32_MAX / 2);
        return -1;
    }
    return 0;
}

int lci_pbvh_build_ex(void *embree_device, const float *xyz, const float *r, float r_all, size_t n, int leaf_size,
                      lci_pbvh_builder builder, lci_pbvh *out, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    if (n == 0) return 0;
    if (lci_pbvh_check_size(n, leaf_size, err, errlen)) return -1;
    if (builder == LCI_PBVH_DEFAULT) builder = env_builder(LCI_PBVH_EMBREE);
    if (builder == LCI_PBVH_SAH) {
        int th = lci_embree_threads(embree_device);
        if (th == 0) {
            long cpus = sysconf(_SC_NPROCESSORS_ONLN);
            th = cpus > 1 ? 2 : 1;
        }
        return lci_pbvh_build_sah(xyz, r, r_all, n, leaf_size, th, out, err, errlen);
    }
    RTCDevice dev = lci_embree_rtc(embree_device);
    if (!dev) {
        snprintf(err, errlen, "no Embree device");
        return -1;
    }
    /* a binary tree over n >= 1 primitives has at most 2n - 1 nodes; pages
       never written stay unmapped */
    size_t cap = 2 * n - 1;
    out->nodes = malloc(cap * sizeof *out->nodes);
    out->rmax = malloc(cap * sizeof *out->rmax);
    out->order = malloc(n * sizeof *out->order);
    if (!out->nodes || !out->rmax || !out->order) {
        lci_pbvh_free(out);
        snprintf(err, errlen, "out of memory for the BVH of %zu particles", n);
        return -1;
    }
    flat_ctx c = {out, xyz, r, r_all, 1, 0, 0};
    int rc = build_part(dev, &c, NULL, n, leaf_size, 0, 0, err, errlen);
    if (rc != 0) {
        lci_pbvh_free(out);
        return rc;
    }
    out->nnodes = c.next_node;
    out->depth = c.depth;
    return 0;
}

int lci_pbvh_build(void *embree_device, const float *xyz, const float *r, float r_all, size_t n, int leaf_size,
                   lci_pbvh *out, char *err, size_t errlen)
{
    return lci_pbvh_build_ex(embree_device, xyz, r, r_all, n, leaf_size, LCI_PBVH_DEFAULT, out, err, errlen);
}
