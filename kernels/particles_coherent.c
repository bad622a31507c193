/* Coherent particle volume rendering (Knoll et al. 2014, Listings 2 and 3),
 * compiled once per target: a group of rays (8x8 by default, or one
 * lane-width packet) walks the BVH with a uniform stack; every leaf particle
 * adds its Gaussian to every buffered sample it overlaps (the uniform sample
 * range is the min/max over the packet's lanes); then the buffer of K samples
 * per ray is integrated front to back through the mode. Multi-pass over the
 * ray segment, stopping when every ray of the group reached alpha_stop. The
 * walk serves a window of passes (the group list, below), not each pass. */
#include "particles_common.h"

#define MAX_GROUP_RAYS 4096

typedef struct pgroup {
    int gw, gh; /* group size in pixels, multiples of DVR_PW x DVR_PH */
    int nv;     /* vectors in the group */
} pgroup;

static inline pgroup group_dims(const lc_kframe *f)
{
    pgroup g;
    int s = f->packet <= 1 ? 1 : f->packet;
    g.gw = s <= DVR_PW ? DVR_PW : (s + DVR_PW - 1) / DVR_PW * DVR_PW;
    g.gh = s <= DVR_PH ? DVR_PH : (s + DVR_PH - 1) / DVR_PH * DVR_PH;
    while (g.gw * g.gh > MAX_GROUP_RAYS) g.gw > g.gh ? (g.gw -= DVR_PW) : (g.gh -= DVR_PH);
    g.nv = (g.gw / DVR_PW) * (g.gh / DVR_PH);
    return g;
}

/* Scratch of one worker: ray arrays for a group, the sample buffer, the stack. */
typedef struct cscratch {
    float *ox, *oy, *oz, *dx, *dy, *dz, *ix, *iy, *iz; /* rays */
    float *w0, *w1;                                    /* this pass's t window per ray (w0 > w1: inactive) */
    int32_t *kf, *kl;
    float *cr, *cg, *cb, *ca;                          /* accumulated colour */
    float *sr, *sg, *sb, *sa;                          /* opaque surface */
    float *buf;                                        /* [field][row][comp][ray] */
    uint32_t *touched;                                 /* per vector: terms deposited this pass */
    int32_t *stack;
    struct gent *list;                                 /* the group's particle list (NULL: none) */
    int32_t cap;                                       /* its capacity in entries */
    int32_t K;                                         /* buffer rows per field (buf_rows) */
} cscratch;

/* One walk per group (issue 8). Instead of walking the BVH for every pass of
 * K samples, the group walks it once per window of passes (a "chunk": 2
 * passes, then twice as many after every chunk whose list fitted, up to
 * GL_MAX_PASSES; half as many after one that did not) and lists the leaves
 * its live rays reach in that window, each with its lattice range [ka, kb]
 * over the group (from the slab test of its grown box, clipped to the chunk)
 * and a bit per vector (or per run of 2^vshift vectors) whose rays reach it.
 * Each pass then deposits the particles of the entries overlapping it, in
 * list order, into the vectors of their bits, and drops the entries that end
 * in it. List order is the walk's depth-first order, the order a walk per
 * pass deposits in, and no term a pass's walk would deposit is missing (the
 * pass's windows lie inside the chunk's, its live rays among the chunk's,
 * and a particle's support inside its leaf's grown box), so every sample a
 * ray integrates sums the same terms in the same order: images are
 * bit-identical to a walk per pass (tests/test_particles_group.c). A
 * chunk's walk costs what the early end of the passes (every ray opaque) may
 * waste; growing chunks bound that. Lists live in the worker's scratch (cap
 * entries, 24 B each); a chunk whose list does not fit falls back to a walk
 * per pass (deposit). */
typedef struct gent {
    int32_t first, count, ka, kb; /* the leaf's particles, its lattice range */
    uint64_t vbits;
} gent;
_Static_assert(sizeof(gent) == 24, "gent layout");

#define GL_DEFAULT_CAP 8192 /* entries (192 KB per worker) */
#define GL_FIRST_PASSES 2
#define GL_MAX_PASSES 16

static int32_t list_cap(const lc_kparticles *s)
{
    return s->group_list_cap < 0 ? 0 : s->group_list_cap > 0 ? s->group_list_cap : GL_DEFAULT_CAP;
}

/* Floats between two rows (sample k, component) of the sample buffer: the
 * group's rays and 64 bytes more, so the rows a vector touches at one
 * position (a block of PG_ANCHOR samples, the gradient components) do not all
 * fall on one L1 set (a power-of-two stride of 4 KB or more would). */
static inline int buf_stride(int nv) { return nv * LC_W + 16; }

static uint64_t align64(uint64_t b) { return (b + 63) & ~(uint64_t)63; }

/* Samples per ray and field the buffer holds: s->buffer_k, or with
 * s->buffer_adapt at most what fits BUF_ADAPT_BYTES per worker (the host's
 * capacity of 128 samples holds for 8x8 groups with gradients; 16x16 groups
 * with gradients get 32, the fixed default's buffer), a multiple of
 * PG_ANCHOR. */
#define BUF_ADAPT_BYTES (4u << 20)

static int32_t buf_rows(const lc_kparticles *s, const lc_kframe *f, int nv)
{
    if (!s->buffer_adapt) return s->buffer_k;
    uint64_t row = (uint64_t)(s->nfields > 0 ? s->nfields : 1) * (mode_needs_grad(f) ? 4u : 1u) *
                   (uint64_t)buf_stride(nv) * 4u;
    uint64_t k = BUF_ADAPT_BYTES / row;
    k = k < (uint64_t)s->buffer_k ? k : (uint64_t)s->buffer_k;
    k = k / PG_ANCHOR * PG_ANCHOR;
    return k < PG_ANCHOR ? PG_ANCHOR : (int32_t)k;
}

