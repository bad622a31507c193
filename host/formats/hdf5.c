/* HDF5 files through libhdf5: a container whose kind the file (and the
 * load request) tells (lci_format.kind_of).
 *
 * Particle snapshots in the GADGET-3 / AREPO / SWIFT layout (PartType0..5
 * groups: hdf5_snapshot.c). Options as the GADGET reader's: types,
 * fields = type|none, value = none|mass|u|rho|hsml, radius, radius_scale,
 * knn (radius = SmoothingLength when the type has it, else the distance to
 * the knn-th neighbour), kernel and hsml_is (host/sph/sph_load.h). `select`
 * (select.h): index over the file's particles (PartType0 first) and type
 * (the N of PartTypeN); a selected particle keeps the radius found among all
 * of its type's particles.
 *
 * `dataset = PATH`: a 3-D dataset (C order, so its last dimension is x)
 * becomes a grid (uint8, int16, uint16 and float32 as they are, other
 * numbers as float32; spacing and origin options); an N x 3 dataset becomes
 * particle positions (radius option or k-NN radii).
 *
 * Errors name the file and the object (and the byte where HDF5 gives one:
 * the signature, a contiguous dataset's address). libhdf5's own error
 * printing is switched off while this file calls it; its innermost message
 * is quoted instead. */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "host/formats/checked.h"
#include "host/formats/guard.h"
#include "host/formats/plist.h"
#include "host/formats/volume_data.h"
#include "host/kinds/grid.h"
#include "host/formats/hdf5_io.h"

#if LC_HAVE_HDF5
/* A grid dataset's value type: uint8, int16 and uint16 as they are, other
 * numbers as float32 (*mem: the memory type libhdf5 converts to). */
static lc_value_type grid_type(const lci_h5_dinfo *di, hid_t *mem)
{
    *mem = H5T_NATIVE_FLOAT;
    if (di->cls == H5T_INTEGER && di->size == 1 && !di->is_signed) return *mem = H5T_NATIVE_UCHAR, LC_VALUE_UINT8;
    if (di->cls == H5T_INTEGER && di->size == 2)
        return *mem = di->is_signed ? H5T_NATIVE_SHORT : H5T_NATIVE_USHORT, di->is_signed ? LC_VALUE_INT16 : LC_VALUE_UINT16;
    return LC_VALUE_FLOAT32;
}

