/* Particle path correctness (issue 3, Tests): lc_volume_sample (with sigma and
 * kappa set by lc_particles_set_params) against brute force in double, BVH structure, and images of every supported target
 * and method (coherent 8x8 groups, coherent lane-width packets, direct)
 * against the independent reference core (tests/ref: ref_core with the
 * particle evaluator of ref_fields) through the one image comparer (imgcmp)
 * within SPEC.md's tolerances: max per-channel difference <= 2/255 and PSNR >= 50 dB
 * with alpha_stop = 1; with alpha_stop < 1 the difference to the alpha_stop = 1
 * image is at most 1 - alpha_stop per channel. NaN or Inf in an image fails
 * every image check (shown by a self-check at the end).
 * usage: test_particles [OUTDIR]   (diff images of failures go to OUTDIR) */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "lanecast/lanecast.h"
#include "host/kinds/kind.h"
#include "kernels/shared/kparticles.h"
#include "check.h"
#include "imgcmp.h"
#include "ref/ref_core.h"
#include "ref/ref_fields.h"

static const char *outdir = ".";

/* ---------------------------------------------------------------- random data */

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static double rnd(void) /* [0, 1) */
{
    rng_state ^= rng_state << 13, rng_state ^= rng_state >> 7, rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}
static float urand(float a, float b) { return a + (b - a) * (float)rnd(); }

typedef struct pdata {
    size_t n;
    float *xyz, *r, *k;
    uint8_t *f;
    int nfields;
} pdata;

static pdata pdata_alloc(size_t n, int nfields)
{
    pdata d = {n, calloc(3 * n + 1, sizeof(float)), calloc(n + 1, sizeof(float)), calloc(n + 1, sizeof(float)),
               calloc(n + 1, 1), nfields};
    return d;
}
static void pdata_free(pdata *d) { free(d->xyz), free(d->r), free(d->k), free(d->f); }

/* Uniform in a box of half-size h, radii in [r0, r1], k in [k0, k1], fields 0..nf-1. */
static pdata random_particles(size_t n, float h, float r0, float r1, float k0, float k1, int nf)
{
    pdata d = pdata_alloc(n, nf);
    for (size_t i = 0; i < n; i++) {
        for (int a = 0; a < 3; a++) d.xyz[3 * i + a] = urand(-h, h);
        d.r[i] = urand(r0, r1);
        d.k[i] = urand(k0, k1);
        d.f[i] = (uint8_t)(rnd() * nf);
    }
    return d;
}

/* Clustered: a few tight clusters plus a sparse halo, radii log-uniform in [1e-3, 10]. */
static pdata clustered_particles(size_t n)
{
    pdata d = pdata_alloc(n, 1);
    float cc[4][3] = {{0, 0, 0}, {3, 1, -2}, {-4, -2, 1}, {0.001f, 0.002f, 0.0f}};
    for (size_t i = 0; i < n; i++) {
        int c = (int)(rnd() * 4);
        float spread = c == 3 ? 0.01f : (c == 0 ? 0.2f : 2.0f);
        for (int a = 0; a < 3; a++) d.xyz[3 * i + a] = cc[c][a] + urand(-spread, spread);
        d.r[i] = (float)(1e-3 * pow(1e4, rnd()));
        d.k[i] = urand(0.5f, 1.0f);
    }
    /* make sure the extremes are there */
    d.r[0] = 1e-3f, d.r[1] = 10.0f;
    return d;
}

static lc_volume *make_particles(lc_device *dev, const pdata *d, int leaf)
{
    lc_particles_desc desc = {.count = d->n, .positions = d->xyz, .radii = d->r, .values = d->k, .fields = d->f,
                              .nfields = d->nfields, .leaf_size = leaf};
    lc_volume *p = NULL;
    lc_status s = lc_particles_create(dev, &desc, &p);
    if (s != LC_OK) printf("lc_particles_create: %s\n", lc_last_error());
    return p;
}

/* The reference's copy of a data set: doubles of the same float values. */
typedef struct refset {
    double *pos, *rad, *val;
    int *fid;
    ref_particle_set set;
} refset;

/* sigma, kappa: 0 for the SPEC.md defaults (2 and 1). */
static refset refset_make(const pdata *d, double sigma, double kappa)
{
    refset r = {malloc(sizeof(double) * (3 * d->n + 1)), malloc(sizeof(double) * (d->n + 1)),
                malloc(sizeof(double) * (d->n + 1)), malloc(sizeof(int) * (d->n + 1)), {0}};
    for (size_t i = 0; i < d->n; i++) {
        for (int a = 0; a < 3; a++) r.pos[3 * i + a] = d->xyz[3 * i + a];
        r.rad[i] = d->r[i], r.val[i] = d->k[i], r.fid[i] = d->f[i];
    }
    r.set = (ref_particle_set){d->n, r.pos, r.rad, r.val, r.fid, d->nfields, sigma, kappa};
    return r;
}

static void refset_free(refset *r) { free(r->pos), free(r->rad), free(r->val), free(r->fid); }

/* ---------------------------------------------------------------- targets */

static lc_target targets[LC_TARGET_COUNT];
static int ntargets;

static void find_targets(void)
{
    for (lc_target t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        if (!lc_target_compiled(t)) printf("skip target %s: not compiled in\n", lc_target_name(t));
        else if (!lc_target_supported(t)) printf("skip target %s: this CPU cannot run it\n", lc_target_name(t));
        else targets[ntargets++] = t;
    }
}

static lc_device *device_for(lc_target t)
{
    lc_device_desc dd = {.target = t, .threads = 2};
    lc_device *dev = NULL;
    if (lc_device_create(&dd, &dev) != LC_OK) printf("lc_device_create(%s): %s\n", lc_target_name(t), lc_last_error());
    return dev;
}

