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
#include <sys/stat.h>
#include <strings.h>
#include "host/formats/volume_data.h"
#if LC_HAVE_ZLIB
#include <zlib.h>
#endif
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
    return 1;
}

int lci_parse_sizes(const char *v, int64_t *out, int n)
{
    char *end;
    for (int i = 0; i < n; i++) {
        errno = 0;
        long long x = strtoll(v, &end, 10);
        if (end == v || errno) return 0;
        out[i] = x;
        v = end;
    }
    while (isspace((unsigned char)*v)) v++;
    return *v == 0;
}

#if LC_HAVE_ZLIB
/* Inflates `avail` bytes at `in` (gzip or zlib wrapper) into exactly `bytes`
 * at dst: the stream must end there, neither short nor long. */
static lc_status inflate_exact(lc_device *dev, const char *file, unsigned char *in, uint64_t avail, uint64_t bytes,
                               void *dst)
{
    z_stream z;
    memset(&z, 0, sizeof z);
    if (inflateInit2(&z, 15 + 32) != Z_OK) /* gzip or zlib header */
        return lci_error(dev, LC_ERROR_INTERNAL, "%s: zlib initialisation failed", file);
    uint64_t out_done = 0, in_done = 0;
    int r = Z_OK;
    unsigned char extra;
    while (r == Z_OK) {
        if (z.avail_in == 0) {
            uint64_t n = avail - in_done < (1u << 30) ? avail - in_done : (1u << 30);
            z.next_in = in + in_done;
            z.avail_in = (uInt)n;
            in_done += n;
        }
        if (out_done < bytes) {
            uint64_t n = bytes - out_done < (1u << 30) ? bytes - out_done : (1u << 30);
            z.next_out = (unsigned char *)dst + out_done;
            z.avail_out = (uInt)n;
        } else {
            z.next_out = &extra; /* anything beyond the expected size is an error */
            z.avail_out = 1;
        }
        uInt before = z.avail_out;
        r = inflate(&z, Z_NO_FLUSH);
        uint64_t produced = before - z.avail_out;
        if (out_done >= bytes && produced) {
            r = Z_DATA_ERROR + 100;
            break;
        }
        out_done += produced;
        if (r == Z_BUF_ERROR && in_done == avail && z.avail_in == 0) break;
        if (r == Z_BUF_ERROR) r = Z_OK;
    }
    inflateEnd(&z);
    if (r == Z_DATA_ERROR + 100)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: gzip data inflates to more than the %llu bytes the sizes and type give",
                         file, (unsigned long long)bytes);
    if (r == Z_STREAM_END && out_done != bytes)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: gzip data inflates to %llu bytes but the sizes and type need %llu",
                         file, (unsigned long long)out_done, (unsigned long long)bytes);
    if (r != Z_STREAM_END)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: gzip data is %s after %llu of %llu bytes", file,
                         r == Z_BUF_ERROR || r == Z_OK ? "truncated" : "corrupt", (unsigned long long)out_done,
                         (unsigned long long)bytes);
    return LC_OK;
}
#else
static lc_status inflate_exact(lc_device *dev, const char *file, unsigned char *in, uint64_t avail, uint64_t bytes,
                               void *dst)
{
    (void)in, (void)avail, (void)bytes, (void)dst;
    return lci_missing(dev, file, "compressed voxel data", LCI_FEATURE_ZLIB);
}
#endif

/* Reads exactly `bytes` of voxels from `file` starting at `offset`: raw data
 * must fill the rest of the file exactly; gzip data must inflate to exactly
 * `bytes` and end its stream. */
