/* Particle volume rendering (Knoll et al. 2014), compiled once per target.
 *
 * coherent: Listings 2 and 3. A group of rays (8x8 by default, or one
 *   lane-width packet) walks the BVH with a uniform stack; every leaf particle
 *   adds its Gaussian to every buffered sample it overlaps (the uniform sample
 *   range is the min/max over the packet's lanes); then the buffer of K
 *   samples per ray is integrated front to back. Multi-pass over the ray
 *   segment, stopping when every ray of the group reached alpha_stop.
 * direct: the paper's baseline. Per sample, gather every overlapping particle
 *   through the BVH, then classify and blend.
 * Both evaluate the field with the same arithmetic (sample_d2, gaussian), so they
 * differ only by summation order. */
#include <math.h>
#include "mode.h"
#include "shared/kparticles.h"
#include "shared/ktable.h"
#include "kernels.h"

#define MAX_GROUP_RAYS 4096

/* ---------------------------------------------------------------- shared */

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

/* Offset of p from particle centre c and the truncation test d2 < R2 = (sigma r)^2. */
static inline vfloat sample_d2(vfloat px, vfloat py, vfloat pz, float cx, float cy, float cz, float r2s, vmask m,
                               vmask *inside, vfloat *ex, vfloat *ey, vfloat *ez)
{
    *ex = vf_sub(px, vf_set1(cx));
    *ey = vf_sub(py, vf_set1(cy));
    *ez = vf_sub(pz, vf_set1(cz));
    vfloat d2 = vf_fma(*ex, *ex, vf_fma(*ey, *ey, vf_mul(*ez, *ez)));
    *inside = vm_and(m, vf_lt(d2, vf_set1(r2s)));
    return d2;
}

/* kappa k_i exp(-d2 / (2 r_i^2)) (paper eq. 2), zero outside the support. */
static inline vfloat gaussian(vfloat d2, float nir, float kk, vmask inside)
{
    return vf_select(inside, vf_mul(vf_set1(kk), vf_exp(vf_mul(d2, vf_set1(nir)))), vf_zero());
}

/* Squared distance of a centre from a ray: |oc - tc d|^2 with tc = oc.d. Not
 * |oc|^2 - tc^2, which cancels catastrophically for a distant eye (|oc|^2 ~ 1e4
 * against R^2 ~ 1) and wrongly drops rays that do pass within the support. */
static inline vfloat perp2(vfloat ocx, vfloat ocy, vfloat ocz, vfloat dx, vfloat dy, vfloat dz, vfloat tc)
{
    vfloat qx = vf_fnma(tc, dx, ocx), qy = vf_fnma(tc, dy, ocy), qz = vf_fnma(tc, dz, ocz);
    return vf_fma(qx, qx, vf_fma(qy, qy, vf_mul(qz, qz)));
}

/* Boxes grow a little more than sigma * rmax so float round-off in the slab
 * test never drops a sample that lies within the truncation radius. */
static inline float grow(float sigma_r) { return sigma_r * 1.0001f + 1e-6f; }

/* Opaque spheres (paper §5.2): nearest hit of radius scale * r_i through the
 * same BVH, shaded with the particle's TF colour and the headlight. */