/* ---------------------------------------------------------------- field and gradient */

/* The reference side of one sample case: points, the reference values and
 * gradients (ref_particles_eval) and their tolerances (ref_particles_budget). */
typedef struct sample_ref {
    int npts, nf;
    float *pts;     /* 3 * npts */
    double *rv, *rg; /* npts * nf values, 3 * npts * nf gradient components */
    double *tv, *tg; /* tolerances of each value and of each gradient component */
    int *amb;       /* point within 1e-5 of a cut-off: skipped */
    int nzero;      /* non-zero reference values */
} sample_ref;

/* Points near particle centres (inside the support and around its edge) and uniform incl. outside. */
static float *sample_points(const pdata *d, float h, int npts)
{
    float *pts = malloc(sizeof(float) * 3 * npts);
    for (int i = 0; i < npts; i++) {
        if (i % 2 == 0) {
            size_t j = (size_t)(rnd() * d->n);
            float dist = d->r[j] * urand(0.0f, 2.5f);
            double dir[3] = {rnd() - 0.5, rnd() - 0.5, rnd() - 0.5}, l = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
            for (int a = 0; a < 3; a++) pts[3 * i + a] = d->xyz[3 * j + a] + (float)(dist * dir[a] / l);
        } else {
            for (int a = 0; a < 3; a++) pts[3 * i + a] = urand(-1.5f * h, 1.5f * h);
        }
    }
    return pts;
}

/* Tolerance. Every term is kappa k exp(-d^2 / 2r^2) with d^2/2r^2 <= sigma^2/2:
 * the float exponent argument carries a few ulps (relative ~5e-7 of at most
 * sigma^2/2 = 2), exp itself <= 1e-6 (SPEC.md), so each term is within ~2e-6
 * relative; summing N terms in float adds <= N * 6e-8 of sum|terms|. For the
 * up to ~50 overlapping terms here, 1e-5 * sum|terms| bounds both. The sample
 * point minus the centre is formed in float, an absolute error of ~6e-8 (|x| +
 * |x_i|) per component: it moves phi by |dphi/dx| times that, and the gradient
 * likewise (the pos_sens budgets from ref_particles_budget, weighted by 2.4e-7 = 4 ulps). */
static sample_ref sample_reference(const ref_particle_set *ps, float *pts, int npts)
{
    const int nf = ps->nfields;
    sample_ref s = {npts, nf, pts, malloc(sizeof(double) * npts * nf), malloc(sizeof(double) * 3 * npts * nf),
                    malloc(sizeof(double) * npts * nf), malloc(sizeof(double) * npts * nf), malloc(sizeof(int) * npts), 0};
    double grad[REF_MAX_FIELDS][3];
    for (int i = 0; i < npts; i++) {
        double x[3] = {pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]}, as[8], gas[8], psens[8], gps[8];
        double *rv = s.rv + (size_t)i * nf, *rg = s.rg + (size_t)i * 3 * nf;
        ref_particles_eval(ps, x, rv, grad);
        ref_particles_budget(ps, x, as, gas, psens, gps, &s.amb[i]);
        for (int f = 0; f < nf; f++) {
            for (int a = 0; a < 3; a++) rg[3 * f + a] = grad[f][a];
            s.tv[(size_t)i * nf + f] = 1e-5 * as[f] + 2.4e-7 * psens[f] + 1e-30;
            s.tg[(size_t)i * nf + f] = 1e-5 * gas[f] + 2.4e-7 * gps[f] + 1e-30;
            s.nzero += rv[f] != 0.0;
        }
    }
    return s;
}

static void sample_ref_free(sample_ref *s) { free(s->rv), free(s->rg), free(s->tv), free(s->tg), free(s->amb), free(s->pts); }

/* lc_volume_sample on one target against the reference; one CHECK line. */
static void sample_on_target(const char *name, lc_target t, const pdata *d, float sigma, float kappa, const sample_ref *r)
{
    const int npts = r->npts, nf = r->nf;
    lc_device *dev = device_for(t);
    lc_volume *p = make_particles(dev, d, 0);
    float *v = malloc(sizeof(float) * npts * nf), *g = malloc(sizeof(float) * 3 * npts * nf);
    lc_particle_params pp = {.sigma = sigma, .kappa = kappa};
    lc_status s = p ? lc_particles_set_params(p, &pp) : LC_ERROR_INTERNAL;
    if (s == LC_OK) s = lc_volume_sample(dev, p, (size_t)npts, r->pts, v, g);
    int bad = 0, badg = 0, skipped = 0;
    double worst = 0.0, worstg = 0.0;
    for (int i = 0; i < npts && s == LC_OK; i++) {
        if (r->amb[i]) { skipped++; continue; }
        for (int f = 0; f < nf; f++) {
            size_t o = (size_t)i * nf + f;
            double e = fabs(v[o] - r->rv[o]) / r->tv[o];
            worst = e > worst ? e : worst;
            if (!(e <= 1.0) && bad++ < 3)
                printf("     point %d field %d: %.9g vs %.9g (tol %.3g)\n", i, f, (double)v[o], r->rv[o], r->tv[o]);
            for (int a = 0; a < 3; a++) {
                double eg = fabs(g[3 * o + a] - r->rg[3 * o + a]) / r->tg[o];
                worstg = eg > worstg ? eg : worstg;
                if (!(eg <= 1.0) && badg++ < 3)
                    printf("     point %d field %d grad %d: %.9g vs %.9g (tol %.3g)\n", i, f, a, (double)g[3 * o + a],
                           r->rg[3 * o + a], r->tg[o]);
            }
        }
    }
    CHECK(s == LC_OK && bad == 0 && badg == 0,
          "sample %-32s %-6s: %d points x %d fields (%d non-zero), value err/tol %.3f, gradient err/tol %.3f, "
          "%d points within 1e-5 of a cut-off skipped", name, lc_target_name(t), npts, nf, r->nzero, worst, worstg,
          skipped);
    free(v), free(g);
    lc_volume_destroy(p);
    lc_device_destroy(dev);
}

