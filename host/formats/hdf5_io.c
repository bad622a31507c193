/* The HDF5 reader's shared parts (hdf5_io.h): libhdf5's calls made safe on
 * damaged files, and the options of the reader. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/checked.h"
#include "host/formats/hdf5_io.h"

#if LC_HAVE_HDF5
void lci_h5_quiet_on(lci_h5_quiet *q)
{
    H5Eget_auto2(H5E_DEFAULT, &q->fn, &q->data);
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
}
void lci_h5_quiet_off(const lci_h5_quiet *q) { H5Eset_auto2(H5E_DEFAULT, q->fn, q->data); }

static herr_t innermost(unsigned n, const H5E_error2_t *e, void *user)
{
    if (n == 0 && e->desc) snprintf(user, 200, "%s", e->desc);
    return 0;
}

/* The deepest message on HDF5's error stack, or "". */
const char *lci_h5_why(void)
{
    static _Thread_local char buf[200];
    buf[0] = 0;
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, innermost, buf);
    return buf;
}

/* Opens path read-only after finding its signature (at 0, 512, 1024, ...). */
lc_status lci_h5_open(lc_device *dev, const char *path, hid_t *out)
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
                         lci_h5_why());
    return LC_OK;
}

int lci_h5_exists(hid_t loc, const char *name) { return H5Lexists(loc, name, H5P_DEFAULT) > 0; }

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


lc_status lci_h5_dataset_info(lc_device *dev, const char *path, const char *name, hid_t ds, lci_h5_dinfo *d)
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
lc_status lci_h5_read_floats(lc_device *dev, const char *path, const char *name, hid_t ds, const lci_h5_dinfo *di, float *out,
                             size_t n)
{
    if (H5Dread(ds, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, out) < 0)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: libhdf5 cannot read it (%s)", path, name, di->where, lci_h5_why());
    for (size_t i = 0; i < n; i++)
        if (!isfinite(out[i]))
            return lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: value %zu is not finite", path, name, di->where, i);
    return LC_OK;
}


/* The /Header attribute name of 1 to n numbers as doubles into v[n] (the
 * rest 0): 1 when read, 0 when absent, -1 (with why) when present but empty,
 * longer than n or of a type libhdf5 does not convert safely. (SWIFT writes
 * 7 types where GADGET writes 6.) */
int lci_h5_header_attr(hid_t f, const char *name, double *v, hssize_t n, char *why, size_t wn)
{
    if (!lci_h5_exists(f, "Header") || H5Aexists_by_name(f, "Header", name, H5P_DEFAULT) <= 0) return 0;
    hid_t a = H5Aopen_by_name(f, "Header", name, H5P_DEFAULT, H5P_DEFAULT);
    if (a < 0) {
        snprintf(why, wn, "libhdf5 cannot open it (%s)", lci_h5_why());
        return -1;
    }
    hid_t sp = H5Aget_space(a), ty = H5Aget_type(a);
    hssize_t got = sp >= 0 ? H5Sget_simple_extent_npoints(sp) : -1;
    int ok = ty >= 0 && type_sane(ty, why, wn);
    if (ok && (got < 1 || got > n)) snprintf(why, wn, "%lld values, expected 1 to %lld", (long long)got, (long long)n), ok = 0;
    for (hssize_t i = 0; i < n; i++) v[i] = 0.0;
    if (ok && H5Aread(a, H5T_NATIVE_DOUBLE, v) < 0) snprintf(why, wn, "libhdf5 cannot read it (%s)", lci_h5_why()), ok = 0;
    if (sp >= 0) H5Sclose(sp);
    if (ty >= 0) H5Tclose(ty);
    H5Aclose(a);
    return ok ? 1 : -1;
}

const char *const lci_h5_vnames[5] = {"none", "mass", "u", "rho", "hsml"};

int64_t lci_h5_select_range(lci_psel *ps, lci_plist *p, size_t base, int64_t n, size_t first, int t, float *w8)
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
        if (w8) w8[w] = w8[q];
        w++;
    }
    return (int64_t)(w - base);
}

lc_status lci_h5_parse_opts(lc_device *dev, const lci_read_args *a, lci_h5_opts *o)
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
    o->vtext = "none";
    if (s == LC_OK && (x = lci_option_find(a, "value"))) {
        o->value = LCI_H5_V_NAMED;
        o->vtext = x->value;
        for (int i = 0; i < 5; i++)
            if (!strcmp(x->value, lci_h5_vnames[i])) o->value = i;
        if (o->value == LCI_H5_V_NAMED && lci_value_spec_parse(x->value, &o->vs))
            s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                          "%s: option value = '%s', expected none, mass, u, rho, hsml or a dataset of the PartTypeN "
                          "groups: NAME (N or N x 1 values), NAME:K (component K of N x C) or |NAME| (the magnitude)",
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

/* Radii of n points: radius option, else k-NN, zeros replaced by the smallest. */
lc_status lci_h5_fill_radii(lc_device *dev, const char *path, const lci_h5_opts *o, const float *x, int64_t n, float *r, int have)
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
#endif
