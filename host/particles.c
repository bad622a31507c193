/* Particle scene objects (Knoll 2014): validation, copy into leaf-ordered
 * structure-of-arrays, the Embree BVH, and the per-frame kernel scene. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <embree3/rtcore.h>
#include "scene.h"
#include "../bvh/particle_bvh.h"

struct lc_particles {
    lc_device *device;
    lc_particles_info info;
    lci_pbvh bvh;
    float *px, *py, *pz, *r, *nir, *k; /* leaf order */
    uint8_t *field;
};

static void embree_error(void *user, enum RTCError code, const char *str)
{
    lci_log(user, LC_LOG_WARNING, "Embree error %d: %s", (int)code, str ? str : "");
}

void *lci_embree_device(lc_device *dev)
{
    if (!dev->embree) {
        char cfg[64];
        snprintf(cfg, sizeof cfg, "threads=%d", dev->threads);
        RTCDevice e = rtcNewDevice(cfg);
        if (!e) {
            lci_error(dev, LC_ERROR_INTERNAL, "Embree: rtcNewDevice failed (error %d)", (int)rtcGetDeviceError(NULL));
            return NULL;
        }
        rtcSetDeviceErrorFunction(e, embree_error, dev);
        dev->embree = e;
    }
    return dev->embree;
}

void lci_embree_release(lc_device *dev)
{
    if (dev->embree) rtcReleaseDevice(dev->embree);
    dev->embree = NULL;
}

void lc_particles_destroy(lc_particles *p)
{
    if (!p) return;
    lci_pbvh_free(&p->bvh);
    free(p->px);
    free(p->py);
    free(p->pz);
    free(p->r);
    free(p->nir);
    free(p->k);
    free(p->field);
    free(p);
}

lc_status lc_particles_get_info(const lc_particles *p, lc_particles_info *out)
{
    if (!p) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_particles_get_info: particles is NULL");
    if (!out) return lci_error(p->device, LC_ERROR_INVALID_ARGUMENT, "lc_particles_get_info: out is NULL");
    *out = p->info;
    return LC_OK;
}

/* Why particle i is invalid, or NULL. */
static const char *invalid(const lc_particles_desc *d, size_t i, int nfields)
{
    const float *x = d->positions + 3 * i;
    if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2])) return "non-finite position";
    float r = d->radii ? d->radii[i] : d->radius;
    if (!(r > 0.0f) || !isfinite(r)) return "radius not finite and > 0";
    if (d->values && !isfinite(d->values[i])) return "non-finite value";
    if (d->fields && d->fields[i] >= nfields) return "field id >= nfields";
    return NULL;
}

