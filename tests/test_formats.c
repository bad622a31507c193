/* The formats registry (host/formats/registry.c) through the public API:
 * every row of lc_format_get, detection (magic bytes over the extension, the
 * named format over both), option routing and errors naming the key, kind
 * options, lc_file_probe on the shared data, and the optional features: gzip
 * input and JSON transfer functions work with zlib and json-c and fail with
 * one line naming the package without them. Args: DATA_DIR TMP_DIR. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "check.h"
#include "tmpfiles.h"
#include "gzip_stored.h"
#include "host/internal.h"

static lc_device *dev;

static const char pdb[] =
    "HEADER    TEST\n"
    "ATOM      1  N   ALA A   1      11.104   6.134  -6.504  1.00  0.00           N\n"
    "ATOM      2  CA  ALA A   1      11.639   6.071  -5.147  1.00  0.00           C\n"
    "HETATM    3 FE   HEM A   2       1.000   2.000   3.000  1.00  0.00\n";
static const char xyz[] = "3\ncomment\nC 0 0 0\nO 1 2 3\nN 2 2 2\n";
static const char nrrd_head[] = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 3 4\nencoding: raw\n\n";

/* Loads path with format fmt (NULL = detect) and n key/value pairs. */
static lc_status load(const char *path, const char *fmt, lc_volume **v, int n, ...)
{
    lc_option o[8];
    va_list ap;
    va_start(ap, n);
    for (int i = 0; i < n; i++) o[i].key = va_arg(ap, const char *), o[i].value = va_arg(ap, const char *);
    va_end(ap);
    *v = NULL;
    return lc_volume_load(dev, path, &(lc_load_desc){.format = fmt, .options = o, .noptions = n}, v);
}

static size_t particle_count(const lc_volume *v)
{
    lc_particles_info pi;
    return v && lc_particles_get_info(v, &pi) == LC_OK ? pi.count : (size_t)-1;
}

static void rows(void)
{
    static const char *const want[] = {"nrrd", "metaimage", "pdb", "rbf", "rbf-binary", "xyz",
                                       "gro", "raw-particles", "raw-volume", "dcd", "xtc", "trr", "ncdf", "lammps", "gadget",
                                       "nifti", "vtk", "hdf5", "mmcif", "csv", "dicom"};
    int n = lc_format_count(), found = 0;
    CHECK(n == (int)(sizeof want / sizeof want[0]), "lc_format_count = %d", n);
    for (int i = 0; i < n; i++) {
        lc_format_info f;
        int ok = lc_format_get(i, &f) == LC_OK && f.name && f.name[0] && f.extensions && f.extensions[0] == '.' &&
                 f.options && f.description && f.description[0] && f.package &&
                 f.kind >= LC_KIND_NONE && f.kind < LC_KIND_COUNT &&
                 /* a format behind an optional library names its package; only HDF5 leaves the kind to the file */
                 (f.available == 1 || f.package[0]) && (f.kind != LC_KIND_NONE || !strcmp(f.name, "hdf5"));
        if (ok && !strcmp(f.name, "nifti")) ok = f.available == LC_HAVE_NIFTI && !strcmp(f.package, "libnifti2-dev");
        if (ok && !strcmp(f.name, "hdf5")) ok = f.available == LC_HAVE_HDF5 && !strcmp(f.package, "libhdf5-dev");
        if (ok && !strcmp(f.name, "ncdf")) ok = f.available == LC_HAVE_NETCDF && !strcmp(f.package, "libnetcdf-dev");
        if (ok && !strcmp(f.name, "dicom")) ok = f.available == LC_HAVE_GDCM && !strcmp(f.package, "libgdcm-dev");
        for (int j = 0; ok && j < i; j++) {
            lc_format_info g;
            ok &= lc_format_get(j, &g) == LC_OK && strcmp(g.name, f.name) != 0;
        }
        for (size_t w = 0; ok && w < sizeof want / sizeof want[0]; w++) found += !strcmp(want[w], f.name);
        CHECK(ok, "row %d: %s, %s, '%s', options '%s', available", i, ok ? f.name : "?",
              ok ? lc_kind_name(f.kind) : "?", ok ? f.extensions : "?", ok ? f.options : "?");
    }
    CHECK(found == n, "every expected format is a row");
    lc_format_info f;
    CHECK(lc_format_get(-1, &f) == LC_ERROR_INVALID_ARGUMENT && lc_format_get(n, &f) == LC_ERROR_INVALID_ARGUMENT &&
              lc_format_get(0, NULL) == LC_ERROR_INVALID_ARGUMENT,
          "lc_format_get out of range or without out fails");
    int nf = lc_feature_count();
    lc_feature_info z = {0}, j = {0}, l = {0};
    for (int i = 0; i < nf; i++) {
        lc_feature_info x;
        if (lc_feature_get(i, &x) != LC_OK) continue;
        if (!strcmp(x.name, "zlib")) z = x;
        if (!strcmp(x.name, "json")) j = x;
        if (!strcmp(x.name, "lapacke")) l = x;
    }
    CHECK(l.name && l.available == LC_HAVE_LAPACKE && !strcmp(l.package, "liblapacke-dev"),
          "feature lapacke %d (this build: LC_HAVE_LAPACKE %d)", l.available, LC_HAVE_LAPACKE);
    CHECK(nf == 9 && z.name && j.name && z.available == LC_HAVE_ZLIB && j.available == LC_HAVE_JSON &&
              !strcmp(z.package, "zlib1g-dev") && !strcmp(j.package, "libjson-c-dev") &&
              lc_feature_get(nf, &z) == LC_ERROR_INVALID_ARGUMENT,
          "features: zlib %d, json %d (this build: LC_HAVE_ZLIB %d, LC_HAVE_JSON %d)", z.available, j.available,
          LC_HAVE_ZLIB, LC_HAVE_JSON);
}

