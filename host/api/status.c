/* Status strings, error recording and logging, version. */
#include <stdio.h>
#include <string.h>
#include <stdlib.h>
#include <time.h>
#include "host/internal.h"

static _Thread_local char thread_error[LCI_MSG_MAX];

const char *lc_status_string(lc_status status)
{
    switch (status) {
    case LC_OK: return "ok";
    case LC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case LC_ERROR_UNSUPPORTED: return "unsupported";
    case LC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case LC_ERROR_IO: return "i/o error";
    case LC_ERROR_FORMAT: return "format error";
    case LC_ERROR_INTERNAL: return "internal error";
    case LC_CANCELLED: return "cancelled";
    case LC_TIMEOUT: return "timed out";
    }
    return "unknown status";
}

const char *lc_last_error(void) { return thread_error; }

lc_status lci_error(lc_device *device, lc_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(thread_error, sizeof thread_error, fmt, ap);
    va_end(ap);
    if (device) {
        memcpy(device->last_error, thread_error, sizeof thread_error);
        if (device->log) device->log(device->log_user, LC_LOG_ERROR, thread_error);
    }
    return status;
}

void lci_log(lc_device *device, lc_log_level level, const char *fmt, ...)
{
    if (!device || !device->log) return;
    char msg[LCI_MSG_MAX];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    device->log(device->log_user, level, msg);
}

void lc_version(int *major, int *minor, int *patch)
{
    if (major) *major = LC_VERSION_MAJOR;
    if (minor) *minor = LC_VERSION_MINOR;
    if (patch) *patch = LC_VERSION_PATCH;
}

const char *lc_version_string(void) { return LC_VERSION_STRING; }

double lci_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void *lci_aligned_alloc(size_t align, size_t bytes)
{
    void *p = NULL;
    if (bytes == 0) bytes = align;
    if (posix_memalign(&p, align, bytes) != 0) return NULL;
    memset(p, 0, bytes);
    return p;
}

void lci_aligned_free(void *p) { free(p); }

void lci_load_progress(lc_device *device, double fraction)
{
    if (!device || !device->load_progress) return;
    float f = fraction < 0.0 ? 0.0f : fraction > 1.0 ? 1.0f : (float)fraction;
    if (f < device->load_last + 0.01f) return;
    device->load_last = f;
    device->load_progress(device->load_progress_user, f);
}
