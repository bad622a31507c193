/* The formats registry: every format lanecast reads, how a file is matched
 * to one (the load request's name, else magic bytes, else the extension),
 * and lc_volume_load, which reads through the format and creates the volume
 * through its kind's row. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include "host/formats/checked.h"
#include "host/formats/format.h"
#include "host/formats/text_reader.h"

/* Magic-byte formats first: a file that says what it is wins over its name.
 * Formats sharing an extension: the first listed is the fallback (rbf text). */
static const lci_format *const formats[] = {
    &lci_format_nrrd, &lci_format_metaimage, &lci_format_pdb, &lci_format_rbf, &lci_format_rbf_binary,
    &lci_format_xyz, &lci_format_gro, &lci_format_raw_particles, &lci_format_raw_volume,
    &lci_format_dcd, &lci_format_xtc, &lci_format_trr, &lci_format_ncdf, &lci_format_lammps, &lci_format_gadget,
    &lci_format_nifti, &lci_format_vtk, &lci_format_hdf5, &lci_format_mmcif, &lci_format_csv, &lci_format_dicom,
};
#define NFORMATS ((int)(sizeof formats / sizeof formats[0]))

int lc_format_count(void) { return NFORMATS; }

const lc_option *lci_option_find(const lci_read_args *a, const char *key)
{
    for (int i = 0; i < a->noptions; i++)
        if (!strcmp(a->options[i].key, key)) return &a->options[i];
    return NULL;
}

lc_status lc_format_get(int index, lc_format_info *out)
{
    if (index < 0 || index >= NFORMATS || !out)
        return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_format_get: index %d is not in [0, %d) or out is NULL",
                         index, NFORMATS);
    const lci_format *f = formats[index];
    out->name = f->name;
    out->kind = f->kind;
    out->extensions = f->extensions;
    out->options = f->options;
    out->description = f->description;
    out->available = f->read != NULL;
    out->package = f->package ? f->package : "";
    return LC_OK;
}

void *lci_loaded_keep(lci_loaded *l, void *p)
{
    for (int i = 0; i < LCI_LOADED_MEM; i++)
        if (!l->mem[i]) return l->mem[i] = p;
    free(p);
    return NULL;
}

void lci_loaded_free(lci_loaded *l)
{
    for (int i = 0; i < LCI_LOADED_MEM; i++) free(l->mem[i]);
    free(l->desc);
    memset(l, 0, sizeof *l);
}

/* Is word a member of the space-separated list? */
static int in_list(const char *list, const char *word, size_t len)
{
    for (const char *p = list; p && *p;) {
        while (*p == ' ') p++;
        const char *e = strchr(p, ' ');
        size_t n = e ? (size_t)(e - p) : strlen(p);
        if (n == len && n && !strncasecmp(p, word, len)) return 1;
        p = e;
    }
    return 0;
}

static const lci_format *by_name(const char *name)
{
    for (int i = 0; i < NFORMATS; i++)
        if (!strcmp(formats[i]->name, name)) return formats[i];
    return NULL;
}

/* The extension of path with a trailing ".gz" looked through, or "". */
static void extension(const char *path, char *ext, size_t n, int *gz)
{
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    size_t len = strlen(base);
    *gz = len > 3 && !strcasecmp(base + len - 3, ".gz");
    if (*gz) len -= 3;
    const char *dot = NULL;
    for (size_t i = 0; i < len; i++)
        if (base[i] == '.') dot = base + i;
    ext[0] = '\0';
    if (dot && (size_t)(base + len - dot) < n) snprintf(ext, n, "%.*s", (int)(base + len - dot), dot);
}

