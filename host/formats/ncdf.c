/* AMBER NetCDF trajectories and restarts (the AMBER NetCDF convention,
 * ambermd.org/netcdf/nctraj.xhtml), read through libnetcdf (libnetcdf-dev).
 * A trajectory holds the global attribute Conventions = "AMBER" (restarts:
 * "AMBERRESTART"), dimensions frame (unlimited), atom, spatial = 3, and
 *
 *   float coordinates(frame, atom, spatial)   units "angstrom"
 *   float velocities(frame, atom, spatial)    optional, "angstrom/picosecond"
 *   double cell_lengths(frame, cell_spatial), cell_angles(frame, cell_angular)  optional
 *   float time(frame)                         "picosecond"
 *
 * (a restart drops the frame dimension: one frame). A variable's
 * scale_factor attribute multiplies its values (AMBER's velocities carry
 * 20.455). lc_load_desc.frame picks a frame by index: libnetcdf reads that
 * hyperslab alone. `value = speed` takes |v| (Angstrom/ps) as k_i. The
 * topology is a companion PDB or PSF (or .gro) (topology.h); AMBER's own
 * prmtop is not read. libnetcdf reads netCDF-4 files through libhdf5, which
 * can crash on a damaged file: every file is read once in a guard process
 * first (guard.h), as HDF5 files are. Errors name the file and the variable
 * or attribute. */
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include "host/formats/checked.h"
#include "host/formats/guard.h"
#include "host/formats/topology.h"

#if LC_HAVE_NETCDF
#include <netcdf.h>

#define NC_MAX_ATOMS ((size_t)INT32_MAX / 4)

/* libnetcdf is not thread-safe: one load at a time in this process (the
 * guard's child, a copy of the process, reads without it) */
static pthread_mutex_t nc_lock = PTHREAD_MUTEX_INITIALIZER;

typedef struct ncf {
    int id, coords, vels, restart;
    size_t natom, nframes;
    double cscale, vscale;
} ncf;

static lc_status nc_fail(lc_device *dev, const char *path, const char *what, int rc)
{
    return lci_error(dev, rc == NC_ENOMEM ? LC_ERROR_OUT_OF_MEMORY : LC_ERROR_FORMAT, "%s: %s: %s (netCDF)", path, what,
                     nc_strerror(rc));
}

/* A text attribute of varid ("" when absent). */
static void att_text(int id, int varid, const char *name, char *buf, size_t n)
{
    size_t len = 0;
    nc_type t;
    buf[0] = '\0';
    if (nc_inq_att(id, varid, name, &t, &len) != NC_NOERR || t != NC_CHAR || len >= n) return;
    if (nc_get_att_text(id, varid, name, buf) == NC_NOERR) buf[len] = '\0';
    else buf[0] = '\0';
}

/* The variable's scale_factor (1 when absent); -1 on a bad one. */
static double scale_of(int id, int varid)
{
    nc_type t;
    size_t len;
    double v = 1.0;
    if (nc_inq_att(id, varid, "scale_factor", &t, &len) != NC_NOERR) return 1.0;
    if (len != 1 || nc_get_att_double(id, varid, "scale_factor", &v) != NC_NOERR || !isfinite(v)) return -1.0;
    return v;
}

/* Checks a coordinate-like variable's dimensions: (frame, atom, spatial),
 * or (atom, spatial) in a restart. */
static lc_status check_dims(lc_device *dev, const char *path, const ncf *f, int varid, const char *name)
{
    int nd = 0, dims[NC_MAX_VAR_DIMS];
    nc_type t;
    int rc = nc_inq_var(f->id, varid, NULL, &t, &nd, dims, NULL);
    if (rc != NC_NOERR) return nc_fail(dev, path, name, rc);
    const char *want[3] = {"frame", "atom", "spatial"};
    int first = f->restart ? 1 : 0;
    if (nd != 3 - first)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: variable %s has %d dimensions, expected %s", path, name, nd,
                         f->restart ? "(atom, spatial)" : "(frame, atom, spatial)");
    for (int i = 0; i < nd; i++) {
        char dn[NC_MAX_NAME + 1];
        size_t len;
        if ((rc = nc_inq_dim(f->id, dims[i], dn, &len)) != NC_NOERR) return nc_fail(dev, path, name, rc);
        if (strcmp(dn, want[first + i]) || (i == nd - 1 && len != 3))
            return lci_error(dev, LC_ERROR_FORMAT, "%s: variable %s: dimension %d is '%s' of %zu, expected '%s'%s", path,
                             name, i, dn, len, want[first + i], i == nd - 1 ? " of 3" : "");
    }
    if (t != NC_FLOAT && t != NC_DOUBLE && t != NC_SHORT && t != NC_INT)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: variable %s is not numeric", path, name);
    return LC_OK;
}

