/* RBF set files (docs/FORMATS-rbf.md), read through text_reader.h so gzip-compressed
 * files work too:
 *   text (issue 10): one item per line, `lanecast-rbf 1`, `bias B`,
 *     `count N`, then N lines `x y z s w`; lines starting with '#' (and
 *     blank lines) are skipped. Errors name the file and line.
 *   binary: a 32-byte little-endian header (magic, version, flags, count,
 *     bias, reserved) and count records of five float32. Errors name the file
 *     and byte offset.
 * Arrays grow with the records actually read, never to a declared count, so a
 * lying header cannot make the reader allocate more than the file holds. */
#include <ctype.h>
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/text_reader.h"
#include "host/formats/format.h"

#define MAX_RBFS ((uint64_t)INT32_MAX / 2) /* lc_rbf_create's limit */
static const unsigned char bin_magic[8] = {0x89, 'L', 'C', 'R', 'B', 'F', '\r', '\n'};
#define BIN_HEADER 32
#define BIN_RECORD 20
#define CHUNK 4096 /* records per read */

typedef struct rlist {
    float *c, *s, *w;
    size_t n, cap;
} rlist;

/* Room for one more record; -1 when out of memory. */
static int rlist_grow(rlist *l)
{
    if (l->n < l->cap) return 0;
    size_t cap = l->cap ? l->cap * 2 : 1024;
    float *c = realloc(l->c, cap * 3 * sizeof(float));
    if (!c) return -1;
    l->c = c;
    float *s = realloc(l->s, cap * sizeof(float));
    if (!s) return -1;
    l->s = s;
    float *w = realloc(l->w, cap * sizeof(float));
    if (!w) return -1;
    l->w = w;
    l->cap = cap;
    return 0;
}

static void rlist_free(rlist *l) { free(l->c), free(l->s), free(l->w); }

