/* VTK legacy files as encoder samples (VTK File Formats, "Simple Legacy
 * Formats"): DATASET POLYDATA or UNSTRUCTURED_GRID, ASCII or BINARY (big
 * endian), versions 2.0 to 5.1. The points are the sample positions and
 * the first single-component point data array (SCALARS, or an array of a
 * FIELD) their values. Cell sections (VERTICES, LINES, POLYGONS,
 * TRIANGLE_STRIPS, CELLS with or without OFFSETS/CONNECTIVITY, CELL_TYPES),
 * CELL_DATA and other point attributes are skipped. Errors name the file and
 * the line, or the byte offset inside binary data. The file is read whole
 * (plain or gzip), growing with the bytes actually there. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "host/encode/encode.h"
#include "host/formats/text_reader.h"

typedef struct vtk {
    lc_device *dev;
    const char *path;
    unsigned char *b;
    size_t n, pos;
    long line; /* of pos */
    int binary;
    int v5;    /* version >= 5: CELLS with OFFSETS and CONNECTIVITY */
} vtk;

#define BAD(r, ...) lci_error((r)->dev, LC_ERROR_FORMAT, __VA_ARGS__)

int lci_vtk_magic(const unsigned char *h, size_t n)
{
    static const char m[] = "# vtk DataFile";
    return n >= sizeof m - 1 && !memcmp(h, m, sizeof m - 1);
}

static lc_status slurp(lc_device *dev, const char *path, vtk *r)
{
    lci_text t;
    lc_status s = lci_text_open(dev, path, &t);
    if (s != LC_OK) return s;
    size_t cap = 1 << 16;
    r->b = malloc(cap + 1);
    long long k = 1;
    while (r->b && k > 0) {
        if (r->n == cap) {
            unsigned char *nb = cap < ((size_t)1 << 40) ? realloc(r->b, 2 * cap + 1) : NULL;
            if (!nb) break;
            r->b = nb, cap *= 2;
        }
        k = lci_text_read(&t, r->b + r->n, cap - r->n);
        if (k > 0) r->n += (size_t)k;
    }
    lci_text_close(&t);
    if (!r->b || k > 0) {
        free(r->b);
        r->b = NULL;
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory reading the file", path);
    }
    if (k < 0) {
        free(r->b);
        r->b = NULL;
        return LC_ERROR_IO;
    }
    r->b[r->n] = 0;
    return LC_OK;
}

/* The next line (from pos to its newline) into out; 0 at the end. */
static int line(vtk *r, char *out, size_t cap)
{
    if (r->pos >= r->n) return 0;
    size_t e = r->pos;
    while (e < r->n && r->b[e] != '\n') e++;
    size_t len = e - r->pos < cap - 1 ? e - r->pos : cap - 1;
    memcpy(out, r->b + r->pos, len);
    out[len] = 0;
    out[strcspn(out, "\r")] = 0;
    r->pos = e < r->n ? e + 1 : e;
    r->line++;
    return 1;
}

/* The next non-blank line (a keyword line) into out, its tokens in tok. */
static int keyword(vtk *r, char *out, size_t cap, char **tok, int ntok, int *k)
{
    for (;;) {
        if (!line(r, out, cap)) return 0;
        *k = 0;
        for (char *t = strtok(out, " \t"); t && *k < ntok; t = strtok(NULL, " \t")) tok[(*k)++] = t;
        if (*k) return 1;
    }
}

static int type_bytes(const char *t)
{
    static const char *const n1[] = {"char", "unsigned_char", NULL};
    static const char *const n2[] = {"short", "unsigned_short", NULL};
    static const char *const n4[] = {"int", "unsigned_int", "float", "vtktypeint32", "vtktypeuint32", NULL};
    static const char *const n8[] = {"long", "unsigned_long", "double", "vtktypeint64", "vtktypeuint64", "vtkIdType", NULL};
    const char *const *lists[4] = {n1, n2, n4, n8};
    int sizes[4] = {1, 2, 4, 8};
    for (int l = 0; l < 4; l++)
        for (const char *const *n = lists[l]; *n; n++)
            if (!strcasecmp(t, *n)) return sizes[l];
    return 0;
}

