/* GROMACS XTC and TRR trajectories (host/formats/xtc.c, trr.c) and their
 * topologies (topology.c), on files written by third-party writers
 * (tests/data/traj/README.md: MDAnalysis's xdrfile and GROMACS's own
 * gmx/gmx_d): every frame's atom count, a sample of atoms and the per-axis
 * sums over all atoms against what the writer's own reader gives (the .ref
 * files), frames counted, random access, topologies by stem and by
 * --topology, speeds and forces as values, and malformed variants that must
 * each fail naming the file, the byte and the frame.
 * Args: SHARED_DATA_DIR TMP_DIR TRAJ_DATA_DIR. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "host/formats/format.h"
#include "tmpfiles.h"

static lc_device *dev;
static const char *traj_dir, *shared;

static const char *dpath(const char *name)
{
    static char buf[4][1024];
    static int k;
    char *p = buf[k++ % 4];
    snprintf(p, sizeof buf[0], "%s/%s", traj_dir, name);
    return p;
}

static const lc_particles_desc *load(const lci_format *fmt, const char *path, int64_t frame, const char *companion,
                                     const lc_option *o, int n, lci_loaded *l)
{
    memset(l, 0, sizeof *l);
    lc_load_desc d = {.frame = frame, .companion = companion, .options = o, .noptions = n};
    lci_read_args a = {path, &d, o, n, fmt->name};
    return fmt->read(dev, &a, l) == LC_OK ? l->desc : NULL;
}

/* Relative closeness of float32 values read by two decoders (both round
 * the same integers or the same reals: they should agree to the last bits). */
static int close_to(double a, double b) { return fabs(a - b) <= 2e-7 * fmax(1.0, fabs(b)); }

/* Compares every frame of path with its .ref file; returns frames checked. */
static int against_ref(const lci_format *fmt, const char *name)
{
    char refname[256];
    snprintf(refname, sizeof refname, "%s.ref", name);
    FILE *f = fopen(dpath(refname), "r");
    if (!f) {
        CHECK(0, "%s: reference %s opens", name, refname);
        return 0;
    }
    char line[512];
    lci_loaded l = {0};
    const lc_particles_desc *d = NULL;
    int frames = 0, bad_atoms = 0, atoms = 0;
    long frame = -1;
    while (fgets(line, sizeof line, f)) {
        long k, n, step, i;
        double t, sx, sy, sz, x, y, z;
        if (sscanf(line, "frame %ld natoms %ld step %ld time %lf sum %lf %lf %lf", &k, &n, &step, &t, &sx, &sy, &sz) == 7) {
            lci_loaded_free(&l);
            d = load(fmt, dpath(name), k, NULL, NULL, 0, &l);
            frame = k;
            frames++;
            if (!d || d->count != (uint64_t)n) {
                CHECK(0, "%s frame %ld: %ld atoms (got %s, %lld)", name, k, n, d ? "a frame" : lc_last_error(),
                      d ? (long long)d->count : -1LL);
                d = NULL;
                continue;
            }
            double s[3] = {0, 0, 0};
            for (uint64_t j = 0; j < d->count; j++)
                for (int c = 0; c < 3; c++) s[c] += d->positions[3 * j + c];
            CHECK(fabs(s[0] - sx) <= 1e-6 * fmax(1, fabs(sx)) + 1e-9 * n * 1e3 &&
                      fabs(s[1] - sy) <= 1e-6 * fmax(1, fabs(sy)) + 1e-9 * n * 1e3 &&
                      fabs(s[2] - sz) <= 1e-6 * fmax(1, fabs(sz)) + 1e-9 * n * 1e3,
                  "%s frame %ld: sums over its %ld atoms %.9g %.9g %.9g (writer's reader %.9g %.9g %.9g)", name, k, n,
                  s[0], s[1], s[2], sx, sy, sz);
        } else if (d && sscanf(line, "atom %ld %lf %lf %lf", &i, &x, &y, &z) == 4) {
            atoms++;
            const float *p = d->positions + 3 * i;
            if (!(close_to(p[0], x) && close_to(p[1], y) && close_to(p[2], z))) {
                if (bad_atoms++ < 3)
                    printf("     %s frame %ld atom %ld: %.9g %.9g %.9g, the writer's reader %.9g %.9g %.9g\n", name, frame,
                           i, p[0], p[1], p[2], x, y, z);
            }
        }
    }
    fclose(f);
    lci_loaded_free(&l);
    CHECK(frames > 0 && atoms > 0 && bad_atoms == 0, "%s: %d frames, %d sampled atoms as the writer's reader reads them "
          "(%d differ)", name, frames, atoms, bad_atoms);
    lc_file_info fi;
    CHECK(lc_file_probe(dev, dpath(name), NULL, &fi) == LC_OK && fi.frames == frames && !strcmp(fi.format, fmt->name),
          "%s: probed as %s with %d frames (got %lld)", name, fmt->name, frames, (long long)fi.frames);
    return frames;
}

