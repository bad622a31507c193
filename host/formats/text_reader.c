/* Plain or gzip-compressed input for the particle formats (text_reader.h).
 * Plain files are read with stdio, gzip ones through the streaming inflater
 * (gzstream.h: fixed buffers, several members read as one, trailing bytes an
 * error); a gzip file is
 * recognised by its first two bytes (1f 8b, RFC 1952), not its name. In a
 * build without zlib (-Dzlib=disabled) a gzip file fails to open with one
 * line naming the file, zlib and its Debian package. */
#include <ctype.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/checked.h"
#include "host/formats/gzstream.h"
#include "host/formats/text_reader.h"

/* Bytes of the file consumed so far (compressed bytes for gzip). */
static long long consumed(const lci_text *t)
{
    if (t->gz) return (long long)lci_gz_offset(t->gz);
    return t->f ? (long long)ftello(t->f) : 0;
}

static void report(const lci_text *t)
{
    if (t->size > 0) lci_load_progress(t->dev, (double)consumed(t) / (double)t->size);
}

/* Opens a regular file and tells whether it starts with the gzip magic. */
static lc_status open_file(lc_device *dev, const char *path, FILE **f, int64_t *size, int *gz)
{
    lc_status s = lci_open_regular(dev, path, NULL, f, size);
    if (s != LC_OK) return s;
    unsigned char m[2] = {0, 0};
    *gz = fread(m, 1, 2, *f) == 2 && m[0] == 0x1f && m[1] == 0x8b;
    rewind(*f);
    return LC_OK;
}

lc_status lci_text_open(lc_device *dev, const char *path, lci_text *t)
{
    memset(t, 0, sizeof *t);
    t->dev = dev;
    t->path = path;
    int gz;
    int64_t size;
    lc_status s = open_file(dev, path, &t->f, &size, &gz);
    if (s != LC_OK) return s;
    t->size = size;
    if (gz) {
        if (!LC_HAVE_ZLIB) s = lci_missing(dev, path, "gzip-compressed input", LCI_FEATURE_ZLIB);
        else s = lci_gz_open(dev, path, t->f, 0, size, &t->gz);
        if (s != LC_OK) lci_text_close(t);
    }
    return s;
}

void lci_text_close(lci_text *t)
{
    lci_gz_close(t->gz);
    if (t->f) fclose(t->f);
    t->gz = NULL;
    t->f = NULL;
}

/* The next byte: 0..255, -1 at the end, -2 after an error (reported). */
static int next_byte(lci_text *t)
{
    if (t->gz) return lci_gz_getc(t->gz);
    int c = getc_unlocked(t->f);
    if (c != EOF) return c;
    if (ferror(t->f)) {
        lci_error(t->dev, LC_ERROR_IO, "%s:%ld: read error: %s", t->path, t->lineno + 1, strerror(errno));
        return -2;
    }
    return -1;
}

int lci_text_line(lci_text *t)
{
    size_t len = 0, cap = sizeof t->line - 1;
    int c;
    while ((c = next_byte(t)) >= 0) {
        if (c == 0) {
            lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: a NUL byte at column %zu (binary data in a text file?)", t->path,
                      t->lineno + 1, len + 1);
            return -1;
        }
        if (c == '\n') {
            if (len < cap) t->line[len++] = '\n'; /* a line of exactly cap characters keeps no newline */
            break;
        }
        if (len == cap) {
            lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: line longer than %zu characters", t->path, t->lineno + 1, cap);
            return -1;
        }
        t->line[len++] = (char)c;
    }
    if (c == -2) return -1;
    if (c == -1 && len == 0) return 0;
    t->line[len] = '\0';
    t->lineno++;
    if (!(t->lineno & 4095)) report(t);
    return 1;
}

long long lci_text_read(lci_text *t, void *dst, size_t n)
{
    size_t got = 0;
    while (got < n) {
        size_t chunk = n - got > (1u << 24) ? (1u << 24) : n - got;
        size_t k;
        if (t->gz) {
            long long r = lci_gz_read(t->gz, (unsigned char *)dst + got, chunk);
            if (r < 0) return -1;
            k = (size_t)r;
        } else {
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
    FILE *f;
    int64_t size;
    lc_status s = open_file(dev, path, &f, &size, gzip);
    if (s != LC_OK) return s;
    if (*gzip) {
        /* a read error here only means no magic bytes; the reader reports it.
           Without zlib: no magic bytes to look at; the extension decides and
           the reader says what is missing */
        lci_gz *g = NULL;
        char keep[LCI_MSG_MAX];
        snprintf(keep, sizeof keep, "%s", lc_last_error());
        if (LC_HAVE_ZLIB && lci_gz_open(NULL, path, f, 0, size, &g) == LC_OK) {
            long long k = lci_gz_read(g, head, cap);
            *n = k > 0 ? (size_t)k : 0;
            lci_gz_close(g);
        }
        lci_error(NULL, LC_OK, "%s", keep);
    } else {
        *n = fread(head, 1, cap, f);
    }
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