/* Classic netCDF (CDF-1, -2, -5) files, before libnetcdf sees them: the
 * header's lists and names must fit the file (libnetcdf allocates what a
 * damaged count says: 4 GB for one name, found by fuzz_ncdf), and, since
 * libnetcdf fills what lies past the end of a cut file with zeros, the end
 * of every variable's data (begin offsets, numrecs and vsizes; NetCDF
 * Classic Format Specification) must lie inside the file. Returns 0 (ok, or
 * a header longer than the bytes read: left to libnetcdf), -1 (the data is
 * cut) or the byte offset where the header stops making sense. AMBER files
 * have a dozen variables; more than 1024 dimensions or variables are
 * refused. */
typedef struct cdf {
    const unsigned char *p;
    size_t n, at;
    int v; /* 1, 2 or 5 */
    int bad;    /* a count or a name past the end of the file */
    int beyond; /* past the bytes read, inside the file */
    uint64_t fsize;
} cdf;

static uint64_t cdf_u(cdf *c, int bytes)
{
    if (c->bad) return 0; /* the first damage decides: not read past */
    if (c->at + (size_t)bytes > c->n) {
        if ((uint64_t)c->at + (uint64_t)bytes <= c->fsize) c->beyond = 1; /* only past the bytes read */
        return c->bad = 1, 0;
    }
    uint64_t v = 0;
    for (int i = 0; i < bytes; i++) v = v << 8 | c->p[c->at++];
    return v;
}

static void cdf_skip(cdf *c, uint64_t bytes)
{
    if (c->bad) return;
    if (bytes > c->fsize - c->at) c->bad = 1;
    else if (bytes > c->n - c->at) c->beyond = c->bad = 1;
    if (c->bad) c->at = c->n;
    else c->at += (size_t)bytes;
}

static uint64_t cdf_count(cdf *c) { return cdf_u(c, c->v == 5 ? 8 : 4); }
static void cdf_name(cdf *c) { cdf_skip(c, (cdf_count(c) + 3) / 4 * 4); }

static void cdf_atts(cdf *c)
{
    static const int tsize[] = {0, 1, 1, 2, 4, 4, 8, 1, 2, 4, 8, 8};
    uint64_t tag = cdf_u(c, 4), n = cdf_count(c);
    if (tag != 0 && tag != 12) c->bad = 1;
    for (uint64_t i = 0; i < n && !c->bad; i++) {
        cdf_name(c);
        uint64_t t = cdf_u(c, 4), k = cdf_count(c);
        if (t < 1 || t > 11 || k > c->fsize) c->bad = 1;
        else cdf_skip(c, (k * (uint64_t)tsize[t] + 3) / 4 * 4);
    }
}