/* Big-endian value of type t at p. */
static double be_value(const unsigned char *p, const char *t, int bytes)
{
    uint64_t u = 0;
    for (int i = 0; i < bytes; i++) u = u << 8 | p[i];
    if (!strcasecmp(t, "float")) {
        uint32_t x = (uint32_t)u;
        float f;
        memcpy(&f, &x, 4);
        return f;
    }
    if (!strcasecmp(t, "double")) {
        double d;
        memcpy(&d, &u, 8);
        return d;
    }
    int is_unsigned = !strncasecmp(t, "unsigned", 8) || !strncasecmp(t, "vtktypeuint", 11);
    if (is_unsigned || bytes == 8) return is_unsigned ? (double)u : (double)(int64_t)u;
    if (bytes == 4) return (double)(int32_t)(uint32_t)u;
    if (bytes == 2) return (double)(int16_t)(uint16_t)u;
    return !strcasecmp(t, "char") ? (double)(int8_t)(uint8_t)u : (double)(uint8_t)u;
}

/* Reads (out != NULL) or skips count values of type t; what names them in
 * errors; finite: NaN and infinities are errors. */
static lc_status values(vtk *r, uint64_t count, const char *t, double *out, const char *what)
{
    int bytes = type_bytes(t);
    if (!bytes) return BAD(r, "%s:%ld: type '%s' of %s is not supported", r->path, r->line, t, what);
    if (r->binary) {
        if (count > (r->n - r->pos) / (uint64_t)bytes)
            return BAD(r, "%s: byte %zu: %s: %llu values of %d bytes do not fit in the %zu bytes left", r->path, r->pos,
                       what, (unsigned long long)count, bytes, r->n - r->pos);
        for (uint64_t i = 0; out && i < count; i++) {
            size_t at = r->pos + i * (uint64_t)bytes;
            out[i] = be_value(r->b + at, t, bytes);
            if (!isfinite(out[i])) return BAD(r, "%s: byte %zu: %s: value %llu is not finite", r->path, at, what,
                                              (unsigned long long)i);
        }
        r->pos += count * (uint64_t)bytes;
        while (r->pos < r->n && (r->b[r->pos] == '\n' || r->b[r->pos] == '\r')) /* the newline after the data */
            if (r->b[r->pos++] == '\n') r->line++;
        return LC_OK;
    }
    for (uint64_t i = 0; i < count; i++) {
        while (r->pos < r->n && isspace(r->b[r->pos]))
            if (r->b[r->pos++] == '\n') r->line++;
        if (r->pos >= r->n)
            return BAD(r, "%s:%ld: the file ends after %llu of the %llu values of %s", r->path, r->line + 1,
                       (unsigned long long)i, (unsigned long long)count, what);
        char *end;
        errno = 0;
        double d = strtod((const char *)r->b + r->pos, &end);
        size_t len = (size_t)((unsigned char *)end - (r->b + r->pos));
        if (!len || (end[0] && !isspace((unsigned char)end[0])))
            return BAD(r, "%s:%ld: %s: value %llu is not a number", r->path, r->line + 1, what, (unsigned long long)i);
        if (!isfinite(d) || (!strcasecmp(t, "float") && !isfinite((float)d)))
            return BAD(r, "%s:%ld: %s: value %llu is not finite", r->path, r->line + 1, what, (unsigned long long)i);
        if (out) out[i] = d;
        r->pos += len;
    }
    return LC_OK;
}

static lc_status count_of(vtk *r, const char *s, uint64_t max, uint64_t *out, const char *what)
{
    char *end;
    errno = 0;
    unsigned long long c = strtoull(s, &end, 10);
    if (!isdigit((unsigned char)s[0]) || *end || errno || c > max)
        return BAD(r, "%s:%ld: %s '%s' is not an integer in 0..%llu", r->path, r->line, what, s, (unsigned long long)max);
    *out = c;
    return LC_OK;
}

