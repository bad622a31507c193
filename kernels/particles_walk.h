/* The coherent particle kernel's BVH walk and deposits (Knoll et al. 2014,
 * Listing 2, lines 3-10), included once by kernels/particles_coherent.c
 * after its scratch layout (cscratch, gent): the exp-free Gaussian along a
 * ray vector (deposit_samples), a leaf particle's deposit for the walk per
 * pass (deposit) and from a group list entry (deposit_entry), the walk that
 * deposits or lists leaves (walk_group), and the list's deposit per pass. */
#ifndef LC_PARTICLES_WALK_H
#define LC_PARTICLES_WALK_H

/* The host's table of c_i = pgauss_c(nir_i, dt) (kparticles.h cstep), or
 * NULL when there is none for this dt: then each particle computes it. */
static inline const float *particle_cstep(const lc_kparticles *s, float dt)
{
    return s->cstep && s->cstep_dt == dt ? s->cstep : NULL;
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
static inline __attribute__((always_inline)) uint64_t deposit_samples(const pgauss_consts *gc, const float *kdt,
                                                                       float *fb, int rays,
                                                                       int o, int comps, int kp, int ka, int kb,
                                                                       float r2s, float gscale, vfloat tc,
                                                                       vfloat d2, vfloat ocx, vfloat ocy, vfloat ocz,
                                                                       vfloat dx, vfloat dy, vfloat dz, vmask m)
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
        /* (float)k * dt from the pass's table (k >= kp - PG_ANCHOR here) */
        const float *kd = kdt + (PG_ANCHOR - kp);
        vfloat u = vf_sub(vf_set1(kd[k0]), tc);
        vfloat ue = vf_sub(vf_set1(kd[k1]), tc);
        /* the block's sample nearest to the centre's foot (u0 or ue, or 0
           when the foot lies within the block: then conservatively d2 alone)
           takes the sample's own support test: none passes, no term lands */
        vfloat un = vf_max(u, vf_min(vf_zero(), ue));
        if (vm_none(vm_and(m, vf_lt(vf_madd(un, un, d2), rr)))) continue;
        vfloat g, q;
        pgauss_anchor(gc, d2, u, m, &g, &q);
        for (int k = k0; k <= k1; k++) {
            if (k < ka) { /* before this pass or chord: stepped, not stored */
                pgauss_step(gc, &g, &q);
                u = vf_sub(vf_set1(kd[k + 1]), tc);
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
            u = vf_sub(vf_set1(kd[k + 1]), tc);
        }
    }
    return evals;
}

/* deposit_samples for an SPH kernel (particles_sph.h): the same samples and
 * support test, each term evaluated directly (a compact polynomial has no
 * ratio recurrence); samples where no lane of m lies inside add nothing. */
static inline __attribute__((always_inline)) uint64_t deposit_samples_sph(int kernel, const sph_consts *sc,
                                                                           const float *kdt, float *fb, int rays,
                                                                           int o, int comps, int kp, int ka, int kb,
                                                                           float r2s, vfloat tc, vfloat d2,
                                                                           vfloat ocx, vfloat ocy, vfloat ocz,
                                                                           vfloat dx, vfloat dy, vfloat dz, vmask m)
{
    uint64_t evals = 0;
    vfloat qx = vf_fnma(tc, dx, ocx), qy = vf_fnma(tc, dy, ocy), qz = vf_fnma(tc, dz, ocz);
    vfloat rr = vf_set1(r2s);
    const float *kd = kdt + (PG_ANCHOR - kp);
    for (int k = ka; k <= kb; k++) {
        vfloat u = vf_sub(vf_set1(kd[k]), tc);
        vfloat a = vf_madd(u, u, d2);
        vmask in = vm_and(m, vf_lt(a, rr));
        if (vm_none(in)) continue;
        evals += (uint64_t)vm_popcnt(in);
        vfloat gs = vf_zero();
        vfloat phi = sph_term(kernel, sc, a, in, comps == 4 ? &gs : NULL);
        float *row = fb + (size_t)(k - kp) * (size_t)comps * (size_t)rays + o;
        vf_store(row, vf_add(vf_load(row), phi));
        if (comps == 4) {
            vfloat ex = vf_fms(u, dx, qx), ey = vf_fms(u, dy, qy), ez = vf_fms(u, dz, qz);
            vf_store(row + rays, vf_fma(ex, gs, vf_load(row + rays)));
            vf_store(row + 2 * rays, vf_fma(ey, gs, vf_load(row + 2 * rays)));
            vf_store(row + 3 * rays, vf_fma(ez, gs, vf_load(row + 3 * rays)));
        }
    }
    return evals;
}

