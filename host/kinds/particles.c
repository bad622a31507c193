/* Particle scene objects (Knoll 2014): validation, copy into leaf-ordered
 * structure-of-arrays, the Embree BVH, and the per-frame kernel scene.
 * A desc with defer_bvh keeps the particles in the desc's order and builds
 * the BVH when a render or a sample first needs it (ensure_bvh): a
 * projection reads the particles only, and the build is most of a large
 * set's load (docs/bench/sph.md). */
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/kinds/kind.h"
#include "host/api/tf.h"
#include "bvh/particle_bvh.h"
#include "host/kinds/particles_cstep.h"
#include "host/kinds/particles_frame.h"
#include "host/sph/sph_kernel.h"

_Static_assert(LC_KSPH_M4 == (int)LC_KERNEL_M4 && LC_KSPH_M5 == (int)LC_KERNEL_M5 && LC_KSPH_M6 == (int)LC_KERNEL_M6 &&
                   LC_KSPH_C2 == (int)LC_KERNEL_WENDLAND_C2 && LC_KSPH_C4 == (int)LC_KERNEL_WENDLAND_C4 &&
                   LC_KSPH_C6 == (int)LC_KERNEL_WENDLAND_C6 && LC_KSPH_GAUSSIAN == (int)LC_KERNEL_GAUSSIAN,
               "kernel ids: kparticles.h against lanecast.h");

typedef struct particles {
    lc_volume base; /* first: the kind-neutral handle */
    lc_particles_info info;
    lci_pbvh bvh;
    float *node_ksum; /* per node: sum of |k_i| below it */
    float *node_fbound; /* per node and field: field bound (field_bounds); NULL = none */
    float fbound_sigma; /* the support sigma node_fbound was computed for */
    lc_kernel fbound_kernel; /* and the kernel */
    float *node_ksph;   /* SPH kernels: per node the sum of the peaks |k_i| norm / H_i^3 below it */
    lc_kernel ksph_kernel; /* the kernel node_ksph holds (LC_KERNEL_GAUSSIAN: none) */
    double kh3min, kh3max; /* of the k_i / r_i^3 and 0: an SPH kernel's default range is kappa norm times them */
    float *px, *py, *pz, *r, *nir, *k; /* leaf order */
    float *kn; /* leaf order: the desc's norm_weights (m_i / rho_i), or NULL */
    float amin, amax; /* with kn: of the A_i = k_i / kn_i, the normalised field's default range */
    float kmin, kmax; /* of the k_i and 0: the default value range is kappa times them */
    uint8_t *field;
    uint32_t *src; /* leaf order -> index in the lc_particles_desc (projections pair sets by it) */
    atomic_int built;      /* the BVH, the leaf order and the node bounds exist */
    int canonical;         /* desc.canonical_order, and its box (resolved at creation) */
    lc_box3 order_box;
    pthread_mutex_t bvh_mu; /* guards the deferred build and the arrays' pointers while it swaps them */
    void *retired[9];      /* the desc-ordered arrays a deferred build replaced: a projection or a
                              resample on another thread may still read them (freed by destroy) */
    pthread_mutex_t cs_mu; /* guards cs */
    lci_vcache_entry *cs;  /* an lci_pcstep: the recurrence ratios for the last step (particles_cstep.c) */
    size_t global_count;   /* a part of a data-parallel load: the whole set's count (lci_particles_set_global) */
    void *part;            /* and what host/mpi/ keeps with it (its region, tree, ghost reach) */
    void (*part_free)(void *);
} particles;

/* A support radius grown so float round-off never leaves out a cell a sample
 * the kernels count as inside (they test d^2 < (sigma r)^2). */
static float grow_support(float rs) { return rs * 1.001f + 1e-6f; }

/* The support radius in units of r_i: sigma for the Gaussian; an SPH
 * kernel's support is r_i = H_i itself (lanecast.h lc_kernel). */
static float support_sigma(const lc_particle_params *q) { return q->kernel == LC_KERNEL_GAUSSIAN ? q->sigma : 1.0f; }

static void field_bounds(particles *p);

static void destroy(lc_volume *v)
{
    particles *p = (particles *)v;
    if (!p) return;
    lci_pbvh_free(&p->bvh);
    lci_vcache_release(p->cs);
    pthread_mutex_destroy(&p->cs_mu);
    pthread_mutex_destroy(&p->bvh_mu);
    for (size_t i = 0; i < sizeof p->retired / sizeof p->retired[0]; i++) free(p->retired[i]);
    free(p->node_ksum);
    free(p->node_fbound);
    free(p->node_ksph);
    free(p->px);
    free(p->py);
    free(p->pz);
    free(p->r);
    free(p->nir);
    free(p->k);
    free(p->kn);
    free(p->field);
    free(p->src);
    if (p->part_free) p->part_free(p->part);
    free(p);
}

/* Zero fields become SPEC.md's defaults; the ranges are checked. */
static lc_status fill_params(lc_device *dev, const char *fn, const lc_particle_params *in, lc_particle_params *out)
{
    lc_particle_params q = in ? *in : (lc_particle_params){0};
    q.sigma = q.sigma == 0.0f ? 2.0f : q.sigma;
    q.kappa = q.kappa == 0.0f ? 1.0f : q.kappa;
    if (!(q.sigma > 0.0f && q.sigma <= 100.0f))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: sigma = %g, expected (0, 100]", fn, (double)q.sigma);
    if (!isfinite(q.kappa))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: kappa = %g, expected a finite value", fn, (double)q.kappa);
    if (!(q.sphere_scale >= 0.0f && q.sphere_scale <= 100.0f))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: sphere scale = %g, expected [0, 100]", fn,
                         (double)q.sphere_scale);
    if (q.buffer_samples < 0 || q.buffer_samples > 4096)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: buffer samples = %d, expected 0 (default) to 4096", fn,
                         q.buffer_samples);
    if (!lc_kernel_name(q.kernel))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: kernel = %d, expected an lc_kernel value", fn, (int)q.kernel);
    if (q.normalise != 0 && q.normalise != 1)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: normalise = %d, expected 0 or 1", fn, q.normalise);
    if (q.normalise && q.kernel == LC_KERNEL_GAUSSIAN)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "%s: normalise = 1 is the normalised SPH interpolant and needs an SPH kernel (kernel is gaussian)",
                         fn);
    *out = q;
    return LC_OK;
}