static uint64_t coherent_layout(const lc_kparticles *s, const lc_kframe *f, unsigned char *base, cscratch *c)
{
    pgroup g = group_dims(f);
    uint64_t rays = (uint64_t)g.nv * LC_W;
    uint64_t comps = mode_needs_grad(f) ? 4 : 1;
    uint64_t off = 0;
    float **fa[] = {&c->ox, &c->oy, &c->oz, &c->dx, &c->dy, &c->dz, &c->ix, &c->iy, &c->iz, &c->w0, &c->w1,
                    &c->cr, &c->cg, &c->cb, &c->ca, &c->sr, &c->sg, &c->sb, &c->sa};
    for (size_t i = 0; i < sizeof fa / sizeof fa[0]; i++) {
        if (base) *fa[i] = (float *)(base + off);
        off += align64(rays * 4);
    }
    if (base) c->kf = (int32_t *)(base + off);
    off += align64(rays * 4);
    if (base) c->kl = (int32_t *)(base + off);
    off += align64(rays * 4);
    if (base) c->buf = (float *)(base + off);
    c->K = buf_rows(s, f, g.nv);
    off += align64((uint64_t)(s->nfields > 0 ? s->nfields : 1) * (uint64_t)c->K * comps *
                   (uint64_t)buf_stride(g.nv) * 4);
    if (base) c->touched = (uint32_t *)(base + off);
    off += align64((uint64_t)g.nv * 4);
    if (base) c->stack = (int32_t *)(base + off);
    off += align64((uint64_t)(s->depth + 4) * 4);
    c->cap = list_cap(s);
    c->list = NULL;
    if (base && c->cap > 0) c->list = (gent *)(base + off);
    off += align64((uint64_t)c->cap * sizeof(gent));
    return off;
}

uint64_t LC_KFN(particles_coherent_scratch_bytes)(const void *scene, const lc_kframe *f)
{
    cscratch c;
    return coherent_layout(scene, f, NULL, &c);
}

/* The samples ka..kb of one vector's rays from particle i's Gaussian (and
 * gradient), on the lanes in m that lie within its support. Exp-free
 * (SPEC.md "Fields"): along a ray, d^2 = d_perp^2 + u^2 with u = t - tc, and
 * the Gaussian at consecutive lattice samples follows the ratio recurrence
 * g(k+1) = g(k) q(k), q(k+1) = q(k) c, c = exp(-dt^2 / r^2) (pgauss_step),
 * re-anchored by a direct evaluation every PG_ANCHOR samples. The value at a
 * sample depends only on the ray, the particle and k, not on [ka, kb] (which
 * only has to hold every sample of the support in m's lanes): blocks of
 * PG_ANCHOR samples where no sample of any lane passes the support test are
 * skipped: the test of the block's sample nearest to the centre's foot (the
 * same arithmetic as the sample's own test; when the foot lies inside the
 * block, d_perp^2 alone, which only keeps more blocks). Returns the terms
 * added. */
static inline uint64_t deposit_samples(const pgauss_consts *gc, float *fb, int rays, int o, int comps, int kp, int ka,
                                       int kb, float dt, float r2s, float gscale, vfloat tc, vfloat d2,
                                       vfloat ocx, vfloat ocy, vfloat ocz, vfloat dx, vfloat dy, vfloat dz, vmask m)
{
    uint64_t evals = 0;
    /* p - c = u d - (oc - tc d): the gradient's offset, linear in u */
    vfloat qx = vf_fnma(tc, dx, ocx), qy = vf_fnma(tc, dy, ocy), qz = vf_fnma(tc, dz, ocz);
    vfloat rr = vf_set1(r2s);
    /* branch-free within a run: [ka, kb] is the union of the lanes' chords,
       so almost every step has active lanes */
    /* anchors on the lattice indices that are multiples of PG_ANCHOR, not
       at ka: ka depends on which rays share the vector and on the pass,
       and the image must not depend on tiles, packets or threads */
    const int kal = ka - ((ka % PG_ANCHOR) + PG_ANCHOR) % PG_ANCHOR;
    for (int k0 = kal; k0 <= kb; k0 += PG_ANCHOR) {
        int k1 = k0 + PG_ANCHOR - 1 < kb ? k0 + PG_ANCHOR - 1 : kb;
        vfloat u = vf_sub(vf_set1((float)k0 * dt), tc);
        vfloat ue = vf_sub(vf_set1((float)k1 * dt), tc);
        /* the block's sample nearest to the centre's foot (u0 or ue, or 0
           when the foot lies within the block: then conservatively d2 alone)
           takes the sample's own support test: none passes, no term lands */
        vfloat un = vf_max(u, vf_min(vf_zero(), ue));
        if (vm_none(vm_and(m, vf_lt(vf_madd(un, un, d2), rr)))) continue;
        vfloat g, q;
        pgauss_anchor(gc, d2, u, m, &g, &q);
        vfloat vk = vf_set1((float)k0); /* exact: |k| < 2^24; vk dt rounds as (float)k * dt */
        for (int k = k0; k <= k1; k++) {
            if (k < ka) { /* before this pass or chord: stepped, not stored */
                pgauss_step(gc, &g, &q);
                vk = vf_add(vk, vf_set1(1.0f));
                u = vf_sub(vf_mul(vk, vf_set1(dt)), tc);
                continue;
            }
            vfloat a = vf_madd(u, u, d2);
            vmask in = vm_and(m, vf_lt(a, rr));
            evals += (uint64_t)vm_popcnt(in);
            vfloat phi = vf_select(in, g, vf_zero());
            float *row = fb + (size_t)(k - kp) * (size_t)comps * (size_t)rays + o;
            vf_store(row, vf_add(vf_load(row), phi));
            if (comps == 4) {
                vfloat gp = vf_mul(phi, vf_set1(gscale));
                vfloat ex = vf_fms(u, dx, qx), ey = vf_fms(u, dy, qy), ez = vf_fms(u, dz, qz);
                vf_store(row + rays, vf_fma(ex, gp, vf_load(row + rays)));
                vf_store(row + 2 * rays, vf_fma(ey, gp, vf_load(row + 2 * rays)));
                vf_store(row + 3 * rays, vf_fma(ez, gp, vf_load(row + 3 * rays)));
            }
            pgauss_step(gc, &g, &q);
            vk = vf_add(vk, vf_set1(1.0f));
            u = vf_sub(vf_mul(vk, vf_set1(dt)), tc);
        }
    }
    return evals;
}

