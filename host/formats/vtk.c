/* VTK legacy files ("File Formats for VTK Version 4.2", the legacy simple
 * format), DATASET STRUCTURED_POINTS only: DIMENSIONS, SPACING (or the old
 * ASPECT_RATIO), ORIGIN and POINT_DATA with one scalar array, ASCII or
 * BINARY (big-endian, as the format prescribes). The array is the first
 * SCALARS of the point data, or the one `scalars = NAME` names (a SCALARS
 * or a one-component FIELD array); the others (VECTORS, NORMALS, TENSORS,
 * TEXTURE_COORDINATES, COLOR_SCALARS, LOOKUP_TABLE, FIELD arrays) are read
 * past. unsigned_char, short, unsigned_short and float stay as they are;
 * char, int, unsigned_int, long, unsigned_long (8 bytes, as VTK writes them
 * on LP64 systems), vtktypeint64/uint64 and double become float32 (with a
 * note). Every error names the file and the line, or the byte offset in
 * binary data. Sizes are checked against the file before allocating. */
#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "host/formats/checked.h"
#include "host/formats/volume_data.h"
#include "host/kinds/grid.h"

typedef struct vrd {
    lc_device *dev;
    const char *path;
    FILE *f;
    int64_t size;
    long ln; /* line of the last header line read */
    int binary;
    char line[1024];
} vrd;

#define BAD(...) lci_error(r->dev, LC_ERROR_FORMAT, __VA_ARGS__)

/* The next non-blank header line, trimmed, in r->line: 1, or 0 at the end. */
static int header_line(vrd *r)
{
    while (fgets(r->line, sizeof r->line, r->f)) {
        r->ln++;
        char *s = r->line;
        while (isspace((unsigned char)*s)) s++;
        size_t n = strlen(s);
        while (n && isspace((unsigned char)s[n - 1])) s[--n] = 0;
        memmove(r->line, s, n + 1);
        if (n) return 1;
    }
    return 0;
}

typedef struct vtype {
    const char *name;
    int bytes;        /* in BINARY data */
    int is_float, is_signed;
    lc_value_type to; /* lanecast's type: the same, or float32 converted */
} vtype;

static const vtype types[] = {
    {"unsigned_char", 1, 0, 0, LC_VALUE_UINT8},   {"char", 1, 0, 1, LC_VALUE_FLOAT32},
    {"short", 2, 0, 1, LC_VALUE_INT16},           {"unsigned_short", 2, 0, 0, LC_VALUE_UINT16},
    {"int", 4, 0, 1, LC_VALUE_FLOAT32},           {"unsigned_int", 4, 0, 0, LC_VALUE_FLOAT32},
    {"long", 8, 0, 1, LC_VALUE_FLOAT32},          {"unsigned_long", 8, 0, 0, LC_VALUE_FLOAT32},
    {"vtktypeint64", 8, 0, 1, LC_VALUE_FLOAT32},  {"vtktypeuint64", 8, 0, 0, LC_VALUE_FLOAT32},
    {"vtkidtype", 4, 0, 1, LC_VALUE_FLOAT32},     {"float", 4, 1, 1, LC_VALUE_FLOAT32},
    {"double", 8, 1, 1, LC_VALUE_FLOAT32},
};

static const vtype *type_of(const char *name)
{
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (!strcasecmp(name, types[i].name)) return &types[i];
    return NULL;
}

/* An ASCII value must be what its declared type can hold: an integer type an
 * integer within the type's range (0..255 for unsigned_char, -32768..32767 for
 * short, ...: stored as is, it would wrap), and every value within float32's
 * range, the type the others are stored as. Returns the range's text when v
 * is out of it, NULL when it fits. */
