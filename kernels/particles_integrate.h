/* The coherent particle kernel's integration of a pass (Knoll et al. 2014,
 * Listing 2, lines 11-13), included once by kernels/particles_coherent.c
 * after its scratch layout (cscratch): the general loop (integrate_buffer),
 * the paired loop for one field without gradient in dvr and mip
 * (integrate_two) and the out-of-line entry (integrate_pass); measured in
 * docs/bench/particles.md "Integration". */
#ifndef LC_PARTICLES_INTEGRATE_H
#define LC_PARTICLES_INTEGRATE_H

/* One ray vector's state while a pass is integrated: the live lanes (live0
 * at the start), their ranges, the sample where each lane became opaque
 * (kdie, without a branch per death: commit e405e06, the branch and its
 * reduction were ~15% of the integration on 1e6 far), its colour and the
 * samples taken. */
typedef struct ivec {
    int o;
    vmask live, live0;
    vint kf, kl, klp, kdie;
    vcolor col;
    uint64_t nsamp;
} ivec;

static inline __attribute__((always_inline)) void ivec_load(const cscratch *c, int v, int kend, ivec *q)
{
    q->o = v * LC_W;
    q->live = q->live0 = vf_le(vf_load(c->w0 + q->o), vf_load(c->w1 + q->o));
    q->kf = vi_load(c->kf + q->o), q->kl = vi_load(c->kl + q->o);
    q->klp = vi_min(q->kl, vi_set1(kend)); /* the pass's last sample of each lane's range */
    q->kdie = q->klp;
    q->col = (vcolor){vf_load(c->cr + q->o), vf_load(c->cg + q->o), vf_load(c->cb + q->o), vf_load(c->ca + q->o)};
    q->nsamp = 0;
}

/* The lanes that take sample k (live, k in their range), counted. */
static inline __attribute__((always_inline)) vmask ivec_mask(ivec *q, int k)
{
    vmask m = vm_and(q->live, vm_and(vi_lt(q->kf, vi_set1(k + 1)), vi_gt(q->kl, vi_set1(k - 1))));
    q->nsamp += (uint64_t)vm_popcnt(m);
    return m;
}

/* After sample k: the lanes it made opaque leave live, k noted for the waste. */
static inline __attribute__((always_inline)) void ivec_die(const lc_kframe *f, ivec *q, int k)
{
    vmask died = vm_andnot(q->live, vf_lt(q->col.a, vf_set1(f->alpha_stop)));
    q->kdie = vi_select(died, vi_set1(k), q->kdie);
    q->live = vm_andnot(q->live, died);
}

/* The vector's colour back, its samples counted and its waste: the terms
 * deposited behind the samples where its lanes became opaque were for
 * nothing, estimated as the vector's terms times the share of its lanes'
 * samples in the pass behind them (each lane's own opacity, not only the
 * whole vector's: commit d036bb2). The lane samples behind are a sum of small
 * integers, exact in any order. */
static inline __attribute__((always_inline)) float ivec_store(const cscratch *c, int v, int kp, ivec *q,
                                                              lc_kstats *st)
{
    st->samples += q->nsamp;
    float waste = 0.0f;
    float dead = vf_reduce_add_masked(vm_andnot(q->live0, q->live),
                                      vi_to_vf(vi_max(vi_sub(q->klp, q->kdie), vi_set1(0))));
    if (dead > 0.0f) {
        vint kfp = vi_max(q->kf, vi_set1(kp));
        float all = vf_reduce_add_masked(q->live0,
                                         vi_to_vf(vi_max(vi_sub(vi_add(q->klp, vi_set1(1)), kfp), vi_set1(0))));
        if (all > 0.0f) waste = (float)c->touched[v] * dead / all;
    }
    vf_store(c->cr + q->o, q->col.r), vf_store(c->cg + q->o, q->col.g);
    vf_store(c->cb + q->o, q->col.b), vf_store(c->ca + q->o, q->col.a);
    return waste;
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
        if (vm_none(vf_le(vf_load(c->w0 + o), vf_load(c->w1 + o)))) continue;
        /* no particle reached these rays in this pass: every sample is the bias (0
           for particles) and, with tau(bias) = 0, blends to exactly nothing */
        if (skip && !c->touched[v]) continue;
        vray r;
        r.dx = vf_load(c->dx + o), r.dy = vf_load(c->dy + o), r.dz = vf_load(c->dz + o);
        /* origins are read by iso only; set otherwise so that GCC at -O1/-O2 (the sanitizer
           builds) sees no use before definition */
        if (mode == LC_KMODE_ISO) r.ox = vf_load(c->ox + o), r.oy = vf_load(c->oy + o), r.oz = vf_load(c->oz + o);
        else r.ox = r.oy = r.oz = vf_set1(0.0f);
        ivec q;
        ivec_load(c, v, kend, &q);
        for (int k = kp; k <= kend; k++) {
            vmask m = ivec_mask(&q, k);
            if (vm_none(m)) continue;
            for (int fi = 0; fi < nf; fi++) {
                const float *p = c->buf + (((size_t)fi * (size_t)K + (size_t)(k - kp)) * (size_t)comps) *
                                             (size_t)rays + (size_t)o;
                vfloat phi = vf_load(p);
                if (skip && vm_none(vm_and(m, vf_ne(phi, vbias)))) continue;
                vgrad gr;
                if (comps == 4) gr.x = vf_load(p + rays), gr.y = vf_load(p + 2 * rays), gr.z = vf_load(p + 3 * rays);
                mode_sample_as(f, mode, fi, &q.col, m, phi, comps == 4 ? &gr : NULL, &r, NULL, vi_set1(k),
                               vf_set1((float)k * f->dt), probe);
            }
            ivec_die(f, &q, k);
            if (vm_none(q.live)) break;
        }
        waste += ivec_store(c, v, kp, &q, st);
    }
    return waste;
}

