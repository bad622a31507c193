/* HDF5 files through libhdf5: a container whose kind the file (and the
 * load request) tells (lci_format.kind_of).
 *
 * Particle snapshots in the GADGET-3 / AREPO / SWIFT layout: groups
 * PartType0..5 with Coordinates (N x 3), and when present Masses (else the
 * /Header attribute MassTable), SmoothingLength(s), Density/Densities,
 * InternalEnergy/InternalEnergies. Options as the GADGET reader's: types,
 * fields = type|none, value = none|mass|u|rho|hsml, radius, radius_scale,
 * knn (radius = SmoothingLength when the type has it, else the distance to
 * the knn-th neighbour). `select` (select.h): index over the file's
 * particles (PartType0 first) and type (the N of PartTypeN); a selected
 * particle keeps the radius found among all of its type's particles.
 * SPH (host/sph/sph_load.h): radii are lanecast's support radius H. GADGET-3
 * and AREPO's SmoothingLength is H; SWIFT's SmoothingLengths (its spelling,
 * or a /HydroScheme group) are h, converted to H = gamma h with the gamma of
 * the kernel rendered, else of the /HydroScheme "Kernel function" the file
 * records, else the cubic spline's; `hsml_is = h|H` overrides. With an SPH
 * kernel and a value A, k_i = m_i / rho_i A_i (Masses or MassTable,
 * Density/Densities; groups without densities are skipped unless named).
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
#include "host/sph/sph_kernel.h"
#include "host/sph/sph_load.h"

#if LC_HAVE_HDF5
#include <hdf5.h>

#define MAX_PARTICLES ((int64_t)1 << 31)

/* libhdf5's automatic error printing off while reading, and back after. */
typedef struct quiet {
    H5E_auto2_t fn;
    void *data;
} quiet;
static void quiet_on(quiet *q)
{
    H5Eget_auto2(H5E_DEFAULT, &q->fn, &q->data);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
}
static void quiet_off(const quiet *q) { H5Eset_auto2(H5E_DEFAULT, q->fn, q->data); }

static herr_t innermost(unsigned n, const H5E_error2_t *e, void *user)
{
    if (n == 0 && e->desc) snprintf(user, 200, "%s", e->desc);
    return 0;
}

/* The deepest message on HDF5's error stack, or "". */
static const char *h5_why(void)
{
    static _Thread_local char buf[200];
    buf[0] = 0;
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, innermost, buf);
    return buf;
}

/* Opens path read-only after finding its signature (at 0, 512, 1024, ...). */
static lc_status h5_open(lc_device *dev, const char *path, hid_t *out)
{
    static const unsigned char sig[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
    FILE *f = fopen(path, "rb");
    if (!f) return lci_error(dev, LC_ERROR_IO, "%s: cannot open", path);
    long long at = -1;
    unsigned char b[8];
    for (long long o = 0; o <= (1LL << 40) && at < 0; o = o ? 2 * o : 512) {
        if (fseeko(f, o, SEEK_SET) || fread(b, 1, 8, f) != 8) break;
        if (!memcmp(b, sig, 8)) at = o;
    }
    fclose(f);
    if (at < 0) return lci_error(dev, LC_ERROR_FORMAT, "%s: byte 0: not an HDF5 file (no \\211HDF signature at byte 0, 512, 1024, ...)", path);
    *out = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    if (*out < 0)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: byte %lld: libhdf5 cannot open it (%s): truncated or damaged", path, at,
                         h5_why());
    return LC_OK;
}

static int exists(hid_t loc, const char *name) { return H5Lexists(loc, name, H5P_DEFAULT) > 0; }

/* Whether libhdf5 can convert numbers of type ty to native ones safely. Its
 * converters trust the bit layout a file declares: a float whose exponent
 * or mantissa is wider than 64 bits, or fields outside the type's bytes,
 * overrun fixed buffers inside libhdf5 1.10 (a fuzzed GADGET snapshot
 * smashed the stack in H5T__bit_get_d). So every dataset and attribute is
 * checked here before it is read: integers and floats of 1, 2, 4 or 8 bytes
 * whose declared fields lie inside those bytes, exponents of at most 16
 * bits and mantissas of at most 64. why gets the reason. */