/* Leaf particle i adds its Gaussian (and gradient) to every buffered sample
 * of the group it overlaps (Listing 2, lines 6-8), on the vectors of vbits
 * (bit v >> vshift): the walk per pass. sph (a constant): its SPH kernel
 * instead (deposit_samples_sph). */
static inline __attribute__((always_inline)) void deposit_as(const lc_kparticles *s, const cscratch *c, int nv,
                                                              int kp, int kend, float dt, int comps, int32_t i,
                                                              float cstep, uint64_t vbits, int vshift, lc_kstats *st,
                                                              int sph)
{
    float cx = s->px[i], cy = s->py[i], cz = s->pz[i];
    float rs = s->sigma * s->r[i], r2s = rs * rs, nir = s->neg_inv_2r2[i], kk = s->kappa * s->k[i];
    float x2 = r2s * 1.001f + 1e-12f;
    int rays = buf_stride(nv);
    int K = c->K;
    float *fb = c->buf + (size_t)s->field[i] * (size_t)K * (size_t)comps * (size_t)rays;
    float gscale = 2.0f * nir; /* grad phi_i = -(p - c) / r^2 phi_i */
    pgauss_consts gc = pgauss_consts_make(nir, kk, dt, cstep);
    sph_consts sc = {0.0f, 0.0f};
    if (sph) sc = sph_consts_make(s->r[i], kk, s->knorm); /* the Gaussian computes none of it */
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
        uint64_t e = sph ? deposit_samples_sph(s->kernel, &sc, c->kdt, fb, rays, o, comps, kp, ka, kb, r2s, tc, d2,
                                               ocx, ocy, ocz, dx, dy, dz, m)
                         : deposit_samples(&gc, c->kdt, fb, rays, o, comps, kp, ka, kb, r2s, gscale, tc, d2, ocx, ocy,
                                           ocz, dx, dy, dz, m);
        c->touched[v] += (uint32_t)e;
        st->kernel_evals += e;
    }
}

/* The Gaussian's deposit compiles as it did before the SPH kernels; theirs
 * is a function of its own. */
static inline void deposit(const lc_kparticles *s, const cscratch *c, int nv, int kp, int kend, float dt, int comps,
                           int32_t i, float cstep, uint64_t vbits, int vshift, lc_kstats *st)
{
    deposit_as(s, c, nv, kp, kend, dt, comps, i, cstep, vbits, vshift, st, 0);
}

static __attribute__((noinline)) void deposit_sph(const lc_kparticles *s, const cscratch *c, int nv, int kp, int kend,
                                                  float dt, int comps, int32_t i, uint64_t vbits, int vshift,
                                                  lc_kstats *st)
{
    deposit_as(s, c, nv, kp, kend, dt, comps, i, 0.0f, vbits, vshift, st, 1);
}

/* Per-vector cones (issue 8; docs/bench/particles.md "Cone pre-test"): a cheap pre-test of a particle
 * against the vectors of a list entry, LC_W vectors per vector operation,
 * before the per-vector support test (tc, d_perp^2 on every lane).
 *
 * With rays from the eye, each lane's support test passes when its line
 * (through the eye, direction d) comes within sqrt(x2) of the centre: d2 =
 * |oc - (oc.d) d|^2 <= x2. The valid lanes of a vector lie in a cone around
 * an axis a (unit, through the eye) of half-angle theta, and a point at oc
 * whose distance from the axis's line is p, with ta = oc.a, lies at
 * p cos(theta) - |ta| sin(theta) from the nearest line of the (double) cone,
 * so no lane's line comes within R of it unless p <= |ta| T + R S for any
 * T >= tan(theta), S >= sec(theta). vcone_make stores a, T and S per vector
 * (rows of c->vc, VCONE_ROWS x nvq); vcone_bits tests the centre with
 * R = sqrt(x2) grown for the float arithmetic of both tests (the lane's d2
 * errs by a few ulps of |oc| in each component of q: in exact arithmetic a
 * direction of norm s != 1 adds (1 - s^2)^2 (oc.n)^2, so only round-off can
 * make it smaller), and T, S grown by 1e-3 relative and 1e-6 absolute for
 * the cross product's round-off. Conservative: a vector the pre-test drops
 * would have failed the support test on every lane, so the same terms land
 * in the same order (tests/test_particles_cone.c: on = off, memcmp and term
 * counts, every target). */