static const char *out_of_type(const vtype *t, double v, char *range, size_t cap)
{
    if (t->is_float) {
        if (fabs(v) <= FLT_MAX) return NULL;
        snprintf(range, cap, "beyond float32's range (+-%g)", FLT_MAX);
        return range;
    }
    int bits = 8 * t->bytes;
    double lo = t->is_signed ? -ldexp(1.0, bits - 1) : 0.0, top = ldexp(1.0, t->is_signed ? bits - 1 : bits);
    if (v == floor(v) && v >= lo && v < top) return NULL;
    if (v != floor(v)) snprintf(range, cap, "not an integer, as %s values are", t->name);
    else snprintf(range, cap, "outside %s's range %.0f..%.0f", t->name, lo, top - 1.0);
    return range;
}

/* One BINARY value (big-endian) as a double. */
static double be_value(const vtype *t, const unsigned char *p)
{
    uint64_t u = 0;
    for (int i = 0; i < t->bytes; i++) u = u << 8 | p[i];
    if (t->is_float && t->bytes == 4) {
        uint32_t w = (uint32_t)u;
        float f;
        memcpy(&f, &w, 4);
        return f;
    }
    if (t->is_float) {
        double d;
        memcpy(&d, &u, 8);
        return d;
    }
    if (!t->is_signed) return (double)u;
    int shift = 64 - 8 * t->bytes;
    return (double)((int64_t)(u << shift) >> shift);
}

static void store(lc_value_type to, void *dst, size_t i, double v)
{
    switch (to) {
    case LC_VALUE_UINT8: ((uint8_t *)dst)[i] = (uint8_t)v; break;
    case LC_VALUE_INT16: ((int16_t *)dst)[i] = (int16_t)v; break;
    case LC_VALUE_UINT16: ((uint16_t *)dst)[i] = (uint16_t)v; break;
    default: ((float *)dst)[i] = (float)v; break;
    }
}

/* Reads (dst != NULL) or skips n values of type t at the current position. */
static lc_status values(vrd *r, const vtype *t, uint64_t n, void *dst, const char *what)
{
    int64_t at = ftello(r->f);
    if (r->binary) {
        uint64_t bytes = n * (uint64_t)t->bytes;
        if (at < 0 || (uint64_t)(r->size - at) < bytes)
            return BAD("%s: byte %lld: %s needs %llu bytes (%llu %s values), the file has %lld left", r->path,
                       (long long)at, what, (unsigned long long)bytes, (unsigned long long)n, t->name,
                       (long long)(r->size - at));
        if (!dst) return fseeko(r->f, (off_t)bytes, SEEK_CUR) ? BAD("%s: byte %lld: cannot seek", r->path, (long long)at) : LC_OK;
        unsigned char buf[8192];
        uint64_t per = sizeof buf / (uint64_t)t->bytes;
        for (uint64_t i = 0; i < n; i += per) {
            uint64_t m = n - i < per ? n - i : per;
            if (fread(buf, (size_t)t->bytes, (size_t)m, r->f) != m)
                return lci_error(r->dev, LC_ERROR_IO, "%s: byte %lld: read failed", r->path, (long long)ftello(r->f));
            for (uint64_t j = 0; j < m; j++) {
                double v = be_value(t, buf + j * (uint64_t)t->bytes);
                if (t->is_float && !(fabs(v) <= FLT_MAX))
                    return BAD("%s: byte %lld: %s value %llu is %s", r->path,
                               (long long)(at + (int64_t)((i + j) * (uint64_t)t->bytes)), what,
                               (unsigned long long)(i + j), isfinite(v) ? "beyond float32's range" : "not finite");
                store(t->to, dst, i + j, v);
            }
        }
        return LC_OK;
    }
    /* ASCII: n numbers separated by white space, lines counted */
    if (at < 0 || (uint64_t)(r->size - at) / 2 + 1 < n)
        return BAD("%s:%ld: %s needs %llu numbers, more than the %lld bytes left can hold", r->path, r->ln + 1, what,
                   (unsigned long long)n, (long long)(r->size - at));
    long ln = r->ln + 1, last = ln;
    char tok[80];
    for (uint64_t i = 0; i < n; i++) {
        int c;
        while ((c = getc(r->f)) != EOF && isspace(c))
            if (c == '\n') ln++;
        size_t k = 0;
        while (c != EOF && !isspace(c)) {
            if (k < sizeof tok - 1) tok[k++] = (char)c;
            c = getc(r->f);
        }
        tok[k] = 0;
        if (c == '\n') ungetc(c, r->f);
        if (k) last = ln;
        if (!k)
            return BAD("%s:%ld: the file ends after %llu of the %llu values of %s", r->path, last, (unsigned long long)i,
                       (unsigned long long)n, what);
        char *end;
        errno = 0;
        double v = strtod(tok, &end);
        if (*end || errno == ERANGE || !isfinite(v))
            return BAD("%s:%ld: value %llu of %s is '%s', expected a %s number", r->path, ln, (unsigned long long)i,
                       what, tok, t->name);
        char range[96];
        if (out_of_type(t, v, range, sizeof range))
            return BAD("%s:%ld: value %llu of %s is '%s', %s", r->path, ln, (unsigned long long)i, what, tok, range);
        if (dst) store(t->to, dst, i, v);
    }
    /* the header continues after the line the last value ends */
    int c;
    while ((c = getc(r->f)) != EOF && c != '\n')
        if (!isspace(c)) {
            ungetc(c, r->f);
            break;
        }
    r->ln = ln;
    return LC_OK;
}