/* Magnitudes of the v / f lines of the TRR reference against value = speed | force. */
static void trr_values(void)
{
    FILE *f = fopen(dpath("adk_ca.trr.ref"), "r");
    if (!f) return;
    lc_option os = {"value", "speed"}, of = {"value", "force"};
    lci_loaded lv, lf;
    const lc_particles_desc *dv = load(&lci_format_trr, dpath("adk_ca.trr"), 0, NULL, &os, 1, &lv);
    const lc_particles_desc *df = load(&lci_format_trr, dpath("adk_ca.trr"), 0, NULL, &of, 1, &lf);
    char line[512];
    int nv = 0, nf = 0, bad = 0;
    while (dv && df && fgets(line, sizeof line, f) && strncmp(line, "frame 1", 7)) {
        long i;
        double x, y, z;
        char c;
        if (sscanf(line, "%c %ld %lf %lf %lf", &c, &i, &x, &y, &z) != 5 || (c != 'v' && c != 'f')) continue;
        /* MDAnalysis reports Angstrom/ps and kJ/mol/Angstrom; the file holds nm/ps and kJ/mol/nm */
        double m = sqrt(x * x + y * y + z * z), want = c == 'v' ? m / 10.0 : m * 10.0;
        double got = c == 'v' ? dv->values[i] : df->values[i];
        bad += fabs(got - want) > 1e-5 * want;
        nv += c == 'v';
        nf += c == 'f';
    }
    fclose(f);
    CHECK(dv && df && nv > 10 && nf > 10 && !bad, "adk_ca.trr frame 0: value = speed and force are |v| (nm/ps) and |f| "
          "(kJ/mol/nm) of %d and %d sampled atoms (%d differ)", nv, nf, bad);
    if (dv) lci_loaded_free(&lv);
    if (df) lci_loaded_free(&lf);
    lci_loaded l;
    const lc_particles_desc *d = load(&lci_format_trr, dpath("gmx_ca_d.trr"), 1, NULL, &of, 1, &l);
    CHECK(!d && strstr(lc_last_error(), "value = 'force': this frame holds no forces"),
          "gmx_ca_d.trr (no forces): value = force fails: %s", d ? "(loaded)" : lc_last_error());
    if (d) lci_loaded_free(&l);
}