#define VCONE_MAX_SETS 4

/* The targets that take the pre-test: avx512 and avx2 (their default groups
 * are 16 and 32 vectors). Compiled out elsewhere: sse4's and scalar's
 * default groups have more than VCONE_MAX_SETS x LC_W vectors, and with the
 * code merely present (never run) 1tw7 frames were 1-2% (sse4) and 5-10%
 * (avx512_8) slower, a code generation effect of the bigger list deposit
 * (docs/bench/particles.md "Cone pre-test"). */
#if defined(LC_TARGET_AVX512) || defined(LC_TARGET_AVX2)
#define VCONES 1
#else
#define VCONES 0
#endif

static inline int vcone_on(const lc_kparticles *s, const lc_kframe *f, int nv)
{
#if VCONES
    return !f->cam.ortho && !s->eye_generic && !s->cone_off && nv <= 64 && nv <= VCONE_MAX_SETS * LC_W;
#else
    (void)s, (void)f, (void)nv;
    return 0;
#endif
}

static inline void vcone_make(const cscratch *c, int nv)
{
    const int q = c->nvq;
    float *r = c->vc;
    for (int v = 0; v < q; v++) {
        float ax = 0.0f, ay = 0.0f, az = 0.0f, T = 0.0f, S = 0.0f; /* no valid lane: any centre fails */
        if (v < nv) {
            int o = v * LC_W;
            /* every lane set_windows may make live: kf <= kl + 1 (an empty range kl + 1
               still has a window of zero width, w0 = w1, and the deposit runs on it) */
            vmask valid = vi_lt(vi_load(c->kf + o), vi_add(vi_load(c->kl + o), vi_set1(2)));
            vfloat dx = vf_load(c->dx + o), dy = vf_load(c->dy + o), dz = vf_load(c->dz + o);
            float sx = vf_reduce_add_masked(valid, dx), sy = vf_reduce_add_masked(valid, dy);
            float sz = vf_reduce_add_masked(valid, dz);
            float n = sqrtf(sx * sx + sy * sy + sz * sz);
            if (vm_any(valid) && n > 0.0f) {
                ax = sx / n, ay = sy / n, az = sz / n;
                vfloat vax = vf_set1(ax), vay = vf_set1(ay), vaz = vf_set1(az);
                vfloat cs = vf_madd(vax, dx, vf_madd(vay, dy, vf_mul(vaz, dz)));
                vfloat kx = vf_sub(vf_mul(vay, dz), vf_mul(vaz, dy));
                vfloat ky = vf_sub(vf_mul(vaz, dx), vf_mul(vax, dz));
                vfloat kz = vf_sub(vf_mul(vax, dy), vf_mul(vay, dx));
                vfloat sn2 = vf_madd(kx, kx, vf_madd(ky, ky, vf_mul(kz, kz)));
                float cmin = vf_reduce_min(vf_select(valid, cs, vf_set1(1.0f)));
                float t2 = vf_reduce_max(vf_select(valid, vf_div(sn2, vf_mul(cs, cs)), vf_zero()));
                if (cmin > 0.5f) {
                    T = sqrtf(t2) * 1.001f + 1e-6f;
                    S = sqrtf(1.0f + T * T) * 1.0001f;
                } else { /* a wide cone (no such vector at sane fields of view): always test */
                    T = S = 1e30f;
                }
            }
        }
        r[v] = ax, r[q + v] = ay, r[2 * q + v] = az, r[3 * q + v] = T, r[4 * q + v] = S;
    }
}

/* The vectors among todo (bit v: vector v) whose cones a support of squared
 * radius x2 centred at oc (from the eye) may reach. */
