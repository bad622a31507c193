/* Embree device creation for the particle BVH builder (bvh/particle_bvh.c). */
#include "embree.h"
#include <stdio.h>
#include <stdlib.h>
#include <embree3/rtcore.h>

/* The handle the host keeps: the device and where its errors go. */
typedef struct lci_embree {
    RTCDevice device;
    int threads;
    lci_embree_log_fn log;
    void *user;
} lci_embree;

static void on_error(void *user, enum RTCError code, const char *str)
{
    const lci_embree *e = user;
    if (e->log) e->log(e->user, (int)code, str ? str : "");
}

void *lci_embree_new(int threads, lci_embree_log_fn log, void *user, char *err, size_t errlen)
{
    lci_embree *e = calloc(1, sizeof *e);
    if (!e) {
        snprintf(err, errlen, "Embree: out of memory");
        return NULL;
    }
    char cfg[64];
    snprintf(cfg, sizeof cfg, "threads=%d", threads > 0 ? threads : 0);
    e->device = rtcNewDevice(cfg);
    if (!e->device) {
        snprintf(err, errlen, "Embree: rtcNewDevice failed (error %d)", (int)rtcGetDeviceError(NULL));
        free(e);
        return NULL;
    }
    e->threads = threads > 0 ? threads : 0;
    e->log = log;
    e->user = user;
    rtcSetDeviceErrorFunction(e->device, on_error, e);
    return e;
}

int lci_embree_threads(void *handle) { return handle ? ((lci_embree *)handle)->threads : 1; }

void *lci_embree_rtc(void *handle) { return handle ? ((lci_embree *)handle)->device : NULL; }

void lci_embree_free(void *handle)
{
    lci_embree *e = handle;
    if (!e) return;
    rtcReleaseDevice(e->device);
    free(e);
}
