/* lc_image_write: SPEC.md "Output" conversion, then OpenImageIO through the
 * C++ shim. Files appear complete or not at all: the image goes to a private
 * temporary file next to the target (created with O_EXCL by mkstemps, so a
 * planted name or symlink is never followed), written with checked writes
 * and fsync, then renamed over the target. */
#define _GNU_SOURCE /* dladdr */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <dlfcn.h>
#include <pthread.h>
#include "host/internal.h"

/* The OpenImageIO shim (host/api/image_oiio.cpp) is a module loaded on the
 * first image write or check: linking OpenImageIO and the ~250 libraries it
 * pulls in costs every run ~0.2-0.3 s of dynamic linking (docs/bench/sph.md),
 * while float maps (.npy, .fits) and most commands never encode an image. */
typedef int (*oiio_encode_fn)(const char *path, const char *format_name, int width, int height, int channels,
                              int is_float, const void *pixels, void **bytes, size_t *nbytes, char *err, size_t errlen);
typedef int (*oiio_can_write_fn)(const char *path);

static pthread_once_t oiio_once = PTHREAD_ONCE_INIT;
static oiio_encode_fn oiio_encode;
static oiio_can_write_fn oiio_can_write;
static char oiio_why[768];

/* Where the module is: LANECAST_OIIO_MODULE alone when set; else beside
 * the object holding this code (an installed liblanecast: LIBDIR/lanecast/,
 * an installed program: ../LIBDIR/lanecast/), the configured install path,
 * the build tree's. */
static void oiio_load(void)
{
    char cand[4][1024];
    int n = 0;
    const char *env = getenv("LANECAST_OIIO_MODULE");
    if (env && *env) snprintf(cand[n++], sizeof cand[0], "%s", env);
    Dl_info di;
    if (n == 0 && dladdr(&oiio_why, &di) && di.dli_fname) { /* the object holding this code */
        char dir[900];
        snprintf(dir, sizeof dir, "%s", di.dli_fname);
        char *slash = strrchr(dir, '/');
        if (slash) {
            *slash = 0;
            snprintf(cand[n++], sizeof cand[0], "%s/lanecast/lanecast_oiio.so", dir);
            snprintf(cand[n++], sizeof cand[0], "%s/../%s/lanecast/lanecast_oiio.so", dir, LC_OIIO_LIBDIR);
        }
    }
    const char *fixed[] = {LC_OIIO_INSTALL, LC_OIIO_BUILD};
    const int nfixed = env && *env ? 0 : 2; /* the variable names the only place to look */
    size_t w = 0;
    for (int i = 0; i < n + nfixed; i++) {
        const char *path = i < n ? cand[i] : fixed[i - n];
        if (access(path, F_OK) != 0) continue;
        void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
        const char *e = h ? "no lci_oiio_encode in it" : dlerror();
        if (h) {
            *(void **)&oiio_encode = dlsym(h, "lci_oiio_encode"); /* POSIX's form (ISO C has no such cast) */
            *(void **)&oiio_can_write = dlsym(h, "lci_oiio_can_write");
            if (oiio_encode && oiio_can_write) return; /* kept loaded for the process */
            oiio_encode = NULL, oiio_can_write = NULL;
            dlclose(h);
        }
        if (w < sizeof oiio_why) w += (size_t)snprintf(oiio_why + w, sizeof oiio_why - w, "%s%s: %s", w ? "; " : "", path, e);
    }
    if (!w && nfixed)
        snprintf(oiio_why, sizeof oiio_why, "no lanecast_oiio.so at %.300s, %.200s or %.200s; LANECAST_OIIO_MODULE names "
                 "another", n ? cand[0] : "the program's folder", LC_OIIO_INSTALL, LC_OIIO_BUILD);
    else if (!w) snprintf(oiio_why, sizeof oiio_why, "LANECAST_OIIO_MODULE=%.600s: no such file", env);
}

/* 0 when the module is missing (oiio_why says where it was looked for). */
static int oiio_ready(void)
{
    pthread_once(&oiio_once, oiio_load);
    return oiio_encode != NULL;
}


static int is_float_format(const char *ext)
{
    static const char *const fl[] = {".exr", ".hdr", ".pfm", ".tif", ".tiff", ".fits"};
    for (size_t i = 0; i < sizeof fl / sizeof fl[0]; i++)
        if (!strcasecmp(ext, fl[i])) return 1;
    return 0;
}

/* Test hook: LANECAST_TEST_WRITE_LIMIT=N makes image writes fail with ENOSPC
 * after N bytes, as on a full disk. */
static long long write_limit(void)
{
    const char *e = getenv("LANECAST_TEST_WRITE_LIMIT");
    return e && *e ? atoll(e) : -1;
}


/* Writes all n bytes or fails with errno set. */
static int write_all(int fd, const unsigned char *b, size_t n)
{
    long long limit = write_limit();
    size_t done = 0;
    while (done < n) {
        size_t chunk = n - done > (1u << 20) ? (1u << 20) : n - done;
        if (limit >= 0 && (long long)(done + chunk) > limit) {
            errno = ENOSPC;
            return -1;
        }
        ssize_t k = write(fd, b + done, chunk);
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0) {
            if (k == 0) errno = EIO;
            return -1;
        }
        done += (size_t)k;
    }
    return 0;
}