static void trace_spheres(const lc_kparticles *s, const lc_kframe *f, const vray *ray, vmask valid, int32_t *stack,
                          vfloat *thit, vcolor *surf, lc_kstats *st)
{
    vfloat inf = vf_set1(3.0e38f);
    vfloat best = inf, nx = vf_zero(), ny = vf_zero(), nz = vf_zero(), sr = vf_zero(), sg = vf_zero(), sb = vf_zero();
    vfloat ix = dvr_inv_dir(ray->dx), iy = dvr_inv_dir(ray->dy), iz = dvr_inv_dir(ray->dz);
    float scale = s->sphere_scale;
    int sp = 0;
    stack[sp++] = 0;
    while (sp > 0) {
        int32_t n = stack[--sp];
        const lc_kpnode *node = &s->nodes[n];
        vfloat tn, tf;
        dvr_slab(ray->ox, ray->oy, ray->oz, ix, iy, iz, node->lo, node->hi, grow(scale * s->node_rmax[n]), &tn, &tf);
        vmask hit = vm_and(valid, vm_and(vf_le(vf_max(tn, vf_zero()), tf), vf_lt(tn, best)));
        st->nodes++;
        if (vm_none(hit)) continue;
        if (node->count == 0) {
            stack[sp++] = node->first;
            stack[sp++] = node->first + 1;
            continue;
        }
        st->leaves++;
        for (int32_t i = node->first; i < node->first + node->count; i++) {
            float rr = scale * s->r[i];
            vfloat ocx = vf_sub(vf_set1(s->px[i]), ray->ox), ocy = vf_sub(vf_set1(s->py[i]), ray->oy),
                   ocz = vf_sub(vf_set1(s->pz[i]), ray->oz);
            vfloat tc = vf_fma(ocx, ray->dx, vf_fma(ocy, ray->dy, vf_mul(ocz, ray->dz)));
            vfloat d2 = perp2(ocx, ocy, ocz, ray->dx, ray->dy, ray->dz, tc);
            vfloat h2 = vf_sub(vf_set1(rr * rr), d2);
            vmask m = vm_and(hit, vf_ge(h2, vf_zero()));
            if (vm_none(m)) continue;
            vfloat h = vf_sqrt(vf_max(h2, vf_zero()));
            vfloat t = vf_sub(tc, h);
            t = vf_select(vf_gt(t, vf_zero()), t, vf_add(tc, h)); /* eye inside: the far side */
            m = vm_and(m, vm_and(vf_gt(t, vf_zero()), vf_lt(t, best)));
            if (vm_none(m)) continue;
            best = vf_select(m, t, best);
            vfloat inv = vf_set1(1.0f / rr);
            nx = vf_select(m, vf_mul(vf_fms(ray->dx, t, ocx), inv), nx);
            ny = vf_select(m, vf_mul(vf_fms(ray->dy, t, ocy), inv), ny);
            nz = vf_select(m, vf_mul(vf_fms(ray->dz, t, ocz), inv), nz);
            vfloat r, g, b, tau;
            dvr_classify(&f->tf[s->field[i]], vf_set1(s->kappa * s->k[i]), &r, &g, &b, &tau);
            sr = vf_select(m, r, sr), sg = vf_select(m, g, sg), sb = vf_select(m, b, sb);
        }
    }
    vmask hit = vf_lt(best, inf);
    /* diffuse (+ specular for phong) with the headlight: n.l = -n.dir */
    vfloat ndl = vf_abs(vf_fma(nx, ray->dx, vf_fma(ny, ray->dy, vf_mul(nz, ray->dz))));
    vfloat k = vf_fma(vf_set1(f->kd), ndl, vf_set1(f->ka));
    vfloat spec = f->shade == LC_KSHADE_PHONG ? vf_mul(vf_set1(f->ks), vf_powi(ndl, f->phong_exp)) : vf_zero();
    surf->r = vf_select(hit, vf_fma(sr, k, spec), vf_zero());
    surf->g = vf_select(hit, vf_fma(sg, k, spec), vf_zero());
    surf->b = vf_select(hit, vf_fma(sb, k, spec), vf_zero());
    surf->a = vf_select(hit, vf_set1(1.0f), vf_zero());
    *thit = best;
}

/* Rays, lattice range and (with spheres) the opaque hit for one vector of the
 * group: the ray, its lattice range [kf, kl] (empty for rays outside the tile
 * or the data) and the surface colour to composite behind the volume. */