/* Hands the records over as an lc_rbf_desc (the registry frees them). */
static lc_status hand_over(lc_device *dev, const char *path, rlist *l, float bias, lci_loaded *out)
{
    lc_rbf_desc *d = calloc(1, sizeof *d);
    if (!d) {
        rlist_free(l);
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    d->count = l->n;
    d->centres = l->c, d->widths = l->s, d->weights = l->w;
    d->bias = bias;
    out->desc = d;
    lci_loaded_keep(out, l->c), lci_loaded_keep(out, l->s), lci_loaded_keep(out, l->w);
    return LC_OK;
}

/* ---------------------------------------------------------------- text */

/* Lines with numbers and errors naming them (text_reader.h: plain or gzip). */
typedef lci_text treader;

/* The next line that is not a comment or blank, trimmed at the start; 1 ok,
 * 0 end of file, -1 error (reported). */
static int next_item(treader *r, char **item)
{
    for (;;) {
        int rc = lci_text_line(r);
        if (rc <= 0) return rc;
        if (r->line[0] == '#') continue;
        char *s = r->line;
        while (isspace((unsigned char)*s)) s++;
        if (!*s) continue;
        s[strcspn(s, "\r\n")] = '\0';
        *item = s;
        return 1;
    }
}

/* Splits s into at most n whitespace-separated tokens; returns how many
 * there were (n + 1 when there are more). */
static int tokens(char *s, char **tok, int n)
{
    int k = 0;
    for (char *t = strtok(s, " \t"); t; t = strtok(NULL, " \t")) {
        if (k == n) return n + 1;
        tok[k++] = t;
    }
    return k;
}

/* A finite float; -1 when t is not a number or overflows float. */
static int parse_float(const char *t, float *out)
{
    char *end;
    errno = 0;
    double v = strtod(t, &end);
    if (end == t || *end || !isfinite(v) || !isfinite((float)v)) return -1;
    *out = (float)v;
    return 0;
}

/* "key value" with the given key; value in *val. */
static lc_status key_line(treader *r, const char *key, char **val)
{
    char *item;
    int rc = next_item(r, &item);
    if (rc < 0) return LC_ERROR_IO;
    if (rc == 0) return lci_error(r->dev, LC_ERROR_FORMAT, "%s:%ld: the file ends before the '%s' line", r->path,
                                  r->lineno, key);
    char *tok[2];
    int n = tokens(item, tok, 2);
    if (n != 2 || strcmp(tok[0], key))
        return lci_error(r->dev, LC_ERROR_FORMAT, "%s:%ld: expected '%s VALUE' (issue 10 order: lanecast-rbf 1, bias, "
                         "count, records)", r->path, r->lineno, key);
    *val = tok[1];
    return LC_OK;
}

static lc_status text_header(treader *r, float *bias, uint64_t *count)
{
    char *item, *v, *tok[2];
    int rc = next_item(r, &item);
    if (rc < 0) return LC_ERROR_IO;
    if (rc == 0 || tokens(item, tok, 2) != 2 || strcmp(tok[0], "lanecast-rbf"))
        return lci_error(r->dev, LC_ERROR_FORMAT, "%s:%ld: missing the header line 'lanecast-rbf 1'", r->path,
                         r->lineno);
    if (strcmp(tok[1], "1"))
        return lci_error(r->dev, LC_ERROR_FORMAT, "%s:%ld: version '%s'; this build reads version 1", r->path,
                         r->lineno, tok[1]);
    lc_status s = key_line(r, "bias", &v);
    if (s != LC_OK) return s;
    if (parse_float(v, bias))
        return lci_error(r->dev, LC_ERROR_FORMAT, "%s:%ld: bias '%s' is not a finite number", r->path, r->lineno, v);
    if ((s = key_line(r, "count", &v)) != LC_OK) return s;
    char *end;
    errno = 0;
    unsigned long long c = strtoull(v, &end, 10);
    if (!isdigit((unsigned char)v[0]) || *end || errno || c > MAX_RBFS)
        return lci_error(r->dev, LC_ERROR_FORMAT, "%s:%ld: count '%s' is not an integer in 0..%" PRIu64, r->path,
                         r->lineno, v, MAX_RBFS);
    *count = c;
    return LC_OK;
}

/* One record line into l. */
static lc_status text_record(treader *r, char *item, rlist *l)
{
    static const char *const names[5] = {"x", "y", "z", "width s", "weight w"};
    char *tok[5];
    float v[5];
    if (tokens(item, tok, 5) != 5)
        return lci_error(r->dev, LC_ERROR_FORMAT, "%s:%ld: expected 5 numbers 'x y z s w'", r->path, r->lineno);
    for (int k = 0; k < 5; k++)
        if (parse_float(tok[k], &v[k]))
            return lci_error(r->dev, LC_ERROR_FORMAT, "%s:%ld: %s '%s' is not a finite number", r->path, r->lineno,
                             names[k], tok[k]);
    if (!(v[3] > 0.0f))
        return lci_error(r->dev, LC_ERROR_FORMAT, "%s:%ld: width %g, expected > 0", r->path, r->lineno, (double)v[3]);
    if (rlist_grow(l)) return lci_error(r->dev, LC_ERROR_OUT_OF_MEMORY, "%s:%ld: out of memory", r->path, r->lineno);
    memcpy(l->c + 3 * l->n, v, sizeof(float) * 3);
    l->s[l->n] = v[3], l->w[l->n] = v[4];
    l->n++;
    return LC_OK;
}

static lc_status text_body(treader *r, uint64_t count, rlist *l)
{
    char *item;
    int rc;
    while ((rc = next_item(r, &item)) == 1) {
        if (l->n == count)
            return lci_error(r->dev, LC_ERROR_FORMAT, "%s:%ld: more records than count %" PRIu64, r->path, r->lineno,
                             count);
        lc_status s = text_record(r, item, l);
        if (s != LC_OK) return s;
    }
    if (rc < 0) return LC_ERROR_IO;
    if (l->n < count)
        return lci_error(r->dev, LC_ERROR_FORMAT, "%s:%ld: count %" PRIu64 " but the file ends after %zu records",
                         r->path, r->lineno, count, l->n);
    return LC_OK;
}

static lc_status text_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    treader r;
    lc_status os = lci_text_open(dev, a->path, &r);
    if (os != LC_OK) return os;
    float bias = 0.0f;
    uint64_t count = 0;
    rlist l = {0};
    lc_status s = text_header(&r, &bias, &count);
    if (s == LC_OK) s = text_body(&r, count, &l);
    lci_text_close(&r);
    if (s != LC_OK) {
        rlist_free(&l);
        return s;
    }
    return hand_over(dev, a->path, &l, bias, out);
}

/* ---------------------------------------------------------------- binary */

