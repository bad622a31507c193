/* Particle path correctness (issue 3, Tests): lc_volume_sample (with sigma and
 * kappa set by lc_particles_set_params) against brute force in double, BVH structure, and images of every supported target
 * and method (coherent 8x8 groups, coherent lane-width packets, direct)
 * against the double-precision reference renderer (ref_particles.c) within
 * SPEC.md's tolerances: max per-channel difference <= 2/255 and PSNR >= 50 dB
 * with alpha_stop = 1; with alpha_stop < 1 the difference to the alpha_stop = 1
 * image is at most 1 - alpha_stop per channel.
 * usage: test_particles [OUTDIR]   (diff images of failures go to OUTDIR) */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "lanecast/lanecast.h"
#include "host/kinds/kind.h"
#include "kernels/shared/kparticles.h"
#include "check.h"
#include "ref_particles.h"

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

static ref_particles as_ref(const pdata *d)
{
    ref_particles r = {d->n, d->xyz, d->r, d->k, d->f, d->nfields};
    return r;
}

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

/* Tolerance. Every term is kappa k exp(-d^2 / 2r^2) with d^2/2r^2 <= sigma^2/2:
 * the float exponent argument carries a few ulps (relative ~5e-7 of at most
 * sigma^2/2 = 2), exp itself <= 1e-6 (SPEC.md), so each term is within ~2e-6
 * relative; summing N terms in float adds <= N * 6e-8 of sum|terms|. For the
 * up to ~50 overlapping terms here, 1e-5 * sum|terms| bounds both. The sample
 * point minus the centre is formed in float, an absolute error of ~6e-8 (|x| +
 * |x_i|) per component: it moves phi by |dphi/dx| times that, and the gradient
 * likewise (the pos_sens budgets from ref_field, weighted by 2.4e-7 = 4 ulps). */
static void test_sample(void)
{
    printf("-- lc_volume_sample (particles) vs brute force (double)\n");
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
        /* points: near particle centres (inside the support and around its edge) and uniform incl. outside */
        float *pts = malloc(sizeof(float) * 3 * npts);
        for (int i = 0; i < npts; i++) {
            if (i % 2 == 0) {
                size_t j = (size_t)(rnd() * d.n);
                float dist = d.r[j] * urand(0.0f, 2.5f);
                double dir[3] = {rnd() - 0.5, rnd() - 0.5, rnd() - 0.5}, l = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
                for (int a = 0; a < 3; a++) pts[3 * i + a] = d.xyz[3 * j + a] + (float)(dist * dir[a] / l);
            } else {
                for (int a = 0; a < 3; a++) pts[3 * i + a] = urand(-1.5f * cases[c].h, 1.5f * cases[c].h);
            }
        }
        double sigma = cases[c].sigma == 0.0f ? 2.0 : cases[c].sigma, kappa = cases[c].kappa == 0.0f ? 1.0 : cases[c].kappa;
        int nf = cases[c].nf;
        ref_particles rp = as_ref(&d);
        double *rv = malloc(sizeof(double) * npts * nf), *rg = malloc(sizeof(double) * 3 * npts * nf);
        double *tv = malloc(sizeof(double) * npts * nf), *tg = malloc(sizeof(double) * npts * nf);
        int *amb = malloc(sizeof(int) * npts), nzero = 0, namb = 0;
        for (int i = 0; i < npts; i++) {
            double x[3] = {pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]}, as[8], gas[8], ps[8], gps[8];
            ref_field(&rp, sigma, kappa, x, rv + (size_t)i * nf, rg + (size_t)i * 3 * nf, as, gas, ps, gps, &amb[i]);
            namb += amb[i];
            for (int f = 0; f < nf; f++) {
                tv[(size_t)i * nf + f] = 1e-5 * as[f] + 2.4e-7 * ps[f] + 1e-30;
                tg[(size_t)i * nf + f] = 1e-5 * gas[f] + 2.4e-7 * gps[f] + 1e-30;
                nzero += rv[(size_t)i * nf + f] != 0.0;
            }
        }
        for (int ti = 0; ti < ntargets; ti++) {
            lc_device *dev = device_for(targets[ti]);
            lc_volume *p = make_particles(dev, &d, 0);
            float *v = malloc(sizeof(float) * npts * nf), *g = malloc(sizeof(float) * 3 * npts * nf);
            lc_particle_params pp = {.sigma = cases[c].sigma, .kappa = cases[c].kappa};
            lc_status s = p ? lc_particles_set_params(p, &pp) : LC_ERROR_INTERNAL;
            if (s == LC_OK) s = lc_volume_sample(dev, p, (size_t)npts, pts, v, g);
            int bad = 0, badg = 0, skipped = 0;
            double worst = 0.0, worstg = 0.0;
            for (int i = 0; i < npts && s == LC_OK; i++) {
                if (amb[i]) { skipped++; continue; }
                for (int f = 0; f < nf; f++) {
                    size_t o = (size_t)i * nf + f;
                    double e = fabs(v[o] - rv[o]) / tv[o];
                    worst = e > worst ? e : worst;
                    if (e > 1.0 && bad++ < 3)
                        printf("     point %d field %d: %.9g vs %.9g (tol %.3g)\n", i, f, (double)v[o], rv[o], tv[o]);
                    for (int a = 0; a < 3; a++) {
                        double eg = fabs(g[3 * o + a] - rg[3 * o + a]) / tg[o];
                        worstg = eg > worstg ? eg : worstg;
                        if (eg > 1.0 && badg++ < 3)
                            printf("     point %d field %d grad %d: %.9g vs %.9g (tol %.3g)\n", i, f, a,
                                   (double)g[3 * o + a], rg[3 * o + a], tg[o]);
                    }
                }
            }
            CHECK(s == LC_OK && bad == 0 && badg == 0,
                  "sample %-32s %-6s: %d points x %d fields (%d non-zero), value err/tol %.3f, gradient err/tol %.3f, "
                  "%d points within 1e-5 of a cut-off skipped", cases[c].name, lc_target_name(targets[ti]), npts, nf,
                  nzero, worst, worstg, skipped);
            free(v), free(g);
            lc_volume_destroy(p);
            lc_device_destroy(dev);
        }
        free(rv), free(rg), free(tv), free(tg), free(amb), free(pts);
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