lc_status lc_particles_get_info(const lc_volume *v, lc_particles_info *out)
{
    const particles *p = lci_volume_as(v, LC_KIND_PARTICLES, "lc_particles_get_info");
    if (!p) return LC_ERROR_INVALID_ARGUMENT;
    if (!out) return lci_error(v->device, LC_ERROR_INVALID_ARGUMENT, "lc_particles_get_info: out is NULL");
    pthread_mutex_t *mu = (pthread_mutex_t *)&p->bvh_mu; /* a deferred build writes its figures */
    pthread_mutex_lock(mu);
    *out = p->info;
    pthread_mutex_unlock(mu);
    return LC_OK;
}

/* floor(x) as a cell index clamped to [0, dim - 1]; NaN gives 0. */
static inline int cell_index(float x, int dim)
{
    float f = floorf(x);
    return !(f >= 0.0f) ? 0 : f >= (float)(dim - 1) ? dim - 1 : (int)f;
}

/* Transparent-space skipping (issue 8): for every node and field a bound of
 * |Phi_f| / |kappa| over the samples the node's particles reach, so a dvr
 * traversal may skip the node when |kappa| * bound lies where the field's TF
 * has zero extinction (prepare, lci_tf_clear_below). A coarse grid of cells (side
 * at least the largest support radius, at most 128 per axis) sums, over
 * every particle whose support box overlaps a cell, |k_i| times its
 * Gaussian's largest value in the cell (padded against round-off); a leaf takes the largest
 * cell sum over the cells its grown box overlaps, an inner node the larger of
 * its children (its particles reach only their own leaves' grown boxes). An
 * SPH kernel's largest value over a cell is its peak |k_i| norm / H^3 times
 * f at the cell point nearest the centre (f decreases; not a product over
 * the axes). It depends on sigma and the kernel, not on kappa: recomputed
 * when either changes, not rebuilt.
 * Zero for fields a node holds no particle of. Out of memory: NULL, no
 * skipping. */

static void field_bounds(particles *p)
{
    free(p->node_fbound);
    p->node_fbound = NULL;
    p->fbound_sigma = support_sigma(&p->info.params);
    p->fbound_kernel = p->info.params.kernel;
    const lci_sph_kernel *sk = lci_sph_kernel_get(p->info.params.kernel);
    int nn = p->bvh.nnodes, nf = p->info.nfields;
    if (nn <= 0) return;
    float sig = p->fbound_sigma, R = sig * p->info.max_radius;
    lc_box3 b = p->info.bounds;
    float lo[3] = {b.lo.x - R, b.lo.y - R, b.lo.z - R}, ext[3] = {b.hi.x - b.lo.x + 2 * R, b.hi.y - b.lo.y + 2 * R,
                                                                   b.hi.z - b.lo.z + 2 * R};
    /* cells of side >= R: a support spans at most 3 per axis (4 with round-off) */
    float h = fmaxf(R * 1.01f, fmaxf(ext[0], fmaxf(ext[1], ext[2])) / 128.0f);
    if (!(h > 0.0f) || !isfinite(h)) return;
    int dim[3];
    for (int a = 0; a < 3; a++) dim[a] = (int)(ext[a] / h) + 1;
    size_t cells = (size_t)dim[0] * (size_t)dim[1] * (size_t)dim[2];
    float *g = calloc(cells * (size_t)nf, sizeof *g);
    float *nb = calloc((size_t)nn * (size_t)nf, sizeof *nb);
    if (!g || !nb) {
        free(g), free(nb);
        return;
    }
    const float inv = 1.0f / h;
    /* clamped in float before converting: with a tiny radius the cell index
       can be far outside int (undefined behaviour, found by UBSan's
       float-cast-overflow) */
#define CELL_RANGE(c, r, a, i0, i1)                                                                                    \
    int i0 = cell_index(((c) - (r) - lo[a]) * inv, dim[a]), i1 = cell_index(((c) + (r) - lo[a]) * inv, dim[a]);
    for (size_t j = 0; j < p->info.count; j++) {
        float rs = grow_support(sig * p->r[j]), ak = fabsf(p->k[j]);
        CELL_RANGE(p->px[j], rs, 0, x0, x1)
        CELL_RANGE(p->py[j], rs, 1, y0, y1)
        CELL_RANGE(p->pz[j], rs, 2, z0, z1)
        /* the Gaussian's largest value over a cell, at the cell point nearest the
           centre: a product of one factor per axis */
        float pc[3] = {p->px[j], p->py[j], p->pz[j]}, e[3][4] = {{0}};
        int i0[3] = {x0, y0, z0}, i1[3] = {x1, y1, z1};
        float nir2 = 1.0f / (2.0f * p->r[j] * p->r[j]);
        for (int a = 0; a < 3; a++)
            for (int q = 0; q < 4 && i0[a] + q <= i1[a]; q++) {
                float clo = lo[a] + (float)(i0[a] + q) * h, chi = clo + h, dd = 0.0f;
                if (pc[a] < clo) dd = clo - pc[a];
                else if (pc[a] > chi) dd = pc[a] - chi;
                dd = fmaxf(0.0f, dd - 1e-3f * h); /* round-off: never below the true maximum */
                /* 1e-4 covers expf's and the argument's round-off; SPH: the squared distance */
                e[a][q] = sk ? dd * dd : expf(-dd * dd * nir2) * 1.0001f;
            }
        if (sk) {
            double H = p->r[j], amp = (double)ak * sk->norm / (H * H * H) * 1.0001;
            for (int z = z0; z <= z1; z++)
                for (int y = y0; y <= y1; y++) {
                    float *row = g + (((size_t)z * (size_t)dim[1] + (size_t)y) * (size_t)dim[0]) * (size_t)nf + p->field[j];
                    for (int x = x0; x <= x1; x++) {
                        double u = sqrt((double)e[0][x - x0] + (double)e[1][y - y0] + (double)e[2][z - z0]) / H;
                        row[(size_t)x * (size_t)nf] += (float)(amp * sk->f(u));
                    }
                }
            continue;
        }
        for (int z = z0; z <= z1; z++)
            for (int y = y0; y <= y1; y++) {
                float eyz = ak * e[1][y - y0] * e[2][z - z0];
                float *row = g + (((size_t)z * (size_t)dim[1] + (size_t)y) * (size_t)dim[0]) * (size_t)nf + p->field[j];
                for (int x = x0; x <= x1; x++) row[(size_t)x * (size_t)nf] += eyz * e[0][x - x0];
            }
    }
    /* children follow their parent in the flat array: one backward sweep */
    for (int32_t n = nn - 1; n >= 0; n--) {
        const lc_kpnode *node = &p->bvh.nodes[n];
        float *out = nb + (size_t)n * (size_t)nf;
        if (node->count == 0) {
            const float *c0 = nb + (size_t)node->first * (size_t)nf, *c1 = c0 + nf;
            for (int f = 0; f < nf; f++) out[f] = fmaxf(c0[f], c1[f]);
            continue;
        }
        int has[LC_MAX_FIELDS] = {0};
        for (int32_t i = node->first; i < node->first + node->count; i++) has[p->field[i]] = 1;
        float rs = grow_support(sig * p->bvh.rmax[n]);
        float cx = 0.5f * (node->lo[0] + node->hi[0]), cy = 0.5f * (node->lo[1] + node->hi[1]),
              cz = 0.5f * (node->lo[2] + node->hi[2]);
        float hx = rs + 0.5f * (node->hi[0] - node->lo[0]), hy = rs + 0.5f * (node->hi[1] - node->lo[1]),
              hz = rs + 0.5f * (node->hi[2] - node->lo[2]);
        CELL_RANGE(cx, hx, 0, x0, x1)
        CELL_RANGE(cy, hy, 1, y0, y1)
        CELL_RANGE(cz, hz, 2, z0, z1)
        for (int z = z0; z <= z1; z++)
            for (int y = y0; y <= y1; y++)
                for (int x = x0; x <= x1; x++) {
                    const float *c = g + (((size_t)z * (size_t)dim[1] + (size_t)y) * (size_t)dim[0] + (size_t)x) *
                                             (size_t)nf;
                    for (int f = 0; f < nf; f++)
                        if (has[f]) out[f] = fmaxf(out[f], c[f]);
                }
    }
#undef CELL_RANGE
    free(g);
    p->node_fbound = nb;
}