static void test_sample(void)
{
    printf("-- lc_volume_sample (particles) vs brute force (double, ref_fields)\n");
    const int npts = 2000;
    struct { const char *name; size_t n; float h, r0, r1, k0, k1; int nf; float sigma, kappa; } cases[] = {
        {"single field", 300, 4.0f, 0.3f, 1.2f, 1.0f, 1.0f, 1, 0.0f, 0.0f},
        {"3 fields, varying k", 400, 4.0f, 0.2f, 1.5f, 0.2f, 3.0f, 3, 0.0f, 0.0f},
        {"8 fields, sigma 3 kappa 0.5", 300, 3.0f, 0.1f, 1.0f, -1.0f, 2.0f, 8, 3.0f, 0.5f},
        {"radii 1e-2..3, sigma 1.5 kappa 4", 200, 5.0f, 0.01f, 3.0f, 0.5f, 1.5f, 2, 1.5f, 4.0f},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        pdata d = random_particles(cases[c].n, cases[c].h, cases[c].r0, cases[c].r1, cases[c].k0, cases[c].k1,
                                   cases[c].nf);
        float *pts = sample_points(&d, cases[c].h, npts);
        /* sigma and kappa 0 are the defaults on both sides (2 and 1) */
        refset rs = refset_make(&d, cases[c].sigma, cases[c].kappa);
        sample_ref r = sample_reference(&rs.set, pts, npts);
        for (int ti = 0; ti < ntargets; ti++)
            sample_on_target(cases[c].name, targets[ti], &d, cases[c].sigma, cases[c].kappa, &r);
        sample_ref_free(&r);
        refset_free(&rs);
        pdata_free(&d);
    }
}

/* ---------------------------------------------------------------- BVH structure */

typedef struct tup { float x, y, z, r, k; int f; } tup;
static int tup_cmp(const void *a, const void *b)
{
    const float *p = a, *q = b;
    for (int i = 0; i < 5; i++)
        if (p[i] != q[i]) return p[i] < q[i] ? -1 : 1;
    return ((const tup *)a)->f - ((const tup *)b)->f;
}

typedef struct bvh_walk {
    const lc_kparticles *k;
    int *seen;     /* per leaf-order slot */
    int *visited;  /* per node */
    int leaf, max_depth, errors, nleaves;
} bvh_walk;

#define BVH_ERR(w, ...) do { if ((w)->errors++ < 5) { printf("     "); printf(__VA_ARGS__); printf("\n"); } } while (0)

/* Returns the largest radius below node n; adds the sum of |k_i| below it to *ksum. */
static float walk(bvh_walk *w, int32_t n, int depth, double *ksum)
{
    const lc_kparticles *k = w->k;
    if (n < 0 || n >= k->nnodes) {
        BVH_ERR(w, "node index %d outside [0, %d)", n, k->nnodes);
        return 0.0f;
    }
    double ks = 0.0;
    if (w->visited[n]++) BVH_ERR(w, "node %d reached twice", n);
    if (depth > w->max_depth) w->max_depth = depth;
    const lc_kpnode *nd = &k->nodes[n];
    float rmax = 0.0f;
    if (nd->count > 0) {
        w->nleaves++;
        if (nd->count > w->leaf) BVH_ERR(w, "leaf %d holds %d particles, leaf size %d", n, nd->count, w->leaf);
        if (nd->first < 0 || nd->first + nd->count > k->count) {
            BVH_ERR(w, "leaf %d range [%d, %d) outside the %lld particles", n, nd->first, nd->first + nd->count,
                    (long long)k->count);
            return 0.0f;
        }
        for (int32_t i = nd->first; i < nd->first + nd->count; i++) {
            w->seen[i]++;
            float c[3] = {k->px[i], k->py[i], k->pz[i]};
            for (int a = 0; a < 3; a++)
                if (!(c[a] >= nd->lo[a] && c[a] <= nd->hi[a]))
                    BVH_ERR(w, "leaf %d box [%g, %g] (axis %d) misses particle %d at %g", n, (double)nd->lo[a],
                            (double)nd->hi[a], a, i, (double)c[a]);
            rmax = k->r[i] > rmax ? k->r[i] : rmax;
            ks += fabs((double)k->k[i]);
        }
    } else if (nd->count == 0) {
        for (int ch = 0; ch < 2; ch++) {
            int32_t c = nd->first + ch;
            if (c <= n || c >= k->nnodes) {
                BVH_ERR(w, "inner node %d has child %d (nodes %d)", n, c, k->nnodes);
                continue;
            }
            float r = walk(w, c, depth + 1, &ks);
            rmax = r > rmax ? r : rmax;
            for (int a = 0; a < 3; a++)
                if (!(k->nodes[c].lo[a] >= nd->lo[a] && k->nodes[c].hi[a] <= nd->hi[a]))
                    BVH_ERR(w, "node %d box does not contain child %d (axis %d)", n, c, a);
        }
    } else {
        BVH_ERR(w, "node %d has count %d", n, nd->count);
    }
    if (!(k->node_rmax[n] >= rmax)) BVH_ERR(w, "node %d rmax %g < largest radius below %g", n, (double)k->node_rmax[n], (double)rmax);
    /* node_ksum bounds the node's contribution: at least the sum of |k_i| below it (float rounding aside) */
    if (!((double)k->node_ksum[n] >= ks * (1.0 - 1e-6)))
        BVH_ERR(w, "node %d ksum %g < sum of |k| below %g", n, (double)k->node_ksum[n], ks);
    *ksum += ks;
    return rmax;
}

