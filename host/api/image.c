/* lc_image_write: SPEC.md "Output" conversion, then OpenImageIO through the
 * C++ shim. Files appear complete or not at all (temporary name, rename). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>
#include "host/internal.h"

int lci_oiio_write(const char *path, int width, int height, int channels, int is_float, const void *pixels,
                   char *err, size_t errlen);
int lci_oiio_can_write(const char *path);

static const char *extension(const char *path)
{
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(path, '.');
    if (!dot || (slash && dot < slash)) return "";
    return dot;
}

static int is_float_format(const char *ext)
{
    static const char *const fl[] = {".exr", ".hdr", ".pfm", ".tif", ".tiff", ".fits"};
    for (size_t i = 0; i < sizeof fl / sizeof fl[0]; i++)
        if (!strcasecmp(ext, fl[i])) return 1;
    return 0;
}

/* A temporary name next to the target with the same extension, so OIIO picks
 * the same format. */
static int temp_name(const char *path, char *out, size_t n)
{
    const char *ext = extension(path);
    size_t stem = strlen(path) - strlen(ext);
    int w = snprintf(out, n, "%.*s.lanecast-tmp-%ld%s", (int)stem, path, (long)getpid(), ext);
    return w > 0 && (size_t)w < n;
}

lc_status lc_image_check(lc_device *device, const char *path)
{
    if (!path || !*path) return lci_error(device, LC_ERROR_INVALID_ARGUMENT, "image path is empty");
    const char *ext = extension(path);
    if (!*ext)
        return lci_error(device, LC_ERROR_INVALID_ARGUMENT,
                         "%s: no file extension to choose an image format (.png, .exr, .tif, ...)", path);
    if (!lci_oiio_can_write(path))
        return lci_error(device, LC_ERROR_UNSUPPORTED, "%s: OpenImageIO cannot write '%s' files", path, ext);
    char tmp[4096];
    if (!temp_name(path, tmp, sizeof tmp)) return lci_error(device, LC_ERROR_INVALID_ARGUMENT, "%s: path too long", path);
    FILE *fp = fopen(tmp, "wb");
    if (!fp) return lci_error(device, LC_ERROR_IO, "%s: cannot write here: %s", path, strerror(errno));
    fclose(fp);
    remove(tmp);
    return LC_OK;
}

static unsigned char quantise(float c)
{
    c = c < 0.0f ? 0.0f : c > 1.0f ? 1.0f : c;
    return (unsigned char)lrintf(255.0f * c);
}

lc_status lc_image_write(lc_device *device, const char *path, const lc_image_desc *d)
{
    if (!path) return lci_error(device, LC_ERROR_INVALID_ARGUMENT, "lc_image_write: path is NULL");
    if (!d) return lci_error(device, LC_ERROR_INVALID_ARGUMENT, "lc_image_write: desc is NULL");
    if (!d->rgba) return lci_error(device, LC_ERROR_INVALID_ARGUMENT, "lc_image_write: rgba is NULL");
    if (d->width < 1 || d->height < 1 || d->width > LC_MAX_IMAGE_SIDE || d->height > LC_MAX_IMAGE_SIDE)
        return lci_error(device, LC_ERROR_INVALID_ARGUMENT, "lc_image_write: size %dx%d, expected 1 to %d per side",
                         d->width, d->height, LC_MAX_IMAGE_SIDE);
    lc_status s = lc_image_check(device, path);
    if (s != LC_OK) return s;
    const char *ext = extension(path);
    int fl = is_float_format(ext);
    int ch = d->alpha ? 4 : 3;
    size_t n = (size_t)d->width * (size_t)d->height;
    void *buf = malloc(n * (size_t)ch * (fl ? sizeof(float) : 1));
    if (!buf) return lci_error(device, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    const float bg[3] = {d->background.x, d->background.y, d->background.z};
    for (size_t i = 0; i < n; i++) {
        const float *p = d->rgba + 4 * i;
        float o[4];
        if (!d->alpha) {
            for (int c = 0; c < 3; c++) o[c] = p[c] + (1.0f - p[3]) * bg[c];
        } else if (fl) {
            for (int c = 0; c < 4; c++) o[c] = p[c]; /* premultiplied */
        } else {
            for (int c = 0; c < 3; c++) o[c] = p[3] > 0.0f ? p[c] / p[3] : 0.0f; /* straight */
            o[3] = p[3];
        }
        if (fl) memcpy((float *)buf + i * (size_t)ch, o, sizeof(float) * (size_t)ch);
        else
            for (int c = 0; c < ch; c++) ((unsigned char *)buf)[i * (size_t)ch + (size_t)c] = quantise(o[c]);
    }
    char tmp[4096], err[512] = "";
    temp_name(path, tmp, sizeof tmp);
    int r = lci_oiio_write(tmp, d->width, d->height, ch, fl, buf, err, sizeof err);
    free(buf);
    if (r != 0) {
        remove(tmp);
        return lci_error(device, LC_ERROR_IO, "%s: %s", path, err);
    }
    if (rename(tmp, path) != 0) {
        int e = errno;
        remove(tmp);
        return lci_error(device, LC_ERROR_IO, "%s: cannot rename the finished image into place: %s", path, strerror(e));
    }
    return LC_OK;
}