/* node_ksph for the current kernel (an SPH kernel's peaks |k_i| norm / H_i^3
 * summed per node, rounded up), computed when the kernel changes; kept for
 * the Gaussian, which does not read it. */
static lc_status sph_sums(particles *p)
{
    const lci_sph_kernel *sk = lci_sph_kernel_get(p->info.params.kernel);
    if (!sk || p->ksph_kernel == p->info.params.kernel) return LC_OK;
    size_t nn = (size_t)(p->bvh.nnodes > 0 ? p->bvh.nnodes : 1);
    if (!p->node_ksph && !(p->node_ksph = malloc(sizeof(float) * nn)))
        return lci_error(p->base.device, LC_ERROR_OUT_OF_MEMORY, "particles: out of memory for %zu node bounds", nn);
    for (int32_t n = p->bvh.nnodes - 1; n >= 0; n--) {
        const lc_kpnode *node = &p->bvh.nodes[n];
        double sum = 0.0;
        if (node->count == 0) sum = (double)p->node_ksph[node->first] + (double)p->node_ksph[node->first + 1];
        else
            for (int32_t i = node->first; i < node->first + node->count; i++) {
                double H = p->r[i];
                sum += fabs((double)p->k[i]) * sk->norm / (H * H * H);
            }
        p->node_ksph[n] = (float)sum * (1.0f + 1e-6f);
    }
    p->ksph_kernel = p->info.params.kernel;
    return LC_OK;
}

lc_status lc_particles_set_params(lc_volume *v, const lc_particle_params *params)
{
    particles *p = lci_volume_as(v, LC_KIND_PARTICLES, "lc_particles_set_params");
    if (!p) return LC_ERROR_INVALID_ARGUMENT;
    lc_particle_params q;
    lc_status s = fill_params(v->device, "lc_particles_set_params", params, &q);
    if (s == LC_OK && q.normalise && !p->kn && p->info.count > 0)
        s = lci_error(v->device, LC_ERROR_INVALID_ARGUMENT,
                      "lc_particles_set_params: normalise = 1, but the particles were created without norm_weights");
    if (s != LC_OK) return s;
    p->info.params = q;
    if (!atomic_load_explicit(&p->built, memory_order_acquire)) return LC_OK; /* the build computes the bounds */
    s = sph_sums(p);
    if (s == LC_OK && (support_sigma(&p->info.params) != p->fbound_sigma || p->info.params.kernel != p->fbound_kernel))
        field_bounds(p);
    return s;
}

/* Sum of |k_i| under every node: children follow their parent in the flat
 * array, so one backward sweep sees children first. */
static void node_sums(particles *p)
{
    for (int32_t n = p->bvh.nnodes - 1; n >= 0; n--) {
        const lc_kpnode *node = &p->bvh.nodes[n];
        double s = 0.0;
        if (node->count == 0) s = (double)p->node_ksum[node->first] + (double)p->node_ksum[node->first + 1];
        else
            for (int32_t i = node->first; i < node->first + node->count; i++) s += fabs((double)p->k[i]);
        p->node_ksum[n] = (float)s * (1.0f + 1e-6f); /* round up: a bound */
    }
}

/* Why particle i is invalid, or NULL. */
/* Coordinates and radii are bounded so that every extent the BVH builder and
 * the kernels form (max - min, centre +- sigma r with sigma <= 100) stays far
 * from float overflow: Embree's binning asserts (aborts) on infinite extents. */
#define MAX_COORD 1e18f

static const char *invalid(const lc_particles_desc *d, size_t i, int nfields)
{
    const float *x = d->positions + 3 * i;
    if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2])) return "non-finite position";
    if (fabsf(x[0]) > MAX_COORD || fabsf(x[1]) > MAX_COORD || fabsf(x[2]) > MAX_COORD)
        return "a coordinate beyond +-1e18";
    float r = d->radii ? d->radii[i] : d->radius;
    if (!(r > 0.0f) || !isfinite(r)) return "radius not finite and > 0";
    if (r > MAX_COORD) return "radius beyond 1e18";
    if (d->values && !isfinite(d->values[i])) return "non-finite value";
    if (d->norm_weights && !(d->norm_weights[i] > 0.0f && isfinite(d->norm_weights[i])))
        return "norm weight not finite and > 0";
    if (d->fields && d->fields[i] >= nfields) return "field id >= nfields";
    return NULL;
}