static int64_t cdf_check(const unsigned char *p, size_t n, int64_t fsize)
{
    cdf c = {p, n, 4, p[3], 0, 0, (uint64_t)fsize};
    uint64_t numrecs = cdf_count(&c);
    uint64_t tag = cdf_u(&c, 4), ndims = cdf_count(&c);
    uint64_t dimlen[1024];
    int recdim = -1;
    if (c.beyond) return 0;
    if ((tag != 0 && tag != 10) || ndims > 1024) return (int64_t)c.at;
    for (uint64_t i = 0; i < ndims && !c.bad; i++) {
        cdf_name(&c);
        dimlen[i] = cdf_count(&c);
        if (dimlen[i] == 0) recdim = (int)i;
        if (dimlen[i] > c.fsize) c.bad = 1; /* longer than the file: libnetcdf sizes its shapes from it */
    }
    cdf_atts(&c);
    tag = cdf_u(&c, 4);
    uint64_t nvars = cdf_count(&c);
    if (c.beyond) return 0;
    if (c.bad || (tag != 0 && tag != 11) || nvars > 1024) return (int64_t)c.at;
    uint64_t recsize = 0, nrecvars = 0, begins[1024], vsizes[1024];
    int isrec[1024];
    for (uint64_t i = 0; i < nvars && !c.bad; i++) {
        cdf_name(&c);
        uint64_t nd = cdf_count(&c), first = 0;
        for (uint64_t j = 0; j < nd && !c.bad; j++) {
            uint64_t id = cdf_count(&c);
            if (id >= ndims) c.bad = 1;
            if (j == 0) first = id;
        }
        cdf_atts(&c);
        cdf_u(&c, 4);
        vsizes[i] = cdf_u(&c, c.v == 5 ? 8 : 4);
        begins[i] = cdf_u(&c, c.v == 1 ? 4 : 8);
        isrec[i] = nd > 0 && (int)first == recdim;
        if (isrec[i]) recsize += vsizes[i], nrecvars++;
    }
    if (c.beyond) return 0;
    if (c.bad) return (int64_t)(c.at ? c.at : 1);
    for (uint64_t i = 0; i < nvars; i++) {
        uint64_t rs = nrecvars == 1 ? vsizes[i] : recsize; /* one record variable: records are not padded */
        uint64_t f = (uint64_t)fsize;
        if (begins[i] > f || vsizes[i] > f || (isrec[i] && numrecs > 1 && (rs == 0 || numrecs - 1 > f / rs))) return -1;
        uint64_t end = isrec[i] ? (numrecs ? begins[i] + (numrecs - 1) * rs + vsizes[i] : 0) : begins[i] + vsizes[i];
        if (end > f) return -1;
    }
    return 0;
}

static lc_status nc_header(lc_device *dev, const char *path, ncf *f)
{
    memset(f, 0, sizeof *f);
    f->id = -1;
    FILE *fp;
    int64_t size;
    lc_status s = lci_open_regular(dev, path, NULL, &fp, &size);
    if (s != LC_OK) return s;
    /* a classic file's header, up to 1 MiB, for the data-size check */
    unsigned char *head = NULL;
    size_t hn = 0;
    unsigned char magic[4] = {0};
    if (fread(magic, 1, 4, fp) == 4 && !memcmp(magic, "CDF", 3) && (magic[3] == 1 || magic[3] == 2 || magic[3] == 5)) {
        hn = size < (1 << 20) ? (size_t)size : (size_t)1 << 20;
        head = malloc(hn ? hn : 1);
        if (!head || fseek(fp, 0, SEEK_SET) || fread(head, 1, hn, fp) != hn) hn = 0;
    }
    fclose(fp);
    int64_t bad = hn ? cdf_check(head, hn, size) : 0;
    free(head);
    if (bad < 0)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: byte %lld: the file ends before the data its header declares (cut "
                         "short?)", path, (long long)size);
    if (bad > 0)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: byte %lld: damaged netCDF header (a list, name, type or dimension "
                         "that does not fit the file, or over 1024 dimensions or variables)", path, (long long)bad);
    int rc = nc_open(path, NC_NOWRITE, &f->id);
    if (rc != NC_NOERR) return f->id = -1, nc_fail(dev, path, "not readable as netCDF", rc);
    char conv[256];
    att_text(f->id, NC_GLOBAL, "Conventions", conv, sizeof conv);
    /* a list, comma or space separated, holding AMBER or AMBERRESTART */
    int amber = 0;
    for (char *w = strtok(conv, ", "); w; w = strtok(NULL, ", ")) {
        if (!strcmp(w, "AMBER")) amber = 1;
        if (!strcmp(w, "AMBERRESTART")) amber = f->restart = 1;
    }
    if (!amber)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: global attribute Conventions does not name AMBER or AMBERRESTART: not "
                         "an AMBER NetCDF trajectory", path);
    int d;
    if ((rc = nc_inq_dimid(f->id, "atom", &d)) != NC_NOERR || (rc = nc_inq_dimlen(f->id, d, &f->natom)) != NC_NOERR)
        return nc_fail(dev, path, "dimension atom", rc);
    if (f->natom == 0 || f->natom > NC_MAX_ATOMS)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: dimension atom is %zu, expected 1 to %zu", path, f->natom,
                         (size_t)NC_MAX_ATOMS);
    f->nframes = 1;
    if (!f->restart &&
        ((rc = nc_inq_dimid(f->id, "frame", &d)) != NC_NOERR || (rc = nc_inq_dimlen(f->id, d, &f->nframes)) != NC_NOERR))
        return nc_fail(dev, path, "dimension frame", rc);
    if ((rc = nc_inq_varid(f->id, "coordinates", &f->coords)) != NC_NOERR)
        return nc_fail(dev, path, "variable coordinates", rc);
    if ((s = check_dims(dev, path, f, f->coords, "coordinates")) != LC_OK) return s;
    char units[64];
    att_text(f->id, f->coords, "units", units, sizeof units);
    if (units[0] && strcasecmp(units, "angstrom") && strcasecmp(units, "angstroms"))
        return lci_error(dev, LC_ERROR_FORMAT, "%s: coordinates in '%s', expected angstrom", path, units);
    f->cscale = scale_of(f->id, f->coords);
    f->vels = -1;
    if (nc_inq_varid(f->id, "velocities", &f->vels) != NC_NOERR) f->vels = -1;
    else if ((s = check_dims(dev, path, f, f->vels, "velocities")) != LC_OK) return s;
    f->vscale = f->vels >= 0 ? scale_of(f->id, f->vels) : 1.0;
    if (f->cscale <= 0.0 || f->vscale < 0.0)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: %s: scale_factor is not one positive number", path,
                         f->cscale <= 0.0 ? "coordinates" : "velocities");
    return LC_OK;
}

