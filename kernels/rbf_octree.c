/* RBF sets through the adaptive octree of Jang et al. 2004, §5 (the volume's
 * accel = octree; bvh/rbf_octree.c builds it), compiled once per target.
 *
 * Rays come in lane-width packets as in the other methods, but a leaf's list
 * is evaluated along one ray at a time: the ray's lattice samples inside the
 * leaf fill the lanes (the RBF is uniform, the samples vary), so the whole
 * list runs once per lane-width run of samples in the cell. Each ray walks
 * its cells front to back: the leaf holding the next sample is found by
 * descending from the root, and the following samples stay with it while
 * they lie in its region (the same half-open test the descent makes, so the
 * two never disagree). Samples are computed exactly as the BVH method
 * computes them (t_k = k dt, p = o + d t_k with the same fma), and the lists
 * name the RBFs in the BVH's leaf order, so with exact lists both methods sum
 * the same terms in the same order: the images agree to the bit.
 *
 * The field values go to a per-packet buffer of up to CHUNK_MAX lattice
 * steps per ray, then the packet integrates the buffer step by step through
 * mode_sample_as with the mode a compile-time constant. Chunks start at
 * CHUNK_MIN steps and double, so rays that end early (opacity) evaluate
 * little past their end. In significant mode a leaf also adds the trilinear
 * interpolation of the dropped terms' sum stored at its corners (and its
 * gradient). */
#include "rbf_common.h"
#include "shared/ktable.h"
#include "kernels.h"

enum { CHUNK_MIN = 16, CHUNK_MAX = 128 };

/* Per-packet sample buffer, row k - kc holds lattice step k of every lane. */
typedef struct obuf {
    float *phi, *gx, *gy, *gz;
    uint8_t *hit; /* row: some term (or a correction) contributed on some lane */
} obuf;

/* The leaf whose region holds (x, y, z); *steps counts the cells passed. */
static inline int32_t locate(const lc_kcell *c, float x, float y, float z, uint64_t *steps)
{
    int32_t i = 0;
    while (c[i].child >= 0) {
        const lc_kcell *n = &c[i];
        i = n->child + (x >= n->split[0]) + 2 * (y >= n->split[1]) + 4 * (z >= n->split[2]);
        (*steps)++;
    }
    return i;
}

/* The trilinear interpolation of the corner errors k[8..15] over the box
 * (k[0..2], inverse extent k[3..5]) at the points, and its gradient. */
static inline void correction(const float *k, vfloat px, vfloat py, vfloat pz, vmask m, int grad, vfloat *phi,
                              vfloat *gx, vfloat *gy, vfloat *gz)
{
    vfloat one = vf_set1(1.0f), zero = vf_zero();
    vfloat ux = vf_min(vf_max(vf_mul(vf_sub(px, vf_set1(k[0])), vf_set1(k[3])), zero), one);
    vfloat uy = vf_min(vf_max(vf_mul(vf_sub(py, vf_set1(k[1])), vf_set1(k[4])), zero), one);
    vfloat uz = vf_min(vf_max(vf_mul(vf_sub(pz, vf_set1(k[2])), vf_set1(k[5])), zero), one);
    vfloat d0 = vf_set1(k[9] - k[8]), d1 = vf_set1(k[11] - k[10]), d2 = vf_set1(k[13] - k[12]),
           d3 = vf_set1(k[15] - k[14]);
    vfloat x00 = vf_fma(ux, d0, vf_set1(k[8])), x10 = vf_fma(ux, d1, vf_set1(k[10]));
    vfloat x01 = vf_fma(ux, d2, vf_set1(k[12])), x11 = vf_fma(ux, d3, vf_set1(k[14]));
    vfloat y0 = vf_fma(uy, vf_sub(x10, x00), x00), y1 = vf_fma(uy, vf_sub(x11, x01), x01);
    *phi = vf_add(*phi, vf_select(m, vf_fma(uz, vf_sub(y1, y0), y0), zero));
    if (!grad) return;
    vfloat e0 = vf_fma(uy, vf_sub(d1, d0), d0), e1 = vf_fma(uy, vf_sub(d3, d2), d2);
    vfloat dux = vf_fma(uz, vf_sub(e1, e0), e0);
    vfloat duy = vf_fma(uz, vf_sub(vf_sub(x11, x01), vf_sub(x10, x00)), vf_sub(x10, x00));
    vfloat duz = vf_sub(y1, y0);
    *gx = vf_add(*gx, vf_select(m, vf_mul(dux, vf_set1(k[3])), zero));
    *gy = vf_add(*gy, vf_select(m, vf_mul(duy, vf_set1(k[4])), zero));
    *gz = vf_add(*gz, vf_select(m, vf_mul(duz, vf_set1(k[5])), zero));
}

