/* One cached entry per volume of per-frame data that depends on the frame's
 * TF, step or parameters but not on its camera (the grid's pre-integrated
 * tables and node bits, the particles' recurrence ratios): built once,
 * reused by every frame with the same key.
 *
 * Threads: one volume may be rendered from several threads at once
 * (lanecast.h), so the slot sits behind the volume's mutex and entries are
 * reference counted: the volume holds one reference, each frame using the
 * entry another, dropped with lci_vcache_release after the frame. Entries are
 * never written after they are published; a new key builds a new entry
 * (outside the lock) that replaces the slot's. */
#ifndef LANECAST_HOST_VCACHE_H
#define LANECAST_HOST_VCACHE_H
#include <pthread.h>
#include <stdatomic.h>

/* the first member of every cached entry */
typedef struct lci_vcache_entry {
    atomic_int refs;
} lci_vcache_entry;

/* does entry e hold what key asks for? */
typedef int (*lci_vcache_match)(const lci_vcache_entry *e, const void *key);
/* a new entry for key, from lci_aligned_alloc (refs are the cache's), or NULL */
typedef lci_vcache_entry *(*lci_vcache_build)(const void *key);

/* A referenced entry matching key: the slot's, or a new one built and
 * published in the slot. NULL when the build fails (out of memory). */
lci_vcache_entry *lci_vcache_get(pthread_mutex_t *mu, lci_vcache_entry **slot, lci_vcache_match match,
                                 lci_vcache_build build, const void *key);
/* drops one reference (NULL: nothing); the last one frees the entry */
void lci_vcache_release(lci_vcache_entry *e);

#endif
