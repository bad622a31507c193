/* Coherent packet traversal of the implicit min-max BVH (Knoll et al. 2011
 * §5.2, Listing 1, Fig. 3): packets of P x P rays made of lane-width
 * packlets, a uniform node index and stack with the first-active packlet per
 * stack entry, speculative first-active test, interval-arithmetic frustum
 * culling, front-to-back child order, and the transfer-function heuristics
 * decided per packet from the pre-integrated table: empty-space skipping
 * (eq. 5), pruning to larger leaves (eq. 6) and constant subvolumes (eq. 7).
 * Leaves are integrated per ray on the SPEC.md lattice (grid_common.h). */
#include <math.h>
#include "grid_common.h"
#include "kernels.h"

/* Interval bounds of a packet's rays for the frustum test: origins in
 * [olo, ohi], inverse directions in [ilo, ihi] per axis; ok[a] = 0 when the
 * directions' signs differ along a (the axis then bounds nothing). */
typedef struct frustum {
    float olo[3], ohi[3], ilo[3], ihi[3];
    int ok[3];
} frustum;

/* fminf/fmaxf without their NaN rules, which GCC calls out of line (3-4%
 * of a BVH frame); the operands here are finite */
static inline float minf(float a, float b) { return a < b ? a : b; }
static inline float maxf(float a, float b) { return a > b ? a : b; }
static inline float min4(float a, float b, float c, float d) { return minf(minf(a, b), minf(c, d)); }
static inline float max4(float a, float b, float c, float d) { return maxf(maxf(a, b), maxf(c, d)); }

static void frustum_build(const gpk *pk, int npk, frustum *fr)
{
    for (int a = 0; a < 3; a++) {
        fr->olo[a] = fr->ilo[a] = INFINITY;
        fr->ohi[a] = fr->ihi[a] = -INFINITY;
    }
    float dlo[3] = {INFINITY, INFINITY, INFINITY}, dhi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int p = 0; p < npk; p++) {
        vmask m = pk[p].live;
        if (vm_none(m)) continue;
        const vfloat *o[3] = {&pk[p].ray.ox, &pk[p].ray.oy, &pk[p].ray.oz};
        const vfloat *d[3] = {&pk[p].ray.dx, &pk[p].ray.dy, &pk[p].ray.dz};
        const vfloat *iv[3] = {&pk[p].ix, &pk[p].iy, &pk[p].iz};
        for (int a = 0; a < 3; a++) {
            fr->olo[a] = fminf(fr->olo[a], vf_reduce_min_masked(m, *o[a]));
            fr->ohi[a] = fmaxf(fr->ohi[a], vf_reduce_max_masked(m, *o[a]));
            fr->ilo[a] = fminf(fr->ilo[a], vf_reduce_min_masked(m, *iv[a]));
            fr->ihi[a] = fmaxf(fr->ihi[a], vf_reduce_max_masked(m, *iv[a]));
            dlo[a] = fminf(dlo[a], vf_reduce_min_masked(m, *d[a]));
            dhi[a] = fmaxf(dhi[a], vf_reduce_max_masked(m, *d[a]));
        }
    }
    for (int a = 0; a < 3; a++)
        fr->ok[a] = (dlo[a] > 0.0f || dhi[a] < 0.0f) && isfinite(fr->ilo[a]) && isfinite(fr->ihi[a]);
}

/* Interval arithmetic: bounds of every ray's entry and exit along each axis;
 * if the largest lower bound of the entries exceeds the smallest upper bound
 * of the exits (or that is behind the eye), no ray of the packet hits. */
static int frustum_misses(const frustum *fr, const lc_kgrid_node *n)
{
    float nlo = 0.0f, fhi = INFINITY;
    for (int a = 0; a < 3; a++) {
        if (!fr->ok[a]) continue;
        float l0 = n->lo[a] - fr->ohi[a], l1 = n->lo[a] - fr->olo[a]; /* lo - o */
        float h0 = n->hi[a] - fr->ohi[a], h1 = n->hi[a] - fr->olo[a]; /* hi - o */
        float i0 = fr->ilo[a], i1 = fr->ihi[a];
        float lmin = min4(l0 * i0, l0 * i1, l1 * i0, l1 * i1), lmax = max4(l0 * i0, l0 * i1, l1 * i0, l1 * i1);
        float hmin = min4(h0 * i0, h0 * i1, h1 * i0, h1 * i1), hmax = max4(h0 * i0, h0 * i1, h1 * i0, h1 * i1);
        /* positive directions enter at lo, negative at hi */
        float near_lb = i0 > 0.0f ? lmin : hmin, far_ub = i0 > 0.0f ? hmax : lmax;
        nlo = maxf(nlo, near_lb);
        fhi = minf(fhi, far_ub);
    }
    /* slack for the per-ray round-off of the exact test */
    return nlo > fhi * 1.0001f + 1e-6f;
}