lc_status lc_particles_create(lc_device *dev, const lc_particles_desc *d, lc_particles **out)
{
    if (!dev) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_particles_create: device is NULL");
    if (!out) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_particles_create: out is NULL");
    *out = NULL;
    if (!d) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_particles_create: desc is NULL");
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
    /* validate: first bad index and count */
    size_t bad = 0, first_bad = 0;
    const char *why = NULL;
    for (size_t i = 0; i < d->count; i++) {
        const char *w = invalid(d, i, nfields);
        if (w) {
            if (!bad) first_bad = i, why = w;
            bad++;
        }
    }
    if (bad && !d->drop_invalid)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "lc_particles_create: %zu of %zu particles are invalid; the first is particle %zu (%s)", bad,
                         d->count, first_bad, why);
    size_t n = d->count - bad;
    lc_particles *p = calloc(1, sizeof *p);
    if (!p) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_particles_create: out of memory");
    /* With nothing dropped the BVH is built straight from the caller's arrays;
     * otherwise from compacted copies (src maps them back). */
    const float *xyz = d->positions, *rad = d->radii;
    float *own_xyz = NULL, *own_rad = NULL;
    size_t *src = NULL;
    if (bad) {
        own_xyz = malloc(sizeof(float) * 3 * (n ? n : 1));
        own_rad = malloc(sizeof(float) * (n ? n : 1));
        src = malloc(sizeof(size_t) * (n ? n : 1));
        if (!own_xyz || !own_rad || !src) {
            free(p), free(own_xyz), free(own_rad), free(src);
            return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_particles_create: out of memory for %zu particles", n);
        }
        for (size_t i = 0, j = 0; i < d->count; i++) {
            if (invalid(d, i, nfields)) continue;
            memcpy(own_xyz + 3 * j, d->positions + 3 * i, sizeof(float) * 3);
            own_rad[j] = d->radii ? d->radii[i] : d->radius;
            src[j++] = i;
        }
        xyz = own_xyz, rad = own_rad;
    }
    p->device = dev;
    lc_particles_info *info = &p->info;
    info->count = n;
    info->dropped = bad;
    info->nfields = nfields;
    info->leaf_size = leaf;
    info->min_radius = INFINITY;
    info->max_radius = 0.0f;
    lc_box3 bb = {{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
    for (size_t j = 0; j < n; j++) {
        const float *x = xyz + 3 * j;
        float rj = rad ? rad[j] : d->radius;
        info->min_radius = fminf(info->min_radius, rj);
        info->max_radius = fmaxf(info->max_radius, rj);
        bb.lo.x = fminf(bb.lo.x, x[0]), bb.lo.y = fminf(bb.lo.y, x[1]), bb.lo.z = fminf(bb.lo.z, x[2]);
        bb.hi.x = fmaxf(bb.hi.x, x[0]), bb.hi.y = fmaxf(bb.hi.y, x[1]), bb.hi.z = fmaxf(bb.hi.z, x[2]);
    }
    if (n == 0) {
        bb = (lc_box3){{0, 0, 0}, {0, 0, 0}};
        info->min_radius = info->max_radius = 0.0f;
    }
    info->bounds = bb;
    lc_status s = LC_OK;
    double t0 = lci_now();
    if (n > 0) {
        void *e = lci_embree_device(dev);
        char err[256];
        if (!e) s = LC_ERROR_INTERNAL;
        else if (lci_pbvh_build(e, xyz, rad, d->radius, n, leaf, &p->bvh, err, sizeof err) != 0)
            s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_particles_create: BVH build failed: %s", err);
    }
    if (s == LC_OK) {
        size_t m = n ? n : 1;
        p->px = malloc(sizeof(float) * m), p->py = malloc(sizeof(float) * m), p->pz = malloc(sizeof(float) * m);
        p->r = malloc(sizeof(float) * m), p->nir = malloc(sizeof(float) * m), p->k = malloc(sizeof(float) * m);
        p->field = malloc(m);
        if (!p->px || !p->py || !p->pz || !p->r || !p->nir || !p->k || !p->field)
            s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_particles_create: out of memory for %zu particles", n);
    }
    if (s == LC_OK) {
        for (size_t j = 0; j < n; j++) {
            uint32_t o = p->bvh.order[j];
            size_t i = src ? src[o] : o;
            float ro = rad ? rad[o] : d->radius;
            p->px[j] = xyz[3 * o], p->py[j] = xyz[3 * o + 1], p->pz[j] = xyz[3 * o + 2];
            p->r[j] = ro;
            p->nir[j] = -1.0f / (2.0f * ro * ro);
            p->k[j] = d->values ? d->values[i] : 1.0f;
            p->field[j] = d->fields ? d->fields[i] : 0;
        }
        free(p->bvh.order);
        p->bvh.order = NULL;
        info->build_seconds = lci_now() - t0;
        info->bvh_nodes = p->bvh.nnodes;
        info->bvh_depth = p->bvh.depth;
        info->bvh_bytes = (size_t)p->bvh.nnodes * (sizeof(lc_kpnode) + sizeof(float));
        info->data_bytes = n * (6 * sizeof(float) + 1);
        lci_log(dev, LC_LOG_INFO, "particles: %zu (%zu dropped), %d fields, BVH %d nodes depth %d, %.1f MB, %.3f s", n,
                bad, nfields, p->bvh.nnodes, p->bvh.depth, (double)info->bvh_bytes / 1e6, info->build_seconds);
    }
    free(own_xyz);
    free(own_rad);
    free(src);
    if (s != LC_OK) {
        lc_particles_destroy(p);
        return s;
    }
    *out = p;
    return LC_OK;
}

static void pparams(const lc_render_desc *d, float *sigma, float *kappa)
{
    *sigma = d->particle.sigma == 0.0f ? 2.0f : d->particle.sigma;
    *kappa = d->particle.kappa == 0.0f ? 1.0f : d->particle.kappa;
}

lc_status lci_particles_info(lc_device *dev, const lc_particles *p, const lc_render_desc *d, lci_scene_info *out)
{
    float sigma, kappa;
    pparams(d, &sigma, &kappa);
    if (!(sigma > 0.0f && sigma <= 100.0f))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "sigma = %g, expected (0, 100]", (double)d->particle.sigma);
    if (!isfinite(kappa))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "kappa = %g, expected a finite value", (double)kappa);
    float ss = d->particle.sphere_scale;
    if (!(ss >= 0.0f && ss <= 100.0f))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "sphere scale = %g, expected [0, 100]", (double)ss);
    float g = fmaxf(sigma, ss) * p->info.max_radius;
    out->bounds = p->info.bounds;
    out->bounds.lo.x -= g, out->bounds.lo.y -= g, out->bounds.lo.z -= g;
    out->bounds.hi.x += g, out->bounds.hi.y += g, out->bounds.hi.z += g;
    /* a quarter of the smallest radius resolves every Gaussian */
    out->default_dt = p->info.count ? 0.25f * p->info.min_radius : 1.0f;
    out->default_range[0] = 0.0f;
    out->default_range[1] = fabsf(kappa);
    out->nfields = p->info.nfields;
    return LC_OK;
}

