/* The canonical particle BVH (bvh/particle_bvh_canon.c), what data-parallel
 * parts' bit-identity rests on: the leaf order is a function of the
 * particles' data and the box alone. Over 3000 clustered particles with
 * exact duplicates, pairs sharing a centre (radii differ) and pairs in one
 * Morton cell: a shuffled input gives the same sequence of particles in leaf
 * order (memcmp of centre, radius and value), a random subset (a part:
 * owners and ghosts) gives the whole set's sequence with the others left
 * out, the extra values break ties (two particles alike but for the value
 * keep value order); the tree is well formed (each particle in one leaf of
 * 1..leaf_size, node boxes the hull of the centres below, rmax the largest
 * radius). Controls: the own SAH builder's sequences differ on the shuffled
 * input and the subset (the checks can fail). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "bvh/particle_bvh.h"

enum { N = 3000, LEAF = 4 };

static uint32_t rng = 2024u;
static float urand(void)
{
    rng = rng * 1664525u + 1013904223u;
    return (float)(rng >> 8) / 16777216.0f;
}

typedef struct pset {
    size_t n;
    float xyz[3 * N], r[N], k[N];
} pset;

/* The particles in leaf order as (x, y, z, r, k) records. */
static int sequence(const pset *s, const lci_pbvh *b, float *out)
{
    for (size_t j = 0; j < s->n; j++) {
        uint32_t o = b->order[j];
        if (o >= s->n) return -1;
        memcpy(out + 5 * j, s->xyz + 3 * (size_t)o, 12);
        out[5 * j + 3] = s->r[o], out[5 * j + 4] = s->k[o];
    }
    return 0;
}

static int build(const pset *s, int canonical, const float *lo, const float *hi, lci_pbvh *b)
{
    char err[256];
    if (!canonical) return lci_pbvh_build_ex(NULL, s->xyz, s->r, 0.0f, s->n, LEAF, LCI_PBVH_SAH, b, err, sizeof err);
    lci_pbvh_keys q = {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}, {s->k, NULL, NULL}, NULL, NULL};
    return lci_pbvh_build_canonical(s->xyz, s->r, 0.0f, s->n, LEAF, &q, b, err, sizeof err);
}

/* Every particle in exactly one leaf of 1..LEAF, boxes and rmax exact. */
static int well_formed(const pset *s, const lci_pbvh *b)
{
    uint8_t *seen = calloc(s->n, 1);
    int ok = seen != NULL && b->nnodes >= 1;
    for (int32_t nd = b->nnodes - 1; ok && nd >= 0; nd--) {
        const lc_kpnode *n = &b->nodes[nd];
        float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f}, rm = 0.0f;
        if (n->count == 0) {
            ok = n->first > nd && n->first + 1 < b->nnodes;
            for (int c = 0; ok && c < 2; c++) {
                const lc_kpnode *ch = &b->nodes[n->first + c];
                for (int a = 0; a < 3; a++)
                    lo[a] = ch->lo[a] < lo[a] ? ch->lo[a] : lo[a], hi[a] = ch->hi[a] > hi[a] ? ch->hi[a] : hi[a];
                rm = b->rmax[n->first + c] > rm ? b->rmax[n->first + c] : rm;
            }
        } else {
            ok = n->count <= LEAF && n->first >= 0 && (size_t)(n->first + n->count) <= s->n;
            for (int32_t j = n->first; ok && j < n->first + n->count; j++) {
                uint32_t o = b->order[j];
                ok = o < s->n && !seen[o];
                if (!ok) break;
                seen[o] = 1;
                for (int a = 0; a < 3; a++) {
                    float v = s->xyz[3 * (size_t)o + (size_t)a];
                    lo[a] = v < lo[a] ? v : lo[a], hi[a] = v > hi[a] ? v : hi[a];
                }
                rm = s->r[o] > rm ? s->r[o] : rm;
            }
        }
        ok = ok && !memcmp(lo, n->lo, sizeof lo) && !memcmp(hi, n->hi, sizeof hi) && rm == b->rmax[nd];
    }
    for (size_t i = 0; ok && i < s->n; i++) ok = seen[i];
    free(seen);
    return ok;
}