/* A cell section header "KEY n size" was read: skip its data. */
static lc_status skip_cells(vtk *r, char **tok, int k)
{
    uint64_t n, size;
    if (k < 3) return BAD(r, "%s:%ld: expected '%s COUNT SIZE'", r->path, r->line, tok[0]);
    lc_status s = count_of(r, tok[1], UINT32_MAX, &n, tok[0]);
    if (s == LC_OK) s = count_of(r, tok[2], (uint64_t)1 << 40, &size, tok[0]);
    if (s != LC_OK) return s;
    if (!r->v5) return values(r, size, "int", NULL, tok[0]);
    char buf[256], *t[4];
    for (int part = 0; part < 2; part++) { /* OFFSETS type, CONNECTIVITY type */
        int kk;
        if (!keyword(r, buf, sizeof buf, t, 4, &kk) || kk < 2 || strcasecmp(t[0], part ? "CONNECTIVITY" : "OFFSETS"))
            return BAD(r, "%s:%ld: expected '%s TYPE' in a version 5 %s section", r->path, r->line,
                       part ? "CONNECTIVITY" : "OFFSETS", tok[0]);
        if ((s = values(r, part ? size : n, t[1], NULL, t[0])) != LC_OK) return s;
    }
    return LC_OK;
}

/* Attribute data of `count` tuples (POINT_DATA or CELL_DATA): the first
 * one-component array into val (when val != NULL); stops there. *got = 1
 * when found. */
static lc_status attributes(vtk *r, uint64_t count, double *val, int *got)
{
    char buf[512], *tok[8];
    int k;
    size_t at = r->pos;
    long at_line = r->line;
    for (; keyword(r, buf, sizeof buf, tok, 8, &k); at = r->pos, at_line = r->line) {
        lc_status s;
        if (!strcasecmp(tok[0], "SCALARS")) {
            uint64_t nc = 1;
            if (k < 3) return BAD(r, "%s:%ld: expected 'SCALARS NAME TYPE [COMPONENTS]'", r->path, r->line);
            if (k > 3 && (s = count_of(r, tok[3], 4, &nc, "components")) != LC_OK) return s;
            char type[64];
            snprintf(type, sizeof type, "%s", tok[2]);
            size_t save = r->pos;
            long save_line = r->line;
            char b2[256], *t2[4];
            int k2;
            if (!keyword(r, b2, sizeof b2, t2, 4, &k2) || strcasecmp(t2[0], "LOOKUP_TABLE"))
                r->pos = save, r->line = save_line; /* LOOKUP_TABLE is optional */
            if (val && nc == 1) {
                *got = 1;
                return values(r, count, type, val, "SCALARS");
            }
            if ((s = values(r, count * nc, type, NULL, "SCALARS")) != LC_OK) return s;
        } else if (!strcasecmp(tok[0], "FIELD")) {
            uint64_t na;
            if (k < 3 || (s = count_of(r, tok[2], 1024, &na, "FIELD arrays")) != LC_OK)
                return k < 3 ? BAD(r, "%s:%ld: expected 'FIELD NAME ARRAYS'", r->path, r->line) : s;
            for (uint64_t a = 0; a < na; a++) {
                uint64_t nc, nt;
                if (!keyword(r, buf, sizeof buf, tok, 8, &k) || k < 4)
                    return BAD(r, "%s:%ld: expected 'NAME COMPONENTS TUPLES TYPE' for field array %llu", r->path,
                               r->line, (unsigned long long)a);
                if ((s = count_of(r, tok[1], 1 << 16, &nc, "components")) != LC_OK ||
                    (s = count_of(r, tok[2], UINT32_MAX, &nt, "tuples")) != LC_OK)
                    return s;
                if (val && nc == 1 && nt == count) {
                    *got = 1;
                    return values(r, count, tok[3], val, tok[0]);
                }
                if ((s = values(r, nc * nt, tok[3], NULL, tok[0])) != LC_OK) return s;
            }
        } else if (!strcasecmp(tok[0], "VECTORS") || !strcasecmp(tok[0], "NORMALS")) {
            if (k < 3) return BAD(r, "%s:%ld: expected '%s NAME TYPE'", r->path, r->line, tok[0]);
            if ((s = values(r, 3 * count, tok[2], NULL, tok[0])) != LC_OK) return s;
        } else if (!strcasecmp(tok[0], "TENSORS")) {
            if (k < 3) return BAD(r, "%s:%ld: expected 'TENSORS NAME TYPE'", r->path, r->line);
            if ((s = values(r, 9 * count, tok[2], NULL, tok[0])) != LC_OK) return s;
        } else if (!strcasecmp(tok[0], "POINT_DATA") || !strcasecmp(tok[0], "CELL_DATA")) {
            r->pos = at, r->line = at_line; /* hand the section back to the caller */
            return LC_OK;
        } else {
            return BAD(r, "%s:%ld: '%s' is not supported in attribute data (SCALARS, FIELD, VECTORS, NORMALS, TENSORS)",
                       r->path, r->line, tok[0]);
        }
    }
    return LC_OK;
}

