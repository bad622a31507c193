/* Header lines, options and voxel reading shared by the volume formats
 * (volume_data.h). Every error is one line naming the file (and the header
 * line); sizes are checked before allocating. Compressed voxels need zlib
 * (LC_HAVE_ZLIB); the headers ask for it at their own line first. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "host/formats/volume_data.h"
#include "host/formats/checked.h"
#include "host/formats/gzstream.h"
#include "host/kinds/grid.h"

static char *trim(char *s)
{
    while (isspace((unsigned char)*s)) s++;
    size_t n = strlen(s);
    while (n && isspace((unsigned char)s[n - 1])) s[--n] = 0;
    return s;
}

lc_status lci_header_next(lci_header_lines *r, char **key, char **value)
{
    *key = *value = NULL;
    int meta = r->meta;
    while (fgets(r->line, sizeof r->line, r->f)) {
        r->ln++;
        if (!strchr(r->line, '\n') && !feof(r->f))
            return lci_error(r->dev, LC_ERROR_FORMAT, "%s:%d: header line longer than %zu bytes", r->path, r->ln,
                             sizeof r->line - 1);
        char *s = trim(r->line);
        if (!meta && *s == 0) return LC_OK; /* end of a NRRD header */
        if (*s == '#' || *s == 0) continue;
        char *sep = meta ? strchr(s, '=') : strstr(s, ": ");
        if (!meta && !sep && strstr(s, ":=")) continue; /* key/value pair */
        if (!sep) {
            if (!meta && s[strlen(s) - 1] == ':') sep = s + strlen(s) - 1;
            else
                return lci_error(r->dev, LC_ERROR_FORMAT, "%s:%d: expected \"%s\", got \"%s\"", r->path, r->ln,
                                 meta ? "key = value" : "field: value", s);
        }
        *sep = 0;
        *key = trim(s);
        *value = trim(sep + 1 + (meta ? 0 : 1) - (sep[1] == 0 ? 1 : 0));
        return LC_OK;
    }
    return LC_OK;
}

lc_status lci_missing_at(const lci_header_lines *r, const char *what)
{
    char where[1100];
    snprintf(where, sizeof where, "%s:%d", r->path, r->ln);
    return lci_missing(r->dev, where, what, LCI_FEATURE_ZLIB);
}

lc_status lci_header_done(lci_header_lines *r, lci_vol_header *h, const char *type_key, const char *sizes_key)
{
    if (!h->have_type) return lci_error(r->dev, LC_ERROR_FORMAT, "%s: the header gives no %s", r->path, type_key);
    if (!h->have_sizes) return lci_error(r->dev, LC_ERROR_FORMAT, "%s: the header gives no %s", r->path, sizes_key);
    h->data_offset = ftell(r->f);
    return LC_OK;
}

int lci_parse_doubles(const char *v, double *out, int n)
{
    char *end;
    for (int i = 0; i < n; i++) {
        while (*v && (isspace((unsigned char)*v) || *v == '(' || *v == ')' || *v == ',')) v++;
        errno = 0;
        out[i] = strtod(v, &end);
        if (end == v || errno || !isfinite(out[i])) return 0;
        v = end;
    }
    while (*v && (isspace((unsigned char)*v) || *v == ')' || *v == ',')) v++;
    return *v == 0; /* nothing but separators after the numbers */
}

int lci_parse_sizes(const char *v, int64_t *out, int n)
{
    char *end;
    for (int i = 0; i < n; i++) {
        while (isspace((unsigned char)*v)) v++;
        if (!isdigit((unsigned char)*v)) return 0; /* no sign: sizes are >= 2 */
        errno = 0;
        long long x = strtoll(v, &end, 10);
        if (end == v || errno || x < 2 || x > INT32_MAX) return 0;
        out[i] = x;
        v = end;
    }
    while (isspace((unsigned char)*v)) v++;
    return *v == 0;
}

int lci_parse_offset(const char *v, long long *out)
{
    char *end;
    while (isspace((unsigned char)*v)) v++;
    if (!isdigit((unsigned char)*v) && *v != '-') return 0;
    errno = 0;
    long long x = strtoll(v, &end, 10);
    if (end == v || errno || x < -1 || x > LCI_MAX_OFFSET) return 0;
    while (isspace((unsigned char)*end)) end++;
    if (*end) return 0;
    *out = x;
    return 1;
}