static lc_status read_dataset(lc_device *dev, const lci_read_args *a, hid_t f, lci_h5_opts *o, lci_loaded *out)
{
    const char *path = a->path, *name = o->dataset;
    if (!lci_h5_exists(f, name) && strcmp(name, "/"))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: option dataset = '%s': no such object", path, name);
    hid_t ds = H5Dopen2(f, name, H5P_DEFAULT);
    if (ds < 0) return lci_error(dev, LC_ERROR_FORMAT, "%s: %s: not a dataset (%s)", path, name, lci_h5_why());
    lci_h5_dinfo di;
    lc_status s = lci_h5_dataset_info(dev, path, name, ds, &di);
    void *data = NULL;
    if (s == LC_OK && di.rank == 2 && di.dims[1] == 3) { /* particle positions */
        lci_plist p;
        memset(&p, 0, sizeof p);
        int64_t n = (int64_t)di.dims[0];
        if (n < 1 || n > LCI_H5_MAX_PARTICLES) s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: %lld positions, expected 1 to 2^31", path, name, di.where, (long long)n);
        else if (lci_plist_reserve(&p, (size_t)n)) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
        if (s == LC_OK) s = lci_h5_read_floats(dev, path, name, ds, &di, p.xyz, 3 * (size_t)n);
        if (s == LC_OK) s = lci_h5_fill_radii(dev, path, o, p.xyz, n, p.r, 0);
        if (s == LC_OK) {
            memset(p.f, 0, (size_t)n);
            p.n = (size_t)lci_h5_select_range(&o->sel, &p, 0, n, 0, -1, NULL);
        }
        H5Dclose(ds);
        return lci_plist_finish(dev, path, s, &p, 1, 0, out);
    }
    if (s == LC_OK && o->sel.sel)
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: select applies to particles, but %s is a grid", path, name);
    if (s == LC_OK && di.rank != 3)
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: rank %d, expected a 3-D dataset (a grid) or N x 3 (positions)", path,
                      name, di.where, di.rank);
    for (int k = 0; s == LC_OK && k < 3; k++)
        if (di.dims[k] < 2 || di.dims[k] > INT32_MAX)
            s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: shape %llu x %llu x %llu: each must be 2 or more", path, name,
                          di.where, (unsigned long long)di.dims[0], (unsigned long long)di.dims[1],
                          (unsigned long long)di.dims[2]);
    uint64_t count = (uint64_t)di.dims[0] * di.dims[1] * di.dims[2];
    if (s == LC_OK && (di.dims[1] * di.dims[2] > INT32_MAX || count > INT32_MAX - 64))
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: more than 2^31 values", path, name, di.where);
    hid_t mem;
    lc_value_type t = grid_type(&di, &mem);
    lci_vol_opts vo;
    if (s == LC_OK) s = lci_vol_options(dev, a, &vo);
    if (s == LC_OK && vo.type != LC_VALUE_DEFAULT && vo.type != t)
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: %s: the dataset's type differs from the requested one", path, name);
    int es = lci_value_size(t);
    if (s == LC_OK && !(data = malloc(count * (uint64_t)es + 64)))
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %llu values", path, (unsigned long long)count);
    if (s == LC_OK && t == LC_VALUE_FLOAT32) s = lci_h5_read_floats(dev, path, name, ds, &di, data, (size_t)count);
    else if (s == LC_OK && H5Dread(ds, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: libhdf5 cannot read it (%s)", path, name, di.where, lci_h5_why());
    if (s == LC_OK && t == LC_VALUE_FLOAT32 && !(di.cls == H5T_FLOAT && di.size == 4))
        lci_log(dev, LC_LOG_INFO, "%s: %s: %s of %zu bytes read as float32", path, name,
                di.cls == H5T_FLOAT ? "floats" : "integers", di.size);
    H5Dclose(ds);
    lc_grid_desc *d = s == LC_OK ? calloc(1, sizeof *d) : NULL;
    if (s == LC_OK && !d) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    if (s != LC_OK) {
        free(data);
        return s;
    }
    for (int k = 0; k < 3; k++) d->size[k] = (int)di.dims[2 - k];
    d->type = t;
    d->spacing = vo.spacing;
    d->origin = vo.origin;
    d->data = data;
    out->desc = d;
    lci_loaded_keep(out, data);
    return LC_OK;
}

static lc_status hdf5_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    lci_h5_opts o;
    lc_status s = lci_h5_parse_opts(dev, a, &o);
    if (s != LC_OK) return s;
    lci_h5_quiet q;
    lci_h5_quiet_on(&q);
    hid_t f;
    if ((s = lci_psel_open(dev, a, &o.sel)) == LC_OK && (s = lci_h5_open(dev, a->path, &f)) == LC_OK) {
        o.sel.gives = o.dataset ? "index (a positions dataset has no types)" : "index and type (0 to 5)";
        o.share = lci_read_share(dev);
        if (o.share && o.dataset) o.share->whole = "a positions dataset (dataset = PATH): k-nearest-neighbour radii";
        s = o.dataset ? read_dataset(dev, a, f, &o, out) : lci_h5_read_snapshot(dev, a->path, f, &o, out);
        H5Fclose(f);
    }
    lci_h5_quiet_off(&q);
    if (o.sel.sel) { /* after the descriptor was made: a failed check frees it */
        /* a share that needs the whole set read no rows: rank 0's whole read checks what the selection kept */
        size_t kept = s != LC_OK ? 0 : o.share && o.share->whole ? 1 : ((lc_particles_desc *)out->desc)->count;
        lc_status c = lci_psel_close(dev, a, &o.sel, kept, s);
        if (c != LC_OK && s == LC_OK) lci_loaded_free(out);
        s = c;
    }
    return s;
}

