/* NRRD (teem.sourceforge.net/nrrd/format.html): .nrrd with attached data or
 * .nhdr naming a detached data file; raw or gzip encoding; either
 * endianness; 3-D scalar volumes of uint8, uint16, int16 or float. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "host/formats/volume_data.h"

static int parse_type(const char *v, lc_value_type *t)
{
    static const char *u8[] = {"uchar", "unsigned char", "uint8", "uint8_t", NULL};
    static const char *u16[] = {"ushort", "unsigned short", "unsigned short int", "uint16", "uint16_t", NULL};
    static const char *i16[] = {"short", "short int", "signed short", "signed short int", "int16", "int16_t", NULL};
    static const char *f32[] = {"float", NULL};
    const char **lists[4] = {u8, u16, i16, f32};
    lc_value_type types[4] = {LC_VALUE_UINT8, LC_VALUE_UINT16, LC_VALUE_INT16, LC_VALUE_FLOAT32};
    for (int l = 0; l < 4; l++)
        for (const char **n = lists[l]; *n; n++)
            if (!strcasecmp(v, *n)) {
                *t = types[l];
                return 1;
            }
    return 0;
}

#define BAD(...) lci_error(r->dev, LC_ERROR_FORMAT, __VA_ARGS__)

/* The encoding and byte order fields. */
static lc_status layout_field(lci_header_lines *r, const char *k, const char *v, lci_vol_header *h)
{
    const char *path = r->path;
    int ln = r->ln;
    if (!strcasecmp(k, "encoding")) {
        if (!strcasecmp(v, "raw")) h->gzip = 0;
        else if (!strcasecmp(v, "gzip") || !strcasecmp(v, "gz")) {
            h->gzip = 1;
            if (!LC_HAVE_ZLIB) return lci_missing_at(r, "gzip encoding");
        }
        else return BAD("%s:%d: encoding \"%s\" is not supported (raw or gzip)", path, ln, v);
    } else if (!strcasecmp(k, "endian")) {
        if (!strcasecmp(v, "little")) h->big_endian = 0;
        else if (!strcasecmp(v, "big")) h->big_endian = 1;
        else return BAD("%s:%d: endian \"%s\": expected little or big", path, ln, v);
    }
    return LC_OK;
}

/* One "field: value" line; *stop at the data file field (a detached header ends there). */
static lc_status field(lci_header_lines *r, const char *k, const char *v, lci_vol_header *h, int *stop)
{
    const char *path = r->path;
    int ln = r->ln;
    if (!strcasecmp(k, "dimension")) {
        if (strcmp(v, "3") != 0) return BAD("%s:%d: dimension %s, only 3-D volumes are supported", path, ln, v);
    } else if (!strcasecmp(k, "type")) {
        if (!parse_type(v, &h->type))
            return BAD("%s:%d: type \"%s\" is not supported (uint8, uint16, int16 or float)", path, ln, v);
        h->have_type = 1;
    } else if (!strcasecmp(k, "sizes")) {
        if (!lci_parse_sizes(v, h->size, 3))
            return BAD("%s:%d: sizes \"%s\": expected three integers from 2 to 2147483647", path, ln, v);
        h->have_sizes = 1;
    } else if (!strcasecmp(k, "spacings")) {
        if (!lci_parse_spacings(v, h->spacing, 3))
            return BAD("%s:%d: spacings \"%s\": expected three numbers from %g to %g", path, ln, v, LCI_MIN_SPACING,
                       LCI_MAX_COORD);
        h->have_spacing = 1;
    } else if (!strcasecmp(k, "space directions")) {
        double m[9];
        if (!lci_parse_doubles(v, m, 9))
            return BAD("%s:%d: space directions \"%s\": expected three vectors", path, ln, v);
        for (int a = 0; a < 3; a++) {
            h->spacing[a] = sqrt(m[3 * a] * m[3 * a] + m[3 * a + 1] * m[3 * a + 1] + m[3 * a + 2] * m[3 * a + 2]);
            if (!(h->spacing[a] >= LCI_MIN_SPACING && h->spacing[a] <= LCI_MAX_COORD))
                return BAD("%s:%d: space directions: axis %d has length %g, expected %g to %g", path, ln, a,
                           h->spacing[a], LCI_MIN_SPACING, LCI_MAX_COORD);
        }
        h->have_spacing = 1;
    } else if (!strcasecmp(k, "space origin")) {
        if (!lci_parse_doubles(v, h->origin, 3)) return BAD("%s:%d: space origin \"%s\": expected (x,y,z)", path, ln, v);
        h->have_origin = 1;
    } else if (!strcasecmp(k, "data file") || !strcasecmp(k, "datafile")) {
        if (!strncasecmp(v, "LIST", 4) || strchr(v, '%'))
            return BAD("%s:%d: multi-file data (\"%s\") is not supported", path, ln, v);
        snprintf(h->data_file, sizeof h->data_file, "%s", v);
        *stop = 1;
    } else if (!strcasecmp(k, "byte skip")) {
        if (!lci_parse_offset(v, &h->byte_skip))
            return BAD("%s:%d: byte skip \"%s\": expected an integer from -1 (data at the end of the file) to 2^62", path,
                       ln, v);
    } else {
        return layout_field(r, k, v, h);
    }
    return LC_OK;
}

lc_status lci_nrrd_header(lc_device *dev, const char *path, FILE *f, lci_vol_header *h)
{
    lci_header_lines r = {.dev = dev, .path = path, .f = f, .meta = 0, .ln = 1};
    if (!fgets(r.line, sizeof r.line, f) || strncmp(r.line, "NRRD000", 7) != 0)
        return lci_error(dev, LC_ERROR_FORMAT, "%s:1: not a NRRD file (no NRRD000x magic)", path);
    for (int stop = 0; !stop;) {
        char *k, *v;
        lc_status s = lci_header_next(&r, &k, &v);
        if (s == LC_OK && !k) break;
        if (s == LC_OK) s = field(&r, k, v, h, &stop);
        if (s != LC_OK) return s;
    }
    return lci_header_done(&r, h, "type", "sizes");
}

static lc_status nrrd_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    lci_vol_opts o;
    lc_status s = lci_vol_options(dev, a, &o);
    return s != LC_OK ? s : lci_vol_read_with_header(dev, a->path, &o, lci_nrrd_header, out);
}

static int nrrd_magic(const unsigned char *h, size_t n) { return n >= 7 && !memcmp(h, "NRRD000", 7); }

const lci_format lci_format_nrrd = {
    .name = "nrrd", .kind = LC_KIND_GRID, .extensions = ".nrrd .nhdr", .options = "type spacing origin",
    .description = "NRRD: attached or detached data, raw or gzip, either endianness", .magic = nrrd_magic,
    .read = nrrd_read};