static void test_bvh(void)
{
    printf("-- BVH structure\n");
    lc_device *dev = device_for(LC_TARGET_AUTO);
    struct { const char *name; pdata d; } sets[3];
    sets[0].name = "uniform 1000", sets[0].d = random_particles(1000, 10.0f, 0.1f, 1.0f, 0.5f, 2.0f, 3);
    sets[1].name = "clustered 2000", sets[1].d = clustered_particles(2000);
    sets[2].name = "7 particles", sets[2].d = random_particles(7, 1.0f, 0.1f, 0.2f, 1.0f, 1.0f, 1);
    /* duplicates: several particles at one position */
    for (int i = 1; i < 40; i++) memcpy(sets[0].d.xyz + 3 * i, sets[0].d.xyz, sizeof(float) * 3);
    int leaves[] = {1, 4, 16, 32, 0};
    for (int s = 0; s < 3; s++) {
        pdata *d = &sets[s].d;
        tup *in = malloc(sizeof(tup) * d->n), *got = malloc(sizeof(tup) * d->n);
        for (size_t i = 0; i < d->n; i++)
            in[i] = (tup){d->xyz[3 * i], d->xyz[3 * i + 1], d->xyz[3 * i + 2], d->r[i], d->k[i], d->f[i]};
        qsort(in, d->n, sizeof(tup), tup_cmp);
        for (int li = 0; li < 5; li++) {
            lc_volume *p = make_particles(dev, d, leaves[li]);
            if (!p) {
                CHECK(0, "BVH %s leaf %d: create failed", sets[s].name, leaves[li]);
                continue;
            }
            lc_particles_info info;
            lc_particles_get_info(p, &info);
            /* the kernel scene under the default parameters (sigma 2, kappa 1) */
            void *ks = NULL;
            uint64_t scratch_bytes = 0;
            if (p->ops->sample_scene(dev, p, &ks, &scratch_bytes) != LC_OK) {
                CHECK(0, "BVH %s leaf %d: kernel scene: %s", sets[s].name, leaves[li], lc_last_error());
                lc_volume_destroy(p);
                continue;
            }
            lc_kparticles k = *(const lc_kparticles *)ks;
            int leaf = leaves[li] ? leaves[li] : 4;
            bvh_walk w = {&k, calloc(d->n, sizeof(int)), calloc((size_t)k.nnodes + 1, sizeof(int)), leaf, 0, 0, 0};
            double ksum = 0.0;
            walk(&w, 0, 0, &ksum);
            int once = 0, unvisited = 0;
            for (size_t i = 0; i < d->n; i++) once += w.seen[i] == 1;
            for (int i = 0; i < k.nnodes; i++) unvisited += w.visited[i] == 0;
            for (size_t i = 0; i < d->n; i++)
                got[i] = (tup){k.px[i], k.py[i], k.pz[i], k.r[i], k.k[i], k.field[i]};
            qsort(got, d->n, sizeof(tup), tup_cmp);
            int same = memcmp(in, got, sizeof(tup) * d->n) == 0;
            /* rmax at the root is the largest radius */
            int root_ok = k.node_rmax[0] == info.max_radius;
            CHECK(w.errors == 0 && once == (int)d->n && same && unvisited == 0 && w.max_depth == k.depth &&
                      info.bvh_depth == k.depth && info.bvh_nodes == k.nnodes && info.leaf_size == leaf && root_ok &&
                      (size_t)k.count == d->n,
                  "BVH %-14s leaf %2d: %d nodes, %d leaves, depth %d (walk %d), each particle once %d/%zu, data = input %s, "
                  "%d unreachable nodes, %d structure errors", sets[s].name, leaf, k.nnodes, w.nleaves, k.depth,
                  w.max_depth, once, d->n, same ? "yes" : "NO", unvisited, w.errors);
            free(w.seen), free(w.visited);
            lci_aligned_free(ks);
            lc_volume_destroy(p);
        }
        free(in), free(got);
        pdata_free(d);
    }
    lc_device_destroy(dev);
}

/* ---------------------------------------------------------------- images */

typedef struct scene {
    const char *name;
    int data;                /* dataset index; scenes of one dataset share one volume per target */
    int width, height, tile;
    lc_camera cam;
    int tf;                  /* transfer function index */
    float range[2], dt, alpha_stop;
    lc_shading shading;
    lc_lighting light;
    float sigma, kappa, scale;
} scene;

/* colour points [v, r, g, b], opacity points [v, tau] */
static const float c_heat[] = {0.0f, 0.1f, 0.0f, 0.3f, 0.4f, 0.9f, 0.2f, 0.1f, 1.0f, 1.0f, 1.0f, 0.6f};
static const float o_heat[] = {0.0f, 0.0f, 0.1f, 0.0f, 1.0f, 3.0f};
static const float c_f1[] = {0.0f, 0.0f, 0.3f, 0.1f, 1.0f, 0.2f, 1.0f, 0.4f};
static const float o_f1[] = {0.0f, 0.0f, 0.2f, 0.5f, 0.7f, 1.0f, 1.0f, 4.0f};
static const float c_f2[] = {0.0f, 0.2f, 0.2f, 1.0f, 0.5f, 0.6f, 0.2f, 0.9f, 1.0f, 0.9f, 0.9f, 1.0f};
static const float o_f2[] = {0.0f, 0.0f, 0.3f, 0.0f, 0.6f, 2.5f, 1.0f, 1.0f};
static const float o_thin[] = {0.0f, 0.0f, 0.05f, 0.0f, 1.0f, 0.25f};

static lc_tf_field tf_sets[3][3];
static int tf_count[3];

