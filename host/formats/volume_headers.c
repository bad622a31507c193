/* Volume files: NRRD (.nrrd with attached data, .nhdr with
 * a detached data file; raw or gzip encoding; either endianness), MetaImage
 * (.mhd/.mha; raw or zlib-compressed) and headerless raw files. Every error
 * is one line naming the file (and the header line); nothing is created. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <zlib.h>
#include "host/formats/format.h"
#include "host/kinds/grid.h"

/* What these readers take from their options (lci_format.options). */
typedef struct gopts {
    int size[3];
    lc_value_type type;
    lc_vec3 spacing, origin;
    int big_endian;
} gopts;

typedef struct hdr {
    int ndim;
    int64_t size[3];
    lc_value_type type;
    double spacing[3];
    int have_spacing;
    double origin[3];
    int have_origin;
    int gzip;           /* 1: gzip/zlib stream */
    int big_endian;
    char data_file[1024]; /* "" = attached after the header */
    long long byte_skip;
    long data_offset;   /* attached: where the header ends */
} hdr;

static char *trim(char *s)
{
    while (isspace((unsigned char)*s)) s++;
    size_t n = strlen(s);
    while (n && isspace((unsigned char)s[n - 1])) s[--n] = 0;
    return s;
}

static int parse_nrrd_type(const char *v, lc_value_type *t)
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

static int parse_doubles(const char *v, double *out, int n)
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

static int parse_sizes(const char *v, int64_t *out, int n)
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

/* Reads header lines from f until the blank line (NRRD) or the data file key
 * (MetaImage); fills h. */