static herr_t list_names(hid_t g, const char *name, const H5L_info_t *info, void *user)
{
    (void)g, (void)info;
    char *b = user;
    size_t n = strlen(b);
    if (n < 200) snprintf(b + n, 256 - n, "%s%s", n ? ", " : "", name);
    return 0;
}

static lc_status hdf5_kind(lc_device *dev, const char *path, const lc_load_desc *desc, lc_kind *out)
{
    const char *dataset = NULL;
    for (int i = 0; i < desc->noptions; i++)
        if (desc->options[i].key && !strcmp(desc->options[i].key, "dataset")) dataset = desc->options[i].value;
    lci_h5_quiet q;
    lci_h5_quiet_on(&q);
    hid_t f;
    lc_status s = lci_h5_open(dev, path, &f);
    if (s != LC_OK) {
        lci_h5_quiet_off(&q);
        return s;
    }
    if (dataset) {
        hid_t ds = lci_h5_exists(f, dataset) ? H5Dopen2(f, dataset, H5P_DEFAULT) : -1;
        lci_h5_dinfo di;
        if (ds < 0) s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: option dataset = '%s': no such dataset", path, dataset);
        else s = lci_h5_dataset_info(dev, path, dataset, ds, &di);
        if (s == LC_OK) {
            if (di.rank == 3) *out = LC_KIND_GRID;
            else if (di.rank == 2 && di.dims[1] == 3) *out = LC_KIND_PARTICLES;
            else
                s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: rank %d, expected a 3-D dataset (a grid) or N x 3 (positions)",
                              path, dataset, di.where, di.rank);
        }
        if (ds >= 0) H5Dclose(ds);
    } else {
        int parts = 0;
        for (int t = 0; t < 6; t++) {
            char g[16];
            snprintf(g, sizeof g, "PartType%d", t);
            parts |= lci_h5_exists(f, g);
        }
        if (parts) *out = LC_KIND_PARTICLES;
        else {
            char names[256] = "";
            H5Literate(f, H5_INDEX_NAME, H5_ITER_INC, NULL, list_names, names);
            s = lci_error(dev, LC_ERROR_FORMAT,
                          "%s: no PartType0..5 groups (a GADGET/AREPO/SWIFT snapshot); name a dataset with the option "
                          "dataset = PATH (top level: %s)", path, names[0] ? names : "empty");
        }
    }
    H5Fclose(f);
    lci_h5_quiet_off(&q);
    return s;
}

/* The guard process (guard.c): libhdf5 runs on the file in a child first;
 * LANECAST_HDF5_GUARD=0 turns it off (the fuzz harness does, to see the
 * library's faults itself). */
typedef struct gctx {
    const char *path;
    const lc_load_desc *desc;
    const lci_read_args *args; /* NULL: the kind probe */
} gctx;

static lc_status guard_child(lc_device *dev, void *ctx)
{
    const gctx *g = ctx;
    lc_kind k;
    lci_loaded l;
    memset(&l, 0, sizeof l);
    return g->args ? hdf5_read(dev, g->args, &l) : hdf5_kind(dev, g->path, g->desc, &k);
}

/* The guard child's memory: the load's limit (max_memory, default 3/4 of
 * RAM), and at most 64 times the file plus 512 MB (compressed datasets
 * inflate; a damaged file must not make libhdf5 fill the machine first). */
static uint64_t guard_limit(lc_device *dev, const char *path)
{
    uint64_t lim = lci_memory_limit(dev);
    struct stat st;
    if (stat(path, &st) == 0 && st.st_size >= 0) {
        uint64_t f = (uint64_t)st.st_size;
        uint64_t cap = f > (UINT64_MAX >> 8) ? UINT64_MAX : 64 * f + ((uint64_t)512 << 20);
        lim = cap < lim ? cap : lim;
    }
    return lim;
}