static void init_tfs(void)
{
    /* 0: one heat TF, range from [0, kappa] */
    tf_sets[0][0] = (lc_tf_field){c_heat, 3, o_heat, 3, 0, {0, 0}};
    tf_count[0] = 1;
    /* 1: three fields with their own TFs: field 0 its own range, field 1 another, field 2 the default */
    tf_sets[1][0] = (lc_tf_field){c_heat, 3, o_heat, 3, 1, {0.0f, 1.5f}};
    tf_sets[1][1] = (lc_tf_field){c_f1, 2, o_f1, 4, 1, {0.2f, 2.0f}};
    tf_sets[1][2] = (lc_tf_field){c_f2, 3, o_f2, 4, 0, {0, 0}};
    tf_count[1] = 3;
    /* 2: thin, for large clustered data */
    tf_sets[2][0] = (lc_tf_field){c_heat, 3, o_thin, 3, 0, {0, 0}};
    tf_count[2] = 1;
}

#define L0 {0, 0, 0, 0}
#define PERSP(ex, ey, ez, ax, ay, az, fov) {LC_PERSPECTIVE, {ex, ey, ez}, {ax, ay, az}, {0, 1, 0}, fov, 0}


/* ---------------------------------------------------------------- the reference of a scene */

/* The transfer functions as doubles of the same float points, for the reference. */
static double tf_color_d[3][3][12], tf_opacity_d[3][3][8];

static void init_ref_tfs(void)
{
    for (int t = 0; t < 3; t++)
        for (int f = 0; f < tf_count[t]; f++) {
            const lc_tf_field *l = &tf_sets[t][f];
            for (int i = 0; i < 4 * l->ncolor; i++) tf_color_d[t][f][i] = l->color[i];
            for (int i = 0; i < 2 * l->nopacity; i++) tf_opacity_d[t][f][i] = l->opacity[i];
        }
}

/* One ref_tf per data field with the value range lanecast resolves: the
 * render's range if set, else the field's TF range if it has one, else the
 * particles' peaks kappa k_i and 0 (lanecast.h, lc_volume_info.range); one
 * TF in the set is shared by every data field. */
static void scene_ref_tfs(const scene *s, const pdata *d, double kappa, ref_tf *out)
{
    int have_range = s->range[0] != 0.0f || s->range[1] != 0.0f, nfields = d->nfields < 1 ? 1 : d->nfields;
    double klo = 0.0, khi = 0.0;
    for (size_t i = 0; i < d->n; i++) klo = fmin(klo, kappa * d->k[i]), khi = fmax(khi, kappa * d->k[i]);
    for (int f = 0; f < nfields; f++) {
        int tfi = tf_count[s->tf] == 1 ? 0 : f;
        const lc_tf_field *l = &tf_sets[s->tf][tfi];
        double lo, hi;
        if (have_range) lo = s->range[0], hi = s->range[1];
        else if (l->has_range) lo = l->range[0], hi = l->range[1];
        else lo = klo, hi = khi;
        if (!(hi > lo)) hi = lo + 1.0;
        out[f] = (ref_tf){lo, hi, tf_color_d[s->tf][tfi], l->ncolor, tf_opacity_d[s->tf][tfi], l->nopacity};
    }
}

static ref_camera ref_camera_of(const lc_camera *c)
{
    ref_camera r = {c->projection == LC_ORTHOGRAPHIC ? REF_ORTHOGRAPHIC : REF_PERSPECTIVE,
                    {c->eye.x, c->eye.y, c->eye.z}, {c->at.x, c->at.y, c->at.z}, {c->up.x, c->up.y, c->up.z},
                    c->fovy == 0.0f ? 40.0 : c->fovy, c->height};
    return r;
}

/* The reference image of a scene (premultiplied C, A in double): ref_core with
 * the particle evaluator and, for a sphere scale, lanecast's opaque spheres. */
static void ref_for(const scene *s, const pdata *d, double *out)
{
    double sigma = s->sigma == 0.0f ? 2.0 : s->sigma, kappa = s->kappa == 0.0f ? 1.0 : s->kappa;
    refset rs = refset_make(d, sigma, kappa);
    ref_tf tf[REF_MAX_FIELDS];
    scene_ref_tfs(s, d, kappa, tf);
    ref_source src;
    ref_sphere_set spheres = {&rs.set, s->scale};
    ref_params q = {0};
    q.width = s->width, q.height = s->height;
    q.camera = ref_camera_of(&s->cam);
    q.mode = REF_MODE_DVR;
    q.tf = tf;
    q.dt = s->dt;
    q.alpha_stop = s->alpha_stop;
    q.shading = s->shading == LC_SHADE_PHONG ? REF_SHADE_PHONG : s->shading == LC_SHADE_DIFFUSE ? REF_SHADE_DIFFUSE
                                                                                                : REF_SHADE_NONE;
    q.ka = s->light.ka, q.kd = s->light.kd, q.ks = s->light.ks, q.p = s->light.phong_exp;
    if (s->scale > 0.0f) q.surface = ref_particles_spheres, q.surface_user = &spheres;
    if (ref_particles_source(&rs.set, &src) != 0 || ref_render(&src, &q, out) != 0)
        CHECK(0, "reference render of %s", s->name);
    refset_free(&rs);
}

static lc_status render(lc_device *dev, lc_volume *p, const lc_tf *tf, const scene *s, lc_method m, int packet,
                        float alpha_stop, float *out)
{
    lc_particle_params pp = {.sigma = s->sigma, .kappa = s->kappa, .sphere_scale = s->scale};
    lc_status st = lc_particles_set_params(p, &pp);
    if (st != LC_OK) {
        printf("lc_particles_set_params: %s\n", lc_last_error());
        return st;
    }
    lc_render_desc rd = {.width = s->width, .height = s->height, .camera = s->cam, .tf = tf,
                         .range = {s->range[0], s->range[1]}, .volume = p, .dt = s->dt, .alpha_stop = alpha_stop,
                         .shading = s->shading, .lighting = s->light, .method = m, .packet = packet, .tile = s->tile};
    st = lc_render(dev, &rd, out, NULL);
    if (st != LC_OK) printf("lc_render: %s\n", lc_last_error());
    return st;
}