static inline int packlet_hits(const gpk *p, const lc_kgrid_node *n)
{
    if (vm_none(p->live)) return 0;
    vfloat t0, t1;
    grid_box_t(p, n->lo, n->hi, &t0, &t1);
    return vm_any(vm_and(p->live, vf_le(t0, t1)));
}

/* Fig. 3: speculative test of the first active packlet, then the frustum,
 * then the remaining packlets in order. Returns npk when none hits. */
static inline int first_hit(const gpk *pk, int fa, int npk, const frustum *fr, const lc_kgrid_node *n)
{
    if (packlet_hits(&pk[fa], n)) return fa;
    if (fa + 1 >= npk || frustum_misses(fr, n)) return npk;
    for (int p = fa + 1; p < npk; p++)
        if (packlet_hits(&pk[p], n)) return p;
    return npk;
}

/* The frame's TF tests of node id (kgrid.h LC_KGRID_NODE_*): one byte the
 * host computed per node from the pre-integrated table. */
static inline int node_bits(const lc_kgrid *g, int32_t id) { return g->node_tf_bits[id]; }

/* A node is skipped when the mode says it cannot matter; the grid tells it
 * the node's value range (which bounds the field) and eq. 5's transparency
 * test (a node is empty when the pre-integrated opacity over its range is at
 * most delta_c; the mean extinction being exactly zero is always used: it
 * means zero opacity at every sample, so skipping is exact). */
static inline int node_empty(const lc_kgrid *g, const lc_kframe *f, int32_t id, float mfloor)
{
    /* dvr: mode_node_matters(f, mn) is !mn.transparent; answered here
     * without loading the node (the traversal tests both children of every
     * node it descends, and their 40-byte nodes missed the cache) */
    if (f->mode == LC_KMODE_DVR) return node_bits(g, id) & LC_KGRID_NODE_EMPTY;
    const lc_kgrid_node *n = &g->nodes[id];
    mnode mn = {n->vmin, n->vmax, 1, 0, mfloor};
    return !mode_node_matters(f, &mn);
}

/* eq. 6: treat an inner node as a leaf when its opacity relative to its size
 * exceeds delta_p (the host's DENSE bit). Exact: a larger leaf takes the
 * same lattice samples. */
static inline int node_prune(const lc_kgrid *g, const lc_kframe *f, int32_t id, const lc_kgrid_node *n,
                             float footprint)
{
    if (!(g->bvh_flags & LC_KGRID_PRUNE)) return 0;
    /* Also stop where the node is no wider than the packet's footprint at its
     * distance: below that, descending costs node tests for every ray and
     * saves few samples. Like eq. 6 this is exact here (a larger leaf takes
     * the same lattice samples; skipped children had zero opacity). */
    if (footprint > 0.0f) {
        float dbox = lc_kgrid_node_diag(n);
        const float *e = f->cam.eye;
        float cx = 0.5f * (n->lo[0] + n->hi[0]) - e[0], cy = 0.5f * (n->lo[1] + n->hi[1]) - e[1],
              cz = 0.5f * (n->lo[2] + n->hi[2]) - e[2];
        float dist = f->cam.ortho ? 1.0f : sqrtf(cx * cx + cy * cy + cz * cz);
        if (dbox < footprint * dist) return 1;
    }
    return node_bits(g, id) & LC_KGRID_NODE_DENSE;
}

/* eq. 7: constant subvolume when the opacity over [min, max] differs from
 * that of either end by less than delta_sv. We also require the colour at the
 * ends to agree within delta_sv (weighted by opacity), since the paper's test
 * alone would flatten a TF with constant opacity and varying colour; and,
 * because the closed form is unshaded, lit frames use it only where the data
 * is truly constant (zero gradient: unshaded by SPEC.md anyway). The TF part
 * is the host's CONST bit. */
