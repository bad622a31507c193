/* One BVH walk per block of groups (issue 8, session 6 round 2), included by
 * particles_coherent.c after its scratch
 * types.
 *
 * A group's list (gent) used to come from its own BVH walk for each chunk of
 * passes. Now a block of groups (up to BL_SIDE x BL_SIDE pixels of the tile,
 * 16 groups of 8x8 at the default) walks the BVH once per segment of BL_SEG
 * lattice samples (segments on multiples of BL_SEG, built when the first
 * group of the block reaches them) with the same node tests, every block ray
 * and one window [(s0 - 1/2) dt, (s1 + 1/2) dt] for the segment s0..s1, and
 * lists the leaves it reaches with a bit per group whose rays reach the
 * leaf's grown box. A group's chunk (clipped to one segment) then takes its
 * list from the block's: the entries with its bit, each given the leaf test
 * of walk_group (same slab test, windows, vector bits and lattice range,
 * same arithmetic). So the group list is the one its own walk would give,
 * entry for entry and in the same (depth-first) order:
 * - every leaf the group's walk lists is in the block list with the group's
 *   bit: the group's windows lie within the segment's (set_windows rounds
 *   (k -/+ 1/2) dt alike for k within s0..s1), its rays are the block's
 *   (the same camera arithmetic as setup_vector), and the mode's node test
 *   depends on the node and frame only;
 * - a block entry that passes the group's leaf test is one the group's walk
 *   reaches: an ancestor's grown box holds the leaf's (boxes and radius
 *   bounds are unions over the subtree; the slab arithmetic is monotone),
 *   so the ancestors pass the group's tests too.
 * Images are therefore bit-identical (tests/test_particles_group.c compares
 * with memcmp). What a block walk saves is the upper tree's node tests,
 * repeated per group and chunk; what it may waste is segments listed for
 * groups that end early (only blocks where some group reaches a segment
 * build it). A segment that does not fit the block's pool, or a slot taken
 * by another segment, leaves the group to its own walk (collect_group). */

#define BL_SIDE 32              /* block side in pixels at most */
#define BL_SEG 64               /* samples per segment, a multiple of PG_ANCHOR */
#define BL_DEFAULT_CAP 32768    /* block list entries (512 KB per worker) */
#define BL_SLOTS 128            /* segments per block kept (direct-mapped) */
#define BL_EMPTY INT32_MIN

_Static_assert(BL_SEG % PG_ANCHOR == 0, "segments end on anchor blocks");

static int32_t block_cap(const lc_kparticles *s)
{
    return s->block_list_cap < 0 ? 0 : s->block_list_cap > 0 ? s->block_list_cap : BL_DEFAULT_CAP;
}

/* The block of groups a tile is cut into: bgx x bgy groups (on: at least 2,
 * at most 64, and lists in use). */
typedef struct pblock {
    int on, bgx, bgy, bw, bh;
} pblock;

static inline pblock block_dims(const cscratch *c, const lc_ktile *t, pgroup g)
{
    pblock b;
    int tw = (t->x1 - t->x0 + g.gw - 1) / g.gw, th = (t->y1 - t->y0 + g.gh - 1) / g.gh;
    b.bgx = BL_SIDE / g.gw, b.bgy = BL_SIDE / g.gh;
    b.bgx = b.bgx < tw ? b.bgx : tw;
    b.bgy = b.bgy < th ? b.bgy : th;
    b.on = c->list && c->blist && b.bgx >= 1 && b.bgy >= 1 && b.bgx * b.bgy >= 2 && b.bgx * b.bgy <= 64;
    if (!b.on) b.bgx = tw, b.bgy = th; /* one block: the tile, groups in the order of old */
    b.bw = b.bgx * g.gw, b.bh = b.bgy * g.gh;
    return b;
}

static inline int seg_key(int k) { return k >= 0 ? k / BL_SEG : -((-k + BL_SEG - 1) / BL_SEG); }

/* The block's rays at (bx, by), group by group (group gi's vector v at
 * gi * nv + v), as setup_vector computes them; the segment table emptied. */
static void block_setup(const lc_kframe *f, cscratch *c, pgroup g, pblock b, int bx, int by)
{
    const int nv = g.nv, vpr = g.gw / DVR_PW;
    for (int gi = 0; gi < b.bgx * b.bgy; gi++) {
        int gx = bx + (gi % b.bgx) * g.gw, gy = by + (gi / b.bgx) * g.gh;
        for (int v = 0; v < nv; v++) {
            int o = (gi * nv + v) * LC_W;
            vint px, py;
            dvr_packet_pixels(gx + (v % vpr) * DVR_PW, gy + (v / vpr) * DVR_PH, &px, &py);
            vray r = dvr_camera_rays(&f->cam, px, py);
            vf_store(c->box + o, r.ox), vf_store(c->boy + o, r.oy), vf_store(c->boz + o, r.oz);
            vf_store(c->bix + o, dvr_inv_dir(r.dx));
            vf_store(c->biy + o, dvr_inv_dir(r.dy));
            vf_store(c->biz + o, dvr_inv_dir(r.dz));
        }
    }
    for (int i = 0; i < BL_SLOTS; i++) c->bseg[i].key = BL_EMPTY;
    c->bn = 0;
}