static lc_status guard_run(lc_device *dev, const char *path, lc_status (*fn)(lc_device *dev, void *ctx), void *ctx)
{
    lc_status cs;
    char msg[LCI_MSG_MAX];
    int sig = lci_guarded(dev, "LANECAST_HDF5_GUARD", guard_limit(dev, path), fn, ctx, &cs, msg, sizeof msg);
    if (sig < 0) return LC_OK;
    if (sig == 0) return cs == LC_OK ? LC_OK : lci_error(dev, cs, "%s", msg);
    if (sig == SIGINT || sig == SIGTERM || sig == SIGHUP)
        return lci_error(dev, LC_ERROR_IO, "%s: reading stopped by signal %d", path, sig);
    if (sig == SIGKILL) /* the kernel's OOM killer, or someone's kill -9 */
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY,
                         "%s: libhdf5 was killed (signal 9) in lanecast's guard process, most likely out of memory: "
                         "the file is damaged or needs more memory than this machine has", path);
    return lci_error(dev, LC_ERROR_FORMAT,
                     "%s: libhdf5 crashed on this file (signal %d: %s) in lanecast's guard process: the file is damaged "
                     "(libhdf5 1.10 trusts the sizes and layouts a file declares)", path, sig, strsignal(sig));
}

static lc_status guard(lc_device *dev, const char *path, const lc_load_desc *desc, const lci_read_args *args)
{
    gctx g = {path, desc, args};
    return guard_run(dev, path, guard_child, &g);
}

/* A file libhdf5 reads cleanly in the guard is read again here; one it
 * fails on gets the guard's message without a second run. */
static lc_status hdf5_read_guarded(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    lc_status s = guard(dev, a->path, NULL, a);
    return s != LC_OK ? s : hdf5_read(dev, a, out);
}

static lc_status hdf5_kind_guarded(lc_device *dev, const char *path, const lc_load_desc *desc, lc_kind *out)
{
    lc_status s = guard(dev, path, desc, NULL);
    return s != LC_OK ? s : hdf5_kind(dev, path, desc, out);
}
/* lanecast info: a snapshot's PartTypeN datasets (the names value = takes). */
static lc_status hdf5_describe(lc_device *dev, const lci_read_args *a, char *text, size_t size)
{
    text[0] = 0;
    lc_status s = guard(dev, a->path, a->desc, NULL);
    if (s != LC_OK || lci_option_find(a, "dataset")) return s;
    lci_h5_quiet q;
    lci_h5_quiet_on(&q);
    hid_t f;
    if ((s = lci_h5_open(dev, a->path, &f)) == LC_OK) {
        s = lci_h5_describe_snapshot(dev, a->path, f, text, size);
        H5Fclose(f);
    }
    lci_h5_quiet_off(&q);
    return s;
}
/* ---------------------------------------------------------------- grids by hyperslab */

/* A grid dataset's box for lci_hdf5_read_box, or its metadata alone (out NULL). */
typedef struct h5box {
    const char *path, *dataset;
    lc_value_type t;
    const int64_t *start, *count; /* x, y, z: the dataset's dimensions 2, 1, 0 */
    void *out;
    lci_h5_dinfo di; /* found */
    int chunked;
} h5box;