static lc_status decide(lc_device *dev, const char *path, const lc_load_desc *d, const lci_format **out, int *gzip)
{
    *out = NULL;
    struct stat st;
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) { /* a folder: the format that reads folders */
        *gzip = 0;
        for (int i = 0; i < NFORMATS; i++)
            if (formats[i]->folders && (!d->format || !d->format[0] || !strcmp(d->format, formats[i]->name))) {
                if (!formats[i]->read) /* compiled out: still an I/O error, as any folder was before */
                    return lci_error(dev, LC_ERROR_IO,
                                     "%s: is a directory (lanecast reads folders as %s series, which this build "
                                     "lacks: install %s and rebuild)", path, formats[i]->name, formats[i]->package);
                return *out = formats[i], LC_OK;
            }
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: a folder; %s files are read one file at a time", path,
                         d->format);
    }
    unsigned char head[512];
    size_t n = 0;
    lc_status s = lci_file_head(dev, path, head, sizeof head, &n, gzip);
    if (s != LC_OK) return s;
    if (d->format && d->format[0]) {
        *out = by_name(d->format);
        if (!*out) {
            char names[512] = "";
            for (int i = 0; i < NFORMATS; i++)
                snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", i ? ", " : "", formats[i]->name);
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: unknown format '%s' (known: %s)", path, d->format,
                             names);
        }
        return LC_OK;
    }
    for (int i = 0; i < NFORMATS; i++)
        if (formats[i]->magic && formats[i]->magic(head, n)) return *out = formats[i], LC_OK;
    char ext[32];
    int gz;
    extension(path, ext, sizeof ext, &gz);
    for (int i = 0; i < NFORMATS; i++)
        if (ext[0] && in_list(formats[i]->extensions, ext, strlen(ext))) return *out = formats[i], LC_OK;
    return lci_error(dev, LC_ERROR_UNSUPPORTED,
                     "%s: unknown file format (extension '%s'; `lanecast formats` lists what lanecast reads; raw data "
                     "needs its format named)",
                     path, ext);
}

/* The kind a file of format f holds: the format's, or what the file says. */
static lc_status kind_of(lc_device *dev, const lci_format *f, const char *path, const lc_load_desc *d, lc_kind *out)
{
    *out = f->kind;
    if (f->kind != LC_KIND_NONE) return LC_OK;
    if (!f->kind_of || !f->read)
        return lci_error(dev, LC_ERROR_UNSUPPORTED, "%s: cannot tell what kind of data this %s file holds", path,
                         f->name);
    lc_status s = f->kind_of(dev, path, d, out);
    if (s == LC_OK && !lci_kind(*out))
        return lci_error(dev, LC_ERROR_INTERNAL, "%s: the %s reader named kind %d", path, f->name, (int)*out);
    return s;
}

lc_status lc_file_probe(lc_device *dev, const char *path, const lc_load_desc *desc, lc_file_info *out)
{
    if (!path || !out) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_file_probe: path and out must not be NULL");
    lc_load_desc none = {0};
    const lci_format *f;
    int gzip;
    lc_status s = decide(dev, path, desc ? desc : &none, &f, &gzip);
    if (s == LC_OK) s = kind_of(dev, f, path, desc ? desc : &none, &out->kind);
    if (s != LC_OK) return s;
    out->format = f->name;
    out->frames = 1;
    out->gzip = gzip;
    if (f->frames && f->read) {
        /* Counting may fail (no zlib, a malformed file): the probe still
         * answers, with 0 = unknown, and leaves the message to the load. */
        char keep[LCI_MSG_MAX];
        snprintf(keep, sizeof keep, "%s", lc_last_error());
        if (f->frames(NULL, path, &out->frames) != LC_OK) {
            out->frames = 0;
            lci_error(NULL, LC_OK, "%s", keep);
        }
    }
    return LC_OK;
}

lc_status lc_file_describe(lc_device *dev, const char *path, const lc_load_desc *desc, char *text, size_t size)
{
    if (!path || !text || size == 0)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_file_describe: path and text must not be NULL, size not 0");
    text[0] = 0;
    lc_load_desc none = {0};
    const lc_load_desc *d = desc ? desc : &none;
    if (d->noptions < 0 || (d->noptions > 0 && !d->options))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_file_describe: bad options list");
    const lci_format *f;
    int gzip;
    lc_status s = decide(dev, path, d, &f, &gzip);
    if (s != LC_OK || !f->describe || !f->read) return s;
    /* the format's own options only: the description does not build a volume */
    lc_option *fo = malloc(sizeof *fo * (size_t)(d->noptions + 1));
    if (!fo) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_file_describe: out of memory");
    int nf = 0;
    for (int i = 0; i < d->noptions; i++)
        if (d->options[i].key && d->options[i].value &&
            in_list(f->options, d->options[i].key, strlen(d->options[i].key)))
            fo[nf++] = d->options[i];
    lci_read_args a = {path, d, fo, nf, f->name};
    s = f->describe(dev, &a, text, size);
    free(fo);
    return s;
}