/* Leaf particle i adds its Gaussian (and gradient) to every buffered sample
 * of the group it overlaps (Listing 2, lines 6-8), on the vectors of vbits
 * (bit v >> vshift): the walk per pass. */
static inline void deposit(const lc_kparticles *s, const cscratch *c, int nv, int kp, int kend, float dt, int comps,
                           int32_t i, float cstep, uint64_t vbits, int vshift, lc_kstats *st)
{
    float cx = s->px[i], cy = s->py[i], cz = s->pz[i];
    float rs = s->sigma * s->r[i], r2s = rs * rs, nir = s->neg_inv_2r2[i], kk = s->kappa * s->k[i];
    float x2 = r2s * 1.001f + 1e-12f;
    int rays = buf_stride(nv);
    int K = c->K;
    float *fb = c->buf + (size_t)s->field[i] * (size_t)K * (size_t)comps * (size_t)rays;
    float gscale = 2.0f * nir; /* grad phi_i = -(p - c) / r^2 phi_i */
    pgauss_consts gc = pgauss_consts_make(nir, kk, dt, cstep);
    for (int v = 0; v < nv; v++) {
        if (!((vbits >> (v >> vshift)) & 1u)) continue; /* the leaf's box misses these rays */
        int o = v * LC_W;
        vfloat w0 = vf_load(c->w0 + o), w1 = vf_load(c->w1 + o);
        vmask m = vf_le(w0, w1);
        if (vm_none(m)) continue;
        vfloat ox = vf_load(c->ox + o), oy = vf_load(c->oy + o), oz = vf_load(c->oz + o);
        vfloat dx = vf_load(c->dx + o), dy = vf_load(c->dy + o), dz = vf_load(c->dz + o);
        vfloat ocx = vf_sub(vf_set1(cx), ox), ocy = vf_sub(vf_set1(cy), oy), ocz = vf_sub(vf_set1(cz), oz);
        vfloat tc = vf_madd(ocx, dx, vf_madd(ocy, dy, vf_mul(ocz, dz)));
        vfloat d2 = perp2(ocx, ocy, ocz, dx, dy, dz, tc);
        /* conservative chord: the per-sample test below is the exact one */
        vfloat h2 = vf_sub(vf_set1(x2), d2);
        m = vm_and(m, vf_ge(h2, vf_zero()));
        if (vm_none(m)) continue;
        vfloat half = vf_add(vf_sqrt(vf_max(h2, vf_zero())), vf_set1(1e-4f * rs));
        vfloat ta = vf_max(vf_sub(tc, half), w0), tb = vf_min(vf_add(tc, half), w1);
        m = vm_and(m, vf_le(ta, tb));
        if (vm_none(m)) continue;
        int ka = (int)__builtin_floorf(vf_reduce_min_masked(m, ta) / dt);
        int kb = (int)__builtin_ceilf(vf_reduce_max_masked(m, tb) / dt);
        ka = ka < kp ? kp : ka;
        kb = kb > kend ? kend : kb;
        if (ka > kb) continue;
        uint64_t e = deposit_samples(&gc, fb, rays, o, comps, kp, ka, kb, dt, r2s, gscale, tc, d2, ocx, ocy,
                                     ocz, dx, dy, dz, m);
        c->touched[v] += (uint32_t)e;
        st->kernel_evals += e;
    }
}

/* The same from a group list entry (one walk per group): samples ka..kb
 * (the entry's range over the group, clipped to the pass) on the vectors of
 * vbits. No chord per vector: every live lane whose ray passes within the
 * support takes part. That may add terms at samples outside a lane's own
 * window (the same happens above wherever the range is another lane's), which
 * the integration never reads (it takes a ray's samples kf..kl of the pass),
 * and every sample within a lane's window that deposit above fills is
 * filled here with the same value: the used samples sum the same terms. */