/* The field count (nfields, or 1 + the largest id) and the desc's limits. */
static lc_status check_desc(lc_device *dev, const lc_particles_desc *d, int *nfields_out)
{
    if (d->count > 0 && !d->positions)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_particles_create: %zu particles but positions is NULL",
                         d->count);
    if (d->count > (size_t)INT32_MAX / 2)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_particles_create: %zu particles, at most %d", d->count,
                         INT32_MAX / 2);
    int leaf = d->leaf_size == 0 ? 4 : d->leaf_size;
    if (leaf < 1 || leaf > 32)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_particles_create: leaf_size = %d, expected 1 to 32",
                         d->leaf_size);
    int nfields = d->nfields;
    if (nfields < 0 || nfields > LC_MAX_FIELDS)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_particles_create: nfields = %d, expected 0 (auto) to %d",
                         nfields, LC_MAX_FIELDS);
    if (nfields == 0) {
        int mx = 0;
        if (d->fields)
            for (size_t i = 0; i < d->count; i++) mx = d->fields[i] > mx ? d->fields[i] : mx;
        if (mx >= LC_MAX_FIELDS) {
            size_t first = 0, bad = 0;
            for (size_t i = 0; i < d->count; i++)
                if (d->fields[i] >= LC_MAX_FIELDS) first = bad++ ? first : i;
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                             "lc_particles_create: particle %zu has field id %d; at most %d fields (%zu particles affected)",
                             first, d->fields[first], LC_MAX_FIELDS, bad);
        }
        nfields = mx + 1;
    }
    *nfields_out = nfields;
    return LC_OK;
}

/* The particles kept, as arrays the BVH builds from: the caller's when
 * nothing is dropped, else compacted copies (src maps them back). */
typedef struct kept {
    size_t n, bad;
    const float *xyz, *rad;
    float *own_xyz, *own_rad;
    size_t *src;
} kept;

static lc_status keep_valid(lc_device *dev, const lc_particles_desc *d, int nfields, kept *k)
{
    size_t first_bad = 0;
    const char *why = NULL;
    for (size_t i = 0; i < d->count; i++) {
        const char *w = invalid(d, i, nfields);
        if (w) {
            if (!k->bad) first_bad = i, why = w;
            k->bad++;
        }
    }
    if (k->bad && !d->drop_invalid)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "lc_particles_create: %zu of %zu particles are invalid; the first is particle %zu (%s)", k->bad,
                         d->count, first_bad, why);
    size_t n = k->n = d->count - k->bad;
    k->xyz = d->positions, k->rad = d->radii;
    if (!k->bad) return LC_OK;
    k->own_xyz = malloc(sizeof(float) * 3 * (n ? n : 1));
    k->own_rad = malloc(sizeof(float) * (n ? n : 1));
    k->src = malloc(sizeof(size_t) * (n ? n : 1));
    if (!k->own_xyz || !k->own_rad || !k->src)
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_particles_create: out of memory for %zu particles", n);
    for (size_t i = 0, j = 0; i < d->count; i++) {
        if (invalid(d, i, nfields)) continue;
        memcpy(k->own_xyz + 3 * j, d->positions + 3 * i, sizeof(float) * 3);
        k->own_rad[j] = d->radii ? d->radii[i] : d->radius;
        k->src[j++] = i;
    }
    k->xyz = k->own_xyz, k->rad = k->own_rad;
    return LC_OK;
}