static inline int node_constant(const lc_kgrid *g, const lc_kframe *f, int32_t id, const lc_kgrid_node *n)
{
    if (!(g->bvh_flags & LC_KGRID_CONST)) return 0;
    /* iso pairs every sample with the one before: no closed form */
    if (f->mode == LC_KMODE_ISO) return 0;
    /* lit frames and modes other than dvr: only truly constant data (exact) */
    if ((f->shade != LC_KSHADE_NONE || f->mode != LC_KMODE_DVR) && n->vmin != n->vmax) return 0;
    if (n->vmin == n->vmax) return 1;
    return node_bits(g, id) & LC_KGRID_NODE_CONST;
}

/* Leaves are not integrated one by one: each lane collects the lattice
 * samples of consecutive leaves into a pending run [pa, pb] and integrates it
 * when the next leaf leaves a gap (skipped empty space), when it grows past
 * run_max samples (so early termination still stops traversal), before a
 * constant subvolume, and at the end. The samples and their order are those
 * of leaf-by-leaf integration; only the loop over them is longer, which keeps
 * the lanes of a packlet busy. */
static inline void flush(const lc_kgrid *g, const lc_kframe *f, gpk *q, lc_kstats *st)
{
    vmask has = vm_not(vi_gt(q->pa, q->pb));
    if (vm_none(has)) return;
    vint knext = q->knext;
    q->knext = vi_select(has, q->pa, q->knext);
    grid_integrate(g, f, q, q->pa, vi_select(has, q->pb, vi_sub(q->pa, vi_set1(1))), st);
    q->knext = vi_max(q->knext, knext);
    q->pa = vi_set1(1);
    q->pb = vi_set1(0);
}

static void integrate_node(const lc_kgrid *g, const lc_kframe *f, gpk *pk, int fa, int npk, const lc_kgrid_node *n,
                           int csv, lc_kstats *st)
{
    float phi = 0.5f * (n->vmin + n->vmax);
    const int pairs = mode_pairs(f);
    for (int p = fa; p < npk; p++) {
        gpk *q = &pk[p];
        if (vm_none(q->live)) continue;
        vfloat t0, t1;
        grid_box_t(q, n->lo, n->hi, &t0, &t1);
        /* a packlet of the group that misses the leaf (most, with 32x32
         * groups): no lattice indices (two divisions) to compute */
        if (vm_none(vm_and(q->live, vf_le(t0, t1)))) continue;
        vint kf, kl;
        grid_lattice(g, f->dt, t0, t1, &kf, &kl);
        if (pairs) {
            /* iso: also the samples just before and after the node, so every step
               between two samples that overlaps the node is seen whole (even one
               with no sample inside the node); mode_node_matters says why culling
               is then exact */
            vmask hit = vf_le(t0, t1);
            kf = vi_select(hit, vi_sub(kf, vi_set1(1)), kf);
            kl = vi_select(hit, vi_add(kl, vi_set1(1)), kl);
        }
        vint ka = vi_max(q->knext, kf), kb = vi_min(q->klast, kl);
        vmask v = vm_and(q->live, vm_not(vi_gt(ka, kb)));
        if (vm_none(v)) continue;
        if (csv) {
            flush(g, f, q, st);
            grid_integrate_const(g, f, q, ka, kb, phi, st);
            continue;
        }
        vmask pending = vm_not(vi_gt(q->pa, q->pb));
        vmask gap = vm_and(v, vm_and(pending, vi_gt(ka, vi_add(q->pb, vi_set1(1)))));
        if (vm_any(gap)) flush(g, f, q, st);
        pending = vm_not(vi_gt(q->pa, q->pb));
        q->pa = vi_select(vm_and(v, vm_not(pending)), ka, q->pa);
        q->pb = vi_select(v, kb, q->pb);
        q->knext = vi_select(v, vi_add(kb, vi_set1(1)), q->knext);
        if (vm_any(vi_gt(vi_sub(q->pb, q->pa), vi_set1(g->run_max)))) flush(g, f, q, st);
    }
}

/* mip: the smallest current maximum over the packet's live rays (-inf
 * while any live ray has none): nodes whose values cannot beat it are
 * skipped. Other modes: -inf (unused). */
static float mip_floor(const lc_kframe *f, const gpk *pk, int npk)
{
    if (f->mode != LC_KMODE_MIP) return -INFINITY;
    float fl = INFINITY;
    for (int p = 0; p < npk; p++) {
        if (vm_none(pk[p].live)) continue;
        if (vm_any(vm_and(pk[p].live, vm_not(vf_gt(pk[p].c.b, vf_zero()))))) return -INFINITY;
        fl = fminf(fl, vf_reduce_min_masked(pk[p].live, pk[p].c.r));
    }
    return fl;
}