static void detection(void)
{
    char buf[512];
    unsigned char vox[24];
    for (int i = 0; i < 24; i++) vox[i] = (unsigned char)(10 * i);
    memcpy(buf, nrrd_head, strlen(nrrd_head));
    memcpy(buf + strlen(nrrd_head), vox, sizeof vox);
    put("nrrd_named.raw", buf, strlen(nrrd_head) + sizeof vox);
    put("pdb_named.txt", pdb, strlen(pdb));
    put("xyz_named.pdb", xyz, strlen(xyz));
    lc_file_info fi;
    lc_volume *v;
    CHECK(lc_file_probe(dev, tpath("nrrd_named.raw"), NULL, &fi) == LC_OK && !strcmp(fi.format, "nrrd") &&
              fi.kind == LC_KIND_GRID,
          "an NRRD named .raw is probed as nrrd (magic beats extension)");
    lc_grid_info gi;
    CHECK(load(tpath("nrrd_named.raw"), NULL, &v, 0) == LC_OK && lc_grid_get_info(v, &gi) == LC_OK &&
              gi.size[0] == 2 && gi.size[2] == 4 && gi.value_max == 230.0f,
          "... and read as NRRD: 2x3x4, max 230");
    lc_volume_destroy(v);
    CHECK(lc_file_probe(dev, tpath("pdb_named.txt"), NULL, &fi) == LC_OK && !strcmp(fi.format, "pdb"),
          "a PDB named .txt is found by its records");
    CHECK(load(tpath("pdb_named.txt"), NULL, &v, 0) == LC_OK && particle_count(v) == 3, "... and read: 3 atoms");
    lc_volume_destroy(v);
    CHECK(load(tpath("xyz_named.pdb"), NULL, &v, 0) == LC_ERROR_FORMAT && strstr(lc_last_error(), "no ATOM"),
          "XYZ text named .pdb goes to the PDB reader by extension: %s", lc_last_error());
    CHECK(load(tpath("xyz_named.pdb"), "xyz", &v, 0) == LC_OK && particle_count(v) == 3,
          "the named format overrides the extension: xyz reads it");
    lc_volume_destroy(v);
    CHECK(load(tpath("nrrd_named.raw"), "raw-volume", &v, 2, "size", "2,3,4", "type", "uint8") == LC_ERROR_FORMAT &&
              strstr(lc_last_error(), "holds") && strstr(lc_last_error(), "need 24"),
          "the named format overrides the magic bytes: raw-volume sees header + voxels: %s", lc_last_error());
    CHECK(load(tpath("xyz_named.pdb"), "nope", &v, 0) == LC_ERROR_INVALID_ARGUMENT &&
              strstr(lc_last_error(), "unknown format 'nope'") && strstr(lc_last_error(), "gro"),
          "unknown format name: %s", lc_last_error());
    put("what.abc", "hello\n", 6);
    CHECK(lc_file_probe(dev, tpath("what.abc"), NULL, &fi) == LC_ERROR_UNSUPPORTED &&
              strstr(lc_last_error(), "unknown file format") && strstr(lc_last_error(), ".abc"),
          "unknown extension: %s", lc_last_error());
    CHECK(load(tpath("absent.xyz"), NULL, &v, 0) == LC_ERROR_IO && strstr(lc_last_error(), "absent.xyz: cannot open"),
          "missing file: %s", lc_last_error());
}