static inline void setup_vector(const lc_kparticles *s, const lc_kframe *f, const lc_ktile *t, int x, int y,
                                int32_t *stack, vray *ray, vint *kf, vint *kl, vcolor *surf, lc_kstats *st)
{
    vint px, py;
    dvr_packet_pixels(x, y, &px, &py);
    vmask valid = vm_and(vi_lt(px, vi_set1(t->x1)), vi_lt(py, vi_set1(t->y1)));
    *ray = dvr_camera_rays(&f->cam, px, py);
    vfloat t0, t1;
    dvr_clip_box(ray, s->lo, s->hi, &t0, &t1);
    valid = vm_and(valid, vf_le(t0, t1));
    dvr_lattice(vf_select(valid, t0, vf_set1(1.0f)), vf_select(valid, t1, vf_set1(-1.0f)), f->dt, kf, kl);
    surf->r = surf->g = surf->b = surf->a = vf_zero();
    if (s->sphere_scale > 0.0f && s->nnodes > 0 && vm_any(valid)) {
        vfloat thit;
        trace_spheres(s, f, ray, valid, stack, &thit, surf, st);
        /* only samples strictly in front of the surface: k dt < t_hit */
        vfloat kh = vf_floor(vf_div(thit, vf_set1(f->dt)));
        kh = vf_select(vf_lt(vf_mul(kh, vf_set1(f->dt)), thit), kh, vf_sub(kh, vf_set1(1.0f)));
        vmask h = vf_gt(surf->a, vf_zero());
        *kl = vi_select(h, vi_min(*kl, vf_to_vi(vf_min(kh, vf_set1(LC_KLATTICE_MAX)))), *kl);
    }
    st->rays += (uint64_t)vm_popcnt(valid);
}

/* Finishes the rays in the mode, composites the opaque surface behind them
 * and writes the pixels. */
static inline void finish_vector(const lc_kframe *f, const lc_ktile *t, int x, int y, vcolor *c, const vcolor *surf)
{
    vint px, py;
    dvr_packet_pixels(x, y, &px, &py);
    mode_finish(f, c);
    vfloat w = vf_sub(vf_set1(1.0f), c->a);
    c->r = vf_fma(w, surf->r, c->r);
    c->g = vf_fma(w, surf->g, c->g);
    c->b = vf_fma(w, surf->b, c->b);
    c->a = vf_fma(w, surf->a, c->a);
    dvr_store(t, px, py, c);
}

/* ---------------------------------------------------------------- coherent */

/* Scratch of one worker: ray arrays for a group, the sample buffer, the stack. */
typedef struct cscratch {
    float *ox, *oy, *oz, *dx, *dy, *dz, *ix, *iy, *iz; /* rays */
    float *w0, *w1;                                    /* this pass's t window per ray (w0 > w1: inactive) */
    int32_t *kf, *kl;
    float *cr, *cg, *cb, *ca;                          /* accumulated colour */
    float *sr, *sg, *sb, *sa;                          /* opaque surface */
    float *buf;                                        /* [field][row][comp][ray] */
    int32_t *touched;                                  /* per vector: deposits this pass */
    int32_t *stack;
} cscratch;

static uint64_t align64(uint64_t b) { return (b + 63) & ~(uint64_t)63; }

static uint64_t coherent_layout(const lc_kparticles *s, const lc_kframe *f, unsigned char *base, cscratch *c)
{
    pgroup g = group_dims(f);
    uint64_t rays = (uint64_t)g.nv * LC_W;
    uint64_t comps = f->shade != LC_KSHADE_NONE ? 4 : 1;
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
    off += align64((uint64_t)(s->nfields > 0 ? s->nfields : 1) * (uint64_t)s->buffer_k * comps * rays * 4);
    if (base) c->touched = (int32_t *)(base + off);
    off += align64((uint64_t)g.nv * 4);
    if (base) c->stack = (int32_t *)(base + off);
    off += align64((uint64_t)(s->depth + 4) * 4);
    return off;
}