static lc_status box_run(lc_device *dev, h5box *b)
{
    const char *path = b->path, *name = b->dataset;
    lci_h5_quiet q;
    lci_h5_quiet_on(&q);
    hid_t f, ds = -1, fs = -1, ms = -1, pl = -1;
    lc_status s = lci_h5_open(dev, path, &f);
    if (s != LC_OK) {
        lci_h5_quiet_off(&q);
        return s;
    }
    if (!lci_h5_exists(f, name)) s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: option dataset = '%s': no such object", path, name);
    else if ((ds = H5Dopen2(f, name, H5P_DEFAULT)) < 0)
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s: not a dataset (%s)", path, name, lci_h5_why());
    if (s == LC_OK) s = lci_h5_dataset_info(dev, path, name, ds, &b->di);
    const lci_h5_dinfo *di = &b->di;
    if (s == LC_OK && di->rank != 3)
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: rank %d, expected a 3-D dataset (a grid)", path, name, di->where,
                      di->rank);
    for (int k = 0; s == LC_OK && k < 3; k++)
        if (di->dims[k] < 2 || di->dims[k] > INT32_MAX)
            s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: shape %llu x %llu x %llu: each must be 2 or more", path, name,
                          di->where, (unsigned long long)di->dims[0], (unsigned long long)di->dims[1],
                          (unsigned long long)di->dims[2]);
    if (s == LC_OK) {
        pl = H5Dget_create_plist(ds);
        b->chunked = pl < 0 || H5Pget_layout(pl) != H5D_CONTIGUOUS;
    }
    if (s == LC_OK && b->out) {
        hsize_t st[3], ct[3];
        hid_t mem;
        for (int k = 0; k < 3; k++) st[k] = (hsize_t)b->start[2 - k], ct[k] = (hsize_t)b->count[2 - k];
        for (int k = 0; s == LC_OK && k < 3; k++)
            if (st[k] + ct[k] > di->dims[k] || ct[k] == 0)
                s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: nodes %llu + %llu of dimension %d are past its %llu (the "
                              "file changed?)", path, name, di->where, (unsigned long long)st[k], (unsigned long long)ct[k],
                              k, (unsigned long long)di->dims[k]);
        if (s == LC_OK && grid_type(di, &mem) != b->t)
            s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: the value type changed while reading", path, name, di->where);
        if (s == LC_OK) fs = H5Dget_space(ds), ms = H5Screate_simple(3, ct, NULL);
        if (s == LC_OK && (fs < 0 || ms < 0 || H5Sselect_hyperslab(fs, H5S_SELECT_SET, st, NULL, ct, NULL) < 0 ||
                           H5Dread(ds, mem, ms, fs, H5P_DEFAULT, b->out) < 0))
            s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: libhdf5 cannot read the hyperslab %llu+%llu, %llu+%llu, "
                          "%llu+%llu (%s)", path, name, di->where, (unsigned long long)st[0], (unsigned long long)ct[0],
                          (unsigned long long)st[1], (unsigned long long)ct[1], (unsigned long long)st[2],
                          (unsigned long long)ct[2], lci_h5_why());
    }
    if (ms >= 0) H5Sclose(ms);
    if (fs >= 0) H5Sclose(fs);
    if (pl >= 0) H5Pclose(pl);
    if (ds >= 0) H5Dclose(ds);
    H5Fclose(f);
    lci_h5_quiet_off(&q);
    return s;
}

/* The guard child of a box: the metadata alone, or (chunked) the box read
 * into memory of its own too, as libhdf5 walks the chunk index as it reads. */
static lc_status box_child(lc_device *dev, void *ctx)
{
    h5box b = *(const h5box *)ctx;
    if (!b.out) return box_run(dev, &b);
    uint64_t n = (uint64_t)b.count[0] * (uint64_t)b.count[1] * (uint64_t)b.count[2];
    b.out = malloc(n * (uint64_t)lci_value_size(b.t) + 1);
    if (!b.out) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %llu values", b.path, (unsigned long long)n);
    return box_run(dev, &b);
}