static inline uint64_t vcone_bits(const cscratch *c, uint64_t todo, float ocx, float ocy, float ocz, float x2)
{
    const int q = c->nvq;
    const float *r = c->vc;
    const float rg = (sqrtf(x2) + 1e-5f * (fabsf(ocx) + fabsf(ocy) + fabsf(ocz))) * 1.0001f + 1e-6f;
    const vfloat ox = vf_set1(ocx), oy = vf_set1(ocy), oz = vf_set1(ocz), vr = vf_set1(rg);
    uint64_t bits = 0;
    for (int v = 0; v < q; v += LC_W) {
        if (!((todo >> v) & (((uint64_t)1 << LC_W) - 1))) continue;
        vfloat ax = vf_load(r + v), ay = vf_load(r + q + v), az = vf_load(r + 2 * q + v);
        vfloat ta = vf_madd(ax, ox, vf_madd(ay, oy, vf_mul(az, oz)));
        vfloat px = vf_nmadd(ta, ax, ox), py = vf_nmadd(ta, ay, oy), pz = vf_nmadd(ta, az, oz);
        vfloat p2 = vf_madd(px, px, vf_madd(py, py, vf_mul(pz, pz)));
        vfloat rhs = vf_madd(vf_abs(ta), vf_load(r + 3 * q + v), vf_mul(vr, vf_load(r + 4 * q + v)));
        bits |= (uint64_t)vm_bits(vf_le(p2, vf_mul(rhs, rhs))) << v;
    }
    return todo & bits;
}

/* Does a support of squared radius x2 centred at oc (from the eye) miss the
 * samples ka..kb of every ray from the eye (issue 8; docs/bench/particles.md
 * "Range test from the eye", commit 44bfa95)? A ray
 * eye + t d with |d| = 1 is at distance >= |t - |oc|| from the centre, so
 * its samples inside the support lie within R of |oc|: none of ka..kb does
 * when kd[kb] + R < |oc| or kd[ka] - R > |oc|. R is grown as vcone_bits
 * grows it (the lane test's round-off, a few ulps of |oc| per component of
 * its offsets, and |d| = 1 within a few ulps), and the comparisons of
 * squares by 1e-4 relative, far beyond their own round-off. Conservative: a
 * particle it skips would have added no term in ka..kb on any lane (the
 * list deposit's terms outside a lane's window included), so images and
 * term counts stay as they were (tests/test_particles_range.c). In the work
 * counters of a3daaf0 24-48% of the list deposit's (particle, vector) pairs had no
 * term in their pass (the entry's range spans several passes). */