static inline __attribute__((always_inline)) void deposit_entry(const lc_kparticles *s, const cscratch *c, int nv,
                                                                 int kp, int ka, int kb, float dt, int comps, int32_t i,
                                                                 float cstep, uint64_t vbits, int vshift,
                                                                 const float *eye, lc_kstats *st)
{
    float cx = s->px[i], cy = s->py[i], cz = s->pz[i];
    float rs = s->sigma * s->r[i], r2s = rs * rs, nir = s->neg_inv_2r2[i], kk = s->kappa * s->k[i];
    float x2 = r2s * 1.001f + 1e-12f;
    int rays = buf_stride(nv);
    float *fb = c->buf + (size_t)s->field[i] * (size_t)c->K * (size_t)comps * (size_t)rays;
    pgauss_consts gc = pgauss_consts_make(nir, kk, dt, cstep);
    for (int v = 0; v < nv; v++) {
        if (!((vbits >> (v >> vshift)) & 1u)) continue; /* the list found the support misses these rays */
        int o = v * LC_W;
        vmask m = vf_le(vf_load(c->w0 + o), vf_load(c->w1 + o));
        if (vm_none(m)) continue;
        vfloat dx = vf_load(c->dx + o), dy = vf_load(c->dy + o), dz = vf_load(c->dz + o);
        /* eye (perspective): every lane's origin, so the differences are scalars */
        vfloat ocx = eye ? vf_set1(cx - eye[0]) : vf_sub(vf_set1(cx), vf_load(c->ox + o));
        vfloat ocy = eye ? vf_set1(cy - eye[1]) : vf_sub(vf_set1(cy), vf_load(c->oy + o));
        vfloat ocz = eye ? vf_set1(cz - eye[2]) : vf_sub(vf_set1(cz), vf_load(c->oz + o));
        vfloat tc = vf_madd(ocx, dx, vf_madd(ocy, dy, vf_mul(ocz, dz)));
        vfloat d2 = perp2(ocx, ocy, ocz, dx, dy, dz, tc);
        m = vm_and(m, vf_ge(vf_sub(vf_set1(x2), d2), vf_zero()));
        if (vm_none(m)) continue;
        uint64_t e = deposit_samples(&gc, fb, rays, o, comps, kp, ka, kb, dt, r2s, 2.0f * nir, tc, d2, ocx,
                                     ocy, ocz, dx, dy, dz, m);
        /* integrate only where some term landed (lanes without a chord in
           their window would otherwise mark it) */
        c->touched[v] += (uint32_t)e;
        st->kernel_evals += e;
    }
}

int LC_KFN(lc_pgauss_probe)(const float *d2, const float *tc, float nir, float kk, float dt, int ka, int kb,
                            int period, float *out)
{
    period = period > 0 ? period : PG_ANCHOR;
    pgauss_consts gc = pgauss_consts_make(nir, kk, dt, pgauss_c(nir, dt));
    vfloat vd2 = vf_load(d2), vtc = vf_load(tc);
    for (int k0 = ka; k0 <= kb; k0 += period) {
        int k1 = k0 + period - 1 < kb ? k0 + period - 1 : kb;
        vfloat g, q;
        pgauss_anchor(&gc, vd2, vf_sub(vf_set1((float)k0 * dt), vtc), vm_first_n(LC_W), &g, &q);
        for (int k = k0; k <= k1; k++) {
            vf_store(out + (size_t)(k - ka) * LC_W, g);
            pgauss_step(&gc, &g, &q);
        }
    }
    return period;
}

/* dvr_slab for rays from the eye (perspective: c->ox.. hold the eye in
 * every lane): (lo - g) - o is the same float in every lane, so it is
 * computed once, and the products with the inverse directions are those of
 * dvr_slab, bit for bit. */
static inline void slab_eye(const lc_kpnode *node, float g, float ex, float ey, float ez, vfloat ix, vfloat iy,
                            vfloat iz, vfloat *tn, vfloat *tf)
{
    vfloat ax = vf_mul(vf_set1((node->lo[0] - g) - ex), ix), bx = vf_mul(vf_set1((node->hi[0] + g) - ex), ix);
    vfloat ay = vf_mul(vf_set1((node->lo[1] - g) - ey), iy), by = vf_mul(vf_set1((node->hi[1] + g) - ey), iy);
    vfloat az = vf_mul(vf_set1((node->lo[2] - g) - ez), iz), bz = vf_mul(vf_set1((node->hi[2] + g) - ez), iz);
    *tn = vf_max(vf_max(vf_min(ax, bx), vf_min(ay, by)), vf_min(az, bz));
    *tf = vf_min(vf_min(vf_max(ax, bx), vf_max(ay, by)), vf_max(az, bz));
}

/* Listing 2, lines 3-10: coherent traversal for samples kp..kend (node and
 * stack uniform, rays varying), either depositing every leaf's particles
 * (collect 0: a walk per pass) or listing the leaves (collect 1, the group
 * list: returns the entries, or -1 when they do not fit). Both visit the
 * leaves in the same depth-first order. A leaf's vector bits name the
 * vectors whose rays reach its grown box (a particle's support lies in it);
 * its range is the hull over those rays of box interval within the window,
 * so it holds every sample of its particles' supports on a live ray. */