/* ---------------------------------------------------------------- images */

enum { NDATA = 6, NASTOP = 5, NMETHODS = 3 };

static const struct { const char *name; lc_method m; int packet; } methods[NMETHODS] = {
    {"coherent8", LC_METHOD_COHERENT, 8}, {"coherent1", LC_METHOD_COHERENT, 1}, {"direct", LC_METHOD_DIRECT, 0}};

/* Everything the image checks share: scenes, data, the reference images (as
 * doubles and as the floats imgcmp takes) and the worst cases seen. */
typedef struct img_ctx {
    const scene *scenes;
    int nscenes;
    const pdata *data;
    double **refs, **refs_stop; /* per scene; per alpha_stop scene */
    float **want, **want_stop;
    const int *astop_scenes;    /* NASTOP scenes rendered again with alpha_stop = astop */
    float astop;
    imgcmp_worst w_ref, w_c8, w_stop;
} img_ctx;

static float *to_float(const double *d, size_t n)
{
    float *f = malloc(sizeof(float) * n);
    for (size_t i = 0; i < n; i++) f[i] = (float)d[i];
    return f;
}

/* The one image check of this test: imgcmp (NaN or Inf fails) quietly, a diff
 * image in outdir on failure; r receives the figures for the caller's line. */
static int check_image(const char *scene_name, const char *tn, const char *method, const char *what, const float *got,
                       const float *want, int w, int h, double max_255, double min_psnr, imgcmp_result *r)
{
    char label[256];
    snprintf(label, sizeof label, "%s_%s_%s_%s", scene_name, tn, method, what);
    return imgcmp_check_ex(label, got, want, w, h, max_255, min_psnr, outdir, 1, r);
}

static void reference_renders(img_ctx *c)
{
    printf("   reference renders ...\n");
    fflush(stdout);
    for (int i = 0; i < c->nscenes; i++) {
        const scene *s = &c->scenes[i];
        int n = s->width * s->height, cov = 0;
        c->refs[i] = malloc(sizeof(double) * 4 * (size_t)n);
        ref_for(s, &c->data[s->data], c->refs[i]);
        c->want[i] = to_float(c->refs[i], 4 * (size_t)n);
        double ma = 0, mc = 0;
        for (int q = 0; q < n; q++) {
            ma += c->refs[i][4 * q + 3] / n, mc += (c->refs[i][4 * q] + c->refs[i][4 * q + 1] + c->refs[i][4 * q + 2]) / (3.0 * n);
            cov += c->refs[i][4 * q + 3] > 0.01;
        }
        /* shows the scenes are not vacuous: mean opacity and colour, pixels with A > 0.01 */
        printf("   ref %-22s %dx%d: mean A %.3f, mean rgb %.3f, %d/%d pixels with A > 0.01\n", s->name, s->width,
               s->height, ma, mc, cov, n);
    }
    for (int j = 0; j < NASTOP; j++) {
        scene s = c->scenes[c->astop_scenes[j]];
        size_t nv = 4 * (size_t)s.width * s.height;
        s.alpha_stop = c->astop;
        c->refs_stop[j] = malloc(sizeof(double) * nv);
        ref_for(&s, &c->data[s.data], c->refs_stop[j]);
        c->want_stop[j] = to_float(c->refs_stop[j], nv);
        double m = 0;
        for (size_t q = 0; q < nv; q++) m = fmax(m, fabs(c->refs_stop[j][q] - c->refs[c->astop_scenes[j]][q]));
        CHECK(m <= 1.0 - c->astop + 1e-12, "ref    %-22s alpha_stop %.2f vs 1: max diff %.4f <= %.4f", s.name,
              (double)c->astop, m, 1.0 - c->astop);
    }
}

/* Early termination bound of one scene, target and method, against this
 * target's and method's alpha_stop = 1 image full; the reference at alpha_stop
 * for information. */
static void check_alpha_stop(img_ctx *c, lc_device *dev, lc_volume *p, const lc_tf *tf, int si, int j, int mi,
                             const char *tn, const float *full, float *img)
{
    const scene *s = &c->scenes[si];
    imgcmp_result r, rr;
    render(dev, p, tf, s, methods[mi].m, methods[mi].packet, c->astop, img);
    /* 1e-6: alpha_stop itself is a float; no PSNR bound */
    int rc = check_image(s->name, tn, methods[mi].name, "astop-vs-1", img, full, s->width, s->height,
                         (1.0 - c->astop + 1e-6) * 255.0, IMGCMP_NO_PSNR_BOUND, &r);
    imgcmp_stats(img, c->want_stop[j], s->width, s->height, 2.0, &rr);
    imgcmp_worst_add(&c->w_stop, &rr);
    CHECK(rc == 0, "img    %-22s %-6s %-9s alpha_stop %.2f vs 1: max diff %.4f <= %.4f%s "
          "(vs ref at %.2f: max %6.3f/255, PSNR %6.1f dB)", s->name, tn, methods[mi].name, (double)c->astop,
          r.max_diff_255 / 255.0, 1.0 - c->astop, r.nonfinite ? ", NaN/Inf" : "", (double)c->astop, rr.max_diff_255,
          rr.psnr_db);
}

/* Every method of one scene on one target: against the reference, against
 * coherent8, and the early termination bound. */