int lci_parse_spacings(const char *v, double *out, int n)
{
    if (!lci_parse_doubles(v, out, n)) return 0;
    for (int i = 0; i < n; i++)
        if (!(out[i] >= LCI_MIN_SPACING && out[i] <= LCI_MAX_COORD)) return 0;
    return 1;
}

lc_status lci_vol_geometry(lc_device *dev, const char *path, const int size[3], lc_vec3 spacing, lc_vec3 origin)
{
    const float s[3] = {spacing.x, spacing.y, spacing.z}, o[3] = {origin.x, origin.y, origin.z};
    for (int a = 0; a < 3; a++) {
        if (!(s[a] >= (float)LCI_MIN_SPACING && s[a] <= (float)LCI_MAX_COORD)) /* in float, as stored */
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                             "%s: spacing %g along %c is outside [%g, %g] (a wrong unit, or a damaged header?)", path,
                             (double)s[a], "xyz"[a], LCI_MIN_SPACING, LCI_MAX_COORD);
        double far = fabs((double)o[a]) + (double)(size[a] - 1) * (double)s[a];
        if (!(far <= (double)(float)LCI_MAX_COORD))
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                             "%s: origin %g and spacing %g along %c put the volume's far side at %g, beyond +-%g (a "
                             "wrong unit, or a damaged header?)",
                             path, (double)o[a], (double)s[a], "xyz"[a], far, LCI_MAX_COORD);
    }
    return LC_OK;
}

/* The data file of a volume, open and checked before anything is allocated:
 * a regular file, long enough for the header's offset, and holding exactly
 * `bytes` of raw data, or gzip data that could inflate to them (deflate
 * compresses at most 1032:1). */
static lc_status open_data(lc_device *dev, const char *header, const char *file, long long *offset, int gzip,
                           uint64_t bytes, FILE **out, int64_t *len)
{
    lc_status s = lci_open_regular(dev, file, header, out, len);
    if (s != LC_OK) return s;
    char who[1200]; /* "header: its data file file" or "file" */
    if (strcmp(header, file)) snprintf(who, sizeof who, "%s: its data file %s", header, file);
    else snprintf(who, sizeof who, "%s", file);
    if (*offset < 0) { /* byte skip / HeaderSize -1: the data is the file's last bytes (raw data only) */
        if (gzip) s = lci_error(dev, LC_ERROR_FORMAT, "%s: a byte skip (HeaderSize) of -1 needs raw, not compressed, data", header);
        else if ((uint64_t)*len < bytes)
            s = lci_error(dev, LC_ERROR_FORMAT, "%s: %lld bytes, fewer than the %llu bytes of voxels the header needs",
                          who, (long long)*len, (unsigned long long)bytes);
        else *offset = *len - (int64_t)bytes;
        if (s != LC_OK) {
            fclose(*out), *out = NULL;
            return s;
        }
    }
    uint64_t avail = *len >= *offset ? (uint64_t)(*len - *offset) : 0;
    if (*len < *offset)
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: %lld bytes, shorter than the header's offset %lld", who,
                      (long long)*len, *offset);
    else if (!gzip && avail != bytes)
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: holds %llu bytes of data but the sizes and type need %llu", who,
                      (unsigned long long)avail, (unsigned long long)bytes);
    else if (gzip && bytes / 1032 > avail)
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: %llu bytes of voxels cannot come from %llu bytes of gzip data", who,
                      (unsigned long long)bytes, (unsigned long long)avail);
    if (s != LC_OK) fclose(*out), *out = NULL;
    return s;
}

/* Reads exactly `bytes` of voxels from f at `offset`, in pieces (for the
 * load progress): raw data as it is; gzip data inflated straight into dst,
 * which must end exactly there (one byte more is looked for and refused,
 * so a member larger than the volume is never read whole). */