static inline int eye_range_misses(const float *kd, int ka, int kb, float ox, float oy, float oz, float x2)
{
    float o2 = ox * ox + oy * oy + oz * oz;
    float rg = (sqrtf(x2) + 1e-5f * (fabsf(ox) + fabsf(oy) + fabsf(oz))) * 1.0001f + 1e-6f;
    float tn = kd[kb] + rg, tf = kd[ka] - rg;
    return tn * tn < o2 * 0.9999f || (tf > 0.0f && tf * tf > o2 * 1.0001f);
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
                                                                 uint64_t live, const float *eye, lc_kstats *st,
                                                                 int sph)
{
    float cx = s->px[i], cy = s->py[i], cz = s->pz[i];
    float rs = s->sigma * s->r[i], r2s = rs * rs, nir = s->neg_inv_2r2[i], kk = s->kappa * s->k[i];
    float x2 = r2s * 1.001f + 1e-12f;
    int rays = buf_stride(nv);
    float *fb = c->buf + (size_t)s->field[i] * (size_t)c->K * (size_t)comps * (size_t)rays;
    pgauss_consts gc = pgauss_consts_make(nir, kk, dt, cstep);
    sph_consts sc = {0.0f, 0.0f};
    if (sph) sc = sph_consts_make(s->r[i], kk, s->knorm); /* the Gaussian computes none of it */
    /* vshift 0: the set bits of vbits (the list found the support misses
       the other vectors) among the live vectors, in order */
    uint64_t todo = vshift ? 0 : vbits & live;
    if (eye && eye_range_misses(c->kdt + (PG_ANCHOR - kp), ka, kb, cx - eye[0], cy - eye[1], cz - eye[2], x2))
        return;
#if VCONES
    if (eye && c->vc && todo) todo = vcone_bits(c, todo, cx - eye[0], cy - eye[1], cz - eye[2], x2);
#endif
    for (int v = 0; v < nv; v++) {
        if (!vshift) {
            if (!todo) break;
            v = __builtin_ctzll(todo);
            todo &= todo - 1;
        } else if (!((vbits >> (v >> vshift)) & 1u)) {
            continue;
        }
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
        uint64_t e = sph ? deposit_samples_sph(s->kernel, &sc, c->kdt, fb, rays, o, comps, kp, ka, kb, r2s, tc, d2,
                                               ocx, ocy, ocz, dx, dy, dz, m)
                         : deposit_samples(&gc, c->kdt, fb, rays, o, comps, kp, ka, kb, r2s, 2.0f * nir, tc, d2, ocx,
                                           ocy, ocz, dx, dy, dz, m);
        /* integrate only where some term landed (lanes without a chord in
           their window would otherwise mark it) */
        c->touched[v] += (uint32_t)e;
        st->kernel_evals += e;
    }
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

/* A whole group's rays against a node at once (perspective: every ray
 * starts at the eye), by interval arithmetic over the group: [ix0, ix1] ..
 * hold every ray's inverse direction, [w0min, w1max] every live ray's
 * window. A float product with a fixed factor is monotone in the other, so
 * the products slab_eye forms for any ray lie between those with the
 * interval's ends: en (ex) is at most (at least) any ray's entry (exit) t.
 * When en > ex, or the entry lies beyond every window or the exit before,
 * no ray of the group hits the node: the per-vector test would set no bit.
 * Culling such nodes before it changes nothing but the work (an inner node
 * that misses costs one slab test per vector: 16 with 16x16 groups). */
typedef struct gcull {
    float ix0, ix1, iy0, iy1, iz0, iz1, w0min, w1max;
} gcull;

static inline float fmin2(float a, float b) { return a < b ? a : b; }
static inline float fmax2(float a, float b) { return a > b ? a : b; }

static inline gcull gcull_make(const cscratch *c, int nv)
{
    vfloat x0 = vf_set1(INFINITY), x1 = vf_set1(-INFINITY), y0 = x0, y1 = x1, z0 = x0, z1 = x1;
    vfloat a = x0, b = x1;
    for (int v = 0; v < nv; v++) {
        int o = v * LC_W;
        vfloat ix = vf_load(c->ix + o), iy = vf_load(c->iy + o), iz = vf_load(c->iz + o);
        x0 = vf_min(x0, ix), x1 = vf_max(x1, ix), y0 = vf_min(y0, iy), y1 = vf_max(y1, iy);
        z0 = vf_min(z0, iz), z1 = vf_max(z1, iz);
        vfloat w0 = vf_load(c->w0 + o), w1 = vf_load(c->w1 + o);
        vmask live = vf_le(w0, w1);
        a = vf_min(a, vf_select(live, w0, vf_set1(INFINITY)));
        b = vf_max(b, vf_select(live, w1, vf_set1(-INFINITY)));
    }
    gcull g = {vf_reduce_min(x0), vf_reduce_max(x1), vf_reduce_min(y0), vf_reduce_max(y1),
               vf_reduce_min(z0), vf_reduce_max(z1), vf_reduce_min(a), vf_reduce_max(b)};
    return g;
}

/* Entry and exit bounds on one axis: the slab's differences a <= b (as
 * slab_eye forms them) times the inverse directions' ends. */
static inline void gcull_axis(float a, float b, float i0, float i1, float *en, float *ex)
{
    float p0 = a * i0, p1 = a * i1, p2 = b * i0, p3 = b * i1;
    *en = fmin2(fmin2(p0, p1), fmin2(p2, p3));
    *ex = fmax2(fmax2(p0, p1), fmax2(p2, p3));
}

static inline int gcull_misses(const gcull *q, const lc_kpnode *node, float g, float ex, float ey, float ez)
{
    float nx, xx, ny, xy, nz, xz;
    gcull_axis((node->lo[0] - g) - ex, (node->hi[0] + g) - ex, q->ix0, q->ix1, &nx, &xx);
    gcull_axis((node->lo[1] - g) - ey, (node->hi[1] + g) - ey, q->iy0, q->iy1, &ny, &xy);
    gcull_axis((node->lo[2] - g) - ez, (node->hi[2] + g) - ez, q->iz0, q->iz1, &nz, &xz);
    float en = fmax2(fmax2(nx, ny), nz), xt = fmin2(fmin2(xx, xy), xz);
    return en > xt || en > q->w1max || xt < q->w0min;
}

/* The same bounds per ray vector, tested for LC_W vectors at once (groups
 * of at most VCULL_MAX_SETS x LC_W vectors, and at most 64): rows of c->vq
 * hold each vector's ix0, ix1, iy0, iy1, iz0, iz1 over its lanes and its
 * live lanes' w0min, w1max (a vector without live lanes, or past nv:
 * w0min = +inf, w1max = -inf). vcull_node gives a bit per vector whose rays
 * may hit the node (every vector the slab test hits among them), so the
 * slab tests run only on those. */
#define VCULL_MAX_SETS 4

static inline int vcull_on(int nv) { return nv <= 64 && nv <= VCULL_MAX_SETS * LC_W; }

static inline void vcull_make(const cscratch *c, int nv)
{
    const int q = c->nvq;
    float *r = c->vq;
    for (int v = 0; v < q; v++) {
        if (v >= nv) {
            for (int k = 0; k < 6; k++) r[k * q + v] = 0.0f;
            r[6 * q + v] = INFINITY, r[7 * q + v] = -INFINITY;
            continue;
        }
        int o = v * LC_W;
        vfloat ix = vf_load(c->ix + o), iy = vf_load(c->iy + o), iz = vf_load(c->iz + o);
        vfloat w0 = vf_load(c->w0 + o), w1 = vf_load(c->w1 + o);
        vmask live = vf_le(w0, w1);
        r[v] = vf_reduce_min(ix), r[q + v] = vf_reduce_max(ix);
        r[2 * q + v] = vf_reduce_min(iy), r[3 * q + v] = vf_reduce_max(iy);
        r[4 * q + v] = vf_reduce_min(iz), r[5 * q + v] = vf_reduce_max(iz);
        r[6 * q + v] = vf_reduce_min(vf_select(live, w0, vf_set1(INFINITY)));
        r[7 * q + v] = vf_reduce_max(vf_select(live, w1, vf_set1(-INFINITY)));
    }
}

static inline uint64_t vcull_node(const cscratch *c, const lc_kpnode *node, float g, float ex, float ey, float ez)
{
    const int q = c->nvq;
    const float *r = c->vq;
    const vfloat ax = vf_set1((node->lo[0] - g) - ex), bx = vf_set1((node->hi[0] + g) - ex);
    const vfloat ay = vf_set1((node->lo[1] - g) - ey), by = vf_set1((node->hi[1] + g) - ey);
    const vfloat az = vf_set1((node->lo[2] - g) - ez), bz = vf_set1((node->hi[2] + g) - ez);
    uint64_t bits = 0;
    for (int v = 0; v < q; v += LC_W) {
        vfloat i0 = vf_load(r + v), i1 = vf_load(r + q + v);
        vfloat p0 = vf_mul(ax, i0), p1 = vf_mul(ax, i1), p2 = vf_mul(bx, i0), p3 = vf_mul(bx, i1);
        vfloat en = vf_min(vf_min(p0, p1), vf_min(p2, p3)), xt = vf_max(vf_max(p0, p1), vf_max(p2, p3));
        i0 = vf_load(r + 2 * q + v), i1 = vf_load(r + 3 * q + v);
        p0 = vf_mul(ay, i0), p1 = vf_mul(ay, i1), p2 = vf_mul(by, i0), p3 = vf_mul(by, i1);
        en = vf_max(en, vf_min(vf_min(p0, p1), vf_min(p2, p3)));
        xt = vf_min(xt, vf_max(vf_max(p0, p1), vf_max(p2, p3)));
        i0 = vf_load(r + 4 * q + v), i1 = vf_load(r + 5 * q + v);
        p0 = vf_mul(az, i0), p1 = vf_mul(az, i1), p2 = vf_mul(bz, i0), p3 = vf_mul(bz, i1);
        en = vf_max(en, vf_min(vf_min(p0, p1), vf_min(p2, p3)));
        xt = vf_min(xt, vf_max(vf_max(p0, p1), vf_max(p2, p3)));
        vmask h = vm_and(vf_le(en, xt), vm_and(vf_le(en, vf_load(r + 7 * q + v)), vf_ge(xt, vf_load(r + 6 * q + v))));
        bits |= (uint64_t)vm_bits(h) << v;
    }
    return bits;
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
                                                            lc_kstats *st, int sph)
{
    const float ex = f->cam.eye[0], ey = f->cam.eye[1], ez = f->cam.eye[2];
    int32_t *stack = c->stack;
    int sp = 0, n = 0;
    float cnir = 1.0f, cstep = 0.0f; /* nir < 0: the first particle computes c */
    const float *ctab = particle_cstep(s, dt);
    gcull gq = {0};
    const int vc = persp && vcull_on(nv);
    if (vc) vcull_make(c, nv);
    else if (persp) gq = gcull_make(c, nv);
    stack[sp++] = 0;
    while (sp > 0) {
        int32_t nd = stack[--sp];
        const lc_kpnode *node = &s->nodes[nd];
        float g = grow(s->sigma * s->node_rmax[nd]);
        st->nodes++;
        /* the mode's test on the node's own contribution (dvr: always) */
        float vb = s->kappa * s->node_ksum[nd];
        /* fmin2/fmax2, not fminf/fmaxf (library calls here; vb is never NaN) */
        mnode mn = {fmin2(vb, 0.0f), fmax2(vb, 0.0f), 0, node_clear(s, nd), -INFINITY};
        if (!mode_node_matters(f, &mn)) continue;
        /* the vectors whose rays may hit the node: the slab tests run on those only */
        uint64_t cand = ~(uint64_t)0;
        if (vc) {
            cand = vcull_node(c, node, g, ex, ey, ez);
            if (!cand) continue;
        } else if (persp && gcull_misses(&gq, node, g, ex, ey, ez)) {
            continue;
        }
        /* inner nodes: does any vector's rays reach the grown box; leaves:
           which vectors' (and, listed, over which t) */
        uint64_t bits = 0;
        vfloat lo = vf_set1(INFINITY), hi = vf_set1(-INFINITY);
        for (int v = 0; v < nv; v++) {
            if (vc) { /* the next candidate vector (none left: done) */
                uint64_t rest = cand >> v;
                if (!rest) break;
                v += __builtin_ctzll(rest);
            }
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
            /* c = exp(-dt^2 / r^2): the host's table, or once per radius (neighbours mostly share it) */
            if (sph) {
                deposit_sph(s, c, nv, kp, kend, dt, comps, i, bits, vshift, st);
                continue;
            }
            if (ctab) cstep = ctab[i];
            else if (s->neg_inv_2r2[i] != cnir) cnir = s->neg_inv_2r2[i], cstep = pgauss_c(cnir, dt);
            deposit(s, c, nv, kp, kend, dt, comps, i, cstep, bits, vshift, st);
        }
    }
    return n;
}

/* The walk per pass for the SPH kernels, in a function of its own so the
 * Gaussian's compiles as it did. */
static __attribute__((noinline)) void traverse_pass_sph(const lc_kparticles *s, const lc_kframe *f,
                                                        const cscratch *c, int nv, int vshift, int kp, int kend,
                                                        float dt, int comps, lc_kstats *st)
{
    if (f->cam.ortho || s->eye_generic)
        walk_group(s, f, c, nv, vshift, kp, kend, dt, comps, 0, 0, st, 1);
    else
        walk_group(s, f, c, nv, vshift, kp, kend, dt, comps, 0, 1, st, 1);
}

static __attribute__((noinline)) void traverse_pass(const lc_kparticles *s, const lc_kframe *f, const cscratch *c,
                                                    int nv, int vshift, int kp, int kend, float dt, int comps,
                                                    lc_kstats *st)
{
    if (s->kernel != LC_KSPH_GAUSSIAN)
        traverse_pass_sph(s, f, c, nv, vshift, kp, kend, dt, comps, st);
    else if (f->cam.ortho || s->eye_generic)
        walk_group(s, f, c, nv, vshift, kp, kend, dt, comps, 0, 0, st, 0);
    else
        walk_group(s, f, c, nv, vshift, kp, kend, dt, comps, 0, 1, st, 0);
}

static __attribute__((noinline)) int collect_group(const lc_kparticles *s, const lc_kframe *f, const cscratch *c,
                                                   int nv, int vshift, int kp, int kend, float dt, lc_kstats *st)
{
    return (f->cam.ortho || s->eye_generic) ? walk_group(s, f, c, nv, vshift, kp, kend, dt, 1, 1, 0, st, 0)
                        : walk_group(s, f, c, nv, vshift, kp, kend, dt, 1, 1, 1, st, 0);
}

/* One pass from the group list: deposits the n entries overlapping kp..kend
 * in list order and keeps, in order, those reaching past kend. Returns the
 * entries kept. */
static inline __attribute__((always_inline)) int deposit_list_as(const lc_kparticles *s, const cscratch *c, int nv,
                                                                  int vshift, int n, int kp, int kend, float dt,
                                                                  int comps, const float *eye, lc_kstats *st, int sph)
{
    float cnir = 1.0f, cstep = 0.0f;
    const float *ctab = particle_cstep(s, dt);
    int kept = 0;
    uint64_t live = 0; /* vectors with a live ray (nv <= 64; unused otherwise) */
    for (int v = 0; v < nv && v < 64; v++)
        live |= (uint64_t)vm_any(vf_le(vf_load(c->w0 + v * LC_W), vf_load(c->w1 + v * LC_W))) << v;
    for (int j = 0; j < n; j++) {
        gent e = c->list[j];
        if (e.ka <= kend && e.kb >= kp) {
            for (int32_t i = e.first; i < e.first + e.count; i++) {
                if (sph) cstep = 0.0f; /* no recurrence */
                else if (ctab) cstep = ctab[i];
                else if (s->neg_inv_2r2[i] != cnir) cnir = s->neg_inv_2r2[i], cstep = pgauss_c(cnir, dt);
                deposit_entry(s, c, nv, kp, e.ka > kp ? e.ka : kp, e.kb < kend ? e.kb : kend, dt, comps, i, cstep,
                              e.vbits, vshift, live, eye, st, sph);
            }
        }
        if (e.kb > kend) c->list[kept++] = e;
    }
    return kept;
}

/* The above, with the eye as every ray's origin (perspective) or not, and
 * with the gradient (comps 4) or without (1) as constants: the sample loop
 * then holds no test of comps and no gradient offsets it does not use. */
static inline __attribute__((always_inline)) int deposit_list_any(const lc_kparticles *s, const lc_kframe *f,
                                                                   const cscratch *c, int nv, int vshift, int n,
                                                                   int kp, int kend, float dt, int comps,
                                                                   lc_kstats *st, int sph)
{
    int generic = f->cam.ortho || s->eye_generic;
    if (comps == 4)
        return generic ? deposit_list_as(s, c, nv, vshift, n, kp, kend, dt, 4, NULL, st, sph)
                       : deposit_list_as(s, c, nv, vshift, n, kp, kend, dt, 4, f->cam.eye, st, sph);
    return generic ? deposit_list_as(s, c, nv, vshift, n, kp, kend, dt, 1, NULL, st, sph)
                   : deposit_list_as(s, c, nv, vshift, n, kp, kend, dt, 1, f->cam.eye, st, sph);
}

/* The SPH kernels' list deposits, in a function of their own (the Gaussian's compile as they did). */
static __attribute__((noinline)) int deposit_list_sph(const lc_kparticles *s, const lc_kframe *f, const cscratch *c,
                                                      int nv, int vshift, int n, int kp, int kend, float dt,
                                                      int comps, lc_kstats *st)
{
    return deposit_list_any(s, f, c, nv, vshift, n, kp, kend, dt, comps, st, 1);
}

static __attribute__((noinline)) int deposit_list(const lc_kparticles *s, const lc_kframe *f, const cscratch *c,
                                                  int nv, int vshift, int n, int kp, int kend, float dt, int comps,
                                                  lc_kstats *st)
{
    if (s->kernel != LC_KSPH_GAUSSIAN) return deposit_list_sph(s, f, c, nv, vshift, n, kp, kend, dt, comps, st);
    return deposit_list_any(s, f, c, nv, vshift, n, kp, kend, dt, comps, st, 0);
}

#endif
