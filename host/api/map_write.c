/* lc_map_write: float maps as data (issue 27; SPEC.md "Output"): NumPy .npy
 * with a JSON sidecar, FITS through cfitsio (feature "fits"), one-channel
 * float EXR through the image shim. Every file goes through image.c's
 * temporary-name-and-rename writers, so it appears complete or not at all. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>
#include "host/internal.h"
#if LC_HAVE_FITS
#include <fitsio.h>
#endif

static int is_fits(const char *ext) { return !strcasecmp(ext, ".fits") || !strcasecmp(ext, ".fit") || !strcasecmp(ext, ".fts"); }

int lc_map_format(const char *path)
{
    if (!path) return 0;
    const char *ext = lci_path_extension(path);
    return !strcasecmp(ext, ".npy") || !strcasecmp(ext, ".exr") || is_fits(ext);
}

/* A growing text buffer for the sidecar. */
typedef struct sbuf {
    char *p;
    size_t n, cap;
    int bad;
} sbuf;

static void put(sbuf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void put(sbuf *b, const char *fmt, ...)
{
    for (int tries = 0; tries < 2 && !b->bad; tries++) {
        va_list ap;
        va_start(ap, fmt);
        int w = vsnprintf(b->p ? b->p + b->n : NULL, b->p ? b->cap - b->n : 0, fmt, ap);
        va_end(ap);
        if (w < 0) {
            b->bad = 1;
            return;
        }
        if (b->p && b->n + (size_t)w < b->cap) {
            b->n += (size_t)w;
            return;
        }
        size_t cap = (b->cap + (size_t)w + 1) * 2;
        char *q = realloc(b->p, cap);
        if (!q) {
            b->bad = 1;
            return;
        }
        b->p = q, b->cap = cap;
    }
}

/* A JSON string (quotes, backslashes and control characters escaped). */
static void put_str(sbuf *b, const char *s)
{
    put(b, "\"");
    for (const unsigned char *c = (const unsigned char *)(s ? s : ""); *c; c++) {
        if (*c == '"' || *c == '\\') put(b, "\\%c", *c);
        else if (*c < 0x20) put(b, "\\u%04x", *c);
        else put(b, "%c", *c);
    }
    put(b, "\"");
}

static const char *quantity_of(const lc_map_desc *d) { return d->quantity ? d->quantity : "value"; }

static lc_status write_sidecar(lc_device *dev, const char *path, const char *data_path, const lc_map_desc *d)
{
    sbuf b = {0};
    put(&b, "{\n  \"file\": ");
    const char *slash = strrchr(data_path, '/');
    put_str(&b, slash ? slash + 1 : data_path);
    put(&b, ",\n  \"shape\": [%d, %d],\n  \"dtype\": \"float32\",\n  \"rows\": \"top to bottom\",\n  \"quantity\": ",
        d->height, d->width);
    put_str(&b, quantity_of(d));
    put(&b, ",\n  \"units\": ");
    put_str(&b, d->units);
    if (d->kernel) put(&b, ",\n  \"kernel\": "), put_str(&b, d->kernel);
    if (d->sample) put(&b, ",\n  \"sample\": "), put_str(&b, d->sample);
    put(&b, ",\n  \"depth\": %.9g", d->depth);
    if (d->view) {
        const lc_project_info *v = d->view;
        put(&b, ",\n  \"projection\": \"orthographic\",\n  \"pixel\": %.9g", v->pixel);
        put(&b, ",\n  \"extent\": [%.9g, %.9g, %.9g, %.9g]", v->extent[0], v->extent[1], v->extent[2], v->extent[3]);
        put(&b, ",\n  \"extent_is\": \"left, right, bottom, top along the right and up axes (world coordinates)\"");
        put(&b, ",\n  \"centre\": [%.9g, %.9g, %.9g]", v->centre.x, v->centre.y, v->centre.z);
        put(&b, ",\n  \"right\": [%.9g, %.9g, %.9g]", v->right.x, v->right.y, v->right.z);
        put(&b, ",\n  \"up\": [%.9g, %.9g, %.9g]", v->up.x, v->up.y, v->up.z);
        put(&b, ",\n  \"view\": [%.9g, %.9g, %.9g]", v->view.x, v->view.y, v->view.z);
        put(&b, ",\n  \"mass\": %.12g", v->mass);
    }
    put(&b, "\n}\n");
    lc_status s = b.bad ? lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path)
                        : lci_write_bytes(dev, path, b.p, b.n);
    free(b.p);
    return s;
}