static inline __attribute__((always_inline)) int walk_group(const lc_kparticles *s, const lc_kframe *f,
                                                            const cscratch *c, int nv, int vshift, int kp, int kend,
                                                            float dt, int comps, int collect, int persp,
                                                            lc_kstats *st)
{
    const float ex = f->cam.eye[0], ey = f->cam.eye[1], ez = f->cam.eye[2];
    int32_t *stack = c->stack;
    int sp = 0, n = 0;
    float cnir = 1.0f, cstep = 0.0f; /* nir < 0: the first particle computes c */
    stack[sp++] = 0;
    while (sp > 0) {
        int32_t nd = stack[--sp];
        const lc_kpnode *node = &s->nodes[nd];
        float g = grow(s->sigma * s->node_rmax[nd]);
        st->nodes++;
        /* the mode's test on the node's own contribution (dvr: always) */
        float vb = s->kappa * s->node_ksum[nd];
        mnode mn = {fminf(vb, 0.0f), fmaxf(vb, 0.0f), 0, node_clear(s, nd), -INFINITY};
        if (!mode_node_matters(f, &mn)) continue;
        /* inner nodes: does any vector's rays reach the grown box; leaves:
           which vectors' (and, listed, over which t) */
        uint64_t bits = 0;
        vfloat lo = vf_set1(INFINITY), hi = vf_set1(-INFINITY);
        for (int v = 0; v < nv; v++) {
            if (!collect && ((bits >> (v >> vshift)) & 1u)) continue;
            int o = v * LC_W;
            vfloat w0 = vf_load(c->w0 + o), w1 = vf_load(c->w1 + o);
            vfloat tn, tf;
            if (persp) /* every origin is the eye: the slab's differences are scalars (same values) */
                slab_eye(node, g, ex, ey, ez, vf_load(c->ix + o), vf_load(c->iy + o), vf_load(c->iz + o), &tn, &tf);
            else
                dvr_slab(vf_load(c->ox + o), vf_load(c->oy + o), vf_load(c->oz + o), vf_load(c->ix + o),
                         vf_load(c->iy + o), vf_load(c->iz + o), node->lo, node->hi, g, &tn, &tf);
            vfloat ta = vf_max(tn, w0), tb = vf_min(tf, w1);
            vmask h = vf_le(ta, tb);
            if (vm_any(h)) {
                bits |= (uint64_t)1 << (v >> vshift);
                if (node->count == 0) break;
                if (collect) {
                    lo = vf_min(lo, vf_select(h, ta, vf_set1(INFINITY)));
                    hi = vf_max(hi, vf_select(h, tb, vf_set1(-INFINITY)));
                }
            }
        }
        if (!bits) continue;
        if (node->count == 0) {
            stack[sp++] = node->first + 1;
            stack[sp++] = node->first;
            continue;
        }
        st->leaves++;
        if (collect) {
            int ka = (int)__builtin_floorf(vf_reduce_min(lo) / dt);
            int kb = (int)__builtin_ceilf(vf_reduce_max(hi) / dt);
            ka = ka < kp ? kp : ka;
            kb = kb > kend ? kend : kb;
            if (ka > kb) continue;
            if (n >= c->cap) return -1;
            c->list[n++] = (gent){node->first, node->count, ka, kb, bits};
            continue;
        }
        for (int32_t i = node->first; i < node->first + node->count; i++) {
            /* c = exp(-dt^2 / r^2) once per radius: neighbours mostly share it */
            if (s->neg_inv_2r2[i] != cnir) cnir = s->neg_inv_2r2[i], cstep = pgauss_c(cnir, dt);
            deposit(s, c, nv, kp, kend, dt, comps, i, cstep, bits, vshift, st);
        }
    }
    return n;
}

static __attribute__((noinline)) void traverse_pass(const lc_kparticles *s, const lc_kframe *f, const cscratch *c,
                                                    int nv, int vshift, int kp, int kend, float dt, int comps,
                                                    lc_kstats *st)
{
    if (f->cam.ortho || s->eye_generic)
        walk_group(s, f, c, nv, vshift, kp, kend, dt, comps, 0, 0, st);
    else
        walk_group(s, f, c, nv, vshift, kp, kend, dt, comps, 0, 1, st);
}

static __attribute__((noinline)) int collect_group(const lc_kparticles *s, const lc_kframe *f, const cscratch *c,
                                                   int nv, int vshift, int kp, int kend, float dt, lc_kstats *st)
{
    return (f->cam.ortho || s->eye_generic) ? walk_group(s, f, c, nv, vshift, kp, kend, dt, 1, 1, 0, st)
                        : walk_group(s, f, c, nv, vshift, kp, kend, dt, 1, 1, 1, st);
}

/* One pass from the group list: deposits the n entries overlapping kp..kend
 * in list order and keeps, in order, those reaching past kend. Returns the
 * entries kept. */
static inline __attribute__((always_inline)) int deposit_list_as(const lc_kparticles *s, const cscratch *c, int nv,
                                                                  int vshift, int n, int kp, int kend, float dt,
                                                                  int comps, const float *eye, lc_kstats *st)
{
    float cnir = 1.0f, cstep = 0.0f;
    int kept = 0;
    for (int j = 0; j < n; j++) {
        gent e = c->list[j];
        if (e.ka <= kend && e.kb >= kp) {
            for (int32_t i = e.first; i < e.first + e.count; i++) {
                if (s->neg_inv_2r2[i] != cnir) cnir = s->neg_inv_2r2[i], cstep = pgauss_c(cnir, dt);
                deposit_entry(s, c, nv, kp, e.ka > kp ? e.ka : kp, e.kb < kend ? e.kb : kend, dt, comps, i, cstep,
                              e.vbits, vshift, eye, st);
            }
        }
        if (e.kb > kend) c->list[kept++] = e;
    }
    return kept;
}

/* The above, with the eye as every ray's origin (perspective) or not. */
static __attribute__((noinline)) int deposit_list(const lc_kparticles *s, const lc_kframe *f, const cscratch *c,
                                                  int nv, int vshift, int n, int kp, int kend, float dt, int comps,
                                                  lc_kstats *st)
{
    return (f->cam.ortho || s->eye_generic) ? deposit_list_as(s, c, nv, vshift, n, kp, kend, dt, comps, NULL, st)
                        : deposit_list_as(s, c, nv, vshift, n, kp, kend, dt, comps, f->cam.eye, st);
}

/* Listing 2, lines 11-13: the buffered samples kp..kend of every ray of the
 * group, front to back through the mode (a constant, so each mode gets its
 * own loop). */