static uint64_t particles_scratch_bytes(const void *scene, const lc_kframe *f)
{
    cscratch c;
    return coherent_layout(scene, f, NULL, &c);
}

/* Leaf particle i adds its Gaussian (and gradient) to every buffered sample
 * of the group it overlaps (Listing 2, lines 6-8). */
static inline void deposit(const lc_kparticles *s, const cscratch *c, int nv, int kp, int kend, float dt, int comps,
                           int32_t i, lc_kstats *st)
{
    float cx = s->px[i], cy = s->py[i], cz = s->pz[i];
    float rs = s->sigma * s->r[i], r2s = rs * rs, nir = s->neg_inv_2r2[i], kk = s->kappa * s->k[i];
    int rays = nv * LC_W;
    int K = s->buffer_k;
    float *fb = c->buf + (size_t)s->field[i] * (size_t)K * (size_t)comps * (size_t)rays;
    float gscale = 2.0f * nir; /* grad phi_i = -(p - c) / r^2 phi_i */
    for (int v = 0; v < nv; v++) {
        int o = v * LC_W;
        vfloat w0 = vf_load(c->w0 + o), w1 = vf_load(c->w1 + o);
        vmask m = vf_le(w0, w1);
        if (vm_none(m)) continue;
        vfloat ox = vf_load(c->ox + o), oy = vf_load(c->oy + o), oz = vf_load(c->oz + o);
        vfloat dx = vf_load(c->dx + o), dy = vf_load(c->dy + o), dz = vf_load(c->dz + o);
        vfloat ocx = vf_sub(vf_set1(cx), ox), ocy = vf_sub(vf_set1(cy), oy), ocz = vf_sub(vf_set1(cz), oz);
        vfloat tc = vf_fma(ocx, dx, vf_fma(ocy, dy, vf_mul(ocz, dz)));
        vfloat d2 = perp2(ocx, ocy, ocz, dx, dy, dz, tc);
        /* conservative chord: the per-sample test below is the exact one */
        vfloat h2 = vf_sub(vf_set1(r2s * 1.001f + 1e-12f), d2);
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
        c->touched[v] = 1;
        uint64_t evals = 0;
        /* branch-free: [ka, kb] is the union of the lanes' chords, so almost every
           step has active lanes and a data-dependent branch would mispredict at
           both ends of every chord */
        for (int k = ka; k <= kb; k++) {
            vfloat t = vf_set1((float)k * dt);
            vfloat px = vf_fma(dx, t, ox), py = vf_fma(dy, t, oy), pz = vf_fma(dz, t, oz);
            vmask in;
            vfloat ex, ey, ez;
            vfloat pd2 = sample_d2(px, py, pz, cx, cy, cz, r2s, m, &in, &ex, &ey, &ez);
            evals += (uint64_t)vm_popcnt(in);
            vfloat phi = gaussian(pd2, nir, kk, in);
            float *row = fb + (size_t)(k - kp) * (size_t)comps * (size_t)rays + o;
            vf_store(row, vf_add(vf_load(row), phi));
            if (comps == 4) {
                vfloat gp = vf_mul(phi, vf_set1(gscale));
                vf_store(row + rays, vf_fma(ex, gp, vf_load(row + rays)));
                vf_store(row + 2 * rays, vf_fma(ey, gp, vf_load(row + 2 * rays)));
                vf_store(row + 3 * rays, vf_fma(ez, gp, vf_load(row + 3 * rays)));
            }
        }
        st->kernel_evals += evals;
    }
}

/* Listing 2, lines 3-10: coherent traversal filling the buffer for samples
 * kp..kend. Node and stack are uniform, rays varying. */