/* NumPy format 1.0: magic, version, header length, a Python dict padded with
 * spaces to a multiple of 64 bytes ending in '\n', then the data. */
static lc_status write_npy(lc_device *dev, const char *path, const lc_map_desc *d)
{
    char hdr[256];
    int n = snprintf(hdr, sizeof hdr, "{'descr': '<f4', 'fortran_order': False, 'shape': (%d, %d), }", d->height,
                     d->width);
    size_t total = 10 + (size_t)n + 1, pad = (64 - total % 64) % 64;
    size_t hlen = (size_t)n + pad + 1, data = sizeof(float) * (size_t)d->width * (size_t)d->height;
    unsigned char *buf = malloc(10 + hlen + data);
    if (!buf) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    memcpy(buf, "\x93NUMPY\x01\x00", 8);
    buf[8] = (unsigned char)(hlen & 0xff), buf[9] = (unsigned char)(hlen >> 8);
    memcpy(buf + 10, hdr, (size_t)n);
    memset(buf + 10 + n, ' ', pad);
    buf[10 + hlen - 1] = '\n';
    memcpy(buf + 10 + hlen, d->values, data); /* x86-64: little-endian */
    lc_status s = lci_write_bytes(dev, path, buf, 10 + hlen + data);
    free(buf);
    if (s != LC_OK) return s;
    char side[4096];
    if (snprintf(side, sizeof side, "%s.json", path) >= (int)sizeof side) {
        unlink(path);
        return lci_error(dev, LC_ERROR_IO, "%s: name too long for its .json sidecar", path);
    }
    s = write_sidecar(dev, side, path, d);
    if (s != LC_OK) unlink(path); /* both or neither */
    return s;
}

#if LC_HAVE_FITS
typedef struct fits_job {
    const lc_map_desc *d;
} fits_job;