lc_status lci_particles_prepare(lc_device *dev, const lc_particles *p, const lc_render_desc *d, const lc_kframe *frame,
                                lci_prepared *out)
{
    lc_kparticles *k = lci_aligned_alloc(64, sizeof *k);
    if (!k) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_render: out of memory");
    float sigma, kappa;
    pparams(d, &sigma, &kappa);
    int nf = p->info.nfields;
    int bk = d->particle.buffer_samples == 0 ? (nf > 1 ? 64 / nf : 32) : d->particle.buffer_samples;
    if (bk < 1 || bk > 4096) {
        lci_aligned_free(k);
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "buffer samples = %d, expected 1 to 4096",
                         d->particle.buffer_samples);
    }
    lci_particles_kscene(p, sigma, kappa, k);
    k->buffer_k = bk;
    k->sphere_scale = d->particle.sphere_scale;
    float g = fmaxf(sigma, k->sphere_scale) * p->info.max_radius;
    const lc_box3 *b = &p->info.bounds;
    k->lo[0] = b->lo.x - g, k->lo[1] = b->lo.y - g, k->lo[2] = b->lo.z - g, k->lo[3] = 0.0f;
    k->hi[0] = b->hi.x + g, k->hi[1] = b->hi.y + g, k->hi[2] = b->hi.z + g, k->hi[3] = 0.0f;
    lc_method m = d->method == LC_METHOD_DEFAULT ? LC_METHOD_COHERENT : d->method;
    if (m != LC_METHOD_COHERENT && m != LC_METHOD_DIRECT) {
        lci_aligned_free(k);
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "method %d does not apply to particles (coherent or direct)",
                         (int)d->method);
    }
    out->particles_fn = m == LC_METHOD_COHERENT ? dev->kt->particles_coherent : dev->kt->particles_direct;
    out->particles = k;
    out->scratch_bytes = dev->kt->particles_scratch_bytes(k, frame);
    out->owned = k; /* freed with free(): posix_memalign memory */
    return LC_OK;
}

void lci_particles_kscene(const lc_particles *p, float sigma, float kappa, lc_kparticles *k)
{
    memset(k, 0, sizeof *k);
    k->nodes = p->bvh.nodes;
    k->node_rmax = p->bvh.rmax;
    k->px = p->px, k->py = p->py, k->pz = p->pz;
    k->r = p->r;
    k->neg_inv_2r2 = p->nir;
    k->k = p->k;
    k->field = p->field;
    k->count = (int64_t)p->info.count;
    k->nnodes = p->bvh.nnodes;
    k->depth = p->bvh.depth;
    k->nfields = p->info.nfields;
    k->sigma = sigma;
    k->kappa = kappa;
    k->max_radius = p->info.max_radius;
}

lc_status lc_particles_sample(lc_device *dev, const lc_particles *p, const lc_particle_params *params, size_t n,
                              const float *points, float *values, float *gradients)
{
    if (!dev) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_particles_sample: device is NULL");
    if (!p) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_particles_sample: particles is NULL");
    if (n > 0 && (!points || !values))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_particles_sample: points or values is NULL");
    lc_render_desc d;
    memset(&d, 0, sizeof d);
    if (params) d.particle = *params;
    float sigma, kappa;
    pparams(&d, &sigma, &kappa);
    if (!(sigma > 0.0f && sigma <= 100.0f) || !isfinite(kappa))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_particles_sample: sigma %g or kappa %g out of range",
                         (double)sigma, (double)kappa);
    lc_kparticles k;
    lci_particles_kscene(p, sigma, kappa, &k);
    int32_t *stack = malloc(sizeof(int32_t) * (size_t)(k.depth + 4));
    if (!stack) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_particles_sample: out of memory");
    unsigned int csr = __builtin_ia32_stmxcsr();
    lci_flush_denormals();
    dev->kt->particles_sample(&k, points, (int64_t)n, values, gradients, stack);
    __builtin_ia32_ldmxcsr(csr);
    free(stack);
    return LC_OK;
}
