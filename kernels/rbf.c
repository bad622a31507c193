/* RBF set volume rendering (Jang et al. 2004), compiled once per target.
 * (The coherent method, the fastest, is the particle kind's kernel over the
 * set: kernels/particles_coherent.c, slot LC_KMETHOD_COHERENT below.)
 *
 * The field f(x) = w0 + sum w_i exp(-|x - mu_i|^2 / (2 s_i^2)) over the terms
 * whose support |x - mu_i| < R_i holds x (eqs. 2-3) is reconstructed at every
 * lattice sample by a gather:
 *   bvh (fast): lane-width packets of rays; per sample, the packet walks the
 *     BVH of the supports with a uniform node and stack (a node is entered
 *     when any lane's sample lies in its centre box grown by its largest R)
 *     and evaluates the leaf terms on the lanes inside their support;
 *   brute (base): the same sample loop over every RBF, for checking.
 * Both sum the terms in leaf order with the same arithmetic (term()), so they
 * agree to the last bit.
 *   octree (cells, rbf_octree.c): the paper's adaptive octree with per-cell
 *     RBF lists (§5), when the volume was built with accel = octree. */
#include "rbf_common.h"
#include "shared/ktable.h"
#include "kernels.h"

/* f (and with grad its gradient) at the points on the lanes in m: through
 * the BVH when stack is not NULL, else over every RBF. *found: some term
 * contributed on some lane. */
static inline vfloat gather(const lc_krbf *s, vfloat px, vfloat py, vfloat pz, vmask m, int grad, int32_t *stack,
                            vfloat *gx, vfloat *gy, vfloat *gz, int *found, lc_kstats *st)
{
    vfloat phi = vf_set1(s->bias);
    *gx = *gy = *gz = vf_zero();
    *found = 0;
    uint64_t nodes = 0, leaves = 0, evals = 0;
    if (!stack) {
        for (int32_t i = 0; i < (int32_t)s->count; i++) {
            vmask in = term(s, i, px, py, pz, m, grad, &phi, gx, gy, gz);
            evals += (uint64_t)vm_popcnt(in);
        }
    } else if (s->nnodes > 0) {
        int sp = 0;
        stack[sp++] = 0;
        while (sp > 0) {
            int32_t n = stack[--sp];
            const lc_kpnode *node = &s->nodes[n];
            float g = grow(s->node_rmax[n]);
            nodes++;
            vmask in = vm_and(m, vm_and(vm_and(vf_ge(px, vf_set1(node->lo[0] - g)), vf_le(px, vf_set1(node->hi[0] + g))),
                                        vm_and(vm_and(vf_ge(py, vf_set1(node->lo[1] - g)), vf_le(py, vf_set1(node->hi[1] + g))),
                                               vm_and(vf_ge(pz, vf_set1(node->lo[2] - g)), vf_le(pz, vf_set1(node->hi[2] + g))))));
            if (vm_none(in)) continue;
            if (node->count == 0) { /* first child on top: leaves are visited in array (leaf) order */
                stack[sp++] = node->first + 1;
                stack[sp++] = node->first;
                continue;
            }
            leaves++;
            for (int32_t i = node->first; i < node->first + node->count; i++) {
                vmask hit = term(s, i, px, py, pz, in, grad, &phi, gx, gy, gz);
                evals += (uint64_t)vm_popcnt(hit);
            }
        }
    }
    *found = evals > 0;
    if (st) st->nodes += nodes, st->leaves += leaves, st->kernel_evals += evals;
    return phi;
}

/* The RBF set's point evaluation for the modes (mode.h mprobe): gather
 * through the BVH, or over every RBF when stack is NULL (brute force), so
 * each method refines with its own sums. */
typedef struct rprobe {
    const lc_krbf *s;
    int32_t *stack;
    lc_kstats *st;
} rprobe;

static inline vfloat rbf_probe(const void *ctx, int fi, vfloat x, vfloat y, vfloat z, vmask m, vgrad *g)
{
    const rprobe *p = ctx;
    vgrad gr;
    int found;
    (void)fi;
    vfloat v = gather(p->s, x, y, z, m, g != NULL, p->stack, &gr.x, &gr.y, &gr.z, &found, p->st);
    if (g) *g = gr;
    return v;
}

/* One tile, lane-width packets of rays; stack NULL = brute force. The sample
 * loop is specialised per mode (mode = f->mode, a constant at each call). */
