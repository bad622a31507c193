/* Coherent particle volume rendering (Knoll et al. 2014, Listings 2 and 3),
 * compiled once per target: a group of rays (8x8 by default, or one
 * lane-width packet) walks the BVH with a uniform stack; every leaf particle
 * adds its Gaussian to every buffered sample it overlaps (the uniform sample
 * range is the min/max over the packet's lanes); then the buffer of K samples
 * per ray is integrated front to back through the mode. Multi-pass over the
 * ray segment, stopping when every ray of the group reached alpha_stop. The
 * walk serves a window of passes (the group list, below), not each pass. */
#include <string.h>
#include "particles_common.h"

#define MAX_GROUP_RAYS 4096
#define VCONE_ROWS 5 /* cscratch.vc: axis x, y, z, tan and sec of the half-angle bounds */

typedef struct pgroup {
    int gw, gh; /* group size in pixels, multiples of DVR_PW x DVR_PH */
    int nv;     /* vectors in the group */
} pgroup;

/* Group side: the host's group_side when the render left packet at its
 * default, else the frame's packet (1: one lane-width packet). Groups change
 * no image: a sample's terms and their order do not depend on them
 * (tests/test_particles_gsize.c). */
static inline pgroup group_dims(const lc_kparticles *ps, const lc_kframe *f)
{
    pgroup g;
    int side = ps->group_side > 0 ? ps->group_side : f->packet;
    int s = side <= 1 ? 1 : side;
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
    float *kdt;                                        /* this pass: kdt[k - kp + PG_ANCHOR] = (float)k * dt,
                                                          k = kp - PG_ANCHOR .. kend + 1 */
    float *vq;                                         /* per vector: interval bounds (walk's vcull) */
    int32_t nvq;                                       /* vq's row length: nv rounded up to LC_W */
    float *vc;                                         /* per vector: its rays' cone (list deposits'
                                                          pre-test, vcone_make); NULL: no pre-test */
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

/* The default grows with the group beyond 256 rays (32x32 groups: 32768
 * entries, 768 KB): a chunk's list holds the leaves of every ray of the
 * group, and a list that does not fit costs a walk per pass. */
static int32_t list_cap(const lc_kparticles *s, int nv)
{
    int32_t grow = nv * LC_W > 256 ? nv * LC_W / 256 : 1;
    return s->group_list_cap < 0 ? 0 : s->group_list_cap > 0 ? s->group_list_cap : GL_DEFAULT_CAP * grow;
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
    pgroup g = group_dims(s, f);
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
    if (base) c->kdt = (float *)(base + off);
    off += align64((uint64_t)(c->K + PG_ANCHOR + 1) * 4);
    c->nvq = (g.nv + LC_W - 1) / LC_W * LC_W;
    if (base) c->vq = (float *)(base + off);
    off += align64((uint64_t)c->nvq * 8 * 4);
    if (base) c->stack = (int32_t *)(base + off);
    off += align64((uint64_t)(s->depth + 4) * 4);
    c->cap = list_cap(s, g.nv);
    c->list = NULL;
    if (base && c->cap > 0) c->list = (gent *)(base + off);
    off += align64((uint64_t)c->cap * sizeof(gent));
    /* last, so the offsets above stay those of the layout before the cones */
    if (base) c->vc = (float *)(base + off);
    off += align64((uint64_t)c->nvq * VCONE_ROWS * 4);
    return off;
}

uint64_t LC_KFN(particles_coherent_scratch_bytes)(const void *scene, const lc_kframe *f)
{
    cscratch c;
    return coherent_layout(scene, f, NULL, &c);
}

#include "particles_walk.h"

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

#include "particles_integrate.h"

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
    vint lo = vi_set1(1 << 30), hi = vi_set1(-(1 << 30));
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
        vcolor c0 = dvr_start(t, x, y); /* zero unless the tile carries (C, A) in */
        vf_store(c.cr + o, c0.r), vf_store(c.cg + o, c0.g);
        vf_store(c.cb + o, c0.b), vf_store(c.ca + o, c0.a);
        vf_store(c.sr + o, surf.r), vf_store(c.sg + o, surf.g);
        vf_store(c.sb + o, surf.b), vf_store(c.sa + o, surf.a);
        vmask valid = vm_not(vi_lt(kl, kf)); /* kf <= kl */
        lo = vi_min(lo, vi_select(valid, kf, vi_set1(1 << 30)));
        hi = vi_max(hi, vi_select(valid, kl, vi_set1(-(1 << 30))));
    }
    /* lattice indices and the two sentinels are exact in float (|k| <= 2^30,
       LC_KLATTICE_MAX < 2^24); a branch per lane took ~1% of a far frame */
    *kmin = (int)vf_reduce_min(vi_to_vf(lo));
    *kmax = (int)vf_reduce_max(vi_to_vf(hi));
}