/* Radius range and centre bounds of the kept particles. */
static void measure(const kept *k, float radius, lc_particles_info *info)
{
    info->min_radius = INFINITY;
    info->max_radius = 0.0f;
    lc_box3 bb = {{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
    for (size_t j = 0; j < k->n; j++) {
        const float *x = k->xyz + 3 * j;
        float rj = k->rad ? k->rad[j] : radius;
        info->min_radius = fminf(info->min_radius, rj);
        info->max_radius = fmaxf(info->max_radius, rj);
        bb.lo.x = fminf(bb.lo.x, x[0]), bb.lo.y = fminf(bb.lo.y, x[1]), bb.lo.z = fminf(bb.lo.z, x[2]);
        bb.hi.x = fmaxf(bb.hi.x, x[0]), bb.hi.y = fmaxf(bb.hi.y, x[1]), bb.hi.z = fmaxf(bb.hi.z, x[2]);
    }
    if (k->n == 0) {
        bb = (lc_box3){{0, 0, 0}, {0, 0, 0}};
        info->min_radius = info->max_radius = 0.0f;
    }
    info->bounds = bb;
}

/* Structure-of-arrays copies in the BVH's leaf order (the kept order while
 * the build is deferred), and the node sums. */
static lc_status leaf_order(lc_device *dev, const lc_particles_desc *d, const kept *k, particles *p)
{
    size_t n = k->n, m = n ? n : 1;
    p->px = malloc(sizeof(float) * m), p->py = malloc(sizeof(float) * m), p->pz = malloc(sizeof(float) * m);
    p->r = malloc(sizeof(float) * m), p->nir = malloc(sizeof(float) * m), p->k = malloc(sizeof(float) * m);
    p->field = malloc(m);
    p->src = malloc(sizeof(uint32_t) * m);
    p->node_ksum = malloc(sizeof(float) * (size_t)(p->bvh.nnodes > 0 ? p->bvh.nnodes : 1));
    if (d->norm_weights) p->kn = malloc(sizeof(float) * m);
    if (!p->px || !p->py || !p->pz || !p->r || !p->nir || !p->k || !p->field || !p->src || !p->node_ksum ||
        (d->norm_weights && !p->kn))
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_particles_create: out of memory for %zu particles", n);
    p->amin = INFINITY, p->amax = -INFINITY;
    for (size_t j = 0; j < n; j++) {
        uint32_t o = p->bvh.order ? p->bvh.order[j] : (uint32_t)j; /* deferred: the kept order */
        size_t i = k->src ? k->src[o] : o;
        float ro = k->rad ? k->rad[o] : d->radius;
        p->px[j] = k->xyz[3 * o], p->py[j] = k->xyz[3 * o + 1], p->pz[j] = k->xyz[3 * o + 2];
        p->r[j] = ro;
        p->nir[j] = -1.0f / (2.0f * ro * ro);
        p->k[j] = d->values ? d->values[i] : 1.0f;
        p->kmin = p->k[j] < p->kmin ? p->k[j] : p->kmin, p->kmax = p->k[j] > p->kmax ? p->k[j] : p->kmax;
        double kh3 = (double)p->k[j] / ((double)ro * ro * ro);
        p->kh3min = kh3 < p->kh3min ? kh3 : p->kh3min, p->kh3max = kh3 > p->kh3max ? kh3 : p->kh3max;
        p->field[j] = d->fields ? d->fields[i] : 0;
        p->src[j] = (uint32_t)i;
        if (p->kn) {
            p->kn[j] = d->norm_weights[i];
            float a = p->k[j] / p->kn[j];
            p->amin = fminf(p->amin, a), p->amax = fmaxf(p->amax, a);
        }
    }
    free(p->bvh.order);
    p->bvh.order = NULL;
    node_sums(p);
    return LC_OK;
}

/* The BVH over the particles in their kept order: the canonical one
 * (bvh/particle_bvh_canon.c) over order_box (all zero: the kept centres'
 * bounds at creation), ties by value, norm weight and field (tie arrays
 * indexed by src[j], or j when src is NULL); Embree's with canonical_order
 * -1 (lci_pbvh_canonical: LANECAST_PBVH_BUILDER for A/B runs). */
static lc_status build_bvh(lc_device *dev, const float *xyz, const float *rad, float radius, size_t n,
                           const float *const tie[2], const uint8_t *tag, const size_t *src, particles *p)
{
    char err[256];
    int r;
    if (!lci_pbvh_canonical(p->canonical)) {
        void *e = lci_embree_device(dev);
        if (!e) return LC_ERROR_INTERNAL;
        r = lci_pbvh_build(e, xyz, rad, radius, n, p->info.leaf_size, &p->bvh, err, sizeof err);
    } else {
        const lc_box3 *box = &p->order_box;
        lci_pbvh_keys q = {{box->lo.x, box->lo.y, box->lo.z}, {box->hi.x, box->hi.y, box->hi.z},
                           {tie[0], tie[1], NULL}, tag, src};
        r = lci_pbvh_build_canonical(xyz, rad, radius, n, p->info.leaf_size, &q, &p->bvh, err, sizeof err);
    }
    return r == 0 ? LC_OK : lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_particles_create: BVH build failed: %s", err);
}

/* The node bounds once the arrays are in leaf order, and the build's figures. */
static lc_status finish_build(lc_device *dev, particles *p, double t0)
{
    lc_status s = sph_sums(p);
    if (s == LC_OK) field_bounds(p);
    lc_particles_info *info = &p->info;
    info->build_seconds = lci_now() - t0;
    info->bvh_nodes = p->bvh.nnodes;
    info->bvh_depth = p->bvh.depth;
    info->bvh_bytes = (size_t)p->bvh.nnodes * (sizeof(lc_kpnode) + (2 + (size_t)info->nfields) * sizeof(float));
    if (s == LC_OK)
        lci_log(dev, LC_LOG_INFO, "particles: %zu (%zu dropped), %d fields, BVH %d nodes depth %d, %.1f MB, %.3f s",
                info->count, info->dropped, info->nfields, p->bvh.nnodes, p->bvh.depth, (double)info->bvh_bytes / 1e6,
                info->build_seconds);
    return s;
}

/* The particle arrays in the BVH's leaf order: new arrays, all or none, the
 * old ones retired (readers that took them before the swap keep reading
 * them; destroy frees them). */
static lc_status permute_all(lc_device *dev, particles *p)
{
    void **arr[] = {(void **)&p->px, (void **)&p->py, (void **)&p->pz, (void **)&p->r, (void **)&p->nir,
                    (void **)&p->k, (void **)&p->kn, (void **)&p->src, (void **)&p->field};
    const size_t el[] = {4, 4, 4, 4, 4, 4, 4, 4, 1}, n = p->info.count;
    _Static_assert(sizeof arr / sizeof arr[0] == sizeof p->retired / sizeof p->retired[0], "one retired slot per array");
    const uint32_t *order = p->bvh.order;
    char *o[9] = {0};
    int ok = 1;
    for (int i = 0; i < 9; i++)
        if (*arr[i] && !(o[i] = malloc(el[i] * (n ? n : 1)))) ok = 0;
    if (!ok) {
        for (int i = 0; i < 9; i++) free(o[i]);
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_render: out of memory ordering %zu particles", n);
    }
    for (int i = 0; i < 9; i++) {
        if (!o[i]) continue;
        const char *in = *arr[i];
        for (size_t j = 0; j < n; j++) memcpy(o[i] + j * el[i], in + (size_t)order[j] * el[i], el[i]);
        p->retired[i] = *arr[i];
        *arr[i] = o[i];
    }
    return LC_OK;
}

/* The deferred build (desc.defer_bvh), under bvh_mu: the BVH over the kept
 * order, the arrays permuted into its leaf order, the node bounds for the
 * current parameters. The same BVH and arrays as an immediate build's (same
 * input in the same order), so renders do not depend on when it ran. */
static lc_status deferred_build(lc_device *dev, particles *p)
{
    size_t n = p->info.count;
    double t0 = lci_now();
    float *xyz = malloc(sizeof(float) * 3 * (n ? n : 1));
    if (!xyz) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_render: out of memory building the BVH of %zu particles", n);
    for (size_t j = 0; j < n; j++) xyz[3 * j] = p->px[j], xyz[3 * j + 1] = p->py[j], xyz[3 * j + 2] = p->pz[j];
    /* the kept order's own arrays as the canonical ties (the desc's values, or 1 for all: equal
       ties either way; src NULL: arrays indexed by the kept index) */
    const float *tie[2] = {p->k, p->kn};
    lc_status s = n > 0 ? build_bvh(dev, xyz, p->r, 0.0f, n, tie, p->field, NULL, p) : LC_OK;
    free(xyz);
    float *ksum = s == LC_OK ? malloc(sizeof(float) * (size_t)(p->bvh.nnodes > 0 ? p->bvh.nnodes : 1)) : NULL;
    if (s == LC_OK && !ksum) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_render: out of memory for the BVH's nodes");
    if (s == LC_OK && p->bvh.order) s = permute_all(dev, p);
    if (s != LC_OK) { /* no BVH; the arrays as they were */
        free(ksum);
        lci_pbvh_free(&p->bvh);
        memset(&p->bvh, 0, sizeof p->bvh);
        return s;
    }
    free(p->bvh.order);
    p->bvh.order = NULL;
    free(p->node_ksum);
    p->node_ksum = ksum;
    node_sums(p);
    return finish_build(dev, p, t0);
}

/* The BVH of a deferred set, built once (any thread; the first caller builds,
 * the others wait for it). */
static lc_status ensure_bvh(lc_device *dev, const lc_volume *v)
{
    particles *p = (particles *)v; /* the build and the pointers' swap: behind bvh_mu */
    if (atomic_load_explicit(&p->built, memory_order_acquire)) return LC_OK;
    pthread_mutex_lock(&p->bvh_mu);
    lc_status s = LC_OK;
    if (!atomic_load_explicit(&p->built, memory_order_relaxed) && (s = deferred_build(dev, p)) == LC_OK)
        atomic_store_explicit(&p->built, 1, memory_order_release);
    pthread_mutex_unlock(&p->bvh_mu);
    return s;
}

static lc_status create(lc_device *dev, const void *desc, lc_volume **out)
{
    const lc_particles_desc *d = desc;
    *out = NULL;
    int nfields = 1;
    lc_particle_params params;
    lc_status s = check_desc(dev, d, &nfields);
    if (s == LC_OK) s = fill_params(dev, "lc_particles_create", &d->params, &params);
    if (s == LC_OK && params.normalise && !d->norm_weights && d->count > 0)
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                      "lc_particles_create: params.normalise = 1 needs norm_weights (the m_i / rho_i of the denominator)");
    if (s != LC_OK) return s;
    kept k = {0};
    particles *p = NULL;
    s = keep_valid(dev, d, nfields, &k);
    if (s == LC_OK && !(p = calloc(1, sizeof *p)))
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_particles_create: out of memory");
    if (s == LC_OK && pthread_mutex_init(&p->cs_mu, NULL) != 0) {
        free(p), p = NULL; /* destroy would destroy the mutex */
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_particles_create: out of memory (a mutex)");
    }
    if (s == LC_OK && pthread_mutex_init(&p->bvh_mu, NULL) != 0) {
        pthread_mutex_destroy(&p->cs_mu);
        free(p), p = NULL;
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_particles_create: out of memory (a mutex)");
    }
    if (s == LC_OK) {
        p->base.ops = &lci_particles_ops;
        p->base.device = dev;
        lc_particles_info *info = &p->info;
        info->params = params;
        info->count = k.n;
        info->dropped = k.bad;
        info->nfields = nfields;
        info->leaf_size = d->leaf_size == 0 ? 4 : d->leaf_size;
        if (d->radius_note) snprintf(info->radius_note, sizeof info->radius_note, "%s", d->radius_note);
        measure(&k, d->radius, info);
        static const lc_box3 none;
        p->canonical = d->canonical_order;
        p->order_box = memcmp(&d->order_box, &none, sizeof none) ? d->order_box : info->bounds;
        info->data_bytes = k.n * (6 * sizeof(float) + sizeof(uint32_t) + 1);
        if (d->defer_bvh) s = leaf_order(dev, d, &k, p); /* the kept order; ensure_bvh builds */
        else {
            double t0 = lci_now();
            const float *tie[2] = {d->values, d->norm_weights};
            if (k.n > 0) s = build_bvh(dev, k.xyz, k.rad, d->radius, k.n, tie, d->fields, k.src, p);
            if (s == LC_OK) s = leaf_order(dev, d, &k, p);
            if (s == LC_OK) s = finish_build(dev, p, t0);
            atomic_store_explicit(&p->built, 1, memory_order_release);
        }
    }
    free(k.own_xyz);
    free(k.own_rad);
    free(k.src);
    if (s != LC_OK) {
        destroy(p ? &p->base : NULL);
        return s;
    }
    *out = &p->base;
    return LC_OK;
}

lc_status lc_particles_create(lc_device *dev, const lc_particles_desc *desc, lc_volume **out)
{
    if (!dev) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_particles_create: device is NULL");
    if (!out) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_particles_create: out is NULL");
    *out = NULL;
    if (!desc) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_particles_create: desc is NULL");
    return create(dev, desc, out);
}

/* The centre bounds grown by the larger of the support and the spheres. */
static lc_box3 grown_bounds(const particles *p)
{
    const lc_particle_params *q = &p->info.params;
    float g = fmaxf(support_sigma(q), q->sphere_scale) * p->info.max_radius;
    lc_box3 b = p->info.bounds;
    b.lo.x -= g, b.lo.y -= g, b.lo.z -= g;
    b.hi.x += g, b.hi.y += g, b.hi.z += g;
    return b;
}

static lc_status frame_info(lc_device *dev, const lc_volume *v, lci_frame_info *out)
{
    (void)dev;
    const particles *p = (const particles *)v;
    out->bounds = grown_bounds(p);
    /* a quarter of the smallest radius resolves every Gaussian; an SPH
       kernel's support is its radius, its core about half of it: an eighth */
    const lci_sph_kernel *sk = lci_sph_kernel_get(p->info.params.kernel);
    out->default_dt = p->info.count || p->global_count ? (sk ? 0.125f : 0.25f) * p->info.min_radius : 1.0f;
    /* a particle's own peak is kappa k_i (SPH kernels: kappa k_i norm / H^3):
       the range spans them and 0, so values such as B-factors or charges (and
       a negative kappa) map onto the TF rather than past it; unit values and
       kappa > 0 give [0, kappa] for the Gaussian */
    float kappa = p->info.params.kappa, a = kappa * p->kmin, b = kappa * p->kmax;
    if (sk) a = (float)(kappa * sk->norm * p->kh3min), b = (float)(kappa * sk->norm * p->kh3max);
    /* a weighted mean of the A_i (a part: the whole set's, even holding none) */
    if (p->info.params.normalise && p->amin <= p->amax) a = p->amin, b = p->amax;
    float lo = a < b ? a : b, hi = a < b ? b : a; /* kmin <= 0 <= kmax: both hold 0 */
    out->default_range[0] = lo;
    out->default_range[1] = hi > lo ? hi : lo + 1.0f;
    out->nfields = p->info.nfields;
    return LC_OK;
}

/* The kernel view of the particles under the current parameters. */
static void kscene(const particles *p, lc_kparticles *k)
{
    const lc_particle_params *q = &p->info.params;
    memset(k, 0, sizeof *k);
    k->nodes = p->bvh.nodes;
    k->node_rmax = p->bvh.rmax;
    k->node_ksum = p->node_ksum;
    k->px = p->px, k->py = p->py, k->pz = p->pz;
    k->r = p->r;
    k->neg_inv_2r2 = p->nir;
    k->k = p->k;
    k->field = p->field;
    k->count = (int64_t)p->info.count;
    k->nnodes = p->bvh.nnodes;
    k->depth = p->bvh.depth;
    k->nfields = p->info.nfields;
    k->sigma = support_sigma(q);
    k->kappa = q->kappa;
    const lci_sph_kernel *sk = lci_sph_kernel_get(q->kernel);
    k->kernel = (int32_t)q->kernel;
    k->knorm = sk ? (float)sk->norm : 0.0f;
    if (sk) k->node_ksum = p->node_ksph; /* sph_sums keeps it for the current kernel */
    k->kn = sk && q->normalise ? p->kn : NULL;
    k->normalise = k->kn != NULL;
    k->max_radius = p->info.max_radius;
    lci_pcoherent_settings(k, p->info.nfields, q->buffer_samples);
    k->sphere_scale = q->sphere_scale;
    lc_box3 b = grown_bounds(p);
    k->lo[0] = b.lo.x, k->lo[1] = b.lo.y, k->lo[2] = b.lo.z, k->lo[3] = 0.0f;
    k->hi[0] = b.hi.x, k->hi[1] = b.hi.y, k->hi[2] = b.hi.z, k->hi[3] = 0.0f;
}

/* This frame's node flags: 1 where every field present below the node has
 * |kappa| * bound <= clear_below[f], the largest value the frame's TF of
 * field f makes fully transparent (fields absent below it have bound 0). One
 * byte per node, ~1 ms per million nodes; left NULL when no node is clear,
 * so frames that cannot skip pay nothing in the traversals. */
static void clear_nodes(const particles *p, lc_kparticles *k, const float *clear_below, uint8_t *flags)
{
    int nf = p->info.nfields;
    float ak = fabsf(k->kappa);
    long n_clear = 0;
    for (int32_t n = 0; n < p->bvh.nnodes; n++) {
        const float *b = p->node_fbound + (size_t)n * (size_t)nf;
        int c = 1;
        for (int f = 0; f < nf && c; f++) c = !(b[f] > 0.0f) || ak * b[f] <= clear_below[f];
        flags[n] = (uint8_t)c;
        n_clear += c;
    }
    k->node_clear = n_clear ? flags : NULL;
}

/* LANECAST_PARTICLE_SKIP=0 turns transparent-space skipping off (A/B runs
 * and tests: the images agree within SPEC.md's tolerances). */
static int skip_enabled(void) { return lci_env_long("LANECAST_PARTICLE_SKIP", 0, 1, 1) != 0; }

/* LANECAST_PARTICLE_CSTEP=0 leaves the recurrence ratios to the kernel
 * (tests: the same image, bit for bit). */
static int cstep_enabled(void) { return lci_env_long("LANECAST_PARTICLE_CSTEP", 0, 1, 1) != 0; }

/* A frame's kernel scene and the cached table it reads (released after the frame). */
typedef struct pframe {
    lc_kparticles k;
    lci_pcstep *cs;
} pframe;

static void pframe_release(void *owned)
{
    pframe *pf = owned;
    lci_pcstep_release(pf->cs);
    lci_aligned_free(pf);
}

static lc_status prepare(lc_device *dev, const lc_volume *v, const lc_render_desc *d, const lc_kframe *frame,
                         lci_prepared *out)
{
    lc_method m = d->method == LC_METHOD_DEFAULT ? LC_METHOD_COHERENT : d->method;
    if (m != LC_METHOD_COHERENT && m != LC_METHOD_DIRECT)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "method %d does not apply to particles (coherent or direct)",
                         (int)d->method);
    lc_status bs = ensure_bvh(dev, v);
    if (bs != LC_OK) return bs;
    const particles *p = (const particles *)v;
    if (p->part && !frame->has_region)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "lc_render: these %zu particles are one rank's part of %zu (lc_mpi_volume_load): render them "
                         "with lc_mpi_render",
                         p->info.count, p->global_count);
    /* the normalised interpolant divides per sample: the direct method's
       gather (the coherent deposits carry one sum), no node marked clear */
    const int norm = p->info.params.normalise && p->kn;
    if (norm) m = LC_METHOD_DIRECT;
    int skip = frame->mode == LC_KMODE_DVR && p->node_fbound && skip_enabled() && !norm;
    size_t head = (sizeof(pframe) + 63) & ~(size_t)63;
    pframe *pf = lci_aligned_alloc(64, head + (skip ? (size_t)p->bvh.nnodes : 0));
    if (!pf) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_render: out of memory");
    lc_kparticles *k = &pf->k;
    kscene(p, k);
    k->group_side = lci_pgroup_side(d, lc_target_lanes(dev->target));
    if (m == LC_METHOD_COHERENT && frame->mode != LC_KMODE_SLICE && p->info.count > 0 &&
        p->info.params.kernel == LC_KERNEL_GAUSSIAN && cstep_enabled()) {
        particles *pm = (particles *)v; /* the cache only: behind its mutex */
        pf->cs = lci_pcstep_get(&pm->cs_mu, &pm->cs, p->nir, p->info.count, frame->dt);
        if (!pf->cs) {
            lci_aligned_free(pf);
            return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_render: out of memory (%zu particle step ratios)",
                             p->info.count);
        }
        k->cstep = lci_pcstep_values(pf->cs);
        k->cstep_dt = frame->dt;
    }
    if (skip) {
        float clear_below[LC_KMAX_FIELDS];
        for (int f = 0; f < k->nfields; f++) clear_below[f] = lci_tf_clear_below(&frame->tf[f]);
        clear_nodes(p, k, clear_below, (uint8_t *)pf + head);
    }
    int km = m == LC_METHOD_COHERENT ? LC_KMETHOD_FAST : LC_KMETHOD_BASE;
    const lc_kkind *kk = dev->kt->kind[LC_KKIND_PARTICLES];
    out->tile = kk->render[km];
    out->kscene = k;
    out->scratch_bytes = kk->scratch_bytes[km](k, frame);
    out->owned = pf;
    out->release = pframe_release;
    out->tile_side = lci_ptile_side(frame, k, m == LC_METHOD_COHERENT);
    return LC_OK;
}