static void nc_done(ncf *f)
{
    if (f->id >= 0) nc_close(f->id);
    f->id = -1;
}

/* Variable varid of frame k (n atoms x 3) as floats, times scale. */
static lc_status get_frame(lc_device *dev, const char *path, const ncf *f, int varid, const char *name, size_t k,
                           double scale, float *out)
{
    size_t start[3] = {k, 0, 0}, count[3] = {1, f->natom, 3};
    int rc = f->restart ? nc_get_vara_float(f->id, varid, start + 1, count + 1, out)
                        : nc_get_vara_float(f->id, varid, start, count, out);
    char what[96];
    snprintf(what, sizeof what, "variable %s of frame %zu", name, k);
    if (rc != NC_NOERR) return nc_fail(dev, path, what, rc);
    for (size_t i = 0; i < 3 * f->natom; i++) {
        if (!isfinite(out[i]))
            return lci_error(dev, LC_ERROR_FORMAT, "%s: %s: atom %zu: %c = %g is not finite", path, what, i / 3 + 1,
                             "xyz"[i % 3], (double)out[i]);
        if (scale != 1.0) out[i] = (float)(out[i] * scale);
    }
    return LC_OK;
}

static lc_status ncdf_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    ncf f;
    lci_topo topo = {0};
    float *xyz = NULL, *v = NULL;
    char why[4300] = "";
    lc_status s = nc_header(dev, a->path, &f);
    size_t k = (size_t)a->desc->frame;
    if (s == LC_OK && k >= f.nframes)
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: frame %zu is past the end: the file holds %zu frame%s", a->path,
                      k, f.nframes, f.nframes == 1 ? "" : "s");
    if (s == LC_OK) s = lci_topo_load(dev, a, ".pdb .psf .gro", &topo, why, sizeof why);
    if (s == LC_OK && !(xyz = lci_alloc_checked(dev, a->path, f.natom, 12, 0, "atoms", 0))) s = LC_ERROR_OUT_OF_MEMORY;
    if (s == LC_OK) s = get_frame(dev, a->path, &f, f.coords, "coordinates", k, f.cscale, xyz);
    const lc_option *val = lci_option_find(a, "value");
    if (s == LC_OK && val && !strcasecmp(val->value, "speed") && f.vels >= 0) {
        if (!(v = lci_alloc_checked(dev, a->path, f.natom, 12, 0, "atoms", 0))) s = LC_ERROR_OUT_OF_MEMORY;
        else s = get_frame(dev, a->path, &f, f.vels, "velocities", k, f.vscale, v);
        for (size_t i = 0; s == LC_OK && i < f.natom; i++)
            v[i] = sqrtf(v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
    }
    nc_done(&f);
    lci_traj_values vals = {{"speed", NULL}, {v, NULL}};
    s = lci_topo_atoms(dev, a, s, &topo, why, xyz, s == LC_OK ? (int64_t)f.natom : 0, &vals, out);
    free(xyz);
    free(v);
    lci_topo_free(&topo);
    return s;
}