static inline __attribute__((always_inline)) float integrate_buffer(const lc_kparticles *s, const lc_kframe *f,
                                                                   int mode, const cscratch *c,
                                                                   int nv, int K, int nf, int kp, int kend, int comps,
                                                                   const mprobe *probe, lc_kstats *st)
{
    const int rays = buf_stride(nv);
    const int skip = skip_base(s, f);
    const vfloat vbias = vf_set1(s->bias);
    float waste = 0.0f;
    for (int v = 0; v < nv; v++) {
        int o = v * LC_W;
        vmask live = vf_le(vf_load(c->w0 + o), vf_load(c->w1 + o));
        if (vm_none(live)) continue;
        /* no particle reached these rays in this pass: every sample is the bias (0
           for particles) and, with tau(bias) = 0, blends to exactly nothing */
        if (skip && !c->touched[v]) continue;
        vray r;
        r.dx = vf_load(c->dx + o), r.dy = vf_load(c->dy + o), r.dz = vf_load(c->dz + o);
        if (mode == LC_KMODE_ISO) r.ox = vf_load(c->ox + o), r.oy = vf_load(c->oy + o), r.oz = vf_load(c->oz + o);
        vcolor col = {vf_load(c->cr + o), vf_load(c->cg + o), vf_load(c->cb + o), vf_load(c->ca + o)};
        vint kf = vi_load(c->kf + o), kl = vi_load(c->kl + o);
        for (int k = kp; k <= kend; k++) {
            vmask m = vm_and(live, vm_and(vi_lt(kf, vi_set1(k + 1)), vi_gt(kl, vi_set1(k - 1))));
            if (vm_none(m)) continue;
            st->samples += (uint64_t)vm_popcnt(m);
            for (int fi = 0; fi < nf; fi++) {
                const float *p = c->buf + (((size_t)fi * (size_t)K + (size_t)(k - kp)) * (size_t)comps) *
                                             (size_t)rays + (size_t)o;
                vfloat phi = vf_load(p);
                if (skip && vm_none(vm_and(m, vf_ne(phi, vbias)))) continue;
                vgrad gr;
                if (comps == 4) gr.x = vf_load(p + rays), gr.y = vf_load(p + 2 * rays), gr.z = vf_load(p + 3 * rays);
                mode_sample_as(f, mode, fi, &col, m, phi, comps == 4 ? &gr : NULL, &r, NULL, vi_set1(k),
                               vf_set1((float)k * f->dt), probe);
            }
            live = vm_and(live, vf_lt(col.a, vf_set1(f->alpha_stop)));
            if (vm_none(live)) {
                /* the terms deposited behind this sample were for nothing */
                waste += (float)c->touched[v] * (float)(kend - k) / (float)(kend - kp + 1);
                break;
            }
        }
        vf_store(c->cr + o, col.r), vf_store(c->cg + o, col.g);
        vf_store(c->cb + o, col.b), vf_store(c->ca + o, col.a);
    }
    return waste;
}

/* Writes the group's pixels: each vector's rays finished in the mode, with
 * the opaque surface behind them. */
static inline __attribute__((always_inline)) void finish_group(const lc_kframe *f, int mode, const lc_ktile *t,
                                                               const cscratch *c, int gx, int gy, int nv, int vpr,
                                                               const mprobe *probe)
{
    for (int v = 0; v < nv; v++) {
        int o = v * LC_W, x = gx + (v % vpr) * DVR_PW, y = gy + (v / vpr) * DVR_PH;
        vcolor col = {vf_load(c->cr + o), vf_load(c->cg + o), vf_load(c->cb + o), vf_load(c->ca + o)};
        vcolor surf = {vf_load(c->sr + o), vf_load(c->sg + o), vf_load(c->sb + o), vf_load(c->sa + o)};
        vray r = {vf_load(c->ox + o), vf_load(c->oy + o), vf_load(c->oz + o),
                  vf_load(c->dx + o), vf_load(c->dy + o), vf_load(c->dz + o)};
        if (x < t->x1 && y < t->y1) finish_vector(f, mode, t, x, y, &col, &surf, &r, probe);
    }
}

/* Each ray's window in t for the samples kp..kend (live rays: not opaque and
 * with samples there; others get w0 > w1), padded by half a step against
 * round-off. Returns the number of vectors with a live ray. */
static int set_windows(const lc_kframe *f, const cscratch *c, int nv, int kp, int kend)
{
    const float dt = f->dt;
    int any = 0;
    for (int v = 0; v < nv; v++) {
        int o = v * LC_W;
        vint kf = vi_load(c->kf + o), kl = vi_load(c->kl + o);
        vmask live = vm_and(vf_lt(vf_load(c->ca + o), vf_set1(f->alpha_stop)),
                            vm_and(vi_lt(kf, vi_set1(kend + 1)), vi_gt(kl, vi_set1(kp - 1))));
        vfloat a = vi_to_vf(vi_max(kf, vi_set1(kp))), b = vi_to_vf(vi_min(kl, vi_set1(kend)));
        vf_store(c->w0 + o, vf_select(live, vf_mul(vf_sub(a, vf_set1(0.5f)), vf_set1(dt)), vf_set1(1.0f)));
        vf_store(c->w1 + o, vf_select(live, vf_mul(vf_add(b, vf_set1(0.5f)), vf_set1(dt)), vf_set1(-1.0f)));
        any += vm_any(live);
    }
    return any;
}

/* The group's rays at (gx, gy): origins, directions and their inverses, the
 * lattice ranges [kf, kl] (empty outside the tile or the data), colour 0 and
 * the opaque surface behind; [*kmin, *kmax] the hull of the ranges. */
