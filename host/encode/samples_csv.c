/* CSV samples for the encoder: a header line naming the columns (x, y, z and
 * value in any order, case-insensitive, optionally quoted; other columns are
 * ignored), then one sample per line, comma-separated. Lines starting with
 * '#' and blank lines are skipped. Every error names the file and the line.
 * Plain or gzip (text_reader.h); arrays grow with the rows read. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "host/encode/encode.h"
#include "host/formats/text_reader.h"

#define MAX_COLS 256

typedef struct rows {
    float *p, *v;
    size_t n, cap;
} rows;

static int grow(rows *r)
{
    if (r->n < r->cap) return 0;
    size_t cap = r->cap ? r->cap * 2 : 4096;
    if (cap > LCI_MAX_SAMPLES) cap = LCI_MAX_SAMPLES;
    if (cap <= r->n) return -1;
    float *p = realloc(r->p, sizeof(float) * 3 * cap);
    if (!p) return -1;
    r->p = p;
    float *v = realloc(r->v, sizeof(float) * cap);
    if (!v) return -1;
    r->v = v;
    r->cap = cap;
    return 0;
}

static char *trim(char *s)
{
    while (isspace((unsigned char)*s)) s++;
    size_t n = strlen(s);
    while (n && isspace((unsigned char)s[n - 1])) s[--n] = 0;
    if (n >= 2 && s[0] == '"' && s[n - 1] == '"') s[n - 1] = 0, s++;
    return s;
}

/* Splits line at commas into at most MAX_COLS fields; the count, or -1 for more. */
static int split(char *line, char **f)
{
    line[strcspn(line, "\r\n")] = 0;
    int n = 0;
    for (char *s = line;; n++) {
        if (n == MAX_COLS) return -1;
        char *c = strchr(s, ',');
        if (c) *c = 0;
        f[n] = trim(s);
        if (!c) return n + 1;
        s = c + 1;
    }
}

/* The next line that is not blank or a comment: 1, 0 at the end, -1 error. */
static int next(lci_text *t)
{
    for (;;) {
        int rc = lci_text_line(t);
        if (rc <= 0) return rc;
        const char *s = t->line;
        while (isspace((unsigned char)*s)) s++;
        if (*s && *s != '#') return 1;
    }
}

static lc_status header(lci_text *t, int col[4], int *ncols)
{
    static const char *const want[4] = {"x", "y", "z", "value"};
    char *f[MAX_COLS];
    int rc = next(t);
    if (rc < 0) return LC_ERROR_IO;
    if (rc == 0) return lci_error(t->dev, LC_ERROR_FORMAT, "%s: no header line (expected columns x,y,z,value)", t->path);
    int n = split(t->line, f);
    if (n < 0) return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: more than %d columns", t->path, t->lineno, MAX_COLS);
    for (int k = 0; k < 4; k++) {
        col[k] = -1;
        for (int i = 0; i < n; i++)
            if (!strcasecmp(f[i], want[k])) {
                if (col[k] >= 0)
                    return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: column '%s' appears twice", t->path, t->lineno,
                                     want[k]);
                col[k] = i;
            }
        if (col[k] < 0)
            return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: the header names no column '%s' (expected x,y,z,value)",
                             t->path, t->lineno, want[k]);
    }
    *ncols = n;
    return LC_OK;
}

static lc_status row(lci_text *t, const int col[4], int ncols, rows *r)
{
    static const char *const names[4] = {"x", "y", "z", "value"};
    char *f[MAX_COLS];
    int n = split(t->line, f);
    if (n != ncols)
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: %d columns, the header has %d", t->path, t->lineno,
                         n < 0 ? MAX_COLS + 1 : n, ncols);
    float x[4];
    for (int k = 0; k < 4; k++) {
        char *end;
        const char *s = f[col[k]];
        errno = 0;
        double d = strtod(s, &end);
        if (end == s || *end)
            return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: %s '%s' is not a number", t->path, t->lineno, names[k], s);
        if (!isfinite(d) || !isfinite((float)d))
            return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: %s '%s' is not finite", t->path, t->lineno, names[k], s);
        x[k] = (float)d;
    }
    if (grow(r))
        return lci_error(t->dev, LC_ERROR_OUT_OF_MEMORY, "%s:%ld: out of memory (or more than %zu samples)", t->path,
                         t->lineno, LCI_MAX_SAMPLES);
    memcpy(r->p + 3 * r->n, x, sizeof(float) * 3);
    r->v[r->n++] = x[3];
    return LC_OK;
}

lc_status lci_samples_read_csv(lc_device *dev, const char *path, lc_samples **out)
{
    *out = NULL;
    lci_text t;
    lc_status s = lci_text_open(dev, path, &t);
    if (s != LC_OK) return s;
    int col[4], ncols = 0, rc = 0;
    rows r = {0};
    s = header(&t, col, &ncols);
    while (s == LC_OK && (rc = next(&t)) == 1) s = row(&t, col, ncols, &r);
    if (s == LC_OK && rc < 0) s = LC_ERROR_IO;
    if (s == LC_OK && r.n == 0)
        s = lci_error(dev, LC_ERROR_FORMAT, "%s:%ld: no samples after the header", path, t.lineno);
    lci_text_close(&t);
    if (s != LC_OK) {
        free(r.p), free(r.v);
        return s;
    }
    return lci_samples_adopt(dev, path, r.p, r.v, r.n, "csv", 0, out);
}