static lc_status header(vtk *r)
{
    char buf[512];
    if (!line(r, buf, sizeof buf) || strncmp(buf, "# vtk DataFile Version", 22))
        return BAD(r, "%s:1: not a VTK legacy file (expected '# vtk DataFile Version x.y')", r->path);
    r->v5 = atof(buf + 22) >= 5.0;
    if (!line(r, buf, sizeof buf)) return BAD(r, "%s:2: the file ends before its title line", r->path);
    if (!line(r, buf, sizeof buf)) return BAD(r, "%s:3: the file ends before ASCII or BINARY", r->path);
    char *s = buf;
    while (isspace((unsigned char)*s)) s++;
    s[strcspn(s, " \t")] = 0;
    if (!strcasecmp(s, "ASCII")) r->binary = 0;
    else if (!strcasecmp(s, "BINARY")) r->binary = 1;
    else return BAD(r, "%s:3: '%s': expected ASCII or BINARY", r->path, s);
    return LC_OK;
}

/* The body: points, cells, then point data with the values. */
static lc_status body(vtk *r, double **pts, double **val, uint64_t *np)
{
    char buf[512], *tok[8];
    int k, dataset = 0, got = 0;
    while (keyword(r, buf, sizeof buf, tok, 8, &k)) {
        lc_status s = LC_OK;
        uint64_t n;
        if (!strcasecmp(tok[0], "DATASET")) {
            if (k < 2 || (strcasecmp(tok[1], "POLYDATA") && strcasecmp(tok[1], "UNSTRUCTURED_GRID")))
                return BAD(r, "%s:%ld: DATASET %s: the encoder reads POLYDATA and UNSTRUCTURED_GRID (structured "
                           "volumes through their own formats)", r->path, r->line, k < 2 ? "" : tok[1]);
            dataset = 1;
        } else if (!dataset) {
            return BAD(r, "%s:%ld: expected 'DATASET POLYDATA' or 'DATASET UNSTRUCTURED_GRID'", r->path, r->line);
        } else if (!strcasecmp(tok[0], "POINTS")) {
            if (k < 3) return BAD(r, "%s:%ld: expected 'POINTS COUNT TYPE'", r->path, r->line);
            if ((s = count_of(r, tok[1], LCI_MAX_SAMPLES, &n, "POINTS count")) != LC_OK) return s;
            if (*pts) return BAD(r, "%s:%ld: a second POINTS section", r->path, r->line);
            /* the data must be there before allocating for it */
            int tb = type_bytes(tok[2]);
            if (r->binary && tb && 3 * n > (r->n - r->pos) / (uint64_t)tb)
                return BAD(r, "%s: byte %zu: POINTS: %llu points do not fit in the %zu bytes left", r->path, r->pos,
                           (unsigned long long)n, r->n - r->pos);
            if (!r->binary && 3 * n > r->n - r->pos)
                return BAD(r, "%s:%ld: POINTS: %llu points cannot fit in the %zu bytes left", r->path, r->line,
                           (unsigned long long)n, r->n - r->pos);
            *np = n;
            if (!(*pts = malloc(sizeof(double) * 3 * (n ? n : 1))))
                return lci_error(r->dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", r->path);
            s = values(r, 3 * n, tok[2], *pts, "POINTS");
        } else if (!strcasecmp(tok[0], "VERTICES") || !strcasecmp(tok[0], "LINES") || !strcasecmp(tok[0], "POLYGONS") ||
                   !strcasecmp(tok[0], "TRIANGLE_STRIPS") || !strcasecmp(tok[0], "CELLS")) {
            s = skip_cells(r, tok, k);
        } else if (!strcasecmp(tok[0], "CELL_TYPES")) {
            if (k < 2 || (s = count_of(r, tok[1], UINT32_MAX, &n, "CELL_TYPES count")) != LC_OK)
                return k < 2 ? BAD(r, "%s:%ld: expected 'CELL_TYPES COUNT'", r->path, r->line) : s;
            s = values(r, n, "int", NULL, "CELL_TYPES");
        } else if (!strcasecmp(tok[0], "METADATA")) {
            while (line(r, buf, sizeof buf) && buf[strspn(buf, " \t")]) {}
        } else if (!strcasecmp(tok[0], "CELL_DATA")) {
            if (k < 2 || (s = count_of(r, tok[1], UINT32_MAX, &n, "CELL_DATA count")) != LC_OK)
                return k < 2 ? BAD(r, "%s:%ld: expected 'CELL_DATA COUNT'", r->path, r->line) : s;
            s = attributes(r, n, NULL, &got);
        } else if (!strcasecmp(tok[0], "POINT_DATA")) {
            if (!*pts) return BAD(r, "%s:%ld: POINT_DATA before POINTS", r->path, r->line);
            if (k < 2 || (s = count_of(r, tok[1], UINT32_MAX, &n, "POINT_DATA count")) != LC_OK)
                return k < 2 ? BAD(r, "%s:%ld: expected 'POINT_DATA COUNT'", r->path, r->line) : s;
            if (n != *np)
                return BAD(r, "%s:%ld: POINT_DATA %llu but %llu points", r->path, r->line, (unsigned long long)n,
                           (unsigned long long)*np);
            if (!(*val = malloc(sizeof(double) * (n ? n : 1))))
                return lci_error(r->dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", r->path);
            if ((s = attributes(r, n, *val, &got)) == LC_OK && got) return LC_OK;
        } else {
            return BAD(r, "%s:%ld: unexpected '%s' (POINTS, cells, CELL_DATA or POINT_DATA)", r->path, r->line, tok[0]);
        }
        if (s != LC_OK) return s;
    }
    if (!*pts) return BAD(r, "%s:%ld: no POINTS section", r->path, r->line);
    return BAD(r, "%s:%ld: no point data array with one component (SCALARS or a FIELD array): the samples need values",
               r->path, r->line);
}

lc_status lci_samples_read_vtk(lc_device *dev, const char *path, lc_samples **out)
{
    *out = NULL;
    vtk r = {.dev = dev, .path = path};
    lc_status s = slurp(dev, path, &r);
    if (s != LC_OK) return s;
    double *pts = NULL, *val = NULL;
    uint64_t n = 0;
    s = header(&r);
    if (s == LC_OK) s = body(&r, &pts, &val, &n);
    free(r.b);
    float *p = NULL, *v = NULL;
    if (s == LC_OK && n == 0) s = lci_error(dev, LC_ERROR_FORMAT, "%s: no points", path);
    if (s == LC_OK && (!(p = malloc(sizeof(float) * 3 * n)) || !(v = malloc(sizeof(float) * n))))
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    for (uint64_t j = 0; s == LC_OK && j < n; j++) {
        for (int a = 0; a < 3; a++) p[3 * j + a] = (float)pts[3 * j + a];
        v[j] = (float)val[j];
        if (!isfinite(p[3 * j]) || !isfinite(p[3 * j + 1]) || !isfinite(p[3 * j + 2]) || !isfinite(v[j]))
            s = lci_error(dev, LC_ERROR_FORMAT, "%s: point %llu or its value overflows float32", path,
                          (unsigned long long)j);
    }
    free(pts), free(val);
    if (s != LC_OK) {
        free(p), free(v);
        return s;
    }
    return lci_samples_adopt(dev, path, p, v, (size_t)n, "vtk", 0, out);
}