static lc_status read_data(lc_device *dev, const char *file, FILE *f, long long offset, int64_t len, int gzip,
                           uint64_t bytes, void *dst)
{
    lci_gz *g = NULL;
    lc_status s = LC_OK;
    if (gzip) s = lci_gz_open(dev, file, f, offset, len, &g);
    else if (fseeko(f, (off_t)offset, SEEK_SET) != 0)
        s = lci_error(dev, LC_ERROR_IO, "%s: byte %lld: cannot seek: %s", file, offset, strerror(errno));
    for (uint64_t got = 0; got < bytes && s == LC_OK;) {
        size_t k = bytes - got > (1u << 24) ? (1u << 24) : (size_t)(bytes - got);
        long long r = g ? lci_gz_read(g, (unsigned char *)dst + got, k) : (long long)fread((unsigned char *)dst + got, 1, k, f);
        if (r < 0) s = LC_ERROR_FORMAT; /* reported */
        else if (g && (size_t)r < k)
            s = lci_error(dev, LC_ERROR_FORMAT, "%s: gzip data inflates to %llu bytes but the sizes and type need %llu",
                          file, (unsigned long long)(got + (uint64_t)r), (unsigned long long)bytes);
        else if ((size_t)r < k)
            s = lci_error(dev, LC_ERROR_IO, "%s: byte %llu: read failed: %s", file,
                          (unsigned long long)(offset + (long long)got), strerror(errno));
        got += k;
        lci_load_progress(dev, (double)got / (double)bytes);
    }
    unsigned char extra;
    long long r;
    if (s == LC_OK && g && (r = lci_gz_read(g, &extra, 1)) != 0)
        s = r < 0 ? LC_ERROR_FORMAT
                  : lci_error(dev, LC_ERROR_FORMAT,
                              "%s: gzip data inflates to more than the %llu bytes the sizes and type give", file,
                              (unsigned long long)bytes);
    lci_gz_close(g);
    return s;
}

static void swap_bytes(void *p, uint64_t n, int es)
{
    unsigned char *b = p;
    for (uint64_t i = 0; i < n; i++, b += es) {
        if (es == 2) {
            unsigned char t = b[0];
            b[0] = b[1], b[1] = t;
        } else if (es == 4) {
            unsigned char t = b[0];
            b[0] = b[3], b[3] = t;
            t = b[1], b[1] = b[2], b[2] = t;
        }
    }
}

static lc_status parse_type(lc_device *dev, const char *file, const lc_option *x, lc_value_type *t)
{
    static const char *const names[] = {"", "uint8", "uint16", "int16", "float32"};
    for (int i = 1; i <= 4; i++)
        if (!strcmp(x->value, names[i])) return *t = (lc_value_type)i, LC_OK;
    return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: option type = '%s', expected uint8, uint16, int16 or float32",
                     file, x->value);
}

lc_status lci_vol_options(lc_device *dev, const lci_read_args *a, lci_vol_opts *o)
{
    memset(o, 0, sizeof *o);
    const lc_option *x;
    lc_status s = LC_OK;
    if ((x = lci_option_find(a, "size"))) s = lci_option_ints(dev, a->path, x, 3, 2, INT32_MAX, o->size);
    if (s == LC_OK && (x = lci_option_find(a, "type"))) s = parse_type(dev, a->path, x, &o->type);
    if (s == LC_OK && (x = lci_option_find(a, "spacing"))) s = lci_option_floats(dev, a->path, x, 3, &o->spacing.x);
    if (s == LC_OK && (x = lci_option_find(a, "origin"))) s = lci_option_floats(dev, a->path, x, 3, &o->origin.x);
    if (s == LC_OK && (x = lci_option_find(a, "endian"))) {
        if (!strcmp(x->value, "big")) o->big_endian = 1;
        else if (strcmp(x->value, "little"))
            s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: option endian = '%s', expected little or big", a->path,
                          x->value);
    }
    return s;
}

/* Where the voxels of a parsed header are: the data file (detached:
 * relative to the header's folder) and the byte offset (-1: the last bytes). */
static void data_location(const char *path, const lci_vol_header *h, char *data_path, size_t cap, long long *offset)
{
    if (h->data_file[0]) {
        const char *slash = strrchr(path, '/');
        if (h->data_file[0] == '/' || !slash) snprintf(data_path, cap, "%s", h->data_file);
        else snprintf(data_path, cap, "%.*s/%s", (int)(slash - path), path, h->data_file);
        *offset = h->byte_skip;
    } else {
        snprintf(data_path, cap, "%s", path);
        *offset = h->byte_skip < 0 ? -1 : h->data_offset + h->byte_skip; /* both at most 2^62: no overflow */
    }
}