/* Sample k (buffer row p) of one vector, as integrate_buffer takes it (one
 * field, no gradient, dvr or mip). */
static inline __attribute__((always_inline)) void ivec_sample(const lc_kframe *f, int mode, int skip, vfloat vbias,
                                                              const float *p, int k, ivec *q)
{
    vmask m = ivec_mask(q, k);
    if (vm_none(m)) return;
    vfloat phi = vf_load(p + q->o);
    if (!skip || vm_any(vm_and(m, vf_ne(phi, vbias)))) {
        vray r; /* unused by dvr and mip */
        r.dx = r.dy = r.dz = r.ox = r.oy = r.oz = vf_zero();
        mode_sample_as(f, mode, 0, &q->col, m, phi, NULL, &r, NULL, vi_set1(k), vf_set1((float)k * f->dt), NULL);
    }
    ivec_die(f, q, k);
}

/* integrate_buffer for one field without gradient in dvr or mip, two ray
 * vectors at a time: each sample's blend waits for the previous sample's
 * opacity (the live lanes), so one vector's samples form a chain; two
 * independent chains interleave (commit 3dea72f). Each vector's samples, in
 * order, and the waste summed in vector order: the same bits and counts. */
static inline __attribute__((always_inline)) float integrate_two(const lc_kparticles *s, const lc_kframe *f,
                                                                 int mode, const cscratch *c, int nv, int kp,
                                                                 int kend, lc_kstats *st)
{
    const int rays = buf_stride(nv);
    const int skip = skip_base(s, f);
    const vfloat vbias = vf_set1(s->bias);
    float waste = 0.0f;
    int v = 0;
    for (;;) {
        int va = -1, vb = -1;
        for (; v < nv && vb < 0; v++) {
            int o = v * LC_W;
            if (vm_none(vf_le(vf_load(c->w0 + o), vf_load(c->w1 + o)))) continue;
            if (skip && !c->touched[v]) continue;
            if (va < 0) va = v;
            else vb = v;
        }
        if (va < 0) break;
        ivec a, b;
        ivec_load(c, va, kend, &a);
        if (vb < 0) {
            for (int k = kp; k <= kend && vm_any(a.live); k++)
                ivec_sample(f, mode, skip, vbias, c->buf + (size_t)(k - kp) * (size_t)rays, k, &a);
            waste += ivec_store(c, va, kp, &a, st);
            break;
        }
        ivec_load(c, vb, kend, &b);
        for (int k = kp; k <= kend && (vm_any(a.live) || vm_any(b.live)); k++) {
            const float *p = c->buf + (size_t)(k - kp) * (size_t)rays;
            ivec_sample(f, mode, skip, vbias, p, k, &a);
            ivec_sample(f, mode, skip, vbias, p, k, &b);
        }
        waste += ivec_store(c, va, kp, &a, st);
        waste += ivec_store(c, vb, kp, &b, st);
    }
    return waste;
}

/* integrate_buffer with one field and no gradient (every dvr frame without
 * shading on one field) compiled apart from the general case, in a function
 * of its own: inlined into coherent_tile with nf and comps unknown, its
 * sample loop kept k and its counters in memory (commit 2da8dad). */
static __attribute__((noinline)) float integrate_pass(const lc_kparticles *s, const lc_kframe *f, int mode,
                                                      const cscratch *c, int nv, int K, int nf, int kp, int kend,
                                                      int comps, const mprobe *probe, lc_kstats *st)
{
    if (nf == 1 && comps == 1 && mode != LC_KMODE_ISO) return integrate_two(s, f, mode, c, nv, kp, kend, st);
    if (nf == 1 && comps == 1) return integrate_buffer(s, f, mode, c, nv, K, 1, kp, kend, 1, probe, st);
    return integrate_buffer(s, f, mode, c, nv, K, nf, kp, kend, comps, probe, st);
}

#endif
