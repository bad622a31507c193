/* lc_volume_write: a float grid as a NRRD file (attached .nrrd, or a
 * detached .nhdr header with its .raw data file), float32 or quantised to
 * uint8/uint16 over a stated range. Written through lci_write_with, so each
 * file appears complete or not at all (host/api/image.c). The header uses
 * NRRD0004's world-space fields (space dimension, space directions, space
 * origin), which lanecast's reader (host/formats/nrrd.c) and Teem read. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>
#include "host/internal.h"

typedef struct wjob {
    const lc_volume_write_desc *d;
    float lo, hi;
    const char *data_file; /* detached: the data file's name as the header gives it; NULL: attached */
    int header, data;      /* what this pass writes */
} wjob;

static int little_endian(void)
{
    const uint16_t one = 1;
    unsigned char b;
    memcpy(&b, &one, 1);
    return b == 1;
}

static int write_header(FILE *f, const wjob *j)
{
    const lc_volume_write_desc *d = j->d;
    const char *type = d->type == LC_VALUE_UINT8 ? "uint8" : d->type == LC_VALUE_UINT16 ? "uint16" : "float";
    fprintf(f, "NRRD0004\n# lanecast: particles deposited to grid nodes (lc_particles_resample)\n");
    fprintf(f, "type: %s\ndimension: 3\nsizes: %d %d %d\n", type, d->size[0], d->size[1], d->size[2]);
    fprintf(f, "space dimension: 3\nspace directions: (%.9g,0,0) (0,%.9g,0) (0,0,%.9g)\n", (double)d->spacing.x,
            (double)d->spacing.y, (double)d->spacing.z);
    fprintf(f, "space origin: (%.9g,%.9g,%.9g)\n", (double)d->origin.x, (double)d->origin.y, (double)d->origin.z);
    if (d->type == LC_VALUE_UINT8 || d->type == LC_VALUE_UINT16)
        fprintf(f, "old min: %.9g\nold max: %.9g\n", (double)j->lo, (double)j->hi);
    fprintf(f, "endian: %s\nencoding: raw\n", little_endian() ? "little" : "big");
    if (j->data_file) fprintf(f, "data file: %s\n", j->data_file);
    else fputc('\n', f);
    return ferror(f) ? -1 : 0;
}

/* The values, quantised in chunks when the type asks for it. */
static int write_data(FILE *f, const wjob *j)
{
    const lc_volume_write_desc *d = j->d;
    size_t n = (size_t)d->size[0] * (size_t)d->size[1] * (size_t)d->size[2];
    if (d->type != LC_VALUE_UINT8 && d->type != LC_VALUE_UINT16)
        return fwrite(d->values, sizeof(float), n, f) == n ? 0 : -1;
    enum { CHUNK = 1 << 16 };
    uint16_t *buf = malloc(sizeof(uint16_t) * CHUNK);
    if (!buf) return -1;
    int u8 = d->type == LC_VALUE_UINT8;
    double top = u8 ? 255.0 : 65535.0, scale = j->hi > j->lo ? top / ((double)j->hi - j->lo) : 0.0;
    int r = 0;
    for (size_t i = 0; i < n && !r; i += CHUNK) {
        size_t m = n - i < CHUNK ? n - i : CHUNK;
        for (size_t e = 0; e < m; e++) {
            double q = floor(((double)d->values[i + e] - j->lo) * scale + 0.5);
            q = q < 0.0 ? 0.0 : q > top ? top : q;
            if (u8) ((uint8_t *)buf)[e] = (uint8_t)q;
            else buf[e] = (uint16_t)q;
        }
        r = fwrite(buf, u8 ? 1 : 2, m, f) == m ? 0 : -1;
    }
    free(buf);
    return r;
}

static int fill(void *user, const char *tmp, char *err, size_t errlen)
{
    const wjob *j = user;
    FILE *f = fopen(tmp, "wb");
    if (!f) return snprintf(err, errlen, "cannot open the temporary file"), -1;
    int r = 0;
    if (j->header) r = write_header(f, j);
    if (!r && j->data) r = write_data(f, j);
    if (fclose(f) != 0) r = -1;
    if (r) snprintf(err, errlen, "writing failed (disk full?)");
    return r;
}

lc_status lc_volume_write(lc_device *dev, const char *path, const lc_volume_write_desc *d)
{
    const char *fn = "lc_volume_write";
    if (!path || !d || !d->values)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: %s is NULL", fn, !path ? "path" : !d ? "desc" : "values");
    for (int a = 0; a < 3; a++)
        if (d->size[a] < 1) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: size[%d] = %d", fn, a, d->size[a]);
    if (d->type != LC_VALUE_DEFAULT && d->type != LC_VALUE_FLOAT32 && d->type != LC_VALUE_UINT8 &&
        d->type != LC_VALUE_UINT16)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: type %d: expected float32, uint8 or uint16", fn, d->type);
    const char *ext = lci_path_extension(path);
    int detached = !strcasecmp(ext, ".nhdr");
    if (!detached && strcasecmp(ext, ".nrrd"))
        return lci_error(dev, LC_ERROR_UNSUPPORTED, "%s: the extension of %s: expected .nrrd or .nhdr", path,
                         *ext ? ext : "(none)");
    wjob j = {.d = d, .lo = d->range[0], .hi = d->range[1], .header = 1, .data = 1};
    if (!isfinite(j.lo) || !isfinite(j.hi) || j.hi < j.lo)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: range %g, %g: expected finite lo <= hi", fn,
                         (double)j.lo, (double)j.hi);
    int quant = d->type == LC_VALUE_UINT8 || d->type == LC_VALUE_UINT16;
    if (quant && j.lo == 0.0f && j.hi == 0.0f) { /* the values' own range */
        size_t n = (size_t)d->size[0] * (size_t)d->size[1] * (size_t)d->size[2];
        j.lo = INFINITY, j.hi = -INFINITY;
        for (size_t i = 0; i < n; i++) j.lo = fminf(j.lo, d->values[i]), j.hi = fmaxf(j.hi, d->values[i]);
    }
    if (!detached) return lci_write_with(dev, path, fill, &j);
    /* detached: PATH.raw beside the header (named without its folder in it) */
    size_t len = strlen(path);
    char *data = malloc(len + 1);
    if (!data) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", fn);
    memcpy(data, path, len - 5);
    memcpy(data + len - 5, ".raw", 5);
    const char *base = strrchr(data, '/');
    j.data_file = base ? base + 1 : data;
    j.header = 0;
    lc_status s = lci_write_with(dev, data, fill, &j);
    j.header = 1, j.data = 0;
    if (s == LC_OK && (s = lci_write_with(dev, path, fill, &j)) != LC_OK) unlink(data);
    free(data);
    return s;
}