static uint32_t le32(const unsigned char *b)
{
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static float lef(const unsigned char *b)
{
    uint32_t u = le32(b);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

/* Reads up to n bytes; returns how many (short at the end), -1 on error. */
static long long read_bytes(lci_text *gz, unsigned char *buf, size_t n) { return lci_text_read(gz, buf, n); }

static lc_status bin_header(lc_device *dev, const char *path, lci_text *gz, float *bias, uint64_t *count)
{
    unsigned char h[BIN_HEADER];
    long long k = read_bytes(gz, h, sizeof h);
    if (k < 0) return lci_error(dev, LC_ERROR_IO, "%s: read error", path);
    if (k < BIN_HEADER)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: byte %lld: truncated header (%d bytes expected)", path, k, BIN_HEADER);
    if (memcmp(h, bin_magic, sizeof bin_magic))
        return lci_error(dev, LC_ERROR_FORMAT, "%s: byte 0: not a binary RBF file (bad magic)", path);
    if (le32(h + 8) != 1)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: byte 8: version %" PRIu32 "; this build reads version 1", path,
                         le32(h + 8));
    if (le32(h + 12) != 0 || le32(h + 28) != 0)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: byte %d: reserved field is not zero", path, le32(h + 12) ? 12 : 28);
    *count = (uint64_t)le32(h + 16) | (uint64_t)le32(h + 20) << 32;
    if (*count > MAX_RBFS)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: byte 16: count %" PRIu64 " exceeds %" PRIu64, path, *count, MAX_RBFS);
    *bias = lef(h + 24);
    if (!isfinite(*bias)) return lci_error(dev, LC_ERROR_FORMAT, "%s: byte 24: bias is not finite", path);
    return LC_OK;
}

/* Record i (at byte off) into l. */
static lc_status bin_record(lc_device *dev, const char *path, const unsigned char *b, uint64_t off, rlist *l)
{
    static const char *const names[5] = {"x", "y", "z", "width s", "weight w"};
    float v[5];
    for (int k = 0; k < 5; k++) {
        v[k] = lef(b + 4 * k);
        if (!isfinite(v[k]))
            return lci_error(dev, LC_ERROR_FORMAT, "%s: byte %" PRIu64 ": %s is not finite", path, off + 4 * (uint64_t)k,
                             names[k]);
    }
    if (!(v[3] > 0.0f))
        return lci_error(dev, LC_ERROR_FORMAT, "%s: byte %" PRIu64 ": width %g, expected > 0", path, off + 12,
                         (double)v[3]);
    if (rlist_grow(l)) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    memcpy(l->c + 3 * l->n, v, sizeof(float) * 3);
    l->s[l->n] = v[3], l->w[l->n] = v[4];
    l->n++;
    return LC_OK;
}

static lc_status bin_body(lc_device *dev, const char *path, lci_text *gz, uint64_t count, unsigned char *buf, rlist *l)
{
    uint64_t off = BIN_HEADER;
    for (uint64_t i = 0; i < count;) {
        uint64_t want = count - i < CHUNK ? count - i : CHUNK;
        long long k = read_bytes(gz, buf, (size_t)(want * BIN_RECORD));
        if (k < 0) return lci_error(dev, LC_ERROR_IO, "%s: byte %" PRIu64 ": read error", path, off);
        uint64_t whole = (uint64_t)k / BIN_RECORD;
        for (uint64_t j = 0; j < whole; j++, i++, off += BIN_RECORD) {
            lc_status s = bin_record(dev, path, buf + j * BIN_RECORD, off, l);
            if (s != LC_OK) return s;
        }
        if (whole < want)
            return lci_error(dev, LC_ERROR_FORMAT,
                             "%s: byte %" PRIu64 ": truncated: record %" PRIu64 " of %" PRIu64 " needs %d bytes, %lld left",
                             path, off, i, count, BIN_RECORD, k - (long long)(whole * BIN_RECORD));
    }
    unsigned char extra;
    if (read_bytes(gz, &extra, 1) == 1)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: byte %" PRIu64 ": data after the %" PRIu64 " records of count", path,
                         off, count);
    return LC_OK;
}

static lc_status bin_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    lci_text file;
    lc_status os = lci_text_open(dev, a->path, &file);
    if (os != LC_OK) return os;
    lci_text *gz = &file;
    float bias = 0.0f;
    uint64_t count = 0;
    rlist l = {0};
    unsigned char *buf = malloc(CHUNK * BIN_RECORD);
    lc_status s = buf ? bin_header(dev, a->path, gz, &bias, &count)
                      : lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", a->path);
    if (s == LC_OK) s = bin_body(dev, a->path, gz, count, buf, &l);
    free(buf);
    lci_text_close(gz);
    if (s != LC_OK) {
        rlist_free(&l);
        return s;
    }
    return hand_over(dev, a->path, &l, bias, out);
}

/* ---------------------------------------------------------------- registry */

/* The first line that is not a comment or blank starts with "lanecast-rbf". */
static int text_magic(const unsigned char *h, size_t n)
{
    size_t i = 0;
    while (i < n) {
        if (h[i] == '#') {
            while (i < n && h[i] != '\n') i++;
            i++;
            continue;
        }
        if (isspace(h[i])) {
            i++;
            continue;
        }
        static const char word[] = "lanecast-rbf";
        size_t w = sizeof word - 1;
        return n - i > w && !memcmp(h + i, word, w) && (h[i + w] == ' ' || h[i + w] == '\t');
    }
    return 0;
}

static int bin_magic_test(const unsigned char *h, size_t n)
{
    return n >= sizeof bin_magic && !memcmp(h, bin_magic, sizeof bin_magic);
}

const lci_format lci_format_rbf = {
    .name = "rbf", .kind = LC_KIND_RBF, .extensions = ".rbf", .options = "",
    .description = "RBF set, text: 'lanecast-rbf 1', 'bias B', 'count N', N lines 'x y z s w'; # comments",
    .magic = text_magic, .read = text_read};
const lci_format lci_format_rbf_binary = {
    .name = "rbf-binary", .kind = LC_KIND_RBF, .extensions = ".rbf", .options = "",
    .description = "RBF set, binary: 32-byte little-endian header and float32 x y z s w records (docs/FORMATS-rbf.md)",
    .magic = bin_magic_test, .read = bin_read};
