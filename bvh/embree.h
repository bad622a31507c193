/* The Embree device behind particle BVH builds (bvh/ never sees host types:
 * the host keeps the handle in its lc_device and passes it in). */
#ifndef LC_BVH_EMBREE_H
#define LC_BVH_EMBREE_H

#include <stddef.h>

/* Receives Embree's error messages (code and text). */
typedef void (*lci_embree_log_fn)(void *user, int code, const char *message);

/* A new Embree device with `threads` build threads (0 = Embree's choice), or
 * NULL with a message in err. */
void *lci_embree_new(int threads, lci_embree_log_fn log, void *user, char *err, size_t errlen);
void lci_embree_free(void *handle);
/* The build threads the handle was made for (0 = as many as CPUs). */
int lci_embree_threads(void *handle);
/* The RTCDevice inside a handle from lci_embree_new. */
void *lci_embree_rtc(void *handle);

#endif