/* Splits the options: the format's to the reader (in fopts), the kind's
 * applied to the descriptor after reading; anything else is an error. */
static lc_status split_options(lc_device *dev, const char *path, const lci_format *f, const lci_kind_ops *k,
                               const lc_load_desc *d, lc_option *fopts, int *nf)
{
    *nf = 0;
    for (int i = 0; i < d->noptions; i++) {
        const lc_option *o = &d->options[i];
        if (!o->key || !o->value)
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: option %d has no key or value", path, i);
        if (!strcmp(o->key, "max_memory")) { /* every format: the memory limit (checked.h) */
            uint64_t m;
            if (lci_parse_memory(o->value, &m))
                return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                                 "%s: option max_memory = '%s': expected a size in bytes, e.g. 512M, 8G", path, o->value);
            dev->load_max_memory = m;
        } else if (!strcmp(o->key, "field_by") && in_list(f->options, "fields", 6)) { /* field_by: the name for fields */
            fopts[*nf] = *o;
            fopts[(*nf)++].key = "fields";
        } else if (in_list(f->options, o->key, strlen(o->key)))
            fopts[(*nf)++] = *o;
        else if (!in_list(k->option_keys, o->key, strlen(o->key)))
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                             "%s: option '%s' does not apply to %s files (they take: %s%s%s)", path, o->key, f->name,
                             f->options, f->options[0] ? " " : "", k->option_keys);
    }
    return LC_OK;
}

lc_status lci_read_volume_desc(lc_device *dev, const char *path, const lc_load_desc *d, lc_kind *kind_out,
                               const char **format, lci_loaded *l)
{
    return lci_read_volume_share(dev, path, d, NULL, kind_out, format, l);
}

lc_status lci_read_volume_share(lc_device *dev, const char *path, const lc_load_desc *d, lci_share *share,
                                lc_kind *kind_out, const char **format, lci_loaded *l)
{
    memset(l, 0, sizeof *l);
    const lci_format *f;
    int gzip;
    lc_status s = decide(dev, path, d, &f, &gzip);
    if (s != LC_OK) return s;
    if (d->frame > 0 && !f->frames)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: %s files hold one frame; frame %lld was asked for", path,
                         f->name, (long long)d->frame);
    if (d->companion && d->companion[0] && !f->companion)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: %s files take no companion file (got '%s')", path, f->name,
                         d->companion);
    if (!f->read)
        return lci_error(dev, LC_ERROR_UNSUPPORTED, "%s: %s files are not supported by this build (install %s and rebuild)",
                         path, f->name, f->package ? f->package : "its library");
    if (share && !f->shares)
        return lci_error(dev, LC_ERROR_UNSUPPORTED, "%s: %s files are read whole, not by shares", path, f->name);
    lc_option *fopts = malloc(sizeof *fopts * (size_t)(d->noptions + 1));
    if (!fopts) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_volume_load: out of memory");
    int nf;
    lc_kind kind;
    s = kind_of(dev, f, path, d, &kind);
    const lci_kind_ops *k = lci_kind(kind);
    dev->load_max_memory = 0;
    if (s == LC_OK) s = split_options(dev, path, f, k, d, fopts, &nf);
    if (s == LC_OK) {
        lci_read_args a = {path, d, fopts, nf, f->name};
        dev->load_progress = d->progress, dev->load_progress_user = d->progress_user, dev->load_last = 0.0f;
        if (d->progress) d->progress(d->progress_user, 0.0f);
        dev->load_share = share;
        s = f->read(dev, &a, l);
        dev->load_share = NULL;
        if (s == LC_OK && d->progress) d->progress(d->progress_user, 1.0f);
        dev->load_progress = NULL, dev->load_progress_user = NULL;
    }
    dev->load_max_memory = 0;
    for (int i = 0; s == LC_OK && i < d->noptions; i++)
        if (strcmp(d->options[i].key, "max_memory") && in_list(k->option_keys, d->options[i].key, strlen(d->options[i].key)))
            s = k->set_option(dev, l->desc, &d->options[i], path);
    free(fopts);
    if (s != LC_OK) lci_loaded_free(l);
    if (s == LC_OK) *kind_out = kind, *format = f->name;
    return s;
}

