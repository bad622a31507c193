/* The coherent particle kernel's recurrence ratio per particle (issue 8;
 * docs/bench/particles.md "The exp-free deposit"). The exp-free deposit steps each particle's Gaussian along a ray
 * by g *= q, q *= c with c = exp(2 nir dt^2) (kernels/particles_common.h
 * pgauss_c, rounded once from double). c depends only on the particle's
 * radius and the frame's step, but the kernel computed it per particle and
 * pass wherever neighbours in leaf order differ in radius (every particle of
 * a set with varied radii: one double exp each, ~5% of a uniform 1e6 frame).
 * Here it is computed once per volume and step, with the same function, so
 * the kernel reads the same float (images bit for bit the same;
 * tests/test_particles_cstep.c). 4 bytes per particle; ~10 ms per million
 * particles, serial, in the first frame with a new step.
 *
 * The entry lives in the volume's cache slot (host/api/vcache.h: mutex,
 * reference counts, never written after it is published). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include "host/internal.h"
#include "host/kinds/particles_cstep.h"
#include "kernels/shared/kparticles.h"

struct lci_pcstep {
    lci_vcache_entry head; /* first (vcache.h) */
    float dt;      /* key (the radii never change after creation) */
    size_t n;
    float *c;      /* n values, 64-byte aligned after the header */
};

static size_t head_bytes(void) { return (sizeof(lci_pcstep) + 63) & ~(size_t)63; }

/* what a frame asks the cache for */
typedef struct cstep_key {
    const float *nir;
    size_t n;
    float dt;
} cstep_key;

static lci_vcache_entry *build(const void *key)
{
    const cstep_key *q = key;
    const float *nir = q->nir;
    const size_t n = q->n;
    const float dt = q->dt;
    if (n > (SIZE_MAX - head_bytes()) / sizeof(float)) return NULL;
    unsigned char *mem = lci_aligned_alloc(64, head_bytes() + n * sizeof(float));
    if (!mem) return NULL;
    lci_pcstep *t = (lci_pcstep *)mem;
    t->dt = dt, t->n = n;
    t->c = (float *)(mem + head_bytes());
    /* the kernels' ratio (kparticles.h), neighbours sharing a radius share one exp */
    float last = 1.0f, cl = 0.0f; /* nir < 0: never equal to 1 */
    for (size_t i = 0; i < n; i++) {
        if (nir[i] != last) last = nir[i], cl = lc_kparticles_ratio(nir[i], dt);
        t->c[i] = cl;
    }
    return &t->head;
}

static int matches(const lci_vcache_entry *e, const void *key)
{
    const lci_pcstep *t = (const lci_pcstep *)e;
    const cstep_key *q = key;
    return t->n == q->n && t->dt == q->dt;
}

void lci_pcstep_release(lci_pcstep *t) { lci_vcache_release(t ? &t->head : NULL); }

lci_pcstep *lci_pcstep_get(pthread_mutex_t *mu, lci_vcache_entry **slot, const float *nir, size_t n, float dt)
{
    cstep_key key = {nir, n, dt};
    return (lci_pcstep *)lci_vcache_get(mu, slot, matches, build, &key);
}

const float *lci_pcstep_values(const lci_pcstep *t) { return t->c; }