static lc_status sample_scene(lc_device *dev, const lc_volume *v, void **ks, uint64_t *scratch_bytes)
{
    lc_status bs = ensure_bvh(dev, v);
    if (bs != LC_OK) return bs;
    lc_kparticles *k = lci_aligned_alloc(64, sizeof *k);
    if (!k) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_volume_sample: out of memory");
    kscene((const particles *)v, k);
    *ks = k;
    *scratch_bytes = dev->kt->kind[LC_KKIND_PARTICLES]->sample_scratch_bytes(k);
    return LC_OK;
}

/* Build options a file load may carry (lc_load_desc), applied to the desc. */
static lc_status set_option(lc_device *dev, void *desc, const lc_option *o, const char *file)
{
    lc_particles_desc *d = desc;
    if (!strcmp(o->key, "leaf_size")) return lci_option_int(dev, file, o, 1, 32, &d->leaf_size);
    if (!strcmp(o->key, "drop_invalid")) return lci_option_int(dev, file, o, 0, 1, &d->drop_invalid);
    if (!strcmp(o->key, "defer_bvh")) return lci_option_int(dev, file, o, 0, 1, &d->defer_bvh);
    if (!strcmp(o->key, "kernel") && lc_kernel_from_name(o->value, &d->params.kernel) != LC_OK)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "%s: option kernel = '%s', expected gaussian, m4, m5, m6, wendland-c2, wendland-c4 or wendland-c6",
                         file, o->value);
    if (!strcmp(o->key, "kernel")) return LC_OK;
    if (!strcmp(o->key, "normalise")) return lci_option_int(dev, file, o, 0, 1, &d->params.normalise);
    if (!strcmp(o->key, "canonical_order")) return lci_option_order(dev, file, o, &d->canonical_order);
    return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: option '%s' does not apply to particles", file, o->key);
}