static void topologies(void)
{
    lci_loaded l;
    /* adk_ca.gro beside adk_ca.xtc: CA atoms are carbon */
    const lc_particles_desc *d = load(&lci_format_xtc, dpath("adk_ca.xtc"), 3, NULL, NULL, 0, &l);
    CHECK(d && d->count == 214 && d->radii[0] == 0.76f && d->radii[213] == 0.76f,
          "adk_ca.xtc: STEM.gro found, CA atoms get carbon's radius 0.76");
    if (d) lci_loaded_free(&l);
    lc_option sel = {"select", "resid 1:10 or resname GLY"};
    d = load(&lci_format_xtc, dpath("adk_ca.xtc"), 0, NULL, &sel, 1, &l);
    /* ADK (4AKE) residues 1-10 hold GLY 7 and 10; the other GLY residues: counted from the .gro */
    int gly = 0, lowres = 0;
    FILE *g = fopen(dpath("adk_ca.gro"), "r");
    char line[256];
    for (int ln = 0; g && fgets(line, sizeof line, g); ln++) {
        if (ln < 2 || strlen(line) < 20) continue;
        int resid = atoi(line);
        int is_gly = !strncmp(line + 5, "GLY", 3);
        if (resid >= 1 && resid <= 10) lowres++;
        else gly += is_gly;
    }
    if (g) fclose(g);
    CHECK(d && (int)d->count == lowres + gly && lowres == 10,
          "adk_ca.xtc --select 'resid 1:10 or resname GLY': %d atoms (got %lld)", lowres + gly,
          d ? (long long)d->count : -1LL);
    if (d) lci_loaded_free(&l);
    lc_option col = {"fields", "column:resname"};
    d = load(&lci_format_trr, dpath("adk_ca.trr"), 0, dpath("adk_ca.gro"), &col, 1, &l);
    CHECK(d && d->nfields == 8, "adk_ca.trr --topology adk_ca.gro --field-by column resname: 8 fields (got %d)",
          d ? d->nfields : -1);
    if (d) lci_loaded_free(&l);
    lc_option chain = {"fields", "column:chain"};
    d = load(&lci_format_trr, dpath("adk_ca.trr"), 0, dpath("adk_ca.gro"), &chain, 1, &l);
    CHECK(!d && strstr(lc_last_error(), "the GRO topology has no such column"),
          "a column the .gro lacks fails: %s", d ? "(loaded)" : lc_last_error());
    if (d) lci_loaded_free(&l);
    char psf[1024];
    snprintf(psf, sizeof psf, "%s/particles/adk.psf", shared);
    FILE *p = fopen(psf, "r");
    if (!p) {
        printf("skip: %s is absent (the shared data): the PSF topology cases\n", psf);
        return;
    }
    fclose(p);
    d = load(&lci_format_xtc, dpath("adk_ca.xtc"), 0, psf, NULL, 0, &l);
    CHECK(!d && strstr(lc_last_error(), "holds 214 atoms but its topology") && strstr(lc_last_error(), "has 3341"),
          "adk_ca.xtc with adk.psf (3341 atoms) fails: %s", d ? "(loaded)" : lc_last_error());
    if (d) lci_loaded_free(&l);
    lc_option q = {"value", "charge"};
    d = load(&lci_format_xtc, dpath("adk2.xtc"), 1, psf, &q, 1, &l);
    double qsum = 0;
    for (uint64_t i = 0; d && i < d->count; i++) qsum += d->values[i];
    CHECK(d && d->count == 3341 && d->radii[0] == 0.71f && d->radii[1] == 0.31f && fabs(qsum - -4.0) < 1e-3,
          "adk2.xtc --topology adk.psf --value charge: N then H radii, total charge -4 (got %g)", qsum);
    if (d) lci_loaded_free(&l);
}

/* The bytes of a committed file, to damage. */
static unsigned char *slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long sz = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *b = malloc((size_t)sz);
    *n = b && fread(b, 1, (size_t)sz, f) == (size_t)sz ? (size_t)sz : 0;
    fclose(f);
    return b;
}

static void be32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24), p[1] = (unsigned char)(v >> 16), p[2] = (unsigned char)(v >> 8), p[3] = (unsigned char)v;
}