static int any_live(const gpk *pk, int npk)
{
    for (int p = 0; p < npk; p++)
        if (vm_any(pk[p].live)) return 1;
    return 0;
}

/* Listing 1, with the node index, stack and first-active index uniform. */
static void traverse(const lc_kgrid *g, const lc_kframe *f, gpk *pk, int npk, lc_kstats *st)
{
    const lc_kgrid_node *nodes = g->nodes;
    int stack[LC_KGRID_MAX_DEPTH], fa_stack[LC_KGRID_MAX_DEPTH];
    int d = 0, id = 0, fa = 0;
    frustum fr;
    frustum_build(pk, npk, &fr);
    const int ortho = f->cam.ortho;
    /* packet footprint per unit distance (perspective) or in world units
     * (orthographic): packet side in pixels times the pixel pitch, scaled by
     * prune_footprint at LC_KGRID_PRUNE_ROWS rows whatever the frame's height
     * (a node's packets and the samples descending into it saves both grow
     * with the pixels it covers; measured: 3 footprints best at 512 rows, 6 at
     * 1024), and at least LC_KGRID_PRUNE_MIN footprints at the frame's height
     * (256 rows: 2 beat 1.5 by 3-9 %) */
    float upl = sqrtf(f->cam.up[0] * f->cam.up[0] + f->cam.up[1] * f->cam.up[1] + f->cam.up[2] * f->cam.up[2]);
    float fp_rows = fmaxf(g->prune_footprint / (float)LC_KGRID_PRUNE_ROWS, LC_KGRID_PRUNE_MIN / (float)f->cam.height);
    float footprint =
        g->prune_footprint > 0.0f ? fp_rows * (float)(f->packet > 1 ? f->packet : DVR_PH) * 2.0f * upl : 0.0f;
    float mfloor = mip_floor(f, pk, npk);
    if (node_empty(g, f, 0, mfloor)) return;
    for (;;) {
        const lc_kgrid_node *n = &nodes[id];
        /* speculative min-max descent: go straight into the only non-empty child */
        int dead = 0;
        while (n->child) {
            int e0 = node_empty(g, f, n->child, mfloor), e1 = node_empty(g, f, n->child + 1, mfloor);
            if (e0 && e1) {
                dead = 1;
                break;
            }
            if (e0) id = n->child + 1;
            else if (e1) id = n->child;
            else break;
            n = &nodes[id];
        }
        if (!dead) {
            st->nodes++;
            int hit = first_hit(pk, fa, npk, &fr, n);
            if (hit < npk) {
                fa = hit;
                int csv = node_constant(g, f, id, n);
                if (n->child && !csv && !node_prune(g, f, id, n, footprint)) {
                    /* front child: the eye's side of the split plane (all
                     * perspective rays start there); orthographic: by direction */
                    const lc_kgrid_node *c0 = &nodes[n->child];
                    int ax = n->axis;
                    int front = ortho ? (f->cam.forward[ax] < 0.0f) : (f->cam.eye[ax] > c0->hi[ax]);
                    if (d < LC_KGRID_MAX_DEPTH) {
                        stack[d] = n->child + 1 - front;
                        fa_stack[d] = fa;
                        d++;
                        id = n->child + front;
                        continue;
                    }
                }
                st->leaves++;
                integrate_node(g, f, pk, fa, npk, n, csv, st);
                if (!any_live(pk, npk)) break;
                mfloor = mip_floor(f, pk, npk);
            }
        }
        if (d == 0) break;
        d--;
        id = stack[d];
        fa = fa_stack[d];
    }
}