static int type_sane(hid_t ty, char *why, size_t n)
{
    H5T_class_t cls = H5Tget_class(ty);
    size_t size = H5Tget_size(ty), prec = H5Tget_precision(ty);
    int off = H5Tget_offset(ty);
    if (cls != H5T_INTEGER && cls != H5T_FLOAT) {
        snprintf(why, n, "not a number (HDF5 class %d)", (int)cls);
        return 0;
    }
    if (size != 1 && size != 2 && size != 4 && size != 8) {
        snprintf(why, n, "numbers of %zu bytes, expected 1, 2, 4 or 8", size);
        return 0;
    }
    if (off < 0 || prec < 1 || (size_t)off + prec > 8 * size) {
        snprintf(why, n, "a number type with %zu bits at bit offset %d in %zu bytes", prec, off, size);
        return 0;
    }
    if (cls == H5T_FLOAT) {
        size_t spos, epos, esize, mpos, msize;
        if (size == 1 || H5Tget_fields(ty, &spos, &epos, &esize, &mpos, &msize) < 0 || esize < 1 || esize > 16 ||
            msize < 1 || msize > 64 || spos >= 8 * size || epos + esize > 8 * size || mpos + msize > 8 * size) {
            snprintf(why, n, "a floating-point type with a damaged bit layout (%zu bytes)", size);
            return 0;
        }
    }
    return 1;
}

/* A dataset's shape (rank <= 3) and its place for messages ("byte N" of a contiguous one). */
typedef struct dinfo {
    int rank;
    hsize_t dims[3];
    H5T_class_t cls;
    size_t size;
    int is_signed;
    char where[64];
} dinfo;

static lc_status dataset_info(lc_device *dev, const char *path, const char *name, hid_t ds, dinfo *d)
{
    memset(d, 0, sizeof *d);
    hid_t sp = H5Dget_space(ds), ty = H5Dget_type(ds);
    int rank = sp >= 0 ? H5Sget_simple_extent_ndims(sp) : -1;
    if (rank >= 0 && rank <= 3) H5Sget_simple_extent_dims(sp, d->dims, NULL);
    d->rank = rank;
    d->cls = ty >= 0 ? H5Tget_class(ty) : H5T_NO_CLASS;
    d->size = ty >= 0 ? H5Tget_size(ty) : 0;
    d->is_signed = d->cls == H5T_INTEGER && H5Tget_sign(ty) == H5T_SGN_2;
    char why[96] = "";
    int sane = ty >= 0 && type_sane(ty, why, sizeof why);
    haddr_t addr = H5Dget_offset(ds);
    if (addr != HADDR_UNDEF) snprintf(d->where, sizeof d->where, " (byte %llu)", (unsigned long long)addr);
    if (sp >= 0) H5Sclose(sp);
    if (ty >= 0) H5Tclose(ty);
    if (rank < 0 || rank > 3)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: a dataset of rank %d, expected 1 to 3", path, name, d->where, rank);
    if (d->cls != H5T_INTEGER && d->cls != H5T_FLOAT)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: not a dataset of numbers (HDF5 class %d)", path, name, d->where,
                         (int)d->cls);
    if (!sane) return lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: %s", path, name, d->where, why);
    /* a contiguous dataset's bytes must be in the file */
    if (addr != HADDR_UNDEF) {
        hsize_t need = d->size;
        for (int k = 0; k < rank; k++) need *= d->dims[k];
        hid_t f = H5Iget_file_id(ds);
        hsize_t fsize = 0;
        if (f >= 0) H5Fget_filesize(f, &fsize), H5Fclose(f);
        if (fsize && addr + need > fsize)
            return lci_error(dev, LC_ERROR_FORMAT, "%s: %s (byte %llu): its %llu bytes run past the end of the %llu-byte file",
                             path, name, (unsigned long long)addr, (unsigned long long)need, (unsigned long long)fsize);
    }
    return LC_OK;
}