/* Test hook (tests/test_particles_integrate.c): one pass of a group of nv
 * ray vectors (1..64) through integrate_two and through integrate_buffer
 * (the general loop, one vector at a time) on the same random inputs made
 * from seed: lane ranges about the pass (some empty, some outside it),
 * colours (some lanes already past alpha_stop), samples (some exactly the
 * bias 0, some rows without a term), touched counts (some 0), and a random
 * premultiplied step table; mode dvr or mip. broken 1 gives integrate_two
 * the pass one sample short (the comparison must then fail). mem: at least
 * 1 MB, 64-byte aligned, zeroed by the caller before each call. out[0]: words that differ (colours of every lane,
 * the sample counts, the waste), out[1]: samples integrated, out[2]: lanes
 * that became opaque in the pass. Returns 0, or -1 for arguments out of
 * range. */
int LC_KFN(lc_pintegrate_probe)(int mode, int nv, uint64_t seed, float alpha_stop, int broken, void *mem,
                                uint64_t *out)
{
    if (nv < 1 || nv > 64 || (mode != LC_KMODE_DVR && mode != LC_KMODE_MIP) || !mem) return -1;
    enum { KP = 96, P = 24, KR = 32 };
    const int rays = buf_stride(nv), n = nv * LC_W, kp = KP, kend = KP + P - 1;
    float *fm = mem;
    size_t off = 0;
    cscratch c[2];
    float *cls = fm + off;
    off += (LC_TF_TABLE_SIZE + 1) * 4 + 16;
    for (int i = 0; i < 2; i++) {
        float **fa[] = {&c[i].w0, &c[i].w1, &c[i].cr, &c[i].cg, &c[i].cb, &c[i].ca, &c[i].dx, &c[i].dy, &c[i].dz};
        for (size_t j = 0; j < sizeof fa / sizeof fa[0]; j++) *fa[j] = fm + off, off += (size_t)n + 16;
        c[i].kf = (int32_t *)(fm + off), off += (size_t)n + 16;
        c[i].kl = (int32_t *)(fm + off), off += (size_t)n + 16;
        c[i].touched = (uint32_t *)(fm + off), off += 64 + 16;
        c[i].buf = fm + off, off += (size_t)KR * (size_t)rays + 16;
        c[i].K = KR;
    }
    uint64_t r = seed | 1;
#define PROBE_RND() (r ^= r << 13, r ^= r >> 7, r ^= r << 17, (float)(r >> 40) / 16777216.0f)
    for (int i = 0; i < (LC_TF_TABLE_SIZE + 1) * 4; i++) cls[i] = PROBE_RND() * ((i & 3) == 3 ? 0.3f : 0.25f);
    for (int l = 0; l < n; l++) {
        float u = PROBE_RND();
        int a = kp - 12 + (int)(PROBE_RND() * (float)(P + 12)), b = a + (int)(PROBE_RND() * 40.0f);
        if (u < 0.08f) a = kend + 3, b = kend + 9;      /* after the pass */
        else if (u < 0.12f) a = kp - 20, b = kp - 2;    /* before it */
        else if (u < 0.16f) a = 1, b = 0;               /* no samples at all */
        c[0].kf[l] = a, c[0].kl[l] = b;
        float al = PROBE_RND();
        c[0].ca[l] = al < 0.1f ? alpha_stop : 0.8f * al;
        c[0].cr[l] = 0.3f * PROBE_RND(), c[0].cg[l] = 0.3f * PROBE_RND(), c[0].cb[l] = mode == LC_KMODE_MIP && al < 0.5f ? 0.0f : 0.3f * PROBE_RND();
        c[0].dx[l] = c[0].dy[l] = c[0].dz[l] = 0.0f;
    }
    for (int v = 0; v < nv; v++) c[0].touched[v] = PROBE_RND() < 0.15f ? 0u : 1u + (uint32_t)(PROBE_RND() * 500.0f);
    for (int k = 0; k < KR; k++) {
        int empty = PROBE_RND() < 0.1f;
        for (int q = 0; q < rays; q++) c[0].buf[(size_t)k * (size_t)rays + (size_t)q] = empty || PROBE_RND() < 0.3f ? 0.0f : PROBE_RND();
    }
#undef PROBE_RND
    size_t per = (size_t)(c[1].w0 - c[0].w0); /* copy every array of c[0] into c[1] */
    memcpy(c[1].w0, c[0].w0, per * sizeof(float));
    /* the frame, the scene and the counters from the caller's zeroed memory (no
       struct zeroing here: GCC would expand it with zmm stores on avx512_8) */
    off = (off + 15) & ~(size_t)15;
    lc_kframe *fr = (lc_kframe *)(fm + off);
    off += ((sizeof(lc_kframe) + 63) & ~(size_t)63) / 4; /* whole 64-byte lines: each struct aligned */
    lc_kparticles *sc = (lc_kparticles *)(fm + off);
    off += ((sizeof(lc_kparticles) + 63) & ~(size_t)63) / 4;
    lc_kstats *st = (lc_kstats *)(fm + off);
    fr->mode = mode, fr->dt = 0.1f, fr->alpha_stop = alpha_stop, fr->zero_transparent = 1;
    fr->tf[0].cls = cls, fr->tf[0].rgbt = cls, fr->tf[0].lo = 0.0f, fr->tf[0].inv_range = 1.0f;
    fr->tf[0].cls_vzero = 0.02f;
    sc->nfields = 1;
    const lc_kframe *fp = fr;
    const lc_kparticles *sp = sc;
    set_windows(fp, &c[0], nv, kp, kend);
    set_windows(fp, &c[1], nv, kp, kend);
    float a0 = 0.0f;
    for (int l = 0; l < n; l++) a0 += c[0].ca[l] >= alpha_stop ? 1.0f : 0.0f;
    float w[2];
    w[0] = mode == LC_KMODE_DVR ? integrate_two(sp, fp, LC_KMODE_DVR, &c[0], nv, kp, kend - (broken ? 1 : 0), &st[0])
                                : integrate_two(sp, fp, LC_KMODE_MIP, &c[0], nv, kp, kend - (broken ? 1 : 0), &st[0]);
    w[1] = mode == LC_KMODE_DVR ? integrate_buffer(sp, fp, LC_KMODE_DVR, &c[1], nv, KR, 1, kp, kend, 1, NULL, &st[1])
                                : integrate_buffer(sp, fp, LC_KMODE_MIP, &c[1], nv, KR, 1, kp, kend, 1, NULL, &st[1]);
    uint64_t diff = st[0].samples != st[1].samples;
    diff += memcmp(&w[0], &w[1], sizeof(float)) != 0;
    const float *ca[2][4] = {{c[0].cr, c[0].cg, c[0].cb, c[0].ca}, {c[1].cr, c[1].cg, c[1].cb, c[1].ca}};
    for (int j = 0; j < 4; j++)
        for (int l = 0; l < n; l++) diff += memcmp(&ca[0][j][l], &ca[1][j][l], sizeof(float)) != 0;
    float a1 = 0.0f;
    for (int l = 0; l < n; l++) a1 += c[1].ca[l] >= alpha_stop ? 1.0f : 0.0f;
    out[0] = diff, out[1] = st[1].samples, out[2] = (uint64_t)(a1 - a0);
    return 0;
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

/* Pass length (issue 8; docs/bench/particles.md "Pass length"). Passes change no image, only the work:
 * a long pass deposits terms behind the samples where a vector's rays
 * became opaque (integrate_buffer counts them: the vector's terms of the
 * pass times the share of its lanes' samples in the pass behind each lane's
 * opaque sample; until d036bb2 it counted only those behind the sample where
 * the whole vector became opaque); a short one costs
 * its fixed part again: windows, list scan, the set-up again of every
 * particle and vector pair whose entry spans the boundary, the integration's
 * per-vector setup, each BVH walk for fewer samples. With s->buffer_adapt,
 * each group's totals of both (in deposited terms: the waste, and PASS_COST
 * per live vector and pass for the fixed part) set the next group's pass
 * length: halved when the waste is more than twice the fixed part, doubled
 * when it is less than half (the two balance at the best length; a step of
 * two moves their ratio about four times), within [PG_ANCHOR, K]; each tile
 * starts at PASS_FIRST. PASS_COST was measured (commit b345743, A/B on the
 * benchmark sets): 4 and 16 cost uniform 1e6 10-13% (passes too short on
 * its long chords), 64 keeps its times and most of dense1e6's gain. */
#ifndef PASS_COST
#define PASS_COST 64.0f
#endif
#define PASS_FIRST 32

/* Groups of more than 256 rays (32x32 on 16 lanes) fill a whole 32-pixel
 * tile, so their P is never adapted: they start (and stay) at
 * PASS_FIRST_BIG (commit d036bb2: with 32, dense1e6 far deposited 60% of its
 * terms behind opaque samples; 24 took dense1e6 far 5% faster and 1e6 and
 * 1tw7 far the same or 2% faster, 16 dense1e6 7% faster but 1e6 and 1tw7
 * far 3-4% slower). */
#define PASS_FIRST_BIG 24

/* The same with the eye inside the particles' grown box (commit 2a05c66: close
 * views take 32x32 groups too; fixed passes at 32x32 there, avx512, CPU s:
 * dense1e6 0.774 (8), 0.841 (16), 0.951 (32); 1e6 0.087, 0.079, 0.080; 1tw7
 * 0.272, 0.256, 0.257; 16x16 groups with the adaptive length: 0.917, 0.089,
 * 0.282). */
#ifndef PASS_FIRST_INSIDE
#define PASS_FIRST_INSIDE 16
#endif

static inline int pass_first(const lc_kparticles *s, const lc_kframe *f, int K, int nv)
{
    int first = nv * LC_W <= 256 ? PASS_FIRST : lc_kparticles_eye_inside(s, f) ? PASS_FIRST_INSIDE : PASS_FIRST_BIG;
    return s->buffer_adapt && K > first ? first : K;
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
 * differently and avx512 dvr frames were 2-3% slower (an A/B of CPU time
 * per frame, now lanecast bench --baseline; the iso code was never run). */
static inline __attribute__((always_inline)) void coherent_tile(const lc_kparticles *s, const lc_kframe *f, int mode,
                                                                const lc_ktile *t, lc_kscratch *scratch, lc_kstats *st)
{
    cscratch c;
    coherent_layout(s, f, scratch->mem, &c);
    pgroup g = group_dims(s, f);
    const int nv = g.nv, rays = buf_stride(nv), K = c.K, nf = s->nfields;
    int P = pass_first(s, f, K, nv); /* samples per pass: K, or adapted per group (pass_adapt) */
    const int comps = mode_needs_grad(f) ? 4 : 1;
    const int vpr = g.gw / DVR_PW; /* vectors per group row */
    int vshift = 0; /* list bit of vector v: v >> vshift, < 64 */
    while (((nv - 1) >> vshift) >= 64) vshift++;
    const float dt = f->dt;
    const pprobe pc = {s, c.stack, st};
    const mprobe probe = {particles_probe, &pc};
    const mprobe *pr = mode == LC_KMODE_ISO ? &probe : NULL;
    /* the cone pre-test of list deposits: rays from the eye, one list bit per vector,
       vectors in at most VCULL_MAX_SETS vector operations */
    const int cones = c.list && vcone_on(s, f, nv);
    if (!cones) c.vc = NULL;
    for (int gy = t->y0; gy < t->y1; gy += g.gh) {
        for (int gx = t->x0; gx < t->x1; gx += g.gw) {
            if (lc_ktile_stopped(t)) return;
            /* Listing 3, line 3: rays, their box interval and lattice range */
            int kmin, kmax;
            setup_group(s, f, t, &c, gx, gy, nv, vpr, &kmin, &kmax, st);
            if (cones) vcone_make(&c, nv);
            /* Listing 3, lines 4-6: passes of K samples until every ray is opaque,
               in chunks of passes that share one BVH walk (the group list) */
            int chunk = GL_FIRST_PASSES, done = 0;
            float gwaste = 0.0f, gover = 0.0f; /* this group's, in deposited terms */
            for (int kc = kmin; kc <= kmax && !done;) {
                if (lc_ktile_stopped(t)) return; /* a central group of a dense set takes milliseconds */
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
                    for (int k = kp - PG_ANCHOR; k <= kend + 1; k++) c.kdt[k - kp + PG_ANCHOR] = (float)k * dt;
                    for (int v = 0; v < nv; v++) c.touched[v] = 0;
                    if (n >= 0)
                        n = deposit_list(s, f, &c, nv, vshift, n, kp, kend, dt, comps, st);
                    else
                        traverse_pass(s, f, &c, nv, vshift, kp, kend, dt, comps, st);
                    /* Listing 2, lines 11-13: integrate the buffer front to back */
                    gwaste += integrate_pass(s, f, mode, &c, nv, K, nf, kp, kend, comps, pr, st);
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