static void check_scene(img_ctx *c, lc_device *dev, lc_volume *p, const lc_tf *tf, int si, const char *tn, float *img8,
                        float *img, float *imgs)
{
    const scene *s = &c->scenes[si];
    for (int mi = 0; mi < NMETHODS; mi++) {
        float *out = mi == 0 ? img8 : img;
        imgcmp_result r;
        lc_status st = render(dev, p, tf, s, methods[mi].m, methods[mi].packet, 1.0f, out);
        int ok = check_image(s->name, tn, methods[mi].name, "vs-ref", out, c->want[si], s->width, s->height, 0, 0, &r) == 0;
        ok = ok && st == LC_OK;
        if (s->data == 3) ok = ok && r.max_diff_255 == 0.0; /* empty: exactly zero */
        imgcmp_worst_add(&c->w_ref, &r);
        CHECK(ok, "img    %-22s %-6s %-9s vs ref: max diff %6.3f/255, PSNR %6.1f dB%s", s->name, tn, methods[mi].name,
              r.max_diff_255, r.psnr_db, r.nonfinite ? ", NaN/Inf" : "");
        if (mi > 0) {
            int rc = check_image(s->name, tn, methods[mi].name, "vs-coherent8", out, img8, s->width, s->height, 0, 0, &r);
            imgcmp_worst_add(&c->w_c8, &r);
            CHECK(rc == 0, "img    %-22s %-6s %-9s vs coherent8: max diff %6.3f/255, PSNR %6.1f dB%s", s->name, tn,
                  methods[mi].name, r.max_diff_255, r.psnr_db, r.nonfinite ? ", NaN/Inf" : "");
        }
        for (int j = 0; j < NASTOP; j++)
            if (c->astop_scenes[j] == si) check_alpha_stop(c, dev, p, tf, si, j, mi, tn, out, imgs);
    }
}

static void images_on_target(img_ctx *c, lc_target t)
{
    lc_device *dev = device_for(t);
    const char *tn = lc_target_name(t);
    size_t npix_max = 48 * 40;
    float *img = malloc(sizeof(float) * 4 * npix_max), *img8 = malloc(sizeof(float) * 4 * npix_max);
    float *imgs = malloc(sizeof(float) * 4 * npix_max);
    lc_tf *tfs[3];
    for (int i = 0; i < 3; i++)
        if (lc_tf_create(dev, tf_sets[i], tf_count[i], &tfs[i]) != LC_OK) printf("lc_tf_create: %s\n", lc_last_error());
    for (int di = 0; di < NDATA; di++) {
        /* one volume per dataset: sigma, kappa and sphere scale change between renders without a rebuild
           (lc_particles_set_params) */
        lc_volume *p = make_particles(dev, &c->data[di], 0);
        if (!p) {
            CHECK(0, "create dataset %d on %s", di, tn);
            continue;
        }
        for (int si = 0; si < c->nscenes; si++)
            if (c->scenes[si].data == di) check_scene(c, dev, p, tfs[c->scenes[si].tf], si, tn, img8, img, imgs);
        lc_volume_destroy(p);
    }
    for (int i = 0; i < 3; i++) lc_tf_destroy(tfs[i]);
    lc_device_destroy(dev);
    free(img), free(img8), free(imgs);
}

/* Self-check: an all-NaN library image goes through the same check as every
 * library image above and must fail it ("ok" here means it failed). */
static void nan_self_check(const img_ctx *c)
{
    const scene *s = &c->scenes[0];
    size_t nv = 4 * (size_t)s->width * s->height;
    float *nan_img = malloc(sizeof(float) * nv);
    for (size_t i = 0; i < nv; i++) nan_img[i] = NAN;
    imgcmp_result r;
    printf("   self-check: an all-NaN image through the image check (the FAIL line below is expected)\n");
    int rc = check_image(s->name, "self-check", "all-NaN", "vs-ref", nan_img, c->want[0], s->width, s->height, 0, 0, &r);
    CHECK(rc == 1 && r.nonfinite == (long)nv, "self-check: an all-NaN image fails the image check (%ld NaN values)",
          r.nonfinite);
    free(nan_img);
}