/* Reads all of ds as floats into out (n values), checking they are finite. */
static lc_status read_floats(lc_device *dev, const char *path, const char *name, hid_t ds, const dinfo *di, float *out,
                             size_t n)
{
    if (H5Dread(ds, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) < 0)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: libhdf5 cannot read it (%s)", path, name, di->where, h5_why());
    for (size_t i = 0; i < n; i++)
        if (!isfinite(out[i]))
            return lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: value %zu is not finite", path, name, di->where, i);
    return LC_OK;
}

/* One per-particle dataset of group g (the first of names that exists): 1-D
 * of n values (or n x 1). *found = 0 when none exists. */
static lc_status per_particle(lc_device *dev, const char *path, hid_t g, int type, const char *const *names, int64_t n,
                              float *out, int *found)
{
    *found = 0;
    for (; *names; names++) {
        if (!exists(g, *names)) continue;
        char name[96];
        snprintf(name, sizeof name, "/PartType%d/%s", type, *names);
        hid_t ds = H5Dopen2(g, *names, H5P_DEFAULT);
        if (ds < 0) return lci_error(dev, LC_ERROR_FORMAT, "%s: %s: not a dataset (%s)", path, name, h5_why());
        dinfo di;
        lc_status s = dataset_info(dev, path, name, ds, &di);
        if (s == LC_OK && !((di.rank == 1 || (di.rank == 2 && di.dims[1] == 1)) && (int64_t)di.dims[0] == n))
            s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: shape %llu%s, expected %lld values (one per particle of "
                          "Coordinates)", path, name, di.where, (unsigned long long)di.dims[0],
                          di.rank == 2 ? " x N" : di.rank == 3 ? " x N x M" : "", (long long)n);
        if (s == LC_OK) s = read_floats(dev, path, name, ds, &di, out, (size_t)n);
        H5Dclose(ds);
        *found = s == LC_OK;
        return s;
    }
    return LC_OK;
}

/* The /Header attribute name of 1 to n numbers as doubles into v[n] (the
 * rest 0): 1 when read, 0 when absent, -1 (with why) when present but empty,
 * longer than n or of a type libhdf5 does not convert safely. (SWIFT writes
 * 7 types where GADGET writes 6.) */
static int header_attr(hid_t f, const char *name, double *v, hssize_t n, char *why, size_t wn)
{
    if (!exists(f, "Header") || H5Aexists_by_name(f, "Header", name, H5P_DEFAULT) <= 0) return 0;
    hid_t a = H5Aopen_by_name(f, "Header", name, H5P_DEFAULT, H5P_DEFAULT);
    if (a < 0) {
        snprintf(why, wn, "libhdf5 cannot open it (%s)", h5_why());
        return -1;
    }
    hid_t sp = H5Aget_space(a), ty = H5Aget_type(a);
    hssize_t got = sp >= 0 ? H5Sget_simple_extent_npoints(sp) : -1;
    int ok = ty >= 0 && type_sane(ty, why, wn);
    if (ok && (got < 1 || got > n)) snprintf(why, wn, "%lld values, expected 1 to %lld", (long long)got, (long long)n), ok = 0;
    for (hssize_t i = 0; i < n; i++) v[i] = 0.0;
    if (ok && H5Aread(a, H5T_NATIVE_DOUBLE, v) < 0) snprintf(why, wn, "libhdf5 cannot read it (%s)", h5_why()), ok = 0;
    if (sp >= 0) H5Sclose(sp);
    if (ty >= 0) H5Tclose(ty);
    H5Aclose(a);
    return ok ? 1 : -1;
}

enum { V_NONE, V_MASS, V_U, V_RHO, V_HSML };
static const char *const vnames[] = {"none", "mass", "u", "rho", "hsml"};
static const char *const mass_names[] = {"Masses", NULL};
static const char *const u_names[] = {"InternalEnergy", "InternalEnergies", NULL};
static const char *const rho_names[] = {"Density", "Densities", NULL};
static const char *const hsml_names[] = {"SmoothingLength", "SmoothingLengths", NULL};
static const char *const *const vdatasets[] = {NULL, mass_names, u_names, rho_names, hsml_names};

typedef struct hopts {
    int types[6], types_given, by_type, value, knn;
    float radius, radius_scale;
    const char *dataset;
    lci_psel sel; /* select: index over the file's particles (type order), type = the PartType number */
    lci_sph_opts sph;
} hopts;