static lc_status read_header(lc_device *dev, const char *path, FILE *f, int meta, hdr *h)
{
    char line[4096];
    int ln = 0, have_sizes = 0, have_type = 0;
    h->ndim = 3;
    if (!meta) {
        if (!fgets(line, sizeof line, f) || strncmp(line, "NRRD000", 7) != 0)
            return lci_error(dev, LC_ERROR_FORMAT, "%s:1: not a NRRD file (no NRRD000x magic)", path);
        ln = 1;
    }
    while (fgets(line, sizeof line, f)) {
        ln++;
        if (!strchr(line, '\n') && !feof(f))
            return lci_error(dev, LC_ERROR_FORMAT, "%s:%d: header line longer than %zu bytes", path, ln, sizeof line - 1);
        char *s = trim(line);
        if (!meta && *s == 0) break; /* end of a NRRD header */
        if (*s == '#' || *s == 0) continue;
        char *sep = meta ? strchr(s, '=') : strstr(s, ": ");
        if (!meta && !sep && strstr(s, ":=")) continue; /* key/value pair */
        if (!sep) {
            if (!meta && s[strlen(s) - 1] == ':') sep = s + strlen(s) - 1;
            else return lci_error(dev, LC_ERROR_FORMAT, "%s:%d: expected \"%s\", got \"%s\"", path, ln,
                                  meta ? "key = value" : "field: value", s);
        }
        *sep = 0;
        char *k = trim(s), *v = trim(sep + 1 + (meta ? 0 : 1) - (sep[1] == 0 ? 1 : 0));
        if (!meta) {
            if (!strcasecmp(k, "dimension")) {
                if (strcmp(v, "3") != 0)
                    return lci_error(dev, LC_ERROR_FORMAT, "%s:%d: dimension %s, only 3-D volumes are supported", path, ln, v);
            } else if (!strcasecmp(k, "type")) {
                if (!parse_nrrd_type(v, &h->type))
                    return lci_error(dev, LC_ERROR_FORMAT,
                                     "%s:%d: type \"%s\" is not supported (uint8, uint16, int16 or float)", path, ln, v);
                have_type = 1;
            } else if (!strcasecmp(k, "sizes")) {
                if (!parse_sizes(v, h->size, 3))
                    return lci_error(dev, LC_ERROR_FORMAT, "%s:%d: sizes \"%s\": expected three integers", path, ln, v);
                have_sizes = 1;
            } else if (!strcasecmp(k, "spacings")) {
                if (!parse_doubles(v, h->spacing, 3))
                    return lci_error(dev, LC_ERROR_FORMAT, "%s:%d: spacings \"%s\": expected three numbers", path, ln, v);
                h->have_spacing = 1;
            } else if (!strcasecmp(k, "space directions")) {
                double m[9];
                if (!parse_doubles(v, m, 9))
                    return lci_error(dev, LC_ERROR_FORMAT, "%s:%d: space directions \"%s\": expected three vectors", path,
                                     ln, v);
                for (int a = 0; a < 3; a++)
                    h->spacing[a] = sqrt(m[3 * a] * m[3 * a] + m[3 * a + 1] * m[3 * a + 1] + m[3 * a + 2] * m[3 * a + 2]);
                h->have_spacing = 1;
            } else if (!strcasecmp(k, "space origin")) {
                if (!parse_doubles(v, h->origin, 3))
                    return lci_error(dev, LC_ERROR_FORMAT, "%s:%d: space origin \"%s\": expected (x,y,z)", path, ln, v);
                h->have_origin = 1;
            } else if (!strcasecmp(k, "encoding")) {
                if (!strcasecmp(v, "raw")) h->gzip = 0;
                else if (!strcasecmp(v, "gzip") || !strcasecmp(v, "gz")) h->gzip = 1;
                else
                    return lci_error(dev, LC_ERROR_FORMAT, "%s:%d: encoding \"%s\" is not supported (raw or gzip)", path,
                                     ln, v);
            } else if (!strcasecmp(k, "endian")) {
                if (!strcasecmp(v, "little")) h->big_endian = 0;
                else if (!strcasecmp(v, "big")) h->big_endian = 1;
                else return lci_error(dev, LC_ERROR_FORMAT, "%s:%d: endian \"%s\": expected little or big", path, ln, v);
            } else if (!strcasecmp(k, "data file") || !strcasecmp(k, "datafile")) {
                if (!strncasecmp(v, "LIST", 4) || strchr(v, '%'))
                    return lci_error(dev, LC_ERROR_FORMAT, "%s:%d: multi-file data (\"%s\") is not supported", path, ln, v);
                snprintf(h->data_file, sizeof h->data_file, "%s", v);
                break; /* detached headers end here */
            } else if (!strcasecmp(k, "byte skip")) {
                h->byte_skip = strtoll(v, NULL, 10);
                if (h->byte_skip < 0)
                    return lci_error(dev, LC_ERROR_FORMAT, "%s:%d: byte skip %s is not supported", path, ln, v);
            }
        } else {
            if (!strcasecmp(k, "NDims")) {
                if (strcmp(v, "3") != 0)
                    return lci_error(dev, LC_ERROR_FORMAT, "%s:%d: NDims %s, only 3-D volumes are supported", path, ln, v);
            } else if (!strcasecmp(k, "DimSize")) {
                if (!parse_sizes(v, h->size, 3))
                    return lci_error(dev, LC_ERROR_FORMAT, "%s:%d: DimSize \"%s\": expected three integers", path, ln, v);
                have_sizes = 1;
            } else if (!strcasecmp(k, "ElementType")) {
                if (!strcmp(v, "MET_UCHAR")) h->type = LC_VALUE_UINT8;
                else if (!strcmp(v, "MET_USHORT")) h->type = LC_VALUE_UINT16;
                else if (!strcmp(v, "MET_SHORT")) h->type = LC_VALUE_INT16;
                else if (!strcmp(v, "MET_FLOAT")) h->type = LC_VALUE_FLOAT32;
                else
                    return lci_error(dev, LC_ERROR_FORMAT,
                                     "%s:%d: ElementType %s is not supported (MET_UCHAR, MET_USHORT, MET_SHORT, MET_FLOAT)",
                                     path, ln, v);
                have_type = 1;
            } else if (!strcasecmp(k, "ElementSpacing")) {
                if (!parse_doubles(v, h->spacing, 3))
                    return lci_error(dev, LC_ERROR_FORMAT, "%s:%d: ElementSpacing \"%s\": expected three numbers", path, ln, v);
                h->have_spacing = 1;
            } else if (!strcasecmp(k, "Offset") || !strcasecmp(k, "Origin") || !strcasecmp(k, "Position")) {
                if (!parse_doubles(v, h->origin, 3))
                    return lci_error(dev, LC_ERROR_FORMAT, "%s:%d: %s \"%s\": expected three numbers", path, ln, k, v);
                h->have_origin = 1;
            } else if (!strcasecmp(k, "ElementByteOrderMSB") || !strcasecmp(k, "BinaryDataByteOrderMSB")) {
                h->big_endian = !strcasecmp(v, "True");
            } else if (!strcasecmp(k, "CompressedData")) {
                h->gzip = !strcasecmp(v, "True");
            } else if (!strcasecmp(k, "HeaderSize")) {
                h->byte_skip = strtoll(v, NULL, 10);
            } else if (!strcasecmp(k, "ElementDataFile")) {
                if (strcasecmp(v, "LOCAL") != 0) snprintf(h->data_file, sizeof h->data_file, "%s", v);
                break;
            } else if (!strcasecmp(k, "ElementNumberOfChannels") && strcmp(v, "1") != 0) {
                return lci_error(dev, LC_ERROR_FORMAT, "%s:%d: %s channels, only scalar volumes are supported", path, ln, v);
            }
        }
    }
    if (!have_type) return lci_error(dev, LC_ERROR_FORMAT, "%s: the header gives no %s", path, meta ? "ElementType" : "type");
    if (!have_sizes) return lci_error(dev, LC_ERROR_FORMAT, "%s: the header gives no %s", path, meta ? "DimSize" : "sizes");
    h->data_offset = ftell(f);
    return LC_OK;
}