lc_status lc_image_check(lc_device *device, const char *path)
{
    if (!path || !*path) return lci_error(device, LC_ERROR_INVALID_ARGUMENT, "image path is empty");
    const char *ext = lci_path_extension(path);
    if (!*ext)
        return lci_error(device, LC_ERROR_INVALID_ARGUMENT,
                         "%s: no file extension to choose an image format (.png, .exr, .tif, ...)", path);
    if (!oiio_ready())
        return lci_error(device, LC_ERROR_UNSUPPORTED, "%s: the OpenImageIO module could not be loaded (%s)", path,
                         oiio_why);
    if (!oiio_can_write(path))
        return lci_error(device, LC_ERROR_UNSUPPORTED, "%s: OpenImageIO cannot write '%s' files", path, ext);
    char tmp[LCI_TEMP_NAME];
    int slot;
    int fd = lci_temp_file(path, tmp, sizeof tmp, &slot);
    if (fd < 0) return lci_error(device, LC_ERROR_IO, "%s: cannot write here: %s", path, strerror(errno));
    close(fd);
    unlink(tmp);
    lci_temp_release(slot);
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
    const char *ext = lci_path_extension(path);
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
    lc_status st = lci_image_encode_write(device, path, d->width, d->height, ch, fl, buf);
    free(buf);
    return st;
}

/* Checks the written file, renames it into place; on error removes it. */
static lc_status finish(lc_device *device, const char *path, const char *tmp, int fd, int slot, int r, size_t nbytes,
                        char *err, size_t errlen)
{
    struct stat st;
    if (r == 0 && (fsync(fd) != 0 || fstat(fd, &st) != 0))
        r = -1, snprintf(err, errlen, "flushing the file to disk failed: %s", strerror(errno));
    if (r == 0 && (st.st_size == 0 || (nbytes && (size_t)st.st_size != nbytes)))
        r = -1, snprintf(err, errlen, "the written file holds %lld bytes, expected %zu", (long long)st.st_size, nbytes);
    if (close(fd) != 0 && r == 0) r = -1, snprintf(err, errlen, "closing the file failed: %s", strerror(errno));
    if (r != 0) {
        unlink(tmp);
        lci_temp_release(slot);
        return lci_error(device, LC_ERROR_IO, "%s: %s (nothing written)", path, err);
    }
    if (rename(tmp, path) != 0) {
        int e = errno;
        remove(tmp);
        lci_temp_release(slot);
        return lci_error(device, LC_ERROR_IO, "%s: cannot rename the finished file into place: %s", path, strerror(e));
    }
    lci_temp_release(slot);
    return LC_OK;
}

lc_status lci_image_encode_write(lc_device *device, const char *path, int width, int height, int ch, int fl,
                                 const void *buf)
{
    char tmp[LCI_TEMP_NAME], err[512] = "";
    int slot;
    int fd = lci_temp_file(path, tmp, sizeof tmp, &slot);
    if (fd < 0) return lci_error(device, LC_ERROR_IO, "%s: cannot create a temporary file next to it: %s", path, strerror(errno));
    lci_test_write_delay();
    void *bytes = NULL;
    size_t nbytes = 0;
    int r = oiio_ready() ? oiio_encode(tmp, path, width, height, ch, fl, buf, &bytes, &nbytes, err, sizeof err)
                         : (snprintf(err, sizeof err, "the OpenImageIO module could not be loaded (%.400s)", oiio_why), -1);
    if (r == 0 && bytes && write_all(fd, bytes, nbytes) != 0)
        r = -1, snprintf(err, sizeof err, "writing %zu bytes failed: %s", nbytes, strerror(errno));
    free(bytes);
    return finish(device, path, tmp, fd, slot, r, nbytes, err, sizeof err);
}

lc_status lci_write_bytes(lc_device *device, const char *path, const void *bytes, size_t n)
{
    char tmp[LCI_TEMP_NAME], err[512] = "";
    int slot;
    int fd = lci_temp_file(path, tmp, sizeof tmp, &slot);
    if (fd < 0) return lci_error(device, LC_ERROR_IO, "%s: cannot create a temporary file next to it: %s", path, strerror(errno));
    lci_test_write_delay();
    int r = 0;
    if (write_all(fd, bytes, n) != 0) r = -1, snprintf(err, sizeof err, "writing %zu bytes failed: %s", n, strerror(errno));
    return finish(device, path, tmp, fd, slot, r, n, err, sizeof err);
}

lc_status lci_write_with(lc_device *device, const char *path, int (*write)(void *user, const char *tmp, char *err,
                                                                          size_t errlen), void *user)
{
    char tmp[LCI_TEMP_NAME], err[512] = "";
    int slot;
    int fd = lci_temp_file(path, tmp, sizeof tmp, &slot);
    if (fd < 0) return lci_error(device, LC_ERROR_IO, "%s: cannot create a temporary file next to it: %s", path, strerror(errno));
    lci_test_write_delay();
    close(fd); /* the writer may replace the file (cfitsio's '!'): checked and flushed by name below */
    int r = write(user, tmp, err, sizeof err);
    fd = open(tmp, O_RDONLY);
    if (fd < 0) {
        unlink(tmp);
        lci_temp_release(slot);
        return lci_error(device, LC_ERROR_IO, "%s: %s (nothing written)", path, r ? err : strerror(errno));
    }
    return finish(device, path, tmp, fd, slot, r, 0, err, sizeof err);
}