/* Keeps the particles [base, base + n) of p that the selection takes
 * (index first + i, type t; t < 0: no type); returns how many. */
static int64_t select_range(lci_psel *ps, lci_plist *p, size_t base, int64_t n, size_t first, int t)
{
    if (!ps->sel) return n;
    char ty[2] = {(char)('0' + t), 0};
    lci_atom_attr attr = {.type = t >= 0 ? ty : NULL};
    size_t w = base;
    for (int64_t i = 0; i < n; i++) {
        size_t q = base + (size_t)i;
        if (!lci_psel_keep(ps, first + (size_t)i, NULL, &attr)) continue;
        memmove(p->xyz + 3 * w, p->xyz + 3 * q, 3 * sizeof(float));
        p->r[w] = p->r[q], p->v[w] = p->v[q], p->f[w] = p->f[q];
        w++;
    }
    return (int64_t)(w - base);
}

static lc_status parse_opts(lc_device *dev, const lci_read_args *a, hopts *o)
{
    memset(o, 0, sizeof *o);
    o->by_type = 1;
    o->knn = 32;
    const lc_option *x;
    lc_status s = LC_OK;
    if ((x = lci_option_find(a, "dataset"))) o->dataset = x->value;
    if ((x = lci_option_find(a, "radius"))) s = lci_option_float(dev, a->path, x, 1e-30f, 1e30f, &o->radius);
    if (s == LC_OK && (x = lci_option_find(a, "radius_scale")))
        s = lci_option_float(dev, a->path, x, 1e-30f, 1e30f, &o->radius_scale);
    if (s == LC_OK && (x = lci_option_find(a, "knn"))) s = lci_option_int(dev, a->path, x, 1, 1024, &o->knn);
    if (s == LC_OK && (x = lci_option_find(a, "fields"))) {
        if (!strcmp(x->value, "none")) o->by_type = 0;
        else if (strcmp(x->value, "type"))
            s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: option fields = '%s', expected type or none", a->path, x->value);
    }
    if (s == LC_OK && (x = lci_option_find(a, "value"))) {
        o->value = -1;
        for (int i = 0; i < 5; i++)
            if (!strcmp(x->value, vnames[i])) o->value = i;
        if (o->value < 0)
            s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: option value = '%s', expected none, mass, u, rho or hsml",
                          a->path, x->value);
    }
    if (s == LC_OK && (x = lci_option_find(a, "types"))) {
        o->types_given = 1;
        for (const char *p = x->value;; p += 2) {
            if (*p < '0' || *p > '5' || (p[1] && p[1] != ',')) {
                s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                              "%s: option types = '%s': expected particle types 0 to 5, comma-separated", a->path, x->value);
                break;
            }
            o->types[*p - '0'] = 1;
            if (!p[1]) break;
        }
    }
    if (!o->types_given)
        for (int t = 0; t < 6; t++) o->types[t] = 1;
    if (s == LC_OK) s = lci_sph_opts_parse(dev, a, &o->sph);
    return s;
}

/* The SPH kernel a SWIFT snapshot records (/HydroScheme attribute "Kernel
 * function", a fixed-length string such as "Wendland C2" or "Cubic spline
 * (M4)"), or LC_KERNEL_GAUSSIAN when it records none this reader knows. */
static lc_kernel file_kernel(hid_t f)
{
    static const char *const names[][2] = {{"(M4)", "m4"}, {"(M5)", "m5"}, {"(M6)", "m6"},
                                           {"Wendland C2", "wendland-c2"}, {"Wendland C4", "wendland-c4"},
                                           {"Wendland C6", "wendland-c6"}};
    lc_kernel k = LC_KERNEL_GAUSSIAN;
    if (!exists(f, "HydroScheme") || H5Aexists_by_name(f, "HydroScheme", "Kernel function", H5P_DEFAULT) <= 0) return k;
    hid_t a = H5Aopen_by_name(f, "HydroScheme", "Kernel function", H5P_DEFAULT, H5P_DEFAULT);
    hid_t ty = a >= 0 ? H5Aget_type(a) : -1;
    char buf[256] = "";
    if (ty >= 0 && H5Tget_class(ty) == H5T_STRING && !H5Tis_variable_str(ty) && H5Tget_size(ty) < sizeof buf &&
        H5Aread(a, ty, buf) >= 0)
        for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
            if (strstr(buf, names[i][0])) lc_kernel_from_name(names[i][1], &k);
    if (ty >= 0) H5Tclose(ty);
    if (a >= 0) H5Aclose(a);
    return k;
}