static inline __attribute__((always_inline)) void render_tile_as(const lc_krbf *s, const lc_kframe *f, int mode,
                                                                 const lc_ktile *t, int32_t *stack, lc_kstats *st)
{
    const float dt = f->dt;
    const int shade = mode == LC_KMODE_DVR && f->shade != LC_KSHADE_NONE; /* mode_needs_grad */
    const rprobe pc = {s, stack, st};
    const mprobe probe = {rbf_probe, &pc};
    /* nothing contributed and w0 = 0: the sample is 0 and, with tau(0) = 0, blends to exactly nothing */
    const int skip_zero = f->zero_transparent && s->bias == 0.0f;
    for (int y = t->y0; y < t->y1; y += DVR_PH) {
        if (lc_ktile_stopped(t)) return;
        for (int x = t->x0; x < t->x1; x += DVR_PW) {
            vint px, py, kf, kl;
            vray r;
            vcolor col = dvr_start(t, x, y); /* zero unless the tile carries (C, A) in */
            if (!rbf_packet_begin(s, f, mode, t, x, y, &probe, &px, &py, &r, &kf, &kl, &col, st)) continue;
            int k0 = 1 << 30, k1 = -(1 << 30);
            for (int l = 0; l < LC_W; l++) {
                if (vi_lane(kf, l) > vi_lane(kl, l)) continue;
                k0 = vi_lane(kf, l) < k0 ? vi_lane(kf, l) : k0;
                k1 = vi_lane(kl, l) > k1 ? vi_lane(kl, l) : k1;
            }
            vmask live = vm_and(vi_lt(kf, vi_add(kl, vi_set1(1))), vf_lt(col.a, vf_set1(f->alpha_stop))); /* a carried-in ray may have stopped already */
            for (int k = k0; k <= k1; k++) {
                vmask m = vm_and(live, vm_and(vi_lt(kf, vi_set1(k + 1)), vi_gt(kl, vi_set1(k - 1))));
                if (vm_none(m)) continue;
                vfloat tk = vf_set1((float)k * dt);
                vfloat qx = vf_fma(r.dx, tk, r.ox), qy = vf_fma(r.dy, tk, r.oy), qz = vf_fma(r.dz, tk, r.oz);
                vgrad gr;
                int found;
                vfloat phi = gather(s, qx, qy, qz, m, shade, stack, &gr.x, &gr.y, &gr.z, &found, st);
                if (!found && skip_zero) continue;
                st->samples += (uint64_t)vm_popcnt(m);
                mode_sample_as(f, mode, 0, &col, m, phi, shade ? &gr : NULL, &r, NULL, vi_set1(k), tk, &probe);
                live = vm_and(live, vf_lt(col.a, vf_set1(f->alpha_stop)));
                if (vm_none(live)) break;
            }
            vfloat depth = mode_finish_as(f, mode, &col, &r, &probe);
            mode_store_as(t, mode, px, py, &col, depth);
        }
    }
}

static void render_tile(const lc_krbf *s, const lc_kframe *f, const lc_ktile *t, int32_t *stack, lc_kstats *st)
{
    if (f->mode == LC_KMODE_MIP) render_tile_as(s, f, LC_KMODE_MIP, t, stack, st);
    else if (f->mode == LC_KMODE_ISO) render_tile_as(s, f, LC_KMODE_ISO, t, stack, st);
    else if (f->mode == LC_KMODE_SLICE) render_tile_as(s, f, LC_KMODE_SLICE, t, stack, st);
    else render_tile_as(s, f, LC_KMODE_DVR, t, stack, st);
}

static void rbf_bvh(const void *scene, const lc_kframe *f, const lc_ktile *t, lc_kscratch *scratch, lc_kstats *st)
{
    render_tile(scene, f, t, scratch->mem, st);
}

static void rbf_brute(const void *scene, const lc_kframe *f, const lc_ktile *t, lc_kscratch *scratch, lc_kstats *st)
{
    (void)scratch;
    render_tile(scene, f, t, NULL, st);
}

/* f and its gradient at n points (xyz interleaved) through the BVH. */
static void rbf_sample(const void *scene, const float *xyz, int64_t n, float *phi, float *grad, void *scratch)
{
    const lc_krbf *s = scene;
    if (s->cells) { /* an octree volume samples what its default method renders */
        LC_KFN(rbf_octree_sample)(s, xyz, n, phi, grad);
        return;
    }
    for (int64_t base = 0; base < n; base += LC_W) {
        int cnt = n - base < LC_W ? (int)(n - base) : LC_W;
        float tx[LC_W], ty[LC_W], tz[LC_W];
        for (int l = 0; l < LC_W; l++) {
            int q = l < cnt ? l : 0;
            tx[l] = xyz[3 * (base + q)], ty[l] = xyz[3 * (base + q) + 1], tz[l] = xyz[3 * (base + q) + 2];
        }
        vfloat gx, gy, gz;
        int found;
        vfloat v = gather(s, vf_load(tx), vf_load(ty), vf_load(tz), vm_first_n(cnt), 1, scratch, &gx, &gy, &gz, &found,
                          NULL);
        for (int l = 0; l < cnt; l++) {
            phi[base + l] = vf_lane(v, l);
            if (grad) {
                grad[3 * (base + l)] = vf_lane(gx, l);
                grad[3 * (base + l) + 1] = vf_lane(gy, l);
                grad[3 * (base + l) + 2] = vf_lane(gz, l);
            }
        }
    }
}

/* The traversal stack, depth + 4 entries: all either method and sampling need. */
static uint64_t stack_bytes(const void *scene)
{
    const lc_krbf *s = scene;
    return (uint64_t)(s->depth + 4) * sizeof(int32_t);
}

static uint64_t render_scratch_bytes(const void *scene, const lc_kframe *f)
{
    (void)f;
    return stack_bytes(scene);
}

/* COHERENT renders the set's particle view (lc_kparticles, host/kinds/rbf.c
 * prepare_coherent) through the particle kind's coherent kernel. */
const lc_kkind LC_KFN(lc_kkind_rbf) = {
    .render = {[LC_KMETHOD_FAST] = rbf_bvh, [LC_KMETHOD_BASE] = rbf_brute, [LC_KMETHOD_CELLS] = LC_KFN(rbf_octree),
               [LC_KMETHOD_COHERENT] = LC_KFN(particles_coherent)},
    .scratch_bytes = {[LC_KMETHOD_FAST] = render_scratch_bytes, [LC_KMETHOD_BASE] = render_scratch_bytes,
                      [LC_KMETHOD_CELLS] = LC_KFN(rbf_octree_scratch_bytes),
                      [LC_KMETHOD_COHERENT] = LC_KFN(particles_coherent_scratch_bytes)},
    .sample = rbf_sample,
    .sample_scratch_bytes = stack_bytes,
};