/* The field of leaf ci at the points on the lanes in m: w0 plus its list's
 * terms in order (as the BVH's gather), plus its correction. *hit: the lanes
 * where something was added. */
static inline vfloat cell_eval(const lc_krbf *s, int32_t ci, vfloat px, vfloat py, vfloat pz, vmask m, int grad,
                               vfloat *gx, vfloat *gy, vfloat *gz, vmask *hit, uint64_t *evals)
{
    const lc_kcell *c = &s->cells[ci];
    const int32_t *l = s->cell_list + c->first;
    vfloat phi = vf_set1(s->bias);
    *gx = *gy = *gz = vf_zero();
    vmask h = vm_false();
    for (int32_t j = 0; j < c->count; j++) {
        vmask in = term(s, l[j], px, py, pz, m, grad, &phi, gx, gy, gz);
        h = vm_or(h, in);
        *evals += (uint64_t)vm_popcnt(in);
    }
    if (s->cell_corr) {
        const float *k = s->cell_corr + (int64_t)ci * LC_KCORR;
        if (k[6] != 0.0f) {
            correction(k, px, py, pz, m, grad, &phi, gx, gy, gz);
            h = m;
        }
    }
    *hit = h;
    return phi;
}

/* Lattice steps ka..kb of one ray (origin o, direction d) into lane l of the
 * buffer rows from kc: run after run of samples sharing a leaf. */
static inline void fill_ray(const lc_krbf *s, const float o[3], const float d[3], float dt, int ka, int kb, int kc,
                            int l, int grad, const obuf *b, lc_kstats *st)
{
    const vfloat ox = vf_set1(o[0]), oy = vf_set1(o[1]), oz = vf_set1(o[2]);
    const vfloat dx = vf_set1(d[0]), dy = vf_set1(d[1]), dz = vf_set1(d[2]);
    const vint iota = vi_iota(), end = vi_set1(kb + 1);
    uint64_t steps = 0, cells = 0, evals = 0;
    int k = ka;
    while (k <= kb) {
        int32_t ci = -1;
        for (;;) {
            vint kv = vi_add(vi_set1(k), iota);
            vfloat tk = vf_mul(vi_to_vf(kv), vf_set1(dt));
            vfloat px = vf_fma(dx, tk, ox), py = vf_fma(dy, tk, oy), pz = vf_fma(dz, tk, oz);
            int fresh = ci < 0;
            if (fresh) ci = locate(s->cells, vf_lane(px, 0), vf_lane(py, 0), vf_lane(pz, 0), &steps), cells++;
            const lc_kcell *c = &s->cells[ci];
            vmask in = vm_and(vi_lt(kv, end),
                              vm_and(vm_and(vm_and(vf_ge(px, vf_set1(c->lo[0])), vf_lt(px, vf_set1(c->hi[0]))),
                                            vm_and(vf_ge(py, vf_set1(c->lo[1])), vf_lt(py, vf_set1(c->hi[1])))),
                                     vm_and(vf_ge(pz, vf_set1(c->lo[2])), vf_lt(pz, vf_set1(c->hi[2])))));
            int lead = __builtin_ctz(~vm_bits(in)); /* samples from k on inside the leaf */
            if (lead == 0 && !fresh) break;         /* sample k left the leaf: find its own */
            if (lead == 0) lead = 1; /* cannot happen (the descent and the test agree); progress */
            vmask m = vm_first_n(lead);
            vfloat gx, gy, gz;
            vmask hit;
            vfloat phi = cell_eval(s, ci, px, py, pz, m, grad, &gx, &gy, &gz, &hit, &evals);
            float tp[LC_W], tx[LC_W], ty[LC_W], tz[LC_W];
            vf_store(tp, phi);
            if (grad) vf_store(tx, gx), vf_store(ty, gy), vf_store(tz, gz);
            uint32_t hb = vm_bits(hit);
            for (int i = 0; i < lead; i++) {
                int64_t o2 = (int64_t)(k - kc + i) * LC_W + l;
                b->phi[o2] = tp[i];
                if (grad) b->gx[o2] = tx[i], b->gy[o2] = ty[i], b->gz[o2] = tz[i];
                if ((hb >> i) & 1u) b->hit[k - kc + i] = 1;
            }
            k += lead;
            if (lead < LC_W || k > kb) break;
        }
    }
    st->nodes += steps, st->leaves += cells, st->kernel_evals += evals;
}