/* Does vector o (block layout) reach the node's grown box within [w0, w1]? */
static inline vmask block_hit(const cscratch *c, int o, const lc_kpnode *node, float g, vfloat w0, vfloat w1)
{
    vfloat tn, tf;
    dvr_slab(vf_load(c->box + o), vf_load(c->boy + o), vf_load(c->boz + o), vf_load(c->bix + o),
             vf_load(c->biy + o), vf_load(c->biz + o), node->lo, node->hi, g, &tn, &tf);
    return vf_le(vf_max(tn, w0), vf_min(tf, w1));
}

/* The block walk for the segment of key `key` (ng groups of nv vectors):
 * the leaves reached, depth first, with their group bits, into sg; count -1
 * when the pool is full. */
static __attribute__((noinline)) void block_walk(const lc_kparticles *s, const lc_kframe *f, cscratch *c, int ng,
                                                 int nv, int key, float dt, bseg *sg, lc_kstats *st)
{
    const int nbv = ng * nv;
    const vfloat w0 = vf_set1(((float)(key * BL_SEG) - 0.5f) * dt);
    const vfloat w1 = vf_set1(((float)(key * BL_SEG + BL_SEG - 1) + 0.5f) * dt);
    int32_t *stack = c->stack;
    int sp = 0, n = c->bn;
    sg->key = key, sg->start = n, sg->count = -1;
    stack[sp++] = 0;
    while (sp > 0) {
        int32_t nd = stack[--sp];
        const lc_kpnode *node = &s->nodes[nd];
        float g = grow(s->sigma * s->node_rmax[nd]);
        st->nodes++;
        float vb = s->kappa * s->node_ksum[nd];
        mnode mn = {fminf(vb, 0.0f), fmaxf(vb, 0.0f), 0, node_clear(s, nd), -INFINITY};
        if (!mode_node_matters(f, &mn)) continue;
        if (node->count == 0) {
            int hit = 0;
            for (int v = 0; v < nbv && !hit; v++) hit = vm_any(block_hit(c, v * LC_W, node, g, w0, w1));
            if (!hit) continue;
            stack[sp++] = node->first + 1;
            stack[sp++] = node->first;
            continue;
        }
        uint64_t gb = 0;
        for (int gi = 0; gi < ng; gi++)
            for (int v = gi * nv; v < gi * nv + nv; v++)
                if (vm_any(block_hit(c, v * LC_W, node, g, w0, w1))) {
                    gb |= (uint64_t)1 << gi;
                    break;
                }
        if (!gb) continue;
        if (n >= c->bcap) return; /* full: count stays -1 */
        c->blist[n++] = (bent){nd, 0, gb};
    }
    sg->count = n - sg->start;
    c->bn = n;
}

/* The segment holding sample k, walked when first needed; NULL when it does
 * not fit or its slot holds another segment (the group walks itself). */
static inline const bseg *block_segment(const lc_kparticles *s, const lc_kframe *f, cscratch *c, int ng, int nv, int k,
                                        float dt, lc_kstats *st)
{
    int key = seg_key(k);
    bseg *sg = &c->bseg[key & (BL_SLOTS - 1)];
    if (sg->key == BL_EMPTY) block_walk(s, f, c, ng, nv, key, dt, sg, st);
    return sg->key == key && sg->count >= 0 ? sg : NULL;
}

/* Group gi's list for the chunk kp..kend (windows set) from the block's
 * segment: walk_group's leaf test on each entry with the group's bit.
 * Returns the entries, or -1 when they do not fit. */
static __attribute__((noinline)) int block_group_list(const lc_kparticles *s, const cscratch *c, int nv, int vshift,
                                                      int gi, int kp, int kend, float dt, const bseg *sg,
                                                      lc_kstats *st)
{
    const bent *bl = c->blist + sg->start;
    int n = 0;
    for (int j = 0; j < sg->count; j++) {
        if (!((bl[j].gbits >> gi) & 1u)) continue;
        int32_t nd = bl[j].node;
        const lc_kpnode *node = &s->nodes[nd];
        float g = grow(s->sigma * s->node_rmax[nd]);
        st->nodes++;
        uint64_t bits = 0;
        vfloat lo = vf_set1(INFINITY), hi = vf_set1(-INFINITY);
        for (int v = 0; v < nv; v++) {
            int o = v * LC_W;
            vfloat w0 = vf_load(c->w0 + o), w1 = vf_load(c->w1 + o);
            vfloat tn, tf;
            dvr_slab(vf_load(c->ox + o), vf_load(c->oy + o), vf_load(c->oz + o), vf_load(c->ix + o),
                     vf_load(c->iy + o), vf_load(c->iz + o), node->lo, node->hi, g, &tn, &tf);
            vfloat ta = vf_max(tn, w0), tb = vf_min(tf, w1);
            vmask h = vf_le(ta, tb);
            if (vm_any(h)) {
                bits |= (uint64_t)1 << (v >> vshift);
                lo = vf_min(lo, vf_select(h, ta, vf_set1(INFINITY)));
                hi = vf_max(hi, vf_select(h, tb, vf_set1(-INFINITY)));
            }
        }
        if (!bits) continue;
        st->leaves++;
        int ka = (int)__builtin_floorf(vf_reduce_min(lo) / dt);
        int kb = (int)__builtin_ceilf(vf_reduce_max(hi) / dt);
        ka = ka < kp ? kp : ka;
        kb = kb > kend ? kend : kb;
        if (ka > kb) continue;
        if (n >= c->cap) return -1;
        c->list[n++] = (gent){node->first, node->count, ka, kb, bits};
    }
    return n;
}