const lci_kind_ops lci_particles_ops = {
    .kind = LC_KIND_PARTICLES,
    .name = "particles",
    .krow = LC_KKIND_PARTICLES,
    .option_keys = "leaf_size drop_invalid kernel normalise canonical_order defer_bvh",
    .create = create,
    .set_option = set_option,
    .destroy = destroy,
    .frame_info = frame_info,
    .prepare = prepare,
    .sample_scene = sample_scene,
};

lc_status lci_particles_view(const lc_volume *v, const char *fn, lci_particle_view *out)
{
    const particles *p = lci_volume_as(v, LC_KIND_PARTICLES, fn);
    if (!p) return LC_ERROR_INVALID_ARGUMENT;
    pthread_mutex_t *mu = (pthread_mutex_t *)&p->bvh_mu; /* not while a deferred build swaps the arrays */
    pthread_mutex_lock(mu);
    *out = (lci_particle_view){.n = p->info.count, .total = p->info.count + p->info.dropped, .x = p->px, .y = p->py,
                               .z = p->pz, .r = p->r, .k = p->k, .field = p->field, .src = p->src, .params = p->info.params,
                               .bounds = p->info.bounds, .max_radius = p->info.max_radius};
    pthread_mutex_unlock(mu);
    return LC_OK;
}