/* Radii of n points: radius option, else k-NN, zeros replaced by the smallest. */
static lc_status fill_radii(lc_device *dev, const char *path, const hopts *o, const float *x, int64_t n, float *r, int have)
{
    if (o->radius > 0.0f)
        for (int64_t i = 0; i < n; i++) r[i] = o->radius;
    else if (!have && lci_knn_radii(x, (size_t)n, o->knn, r))
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for the neighbour search", path);
    float rmin = INFINITY;
    for (int64_t i = 0; i < n; i++)
        if (r[i] > 0.0f && r[i] < rmin) rmin = r[i];
    for (int64_t i = 0; i < n; i++) {
        if (!(r[i] > 0.0f)) r[i] = isfinite(rmin) ? rmin : 1.0f;
        if (o->radius_scale > 0.0f) r[i] *= o->radius_scale;
    }
    return LC_OK;
}

static lc_status read_snapshot(lc_device *dev, const char *path, hid_t f, hopts *o, lci_loaded *out)
{
    size_t first = 0; /* the file's particles before this type (the selection's index) */
    lci_plist p;
    memset(&p, 0, sizeof p);
    lc_status s = LC_OK;
    double mtab[16] = {0}, npart[16] = {0};
    char why[96] = "";
    int have_mtab = header_attr(f, "MassTable", mtab, 16, why, sizeof why);
    if (have_mtab < 0) return lci_error(dev, LC_ERROR_FORMAT, "%s: /Header/MassTable: %s", path, why);
    int have_np = header_attr(f, "NumPart_ThisFile", npart, 16, why, sizeof why);
    if (have_np < 0) return lci_error(dev, LC_ERROR_FORMAT, "%s: /Header/NumPart_ThisFile: %s", path, why);
    int nfields = 0, any = 0;
    /* smoothing lengths: h (SWIFT) or H, and the gamma that makes h into H */
    const int weighted = lci_sph_weighted(&o->sph, o->value != V_NONE);
    const int swift = exists(f, "HydroScheme");
    const char *gwhy = "";
    lc_kernel gk = lci_sph_gamma_kernel(&o->sph, file_kernel(f), &gwhy);
    int any_h = 0, any_H = 0; /* groups whose smoothing lengths were read as h, as H */
    for (int t = 0; t < 6 && s == LC_OK; t++) {
        char gname[16], name[96];
        snprintf(gname, sizeof gname, "PartType%d", t);
        if (!o->types[t] || !exists(f, gname)) continue;
        hid_t g = H5Gopen2(f, gname, H5P_DEFAULT);
        if (g < 0) {
            s = lci_error(dev, LC_ERROR_FORMAT, "%s: /%s: not a group (%s)", path, gname, h5_why());
            break;
        }
        snprintf(name, sizeof name, "/%s/Coordinates", gname);
        hid_t ds = exists(g, "Coordinates") ? H5Dopen2(g, "Coordinates", H5P_DEFAULT) : -1;
        dinfo di;
        int64_t n = 0;
        if (ds < 0) s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s: missing (every PartTypeN group needs its positions)", path, name);
        if (s == LC_OK) s = dataset_info(dev, path, name, ds, &di);
        if (s == LC_OK && (di.rank != 2 || di.dims[1] != 3))
            s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: shape %llu x %llu, expected N x 3", path, name, di.where,
                          (unsigned long long)di.dims[0], (unsigned long long)(di.rank == 2 ? di.dims[1] : 0));
        if (s == LC_OK) {
            n = (int64_t)di.dims[0];
            if (n > MAX_PARTICLES - (int64_t)p.n)
                s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s: %lld particles, more than lanecast's 2^31", path, name, (long long)n);
            else if (have_np && npart[t] != (double)n)
                s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s holds %lld particles, /Header NumPart_ThisFile[%d] says %.0f",
                              path, name, di.where, (long long)n, t, npart[t]);
        }
        if (s == LC_OK && n > 0) {
            if (lci_plist_reserve(&p, (size_t)n)) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
            size_t base = p.n;
            float *x = p.xyz + 3 * base, *r = p.r + base, *v = p.v + base;
            if (s == LC_OK) s = read_floats(dev, path, name, ds, &di, x, 3 * (size_t)n);
            int have = 0;
            if (s == LC_OK && !(o->radius > 0.0f)) s = per_particle(dev, path, g, t, hsml_names, n, r, &have);
            if (s == LC_OK && have) { /* SWIFT's spelling (or its /HydroScheme) means h */
                int small = o->sph.hsml_is == LCI_HSML_FILE
                                ? (swift || !exists(g, hsml_names[0]))
                                : o->sph.hsml_is == LCI_HSML_SMALL_H;
                double gamma = small ? lci_sph_kernel_get(gk)->swift_gamma : 1.0;
                for (int64_t i = 0; gamma != 1.0 && i < n; i++) r[i] = (float)(gamma * (double)r[i]);
                any_h |= small, any_H |= !small;
            }
            if (s == LC_OK) s = fill_radii(dev, path, o, x, n, r, have);
            int vfound = 1;
            if (s == LC_OK && o->value != V_NONE) s = per_particle(dev, path, g, t, vdatasets[o->value], n, v, &vfound);
            if (s == LC_OK && o->value == V_MASS && !vfound) {
                if (have_mtab && mtab[t] > 0.0) {
                    for (int64_t i = 0; i < n; i++) v[i] = (float)mtab[t];
                    vfound = 1;
                } else
                    s = lci_error(dev, LC_ERROR_FORMAT, "%s: /%s: value = mass, but there is no Masses dataset and no "
                                  "/Header MassTable entry for type %d", path, gname, t);
            }
            if (s == LC_OK && o->value != V_NONE && !vfound) {
                if (o->types_given)
                    s = lci_error(dev, LC_ERROR_FORMAT, "%s: /%s: value = %s, but the group has no %s dataset", path, gname,
                                  vnames[o->value], vdatasets[o->value][0]);
                else
                    lci_log(dev, LC_LOG_INFO, "%s: /%s skipped: no %s for value = %s", path, gname,
                            vdatasets[o->value][0], vnames[o->value]);
            }
            if (s == LC_OK && vfound && weighted) { /* k_i = m_i / rho_i A_i */
                float *buf = malloc(sizeof(float) * (size_t)n * 2);
                int rf = 0, mf = 0;
                if (!buf) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
                if (s == LC_OK) s = per_particle(dev, path, g, t, rho_names, n, buf, &rf);
                if (s == LC_OK && rf) s = per_particle(dev, path, g, t, mass_names, n, buf + n, &mf);
                if (s == LC_OK && rf && !mf && !(have_mtab && mtab[t] > 0.0))
                    s = lci_error(dev, LC_ERROR_FORMAT, "%s: /%s: value = %s with kernel %s is SPH interpolation (k = m / "
                                  "rho * %s), but there is no Masses dataset and no /Header MassTable entry for type %d",
                                  path, gname, vnames[o->value], lc_kernel_name(o->sph.kernel), vnames[o->value], t);
                if (s == LC_OK && !rf) {
                    vfound = 0;
                    if (o->types_given)
                        s = lci_error(dev, LC_ERROR_FORMAT, "%s: /%s: value = %s with kernel %s is SPH interpolation (k = "
                                      "m / rho * %s), but the group has no Density dataset", path, gname,
                                      vnames[o->value], lc_kernel_name(o->sph.kernel), vnames[o->value]);
                    else
                        lci_log(dev, LC_LOG_INFO, "%s: /%s skipped: no Density for SPH interpolation", path, gname);
                }
                snprintf(name, sizeof name, "/%s/Density", gname);
                if (s == LC_OK && rf)
                    s = lci_sph_weigh(dev, path, name, 0, n, mf ? buf + n : NULL, mtab[t], buf, v);
                free(buf);
            }
            if (s == LC_OK && vfound) {
                if (o->value == V_NONE)
                    for (int64_t i = 0; i < n; i++) v[i] = 1.0f;
                for (int64_t i = 0; i < n; i++) p.f[base + (size_t)i] = (uint8_t)(o->by_type ? nfields : 0);
                int64_t kept = select_range(&o->sel, &p, base, n, first, t);
                if (kept > 0) { /* no field for a type the selection left empty */
                    p.n += (size_t)kept;
                    nfields++;
                    any = 1;
                }
            }
            first += (size_t)n;
        }
        if (ds >= 0) H5Dclose(ds);
        H5Gclose(g);
        lci_load_progress(dev, (t + 1) / 6.0); /* by particle type: libhdf5 reads each dataset in one call */
    }
    if (s == LC_OK && !any && !o->sel.sel) /* with a selection, lci_psel_close says it matched nothing */
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: no particles in the chosen PartTypeN groups%s", path,
                      o->value != V_NONE ? " with that value" : "");
    double nfiles = 0;
    if (s == LC_OK && header_attr(f, "NumFilesPerSnapshot", &nfiles, 1, why, sizeof why) > 0 && nfiles > 1)
        lci_log(dev, LC_LOG_INFO, "%s: one file of a %.0f-file snapshot (its own particles only)", path, nfiles);
    s = lci_plist_finish(dev, path, s, &p, o->by_type ? nfields : 1, o->value != V_NONE, out);
    if (s == LC_OK && (any_h || any_H || weighted)) {
        const char *how = o->sph.hsml_is != LCI_HSML_FILE ? "hsml_is" : swift ? "SWIFT's (/HydroScheme)"
                          : any_h ? "SWIFT's spelling SmoothingLengths" : "GADGET-3/AREPO's SmoothingLength";
        char conv[160];
        if (any_h)
            snprintf(conv, sizeof conv, "H = %.6g h (%s h: gamma of %s, %s)%s", lci_sph_kernel_get(gk)->swift_gamma,
                     how, lc_kernel_name(gk), gwhy, any_H ? "; other groups H as read" : "");
        else if (any_H)
            snprintf(conv, sizeof conv, "H = the smoothing lengths as read (%s: the support radius)", how);
        else
            snprintf(conv, sizeof conv, "radii as read");
        if (weighted)
            lci_sph_note(out, "%s; k = m / rho * %s (SPH interpolation with %s)", conv, vnames[o->value],
                         lc_kernel_name(o->sph.kernel));
        else
            lci_sph_note(out, "%s", conv);
    }
    return s;
}