static lc_status parse_file(lc_device *dev, const char *path, const lci_vol_opts *o, lci_header_fn parse,
                            lci_vol_header *h)
{
    memset(h, 0, sizeof *h);
    FILE *f;
    lc_status s = lci_open_regular(dev, path, NULL, &f, NULL);
    if (s != LC_OK) return s;
    s = parse(dev, path, f, h);
    fclose(f);
    if (s == LC_OK && o->type != LC_VALUE_DEFAULT && o->type != h->type)
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: the header's type differs from the requested one", path);
    return s;
}

/* The header of path parsed and where its voxels are. */
static lc_status locate(lc_device *dev, const char *path, const lci_vol_opts *o, lci_header_fn parse, lci_vol_header *h,
                        char *data_path, size_t cap, long long *offset)
{
    lc_status s = parse_file(dev, path, o, parse, h);
    if (s == LC_OK) data_location(path, h, data_path, cap, offset);
    return s;
}

lc_status lci_vol_read_with_header(lc_device *dev, const char *path, const lci_vol_opts *o, lci_header_fn parse,
                                   lci_loaded *out)
{
    lci_vol_header h;
    char data_path[2048];
    long long offset;
    lc_status s = locate(dev, path, o, parse, &h, data_path, sizeof data_path, &offset);
    return s != LC_OK ? s : lci_vol_load(dev, path, data_path, offset, &h, o, out);
}

lc_status lci_vol_layout_of(lc_device *dev, const char *path, const lci_vol_opts *o, lci_header_fn parse,
                            lci_vol_layout *l)
{
    lci_vol_header h;
    char data_path[2048];
    long long offset;
    lc_status s = locate(dev, path, o, parse, &h, data_path, sizeof data_path, &offset);
    return s != LC_OK ? s : lci_vol_layout_from_header(dev, path, data_path, offset, &h, o, l);
}

/* Voxel count of h's sizes, or 0 after an error. */
static uint64_t voxel_count(lc_device *dev, const char *path, const lci_vol_header *h)
{
    uint64_t count = 1;
    for (int a = 0; a < 3; a++) {
        if (h->size[a] < 2 || h->size[a] > INT32_MAX)
            return lci_error(dev, LC_ERROR_FORMAT, "%s: size %lld along axis %d, expected 2 to 2^31-1", path,
                             (long long)h->size[a], a), 0;
        if (count > ((uint64_t)INT32_MAX - 64) / (uint64_t)h->size[a])
            return lci_error(dev, LC_ERROR_FORMAT, "%s: sizes %lld x %lld x %lld overflow (more than 2^31 values)", path,
                             (long long)h->size[0], (long long)h->size[1], (long long)h->size[2]), 0;
        count *= (uint64_t)h->size[a];
    }
    return count;
}

lc_status lci_vol_load(lc_device *dev, const char *path, const char *data_path, long long offset,
                       const lci_vol_header *h, const lci_vol_opts *o, lci_loaded *out)
{
    int es = lci_value_size(h->type);
    if (!es) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: value type %d is not supported", path, (int)h->type);
    uint64_t count = voxel_count(dev, path, h);
    if (!count) return LC_ERROR_FORMAT;
    uint64_t bytes = count * (uint64_t)es;
    FILE *f;
    int64_t len;
    lc_status s = open_data(dev, path, data_path, &offset, h->gzip, bytes, &f, &len);
    if (s != LC_OK) return s;
    void *data = lci_alloc_checked(dev, path, count, (uint64_t)es, 64, "voxels", 0);
    if (!data) s = LC_ERROR_OUT_OF_MEMORY;
    if (s == LC_OK) s = read_data(dev, data_path, f, offset, len, h->gzip, bytes, data);
    fclose(f);
    lc_grid_desc *d = s == LC_OK ? calloc(1, sizeof *d) : NULL; /* copied by the grid, which owns its voxels */
    if (s == LC_OK && !d) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    if (s != LC_OK) {
        free(data);
        return s;
    }
    if (h->big_endian) swap_bytes(data, count, es);
    if (h->type == LC_VALUE_FLOAT32) /* name the byte of a non-finite value (a wrong byte order shows here) */
        for (uint64_t i = 0; i < count; i++) {
            float v;
            memcpy(&v, (unsigned char *)data + 4 * i, 4);
            if (isfinite(v)) continue;
            char where[64];
            if (h->gzip) snprintf(where, sizeof where, "inflated data byte %llu", (unsigned long long)(4 * i));
            else snprintf(where, sizeof where, "byte %llu", (unsigned long long)offset + 4 * i);
            lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s%s: voxel %llu is %g, expected a finite %s-endian float32", path,
                      strcmp(path, data_path) ? data_path : "", strcmp(path, data_path) ? " " : "", where,
                      (unsigned long long)i, (double)v, h->big_endian ? "big" : "little");
            free(d);
            free(data);
            return LC_ERROR_FORMAT;
        }
    const double one[3] = {1, 1, 1}, zero[3] = {0, 0, 0};
    return lci_vol_hand_over(dev, path, d, h->size, h->type, h->have_spacing ? h->spacing : one,
                             h->have_origin ? h->origin : zero, o, data, out);
}

