/* Text options of lc_load_desc, parsed strictly: the whole value must be a
 * number in range, or the error names the file, the key and the value. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include "host/internal.h"

static lc_status bad(lc_device *dev, const char *file, const lc_option *o, const char *what)
{
    return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: option %s = '%s': expected %s", file, o->key, o->value,
                     what);
}

lc_status lci_option_int(lc_device *dev, const char *file, const lc_option *o, int lo, int hi, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(o->value, &end, 10);
    if (end == o->value || *end || errno || v < lo || v > hi) {
        char what[64];
        snprintf(what, sizeof what, "an integer from %d to %d", lo, hi);
        return bad(dev, file, o, what);
    }
    *out = (int)v;
    return LC_OK;
}

lc_status lci_option_size(lc_device *dev, const char *file, const lc_option *o, size_t hi, size_t *out)
{
    char *end;
    errno = 0;
    unsigned long long v = strtoull(o->value, &end, 10);
    if (end == o->value || *end || errno || o->value[0] == '-' || v > hi) {
        char what[64];
        snprintf(what, sizeof what, "a count from 0 to %zu", hi);
        return bad(dev, file, o, what);
    }
    *out = (size_t)v;
    return LC_OK;
}

lc_status lci_option_float(lc_device *dev, const char *file, const lc_option *o, float lo, float hi, float *out)
{
    char *end;
    errno = 0;
    float v = strtof(o->value, &end); /* compared in float, as the bounds: 1e-30 is within [1e-30, ...] */
    if (end == o->value || *end || errno || !isfinite(v) || v < lo || v > hi) {
        char what[96];
        snprintf(what, sizeof what, "a number from %g to %g", (double)lo, (double)hi);
        return bad(dev, file, o, what);
    }
    *out = v;
    return LC_OK;
}

lc_status lci_option_floats(lc_device *dev, const char *file, const lc_option *o, int n, float *out)
{
    const char *p = o->value;
    for (int i = 0; i < n; i++) {
        char *end;
        errno = 0;
        double v = strtod(p, &end);
        if (end == p || errno || !isfinite(v) || (i + 1 < n ? *end != ',' : *end != '\0')) {
            char what[64];
            snprintf(what, sizeof what, "%d comma-separated finite numbers", n);
            return bad(dev, file, o, what);
        }
        out[i] = (float)v;
        p = end + 1;
    }
    return LC_OK;
}

lc_status lci_option_ints(lc_device *dev, const char *file, const lc_option *o, int n, int lo, int hi, int *out)
{
    const char *p = o->value;
    for (int i = 0; i < n; i++) {
        char *end;
        errno = 0;
        long v = strtol(p, &end, 10);
        if (end == p || errno || v < lo || v > hi || (i + 1 < n ? *end != ',' : *end != '\0')) {
            char what[96];
            snprintf(what, sizeof what, "%d comma-separated integers from %d to %d", n, lo, hi);
            return bad(dev, file, o, what);
        }
        out[i] = (int)v;
        p = end + 1;
    }
    return LC_OK;
}

long lci_env_long(const char *name, long lo, long hi, long unset)
{
    const char *e = getenv(name);
    if (!e || !*e) return unset;
    char *end;
    long v = strtol(e, &end, 10);
    return *end || v < lo || v > hi ? unset : v;
}

lc_status lci_option_order(lc_device *dev, const char *file, const lc_option *o, int *out)
{
    lc_status s = lci_option_int(dev, file, o, 0, 1, out);
    if (s == LC_OK && *out == 0) *out = -1;
    return s;
}