static lc_status read_data(lc_device *dev, const char *header, const char *file, long long offset, int gzip,
                           uint64_t bytes, void *dst)
{
    FILE *f = fopen(file, "rb");
    if (!f && strcmp(header, file))
        return lci_error(dev, LC_ERROR_IO, "%s: its data file %s: cannot open: %s", header, file, strerror(errno));
    if (!f) return lci_error(dev, LC_ERROR_IO, "%s: cannot open: %s", file, strerror(errno));
    lc_status s = LC_OK;
    unsigned char *in = NULL;
    long long len = fseeko(f, 0, SEEK_END) == 0 ? ftello(f) : -1;
    uint64_t avail = len >= offset ? (uint64_t)(len - offset) : 0;
    if (len < 0) s = lci_error(dev, LC_ERROR_IO, "%s: cannot seek: %s", file, strerror(errno));
    else if (len < offset)
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: %lld bytes, shorter than the header's offset %lld", file, len, offset);
    else if (!gzip && avail != bytes)
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: holds %llu bytes of data but the sizes and type need %llu", file,
                      (unsigned long long)avail, (unsigned long long)bytes);
    else if (!gzip) {
        fseeko(f, offset, SEEK_SET);
        for (uint64_t got = 0; got < bytes && s == LC_OK; ) { /* in pieces, for the load progress */
            size_t k = bytes - got > (1u << 24) ? (1u << 24) : (size_t)(bytes - got);
            if (fread((unsigned char *)dst + got, 1, k, f) != k)
                s = lci_error(dev, LC_ERROR_IO, "%s: byte %llu: read failed: %s", file,
                              (unsigned long long)(offset + (long long)got), strerror(errno));
            got += k;
            lci_load_progress(dev, (double)got / (double)bytes);
        }
    } else if (!(in = malloc(avail ? avail : 1))) {
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %llu compressed bytes", file,
                      (unsigned long long)avail);
    } else {
        fseeko(f, offset, SEEK_SET);
        if (fread(in, 1, avail, f) != avail) s = lci_error(dev, LC_ERROR_IO, "%s: read failed: %s", file, strerror(errno));
        else s = inflate_exact(dev, file, in, avail, bytes, dst);
    }
    free(in);
    fclose(f);
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

lc_status lci_vol_read_with_header(lc_device *dev, const char *path, const lci_vol_opts *o, lci_header_fn parse,
                                   lci_loaded *out)
{
    lci_vol_header h;
    memset(&h, 0, sizeof h);
    FILE *f = fopen(path, "rb");
    if (!f) return lci_error(dev, LC_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    lc_status s = parse(dev, path, f, &h);
    fclose(f);
    if (s != LC_OK) return s;
    char data_path[2048];
    long long offset;
    if (h.data_file[0]) {
        const char *slash = strrchr(path, '/');
        if (h.data_file[0] == '/' || !slash) snprintf(data_path, sizeof data_path, "%s", h.data_file);
        else snprintf(data_path, sizeof data_path, "%.*s/%s", (int)(slash - path), path, h.data_file);
        offset = h.byte_skip;
    } else {
        snprintf(data_path, sizeof data_path, "%s", path);
        offset = h.data_offset + h.byte_skip;
    }
    if (o->type != LC_VALUE_DEFAULT && o->type != h.type)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: the header's type differs from the requested one", path);
    return lci_vol_load(dev, path, data_path, offset, &h, o, out);
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
    /* the data file must be able to hold the voxels before they are
       allocated (fuzz_nrrd, fuzz_metaimage: sizes of 2^31 values in a
       100-byte file allocated 8 GB): a plain file holds them after the
       offset (-1 = at the end), a gzip one inflates to at most 1032 times
       its size */
    struct stat st;
    if (stat(data_path, &st) == 0 && S_ISREG(st.st_mode)) {
        long long avail = (long long)st.st_size - (offset > 0 ? offset : 0);
        if (h->gzip ? (double)bytes > 1032.0 * (double)avail : avail < (long long)bytes)
            return lci_error(dev, LC_ERROR_FORMAT,
                             "%s: %s holds %lld bytes%s from byte %lld, but %lld x %lld x %lld voxels need %llu", path,
                             strcmp(path, data_path) ? data_path : "the file", avail < 0 ? 0 : avail, h->gzip ? " of gzip data" : "",
                             offset > 0 ? offset : 0, (long long)h->size[0], (long long)h->size[1],
                             (long long)h->size[2], (unsigned long long)bytes);
    }
    void *data = malloc(bytes + 64);
    if (!data)
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %llu bytes of voxels", path,
                         (unsigned long long)bytes);
    lc_status s = read_data(dev, path, data_path, offset, h->gzip, bytes, data);
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
    for (int a = 0; a < 3; a++) d->size[a] = (int)h->size[a];
    d->type = h->type;
    d->spacing = h->have_spacing ? (lc_vec3){(float)h->spacing[0], (float)h->spacing[1], (float)h->spacing[2]}
                                 : (lc_vec3){1, 1, 1};
    if (o->spacing.x != 0 || o->spacing.y != 0 || o->spacing.z != 0) d->spacing = o->spacing;
    if (h->have_origin) d->origin = (lc_vec3){(float)h->origin[0], (float)h->origin[1], (float)h->origin[2]};
    if (o->origin.x != 0 || o->origin.y != 0 || o->origin.z != 0) d->origin = o->origin;
    d->data = data;
    out->desc = d;
    lci_loaded_keep(out, data);
    return LC_OK;
}