typedef struct cmp { double maxd, psnr; } cmp;

static cmp compare(const float *a, const double *b, int n)
{
    double m = 0.0, se = 0.0;
    for (int i = 0; i < 4 * n; i++) {
        double d = fabs((double)a[i] - b[i]);
        if (!(d <= m)) m = d; /* NaN propagates */
        se += d * d;
    }
    cmp c = {m, se > 0.0 ? 10.0 * log10(1.0 / (se / (4.0 * n))) : INFINITY};
    return c;
}

/* PPM: the library image | the reference | the max channel difference, 2/255 -> white. */
static void write_diff(const char *tag, const float *a, const double *b, int w, int h)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/diff_%s.ppm", outdir, tag);
    for (char *c = path + strlen(outdir) + 1; *c; c++)
        if (*c == ' ' || *c == '/' || *c == ',') *c = '_';
    FILE *fp = fopen(path, "wb");
    if (!fp) {
        printf("     cannot write %s\n", path);
        return;
    }
    fprintf(fp, "P6\n%d %d\n255\n", 3 * w, h);
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            const float *p = a + 4 * ((size_t)y * w + x);
            for (int c = 0; c < 3; c++) fputc((int)lround(255.0 * fmin(fmax(p[c], 0.0), 1.0)), fp);
        }
        for (int x = 0; x < w; x++) {
            const double *p = b + 4 * ((size_t)y * w + x);
            for (int c = 0; c < 3; c++) fputc((int)lround(255.0 * fmin(fmax(p[c], 0.0), 1.0)), fp);
        }
        for (int x = 0; x < w; x++) {
            double m = 0;
            for (int c = 0; c < 4; c++) m = fmax(m, fabs(a[4 * ((size_t)y * w + x) + c] - b[4 * ((size_t)y * w + x) + c]));
            int v = (int)fmin(255.0, m * 255.0 * 127.5);
            fputc(v, fp), fputc(v, fp), fputc(v, fp);
        }
    }
    fclose(fp);
    printf("     diff image: %s\n", path);
}