/* The octree's point evaluation for the modes (mode.h mprobe): each lane's
 * leaf, its list and correction, as the sample buffer computes them. */
static inline vfloat octree_probe(const void *ctx, int fi, vfloat x, vfloat y, vfloat z, vmask m, vgrad *g)
{
    const lc_krbf *s = ctx;
    float px[LC_W], py[LC_W], pz[LC_W], v[LC_W] = {0}, gx[LC_W] = {0}, gy[LC_W] = {0}, gz[LC_W] = {0};
    uint64_t steps = 0, evals = 0;
    (void)fi;
    vf_store(px, x), vf_store(py, y), vf_store(pz, z);
    const uint32_t mb = vm_bits(m);
    for (int l = 0; l < LC_W; l++) {
        if (!((mb >> l) & 1u)) continue;
        int32_t ci = locate(s->cells, px[l], py[l], pz[l], &steps);
        vfloat ax, ay, az;
        vmask hit;
        vfloat p = cell_eval(s, ci, vf_set1(px[l]), vf_set1(py[l]), vf_set1(pz[l]), vm_first_n(1), g != NULL, &ax,
                             &ay, &az, &hit, &evals);
        v[l] = vf_lane(p, 0);
        if (g) gx[l] = vf_lane(ax, 0), gy[l] = vf_lane(ay, 0), gz[l] = vf_lane(az, 0);
    }
    if (g) g->x = vf_load(gx), g->y = vf_load(gy), g->z = vf_load(gz);
    return vf_load(v);
}

static inline __attribute__((always_inline)) void octree_tile(const lc_krbf *s, const lc_kframe *f, int mode,
                                                              const lc_ktile *t, lc_kscratch *scratch, lc_kstats *st)
{
    const float dt = f->dt;
    const int shade = mode == LC_KMODE_DVR && f->shade != LC_KSHADE_NONE; /* mode_needs_grad */
    const mprobe probe = {octree_probe, s};
    const int skip_zero = f->zero_transparent && s->bias == 0.0f; /* as the BVH method */
    float *mem = scratch->mem;
    const int64_t rows = (int64_t)CHUNK_MAX * LC_W;
    const obuf b = {mem, mem + rows, mem + 2 * rows, mem + 3 * rows, (uint8_t *)(mem + 4 * rows)};
    for (int y = t->y0; y < t->y1; y += DVR_PH) {
        if (lc_ktile_stopped(t)) return;
        for (int x = t->x0; x < t->x1; x += DVR_PW) {
            vint px, py, kf, kl;
            vray r;
            vcolor col = dvr_start(t, x, y); /* zero unless the tile carries (C, A) in */
            if (!rbf_packet_begin(s, f, mode, t, x, y, &probe, &px, &py, &r, &kf, &kl, &col, st)) continue;
            int32_t kfa[LC_W], kla[LC_W];
            float ro[3][LC_W], rd[3][LC_W];
            vi_store(kfa, kf), vi_store(kla, kl);
            vf_store(ro[0], r.ox), vf_store(ro[1], r.oy), vf_store(ro[2], r.oz);
            vf_store(rd[0], r.dx), vf_store(rd[1], r.dy), vf_store(rd[2], r.dz);
            int k0 = 1 << 30, k1 = -(1 << 30);
            for (int l = 0; l < LC_W; l++) {
                if (kfa[l] > kla[l]) continue;
                k0 = kfa[l] < k0 ? kfa[l] : k0;
                k1 = kla[l] > k1 ? kla[l] : k1;
            }
            vmask live = vm_and(vi_lt(kf, vi_add(kl, vi_set1(1))), vf_lt(col.a, vf_set1(f->alpha_stop))); /* a carried-in ray may have stopped already */
            int len = CHUNK_MIN;
            for (int kc = k0; kc <= k1 && vm_any(live); kc += len, len = len < CHUNK_MAX ? 2 * len : CHUNK_MAX) {
                const int ke = kc + len - 1 < k1 ? kc + len - 1 : k1;
                for (int row = 0; row <= ke - kc; row++) {
                    vf_store(b.phi + (int64_t)row * LC_W, vf_zero());
                    if (shade) {
                        vf_store(b.gx + (int64_t)row * LC_W, vf_zero());
                        vf_store(b.gy + (int64_t)row * LC_W, vf_zero());
                        vf_store(b.gz + (int64_t)row * LC_W, vf_zero());
                    }
                    b.hit[row] = 0;
                }
                const uint32_t lb = vm_bits(live);
                for (int l = 0; l < LC_W; l++) {
                    if (!((lb >> l) & 1u)) continue;
                    const int ka = kfa[l] > kc ? kfa[l] : kc, kb = kla[l] < ke ? kla[l] : ke;
                    const float o[3] = {ro[0][l], ro[1][l], ro[2][l]}, d[3] = {rd[0][l], rd[1][l], rd[2][l]};
                    if (ka <= kb) fill_ray(s, o, d, dt, ka, kb, kc, l, shade, &b, st);
                }
                for (int k = kc; k <= ke; k++) {
                    vmask m = vm_and(live, vm_and(vi_lt(kf, vi_set1(k + 1)), vi_gt(kl, vi_set1(k - 1))));
                    const int64_t row = k - kc;
                    if (vm_none(m) || (skip_zero && !b.hit[row])) continue;
                    st->samples += (uint64_t)vm_popcnt(m);
                    vfloat phi = vf_load(b.phi + row * LC_W);
                    vgrad gr = {vf_zero(), vf_zero(), vf_zero()};
                    if (shade)
                        gr.x = vf_load(b.gx + row * LC_W), gr.y = vf_load(b.gy + row * LC_W),
                        gr.z = vf_load(b.gz + row * LC_W);
                    mode_sample_as(f, mode, 0, &col, m, phi, shade ? &gr : NULL, &r, NULL, vi_set1(k),
                                   vf_set1((float)k * dt), &probe);
                    live = vm_and(live, vf_lt(col.a, vf_set1(f->alpha_stop)));
                    if (vm_none(live)) break;
                }
            }
            vfloat depth = mode_finish_as(f, mode, &col, &r, &probe);
            mode_store_as(t, mode, px, py, &col, depth);
        }
    }
}