static int fits_fill(void *user, const char *tmp, char *err, size_t errlen)
{
    const lc_map_desc *d = ((fits_job *)user)->d;
    char name[LCI_TEMP_NAME + 2];
    snprintf(name, sizeof name, "!%s", tmp); /* '!': replace the (empty) temporary file */
    fitsfile *f = NULL;
    int st = 0;
    long naxes[2] = {d->width, d->height};
    fits_create_file(&f, name, &st);
    fits_create_img(f, FLOAT_IMG, 2, naxes, &st);
    for (int j = 0; j < d->height && !st; j++) /* FITS's first row is the bottom one */
        fits_write_img(f, TFLOAT, (LONGLONG)j * d->width + 1, d->width,
                       (void *)(d->values + (size_t)(d->height - 1 - j) * (size_t)d->width), &st);
    char q[FLEN_VALUE], u[FLEN_VALUE];
    snprintf(q, sizeof q, "%s", quantity_of(d));
    snprintf(u, sizeof u, "%s", d->units ? d->units : "");
    fits_update_key(f, TSTRING, "BTYPE", q, "what a pixel holds", &st);
    fits_update_key(f, TSTRING, "BUNIT", u, "units of a pixel", &st);
    if (d->kernel) {
        char k[FLEN_VALUE];
        snprintf(k, sizeof k, "%s", d->kernel);
        fits_update_key(f, TSTRING, "KERNEL", k, "SPH kernel (lanecast names, support-radius H)", &st);
    }
    if (d->sample) {
        char s[FLEN_VALUE];
        snprintf(s, sizeof s, "%s", d->sample);
        fits_update_key(f, TSTRING, "SAMPLE", s, "exact: pixel averages; centre: pixel centres", &st);
    }
    double depth = d->depth;
    fits_update_key(f, TDOUBLE, "DEPTH", &depth, "slab thickness (0: whole line of sight)", &st);
    if (d->view) {
        const lc_project_info *v = d->view;
        double one = 0.5, px = v->pixel;
        double e[4] = {v->extent[0], v->extent[1], v->extent[2], v->extent[3]};
        fits_update_key(f, TSTRING, "CTYPE1", "LINEAR", "world coordinate along the image's right axis", &st);
        fits_update_key(f, TSTRING, "CTYPE2", "LINEAR", "world coordinate along the image's up axis", &st);
        fits_update_key(f, TDOUBLE, "CRPIX1", &one, "the left edge of the first pixel", &st);
        fits_update_key(f, TDOUBLE, "CRPIX2", &one, "the bottom edge of the first row", &st);
        fits_update_key(f, TDOUBLE, "CRVAL1", &e[0], NULL, &st);
        fits_update_key(f, TDOUBLE, "CRVAL2", &e[2], NULL, &st);
        fits_update_key(f, TDOUBLE, "CDELT1", &px, "pixel side", &st);
        fits_update_key(f, TDOUBLE, "CDELT2", &px, "pixel side", &st);
        fits_update_key(f, TDOUBLE, "XMIN", &e[0], "image extent along the right axis", &st);
        fits_update_key(f, TDOUBLE, "XMAX", &e[1], NULL, &st);
        fits_update_key(f, TDOUBLE, "YMIN", &e[2], "image extent along the up axis", &st);
        fits_update_key(f, TDOUBLE, "YMAX", &e[3], NULL, &st);
        const char *names[9] = {"RIGHT_X", "RIGHT_Y", "RIGHT_Z", "UP_X", "UP_Y", "UP_Z", "VIEW_X", "VIEW_Y", "VIEW_Z"};
        double ax[9] = {v->right.x, v->right.y, v->right.z, v->up.x, v->up.y, v->up.z, v->view.x, v->view.y, v->view.z};
        for (int i = 0; i < 9; i++) fits_update_key(f, TDOUBLE, names[i], &ax[i], NULL, &st);
        double mass = v->mass;
        fits_update_key(f, TDOUBLE, "MAPSUM", &mass, "sum of pixels x pixel area", &st);
    }
    fits_write_date(f, &st);
    int cst = 0;
    if (f) fits_close_file(f, st ? &cst : &st);
    if (st) {
        char text[FLEN_STATUS];
        fits_get_errstatus(st, text);
        snprintf(err, errlen, "cfitsio: %s", text);
        return -1;
    }
    return 0;
}
#endif

lc_status lc_map_write(lc_device *dev, const char *path, const lc_map_desc *d)
{
    if (!path || !*path) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_map_write: path is empty");
    if (!d || !d->values) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_map_write: %s is NULL", d ? "values" : "desc");
    if (d->width < 1 || d->height < 1 || d->width > LC_MAX_IMAGE_SIDE || d->height > LC_MAX_IMAGE_SIDE)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_map_write: size %dx%d, expected 1 to %d per side", d->width,
                         d->height, LC_MAX_IMAGE_SIDE);
    const char *ext = lci_path_extension(path);
    if (!strcasecmp(ext, ".npy")) return write_npy(dev, path, d);
    if (!strcasecmp(ext, ".exr")) return lci_image_encode_write(dev, path, d->width, d->height, 1, 1, d->values);
    if (is_fits(ext)) {
#if LC_HAVE_FITS
        fits_job j = {d};
        return lci_write_with(dev, path, fits_fill, &j);
#else
        return lci_missing(dev, path, "writing FITS maps", LCI_FEATURE_FITS);
#endif
    }
    return lci_error(dev, LC_ERROR_UNSUPPORTED, "%s: '%s' is not a float-map format (.npy, .fits, .exr)", path, ext);
}
