/* HDF5 particle snapshots in the GADGET-3 / AREPO / SWIFT layout: groups
 * PartType0..5 with Coordinates (N x 3), and when present Masses (else the
 * /Header attribute MassTable), SmoothingLength(s), Density/Densities,
 * InternalEnergy/InternalEnergies. Options as the GADGET reader's (hdf5.c
 * lists them); `value = ` names any dataset of the groups (a path inside
 * the group such as ElementAbundance/Oxygen; N or N x 1 values, or of an
 * N x C dataset `NAME:K` the component K and `|NAME|` the magnitude), with
 * mass, u, rho and hsml as aliases of the standard names. SPH
 * (host/sph/sph_load.h): radii are lanecast's support
 * radius H. GADGET-3 and AREPO's SmoothingLength is H; SWIFT's
 * SmoothingLengths (its spelling, or a /HydroScheme group) are h, converted
 * to H = gamma h with the gamma of the kernel rendered, else of the
 * /HydroScheme "Kernel function" the file records, else the cubic spline's;
 * `hsml_is = h|H` overrides. With an SPH kernel and a value A,
 * k_i = m_i / rho_i A_i (Masses or MassTable, Density/Densities; groups
 * without densities are skipped unless named). With an lci_share (host/mpi/
 * under mpirun) only the share's rows of each dataset are read, by
 * hyperslab, after the same metadata checks. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/checked.h"
#include "host/formats/hdf5_io.h"
#include "host/sph/sph_kernel.h"

#if LC_HAVE_HDF5
/* Rows [lo, lo + cnt) of ds (dims[0] rows of c values) as floats into out,
 * checked finite as lci_h5_read_floats checks (the value's index in the
 * dataset); all of them: lci_h5_read_floats itself, what a whole read does. */
static lc_status read_rows(lc_device *dev, const char *path, const char *name, hid_t ds, const lci_h5_dinfo *di,
                           int64_t lo, int64_t cnt, int64_t c, float *out)
{
    if (lo == 0 && cnt == (int64_t)di->dims[0]) return lci_h5_read_floats(dev, path, name, ds, di, out, (size_t)(cnt * c));
    if (cnt == 0) return LC_OK;
    hsize_t start[2] = {(hsize_t)lo, 0}, count[2] = {(hsize_t)cnt, di->rank == 2 ? di->dims[1] : 1};
    hsize_t mdim = (hsize_t)(cnt * c);
    hid_t fs = H5Dget_space(ds), ms = H5Screate_simple(1, &mdim, NULL);
    int ok = fs >= 0 && ms >= 0 && H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL) >= 0 &&
             H5Dread(ds, H5T_NATIVE_FLOAT, ms, fs, H5P_DEFAULT, out) >= 0;
    if (fs >= 0) H5Sclose(fs);
    if (ms >= 0) H5Sclose(ms);
    if (!ok)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: libhdf5 cannot read rows %lld .. %lld (%s)", path, name,
                         di->where, (long long)lo, (long long)(lo + cnt - 1), lci_h5_why());
    for (int64_t i = 0; i < cnt * c; i++)
        if (!isfinite(out[i]))
            return lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: value %lld is not finite", path, name, di->where,
                             (long long)(lo * c + i));
    return LC_OK;
}

/* One per-particle dataset of group g (the first of names that lci_h5_exists): 1-D
 * of n values (or n x 1), or with comp >= 0 or LCI_VALUE_MAG (lci_value_spec)
 * the component or magnitude of n x C; its rows [lo, lo + cnt) into out.
 * *found = 0 when none lci_h5_exists. */