static void malformed(void)
{
    size_t n = 0, m = 0;
    unsigned char *x = slurp(dpath("adk_ca.xtc"), &n), *t = slurp(dpath("adk_ca.trr"), &m);
    if (!x || !t || n < 2000 || m < 2000) {
        CHECK(0, "the committed files read");
        free(x), free(t);
        return;
    }
    unsigned char *b = malloc(n > m ? n : m);
    lc_load_desc f1 = {.frame = 1}, f20 = {.frame = 20};
    memcpy(b, x, n), be32(b, 1996);
    put("magic.xtc", b, n);
    load_must_fail(dev, tpath("magic.xtc"), ": byte 0: ", "frame 0: magic number 1996, expected 1995", NULL,
                   LC_ERROR_FORMAT, NULL);
    put("cut.xtc", x, 300);
    load_must_fail(dev, tpath("cut.xtc"), ": byte 88: ", "frame 0:", "compressed coordinates, but the file has",
                   LC_ERROR_FORMAT, NULL);
    memcpy(b, x, n), be32(b + 4, 215);
    put("count.xtc", b, n);
    load_must_fail(dev, tpath("count.xtc"), ": byte 52: ", "frame 0: the coordinates say 214 atoms, the header 215",
                   NULL, LC_ERROR_FORMAT, NULL);
    /* a stream that stops early: the declared bytes of frame 0 cut to 40 */
    uint32_t nb = (uint32_t)x[88] << 24 | (uint32_t)x[89] << 16 | (uint32_t)x[90] << 8 | x[91];
    memcpy(b, x, n), be32(b + 88, 40);
    put("stream.xtc", b, n);
    load_must_fail(dev, tpath("stream.xtc"), ": byte ", "frame 0: damaged compressed coordinates", "of 320)",
                   LC_ERROR_FORMAT, NULL);
    memcpy(b, x, n), be32(b + 84, 80);
    put("smallidx.xtc", b, n);
    load_must_fail(dev, tpath("smallidx.xtc"), ": byte 84: ", "frame 0: small-integer index 80, expected 9 to 72", NULL,
                   LC_ERROR_FORMAT, NULL);
    /* frame 1's magic damaged: frame 0 still loads, frame 1 names its byte */
    int64_t f1off = 92 + (nb + 3) / 4 * 4;
    memcpy(b, x, n), be32(b + f1off, 7);
    put("magic1.xtc", b, n);
    lc_volume *v = NULL;
    CHECK(lc_volume_load(dev, tpath("magic1.xtc"), NULL, &v) == LC_OK, "frame 0 loads when frame 1 is damaged: %s",
          v ? "" : lc_last_error());
    lc_volume_destroy(v);
    char where[64];
    snprintf(where, sizeof where, ": byte %lld: ", (long long)f1off);
    load_must_fail(dev, tpath("magic1.xtc"), where, "frame 1: magic number 7", NULL, LC_ERROR_FORMAT, &f1);
    load_must_fail(dev, dpath("adk_ca.xtc"), ": ", "frame 20 is past the end: the file holds 10 frames", NULL,
                   LC_ERROR_INVALID_ARGUMENT, &f20);
    /* a last frame cut short: the complete frames count, with a warning */
    put("tail.xtc", x, n - 100);
    lc_file_info fi;
    CHECK(lc_file_probe(dev, tpath("tail.xtc"), NULL, &fi) == LC_OK && fi.frames == 9,
          "an XTC cut inside its last frame: 9 whole frames (got %lld)", (long long)fi.frames);
    /* TRR */
    memcpy(b, t, m), be32(b, 1990);
    put("magic.trr", b, m);
    load_must_fail(dev, tpath("magic.trr"), ": byte 0: ", "frame 0: magic number 1990, expected 1993", NULL,
                   LC_ERROR_FORMAT, NULL);
    put("cut.trr", t, 2000);
    load_must_fail(dev, tpath("cut.trr"), ": byte 84: ", "the file ends inside frame 0", NULL, LC_ERROR_FORMAT, NULL);
    memcpy(b, t, m), be32(b + 24 + 7 * 4, 5000); /* x_size for 214 atoms would be 2568 (float) */
    put("xsize.trr", b, m);
    load_must_fail(dev, tpath("xsize.trr"), ": byte 32: ", "frame 0: block sizes box", "neither all float nor all double",
                   LC_ERROR_FORMAT, NULL);
    memcpy(b, t, m), be32(b + 24, 4);
    put("ir.trr", b, m);
    load_must_fail(dev, tpath("ir.trr"), ": byte 24: ", "frame 0: ir_size 4, expected 0", NULL, LC_ERROR_FORMAT, NULL);
    memcpy(b, t, m), be32(b + 24 + 10 * 4, (uint32_t)-5);
    put("natoms.trr", b, m);
    load_must_fail(dev, tpath("natoms.trr"), ": byte 64: ", "frame 0: atom count -5", NULL, LC_ERROR_FORMAT, NULL);
    free(b), free(x), free(t);
}

/* 1 if this build has the named optional feature. */
static int have_feature(const char *name)
{
    for (int i = 0; i < lc_feature_count(); i++) {
        lc_feature_info fi;
        if (lc_feature_get(i, &fi) == LC_OK && !strcmp(fi.name, name)) return fi.available;
    }
    return 0;
}

/* Replaces the first occurrence of `from` (same length as `to`) in a copy of src. */
static void put_edited(const char *name, const unsigned char *src, size_t n, const char *from, const char *to)
{
    unsigned char *b = malloc(n);
    memcpy(b, src, n);
    size_t k = strlen(from);
    for (size_t i = 0; i + k <= n; i++)
        if (!memcmp(b + i, from, k)) {
            memcpy(b + i, to, k);
            break;
        }
    put(name, b, n);
    free(b);
}

/* AMBER NetCDF (host/formats/ncdf.c): MDAnalysis's NCDFWriter file against its
 * reading, a restart made by ncgen from restart.cdl against the CDL's numbers,
 * damaged variants; without libnetcdf, one line naming the package. */