static void options(void)
{
    put("o.xyz", xyz, strlen(xyz));
    const char *x = tpath("o.xyz"), *n = tpath("nrrd_named.raw");
    lc_volume *v;
    CHECK(load(x, NULL, &v, 1, "bogus", "1") == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "'bogus'") &&
              strstr(lc_last_error(), "xyz files") && strstr(lc_last_error(), "leaf_size"),
          "unknown option key: %s", lc_last_error());
    CHECK(load(n, NULL, &v, 1, "radius", "1") == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "'radius'") &&
              strstr(lc_last_error(), "nrrd"),
          "a particle option on a volume: %s", lc_last_error());
    lc_particles_info pi;
    CHECK(load(x, NULL, &v, 1, "leaf_size", "8") == LC_OK && lc_particles_get_info(v, &pi) == LC_OK &&
              pi.leaf_size == 8,
          "kind option leaf_size = 8 applied");
    lc_volume_destroy(v);
    lc_grid_info gi;
    CHECK(load(n, NULL, &v, 1, "brick", "2") == LC_OK && lc_grid_get_info(v, &gi) == LC_OK && gi.brick == 2,
          "kind option brick = 2 applied");
    lc_volume_destroy(v);
    static const struct {
        int nrrd;
        const char *fmt, *key, *value;
    } bad[] = {
        {0, NULL, "leaf_size", "abc"}, {0, NULL, "radius", "abc"}, {0, NULL, "radius_scale", "-1"},
        {0, NULL, "fields", "bogus"}, {0, "raw-particles", "count", "-1"}, {1, NULL, "brick", "3"},
        {1, NULL, "spacing", "1,x,1"}, {1, NULL, "type", "float64"}, {1, "raw-volume", "size", "2,3"},
        {1, "raw-volume", "endian", "middle"}, {1, NULL, "origin", "1,2"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char key[64];
        snprintf(key, sizeof key, "%s", bad[i].key);
        lc_status s = load(bad[i].nrrd ? n : x, bad[i].fmt, &v, 1, bad[i].key, bad[i].value);
        CHECK(s == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), key) && strstr(lc_last_error(), bad[i].value),
              "%s = '%s' fails naming the key: %s", bad[i].key, bad[i].value, lc_last_error());
        lc_volume_destroy(v);
    }
}

static void probe_shared(const char *data_dir)
{
    static const struct {
        const char *file, *format;
        lc_kind kind;
        int gzip;
    } files[] = {
        {"particles/1tii.pdb", "pdb", LC_KIND_PARTICLES, 0},
        {"particles/1tw7_solvated.pdb", "pdb", LC_KIND_PARTICLES, 0},
        {"particles/bigbox_water.gro.gz", "gro", LC_KIND_PARTICLES, 1},
        {"volumes/engine.nhdr", "nrrd", LC_KIND_GRID, 0},
        {"volumes/neghip.nhdr", "nrrd", LC_KIND_GRID, 0},
        {"volumes/headsq.nhdr", "nrrd", LC_KIND_GRID, 0},
        {"volumes/hydrogen.nhdr", "nrrd", LC_KIND_GRID, 0},
        {"volumes/embryo.nhdr", "nrrd", LC_KIND_GRID, 0},
        {"volumes/HeadMRVolume.mhd", "metaimage", LC_KIND_GRID, 0},
        {"particles/adk.dcd", "dcd", LC_KIND_PARTICLES, 0},
        {"particles/adk.psf", NULL, LC_KIND_NONE, 0}, /* a topology: read as a DCD's companion */
        {"particles/gadget_galaxy.dat", "gadget", LC_KIND_PARTICLES, 0},
        {"particles/gadget_lcdm_gas.dat", "gadget", LC_KIND_PARTICLES, 0},
    };
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        char p[1024];
        snprintf(p, sizeof p, "%s/%s", data_dir, files[i].file);
        lc_file_info fi;
        lc_status s = lc_file_probe(dev, p, NULL, &fi);
        if (!files[i].format)
            CHECK(s == LC_ERROR_UNSUPPORTED && strstr(lc_last_error(), "unknown file format"),
                  "probe %s: not a format lanecast reads", files[i].file);
        else
            CHECK(s == LC_OK && !strcmp(fi.format, files[i].format) && fi.kind == files[i].kind &&
                      fi.gzip == files[i].gzip,
                  "probe %s: %s, %s%s", files[i].file, files[i].format, lc_kind_name(files[i].kind),
                  files[i].gzip ? ", gzip" : "");
    }
    char p[1024];
    snprintf(p, sizeof p, "%s/volumes/engine.nhdr", data_dir);
    lc_volume *v;
    lc_status s = load(p, NULL, &v, 0);
    if (LC_HAVE_ZLIB) CHECK(s == LC_OK, "engine.nhdr (gzip encoding) loads with zlib");
    else
        CHECK(s == LC_ERROR_UNSUPPORTED && strstr(lc_last_error(), "engine.nhdr:") &&
                  strstr(lc_last_error(), "gzip encoding needs zlib") && strstr(lc_last_error(), "zlib1g-dev"),
              "engine.nhdr without zlib: %s", lc_last_error());
    lc_volume_destroy(v);
}