lc_status lci_hdf5_grid_layout(lc_device *dev, const lci_read_args *a, const lci_vol_opts *o, lci_vol_layout *l)
{
    const lc_option *d = lci_option_find(a, "dataset");
    if (!d || !d->value) return lci_error(dev, LC_ERROR_UNSUPPORTED, "%s: an HDF5 file without dataset = PATH", a->path);
    memset(l, 0, sizeof *l);
    if (strlen(d->value) >= sizeof l->dataset || strlen(a->path) >= sizeof l->data_path)
        return lci_error(dev, LC_ERROR_UNSUPPORTED, "%s: a path too long to read by parts", a->path);
    h5box b = {a->path, d->value, LC_VALUE_DEFAULT, NULL, NULL, NULL, {0}, 0};
    lc_status s = guard_run(dev, a->path, box_child, &b);
    if (s == LC_OK) s = box_run(dev, &b);
    if (s != LC_OK) return s;
    hid_t mem;
    lc_value_type t = grid_type(&b.di, &mem);
    if (o->type != LC_VALUE_DEFAULT && o->type != t)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: %s: the dataset's type differs from the requested one", a->path,
                         d->value);
    snprintf(l->data_path, sizeof l->data_path, "%s", a->path);
    snprintf(l->dataset, sizeof l->dataset, "%s", d->value);
    l->chunked = b.chunked;
    for (int k = 0; k < 3; k++) l->fsize[k] = (int64_t)b.di.dims[2 - k], l->perm[k] = k;
    /* read_dataset's desc: the options' spacing and origin (zero: the defaults) */
    lc_grid_desc *g = &l->grid;
    for (int k = 0; k < 3; k++) g->size[k] = (int)l->fsize[k];
    g->type = l->type = t;
    g->spacing = o->spacing, g->origin = o->origin;
    return LC_OK;
}

lc_status lci_hdf5_read_box(lc_device *dev, const lci_vol_layout *l, const int64_t start[3], const int64_t count[3],
                            void *out)
{
    h5box b = {l->data_path, l->dataset, l->type, start, count, NULL, {0}, 0};
    lc_status s = LC_OK;
    if (l->chunked) {
        b.out = out; /* box_child reads into memory of its own */
        s = guard_run(dev, l->data_path, box_child, &b);
    }
    b.out = out;
    return s == LC_OK ? box_run(dev, &b) : s;
}
#define HDF5_READ hdf5_read_guarded
#define HDF5_KIND hdf5_kind_guarded
#define HDF5_DESCRIBE hdf5_describe
#else
lc_status lci_hdf5_grid_layout(lc_device *dev, const lci_read_args *a, const lci_vol_opts *o, lci_vol_layout *l)
{
    (void)o, (void)l;
    return lci_error(dev, LC_ERROR_UNSUPPORTED, "%s: HDF5 grids are read whole (no libhdf5)", a->path);
}

lc_status lci_hdf5_read_box(lc_device *dev, const lci_vol_layout *l, const int64_t start[3], const int64_t count[3],
                            void *out)
{
    (void)start, (void)count, (void)out;
    return lci_error(dev, LC_ERROR_UNSUPPORTED, "%s: no libhdf5", l->data_path);
}
#define HDF5_READ NULL
#define HDF5_KIND NULL
#define HDF5_DESCRIBE NULL
#endif

static int hdf5_magic(const unsigned char *h, size_t n)
{
    static const unsigned char sig[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
    return (n >= 8 && !memcmp(h, sig, 8)) || (n >= 520 && !memcmp(h + 512, sig, 8));
}

const lci_format lci_format_hdf5 = {
    .name = "hdf5", .kind = LC_KIND_NONE, .extensions = ".hdf5 .h5 .he5",
    .options = "dataset types value knn radius radius_scale fields spacing origin type select kernel hsml_is normalise",
    .description = "HDF5: GADGET/AREPO/SWIFT PartTypeN snapshots (types as fields, value = none|mass|u|rho|hsml or any "
                   "dataset: NAME, NAME:K, |NAME|), or dataset = PATH: 3-D as a grid, N x 3 as particles",
    .magic = hdf5_magic, .read = HDF5_READ, .package = "libhdf5-dev", .kind_of = HDF5_KIND,
    .describe = HDF5_DESCRIBE, .shares = 1};