int main(void)
{
    static pset whole, shuf, part;
    whole.n = N;
    for (size_t i = 0; i < N; i++) {
        for (int a = 0; a < 3; a++) whole.xyz[3 * i + a] = 2.0f * urand() * urand() - 1.0f;
        whole.r[i] = 0.02f + 0.05f * urand();
        whole.k[i] = urand();
    }
    for (size_t i = 100; i < 110; i++) { /* exact duplicates */
        memcpy(whole.xyz + 3 * i, whole.xyz + 3 * (i - 50), 12);
        whole.r[i] = whole.r[i - 50], whole.k[i] = whole.k[i - 50];
    }
    for (size_t i = 110; i < 120; i++) memcpy(whole.xyz + 3 * i, whole.xyz + 3 * (i - 50), 12); /* radii differ */
    for (size_t i = 120; i < 130; i++) { /* one centre and radius, the values differ */
        memcpy(whole.xyz + 3 * i, whole.xyz + 3 * (i - 50), 12);
        whole.r[i] = whole.r[i - 50];
    }
    for (size_t i = 130; i < 140; i++) /* within one Morton cell (2^-21 of the box) */
        for (int a = 0; a < 3; a++) whole.xyz[3 * i + a] = whole.xyz[3 * (i - 50) + a] + 1e-7f;
    float lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
    for (size_t i = 0; i < N; i++)
        for (int a = 0; a < 3; a++) {
            float v = whole.xyz[3 * i + a];
            lo[a] = v < lo[a] ? v : lo[a], hi[a] = v > hi[a] ? v : hi[a];
        }
    /* the shuffled copy and a part (about 60 %, ties and duplicates among them) */
    size_t perm[N];
    for (size_t i = 0; i < N; i++) perm[i] = i;
    for (size_t i = N - 1; i > 0; i--) {
        size_t j = (size_t)(urand() * (float)(i + 1)) % (i + 1), t = perm[i];
        perm[i] = perm[j], perm[j] = t;
    }
    shuf.n = N;
    uint8_t keep[N];
    for (size_t i = 0; i < N; i++) {
        size_t o = perm[i];
        memcpy(shuf.xyz + 3 * i, whole.xyz + 3 * o, 12);
        shuf.r[i] = whole.r[o], shuf.k[i] = whole.k[o];
        keep[i] = urand() < 0.6f || (i >= 50 && i < 140);
    }
    for (size_t i = 0; i < N; i++)
        if (keep[i]) {
            memcpy(part.xyz + 3 * part.n, shuf.xyz + 3 * i, 12);
            part.r[part.n] = shuf.r[i], part.k[part.n] = shuf.k[i];
            part.n++;
        }
    static float sw[5 * N], ss[5 * N], sp[5 * N], filt[5 * N];
    for (int canonical = 1; canonical >= 0; canonical--) {
        lci_pbvh bw, bs, bp;
        int built = build(&whole, canonical, lo, hi, &bw) == 0;
        built &= build(&shuf, canonical, lo, hi, &bs) == 0;
        built &= build(&part, canonical, lo, hi, &bp) == 0;
        if (!built) {
            CHECK(0, "%s builds", canonical ? "canonical" : "sah");
            continue;
        }
        int seq = sequence(&whole, &bw, sw) == 0 && sequence(&shuf, &bs, ss) == 0 && sequence(&part, &bp, sp) == 0;
        /* the whole set's sequence without the particles the part lacks: whole
           records are matched to the part by their data (duplicates alike) */
        size_t m = 0;
        uint8_t *used = calloc(N, 1);
        for (size_t j = 0; seq && used && j < N; j++)
            for (size_t i = 0; i < N; i++) {
                if (used[i] || !keep[i] || memcmp(shuf.xyz + 3 * i, sw + 5 * j, 12) || shuf.r[i] != sw[5 * j + 3] ||
                    shuf.k[i] != sw[5 * j + 4])
                    continue;
                used[i] = 1;
                memcpy(filt + 5 * m++, sw + 5 * j, 20);
                break;
            }
        free(used);
        int same_shuffled = seq && !memcmp(sw, ss, sizeof(float) * 5 * N);
        int same_part = seq && m == part.n && !memcmp(filt, sp, sizeof(float) * 5 * part.n);
        if (canonical) {
            int ties = 1; /* 120..129: one centre and radius, leaf order follows the value */
            for (size_t j = 0; j + 1 < N; j++)
                if (!memcmp(sw + 5 * j, sw + 5 * j + 5, 16)) ties &= sw[5 * j + 4] <= sw[5 * j + 9];
            CHECK(well_formed(&whole, &bw) && well_formed(&shuf, &bs) && well_formed(&part, &bp),
                  "canonical: every particle in one leaf of 1..%d, boxes the hull of the centres, rmax exact (%d nodes, "
                  "depth %d)", LEAF, bw.nnodes, bw.depth);
            CHECK(same_shuffled, "canonical: a shuffled input gives the same particles in leaf order");
            CHECK(same_part, "canonical: a part of %zu particles gives the whole set's order without the others",
                  part.n);
            CHECK(ties, "canonical: particles alike but for the value are in value order");
        } else {
            CHECK(!same_shuffled && !same_part,
                  "control, the SAH builder: the shuffled input's order %s, the part's %s (the checks above can fail)",
                  same_shuffled ? "is the same" : "differs", same_part ? "is the same" : "differs");
        }
        lci_pbvh_free(&bw), lci_pbvh_free(&bs), lci_pbvh_free(&bp);
    }
    return check_summary("test_dp_order");
}