static lc_status per_particle(lc_device *dev, const char *path, hid_t g, int type, const char *const *names,
                              const lci_value_spec *spec, int64_t n, int64_t lo, int64_t cnt, float *out, int *found)
{
    const int comp = spec ? spec->comp : -1;
    *found = 0;
    for (; *names; names++) {
        if (!lci_h5_exists(g, *names)) continue;
        char name[96];
        snprintf(name, sizeof name, "/PartType%d/%s", type, *names);
        hid_t ds = H5Dopen2(g, *names, H5P_DEFAULT);
        if (ds < 0) return lci_error(dev, LC_ERROR_FORMAT, "%s: %s: not a dataset (%s)", path, name, lci_h5_why());
        lci_h5_dinfo di;
        lc_status s = lci_h5_dataset_info(dev, path, name, ds, &di);
        int64_t c = s == LC_OK && di.rank == 2 ? (int64_t)di.dims[1] : 1;
        if (s == LC_OK && !((di.rank == 1 || di.rank == 2) && (int64_t)di.dims[0] == n && c >= 1))
            s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: shape %llu%s, expected %lld rows (one per particle of "
                          "Coordinates)", path, name, di.where, (unsigned long long)di.dims[0],
                          di.rank == 2 ? " x C" : di.rank == 3 ? " x N x M" : "", (long long)n);
        if (s == LC_OK && c > 1 && comp == -1)
            s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: %s%s: %lld x %lld values; name a component %s:0..%lld "
                          "or the magnitude |%s|", path, name, di.where, (long long)n, (long long)c, *names,
                          (long long)(c - 1), *names);
        if (s == LC_OK && c == 1 && comp != -1)
            s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: %s%s: one value per particle, no components to take",
                          path, name, di.where);
        if (s == LC_OK && comp >= c)
            s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: %s%s: component %d of %lld x %lld values (0..%lld)", path,
                          name, di.where, comp, (long long)n, (long long)c, (long long)(c - 1));
        float *row = s == LC_OK && c > 1 ? malloc(sizeof(float) * (size_t)(cnt * c + 1)) : out;
        if (!row) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: %s: out of memory", path, name);
        if (s == LC_OK) s = read_rows(dev, path, name, ds, &di, lo, cnt, c, row);
        if (s == LC_OK && c > 1) lci_value_spec_reduce(spec, row, cnt, (int)c, out);
        if (row != out) free(row);
        H5Dclose(ds);
        *found = s == LC_OK;
        return s;
    }
    return LC_OK;
}

static const char *const mass_names[] = {"Masses", NULL};
static const char *const u_names[] = {"InternalEnergy", "InternalEnergies", NULL};
static const char *const rho_names[] = {"Density", "Densities", NULL};
static const char *const hsml_names[] = {"SmoothingLength", "SmoothingLengths", NULL};
static const char *const *const vdatasets[] = {NULL, mass_names, u_names, rho_names, hsml_names};

/* The SPH kernel a SWIFT snapshot records (/HydroScheme attribute "Kernel
 * function", a fixed-length string such as "Wendland C2" or "Cubic spline
 * (M4)"), or LC_KERNEL_GAUSSIAN when it records none this reader knows. */