lc_status lc_volume_load(lc_device *dev, const char *path, const lc_load_desc *desc, lc_volume **out)
{
    if (!dev) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_volume_load: device is NULL");
    if (!out) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_volume_load: out is NULL");
    *out = NULL;
    if (!path) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_volume_load: path is NULL");
    lc_load_desc none = {0};
    const lc_load_desc *d = desc ? desc : &none;
    if (d->noptions < 0 || (d->noptions > 0 && !d->options) || d->frame < 0)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_volume_load: bad options list or frame");
    lci_loaded l;
    lc_kind kind;
    const char *format;
    lc_status s = lci_read_volume_desc(dev, path, d, &kind, &format, &l);
    if (s == LC_OK) {
        s = lci_kind(kind)->create(dev, l.desc, out);
        if (s != LC_OK) { /* the message names the file */
            char msg[LCI_MSG_MAX];
            snprintf(msg, sizeof msg, "%s", lc_last_error());
            lci_error(dev, s, "%s: %s", path, msg);
        }
    }
    lci_loaded_free(&l);
    return s;
}

/* For the encoder (host/encode/samples.c): reads a structured volume through
 * its format's reader without creating the volume; the grid descriptor is in
 * out->desc (free with lci_loaded_free). Files of another kind fail, naming
 * the kind. */
lc_status lci_read_grid(lc_device *dev, const char *path, const lc_load_desc *desc, const char **format,
                        lci_loaded *out)
{
    memset(out, 0, sizeof *out);
    lc_load_desc none = {0};
    const lc_load_desc *d = desc ? desc : &none;
    if (d->noptions < 0 || (d->noptions > 0 && !d->options) || d->frame != 0 || (d->companion && d->companion[0]))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: bad options list, frame or companion for a volume", path);
    const lci_format *f;
    int gzip;
    lc_status s = decide(dev, path, d, &f, &gzip);
    if (s != LC_OK) return s;
    if (f->kind != LC_KIND_GRID)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "%s: %s files hold %s data; the encoder reads structured volumes, CSV (x,y,z,value) and "
                         "VTK legacy point data",
                         path, f->name, lc_kind_name(f->kind));
    if (!f->read)
        return lci_error(dev, LC_ERROR_UNSUPPORTED, "%s: %s files are not supported by this build (install %s and rebuild)",
                         path, f->name, f->package ? f->package : "its library");
    uint64_t limit = 0;
    for (int i = 0; i < d->noptions; i++) {
        const lc_option *o = &d->options[i];
        if (o->key && o->value && !strcmp(o->key, "max_memory")) {
            if (lci_parse_memory(o->value, &limit))
                return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                                 "%s: option max_memory = '%s': expected a size in bytes, e.g. 512M, 8G", path, o->value);
        } else if (!o->key || !o->value || !in_list(f->options, o->key, strlen(o->key)))
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: option '%s' does not apply to %s files (they take: %s)",
                             path, o->key ? o->key : "(null)", f->name, f->options);
    }
    *format = f->name;
    /* the reader sees the format's options only */
    lc_option *fo = malloc(sizeof *fo * (size_t)(d->noptions + 1));
    if (!fo) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lci_read_grid: out of memory");
    int nf = 0;
    for (int i = 0; i < d->noptions; i++)
        if (strcmp(d->options[i].key, "max_memory")) fo[nf++] = d->options[i];
    lci_read_args a = {path, d, fo, nf, f->name};
    if (dev) dev->load_max_memory = limit;
    s = f->read(dev, &a, out);
    if (dev) dev->load_max_memory = 0;
    free(fo);
    if (s != LC_OK) lci_loaded_free(out);
    return s;
}