static void ref_for(const scene *s, const pdata *d, double *out)
{
    ref_particles rp = as_ref(d);
    ref_params q = {s->width, s->height, s->cam, tf_sets[s->tf], tf_count[s->tf], {s->range[0], s->range[1]}, s->dt,
                    s->alpha_stop, s->shading, s->light, s->sigma == 0 ? 2.0f : s->sigma,
                    s->kappa == 0 ? 1.0f : s->kappa, s->scale};
    if (ref_render(&rp, &q, out) != 0) printf("ref_render failed for %s\n", s->name);
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

static void test_images(void)
{
    printf("-- images: coherent (8x8 and lane packets) and direct vs the double-precision reference\n");
    init_tfs();
    enum { NDATA = 6 };
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
    const int astop_scenes[] = {0, 3, 7, 14, 17};
    const float astop = 0.9f;
    double *refs[64], *refs_stop[8];
    size_t npix_max = 48 * 40;
    printf("   reference renders ...\n");
    fflush(stdout);
    for (int i = 0; i < nscenes; i++) {
        refs[i] = malloc(sizeof(double) * 4 * (size_t)scenes[i].width * scenes[i].height);
        ref_for(&scenes[i], &data[scenes[i].data], refs[i]);
        int n = scenes[i].width * scenes[i].height, cov = 0;
        double ma = 0, mc = 0;
        for (int q = 0; q < n; q++) {
            ma += refs[i][4 * q + 3] / n, mc += (refs[i][4 * q] + refs[i][4 * q + 1] + refs[i][4 * q + 2]) / (3.0 * n);
            cov += refs[i][4 * q + 3] > 0.01;
        }
        /* shows the scenes are not vacuous: mean opacity and colour, pixels with A > 0.01 */
        printf("   ref %-22s %dx%d: mean A %.3f, mean rgb %.3f, %d/%d pixels with A > 0.01\n", scenes[i].name,
               scenes[i].width, scenes[i].height, ma, mc, cov, n);
    }
    for (int j = 0; j < 5; j++) {
        scene s = scenes[astop_scenes[j]];
        s.alpha_stop = astop;
        refs_stop[j] = malloc(sizeof(double) * 4 * (size_t)s.width * s.height);
        ref_for(&s, &data[s.data], refs_stop[j]);
        double m = 0;
        for (size_t q = 0; q < 4 * (size_t)s.width * s.height; q++) m = fmax(m, fabs(refs_stop[j][q] - refs[astop_scenes[j]][q]));
        CHECK(m <= 1.0 - astop + 1e-12, "ref    %-22s alpha_stop %.2f vs 1: max diff %.4f <= %.4f", s.name, (double)astop,
              m, 1.0 - astop);
    }
    float *img = malloc(sizeof(float) * 4 * npix_max), *img8 = malloc(sizeof(float) * 4 * npix_max);
    float *imgs = malloc(sizeof(float) * 4 * npix_max);
    static const struct { const char *name; lc_method m; int packet; } methods[] = {
        {"coherent8", LC_METHOD_COHERENT, 8}, {"coherent1", LC_METHOD_COHERENT, 1}, {"direct", LC_METHOD_DIRECT, 0}};
    for (int ti = 0; ti < ntargets; ti++) {
        lc_device *dev = device_for(targets[ti]);
        const char *tn = lc_target_name(targets[ti]);
        lc_tf *tfs[3];
        for (int t = 0; t < 3; t++)
            if (lc_tf_create(dev, tf_sets[t], tf_count[t], &tfs[t]) != LC_OK) printf("lc_tf_create: %s\n", lc_last_error());
        for (int di = 0; di < NDATA; di++) {
            /* one volume per dataset: sigma, kappa and sphere scale change between renders without a rebuild
               (lc_particles_set_params) */
            lc_volume *p = make_particles(dev, &data[di], 0);
            if (!p) {
                CHECK(0, "create dataset %d on %s", di, tn);
                continue;
            }
            for (int si = 0; si < nscenes; si++) {
                const scene *s = &scenes[si];
                if (s->data != di) continue;
                int n = s->width * s->height;
                for (int mi = 0; mi < 3; mi++) {
                    float *out = mi == 0 ? img8 : img;
                    lc_status st = render(dev, p, tfs[s->tf], s, methods[mi].m, methods[mi].packet, 1.0f, out);
                    cmp c = compare(out, refs[si], n);
                    int ok = st == LC_OK && c.maxd <= 2.0 / 255.0 && c.psnr >= 50.0;
                    if (di == 3) ok = ok && c.maxd == 0.0; /* empty: exactly zero */
                    CHECK(ok, "img    %-22s %-6s %-9s vs ref: max diff %6.3f/255, PSNR %6.1f dB", s->name, tn,
                          methods[mi].name, c.maxd * 255.0, c.psnr);
                    if (!ok) {
                        char tag[256];
                        snprintf(tag, sizeof tag, "%s_%s_%s", s->name, tn, methods[mi].name);
                        write_diff(tag, out, refs[si], s->width, s->height);
                    }
                    if (mi > 0) {
                        double *as_d = malloc(sizeof(double) * 4 * n);
                        for (int q = 0; q < 4 * n; q++) as_d[q] = img8[q];
                        cmp c2 = compare(out, as_d, n);
                        free(as_d);
                        CHECK(c2.maxd <= 2.0 / 255.0 && c2.psnr >= 50.0,
                              "img    %-22s %-6s %-9s vs coherent8: max diff %6.3f/255, PSNR %6.1f dB", s->name, tn,
                              methods[mi].name, c2.maxd * 255.0, c2.psnr);
                    }
                    /* early termination bound, against this target's and method's alpha_stop = 1 image */
                    for (int j = 0; j < 5; j++) {
                        if (astop_scenes[j] != si) continue;
                        render(dev, p, tfs[s->tf], s, methods[mi].m, methods[mi].packet, astop, imgs);
                        double m = 0;
                        for (int q = 0; q < 4 * n; q++) m = fmax(m, fabs((double)imgs[q] - out[q]));
                        cmp c3 = compare(imgs, refs_stop[j], n);
                        /* 1e-6: alpha_stop itself is a float */
                        CHECK(m <= 1.0 - astop + 1e-6, "img    %-22s %-6s %-9s alpha_stop %.2f vs 1: max diff %.4f <= %.4f "
                              "(vs ref at %.2f: max %6.3f/255, PSNR %6.1f dB)", s->name, tn, methods[mi].name,
                              (double)astop, m, 1.0 - astop, (double)astop, c3.maxd * 255.0, c3.psnr);
                    }
                }
            }
            lc_volume_destroy(p);
        }
        for (int t = 0; t < 3; t++) lc_tf_destroy(tfs[t]);
        lc_device_destroy(dev);
    }
    free(img), free(img8), free(imgs);
    for (int i = 0; i < nscenes; i++) free(refs[i]);
    for (int j = 0; j < 5; j++) free(refs_stop[j]);
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
