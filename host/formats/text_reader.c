/* Plain or gzip-compressed input for the particle formats (text_reader.h).
 * Plain files are read with stdio, gzip ones with zlib; a gzip file is
 * recognised by its first two bytes (1f 8b, RFC 1952), not its name. In a
 * build without zlib (-Dzlib=disabled) a gzip file fails to open with one
 * line naming the file, zlib and its Debian package. */
#include <ctype.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/text_reader.h"
#if LC_HAVE_ZLIB
#include <zlib.h>
#endif

/* 1 if the file starts with the gzip magic, 0 if not, -1 if it cannot be opened. */
/* Bytes of the file consumed so far (compressed bytes for gzip). */
static long long consumed(const lci_text *t)
{
#if LC_HAVE_ZLIB
    if (t->gz) return (long long)gzoffset((gzFile)t->gz);
#endif
    return t->f ? (long long)ftello(t->f) : 0;
}

static void report(const lci_text *t)
{
    if (t->size > 0) lci_load_progress(t->dev, (double)consumed(t) / (double)t->size);
}

static int is_gzip(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return -1;
    unsigned char m[2] = {0, 0};
    int gz = fread(m, 1, 2, f) == 2 && m[0] == 0x1f && m[1] == 0x8b;
    fclose(f);
    return gz;
}

lc_status lci_text_open(lc_device *dev, const char *path, lci_text *t)
{
    memset(t, 0, sizeof *t);
    t->dev = dev;
    t->path = path;
    int gz = is_gzip(path);
    if (gz < 0) return lci_error(dev, LC_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    if (gz) {
#if LC_HAVE_ZLIB
        gzFile g = gzopen(path, "rb");
        if (!g) return lci_error(dev, LC_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
        gzbuffer(g, 1 << 18);
        t->gz = g;
        FILE *f = fopen(path, "rb");
        if (f && fseeko(f, 0, SEEK_END) == 0) t->size = ftello(f);
        if (f) fclose(f);
        return LC_OK;
#else
        return lci_missing(dev, path, "gzip-compressed input", LCI_FEATURE_ZLIB);
#endif
    }
    t->f = fopen(path, "rb");
    if (!t->f) return lci_error(dev, LC_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    if (fseeko(t->f, 0, SEEK_END) == 0) t->size = ftello(t->f);
    rewind(t->f);
    return LC_OK;
}

void lci_text_close(lci_text *t)
{
#if LC_HAVE_ZLIB
    if (t->gz) gzclose((gzFile)t->gz);
#endif
    if (t->f) fclose(t->f);
    t->gz = NULL;
    t->f = NULL;
}

int lci_text_line(lci_text *t)
{
#if LC_HAVE_ZLIB
    if (t->gz) {
        if (!gzgets((gzFile)t->gz, t->line, sizeof t->line)) {
            int err;
            const char *msg = gzerror((gzFile)t->gz, &err);
            if (err != Z_OK && err != Z_STREAM_END) {
                lci_error(t->dev, LC_ERROR_IO, "%s:%ld: read error: %s", t->path, t->lineno + 1, msg);
                return -1;
            }
            return 0;
        }
    } else
#endif
    if (!fgets(t->line, sizeof t->line, t->f)) {
        if (ferror(t->f)) {
            lci_error(t->dev, LC_ERROR_IO, "%s:%ld: read error: %s", t->path, t->lineno + 1, strerror(errno));
            return -1;
        }
        return 0;
    }
    t->lineno++;
    if (!(t->lineno & 4095)) report(t);
    size_t len = strlen(t->line);
    if (len == sizeof t->line - 1 && t->line[len - 1] != '\n') {
        lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: line longer than %zu characters", t->path, t->lineno,
                  sizeof t->line - 2);
        return -1;
    }
    return 1;
}

long long lci_text_read(lci_text *t, void *dst, size_t n)
{
    size_t got = 0;
    while (got < n) {
        size_t chunk = n - got > (1u << 30) ? (1u << 30) : n - got;
        size_t k;
#if LC_HAVE_ZLIB
        if (t->gz) {
            int r = gzread((gzFile)t->gz, (unsigned char *)dst + got, (unsigned)chunk);
            if (r < 0) return lci_error(t->dev, LC_ERROR_IO, "%s: read error", t->path), -1;
            k = (size_t)r;
        } else
#endif
        {
            k = fread((unsigned char *)dst + got, 1, chunk, t->f);
            if (k < chunk && ferror(t->f))
                return lci_error(t->dev, LC_ERROR_IO, "%s: read error: %s", t->path, strerror(errno)), -1;
        }
        if (k == 0) break;
        got += k;
        report(t);
    }
    return (long long)got;
}

lc_status lci_file_head(lc_device *dev, const char *path, unsigned char *head, size_t cap, size_t *n, int *gzip)
{
    *n = 0;
    *gzip = is_gzip(path);
    if (*gzip < 0) return lci_error(dev, LC_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    if (*gzip) {
#if LC_HAVE_ZLIB /* a read error here only means no magic bytes; the reader reports it */
        gzFile g = gzopen(path, "rb");
        if (!g) return lci_error(dev, LC_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
        int k = gzread(g, head, (unsigned)cap);
        gzclose(g);
        *n = k > 0 ? (size_t)k : 0;
#endif /* else: no magic bytes to look at; the extension decides and the reader says what is missing */
        return LC_OK;
    }
    FILE *f = fopen(path, "rb");
    if (!f) return lci_error(dev, LC_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    *n = fread(head, 1, cap, f);
    fclose(f);
    return LC_OK;
}

int lci_parse_float(const char *s, float *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || errno == ERANGE) return -1;
    while (*end && isspace((unsigned char)*end)) end++;
    if (*end) return -1;
    *out = (float)v;
    return 0;
}

void lci_column(const char *line, int a, int b, char *out, size_t n)
{
    size_t len = strlen(line), k = 0;
    for (int c = a - 1; c < b && (size_t)c < len && k + 1 < n; c++) {
        char ch = line[c];
        if (ch == '\n' || ch == '\r') break;
        out[k++] = ch;
    }
    out[k] = '\0';
    char *s = out;
    while (isspace((unsigned char)*s)) s++;
    memmove(out, s, strlen(s) + 1);
    k = strlen(out);
    while (k && isspace((unsigned char)out[k - 1])) out[--k] = '\0';
}