/* After SCALARS: an optional LOOKUP_TABLE line (binary data follows at once). */
static void lookup_table_line(vrd *r)
{
    off_t at = ftello(r->f);
    long ln = r->ln;
    char keep[sizeof r->line];
    memcpy(keep, r->line, sizeof keep);
    if (header_line(r) && !strncasecmp(r->line, "LOOKUP_TABLE", 12)) return;
    fseeko(r->f, at, SEEK_SET);
    r->ln = ln;
    memcpy(r->line, keep, sizeof keep);
}

static lc_status vtk_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    lci_vol_opts o;
    lc_status s = lci_vol_options(dev, a, &o);
    if (s != LC_OK) return s;
    const lc_option *want = lci_option_find(a, "scalars");
    vrd rr = {.dev = dev, .path = a->path}, *r = &rr;
    if ((s = lci_open_regular(dev, a->path, NULL, &r->f, &r->size)) != LC_OK) return s;
    void *data = NULL;
    int64_t dims[3] = {0, 0, 0};
    double spacing[3] = {1, 1, 1}, origin[3] = {0, 0, 0};
    int have_dims = 0;
    const vtype *vt = NULL;
    char name[256] = "";
    if (!fgets(r->line, sizeof r->line, r->f) || strncasecmp(r->line, "# vtk DataFile Version", 22)) {
        s = BAD("%s:1: not a VTK legacy file (expected '# vtk DataFile Version x.x')", a->path);
        goto out;
    }
    r->ln = 1;
    if (!fgets(r->line, sizeof r->line, r->f)) {
        s = BAD("%s:2: the file ends before its title line", a->path);
        goto out;
    }
    r->ln = 2;
    if (!header_line(r) || (strcasecmp(r->line, "ASCII") && strcasecmp(r->line, "BINARY"))) {
        s = BAD("%s:%ld: expected ASCII or BINARY, got '%s'", a->path, r->ln, feof(r->f) ? "the end of the file" : r->line);
        goto out;
    }
    r->binary = !strcasecmp(r->line, "BINARY");
    char kw[64], arg[256];
    if (!header_line(r) || sscanf(r->line, "%63s %255s", kw, arg) != 2 || strcasecmp(kw, "DATASET")) {
        s = BAD("%s:%ld: expected 'DATASET STRUCTURED_POINTS'", a->path, r->ln);
        goto out;
    }
    if (strcasecmp(arg, "STRUCTURED_POINTS")) {
        s = BAD("%s:%ld: DATASET %s: only STRUCTURED_POINTS (a regular grid) is read", a->path, r->ln, arg);
        goto out;
    }
    /* geometry up to POINT_DATA */
    int64_t npoints = -1;
    while (npoints < 0) {
        if (!header_line(r)) {
            s = BAD("%s:%ld: the file ends before POINT_DATA", a->path, r->ln);
            goto out;
        }
        double v[3];
        long long n[3];
        char extra;
        sscanf(r->line, "%63s", kw);
        if (!strcasecmp(kw, "DIMENSIONS")) {
            if (sscanf(r->line + 10, "%lld %lld %lld %c", &n[0], &n[1], &n[2], &extra) != 3) {
                s = BAD("%s:%ld: DIMENSIONS needs three integers, got '%s'", a->path, r->ln, r->line);
                goto out;
            }
            for (int k = 0; k < 3; k++) {
                if (n[k] < 2 || n[k] > INT32_MAX) {
                    s = BAD("%s:%ld: DIMENSIONS %lld %lld %lld: each must be 2 or more (lanecast grids are 3-D)",
                            a->path, r->ln, n[0], n[1], n[2]);
                    goto out;
                }
                dims[k] = n[k];
            }
            have_dims = 1;
        } else if (!strcasecmp(kw, "SPACING") || !strcasecmp(kw, "ASPECT_RATIO") || !strcasecmp(kw, "ORIGIN")) {
            int is_origin = !strcasecmp(kw, "ORIGIN");
            if (!lci_parse_doubles(r->line + strlen(kw), v, 3) || (!is_origin && !(v[0] > 0 && v[1] > 0 && v[2] > 0))) {
                s = BAD("%s:%ld: %s needs three %s, got '%s'", a->path, r->ln, kw, is_origin ? "numbers" : "numbers > 0",
                        r->line);
                goto out;
            }
            memcpy(is_origin ? origin : spacing, v, sizeof v);
        } else if (!strcasecmp(kw, "POINT_DATA")) {
            if (sscanf(r->line + 10, "%lld %c", &n[0], &extra) != 1 || n[0] < 0) {
                s = BAD("%s:%ld: POINT_DATA needs a count, got '%s'", a->path, r->ln, r->line);
                goto out;
            }
            npoints = n[0];
        } else if (!strcasecmp(kw, "CELL_DATA")) {
            s = BAD("%s:%ld: CELL_DATA before any POINT_DATA: lanecast grids hold values at the points", a->path, r->ln);
            goto out;
        } else if (!strcasecmp(kw, "FIELD")) {
            s = BAD("%s:%ld: a FIELD before POINT_DATA is not read", a->path, r->ln);
            goto out;
        } else {
            s = BAD("%s:%ld: expected DIMENSIONS, SPACING, ORIGIN or POINT_DATA, got '%s'", a->path, r->ln, r->line);
            goto out;
        }
    }
    if (!have_dims) {
        s = BAD("%s:%ld: POINT_DATA before DIMENSIONS", a->path, r->ln);
        goto out;
    }
    uint64_t count = (uint64_t)dims[0] * (uint64_t)dims[1] * (uint64_t)dims[2];
    if (dims[0] * dims[1] > INT32_MAX || count > INT32_MAX - 64) {
        s = BAD("%s: DIMENSIONS %lld %lld %lld: more than 2^31 points", a->path, (long long)dims[0], (long long)dims[1],
                (long long)dims[2]);
        goto out;
    }
    if ((uint64_t)npoints != count) {
        s = BAD("%s:%ld: POINT_DATA %lld, but DIMENSIONS give %llu points", a->path, r->ln, (long long)npoints,
                (unsigned long long)count);
        goto out;
    }
    /* the point data's arrays until the wanted one */
    for (;;) {
        if (!header_line(r)) {
            if (want) s = BAD("%s:%ld: no point array named '%s'", a->path, r->ln, want->value);
            else s = BAD("%s:%ld: the point data has no SCALARS array", a->path, r->ln);
            goto out;
        }
        char tname[64] = "", t2[64] = "";
        long long ncomp = 1, ntuples = 0;
        int got = sscanf(r->line, "%63s %255s %63s %lld", kw, arg, tname, &ncomp);
        const char *what = r->line;
        char whatbuf[600];
        snprintf(whatbuf, sizeof whatbuf, "%s %s", kw, got > 1 ? arg : "");
        what = whatbuf;
        if (!strcasecmp(kw, "CELL_DATA") || !strcasecmp(kw, "POINT_DATA")) {
            s = want ? BAD("%s:%ld: no point array named '%s' before %s", a->path, r->ln, want->value, kw)
                     : BAD("%s:%ld: the point data has no SCALARS array", a->path, r->ln);
            goto out;
        }
        if (!strcasecmp(kw, "METADATA")) { /* VTK 5 information keys up to a blank line */
            while (fgets(r->line, sizeof r->line, r->f)) {
                r->ln++;
                if (strspn(r->line, " \t\r\n") == strlen(r->line)) break;
            }
            continue;
        }
        int is_scalars = !strcasecmp(kw, "SCALARS");
        if (is_scalars || !strcasecmp(kw, "VECTORS") || !strcasecmp(kw, "NORMALS") || !strcasecmp(kw, "TENSORS")) {
            if (got < 3) {
                s = BAD("%s:%ld: %s needs a name and a type, got '%s'", a->path, r->ln, kw, r->line);
                goto out;
            }
            if (!is_scalars) ncomp = !strcasecmp(kw, "TENSORS") ? 9 : 3;
            else if (got < 4) ncomp = 1;
            const vtype *t = type_of(tname);
            if (!t || ncomp < 1 || ncomp > 4) {
                s = BAD("%s:%ld: %s '%s': type '%s' with %lld components is not supported", a->path, r->ln, kw, arg,
                        tname, ncomp);
                goto out;
            }
            if (is_scalars) lookup_table_line(r);
            int take = is_scalars && ncomp == 1 && (!want || !strcmp(want->value, arg));
            if (is_scalars && ncomp > 1 && want && !strcmp(want->value, arg)) {
                s = BAD("%s:%ld: SCALARS %s has %lld components, lanecast reads one", a->path, r->ln, arg, ncomp);
                goto out;
            }
            if (take) {
                vt = t;
                snprintf(name, sizeof name, "%s", arg);
                break;
            }
            if ((s = values(r, t, count * (uint64_t)ncomp, NULL, what)) != LC_OK) goto out;
        } else if (!strcasecmp(kw, "TEXTURE_COORDINATES")) {
            long long dim;
            const vtype *t = NULL;
            if (sscanf(r->line, "%*s %*s %lld %63s", &dim, t2) != 2 || dim < 1 || dim > 3 || !(t = type_of(t2))) {
                s = BAD("%s:%ld: expected 'TEXTURE_COORDINATES name dim type', got '%s'", a->path, r->ln, r->line);
                goto out;
            }
            if ((s = values(r, t, count * (uint64_t)dim, NULL, what)) != LC_OK) goto out;
        } else if (!strcasecmp(kw, "COLOR_SCALARS")) {
            long long nv;
            if (sscanf(r->line, "%*s %*s %lld", &nv) != 1 || nv < 1 || nv > 4) {
                s = BAD("%s:%ld: expected 'COLOR_SCALARS name nValues', got '%s'", a->path, r->ln, r->line);
                goto out;
            }
            if ((s = values(r, type_of(r->binary ? "unsigned_char" : "float"), count * (uint64_t)nv, NULL, what)) != LC_OK)
                goto out;
        } else if (!strcasecmp(kw, "LOOKUP_TABLE")) {
            long long nt;
            if (sscanf(r->line, "%*s %*s %lld", &nt) != 1 || nt < 1 || nt > (1LL << 24)) {
                s = BAD("%s:%ld: expected 'LOOKUP_TABLE name size', got '%s'", a->path, r->ln, r->line);
                goto out;
            }
            if ((s = values(r, type_of(r->binary ? "unsigned_char" : "float"), (uint64_t)nt * 4, NULL, what)) != LC_OK)
                goto out;
        } else if (!strcasecmp(kw, "FIELD")) {
            long long narrays;
            if (sscanf(r->line, "%*s %*s %lld", &narrays) != 1 || narrays < 0 || narrays > 100000) {
                s = BAD("%s:%ld: expected 'FIELD name numArrays', got '%s'", a->path, r->ln, r->line);
                goto out;
            }
            for (long long i = 0; i < narrays; i++) {
                const vtype *t = NULL;
                if (!header_line(r) || sscanf(r->line, "%255s %lld %lld %63s", arg, &ncomp, &ntuples, t2) != 4 ||
                    ncomp < 1 || ntuples < 0 || !(t = type_of(t2))) {
                    s = BAD("%s:%ld: expected 'arrayName numComponents numTuples dataType' (array %lld of the FIELD)",
                            a->path, r->ln, i + 1);
                    goto out;
                }
                if (want && !strcmp(want->value, arg)) {
                    if (ncomp != 1 || (uint64_t)ntuples != count) {
                        s = BAD("%s:%ld: field array %s is %lld x %lld, a grid needs 1 x %llu", a->path, r->ln, arg,
                                ncomp, ntuples, (unsigned long long)count);
                        goto out;
                    }
                    vt = t;
                    snprintf(name, sizeof name, "%s", arg);
                    break;
                }
                if ((uint64_t)ntuples > INT64_MAX / 16 / (uint64_t)ncomp) {
                    s = BAD("%s:%ld: field array %s of %lld x %lld values is too large", a->path, r->ln, arg, ncomp, ntuples);
                    goto out;
                }
                snprintf(whatbuf, sizeof whatbuf, "field array %s", arg);
                if ((s = values(r, t, (uint64_t)ntuples * (uint64_t)ncomp, NULL, whatbuf)) != LC_OK) goto out;
            }
            if (vt) break;
        } else {
            s = BAD("%s:%ld: expected a point data attribute (SCALARS, VECTORS, FIELD, ...), got '%s'", a->path, r->ln,
                    r->line);
            goto out;
        }
    }
    /* the array itself */
    int es = lci_value_size(vt->to);
    if (!(data = lci_alloc_checked(dev, a->path, count, (uint64_t)es, 64, "values", 0))) {
        s = LC_ERROR_OUT_OF_MEMORY;
        goto out;
    }
    char what[300];
    snprintf(what, sizeof what, "array %s", name);
    if ((s = values(r, vt, count, data, what)) != LC_OK) goto out;
    if (vt->to == LC_VALUE_FLOAT32 && strcmp(vt->name, "float"))
        lci_log(dev, LC_LOG_INFO, "%s: array %s of type %s read as float32", a->path, name, vt->name);
    if (o.type != LC_VALUE_DEFAULT && o.type != vt->to) {
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: the array's type differs from the requested one", a->path);
        goto out;
    }
    lc_grid_desc *d = calloc(1, sizeof *d);
    if (!d) {
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", a->path);
        goto out;
    }
    s = lci_vol_hand_over(dev, a->path, d, dims, vt->to, spacing, origin, &o, data, out);
    data = NULL; /* out keeps it */
out:
    free(data);
    fclose(r->f);
    return s;
}

static int vtk_magic(const unsigned char *h, size_t n) { return n >= 22 && !strncasecmp((const char *)h, "# vtk DataFile Version", 22); }

const lci_format lci_format_vtk = {
    .name = "vtk", .kind = LC_KIND_GRID, .extensions = ".vtk", .options = "scalars type spacing origin",
    .description = "VTK legacy STRUCTURED_POINTS, ASCII or BINARY: a point-data array (the first SCALARS, or "
                   "scalars = NAME) as a grid",
    .magic = vtk_magic, .read = vtk_read};
