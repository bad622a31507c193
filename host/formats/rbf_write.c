/* lc_rbf_write: an RBF set as a .rbf file (docs/FORMATS-rbf.md), binary or
 * text version 1, written under a temporary name in the target's folder and
 * renamed, so the file appears complete or not at all. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "host/internal.h"

static const unsigned char bin_magic[8] = {0x89, 'L', 'C', 'R', 'B', 'F', '\r', '\n'};

static void put32(unsigned char *b, uint32_t u)
{
    for (int i = 0; i < 4; i++) b[i] = (unsigned char)(u >> (8 * i));
}

static void putf(unsigned char *b, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    put32(b, u);
}

static int write_binary(FILE *f, const lc_rbf_desc *d)
{
    unsigned char h[32] = {0};
    memcpy(h, bin_magic, 8);
    put32(h + 8, 1);
    put32(h + 16, (uint32_t)d->count), put32(h + 20, (uint32_t)((uint64_t)d->count >> 32));
    putf(h + 24, d->bias);
    if (fwrite(h, 1, sizeof h, f) != sizeof h) return -1;
    for (size_t i = 0; i < d->count; i++) {
        unsigned char r[20];
        for (int a = 0; a < 3; a++) putf(r + 4 * a, d->centres[3 * i + a]);
        putf(r + 12, d->widths[i]), putf(r + 16, d->weights[i]);
        if (fwrite(r, 1, sizeof r, f) != sizeof r) return -1;
    }
    return 0;
}

static int write_text(FILE *f, const lc_rbf_desc *d)
{
    /* %.9g round-trips float32 exactly (docs/FORMATS-rbf.md) */
    if (fprintf(f, "# RBF set written by lanecast %s\nlanecast-rbf 1\nbias %.9g\ncount %zu\n", LC_VERSION_STRING,
                (double)d->bias, d->count) < 0)
        return -1;
    for (size_t i = 0; i < d->count; i++) {
        const float *c = d->centres + 3 * i;
        if (fprintf(f, "%.9g %.9g %.9g %.9g %.9g\n", (double)c[0], (double)c[1], (double)c[2], (double)d->widths[i],
                    (double)d->weights[i]) < 0)
            return -1;
    }
    return 0;
}

static lc_status check(lc_device *dev, const char *path, const lc_rbf_desc *d)
{
    if (d->count && (!d->centres || !d->widths || !d->weights))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_rbf_write: %s: centres, widths and weights are required",
                         path);
    if (d->count > (size_t)INT32_MAX / 2)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_rbf_write: %s: count %zu exceeds %d", path, d->count,
                         INT32_MAX / 2);
    if (!isfinite(d->bias))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_rbf_write: %s: the bias is not finite", path);
    for (size_t i = 0; i < d->count; i++) {
        const float *c = d->centres + 3 * i;
        if (!isfinite(c[0]) || !isfinite(c[1]) || !isfinite(c[2]) || !isfinite(d->weights[i]) ||
            !(d->widths[i] > 0.0f) || !isfinite(d->widths[i]))
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                             "lc_rbf_write: %s: RBF %zu has a non-finite centre or weight or a width not > 0", path, i);
    }
    return LC_OK;
}

lc_status lc_rbf_write(lc_device *dev, const char *path, const lc_rbf_desc *d, lc_rbf_file variant)
{
    if (!path || !d) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_rbf_write: path and desc must not be NULL");
    if (variant != LC_RBF_FILE_BINARY && variant != LC_RBF_FILE_TEXT)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_rbf_write: variant %d is not binary (0) or text (1)",
                         (int)variant);
    lc_status s = check(dev, path, d);
    if (s != LC_OK) return s;
    size_t n = strlen(path) + 32;
    char *tmp = malloc(n);
    if (!tmp) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_write: out of memory");
    int slot;
    int fd = lci_temp_file(path, tmp, n, &slot); /* removed by the CLI's signal handler too */
    if (fd < 0) {
        s = lci_error(dev, LC_ERROR_IO, "%s: cannot create a temporary file next to it: %s", path, strerror(errno));
        free(tmp);
        return s;
    }
    lci_test_write_delay();
    FILE *f = fdopen(fd, "wb");
    int bad = !f;
    if (f) {
        bad = variant == LC_RBF_FILE_TEXT ? write_text(f, d) : write_binary(f, d);
        bad |= fflush(f) != 0 || fsync(fileno(f)) != 0;
        bad |= fclose(f) != 0;
    } else {
        close(fd);
    }
    if (!bad && rename(tmp, path) != 0) bad = 1;
    if (bad) {
        int e = errno;
        unlink(tmp);
        s = lci_error(dev, LC_ERROR_IO, "%s: write failed: %s", path, strerror(e));
    }
    lci_temp_release(slot);
    free(tmp);
    return s;
}