/* Reads exactly `bytes` of voxels from `file` starting at `offset`: raw data
 * must fill the rest of the file exactly; gzip data must inflate to exactly
 * `bytes` and end its stream. */
static lc_status read_data(lc_device *dev, const char *file, long long offset, int gzip, uint64_t bytes, void *dst)
{
    FILE *f = fopen(file, "rb");
    if (!f) return lci_error(dev, LC_ERROR_IO, "%s: cannot open: %s", file, strerror(errno));
    lc_status s = LC_OK;
    unsigned char *in = NULL;
    if (fseeko(f, 0, SEEK_END) != 0) {
        s = lci_error(dev, LC_ERROR_IO, "%s: cannot seek: %s", file, strerror(errno));
        goto done;
    }
    long long len = ftello(f);
    if (len < offset) {
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: %lld bytes, shorter than the header's offset %lld", file, len, offset);
        goto done;
    }
    fseeko(f, offset, SEEK_SET);
    uint64_t avail = (uint64_t)(len - offset);
    if (!gzip) {
        if (avail != bytes) {
            s = lci_error(dev, LC_ERROR_FORMAT, "%s: holds %llu bytes of data but the sizes and type need %llu", file,
                          (unsigned long long)avail, (unsigned long long)bytes);
            goto done;
        }
        if (fread(dst, 1, bytes, f) != bytes) s = lci_error(dev, LC_ERROR_IO, "%s: read failed: %s", file, strerror(errno));
        goto done;
    }
    in = malloc(avail ? avail : 1);
    if (!in) {
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %llu compressed bytes", file, (unsigned long long)avail);
        goto done;
    }
    if (fread(in, 1, avail, f) != avail) {
        s = lci_error(dev, LC_ERROR_IO, "%s: read failed: %s", file, strerror(errno));
        goto done;
    }
    z_stream z;
    memset(&z, 0, sizeof z);
    if (inflateInit2(&z, 15 + 32) != Z_OK) { /* gzip or zlib header */
        s = lci_error(dev, LC_ERROR_INTERNAL, "%s: zlib initialisation failed", file);
        goto done;
    }
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
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: gzip data inflates to more than the %llu bytes the sizes and type give", file,
                      (unsigned long long)bytes);
    else if (r == Z_STREAM_END && out_done != bytes)
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: gzip data inflates to %llu bytes but the sizes and type need %llu", file,
                      (unsigned long long)out_done, (unsigned long long)bytes);
    else if (r != Z_STREAM_END)
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: gzip data is %s after %llu of %llu bytes", file,
                      r == Z_BUF_ERROR || r == Z_OK ? "truncated" : "corrupt", (unsigned long long)out_done,
                      (unsigned long long)bytes);
done:
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

static lc_status parse_options(lc_device *dev, const lci_read_args *a, gopts *o)
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