typedef struct nctx {
    const lci_read_args *a;
} nctx;

static lc_status guard_child(lc_device *dev, void *ctx)
{
    lci_loaded l = {0};
    lc_status s = ncdf_read(dev, ((nctx *)ctx)->a, &l);
    lci_loaded_free(&l);
    return s;
}

/* libnetcdf (and the libhdf5 under it) run once in a child first; a crash
 * there becomes one error line. */
static lc_status guard(lc_device *dev, const lci_read_args *a)
{
    nctx g = {a};
    lc_status cs;
    char msg[LCI_MSG_MAX];
    uint64_t lim = lci_memory_limit(dev);
    struct stat st;
    if (stat(a->path, &st) == 0 && st.st_size >= 0 && (uint64_t)st.st_size < (UINT64_MAX >> 8)) {
        uint64_t cap = 64 * (uint64_t)st.st_size + ((uint64_t)512 << 20);
        lim = cap < lim ? cap : lim;
    }
    int sig = lci_guarded(dev, "LANECAST_NETCDF_GUARD", lim, guard_child, &g, &cs, msg, sizeof msg);
    if (sig < 0) return LC_OK;
    if (sig == 0) return cs == LC_OK ? LC_OK : lci_error(dev, cs, "%s", msg);
    if (sig == SIGINT || sig == SIGTERM || sig == SIGHUP)
        return lci_error(dev, LC_ERROR_IO, "%s: reading stopped by signal %d", a->path, sig);
    return lci_error(dev, LC_ERROR_FORMAT, "%s: libnetcdf crashed on this file (signal %d: %s) in lanecast's guard "
                     "process: the file is damaged", a->path, sig, strsignal(sig));
}

static lc_status ncdf_read_guarded(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    lc_status s = guard(dev, a);
    if (s != LC_OK) return s;
    pthread_mutex_lock(&nc_lock);
    s = ncdf_read(dev, a, out);
    pthread_mutex_unlock(&nc_lock);
    return s;
}

static lc_status ncdf_frames(lc_device *dev, const char *path, int64_t *out)
{
    lc_load_desc d = {0};
    lci_read_args a = {path, &d, NULL, 0, "ncdf"};
    ncf f = {.id = -1};
    *out = 0;
    /* the whole read in the guard first: libnetcdf opens the file to count */
    lc_status s = guard(dev, &a);
    if (s != LC_OK) return s;
    pthread_mutex_lock(&nc_lock);
    s = nc_header(dev, path, &f);
    if (s == LC_OK) *out = (int64_t)f.nframes;
    nc_done(&f);
    pthread_mutex_unlock(&nc_lock);
    return s;
}
#define NCDF_READ ncdf_read_guarded
#define NCDF_FRAMES ncdf_frames
#else
#define NCDF_READ NULL
#define NCDF_FRAMES NULL
#endif

/* netCDF classic (CDF\1), 64-bit offset (CDF\2), CDF-5 (CDF\5); netCDF-4
 * files are HDF5 and are named by their extension. */
static int ncdf_magic(const unsigned char *h, size_t n)
{
    return n >= 4 && !memcmp(h, "CDF", 3) && (h[3] == 1 || h[3] == 2 || h[3] == 5);
}

const lci_format lci_format_ncdf = {
    .name = "ncdf", .kind = LC_KIND_PARTICLES, .extensions = ".nc .ncdf .netcdf .ncrst .rst7nc",
    .options = "radius radius_scale fields select value",
    .description = "AMBER NetCDF trajectory or restart (Conventions AMBER; Angstrom; value = speed); elements from the "
                   "topology (companion .pdb/.psf/.gro, or STEM.pdb, STEM.psf, STEM.gro)",
    .magic = ncdf_magic, .read = NCDF_READ, .package = "libnetcdf-dev", .frames = NCDF_FRAMES, .companion = 1};