static inline __attribute__((always_inline)) void setup_group(const lc_kparticles *s, const lc_kframe *f,
                                                              const lc_ktile *t, const cscratch *cs, int gx, int gy,
                                                              int nv, int vpr, int *kmin, int *kmax, lc_kstats *st)
{
    const cscratch c = *cs;
    *kmin = 1 << 30, *kmax = -(1 << 30);
    for (int v = 0; v < nv; v++) {
        int o = v * LC_W, x = gx + (v % vpr) * DVR_PW, y = gy + (v / vpr) * DVR_PH;
        vray r;
        vint kf, kl;
        vcolor surf;
        if (s->nnodes == 0) {
            vint px, py;
            dvr_packet_pixels(x, y, &px, &py);
            r = dvr_camera_rays(&f->cam, px, py);
            kf = vi_set1(1), kl = vi_set1(0);
            surf.r = surf.g = surf.b = surf.a = vf_zero();
        } else {
            setup_vector(s, f, t, x, y, c.stack, &r, &kf, &kl, &surf, st);
        }
        vf_store(c.ox + o, r.ox), vf_store(c.oy + o, r.oy), vf_store(c.oz + o, r.oz);
        vf_store(c.dx + o, r.dx), vf_store(c.dy + o, r.dy), vf_store(c.dz + o, r.dz);
        vf_store(c.ix + o, dvr_inv_dir(r.dx));
        vf_store(c.iy + o, dvr_inv_dir(r.dy));
        vf_store(c.iz + o, dvr_inv_dir(r.dz));
        vi_store(c.kf + o, kf), vi_store(c.kl + o, kl);
        vf_store(c.cr + o, vf_zero()), vf_store(c.cg + o, vf_zero());
        vf_store(c.cb + o, vf_zero()), vf_store(c.ca + o, vf_zero());
        vf_store(c.sr + o, surf.r), vf_store(c.sg + o, surf.g);
        vf_store(c.sb + o, surf.b), vf_store(c.sa + o, surf.a);
        for (int l = 0; l < LC_W; l++) {
            if (c.kf[o + l] > c.kl[o + l]) continue;
            *kmin = c.kf[o + l] < *kmin ? c.kf[o + l] : *kmin;
            *kmax = c.kl[o + l] > *kmax ? c.kl[o + l] : *kmax;
        }
    }
}

/* Every sample of the pass's nrows rows starts at the bias (0 for
 * particles), its gradient at 0. */
static inline void clear_buffer(const lc_kparticles *s, const cscratch *c, int rays, int nf, int K, int comps,
                                int nrows)
{
    const vfloat vbias = vf_set1(s->bias);
    for (int fi = 0; fi < nf; fi++)
        for (int row = 0; row < nrows; row++) {
            float *p = c->buf + ((size_t)fi * (size_t)K + (size_t)row) * (size_t)comps * (size_t)rays;
            for (int q = 0; q < rays; q += LC_W) vf_store(p + q, vbias);
            for (int q = rays; q < comps * rays; q += LC_W) vf_store(p + q, vf_zero());
        }
}

/* The last sample of a pass (or chunk) of up to len samples from kp, at most
 * kmax. Boundaries fall on multiples of PG_ANCHOR when len is one: a block
 * of PG_ANCHOR samples split between two passes costs each of them its
 * anchor (two exps) per particle and vector, and the later one the steps up
 * to its first sample. The first pass of a group is then a little shorter.
 * Pass boundaries change no image (a sample's terms and their order do not
 * depend on them). */
static inline int pass_end(int kp, int len, int kmax)
{
    int e = len % PG_ANCHOR == 0 ? ((kp + len) & ~(PG_ANCHOR - 1)) - 1 : kp + len - 1;
    return e < kmax ? e : kmax;
}

/* Pass length (issue 8, session 6). Passes change no image, only the work:
 * a long pass deposits terms behind the sample where a vector's rays all
 * became opaque (integrate_buffer counts them: the vector's terms of the
 * pass times the share of the pass behind that sample); a short one costs
 * its fixed part again: windows, list scan, the set-up again of every
 * particle and vector pair whose entry spans the boundary, the integration's
 * per-vector setup, each BVH walk for fewer samples. With s->buffer_adapt,
 * each group's totals of both (in deposited terms: the waste, and PASS_COST
 * per live vector and pass for the fixed part) set the next group's pass
 * length: halved when the waste is more than twice the fixed part, doubled
 * when it is less than half (the two balance at the best length; a step of
 * two moves their ratio about four times), within [PG_ANCHOR, K]; each tile
 * starts at PASS_FIRST. PASS_COST was measured (session 6, A/B on the
 * benchmark sets): 4 and 16 cost uniform 1e6 10-13% (passes too short on
 * its long chords), 64 keeps its times and most of dense1e6's gain. */
#ifndef PASS_COST
#define PASS_COST 64.0f
#endif
#define PASS_FIRST 32

static inline int pass_first(const lc_kparticles *s, int K)
{
    return s->buffer_adapt && K > PASS_FIRST ? PASS_FIRST : K;
}

static inline int pass_adapt(const lc_kparticles *s, int K, int P, float waste, float over)
{
    if (!s->buffer_adapt) return P;
    if (waste > 2.0f * over) return P / 2 >= PG_ANCHOR ? P / 2 : P;
    if (waste < 0.5f * over) return 2 * P <= K ? 2 * P : K;
    return P;
}

/* One tile in mode `mode` (a constant); only iso uses the probe. Each mode
 * gets its own function below: with iso's integration, probe and finishing
 * inlined into the same function as the dvr loops, GCC compiled those loops
 * differently and avx512 dvr frames were 2-3% slower (measured with
 * bench/ab_compare.sh; the iso code was never run). */