static void traverse_pass(const lc_kparticles *s, const lc_kframe *f, const cscratch *c, int nv, int kp, int kend,
                          float dt, int comps, lc_kstats *st)
{
    int32_t *stack = c->stack;
    int sp = 0;
    stack[sp++] = 0;
    while (sp > 0) {
        int32_t n = stack[--sp];
        const lc_kpnode *node = &s->nodes[n];
        float g = grow(s->sigma * s->node_rmax[n]);
        st->nodes++;
        /* the mode's test on the node's own contribution (dvr: always) */
        float vb = s->kappa * s->node_ksum[n];
        mnode mn = {fminf(vb, 0.0f), fmaxf(vb, 0.0f), 0, 0, -INFINITY};
        if (!mode_node_matters(f, &mn)) continue;
        int hit = 0;
        for (int v = 0; v < nv && !hit; v++) {
            int o = v * LC_W;
            vfloat w0 = vf_load(c->w0 + o), w1 = vf_load(c->w1 + o);
            vfloat tn, tf;
            dvr_slab(vf_load(c->ox + o), vf_load(c->oy + o), vf_load(c->oz + o), vf_load(c->ix + o), vf_load(c->iy + o),
                 vf_load(c->iz + o), node->lo, node->hi, g, &tn, &tf);
            hit = vm_any(vf_le(vf_max(tn, w0), vf_min(tf, w1)));
        }
        if (!hit) continue;
        if (node->count == 0) {
            stack[sp++] = node->first + 1;
            stack[sp++] = node->first;
            continue;
        }
        st->leaves++;
        for (int32_t i = node->first; i < node->first + node->count; i++) deposit(s, c, nv, kp, kend, dt, comps, i, st);
    }
}

/* Listing 2, lines 11-13: the buffered samples kp..kend of every ray of the
 * group, front to back through the mode (a constant, so each mode gets its
 * own loop). */
static inline __attribute__((always_inline)) void integrate_buffer(const lc_kframe *f, int mode, const cscratch *c,
                                                                   int nv, int K, int nf, int kp, int kend, int comps,
                                                                   lc_kstats *st)
{
    const int rays = nv * LC_W;
    for (int v = 0; v < nv; v++) {
        int o = v * LC_W;
        vmask live = vf_le(vf_load(c->w0 + o), vf_load(c->w1 + o));
        if (vm_none(live)) continue;
        /* no particle reached these rays in this pass: every sample is 0 and, with
           tau(0) = 0, blends to exactly nothing */
        if (f->zero_transparent && !c->touched[v]) continue;
        vray r;
        r.dx = vf_load(c->dx + o), r.dy = vf_load(c->dy + o), r.dz = vf_load(c->dz + o);
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
                if (f->zero_transparent && vm_none(vm_and(m, vf_ne(phi, vf_zero())))) continue;
                vgrad gr;
                if (comps == 4) gr.x = vf_load(p + rays), gr.y = vf_load(p + 2 * rays), gr.z = vf_load(p + 3 * rays);
                mode_sample_as(f, mode, fi, &col, m, phi, comps == 4 ? &gr : NULL, &r, NULL);
            }
            live = vm_and(live, vf_lt(col.a, vf_set1(f->alpha_stop)));
            if (vm_none(live)) break;
        }
        vf_store(c->cr + o, col.r), vf_store(c->cg + o, col.g);
        vf_store(c->cb + o, col.b), vf_store(c->ca + o, col.a);
    }
}

