/* Device: target choice, thread pool, error state. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "host/internal.h"
#include "bvh/embree.h"

#define LCI_MAX_THREADS 1024

static lc_status choose_target(lc_target requested, lc_target *out)
{
    lc_target t = requested;
    if ((int)t < 0 || t >= LC_TARGET_COUNT)
        return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_device_create: target %d is not a valid lc_target", (int)t);
    if (t == LC_TARGET_AUTO) {
        const char *env = getenv("LANECAST_TARGET");
        if (env && *env) {
            if (lc_target_from_name(env, &t) != LC_OK)
                return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT,
                                 "LANECAST_TARGET='%s' is not a target (known: " LCI_TARGET_NAMES ")", env);
        }
    }
    if (t == LC_TARGET_AUTO) {
        *out = lci_target_auto();
        return LC_OK;
    }
    if (!lc_target_compiled(t))
        return lci_error(NULL, LC_ERROR_UNSUPPORTED, "target '%s' is not compiled into this build of lanecast",
                         lc_target_name(t));
    if (!lci_cpu_supports(t))
        return lci_error(NULL, LC_ERROR_UNSUPPORTED, "target '%s' is not supported by this CPU: it lacks %s",
                         lc_target_name(t), lci_cpu_missing(t));
    *out = t;
    return LC_OK;
}

static lc_status choose_threads(int requested, int *out)
{
    int n = requested;
    if (n < 0 || n > LCI_MAX_THREADS)
        return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_device_create: threads = %d, expected 0 (auto) to %d",
                         n, LCI_MAX_THREADS);
    if (n == 0) {
        const char *env = getenv("LANECAST_THREADS");
        if (env && *env) {
            char *end;
            long v = strtol(env, &end, 10);
            if (*end || v < 1 || v > LCI_MAX_THREADS)
                return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "LANECAST_THREADS='%s', expected 1 to %d", env,
                                 LCI_MAX_THREADS);
            n = (int)v;
        }
    }
    if (n == 0) {
        long c = sysconf(_SC_NPROCESSORS_ONLN);
        n = c > 0 ? (int)(c > LCI_MAX_THREADS ? LCI_MAX_THREADS : c) : 1;
    }
    *out = n;
    return LC_OK;
}

lc_status lc_device_create(const lc_device_desc *desc, lc_device **out)
{
    if (!out) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_device_create: out is NULL");
    *out = NULL;
    lc_device_desc d;
    memset(&d, 0, sizeof d);
    if (desc) d = *desc;
    lc_target t = LC_TARGET_SCALAR;
    int threads = 1;
    lc_status s = choose_target(d.target, &t);
    if (s == LC_OK) s = choose_threads(d.threads, &threads);
    if (s != LC_OK) {
        if (d.log) d.log(d.log_user, LC_LOG_ERROR, lc_last_error());
        return s;
    }
    lc_device *dev = calloc(1, sizeof *dev);
    if (!dev) return lci_error(NULL, LC_ERROR_OUT_OF_MEMORY, "lc_device_create: out of memory");
    dev->target = t;
    dev->kt = lci_ktable(t);
    dev->threads = threads;
    dev->log = d.log;
    dev->log_user = d.log_user;
    dev->pool = lci_pool_create(threads);
    if (!dev->pool) {
        free(dev);
        return lci_error(NULL, LC_ERROR_OUT_OF_MEMORY, "lc_device_create: cannot start %d threads", threads);
    }
    lci_log(dev, LC_LOG_INFO, "lanecast %s: target %s (%d lanes), %d threads", LC_VERSION_STRING, lc_target_name(t),
            dev->kt->lanes, threads);
    *out = dev;
    return LC_OK;
}

void lc_device_destroy(lc_device *device)
{
    if (!device) return;
    lci_embree_release(device);
    lci_pool_destroy(device->pool);
    free(device);
}

lc_status lc_device_target(const lc_device *device, lc_target *out)
{
    if (!device) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_device_target: device is NULL");
    if (!out) return lci_error((lc_device *)device, LC_ERROR_INVALID_ARGUMENT, "lc_device_target: out is NULL");
    *out = device->target;
    return LC_OK;
}

lc_status lc_device_threads(const lc_device *device, int *out)
{
    if (!device) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_device_threads: device is NULL");
    if (!out) return lci_error((lc_device *)device, LC_ERROR_INVALID_ARGUMENT, "lc_device_threads: out is NULL");
    *out = device->threads;
    return LC_OK;
}

const char *lc_device_last_error(const lc_device *device)
{
    if (!device) return "lc_device_last_error: device is NULL";
    return device->last_error;
}

static void embree_log(void *user, int code, const char *message)
{
    lci_log(user, LC_LOG_WARNING, "Embree error %d: %s", code, message);
}

void *lci_embree_device(lc_device *dev)
{
    if (!dev->embree) {
        char err[256];
        dev->embree = lci_embree_new(dev->threads, embree_log, dev, err, sizeof err);
        if (!dev->embree) lci_error(dev, LC_ERROR_INTERNAL, "%s", err);
    }
    return dev->embree;
}

void lci_embree_release(lc_device *dev)
{
    lci_embree_free(dev->embree);
    dev->embree = NULL;
}
