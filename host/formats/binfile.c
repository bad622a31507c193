/* Binary files with Fortran records (binfile.h). */
#include <errno.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "host/formats/binfile.h"
#include "host/formats/checked.h"

lc_status lci_bin_open(lc_device *dev, const char *path, const char *what, lci_bin *b)
{
    memset(b, 0, sizeof *b);
    b->dev = dev;
    b->path = path;
    b->marker = 4;
    lc_status s = lci_open_regular(dev, path, NULL, &b->f, &b->size);
    if (s != LC_OK) return s;
    unsigned char m[2] = {0, 0};
    if (fread(m, 1, 2, b->f) == 2 && m[0] == 0x1f && m[1] == 0x8b) {
        lci_bin_close(b);
        return lci_error(dev, LC_ERROR_UNSUPPORTED, "%s: gzip-compressed %s are not read (frames are found by seeking); "
                         "gunzip it first", path, what);
    }
    return LC_OK;
}

void lci_bin_close(lci_bin *b)
{
    if (b->f) fclose(b->f);
    b->f = NULL;
}

lc_status lci_bin_read(lci_bin *b, int64_t off, void *dst, size_t n, const char *what)
{
    if (off < 0 || off > b->size || (int64_t)n > b->size - off)
        return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: the file ends inside %s (%zu bytes needed, %lld left)",
                         b->path, (long long)off, what, n, (long long)(off < b->size ? b->size - off : 0));
    /* pread: no stdio buffer refilled for each small read after a seek (the
       XTC/TRR header scans read 56-92 bytes per frame) */
    int fd = fileno(b->f);
    for (size_t got = 0; got < n;) {
        ssize_t k = pread(fd, (char *)dst + got, n - got, (off_t)(off + (int64_t)got));
        if (k < 0 && errno == EINTR) continue;
        if (k <= 0)
            return lci_error(b->dev, LC_ERROR_IO, "%s: byte %lld: read error in %s: %s", b->path,
                             (long long)(off + (int64_t)got), what, k < 0 ? strerror(errno) : "the file shrank");
        got += (size_t)k;
    }
    if (n >= 4096) lci_load_progress(b->dev, (double)(off + (int64_t)n) / (double)b->size);
    return LC_OK;
}

static void swap_bytes(unsigned char *p, size_t w)
{
    for (size_t i = 0; i < w / 2; i++) {
        unsigned char t = p[i];
        p[i] = p[w - 1 - i];
        p[w - 1 - i] = t;
    }
}

void lci_bin_fix(const lci_bin *b, void *p, size_t n, size_t width)
{
    if (!b->swap || width < 2) return;
    unsigned char *c = p;
    for (size_t i = 0; i < n; i++) swap_bytes(c + i * width, width);
}

int32_t lci_bin_i32(const lci_bin *b, const void *p)
{
    int32_t v;
    memcpy(&v, p, 4);
    lci_bin_fix(b, &v, 1, 4);
    return v;
}

int64_t lci_bin_i64(const lci_bin *b, const void *p)
{
    int64_t v;
    memcpy(&v, p, 8);
    lci_bin_fix(b, &v, 1, 8);
    return v;
}

double lci_bin_f64(const lci_bin *b, const void *p)
{
    double v;
    memcpy(&v, p, 8);
    lci_bin_fix(b, &v, 1, 8);
    return v;
}

static lc_status marker_at(lci_bin *b, int64_t off, const char *what, int64_t *out)
{
    unsigned char m[8];
    lc_status s = lci_bin_read(b, off, m, (size_t)b->marker, what);
    if (s != LC_OK) return s;
    *out = b->marker == 8 ? lci_bin_i64(b, m) : (int64_t)lci_bin_i32(b, m);
    return LC_OK;
}

lc_status lci_bin_record(lci_bin *b, int64_t off, int64_t expect, const char *what, int64_t *len, int64_t *next)
{
    char w[160];
    snprintf(w, sizeof w, "the record marker of %s", what);
    int64_t n;
    lc_status s = marker_at(b, off, w, &n);
    if (s != LC_OK) return s;
    if (n < 0 || (expect >= 0 && n != expect))
        return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte %lld: %s: record marker says %lld bytes, expected %lld",
                         b->path, (long long)off, what, (long long)n, (long long)expect);
    int64_t m = b->marker;
    if (n > b->size - off - 2 * m)
        return lci_error(b->dev, LC_ERROR_FORMAT,
                         "%s: byte %lld: %s: a record of %lld bytes, but only %lld bytes remain in the file", b->path,
                         (long long)off, what, (long long)n, (long long)(b->size - off - m));
    int64_t end;
    snprintf(w, sizeof w, "the end marker of %s", what);
    if ((s = marker_at(b, off + m + n, w, &end)) != LC_OK) return s;
    if (end != n)
        return lci_error(b->dev, LC_ERROR_FORMAT,
                         "%s: byte %lld: %s: the record's end marker says %lld bytes, its start (byte %lld) %lld",
                         b->path, (long long)(off + m + n), what, (long long)end, (long long)off, (long long)n);
    *len = n;
    *next = off + 2 * m + n;
    return LC_OK;
}

lc_status lci_bin_seek_frame(lci_bin *b, int64_t k, lci_frame_header_fn header, void *frame)
{
    int64_t off = 0;
    for (int64_t i = 0;; i++) {
        if (i > 0 && off == b->size)
            return lci_error(b->dev, LC_ERROR_INVALID_ARGUMENT, "%s: frame %lld is past the end: the file holds %lld "
                             "frame%s", b->path, (long long)k, (long long)i, i == 1 ? "" : "s");
        int eof;
        int64_t next;
        lc_status s = header(b, off, i, frame, &next, &eof);
        if (s != LC_OK || i == k) return s;
        off = next;
    }
}

lc_status lci_bin_count_frames(lci_bin *b, lci_frame_header_fn header, void *frame, const char *what, int64_t *out)
{
    int64_t off = 0, k = 0, next;
    lc_status s = LC_OK;
    *out = 0;
    while (off < b->size) {
        int eof;
        s = header(b, off, k, frame, &next, &eof);
        if (s != LC_OK && eof && k > 0) { /* a last frame cut short: the complete ones count */
            lci_log(b->dev, LC_LOG_WARNING, "%s: %lld bytes after frame %lld are not a whole frame (a run cut short?); "
                    "ignored", b->path, (long long)(b->size - off), (long long)k - 1);
            s = LC_OK;
            break;
        }
        if (s != LC_OK) return s;
        off = next;
        k++;
    }
    if (k == 0) return lci_error(b->dev, LC_ERROR_FORMAT, "%s: byte 0: empty file, expected %s", b->path, what);
    *out = k;
    return LC_OK;
}