static inline __attribute__((always_inline)) void coherent_tile(const lc_kparticles *s, const lc_kframe *f, int mode,
                                                                const lc_ktile *t, lc_kscratch *scratch, lc_kstats *st)
{
    cscratch c;
    coherent_layout(s, f, scratch->mem, &c);
    pgroup g = group_dims(f);
    const int nv = g.nv, rays = buf_stride(nv), K = c.K, nf = s->nfields;
    int P = pass_first(s, K); /* samples per pass: K, or adapted per group (pass_adapt) */
    const int comps = mode_needs_grad(f) ? 4 : 1;
    const int vpr = g.gw / DVR_PW; /* vectors per group row */
    int vshift = 0; /* list bit of vector v: v >> vshift, < 64 */
    while (((nv - 1) >> vshift) >= 64) vshift++;
    const float dt = f->dt;
    const pprobe pc = {s, c.stack, st};
    const mprobe probe = {particles_probe, &pc};
    const mprobe *pr = mode == LC_KMODE_ISO ? &probe : NULL;
    for (int gy = t->y0; gy < t->y1; gy += g.gh) {
        for (int gx = t->x0; gx < t->x1; gx += g.gw) {
            /* Listing 3, line 3: rays, their box interval and lattice range */
            int kmin, kmax;
            setup_group(s, f, t, &c, gx, gy, nv, vpr, &kmin, &kmax, st);
            /* Listing 3, lines 4-6: passes of K samples until every ray is opaque,
               in chunks of passes that share one BVH walk (the group list) */
            int chunk = GL_FIRST_PASSES, done = 0;
            float gwaste = 0.0f, gover = 0.0f; /* this group's, in deposited terms */
            for (int kc = kmin; kc <= kmax && !done;) {
                int kc1 = pass_end(kc, chunk * P, kmax);
                int n = -1; /* entries in the list; -1: a walk per pass */
                if (c.list && set_windows(f, &c, nv, kc, kc1)) n = collect_group(s, f, &c, nv, vshift, kc, kc1, dt, st);
                int fits = n >= 0;
                for (int kp = kc, kend; kp <= kc1; kp = kend + 1) {
                    kend = pass_end(kp, P, kc1);
                    int nlive = set_windows(f, &c, nv, kp, kend);
                    if (!nlive) {
                        int alive = 0;
                        for (int v = 0; v < nv && !alive; v++) {
                            int o = v * LC_W;
                            alive = vm_any(vm_and(vf_lt(vf_load(c.ca + o), vf_set1(f->alpha_stop)),
                                                  vi_gt(vi_load(c.kl + o), vi_set1(kend))));
                        }
                        if (!alive) {
                            done = 1;
                            break;
                        }
                        continue;
                    }
                    st->passes++;
                    clear_buffer(s, &c, rays, nf, K, comps, kend - kp + 1);
                    for (int v = 0; v < nv; v++) c.touched[v] = 0;
                    if (n >= 0)
                        n = deposit_list(s, f, &c, nv, vshift, n, kp, kend, dt, comps, st);
                    else
                        traverse_pass(s, f, &c, nv, vshift, kp, kend, dt, comps, st);
                    /* Listing 2, lines 11-13: integrate the buffer front to back */
                    gwaste += integrate_buffer(s, f, mode, &c, nv, K, nf, kp, kend, comps, pr, st);
                    gover += PASS_COST * (float)nlive;
                }
                if (c.list) chunk = fits ? (chunk * 2 < GL_MAX_PASSES ? chunk * 2 : GL_MAX_PASSES)
                                         : (chunk > 1 ? chunk / 2 : 1);
                kc = kc1 + 1;
            }
            P = pass_adapt(s, K, P, gwaste, gover);
            finish_group(f, mode, t, &c, gx, gy, nv, vpr, pr);
        }
    }
}

static __attribute__((noinline)) void coherent_dvr(const lc_kparticles *s, const lc_kframe *f, const lc_ktile *t,
                                                    lc_kscratch *scratch, lc_kstats *st)
{
    coherent_tile(s, f, LC_KMODE_DVR, t, scratch, st);
}

static __attribute__((noinline)) void coherent_mip(const lc_kparticles *s, const lc_kframe *f, const lc_ktile *t,
                                                    lc_kscratch *scratch, lc_kstats *st)
{
    coherent_tile(s, f, LC_KMODE_MIP, t, scratch, st);
}

static __attribute__((noinline)) void coherent_iso(const lc_kparticles *s, const lc_kframe *f, const lc_ktile *t,
                                                    lc_kscratch *scratch, lc_kstats *st)
{
    coherent_tile(s, f, LC_KMODE_ISO, t, scratch, st);
}

/* The coherent method, one function per mode (slice takes no lattice sample:
 * both particle methods share particles_slice_tile). */
void LC_KFN(particles_coherent)(const void *scene, const lc_kframe *f, const lc_ktile *t, lc_kscratch *scratch,
                                lc_kstats *st)
{
    const lc_kparticles *s = scene;
    if (f->mode == LC_KMODE_MIP) {
        coherent_mip(s, f, t, scratch, st);
    } else if (f->mode == LC_KMODE_ISO) {
        coherent_iso(s, f, t, scratch, st);
    } else if (f->mode == LC_KMODE_SLICE) {
        cscratch c;
        coherent_layout(s, f, scratch->mem, &c);
        particles_slice_tile(s, f, t, c.stack, st);
    } else {
        coherent_dvr(s, f, t, scratch, st);
    }
}