/* The octree method, its sample loop specialised per mode. */
void LC_KFN(rbf_octree)(const void *scene, const lc_kframe *f, const lc_ktile *t, lc_kscratch *scratch,
                        lc_kstats *st)
{
    if (f->mode == LC_KMODE_MIP) octree_tile(scene, f, LC_KMODE_MIP, t, scratch, st);
    else if (f->mode == LC_KMODE_ISO) octree_tile(scene, f, LC_KMODE_ISO, t, scratch, st);
    else if (f->mode == LC_KMODE_SLICE) octree_tile(scene, f, LC_KMODE_SLICE, t, scratch, st);
    else octree_tile(scene, f, LC_KMODE_DVR, t, scratch, st);
}

/* The sample buffer: four floats and a flag per lane and step of a chunk. */
uint64_t LC_KFN(rbf_octree_scratch_bytes)(const void *scene, const lc_kframe *f)
{
    (void)scene, (void)f;
    return (uint64_t)CHUNK_MAX * LC_W * 4 * sizeof(float) + CHUNK_MAX + 64;
}

/* f and its gradient at n points (xyz interleaved) through the octree. */
void LC_KFN(rbf_octree_sample)(const lc_krbf *s, const float *xyz, int64_t n, float *phi, float *grad)
{
    uint64_t steps = 0, evals = 0;
    for (int64_t i = 0; i < n; i++) {
        const float *p = xyz + 3 * i;
        int32_t ci = locate(s->cells, p[0], p[1], p[2], &steps);
        vfloat gx, gy, gz;
        vmask hit;
        vfloat v = cell_eval(s, ci, vf_set1(p[0]), vf_set1(p[1]), vf_set1(p[2]), vm_first_n(1), 1, &gx, &gy, &gz,
                             &hit, &evals);
        phi[i] = vf_lane(v, 0);
        if (grad) grad[3 * i] = vf_lane(gx, 0), grad[3 * i + 1] = vf_lane(gy, 0), grad[3 * i + 2] = vf_lane(gz, 0);
    }
}
