/* The coherent particle kernel's per-particle recurrence ratio c_i =
 * exp(2 nir_i dt^2) (kernels/particles_common.h pgauss_c), kept per volume
 * for the last frame step dt (host/kinds/particles_cstep.c). */
#ifndef LCI_PARTICLES_CSTEP_H
#define LCI_PARTICLES_CSTEP_H

#include <pthread.h>
#include <stddef.h>
#include "host/api/vcache.h"

typedef struct lci_pcstep lci_pcstep;

/* The table for dt (reference counted: the caller's reference is dropped
 * by lci_pcstep_release), from the one cached in *slot under mu or built
 * and cached in its place. NULL: out of memory. */
lci_pcstep *lci_pcstep_get(pthread_mutex_t *mu, lci_vcache_entry **slot, const float *nir, size_t n, float dt);
void lci_pcstep_release(lci_pcstep *t);
const float *lci_pcstep_values(const lci_pcstep *t);

#endif
