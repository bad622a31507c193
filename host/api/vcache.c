/* Per-volume cache of one per-frame entry (host/api/vcache.h). */
#include "host/api/vcache.h"
#include "host/internal.h"

void lci_vcache_release(lci_vcache_entry *e)
{
    if (e && atomic_fetch_sub_explicit(&e->refs, 1, memory_order_acq_rel) == 1) lci_aligned_free(e);
}

lci_vcache_entry *lci_vcache_get(pthread_mutex_t *mu, lci_vcache_entry **slot, lci_vcache_match match,
                                 lci_vcache_build build, const void *key)
{
    pthread_mutex_lock(mu);
    lci_vcache_entry *e = *slot;
    if (e && match(e, key)) {
        atomic_fetch_add_explicit(&e->refs, 1, memory_order_relaxed);
        pthread_mutex_unlock(mu);
        return e;
    }
    pthread_mutex_unlock(mu);
    /* built outside the lock: other frames of this volume go on meanwhile */
    e = build(key);
    if (!e) return NULL;
    atomic_init(&e->refs, 2); /* the caller's and the volume's */
    pthread_mutex_lock(mu);
    lci_vcache_entry *old = *slot;
    *slot = e;
    pthread_mutex_unlock(mu);
    lci_vcache_release(old);
    return e;
}