lc_status lci_vol_hand_over(lc_device *dev, const char *path, lc_grid_desc *d, const int64_t size[3], lc_value_type type,
                            const double spacing[3], const double origin[3], const lci_vol_opts *o, void *data,
                            lci_loaded *out)
{
    for (int a = 0; a < 3; a++) d->size[a] = (int)size[a];
    d->type = type;
    d->spacing = (lc_vec3){(float)spacing[0], (float)spacing[1], (float)spacing[2]};
    d->origin = (lc_vec3){(float)origin[0], (float)origin[1], (float)origin[2]};
    if (o->spacing.x != 0 || o->spacing.y != 0 || o->spacing.z != 0) d->spacing = o->spacing;
    if (o->origin.x != 0 || o->origin.y != 0 || o->origin.z != 0) d->origin = o->origin;
    d->data = data;
    out->desc = d;
    lci_loaded_keep(out, data);
    return lci_vol_geometry(dev, path, d->size, d->spacing, d->origin);
}

lc_status lci_vol_layout_from_header(lc_device *dev, const char *path, const char *data_path, long long offset,
                                     const lci_vol_header *h, const lci_vol_opts *o, lci_vol_layout *l)
{
    memset(l, 0, sizeof *l);
    if (h->gzip) return lci_error(dev, LC_ERROR_UNSUPPORTED, "%s: compressed voxels are read whole", path);
    int es = lci_value_size(h->type);
    if (!es) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: value type %d is not supported", path, (int)h->type);
    uint64_t count = voxel_count(dev, path, h);
    if (!count) return LC_ERROR_FORMAT;
    FILE *f;
    int64_t len;
    lc_status s = open_data(dev, path, data_path, &offset, 0, count * (uint64_t)es, &f, &len); /* sizes checked */
    if (s != LC_OK) return s;
    fclose(f);
    snprintf(l->data_path, sizeof l->data_path, "%s", data_path);
    l->offset = offset;
    l->swap = h->big_endian;
    for (int a = 0; a < 3; a++) l->fsize[a] = h->size[a], l->perm[a] = a, l->flip[a] = 0;
    const double one[3] = {1, 1, 1}, zero[3] = {0, 0, 0};
    return lci_vol_layout_grid(dev, path, h->size, h->type, h->have_spacing ? h->spacing : one,
                               h->have_origin ? h->origin : zero, o, l);
}

lc_status lci_vol_layout_grid(lc_device *dev, const char *path, const int64_t size[3], lc_value_type type,
                              const double spacing[3], const double origin[3], const lci_vol_opts *o, lci_vol_layout *l)
{
    /* lci_vol_hand_over's rules, without data */
    lc_grid_desc *d = &l->grid;
    for (int a = 0; a < 3; a++) d->size[a] = (int)size[a];
    d->type = l->type = type;
    d->spacing = (lc_vec3){(float)spacing[0], (float)spacing[1], (float)spacing[2]};
    d->origin = (lc_vec3){(float)origin[0], (float)origin[1], (float)origin[2]};
    if (o->spacing.x != 0 || o->spacing.y != 0 || o->spacing.z != 0) d->spacing = o->spacing;
    if (o->origin.x != 0 || o->origin.y != 0 || o->origin.z != 0) d->origin = o->origin;
    return lci_vol_geometry(dev, path, d->size, d->spacing, d->origin);
}