static void particles_coherent(const void *scene, const lc_kframe *f, const lc_ktile *t, lc_kscratch *scratch,
                               lc_kstats *st)
{
    const lc_kparticles *s = scene;
    cscratch c;
    coherent_layout(s, f, scratch->mem, &c);
    pgroup g = group_dims(f);
    const int nv = g.nv, rays = nv * LC_W, K = s->buffer_k, nf = s->nfields;
    const int comps = f->shade != LC_KSHADE_NONE ? 4 : 1;
    const int vpr = g.gw / DVR_PW; /* vectors per group row */
    const float dt = f->dt;
    for (int gy = t->y0; gy < t->y1; gy += g.gh) {
        for (int gx = t->x0; gx < t->x1; gx += g.gw) {
            /* Listing 3, line 3: rays, their box interval and lattice range */
            int kmin = 1 << 30, kmax = -(1 << 30);
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
                    kmin = c.kf[o + l] < kmin ? c.kf[o + l] : kmin;
                    kmax = c.kl[o + l] > kmax ? c.kl[o + l] : kmax;
                }
            }
            /* Listing 3, lines 4-6: passes of K samples until every ray is opaque */
            for (int kp = kmin; kp <= kmax; kp += K) {
                int kend = kp + K - 1 < kmax ? kp + K - 1 : kmax;
                int any = 0;
                for (int v = 0; v < nv; v++) {
                    int o = v * LC_W;
                    vint kf = vi_load(c.kf + o), kl = vi_load(c.kl + o);
                    vmask live = vm_and(vf_lt(vf_load(c.ca + o), vf_set1(f->alpha_stop)),
                                        vm_and(vi_lt(kf, vi_set1(kend + 1)), vi_gt(kl, vi_set1(kp - 1))));
                    vfloat a = vi_to_vf(vi_max(kf, vi_set1(kp))), b = vi_to_vf(vi_min(kl, vi_set1(kend)));
                    /* window in t, padded by half a step against round-off */
                    vf_store(c.w0 + o, vf_select(live, vf_mul(vf_sub(a, vf_set1(0.5f)), vf_set1(dt)), vf_set1(1.0f)));
                    vf_store(c.w1 + o, vf_select(live, vf_mul(vf_add(b, vf_set1(0.5f)), vf_set1(dt)), vf_set1(-1.0f)));
                    any |= vm_any(live);
                }
                if (!any) {
                    int alive = 0;
                    for (int v = 0; v < nv && !alive; v++) {
                        int o = v * LC_W;
                        alive = vm_any(vm_and(vf_lt(vf_load(c.ca + o), vf_set1(f->alpha_stop)),
                                              vi_gt(vi_load(c.kl + o), vi_set1(kend))));
                    }
                    if (!alive) break;
                    continue;
                }
                st->passes++;
                int nrows = kend - kp + 1;
                for (int fi = 0; fi < nf; fi++)
                    for (int row = 0; row < nrows; row++) {
                        float *p = c.buf + ((size_t)fi * (size_t)K + (size_t)row) * (size_t)comps * (size_t)rays;
                        for (int q = 0; q < comps * rays; q += LC_W) vf_store(p + q, vf_zero());
                    }
                for (int v = 0; v < nv; v++) c.touched[v] = 0;
                traverse_pass(s, f, &c, nv, kp, kend, dt, comps, st);
                /* Listing 2, lines 11-13: integrate the buffer front to back */
                if (f->mode == LC_KMODE_MIP) integrate_buffer(f, LC_KMODE_MIP, &c, nv, K, nf, kp, kend, comps, st);
                else integrate_buffer(f, LC_KMODE_DVR, &c, nv, K, nf, kp, kend, comps, st);
            }
            for (int v = 0; v < nv; v++) {
                int o = v * LC_W, x = gx + (v % vpr) * DVR_PW, y = gy + (v / vpr) * DVR_PH;
                vcolor col = {vf_load(c.cr + o), vf_load(c.cg + o), vf_load(c.cb + o), vf_load(c.ca + o)};
                vcolor surf = {vf_load(c.sr + o), vf_load(c.sg + o), vf_load(c.sb + o), vf_load(c.sa + o)};
                if (x < t->x1 && y < t->y1) finish_vector(f, t, x, y, &col, &surf);
            }
        }
    }
}

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
    .render = {[LC_KMETHOD_FAST] = particles_coherent, [LC_KMETHOD_BASE] = particles_direct},
    .scratch_bytes = {[LC_KMETHOD_FAST] = particles_scratch_bytes, [LC_KMETHOD_BASE] = direct_scratch_bytes},
    .sample = particles_sample,
    .sample_scratch_bytes = stack_bytes,
};
