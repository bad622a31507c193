/* Streaming inflate (gzstream.h). */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/gzstream.h"
#if LC_HAVE_ZLIB
#include <zlib.h>

#define IN_BUF (1 << 16)
#define OUT_BUF (1 << 16)

struct lci_gz {
    lc_device *dev;
    const char *path;
    FILE *f;
    int64_t size;      /* bytes in the file */
    int64_t buf_off;   /* file offset of in[0] */
    int state;         /* 0 inflating, 1 at the end of the data, -1 after an error */
    uint64_t out_total;
    z_stream z;
    unsigned char *out; /* getc's buffer: out[pos..len) not yet handed out */
    size_t pos, len;
    unsigned char in[IN_BUF];
};

static int64_t at(const lci_gz *g) { return g->buf_off + (int64_t)(g->z.next_in - g->in); }

/* Moves what is left of the input to the front and reads more: bytes now
 * available, or -1 after a read error (reported). */
static long refill(lci_gz *g)
{
    size_t keep = g->z.avail_in;
    g->buf_off = at(g);
    memmove(g->in, g->z.next_in, keep);
    size_t k = fread(g->in + keep, 1, IN_BUF - keep, g->f);
    if (k == 0 && ferror(g->f)) {
        g->state = -1;
        lci_error(g->dev, LC_ERROR_IO, "%s: byte %lld: read error: %s", g->path, (long long)g->buf_off + (long long)keep,
                  strerror(errno));
        return -1;
    }
    g->z.next_in = g->in;
    g->z.avail_in = (uInt)(keep + k);
    return (long)(keep + k);
}

lc_status lci_gz_open(lc_device *dev, const char *path, FILE *f, int64_t start, int64_t size, lci_gz **out)
{
    *out = NULL;
    lci_gz *g = calloc(1, sizeof *g);
    if (!g) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    g->dev = dev, g->path = path, g->f = f, g->size = size, g->buf_off = start;
    if (fseeko(f, (off_t)start, SEEK_SET) != 0) {
        free(g);
        return lci_error(dev, LC_ERROR_IO, "%s: byte %lld: cannot seek: %s", path, (long long)start, strerror(errno));
    }
    g->z.next_in = g->in;
    if (inflateInit2(&g->z, 15 + 32) != Z_OK) { /* 32: a gzip or a zlib header */
        free(g);
        return lci_error(dev, LC_ERROR_INTERNAL, "%s: zlib initialisation failed", path);
    }
    *out = g;
    return LC_OK;
}

void lci_gz_close(lci_gz *g)
{
    if (!g) return;
    inflateEnd(&g->z);
    free(g->out);
    free(g);
}

int64_t lci_gz_offset(const lci_gz *g) { return at(g); }

/* After a member's end: another gzip member continues the data; the end of
 * the file ends it; anything else is an error. */
static void after_member(lci_gz *g)
{
    if (g->z.avail_in < 2 && refill(g) < 0) return;
    if (g->z.avail_in == 0) {
        g->state = 1;
        return;
    }
    if (g->z.avail_in >= 2 && g->z.next_in[0] == 0x1f && g->z.next_in[1] == 0x8b) {
        inflateReset(&g->z);
        return;
    }
    g->state = -1;
    lci_error(g->dev, LC_ERROR_FORMAT,
              "%s: byte %lld: %lld bytes follow the end of the compressed data and are not a gzip member (a damaged "
              "or appended file?)",
              g->path, (long long)at(g), (long long)(g->size - at(g)));
}

/* Inflates up to n bytes into dst. */
static long long inflate_into(lci_gz *g, unsigned char *dst, size_t n)
{
    size_t got = 0;
    while (got < n && g->state == 0) {
        if (g->z.avail_in == 0) {
            long k = refill(g);
            if (k < 0) return -1;
            if (k == 0) {
                g->state = -1;
                lci_error(g->dev, LC_ERROR_FORMAT, "%s: byte %lld: the compressed data is truncated (it ends after %llu "
                          "inflated bytes)", g->path, (long long)at(g), (unsigned long long)g->out_total);
                return -1;
            }
        }
        size_t chunk = n - got > (1u << 30) ? (1u << 30) : n - got;
        g->z.next_out = dst + got;
        g->z.avail_out = (uInt)chunk;
        int r = inflate(&g->z, Z_NO_FLUSH);
        size_t made = chunk - g->z.avail_out;
        got += made;
        g->out_total += made;
        if (r == Z_STREAM_END) after_member(g);
        else if (r == Z_BUF_ERROR && g->z.avail_in == 0) continue; /* needs input */
        else if (r != Z_OK) {
            g->state = -1;
            lci_error(g->dev, LC_ERROR_FORMAT, "%s: byte %lld: corrupt compressed data (%s) after %llu inflated bytes",
                      g->path, (long long)at(g), g->z.msg ? g->z.msg : "zlib error", (unsigned long long)g->out_total);
            return -1;
        }
    }
    if (g->state < 0) return -1;
    return (long long)got;
}

long long lci_gz_read(lci_gz *g, void *dst, size_t n)
{
    size_t have = g->len - g->pos, take = have < n ? have : n;
    if (take) memcpy(dst, g->out + g->pos, take), g->pos += take;
    if (take == n) return (long long)n;
    long long k = inflate_into(g, (unsigned char *)dst + take, n - take);
    return k < 0 ? -1 : (long long)take + k;
}

int lci_gz_getc(lci_gz *g)
{
    if (g->pos < g->len) return g->out[g->pos++];
    if (!g->out && !(g->out = malloc(OUT_BUF))) {
        lci_error(g->dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", g->path);
        return -2;
    }
    long long k = inflate_into(g, g->out, OUT_BUF);
    if (k < 0) return -2;
    g->pos = 0, g->len = (size_t)k;
    return k ? g->out[g->pos++] : -1;
}

#else

lc_status lci_gz_open(lc_device *dev, const char *path, FILE *f, int64_t start, int64_t size, lci_gz **out)
{
    (void)f, (void)start, (void)size;
    *out = NULL;
    return lci_missing(dev, path, "gzip-compressed data", LCI_FEATURE_ZLIB);
}
void lci_gz_close(lci_gz *g) { (void)g; }
long long lci_gz_read(lci_gz *g, void *dst, size_t n) { (void)g, (void)dst, (void)n; return -1; }
int lci_gz_getc(lci_gz *g) { (void)g; return -2; }
int64_t lci_gz_offset(const lci_gz *g) { (void)g; return 0; }

#endif