lc_status lci_particles_centres(const lc_volume *v, size_t *n, const float **x, const float **y, const float **z)
{
    const particles *p = lci_volume_as(v, LC_KIND_PARTICLES, "lci_particles_centres");
    if (!p) return LC_ERROR_INVALID_ARGUMENT;
    pthread_mutex_t *mu = (pthread_mutex_t *)&p->bvh_mu;
    pthread_mutex_lock(mu);
    *n = p->info.count, *x = p->px, *y = p->py, *z = p->pz;
    pthread_mutex_unlock(mu);
    return LC_OK;
}

const char *lci_particles_invalid(const lc_particles_desc *d, size_t i, int nfields) { return invalid(d, i, nfields); }

void lci_particles_extremes(const lc_volume *v, lci_particles_global *g)
{
    const particles *p = (const particles *)v;
    const lc_particles_info *in = &p->info;
    g->count = in->count;
    g->bounds = in->bounds, g->min_radius = in->min_radius, g->max_radius = in->max_radius;
    if (!in->count) { /* measure's zeros would join the reductions: the neutral values instead */
        g->bounds = (lc_box3){{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
        g->min_radius = INFINITY, g->max_radius = 0.0f;
    }
    g->kmin = p->kmin, g->kmax = p->kmax, g->kh3min = p->kh3min, g->kh3max = p->kh3max;
    g->amin = p->kn && in->count ? p->amin : INFINITY, g->amax = p->kn && in->count ? p->amax : -INFINITY;
}

void lci_particles_set_global(lc_volume *v, const lci_particles_global *g, void *part, void (*part_free)(void *))
{
    particles *p = (particles *)v;
    p->global_count = g->count;
    if (g->count) {
        p->info.bounds = g->bounds;
        p->info.min_radius = g->min_radius, p->info.max_radius = g->max_radius;
    }
    p->kmin = g->kmin, p->kmax = g->kmax, p->kh3min = g->kh3min, p->kh3max = g->kh3max;
    p->amin = g->amin, p->amax = g->amax;
    if (p->part_free) p->part_free(p->part);
    p->part = part, p->part_free = part_free;
    if (atomic_load_explicit(&p->built, memory_order_acquire))
        field_bounds(p); /* its cells follow the bounds and the largest radius (a deferred build's too) */
}

void *lci_particles_part(const lc_volume *v)
{
    return lc_volume_kind(v) == LC_KIND_PARTICLES ? ((const particles *)v)->part : NULL;
}