static void test_images(void)
{
    printf("-- images: coherent (8x8 and lane packets) and direct vs the reference core\n");
    init_tfs();
    init_ref_tfs();
    pdata data[NDATA];
    data[0] = random_particles(200, 4.0f, 0.3f, 0.8f, 0.5f, 1.5f, 1);
    data[1] = random_particles(300, 4.0f, 0.3f, 0.9f, 0.5f, 1.5f, 3);
    data[2] = clustered_particles(300);
    data[3] = pdata_alloc(0, 1);
    data[4] = random_particles(150, 4.0f, 0.3f, 0.7f, 0.3f, 1.0f, 1);
    data[5] = random_particles(400, 3.0f, 0.2f, 0.6f, 0.5f, 1.2f, 2);
    const lc_lighting own = {0.1f, 0.7f, 0.5f, 8};
    const float A1 = 1.0f;
    scene scenes[] = {
        {"single field", 0, 48, 40, 0, PERSP(2, 3, 16, 0, 0, 0, 35), 0, {0, 0}, 0.05f, A1, LC_SHADE_NONE, L0, 0, 0, 0},
        {"sigma 3 kappa 0.6", 0, 48, 40, 0, PERSP(2, 3, 16, 0, 0, 0, 35), 0, {0, 0}, 0.05f, A1, LC_SHADE_NONE, L0, 3.0f, 0.6f, 0},
        {"sigma 1.5 kappa 2", 0, 48, 40, 0, PERSP(2, 3, 16, 0, 0, 0, 35), 0, {0, 0}, 0.05f, A1, LC_SHADE_NONE, L0, 1.5f, 2.0f, 0},
        {"diffuse", 0, 48, 40, 0, PERSP(2, 3, 16, 0, 0, 0, 35), 0, {0, 0}, 0.05f, A1, LC_SHADE_DIFFUSE, L0, 0, 0, 0},
        {"orthographic", 0, 48, 40, 0, {LC_ORTHOGRAPHIC, {1, -2, 15}, {0, 0, 0}, {0, 1, 0}, 0, 12}, 0, {0, 0}, 0.05f, A1, LC_SHADE_DIFFUSE, L0, 0, 0, 0},
        /* axis-aligned rays (dx = dy = 0 exactly): slab tests must not form 0 * inf */
        {"ortho down -z", 0, 48, 40, 0, {LC_ORTHOGRAPHIC, {0, 0, 15}, {0, 0, 0}, {0, 1, 0}, 0, 12}, 0, {0, 0}, 0.05f, A1, LC_SHADE_DIFFUSE, L0, 0, 0, 0},
        {"ortho down -z spheres", 4, 48, 40, 0, {LC_ORTHOGRAPHIC, {0, 0, 15}, {0, 0, 0}, {0, 1, 0}, 0, 12}, 0, {0, 0}, 0.05f, A1, LC_SHADE_DIFFUSE, L0, 0, 0, 0.6f},
        {"camera inside", 0, 48, 40, 0, PERSP(0.3f, 0.2f, 0.5f, -1, 0.5f, -3, 60), 2, {0, 1.5f}, 0.04f, A1, LC_SHADE_DIFFUSE, L0, 0, 0, 0},
        {"range 0.2,1.2", 0, 48, 40, 0, PERSP(-3, 1, 14, 0, 0, 0, 40), 0, {0.2f, 1.2f}, 0.05f, A1, LC_SHADE_NONE, L0, 0, 0, 0},
        {"multi-field", 1, 48, 40, 0, PERSP(0, 4, 15, 0, 0, 0, 40), 1, {0, 0}, 0.05f, A1, LC_SHADE_NONE, L0, 0, 0, 0},
        {"multi-field phong", 1, 48, 40, 0, PERSP(0, 4, 15, 0, 0, 0, 40), 1, {0, 0}, 0.05f, A1, LC_SHADE_PHONG, own, 0, 0, 0},
        {"multi 45x37 tile 16", 1, 45, 37, 16, PERSP(5, -2, 13, 0, 0, 0, 40), 1, {0, 0}, 0.05f, A1, LC_SHADE_DIFFUSE, L0, 0, 1.3f, 0},
        {"multi 45x37 tile dflt", 1, 45, 37, 0, PERSP(5, -2, 13, 0, 0, 0, 40), 1, {0, 0}, 0.05f, A1, LC_SHADE_DIFFUSE, L0, 0, 1.3f, 0},
        {"clustered 1e-3..10", 2, 48, 40, 0, PERSP(1, 1, 10, 0, 0, 0, 40), 2, {0, 6}, 0.06f, A1, LC_SHADE_DIFFUSE, L0, 0, 0, 0},
        {"clustered close", 2, 48, 40, 0, PERSP(0.3f, 0.2f, 0.8f, 0, 0, 0, 30), 2, {0, 4}, 0.03f, A1, LC_SHADE_NONE, L0, 0, 0, 0},
        {"empty", 3, 48, 40, 0, PERSP(0, 0, 10, 0, 0, 0, 40), 0, {0, 0}, 0.05f, A1, LC_SHADE_NONE, L0, 0, 0, 0},
        {"spheres 0.6 diffuse", 4, 48, 40, 0, PERSP(2, 3, 16, 0, 0, 0, 35), 0, {0, 0}, 0.05f, A1, LC_SHADE_DIFFUSE, L0, 0, 0, 0.6f},
        {"spheres 0.6 unshaded", 4, 48, 40, 0, PERSP(2, 3, 16, 0, 0, 0, 35), 0, {0, 0}, 0.05f, A1, LC_SHADE_NONE, L0, 0, 0, 0.6f},
        {"spheres 2.5 phong", 4, 45, 37, 16, PERSP(-2, 1, 18, 0, 0, 0, 35), 0, {0, 0}, 0.05f, A1, LC_SHADE_PHONG, own, 0, 0.8f, 2.5f},
        {"dense 2 fields", 5, 48, 40, 0, PERSP(1, 2, 11, 0, 0, 0, 40), 0, {0, 0}, 0.04f, A1, LC_SHADE_DIFFUSE, L0, 0, 0, 0},
    };
    const int nscenes = (int)(sizeof scenes / sizeof scenes[0]);
    /* alpha_stop: scenes (no phong, so colours stay <= 1) rendered again with 0.9 */
    static const int astop_scenes[NASTOP] = {0, 3, 7, 14, 17};
    double *refs[64], *refs_stop[NASTOP];
    float *want[64], *want_stop[NASTOP];
    img_ctx c = {scenes, nscenes, data, refs, refs_stop, want, want_stop, astop_scenes, 0.9f,
                 IMGCMP_WORST_INIT, IMGCMP_WORST_INIT, IMGCMP_WORST_INIT};
    reference_renders(&c);
    for (int ti = 0; ti < ntargets; ti++) images_on_target(&c, targets[ti]);
    imgcmp_worst_print("library vs reference (alpha_stop 1)", &c.w_ref);
    imgcmp_worst_print("methods vs coherent8", &c.w_c8);
    imgcmp_worst_print("library vs reference at alpha_stop 0.9 (not checked)", &c.w_stop);
    nan_self_check(&c);
    for (int i = 0; i < nscenes; i++) free(refs[i]), free(want[i]);
    for (int j = 0; j < NASTOP; j++) free(refs_stop[j]), free(want_stop[j]);
    for (int i = 0; i < NDATA; i++) pdata_free(&data[i]);
}

int main(int argc, char **argv)
{
    if (argc > 1) outdir = argv[1];
    setvbuf(stdout, NULL, _IOLBF, 0);
    find_targets();
    test_sample();
    test_bvh();
    test_images();
    return check_summary("test_particles");
}