static void amber_netcdf(void)
{
    if (!have_feature("netcdf")) {
        lc_volume *v = NULL;
        lc_status s = lc_volume_load(dev, dpath("adk_ca.ncdf"), NULL, &v);
        CHECK(s == LC_ERROR_UNSUPPORTED && strstr(lc_last_error(), "libnetcdf-dev") && !strchr(lc_last_error(), '\n'),
              "without libnetcdf: adk_ca.ncdf fails naming libnetcdf-dev: %s", lc_last_error());
        lc_volume_destroy(v);
        printf("skip: this build has no netcdf feature: the AMBER NetCDF decoding cases\n");
        return;
    }
    against_ref(&lci_format_ncdf, "adk_ca.ncdf");
    lc_option sp = {"value", "speed"};
    lci_loaded l;
    const lc_particles_desc *d = load(&lci_format_ncdf, dpath("restart.ncrst"), 0, NULL, &sp, 1, &l);
    static const float want[9] = {1.5f, 2.25f, -3.125f, 2.0f, 2.25f, -3.125f, 1.25f, 2.75f, -3.0f};
    int same = d && d->count == 3;
    for (int i = 0; same && i < 9; i++) same = d->positions[i] == want[i];
    CHECK(same && fabsf(d->values[0] - 0.1f * 20.455f) < 1e-5f && fabsf(d->values[2] - 0.3f * 20.455f) < 1e-5f,
          "restart.ncrst (ncgen, AMBERRESTART): the CDL's 3 atoms, speeds |v| x scale_factor 20.455");
    if (d) lci_loaded_free(&l);
    d = load(&lci_format_ncdf, dpath("adk_ca.ncdf"), 2, dpath("adk_ca.gro"), &sp, 1, &l);
    CHECK(d && d->count == 214 && d->radii[5] == 0.76f && d->values, "adk_ca.ncdf --topology adk_ca.gro --value speed");
    if (d) lci_loaded_free(&l);
    size_t n = 0, m = 0;
    unsigned char *r = slurp(dpath("restart.ncrst"), &n), *t = slurp(dpath("adk_ca.ncdf"), &m);
    if (!r || !t) {
        CHECK(0, "the NetCDF files read");
        free(r), free(t);
        return;
    }
    put_edited("conv.ncrst", r, n, "AMBERRESTART", "AMBERXESTART");
    load_must_fail(dev, tpath("conv.ncrst"), ": ", "Conventions does not name AMBER", NULL, LC_ERROR_FORMAT, NULL);
    put_edited("var.ncrst", r, n, "coordinates", "coordinatez");
    load_must_fail(dev, tpath("var.ncrst"), ": ", "variable coordinates:", "(netCDF)", LC_ERROR_FORMAT, NULL);
    put_edited("dim.ncrst", r, n, "spatial", "spatiaX");
    load_must_fail(dev, tpath("dim.ncrst"), ": ", "variable coordinates: dimension 1 is 'spatiaX'", NULL,
                   LC_ERROR_FORMAT, NULL);
    put("cut.ncdf", t, m - 3000);
    lc_load_desc f4 = {.frame = 4};
    load_must_fail(dev, tpath("cut.ncdf"), ": byte 23332: ", "the file ends before the data its header declares", NULL,
                   LC_ERROR_FORMAT, &f4);
    put("head.ncdf", t, 200);
    load_must_fail(dev, tpath("head.ncdf"), ": byte 44: ", "damaged netCDF header", NULL, LC_ERROR_FORMAT, NULL);
    lc_load_desc f5 = {.frame = 5};
    load_must_fail(dev, dpath("adk_ca.ncdf"), ": ", "frame 5 is past the end: the file holds 5 frames", NULL,
                   LC_ERROR_INVALID_ARGUMENT, &f5);
    free(r), free(t);
}

int main(int argc, char **argv)
{
    if (argc < 4) return fprintf(stderr, "usage: test_traj SHARED_DATA_DIR TMP_DIR TRAJ_DATA_DIR\n"), 2;
    shared = argv[1];
    tmp = argv[2];
    traj_dir = argv[3];
    if (lc_device_create(NULL, &dev) != LC_OK) return 1;
    against_ref(&lci_format_xtc, "adk_ca.xtc");
    against_ref(&lci_format_xtc, "adk2.xtc");
    against_ref(&lci_format_xtc, "small.xtc");
    against_ref(&lci_format_xtc, "wide.xtc");
    against_ref(&lci_format_xtc, "gmx_ca.xtc");
    against_ref(&lci_format_trr, "adk_ca.trr");
    against_ref(&lci_format_trr, "gmx_ca_d.trr");
    trr_values();
    topologies();
    malformed();
    amber_netcdf();
    lc_device_destroy(dev);
    return check_summary("traj");
}