static void grid_bvh(const void *scene, const lc_kframe *f, const lc_ktile *t, lc_kscratch *scratch, lc_kstats *st)
{
    const lc_kgrid *g = scene;
    int pw, ph;
    grid_packet_dims(f, &pw, &ph);
    /* groups no larger than the tile (rounded up to whole packlets): the
       rest of a larger group would be dead packlets (measured: 64x64 groups
       in 32-pixel tiles, 0.85-0.95x of 32x32) */
    int tw = (t->x1 - t->x0 + DVR_PW - 1) / DVR_PW * DVR_PW, th = (t->y1 - t->y0 + DVR_PH - 1) / DVR_PH * DVR_PH;
    pw = pw < tw ? pw : tw;
    ph = ph < th ? ph : th;
    int nx = pw / DVR_PW, ny = ph / DVR_PH, npk = nx * ny;
    uintptr_t base = ((uintptr_t)scratch->mem + 63) & ~(uintptr_t)63;
    gpk *pk = (gpk *)base;
    for (int y = t->y0; y < t->y1; y += ph) {
        if (lc_ktile_stopped(t)) return;
        for (int x = t->x0; x < t->x1; x += pw) {
            for (int j = 0; j < ny; j++)
                for (int i = 0; i < nx; i++) {
                    gpk *p = &pk[j * nx + i];
                    grid_packlet_init(g, f, t, x + i * DVR_PW, y + j * DVR_PH, p);
                    st->rays += (uint64_t)vm_popcnt(vm_and(vi_lt(p->px, vi_set1(t->x1)), vi_lt(p->py, vi_set1(t->y1))));
                }
            if (!mode_lattice(f)) {
                for (int p = 0; p < npk; p++) grid_slice(g, f, t, &pk[p], st);
            } else {
                if (any_live(pk, npk)) traverse(g, f, pk, npk, st);
                for (int p = 0; p < npk; p++) flush(g, f, &pk[p], st);
            }
            for (int p = 0; p < npk; p++) grid_finish_store(g, f, t, &pk[p], st);
        }
    }
}

static uint64_t scratch_bytes(const void *scene, const lc_kframe *f)
{
    (void)scene;
    return grid_scratch(f);
}

/* The trilinear value and gradient (eqs. 8-9) at n points; 0 outside the
 * domain (the field is undefined there, SPEC.md). */
static void grid_points(const void *scene, const float *xyz, int64_t n, float *phi, float *grad, void *scratch)
{
    const lc_kgrid *g = scene;
    (void)scratch;
    for (int64_t base = 0; base < n; base += LC_W) {
        int cnt = n - base < LC_W ? (int)(n - base) : LC_W;
        float tx[LC_W], ty[LC_W], tz[LC_W];
        for (int l = 0; l < LC_W; l++) {
            int64_t q = base + (l < cnt ? l : 0);
            tx[l] = xyz[3 * q], ty[l] = xyz[3 * q + 1], tz[l] = xyz[3 * q + 2];
        }
        vfloat x = vf_load(tx), y = vf_load(ty), z = vf_load(tz);
        vmask in = vm_and(vm_and(vm_and(vf_ge(x, vf_set1(g->lo[0])), vf_le(x, vf_set1(g->hi[0]))),
                                 vm_and(vf_ge(y, vf_set1(g->lo[1])), vf_le(y, vf_set1(g->hi[1])))),
                          vm_and(vf_ge(z, vf_set1(g->lo[2])), vf_le(z, vf_set1(g->hi[2]))));
        /* outside lanes sample the origin (a valid voxel), then read as 0 */
        x = vf_select(in, x, vf_set1(g->lo[0])), y = vf_select(in, y, vf_set1(g->lo[1]));
        z = vf_select(in, z, vf_set1(g->lo[2]));
        vfloat gx = vf_zero(), gy = vf_zero(), gz = vf_zero();
        vfloat v = vf_select(in, grid_sample(g, x, y, z, grad != NULL, &gx, &gy, &gz), vf_zero());
        for (int l = 0; l < cnt; l++) {
            int64_t o = base + l;
            phi[o] = vf_lane(v, l);
            if (grad) {
                grad[3 * o] = vf_lane(vf_select(in, gx, vf_zero()), l);
                grad[3 * o + 1] = vf_lane(vf_select(in, gy, vf_zero()), l);
                grad[3 * o + 2] = vf_lane(vf_select(in, gz, vf_zero()), l);
            }
        }
    }
}

static uint64_t no_scratch(const void *scene)
{
    (void)scene;
    return 0;
}

const lc_kkind LC_KFN(lc_kkind_grid) = {
    .render = {[LC_KMETHOD_FAST] = grid_bvh, [LC_KMETHOD_BASE] = LC_KFN(grid_brute)},
    .scratch_bytes = {[LC_KMETHOD_FAST] = scratch_bytes, [LC_KMETHOD_BASE] = scratch_bytes},
    .sample = grid_points,
    .sample_scratch_bytes = no_scratch,
};
