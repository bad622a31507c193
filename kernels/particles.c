/* Particle volume rendering (Knoll et al. 2014), compiled once per target:
 * the kind's kernel sub-table, the direct method (the paper's baseline: per
 * sample, gather every overlapping particle through the BVH, then hand the
 * fields to the mode) and point sampling. The coherent method is in
 * particles_coherent.c; both evaluate the field with the same arithmetic
 * (particles_common.h), so they differ only by summation order. */
#include "particles_common.h"

/* ---------------------------------------------------------------- gathering */

/* Every field (and, with grad, its gradient) at the points p of the lanes in m,
 * through the BVH: the direct method's per-sample gather. Returns whether any
 * particle contributed. */
static inline int gather_fields(const lc_kparticles *s, vfloat px, vfloat py, vfloat pz, vmask m, int grad,
                                int32_t *stack, vfloat *phi, vfloat *gx, vfloat *gy, vfloat *gz, lc_kstats *st)
{
    for (int fi = 0; fi < s->nfields; fi++) phi[fi] = gx[fi] = gy[fi] = gz[fi] = vf_zero();
    if (s->nnodes == 0) return 0;
    int sp = 0, found = 0;
    uint64_t nodes = 0, leaves = 0, evals = 0;
    stack[sp++] = 0;
    while (sp > 0) {
        int32_t n = stack[--sp];
        const lc_kpnode *node = &s->nodes[n];
        float g = grow(s->sigma * s->node_rmax[n]);
        nodes++;
        vmask in = vm_and(m, vm_and(vm_and(vf_ge(px, vf_set1(node->lo[0] - g)), vf_le(px, vf_set1(node->hi[0] + g))),
                                    vm_and(vm_and(vf_ge(py, vf_set1(node->lo[1] - g)), vf_le(py, vf_set1(node->hi[1] + g))),
                                           vm_and(vf_ge(pz, vf_set1(node->lo[2] - g)), vf_le(pz, vf_set1(node->hi[2] + g))))));
        if (vm_none(in)) continue;
        if (node->count == 0) {
            stack[sp++] = node->first + 1;
            stack[sp++] = node->first;
            continue;
        }
        leaves++;
        for (int32_t i = node->first; i < node->first + node->count; i++) {
            float rs = s->sigma * s->r[i];
            vmask inside;
            vfloat ex, ey, ez;
            vfloat d2 = sample_d2(px, py, pz, s->px[i], s->py[i], s->pz[i], rs * rs, in, &inside, &ex, &ey, &ez);
            if (vm_none(inside)) continue;
            found = 1;
            evals += (uint64_t)vm_popcnt(inside);
            vfloat p = gaussian(d2, s->neg_inv_2r2[i], s->kappa * s->k[i], inside);
            int fi = s->field[i];
            phi[fi] = vf_add(phi[fi], p);
            if (grad) {
                vfloat gp = vf_mul(p, vf_set1(2.0f * s->neg_inv_2r2[i])); /* grad phi_i = -(p - c) / r^2 phi_i */
                gx[fi] = vf_fma(ex, gp, gx[fi]);
                gy[fi] = vf_fma(ey, gp, gy[fi]);
                gz[fi] = vf_fma(ez, gp, gz[fi]);
            }
        }
    }
    if (st) st->nodes += nodes, st->leaves += leaves, st->kernel_evals += evals;
    return found;
}

/* ---------------------------------------------------------------- direct */