static void optional_features(void)
{
    /* gzip input made without zlib (stored deflate blocks) */
    gzs_write(tpath("g.xyz.gz"), xyz, strlen(xyz));
    gzs_write(tpath("p.dat.gz"), pdb, strlen(pdb));
    unsigned char vox[24];
    for (int i = 0; i < 24; i++) vox[i] = (unsigned char)i;
    gzs_write(tpath("vox.gz"), vox, sizeof vox);
    const char *nh = "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 3 4\nencoding: gzip\ndata file: vox.gz\n";
    put("gz.nhdr", nh, strlen(nh));
    const char *mh = "NDims = 3\nDimSize = 2 3 4\nElementType = MET_UCHAR\nCompressedData = True\nElementDataFile = vox.gz\n";
    put("z.mhd", mh, strlen(mh));
    lc_file_info fi;
    lc_volume *v;
    CHECK(lc_file_probe(dev, tpath("g.xyz.gz"), NULL, &fi) == LC_OK && !strcmp(fi.format, "xyz") && fi.gzip == 1,
          "probe g.xyz.gz: xyz, gzip (by extension, .gz looked through)");
    lc_status sx = load(tpath("g.xyz.gz"), NULL, &v, 0);
    size_t nx = particle_count(v);
    char msg[LCI_MSG_MAX];
    snprintf(msg, sizeof msg, "%s", lc_last_error());
    lc_volume_destroy(v);
    lc_status sn = load(tpath("gz.nhdr"), NULL, &v, 0);
    lc_volume_destroy(v);
    char nmsg[LCI_MSG_MAX];
    snprintf(nmsg, sizeof nmsg, "%s", lc_last_error());
    lc_status sm = load(tpath("z.mhd"), NULL, &v, 0);
    lc_volume_destroy(v);
    if (LC_HAVE_ZLIB) {
        CHECK(sx == LC_OK && nx == 3, "g.xyz.gz: 3 atoms");
        CHECK(sn == LC_OK && sm == LC_OK, "NRRD gzip encoding and MetaImage CompressedData read");
        CHECK(lc_file_probe(dev, tpath("p.dat.gz"), NULL, &fi) == LC_OK && !strcmp(fi.format, "pdb"),
              "a gzip PDB named .dat.gz is found by its records inside the gzip stream");
    } else {
        char want[1200];
        snprintf(want, sizeof want,
                 "%s: gzip-compressed input needs zlib, which this build of lanecast lacks (install zlib1g-dev and "
                 "rebuild)",
                 tpath("g.xyz.gz"));
        CHECK(sx == LC_ERROR_UNSUPPORTED && !strcmp(msg, want), "g.xyz.gz without zlib: %s", msg);
        CHECK(sn == LC_ERROR_UNSUPPORTED && strstr(nmsg, "gz.nhdr:5: gzip encoding needs zlib"), "gz.nhdr: %s", nmsg);
        CHECK(sm == LC_ERROR_UNSUPPORTED && strstr(lc_last_error(), "z.mhd:4: CompressedData = True needs zlib"),
              "z.mhd: %s", lc_last_error());
    }
    const char *tf = "{\"color\": [[0, 1, 0, 0], [1, 1, 1, 1]], \"opacity\": [[0, 0], [1, 2]]}";
    put("tf.json", tf, strlen(tf));
    lc_tf *t = NULL, *t2 = NULL;
    lc_status sp = lc_tf_parse(dev, tf, "inline.json", &t), sl = lc_tf_load(dev, tpath("tf.json"), &t2);
    if (LC_HAVE_JSON)
        CHECK(sp == LC_OK && sl == LC_OK && lc_tf_field_count(t) == 1 && lc_tf_field_count(t2) == 1,
              "JSON transfer functions parse and load");
    else
        CHECK(sp == LC_ERROR_UNSUPPORTED && sl == LC_ERROR_UNSUPPORTED && !t && !t2 &&
                  strstr(lc_last_error(), "tf.json: a JSON transfer function needs json-c") &&
                  strstr(lc_last_error(), "install libjson-c-dev and rebuild"),
              "JSON TF without json-c: %s", lc_last_error());
    lc_tf_destroy(t);
    lc_tf_destroy(t2);
}

