/* The coherent particle kernel's recurrence ratio per particle (issue 8,
 * session 7). The exp-free deposit steps each particle's Gaussian along a ray
 * by g *= q, q *= c with c = exp(2 nir dt^2) (kernels/particles_common.h
 * pgauss_c, rounded once from double). c depends only on the particle's
 * radius and the frame's step, but the kernel computed it per particle and
 * pass wherever neighbours in leaf order differ in radius (every particle of
 * a set with varied radii: one double exp each, ~5% of a uniform 1e6 frame).
 * Here it is computed once per volume and step, with the same expression, so
 * the kernel reads the same float (images bit for bit the same;
 * tests/test_particles_cstep.c). 4 bytes per particle; ~10 ms per million
 * particles, serial, in the first frame with a new step.
 *
 * Threads: as the grid's tables (host/kinds/grid_tables.c): one entry per
 * volume behind a mutex, reference counted (the volume holds one, each
 * frame another), never written after it is published. */
#include <math.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include "host/internal.h"
#include "host/kinds/particles_cstep.h"

struct lci_pcstep {
    atomic_int refs;
    float dt;      /* key (the radii never change after creation) */
    size_t n;
    float *c;      /* n values, 64-byte aligned after the header */
};

static size_t head_bytes(void) { return (sizeof(lci_pcstep) + 63) & ~(size_t)63; }

static lci_pcstep *build(const float *nir, size_t n, float dt)
{
    if (n > (SIZE_MAX - head_bytes()) / sizeof(float)) return NULL;
    unsigned char *mem = lci_aligned_alloc(64, head_bytes() + n * sizeof(float));
    if (!mem) return NULL;
    lci_pcstep *t = (lci_pcstep *)mem;
    atomic_init(&t->refs, 1);
    t->dt = dt, t->n = n;
    t->c = (float *)(mem + head_bytes());
    /* pgauss_c's expression and rounding, neighbours sharing a radius share one exp */
    float last = 1.0f, cl = 0.0f; /* nir < 0: never equal to 1 */
    for (size_t i = 0; i < n; i++) {
        if (nir[i] != last) last = nir[i], cl = (float)exp(2.0 * (double)nir[i] * (double)dt * (double)dt);
        t->c[i] = cl;
    }
    return t;
}

static int same_key(const lci_pcstep *t, float dt, size_t n)
{
    return t->n == n && t->dt == dt;
}

void lci_pcstep_release(lci_pcstep *t)
{
    if (t && atomic_fetch_sub_explicit(&t->refs, 1, memory_order_acq_rel) == 1) lci_aligned_free(t);
}

lci_pcstep *lci_pcstep_get(pthread_mutex_t *mu, lci_pcstep **slot, const float *nir, size_t n, float dt)
{
    pthread_mutex_lock(mu);
    lci_pcstep *t = *slot;
    if (t && same_key(t, dt, n)) {
        atomic_fetch_add_explicit(&t->refs, 1, memory_order_relaxed);
        pthread_mutex_unlock(mu);
        return t;
    }
    pthread_mutex_unlock(mu);
    /* built outside the lock: other frames of this volume go on meanwhile */
    t = build(nir, n, dt);
    if (!t) return NULL;
    atomic_fetch_add_explicit(&t->refs, 1, memory_order_relaxed); /* the volume's */
    pthread_mutex_lock(mu);
    lci_pcstep *old = *slot;
    *slot = t;
    pthread_mutex_unlock(mu);
    lci_pcstep_release(old);
    return t;
}

const float *lci_pcstep_values(const lci_pcstep *t) { return t->c; }