static inline __attribute__((always_inline)) void direct_tile(const lc_kparticles *s, const lc_kframe *f, int mode,
                                                              const lc_ktile *t, lc_kscratch *scratch, lc_kstats *st)
{
    int32_t *stack = scratch->mem; /* direct needs only the traversal stack (direct_scratch_bytes) */
    const float dt = f->dt;
    const int nf = s->nfields, shade = f->shade != LC_KSHADE_NONE;
    for (int y = t->y0; y < t->y1; y += DVR_PH) {
        for (int x = t->x0; x < t->x1; x += DVR_PW) {
            vcolor col = {vf_zero(), vf_zero(), vf_zero(), vf_zero()};
            vcolor surf = {vf_zero(), vf_zero(), vf_zero(), vf_zero()};
            if (s->nnodes == 0) {
                finish_vector(f, t, x, y, &col, &surf);
                continue;
            }
            vray r;
            vint kf, kl;
            setup_vector(s, f, t, x, y, stack, &r, &kf, &kl, &surf, st);
            vmask has = vi_lt(kf, vi_add(kl, vi_set1(1)));
            if (vm_any(has)) {
                int k0 = 1 << 30, k1 = -(1 << 30);
                for (int l = 0; l < LC_W; l++) {
                    if (vi_lane(kf, l) > vi_lane(kl, l)) continue;
                    k0 = vi_lane(kf, l) < k0 ? vi_lane(kf, l) : k0;
                    k1 = vi_lane(kl, l) > k1 ? vi_lane(kl, l) : k1;
                }
                vmask live = has;
                for (int k = k0; k <= k1; k++) {
                    vmask m = vm_and(live, vm_and(vi_lt(kf, vi_set1(k + 1)), vi_gt(kl, vi_set1(k - 1))));
                    if (vm_none(m)) continue;
                    vfloat tk = vf_set1((float)k * dt);
                    vfloat px = vf_fma(r.dx, tk, r.ox), py = vf_fma(r.dy, tk, r.oy), pz = vf_fma(r.dz, tk, r.oz);
                    vfloat phi[LC_KMAX_FIELDS], gx[LC_KMAX_FIELDS], gy[LC_KMAX_FIELDS], gz[LC_KMAX_FIELDS];
                    /* gather: every particle whose support contains a sample */
                    int found = gather_fields(s, px, py, pz, m, shade, stack, phi, gx, gy, gz, st);
                    if (!found && f->zero_transparent) continue; /* blends to exactly nothing */
                    st->samples += (uint64_t)vm_popcnt(m);
                    for (int fi = 0; fi < nf; fi++) {
                        /* tau(0) = 0 and this field is 0 on every lane: it blends to exactly nothing */
                        if (f->zero_transparent && vm_none(vm_and(m, vf_ne(phi[fi], vf_zero())))) continue;
                        vgrad gr = {gx[fi], gy[fi], gz[fi]};
                        mode_sample_as(f, mode, fi, &col, m, phi[fi], shade ? &gr : NULL, &r, NULL);
                    }
                    live = vm_and(live, vf_lt(col.a, vf_set1(f->alpha_stop)));
                    if (vm_none(live)) break;
                }
            }
            finish_vector(f, t, x, y, &col, &surf);
        }
    }
}

/* The direct method, its sample loop specialised per mode. */
static void particles_direct(const void *scene, const lc_kframe *f, const lc_ktile *t, lc_kscratch *scratch,
                             lc_kstats *st)
{
    if (f->mode == LC_KMODE_MIP) direct_tile(scene, f, LC_KMODE_MIP, t, scratch, st);
    else direct_tile(scene, f, LC_KMODE_DVR, t, scratch, st);
}

/* ---------------------------------------------------------------- point sampling */

/* Every field and its gradient at n points (xyz interleaved) through the BVH:
 * phi[i * nfields + f], grad[(i * nfields + f) * 3 + c]. grad may be NULL. */
static void particles_sample(const void *scene, const float *xyz, int64_t n, float *phi, float *grad, void *scratch)
{
    const lc_kparticles *s = scene;
    int32_t *stack = scratch;
    const int nf = s->nfields;
    for (int64_t base = 0; base < n; base += LC_W) {
        int cnt = n - base < LC_W ? (int)(n - base) : LC_W;
        float tx[LC_W], ty[LC_W], tz[LC_W];
        for (int l = 0; l < LC_W; l++) {
            int q = l < cnt ? l : 0;
            tx[l] = xyz[3 * (base + q)], ty[l] = xyz[3 * (base + q) + 1], tz[l] = xyz[3 * (base + q) + 2];
        }
        vfloat px = vf_load(tx), py = vf_load(ty), pz = vf_load(tz);
        vmask m = vm_first_n(cnt);
        vfloat acc[LC_KMAX_FIELDS], gx[LC_KMAX_FIELDS], gy[LC_KMAX_FIELDS], gz[LC_KMAX_FIELDS];
        gather_fields(s, px, py, pz, m, 1, stack, acc, gx, gy, gz, NULL);
        for (int fi = 0; fi < nf; fi++) {
            for (int l = 0; l < cnt; l++) {
                int64_t o = (base + l) * nf + fi;
                phi[o] = vf_lane(acc[fi], l);
                if (grad) {
                    grad[3 * o] = vf_lane(gx[fi], l);
                    grad[3 * o + 1] = vf_lane(gy[fi], l);
                    grad[3 * o + 2] = vf_lane(gz[fi], l);
                }
            }
        }
    }
}

/* Traversal stack of depth + 4 entries: all point sampling needs. */
static uint64_t stack_bytes(const void *scene)
{
    const lc_kparticles *s = scene;
    return (uint64_t)(s->depth + 4) * sizeof(int32_t);
}

/* The direct method needs only the stack. */
static uint64_t direct_scratch_bytes(const void *scene, const lc_kframe *f)
{
    (void)f;
    return stack_bytes(scene);
}

const lc_kkind LC_KFN(lc_kkind_particles) = {
    .render = {[LC_KMETHOD_FAST] = LC_KFN(particles_coherent), [LC_KMETHOD_BASE] = particles_direct},
    .scratch_bytes = {[LC_KMETHOD_FAST] = LC_KFN(particles_coherent_scratch_bytes), [LC_KMETHOD_BASE] = direct_scratch_bytes},
    .sample = particles_sample,
    .sample_scratch_bytes = stack_bytes,
};