static lc_status read_dataset(lc_device *dev, const lci_read_args *a, hid_t f, hopts *o, lci_loaded *out)
{
    const char *path = a->path, *name = o->dataset;
    if (!exists(f, name) && strcmp(name, "/"))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: option dataset = '%s': no such object", path, name);
    hid_t ds = H5Dopen2(f, name, H5P_DEFAULT);
    if (ds < 0) return lci_error(dev, LC_ERROR_FORMAT, "%s: %s: not a dataset (%s)", path, name, h5_why());
    dinfo di;
    lc_status s = dataset_info(dev, path, name, ds, &di);
    void *data = NULL;
    if (s == LC_OK && di.rank == 2 && di.dims[1] == 3) { /* particle positions */
        lci_plist p;
        memset(&p, 0, sizeof p);
        int64_t n = (int64_t)di.dims[0];
        if (n < 1 || n > MAX_PARTICLES) s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: %lld positions, expected 1 to 2^31", path, name, di.where, (long long)n);
        else if (lci_plist_reserve(&p, (size_t)n)) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
        if (s == LC_OK) s = read_floats(dev, path, name, ds, &di, p.xyz, 3 * (size_t)n);
        if (s == LC_OK) s = fill_radii(dev, path, o, p.xyz, n, p.r, 0);
        if (s == LC_OK) {
            memset(p.f, 0, (size_t)n);
            p.n = (size_t)select_range(&o->sel, &p, 0, n, 0, -1);
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
    lc_value_type t = LC_VALUE_FLOAT32;
    hid_t mem = H5T_NATIVE_FLOAT;
    if (di.cls == H5T_INTEGER && di.size == 1 && !di.is_signed) t = LC_VALUE_UINT8, mem = H5T_NATIVE_UCHAR;
    else if (di.cls == H5T_INTEGER && di.size == 2) t = di.is_signed ? LC_VALUE_INT16 : LC_VALUE_UINT16,
                                                    mem = di.is_signed ? H5T_NATIVE_SHORT : H5T_NATIVE_USHORT;
    lci_vol_opts vo;
    if (s == LC_OK) s = lci_vol_options(dev, a, &vo);
    if (s == LC_OK && vo.type != LC_VALUE_DEFAULT && vo.type != t)
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: %s: the dataset's type differs from the requested one", path, name);
    int es = lci_value_size(t);
    if (s == LC_OK && !(data = malloc(count * (uint64_t)es + 64)))
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %llu values", path, (unsigned long long)count);
    if (s == LC_OK && t == LC_VALUE_FLOAT32) s = read_floats(dev, path, name, ds, &di, data, (size_t)count);
    else if (s == LC_OK && H5Dread(ds, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: libhdf5 cannot read it (%s)", path, name, di.where, h5_why());
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
    hopts o;
    lc_status s = parse_opts(dev, a, &o);
    if (s != LC_OK) return s;
    quiet q;
    quiet_on(&q);
    hid_t f;
    if ((s = lci_psel_open(dev, a, &o.sel)) == LC_OK && (s = h5_open(dev, a->path, &f)) == LC_OK) {
        o.sel.gives = o.dataset ? "index (a positions dataset has no types)" : "index and type (0 to 5)";
        s = o.dataset ? read_dataset(dev, a, f, &o, out) : read_snapshot(dev, a->path, f, &o, out);
        H5Fclose(f);
    }
    quiet_off(&q);
    if (o.sel.sel) { /* after the descriptor was made: a failed check frees it */
        lc_status c = lci_psel_close(dev, a, &o.sel, s == LC_OK ? ((lc_particles_desc *)out->desc)->count : 0, s);
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
    quiet q;
    quiet_on(&q);
    hid_t f;
    lc_status s = h5_open(dev, path, &f);
    if (s != LC_OK) {
        quiet_off(&q);
        return s;
    }
    if (dataset) {
        hid_t ds = exists(f, dataset) ? H5Dopen2(f, dataset, H5P_DEFAULT) : -1;
        dinfo di;
        if (ds < 0) s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: option dataset = '%s': no such dataset", path, dataset);
        else s = dataset_info(dev, path, dataset, ds, &di);
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
            parts |= exists(f, g);
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
    quiet_off(&q);
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

static lc_status guard(lc_device *dev, const char *path, const lc_load_desc *desc, const lci_read_args *args)
{
    gctx g = {path, desc, args};
    lc_status cs;
    char msg[LCI_MSG_MAX];
    int sig = lci_guarded(dev, "LANECAST_HDF5_GUARD", guard_limit(dev, path), guard_child, &g, &cs, msg, sizeof msg);
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
#define HDF5_READ hdf5_read_guarded
#define HDF5_KIND hdf5_kind_guarded
#else
#define HDF5_READ NULL
#define HDF5_KIND NULL
#endif

static int hdf5_magic(const unsigned char *h, size_t n)
{
    static const unsigned char sig[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
    return (n >= 8 && !memcmp(h, sig, 8)) || (n >= 520 && !memcmp(h + 512, sig, 8));
}

const lci_format lci_format_hdf5 = {
    .name = "hdf5", .kind = LC_KIND_NONE, .extensions = ".hdf5 .h5 .he5",
    .options = "dataset types value knn radius radius_scale fields spacing origin type select kernel hsml_is",
    .description = "HDF5: GADGET/AREPO/SWIFT PartTypeN snapshots (types as fields, value = none|mass|u|rho|hsml), "
                   "or dataset = PATH: 3-D as a grid, N x 3 as particles",
    .magic = hdf5_magic, .read = HDF5_READ, .package = "libhdf5-dev", .kind_of = HDF5_KIND};
