/* Particle volume rendering (Knoll et al. 2014), compiled once per target:
 * the kind's kernel sub-table, the direct method (the paper's baseline: per
 * sample, gather every overlapping particle through the BVH, then hand the
 * fields to the mode) and point sampling. The coherent method is in
 * particles_coherent.c; both evaluate the field with the same arithmetic
 * (particles_common.h), so they differ only by summation order. */
#include "particles_common.h"

/* ---------------------------------------------------------------- direct */

static inline __attribute__((always_inline)) void direct_tile(const lc_kparticles *s, const lc_kframe *f, int mode,
                                                              const lc_ktile *t, lc_kscratch *scratch, lc_kstats *st)
{
    int32_t *stack = scratch->mem; /* direct needs only the traversal stack (direct_scratch_bytes) */
    const float dt = f->dt;
    const int nf = s->nfields, shade = mode == LC_KMODE_DVR && f->shade != LC_KSHADE_NONE; /* mode_needs_grad */
    const pprobe pc = {s, stack, st};
    const mprobe probe = {particles_probe, &pc};
    const int skip = skip_base(s, f);
    const vfloat vbias = vf_set1(s->bias);
    for (int y = t->y0; y < t->y1; y += DVR_PH) {
        if (lc_ktile_stopped(t)) return;
        for (int x = t->x0; x < t->x1; x += DVR_PW) {
            vcolor col = dvr_start(t, x, y); /* zero unless the tile carries (C, A) in */
            vcolor surf = {vf_zero(), vf_zero(), vf_zero(), vf_zero()};
            vray r;
            vint kf, kl;
            if (s->nnodes == 0) {
                vint px, py;
                dvr_packet_pixels(x, y, &px, &py);
                r = dvr_camera_rays(&f->cam, px, py);
                finish_vector(f, mode, t, x, y, &col, &surf, &r, &probe);
                continue;
            }
            setup_vector(s, f, t, x, y, stack, &r, &kf, &kl, &surf, st);
            vmask has = vi_lt(kf, vi_add(kl, vi_set1(1)));
            if (vm_any(has)) {
                int k0 = 1 << 30, k1 = -(1 << 30);
                for (int l = 0; l < LC_W; l++) {
                    if (vi_lane(kf, l) > vi_lane(kl, l)) continue;
                    k0 = vi_lane(kf, l) < k0 ? vi_lane(kf, l) : k0;
                    k1 = vi_lane(kl, l) > k1 ? vi_lane(kl, l) : k1;
                }
                vmask live = vm_and(has, vf_lt(col.a, vf_set1(f->alpha_stop))); /* a carried-in ray may have stopped already */
                for (int k = k0; k <= k1; k++) {
                    vmask m = vm_and(live, vm_and(vi_lt(kf, vi_set1(k + 1)), vi_gt(kl, vi_set1(k - 1))));
                    if (vm_none(m)) continue;
                    vfloat tk = vf_set1((float)k * dt);
                    vfloat px = vf_madd(r.dx, tk, r.ox), py = vf_madd(r.dy, tk, r.oy), pz = vf_madd(r.dz, tk, r.oz);
                    vfloat phi[LC_KMAX_FIELDS], gx[LC_KMAX_FIELDS], gy[LC_KMAX_FIELDS], gz[LC_KMAX_FIELDS];
                    /* gather: every particle whose support contains a sample */
                    int found = gather_fields(s, px, py, pz, m, shade, mode == LC_KMODE_DVR, stack, phi, gx, gy, gz, st);
                    if (!found && skip) continue; /* every field is the bias: blends to exactly nothing */
                    st->samples += (uint64_t)vm_popcnt(m);
                    for (int fi = 0; fi < nf; fi++) {
                        /* tau(bias) = 0 and this field is the bias on every lane: it blends to exactly nothing */
                        if (skip && vm_none(vm_and(m, vf_ne(phi[fi], vbias)))) continue;
                        vgrad gr = {gx[fi], gy[fi], gz[fi]};
                        mode_sample_as(f, mode, fi, &col, m, phi[fi], shade ? &gr : NULL, &r, NULL, vi_set1(k), tk,
                                       &probe);
                    }
                    live = vm_and(live, vf_lt(col.a, vf_set1(f->alpha_stop)));
                    if (vm_none(live)) break;
                }
            }
            finish_vector(f, mode, t, x, y, &col, &surf, &r, &probe);
        }
    }
}

/* The direct method, its sample loop specialised per mode. */
static void particles_direct(const void *scene, const lc_kframe *f, const lc_ktile *t, lc_kscratch *scratch,
                             lc_kstats *st)
{
    if (f->mode == LC_KMODE_MIP) direct_tile(scene, f, LC_KMODE_MIP, t, scratch, st);
    else if (f->mode == LC_KMODE_ISO) direct_tile(scene, f, LC_KMODE_ISO, t, scratch, st);
    else if (f->mode == LC_KMODE_SLICE) particles_slice_tile(scene, f, t, scratch->mem, st);
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
        gather_fields(s, px, py, pz, m, 1, 0, stack, acc, gx, gy, gz, NULL);
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