/* lc_load_desc.progress: fractions in [0, 1], non-decreasing, ending at 1. */
typedef struct prog {
    float f[256];
    int n, bad;
} prog;

static void on_progress(void *user, float f)
{
    prog *p = user;
    if (p->n > 0 && f < p->f[p->n - 1 < 255 ? p->n - 1 : 255]) p->bad = 1;
    if (!(f >= 0.0f && f <= 1.0f)) p->bad = 1;
    if (p->n < 256) p->f[p->n] = f;
    p->n++;
}

static void load_progress(void)
{
    /* a text file of 40000 lines (the text reader reports every 4096 lines) */
    FILE *f = fopen(tpath("prog.xyz"), "w");
    if (!f) return;
    fprintf(f, "40000\nprogress\n");
    for (int i = 0; i < 40000; i++) fprintf(f, "C %d %d %d\n", i % 40, (i / 40) % 40, i / 1600);
    fclose(f);
    prog p = {.n = 0};
    lc_volume *v = NULL;
    lc_status s = lc_volume_load(dev, tpath("prog.xyz"), &(lc_load_desc){.progress = on_progress, .progress_user = &p}, &v);
    CHECK(s == LC_OK && p.n >= 5 && !p.bad && p.f[0] == 0.0f && p.f[(p.n < 256 ? p.n : 256) - 1] == 1.0f &&
              p.n <= 110,
          "progress of a 40000-line XYZ: %d calls, from 0 to 1, non-decreasing", p.n);
    if (p.n > 2) CHECK(p.f[1] > 0.0f && p.f[1] < 1.0f, "... with a fraction in between (%g)", (double)p.f[1]);
    lc_volume_destroy(v);
    /* a raw volume (NRRD + voxels) */
    unsigned char vox[24] = {0};
    char buf[sizeof nrrd_head + 24];
    memcpy(buf, nrrd_head, sizeof nrrd_head - 1);
    memcpy(buf + sizeof nrrd_head - 1, vox, 24);
    put("prog.nrrd", buf, sizeof nrrd_head - 1 + 24);
    memset(&p, 0, sizeof p);
    s = lc_volume_load(dev, tpath("prog.nrrd"), &(lc_load_desc){.progress = on_progress, .progress_user = &p}, &v);
    CHECK(s == LC_OK && p.n >= 2 && !p.bad && p.f[p.n - 1] == 1.0f, "progress of a NRRD volume: %d calls ending at 1", p.n);
    lc_volume_destroy(v);
    /* a failing load reports no 1 */
    put("prog_bad.xyz", "2\nc\nC 0 0 0\n", 12);
    memset(&p, 0, sizeof p);
    s = lc_volume_load(dev, tpath("prog_bad.xyz"), &(lc_load_desc){.progress = on_progress, .progress_user = &p}, &v);
    CHECK(s == LC_ERROR_FORMAT && (p.n == 0 || p.f[p.n - 1] < 1.0f), "a failing load never reports 1 (%d calls)", p.n);
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: test_formats DATA_DIR TMP_DIR\n");
        return 2;
    }
    tmp = argv[2];
    if (lc_device_create(&(lc_device_desc){.threads = 2}, &dev) != LC_OK) return 1;
    rows();
    detection();
    options();
    optional_features();
    load_progress();
    char p[1024];
    struct stat st;
    snprintf(p, sizeof p, "%s/particles/1tii.pdb", argv[1]);
    int have_data = stat(p, &st) == 0;
    if (have_data) probe_shared(argv[1]);
    lc_device_destroy(dev);
    int rc = check_summary("test_formats");
    if (!rc && !have_data) {
        printf("skip: the shared data is absent (%s; see ../shared/data/README.md or -Ddata_dir)\n", argv[1]);
        return 77;
    }
    return rc;
}