static lc_kernel file_kernel(hid_t f)
{
    static const char *const names[][2] = {{"(M4)", "m4"}, {"(M5)", "m5"}, {"(M6)", "m6"},
                                           {"Wendland C2", "wendland-c2"}, {"Wendland C4", "wendland-c4"},
                                           {"Wendland C6", "wendland-c6"}};
    lc_kernel k = LC_KERNEL_GAUSSIAN;
    if (!lci_h5_exists(f, "HydroScheme") || H5Aexists_by_name(f, "HydroScheme", "Kernel function", H5P_DEFAULT) <= 0) return k;
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

/* A share's rows (lci_share): the total over the groups the whole read
 * reads (Coordinates' rows; a group that is not one is left to the read's
 * checks) and [a, b) of it, or in sh->whole why the set is needed whole. */
static void share_plan(hid_t f, const lci_h5_opts *o, lci_share *sh)
{
    uint64_t total = 0;
    if (o->sel.sel) sh->whole = "a selection (select = ...) over the whole file's indices";
    for (int t = 0; t < 6; t++) {
        char gname[16];
        snprintf(gname, sizeof gname, "PartType%d", t);
        if (!o->types[t] || !lci_h5_exists(f, gname)) continue;
        hid_t g = H5Gopen2(f, gname, H5P_DEFAULT);
        hid_t ds = g >= 0 && lci_h5_exists(g, "Coordinates") ? H5Dopen2(g, "Coordinates", H5P_DEFAULT) : -1;
        hid_t sp = ds >= 0 ? H5Dget_space(ds) : -1;
        hsize_t dims[3] = {0, 0, 0};
        if (sp >= 0 && H5Sget_simple_extent_ndims(sp) == 2) H5Sget_simple_extent_dims(sp, dims, NULL);
        total += dims[0];
        if (dims[0] > 0 && !(o->radius > 0.0f) && !lci_h5_exists(g, hsml_names[0]) && !lci_h5_exists(g, hsml_names[1]))
            sh->whole = "k-nearest-neighbour radii (a group without SmoothingLength and no radius option)";
        if (sp >= 0) H5Sclose(sp);
        if (ds >= 0) H5Dclose(ds);
        if (g >= 0) H5Gclose(g);
    }
    sh->total = (size_t)total;
    sh->a = (size_t)(total * (uint64_t)sh->rank / (uint64_t)sh->parts);
    sh->b = (size_t)(total * (uint64_t)(sh->rank + 1) / (uint64_t)sh->parts);
    if (sh->whole) sh->a = sh->b = 0; /* nothing read: rank 0 reads it all */
    sh->offset = 0;
}

lc_status lci_h5_read_snapshot(lc_device *dev, const char *path, hid_t f, lci_h5_opts *o, lci_loaded *out)
{
    lci_share *sh = o->share;
    if (sh) share_plan(f, o, sh);
    size_t first = 0; /* the file's particles before this type (the selection's index) */
    lci_plist p;
    memset(&p, 0, sizeof p);
    lc_status s = LC_OK;
    double mtab[16] = {0}, npart[16] = {0};
    char why[96] = "";
    int have_mtab = lci_h5_header_attr(f, "MassTable", mtab, 16, why, sizeof why);
    if (have_mtab < 0) return lci_error(dev, LC_ERROR_FORMAT, "%s: /Header/MassTable: %s", path, why);
    int have_np = lci_h5_header_attr(f, "NumPart_ThisFile", npart, 16, why, sizeof why);
    if (have_np < 0) return lci_error(dev, LC_ERROR_FORMAT, "%s: /Header/NumPart_ThisFile: %s", path, why);
    int nfields = 0, any = 0;
    /* smoothing lengths: h (SWIFT) or H, and the gamma that makes h into H */
    const int weighted = lci_sph_weighted(&o->sph, o->value != LCI_H5_V_NONE);
    if (o->sph.normalise && !weighted)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: normalise = 1 is the normalised SPH interpolant: it needs "
                         "an SPH kernel (kernel = m4, ...) and the quantity interpolated (value = A)", path);
    float *wn = NULL; /* normalise: the m_i / rho_i, as the particles (grown with them) */
    size_t wcap = 0;
    const int swift = lci_h5_exists(f, "HydroScheme");
    const char *gwhy = "";
    lc_kernel gk = lci_sph_gamma_kernel(&o->sph, file_kernel(f), &gwhy);
    int any_h = 0, any_H = 0; /* groups whose smoothing lengths were read as h, as H */
    for (int t = 0; t < 6 && s == LC_OK; t++) {
        char gname[16], name[96];
        snprintf(gname, sizeof gname, "PartType%d", t);
        if (!o->types[t] || !lci_h5_exists(f, gname)) continue;
        hid_t g = H5Gopen2(f, gname, H5P_DEFAULT);
        if (g < 0) {
            s = lci_error(dev, LC_ERROR_FORMAT, "%s: /%s: not a group (%s)", path, gname, lci_h5_why());
            break;
        }
        snprintf(name, sizeof name, "/%s/Coordinates", gname);
        hid_t ds = lci_h5_exists(g, "Coordinates") ? H5Dopen2(g, "Coordinates", H5P_DEFAULT) : -1;
        lci_h5_dinfo di;
        int64_t n = 0;
        if (ds < 0) s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s: missing (every PartTypeN group needs its positions)", path, name);
        if (s == LC_OK) s = lci_h5_dataset_info(dev, path, name, ds, &di);
        if (s == LC_OK && (di.rank != 2 || di.dims[1] != 3))
            s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s: shape %llu x %llu, expected N x 3", path, name, di.where,
                          (unsigned long long)di.dims[0], (unsigned long long)(di.rank == 2 ? di.dims[1] : 0));
        if (s == LC_OK) {
            n = (int64_t)di.dims[0];
            if (n > LCI_H5_MAX_PARTICLES - (int64_t)p.n)
                s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s: %lld particles, more than lanecast's 2^31", path, name, (long long)n);
            else if (have_np && npart[t] != (double)n)
                s = lci_error(dev, LC_ERROR_FORMAT, "%s: %s%s holds %lld particles, /Header NumPart_ThisFile[%d] says %.0f",
                              path, name, di.where, (long long)n, t, npart[t]);
        }
        if (s == LC_OK && n > 0) {
            /* the rows read: all, or the share's [a, b) of the whole read's order in this group */
            int64_t lo = 0, cnt = n;
            if (sh) {
                int64_t a = (int64_t)sh->a - (int64_t)first, b = (int64_t)sh->b - (int64_t)first;
                lo = a < 0 ? 0 : a > n ? n : a, cnt = (b < 0 ? 0 : b > n ? n : b) - lo;
            }
            if (lci_plist_reserve(&p, (size_t)cnt + 1)) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
            size_t base = p.n;
            float *x = p.xyz + 3 * base, *r = p.r + base, *v = p.v + base;
            if (s == LC_OK) s = read_rows(dev, path, name, ds, &di, lo, cnt, 3, x);
            int have = 0;
            if (s == LC_OK && !(o->radius > 0.0f))
                s = per_particle(dev, path, g, t, hsml_names, NULL, n, lo, cnt, r, &have);
            if (s == LC_OK && have) { /* SWIFT's spelling (or its /HydroScheme) means h */
                int small = o->sph.hsml_is == LCI_HSML_FILE
                                ? (swift || !lci_h5_exists(g, hsml_names[0]))
                                : o->sph.hsml_is == LCI_HSML_SMALL_H;
                double gamma = small ? lci_sph_kernel_get(gk)->swift_gamma : 1.0;
                for (int64_t i = 0; gamma != 1.0 && i < cnt; i++) r[i] = (float)(gamma * (double)r[i]);
                any_h |= small, any_H |= !small;
            }
            for (int64_t i = 0; sh && have && i < cnt; i++) /* replaced by the group's smallest: the whole group's */
                if (!(r[i] > 0.0f)) sh->whole = "a smoothing length <= 0 (replaced by its group's smallest)";
            if (s == LC_OK) s = lci_h5_fill_radii(dev, path, o, x, cnt, r, have);
            int vfound = 1;
            const char *named[] = {o->vs.name, NULL};
            const char *const *vnames = o->value == LCI_H5_V_NAMED ? named : vdatasets[o->value];
            if (s == LC_OK && o->value != LCI_H5_V_NONE)
                s = per_particle(dev, path, g, t, vnames, o->value == LCI_H5_V_NAMED ? &o->vs : NULL, n, lo, cnt, v,
                                 &vfound);
            if (s == LC_OK && o->value == LCI_H5_V_MASS && !vfound) {
                if (have_mtab && mtab[t] > 0.0) {
                    for (int64_t i = 0; i < cnt; i++) v[i] = (float)mtab[t];
                    vfound = 1;
                } else
                    s = lci_error(dev, LC_ERROR_FORMAT, "%s: /%s: value = mass, but there is no Masses dataset and no "
                                  "/Header MassTable entry for type %d", path, gname, t);
            }
            if (s == LC_OK && o->value != LCI_H5_V_NONE && !vfound) {
                if (o->types_given)
                    s = lci_error(dev, LC_ERROR_FORMAT, "%s: /%s: value = %s, but the group has no %s dataset (lanecast "
                                  "info lists its datasets)", path, gname, o->vtext, vnames[0]);
                else
                    lci_log(dev, LC_LOG_INFO, "%s: /%s skipped: no %s for value = %s", path, gname, vnames[0], o->vtext);
            }
            if (s == LC_OK && vfound && weighted) { /* k_i = m_i / rho_i A_i */
                float *buf = malloc(sizeof(float) * ((size_t)cnt * 2 + 1));
                int rf = 0, mf = 0;
                if (!buf) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
                if (s == LC_OK) s = per_particle(dev, path, g, t, rho_names, NULL, n, lo, cnt, buf, &rf);
                if (s == LC_OK && rf) s = per_particle(dev, path, g, t, mass_names, NULL, n, lo, cnt, buf + cnt, &mf);
                if (s == LC_OK && rf && !mf && !(have_mtab && mtab[t] > 0.0))
                    s = lci_error(dev, LC_ERROR_FORMAT, "%s: /%s: value = %s with kernel %s is SPH interpolation (k = m / "
                                  "rho * %s), but there is no Masses dataset and no /Header MassTable entry for type %d",
                                  path, gname, o->vtext, lc_kernel_name(o->sph.kernel), o->vtext, t);
                if (s == LC_OK && !rf) {
                    vfound = 0;
                    if (o->types_given)
                        s = lci_error(dev, LC_ERROR_FORMAT, "%s: /%s: value = %s with kernel %s is SPH interpolation (k = "
                                      "m / rho * %s), but the group has no Density dataset", path, gname,
                                      o->vtext, lc_kernel_name(o->sph.kernel), o->vtext);
                    else
                        lci_log(dev, LC_LOG_INFO, "%s: /%s skipped: no Density for SPH interpolation", path, gname);
                }
                snprintf(name, sizeof name, "/%s/Density", gname);
                if (s == LC_OK && rf)
                    s = lci_sph_weigh(dev, path, name, lo, cnt, mf ? buf + cnt : NULL, mtab[t], buf, v);
                if (s == LC_OK && rf && o->sph.normalise && wcap < base + (size_t)cnt + 1) {
                    float *w2 = realloc(wn, sizeof(float) * (base + (size_t)cnt + 1));
                    if (!w2) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
                    else wn = w2, wcap = base + (size_t)cnt + 1;
                }
                if (s == LC_OK && rf && o->sph.normalise)
                    lci_sph_norm_weights(cnt, mf ? buf + cnt : NULL, mtab[t], buf, wn + base);
                free(buf);
            }
            if (s == LC_OK && vfound) {
                if (o->value == LCI_H5_V_NONE)
                    for (int64_t i = 0; i < cnt; i++) v[i] = 1.0f;
                for (int64_t i = 0; i < cnt; i++) p.f[base + (size_t)i] = (uint8_t)(o->by_type ? nfields : 0);
                int64_t kept = lci_h5_select_range(&o->sel, &p, base, cnt, first + (size_t)lo, t, wn);
                if (sh) sh->offset += (size_t)lo; /* a share has no selection: the whole group is kept */
                if (kept > 0 || sh) { /* no field for a type the selection left empty */
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
                      o->value != LCI_H5_V_NONE ? " with that value" : "");
    double nfiles = 0;
    if (s == LC_OK && lci_h5_header_attr(f, "NumFilesPerSnapshot", &nfiles, 1, why, sizeof why) > 0 && nfiles > 1)
        lci_log(dev, LC_LOG_INFO, "%s: one file of a %.0f-file snapshot (its own particles only)", path, nfiles);
    s = lci_plist_finish(dev, path, s, &p, o->by_type ? nfields : 1, o->value != LCI_H5_V_NONE, out);
    if (s == LC_OK) lci_sph_keep_norm(out, wn);
    else free(wn);
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
            lci_sph_note(out, "%s; k = m / rho * %s (SPH interpolation with %s)", conv, o->vtext,
                         lc_kernel_name(o->sph.kernel));
        else
            lci_sph_note(out, "%s", conv);
    }
    return s;
}

/* lanecast info: the datasets below a group, their paths relative to it
 * (what value = names) and their shapes. */
typedef struct dlist {
    char *text;
    size_t size, n;
    char prefix[128];
    int depth;
} dlist;

static herr_t list_datasets(hid_t g, const char *name, const H5L_info_t *info, void *user)
{
    (void)info;
    dlist *d = user;
    if (d->n + 1 >= d->size) return 1;
    hid_t obj = H5Oopen(g, name, H5P_DEFAULT);
    if (obj < 0) return 0;
    H5I_type_t ty = H5Iget_type(obj);
    if (ty == H5I_DATASET) {
        hid_t sp = H5Dget_space(obj);
        hsize_t dims[3] = {0, 0, 0};
        int rank = sp >= 0 ? H5Sget_simple_extent_ndims(sp) : -1;
        if (rank >= 1 && rank <= 3) H5Sget_simple_extent_dims(sp, dims, NULL);
        if (sp >= 0) H5Sclose(sp);
        char shape[64] = "?";
        if (rank == 1) snprintf(shape, sizeof shape, "%llu", (unsigned long long)dims[0]);
        else if (rank == 2) snprintf(shape, sizeof shape, "%llu x %llu", (unsigned long long)dims[0], (unsigned long long)dims[1]);
        else if (rank == 3)
            snprintf(shape, sizeof shape, "%llu x %llu x %llu", (unsigned long long)dims[0], (unsigned long long)dims[1],
                     (unsigned long long)dims[2]);
        int w = snprintf(d->text + d->n, d->size - d->n, "%s %s%s (%s)", d->n && d->text[d->n - 1] != ':' ? "," : "",
                         d->prefix, name, shape);
        if (w > 0) d->n = d->n + (size_t)w < d->size ? d->n + (size_t)w : d->size - 1;
    } else if (ty == H5I_GROUP && d->depth < 4) {
        size_t keep = strlen(d->prefix);
        snprintf(d->prefix + keep, sizeof d->prefix - keep, "%s/", name);
        d->depth++;
        H5Literate(obj, H5_INDEX_NAME, H5_ITER_INC, NULL, list_datasets, d);
        d->depth--;
        d->prefix[keep] = 0;
    }
    H5Oclose(obj);
    return 0;
}

lc_status lci_h5_describe_snapshot(lc_device *dev, const char *path, hid_t f, char *text, size_t size)
{
    (void)dev, (void)path;
    dlist d = {text, size, 0, "", 0};
    text[0] = 0;
    for (int t = 0; t < 6; t++) {
        char gname[16];
        snprintf(gname, sizeof gname, "PartType%d", t);
        if (!lci_h5_exists(f, gname)) continue;
        hid_t g = H5Gopen2(f, gname, H5P_DEFAULT);
        if (g < 0) continue;
        int w = snprintf(text + d.n, size - d.n, "%-13s per-particle datasets:", gname);
        if (w > 0) d.n = d.n + (size_t)w < size ? d.n + (size_t)w : size - 1;
        H5Literate(g, H5_INDEX_NAME, H5_ITER_INC, NULL, list_datasets, &d);
        H5Gclose(g);
        if (d.n + 1 < size) text[d.n++] = '\n', text[d.n] = 0;
    }
    return LC_OK;
}
#endif