/* Reads a volume as format `which` (0 raw, 1 NRRD, 2 MetaImage). */
static lc_status read_volume(lc_device *dev, const lci_read_args *args, int which, lci_loaded *out)
{
    const char *path = args->path;
    gopts o0;
    lc_status os = parse_options(dev, args, &o0);
    if (os != LC_OK) return os;
    const gopts *o = &o0;
    hdr h;
    memset(&h, 0, sizeof h);
    int nrrd = which == 1, meta = which == 2;
    char data_path[2048];
    long long offset = 0;
    if (nrrd || meta) {
        FILE *f = fopen(path, "rb");
        if (!f) return lci_error(dev, LC_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
        lc_status s = read_header(dev, path, f, meta, &h);
        fclose(f);
        if (s != LC_OK) return s;
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
    } else {
        if (o->size[0] <= 0 || o->size[1] <= 0 || o->size[2] <= 0 || o->type == LC_VALUE_DEFAULT)
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                             "%s: a raw volume needs its sizes and value type (--dims X,Y,Z --type T)", path);
        for (int a = 0; a < 3; a++) h.size[a] = o->size[a];
        h.type = o->type;
        h.big_endian = o->big_endian;
        snprintf(data_path, sizeof data_path, "%s", path);
    }
    int es = lci_value_size(h.type);
    if (!es) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: value type %d is not supported", path, (int)h.type);
    uint64_t count = 1;
    for (int a = 0; a < 3; a++) {
        if (h.size[a] < 2 || h.size[a] > INT32_MAX)
            return lci_error(dev, LC_ERROR_FORMAT, "%s: size %lld along axis %d, expected 2 to 2^31-1", path,
                             (long long)h.size[a], a);
        if (count > ((uint64_t)INT32_MAX - 64) / (uint64_t)h.size[a])
            return lci_error(dev, LC_ERROR_FORMAT,
                             "%s: sizes %lld x %lld x %lld overflow (more than 2^31 values)", path, (long long)h.size[0],
                             (long long)h.size[1], (long long)h.size[2]);
        count *= (uint64_t)h.size[a];
    }
    uint64_t bytes = count * (uint64_t)es;
    void *data = malloc(bytes + 64);
    if (!data)
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %llu bytes of voxels", path, (unsigned long long)bytes);
    lc_status s = read_data(dev, data_path, offset, h.gzip, bytes, data);
    if (s != LC_OK) {
        free(data);
        return s;
    }
    if (h.big_endian) swap_bytes(data, count, es);
    lc_grid_desc d;
    memset(&d, 0, sizeof d); /* copied by the grid, which owns its voxels */
    for (int a = 0; a < 3; a++) d.size[a] = (int)h.size[a];
    d.type = h.type;
    d.spacing = h.have_spacing ? (lc_vec3){(float)h.spacing[0], (float)h.spacing[1], (float)h.spacing[2]} : (lc_vec3){1, 1, 1};
    if (o->spacing.x != 0 || o->spacing.y != 0 || o->spacing.z != 0) d.spacing = o->spacing;
    if (h.have_origin) d.origin = (lc_vec3){(float)h.origin[0], (float)h.origin[1], (float)h.origin[2]};
    if (o->origin.x != 0 || o->origin.y != 0 || o->origin.z != 0) d.origin = o->origin;
    lc_grid_desc *dp = malloc(sizeof *dp);
    if (!dp) {
        free(data);
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    d.data = data;
    *dp = d;
    out->desc = dp;
    lci_loaded_keep(out, data);
    return LC_OK;
}
static lc_status raw_read(lc_device *dev, const lci_read_args *a, lci_loaded *out) { return read_volume(dev, a, 0, out); }
static lc_status nrrd_read(lc_device *dev, const lci_read_args *a, lci_loaded *out) { return read_volume(dev, a, 1, out); }
static lc_status mhd_read(lc_device *dev, const lci_read_args *a, lci_loaded *out) { return read_volume(dev, a, 2, out); }

static int nrrd_magic(const unsigned char *h, size_t n) { return n >= 7 && !memcmp(h, "NRRD000", 7); }

const lci_format lci_format_nrrd = {
    .name = "nrrd", .kind = LC_KIND_GRID, .extensions = ".nrrd .nhdr", .options = "type spacing origin",
    .description = "NRRD: attached or detached data, raw or gzip, either endianness", .magic = nrrd_magic,
    .read = nrrd_read};
const lci_format lci_format_metaimage = {
    .name = "metaimage", .kind = LC_KIND_GRID, .extensions = ".mhd .mha", .options = "type spacing origin",
    .description = "MetaImage: .mhd with a data file or .mha with attached data", .read = mhd_read};
const lci_format lci_format_raw_volume = {
    .name = "raw-volume", .kind = LC_KIND_GRID, .extensions = ".raw", .options = "size type spacing origin endian",
    .description = "headerless voxels, x fastest; size and type required", .read = raw_read};

