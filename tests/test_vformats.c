/* The formats users have (issue 11): NIfTI-1/2 (written byte by byte here:
 * flips and a permutation, a marked voxel found in world space, scaling, an
 * oblique sform, 4-D frames, gzip), VTK legacy STRUCTURED_POINTS (ASCII and
 * big-endian BINARY, arrays read past, scalars = NAME), HDF5 (snapshots and
 * datasets written with the HDF5 C API when the build has it), mmCIF (a few
 * atoms of 1tii.pdb, compared with the PDB file read here by columns),
 * CSV particles with named columns, and PDB alternate locations. Each
 * format's malformed variants must fail with one line naming the file and
 * the line or byte. Without libnifti2 / libhdf5 those formats must fail
 * with the one line naming the Debian package. Args: DATA_DIR TMP_DIR. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "tmpfiles.h"
#include "gzip_stored.h"
#include "host/formats/format.h"
#if LC_HAVE_HDF5
#include <hdf5.h>
#endif

static lc_device *dev;
static char warned[2048];

static void on_log(void *user, lc_log_level level, const char *msg)
{
    (void)user;
    if (level == LC_LOG_WARNING) snprintf(warned, sizeof warned, "%s", msg);
}

static const void *read_with(const lci_format *fmt, const char *path, int64_t frame, const lc_option *o, int n,
                             lci_loaded *l)
{
    memset(l, 0, sizeof *l);
    lc_load_desc d = {.frame = frame, .options = o, .noptions = n};
    lci_read_args a = {path, &d, o, n, NULL};
    return fmt->read && fmt->read(dev, &a, l) == LC_OK ? l->desc : NULL;
}

/* lc_volume_load must fail with want and one line starting "FILE<where>" and holding says. */
static void must_fail(const char *name, const char *where, const char *says, lc_status want, const lc_load_desc *d)
{
    load_must_fail(dev, tpath(name), where, says, NULL, want, d);
}

static lc_volume *load(const char *name, const lc_option *o, int n, int64_t frame)
{
    lc_load_desc d = {.frame = frame, .options = o, .noptions = n};
    lc_volume *v = NULL;
    if (lc_volume_load(dev, tpath(name), &d, &v) != LC_OK) printf("     load %s: %s\n", name, lc_last_error());
    return v;
}

static float sample(const lc_volume *v, float x, float y, float z)
{
    float p[3] = {x, y, z}, r = NAN;
    if (!v || lc_volume_sample(dev, v, 1, p, &r, NULL) != LC_OK) return NAN;
    return r;
}

static int near(float a, float b) { return fabsf(a - b) <= 1e-4f * (1.0f + fabsf(b)); }

/* ------------------------------------------------------------------ NIfTI */

typedef struct nii {
    unsigned char b[352 + 4096];
    size_t n;
} nii;

static void le16(unsigned char *p, int v) { p[0] = (unsigned char)v, p[1] = (unsigned char)(v >> 8); }
static void le32f(unsigned char *p, float f) { memcpy(p, &f, 4); } /* the test machine is little-endian */

/* A NIfTI-1 single file: dims, datatype, bitpix, pixdim, sform rows, scaling, data. */
static void nii_make(nii *w, const int dim[5], int dt, int bitpix, const float srow[3][4], float slope, float inter,
                     const void *data, size_t bytes)
{
    memset(w, 0, sizeof *w);
    unsigned char *h = w->b;
    int32_t sz = 348;
    memcpy(h, &sz, 4);
    for (int k = 0; k < 5; k++) le16(h + 40 + 2 * k, dim[k]);
    for (int k = 5; k < 8; k++) le16(h + 40 + 2 * k, 1);
    le16(h + 70, dt);
    le16(h + 72, bitpix);
    le32f(h + 76, 1.0f);
    for (int k = 1; k < 4; k++) le32f(h + 76 + 4 * k, fabsf(srow[k - 1][0]) + fabsf(srow[k - 1][1]) + fabsf(srow[k - 1][2]));
    le32f(h + 108, 352.0f);
    le32f(h + 112, slope);
    le32f(h + 116, inter);
    le16(h + 254, 1); /* sform_code: scanner */
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 4; c++) le32f(h + 280 + 16 * r + 4 * c, srow[r][c]);
    memcpy(h + 344, "n+1", 4);
    memcpy(h + 352, data, bytes);
    w->n = 352 + bytes;
}

static void nifti(void)
{
    /* 3 x 4 x 5 int16 voxels; world x = -2 j + 10, y = 3 k - 1, z = -1.5 i + 4:
       a permutation (i->z, j->x, k->y) with flips on x and z */
    const int dim[5] = {3, 3, 4, 5, 1};
    const float srow[3][4] = {{0, -2, 0, 10}, {0, 0, 3, -1}, {-1.5f, 0, 0, 4}};
    int16_t vox[60];
    for (int i = 0; i < 60; i++) vox[i] = (int16_t)i;
    vox[1 + 3 * (2 + 4 * 3)] = 1000; /* the mark at (i, j, k) = (1, 2, 3) */
    nii w;
    nii_make(&w, dim, 4, 16, srow, 0.0f, 0.0f, vox, sizeof vox);
    put("perm.nii", w.b, w.n);
    gzs_write(tpath("perm.nii.gz"), w.b, w.n);
    if (!LC_HAVE_NIFTI) {
        must_fail("perm.nii", ": ", "install libnifti2-dev and rebuild", LC_ERROR_UNSUPPORTED, NULL);
        return;
    }
    lc_file_info fi;
    CHECK(lc_file_probe(dev, tpath("perm.nii"), NULL, &fi) == LC_OK && !strcmp(fi.format, "nifti") &&
              fi.kind == LC_KIND_GRID && fi.frames == 1,
          "probe perm.nii: nifti, grid, 1 frame");
    const char *names[2] = {"perm.nii", "perm.nii.gz"};
    for (int g = 0; g < 2; g++) {
        lc_volume *v = load(names[g], NULL, 0, 0);
        lc_grid_info gi;
        int ok = v && lc_grid_get_info(v, &gi) == LC_OK;
        CHECK(ok && gi.size[0] == 4 && gi.size[1] == 5 && gi.size[2] == 3 && gi.type == LC_VALUE_INT16 &&
                  gi.spacing.x == 2 && gi.spacing.y == 3 && gi.spacing.z == 1.5f && gi.origin.x == 4 &&
                  gi.origin.y == -1 && gi.origin.z == 1,
              "%s: 4 x 5 x 3 int16 (j, k, i), spacing 2 3 1.5, origin 4 -1 1 (got %d %d %d, %g %g %g, %g %g %g)",
              names[g], ok ? gi.size[0] : 0, ok ? gi.size[1] : 0, ok ? gi.size[2] : 0, ok ? (double)gi.spacing.x : 0,
              ok ? (double)gi.spacing.y : 0, ok ? (double)gi.spacing.z : 0, ok ? (double)gi.origin.x : 0,
              ok ? (double)gi.origin.y : 0, ok ? (double)gi.origin.z : 0);
        /* the mark where the sform puts it; every voxel where the sform puts it */
        float mark = sample(v, 6.0f, 8.0f, 2.5f);
        int all = 1;
        for (int k = 0; k < 5; k++)
            for (int j = 0; j < 4; j++)
                for (int i = 0; i < 3; i++) {
                    float x = -2.0f * j + 10, y = 3.0f * k - 1, z = -1.5f * i + 4;
                    all &= near(sample(v, x, y, z), vox[i + 3 * (j + 4 * k)]);
                }
        CHECK(mark == 1000.0f && all, "%s: voxel (1,2,3) = 1000 at world (6, 8, 2.5) (got %g); all 60 voxels at their "
              "sform positions", names[g], (double)mark);
        lc_volume_destroy(v);
    }
    /* scaling: uint8 * 0.5 + 10 -> float32; identity sform -> no reorder */
    const float id[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
    unsigned char u8[8] = {0, 1, 2, 3, 4, 5, 6, 200};
    nii_make(&w, (const int[5]){3, 2, 2, 2, 1}, 2, 8, id, 0.5f, 10.0f, u8, 8);
    put("scaled.nii", w.b, w.n);
    lc_volume *v = load("scaled.nii", NULL, 0, 0);
    lc_grid_info gi;
    CHECK(v && lc_grid_get_info(v, &gi) == LC_OK && gi.type == LC_VALUE_FLOAT32 && sample(v, 1, 1, 1) == 110.0f &&
              sample(v, 1, 0, 0) == 10.5f,
          "scaled.nii: uint8 * 0.5 + 10 as float32 (voxel 7 = 110, voxel 1 = 10.5)");
    lc_volume_destroy(v);
    /* float64 -> float32, unscaled */
    double f64[8] = {0.25, 1, 2, 3, 4, 5, 6, 7};
    nii_make(&w, (const int[5]){3, 2, 2, 2, 1}, 64, 64, id, 0.0f, 0.0f, f64, sizeof f64);
    put("f64.nii", w.b, w.n);
    v = load("f64.nii", NULL, 0, 0);
    CHECK(v && lc_grid_get_info(v, &gi) == LC_OK && gi.type == LC_VALUE_FLOAT32 && sample(v, 0, 0, 0) == 0.25f,
          "f64.nii: float64 read as float32");
    lc_volume_destroy(v);
    /* an oblique sform (10 degrees about z): nearest frame, centre kept, a warning */
    float c = cosf(10.0f * (float)M_PI / 180.0f), s = sinf(10.0f * (float)M_PI / 180.0f);
    const float ob[3][4] = {{c, -s, 0, 5}, {s, c, 0, 6}, {0, 0, 1, 7}};
    nii_make(&w, (const int[5]){3, 2, 2, 2, 1}, 2, 8, ob, 0.0f, 0.0f, u8, 8);
    put("oblique.nii", w.b, w.n);
    warned[0] = 0;
    v = load("oblique.nii", NULL, 0, 0);
    float cx = 5 + 0.5f * c - 0.5f * s, cy = 6 + 0.5f * s + 0.5f * c;
    CHECK(v && lc_grid_get_info(v, &gi) == LC_OK && strstr(warned, "oblique") && strstr(warned, "10.00 degrees") &&
              near(gi.origin.x + 0.5f * gi.spacing.x, cx) && near(gi.origin.y + 0.5f * gi.spacing.y, cy) &&
              near(gi.spacing.x, 1.0f),
          "oblique.nii: nearest axis-aligned frame about the true centre, warned: %s", warned);
    lc_volume_destroy(v);
    /* 4-D: two volumes are two frames */
    unsigned char two[16];
    for (int i = 0; i < 16; i++) two[i] = (unsigned char)(i < 8 ? 1 : 2);
    nii_make(&w, (const int[5]){4, 2, 2, 2, 2}, 2, 8, id, 0.0f, 0.0f, two, 16);
    put("t.nii", w.b, w.n);
    v = load("t.nii", NULL, 0, 1);
    CHECK(lc_file_probe(dev, tpath("t.nii"), NULL, &fi) == LC_OK && fi.frames == 2 && sample(v, 0, 0, 0) == 2.0f,
          "t.nii: 2 frames, frame 1 is the second volume");
    lc_volume_destroy(v);
    /* malformed */
    nii_make(&w, dim, 4, 16, srow, 0.0f, 0.0f, vox, sizeof vox);
    unsigned char keep[4];
    memcpy(keep, w.b, 4);
    w.b[0] = 0x55;
    put("badsize.nii", w.b, w.n);
    must_fail("badsize.nii", ": byte 0: ", "sizeof_hdr", LC_ERROR_FORMAT, NULL);
    memcpy(w.b, keep, 4);
    le16(w.b + 70, 128); /* RGB24 */
    put("rgb.nii", w.b, w.n);
    must_fail("rgb.nii", ": byte 70: ", "datatype 128", LC_ERROR_FORMAT, NULL);
    le16(w.b + 70, 4);
    put("cut.nii", w.b, w.n - 10);
    must_fail("cut.nii", ": byte 462: ", "ends before the 120 bytes of voxels", LC_ERROR_FORMAT, NULL);
    le16(w.b + 44, 1); /* dim[2] = 1: a 2-D image */
    put("flat.nii", w.b, w.n);
    must_fail("flat.nii", ": byte 44: ", "2 or more", LC_ERROR_FORMAT, NULL);
    le16(w.b + 44, 4);
    memcpy(w.b + 344, "xx1", 4);
    put("magic.nii", w.b, w.n);
    must_fail("magic.nii", ": byte 344: ", "magic", LC_ERROR_FORMAT, NULL);
}

/* ------------------------------------------------------------------ VTK */

static void be32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24), p[1] = (unsigned char)(v >> 16), p[2] = (unsigned char)(v >> 8), p[3] = (unsigned char)v;
}

static void vtk(void)
{
    const char *ascii = "# vtk DataFile Version 3.0\n"
                        "a 3 x 2 x 2 grid\n"
                        "ASCII\n"
                        "DATASET STRUCTURED_POINTS\n"
                        "DIMENSIONS 3 2 2\n"
                        "ORIGIN 1 2 3\n"
                        "SPACING 0.5 1 2\n"
                        "POINT_DATA 12\n"
                        "VECTORS wind float\n"
                        "0 0 0 1 1 1 2 2 2 3 3 3 4 4 4 5 5 5 6 6 6 7 7 7 8 8 8 9 9 9 10 10 10 11 11 11\n"
                        "SCALARS density unsigned_short 1\n"
                        "LOOKUP_TABLE default\n"
                        "0 10 20\n30 40 50\n60 70 80\n90 100 65535\n"
                        "SCALARS temp double\n"
                        "LOOKUP_TABLE default\n"
                        "0.5 1.5 2.5 3.5 4.5 5.5 6.5 7.5 8.5 9.5 10.5 11.5\n";
    puts_("a.vtk", ascii);
    lc_file_info fi;
    CHECK(lc_file_probe(dev, tpath("a.vtk"), NULL, &fi) == LC_OK && !strcmp(fi.format, "vtk") && fi.kind == LC_KIND_GRID,
          "probe a.vtk: vtk, grid");
    lc_volume *v = load("a.vtk", NULL, 0, 0);
    lc_grid_info gi;
    int ok = v && lc_grid_get_info(v, &gi) == LC_OK;
    CHECK(ok && gi.size[0] == 3 && gi.size[1] == 2 && gi.size[2] == 2 && gi.type == LC_VALUE_UINT16 &&
              gi.spacing.x == 0.5f && gi.spacing.z == 2 && gi.origin.x == 1 && gi.origin.z == 3 &&
              gi.value_max == 65535.0f,
          "a.vtk: 3 x 2 x 2 uint16 'density' (the first SCALARS, past a VECTORS array), spacing and origin");
    /* node (i, j, k) = (2, 1, 1) holds the last value, (1, 0, 1) the 8th */
    CHECK(sample(v, 2, 3, 5) == 65535.0f && sample(v, 1.5f, 2, 5) == 70.0f, "a.vtk: values at their nodes");
    lc_volume_destroy(v);
    v = load("a.vtk", (lc_option[]){{"scalars", "temp"}}, 1, 0);
    CHECK(v && lc_grid_get_info(v, &gi) == LC_OK && gi.type == LC_VALUE_FLOAT32 && sample(v, 2, 3, 5) == 11.5f,
          "a.vtk, scalars = temp: the double array as float32");
    lc_volume_destroy(v);
    /* BINARY, big-endian: a FIELD with two arrays, then SCALARS float */
    unsigned char b[2048];
    size_t n = 0;
    const char *h = "# vtk DataFile Version 3.0\nbinary\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\n"
                    "ASPECT_RATIO 1 1 1\nORIGIN 0 0 0\nPOINT_DATA 8\nFIELD FieldData 2\nids 1 8 int\n";
    memcpy(b, h, strlen(h));
    n = strlen(h);
    for (int i = 0; i < 8; i++) be32(b + n + 4 * i, (uint32_t)(100 + i));
    n += 32;
    const char *h2 = "\nflags 1 8 unsigned_char\n";
    memcpy(b + n, h2, strlen(h2));
    n += strlen(h2);
    for (int i = 0; i < 8; i++) b[n++] = (unsigned char)(i * 3);
    const char *h3 = "\nSCALARS phi float 1\nLOOKUP_TABLE default\n";
    memcpy(b + n, h3, strlen(h3));
    n += strlen(h3);
    size_t at_phi = n;
    for (int i = 0; i < 8; i++) {
        float f = 0.25f * (float)i - 1.0f;
        uint32_t u;
        memcpy(&u, &f, 4);
        be32(b + n, u);
        n += 4;
    }
    b[n++] = '\n';
    put("b.vtk", b, n);
    v = load("b.vtk", NULL, 0, 0);
    CHECK(v && lc_grid_get_info(v, &gi) == LC_OK && gi.type == LC_VALUE_FLOAT32 && sample(v, 0, 0, 0) == -1.0f &&
              sample(v, 1, 1, 1) == 0.75f,
          "b.vtk: BINARY big-endian float 'phi' past a FIELD of two arrays");
    lc_volume_destroy(v);
    v = load("b.vtk", (lc_option[]){{"scalars", "ids"}}, 1, 0);
    CHECK(v && sample(v, 1, 1, 1) == 107.0f, "b.vtk, scalars = ids: the FIELD's int array as float32");
    lc_volume_destroy(v);
    /* malformed */
    put("cut.vtk", b, at_phi + 10);
    char where[64];
    snprintf(where, sizeof where, ": byte %zu: ", at_phi);
    must_fail("cut.vtk", where, "needs 32 bytes", LC_ERROR_FORMAT, NULL);
    puts_("dims.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 3 2\nPOINT_DATA 6\n");
    must_fail("dims.vtk", ":5: ", "DIMENSIONS needs three integers", LC_ERROR_FORMAT, NULL);
    puts_("word.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\nPOINT_DATA 8\n"
                      "SCALARS s float\nLOOKUP_TABLE default\n1 2 3 4\n5 six 7 8\n");
    must_fail("word.vtk", ":10: ", "'six', expected a float number", LC_ERROR_FORMAT, NULL);
    puts_("count.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\nPOINT_DATA 9\n");
    must_fail("count.vtk", ":6: ", "POINT_DATA 9, but DIMENSIONS give 8", LC_ERROR_FORMAT, NULL);
    puts_("grid.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n");
    must_fail("grid.vtk", ":4: ", "only STRUCTURED_POINTS", LC_ERROR_FORMAT, NULL);
    puts_("short.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\nPOINT_DATA 8\n"
                       "SCALARS s float\n1 2 3\n4 5                    \n");
    must_fail("short.vtk", ":9: ", "ends after 5 of the 8 values", LC_ERROR_FORMAT, NULL);
    /* ASCII values the declared type cannot hold are refused, not wrapped (444444 as a short was
       -14308): the type's own limits load exactly */
    const char *head = "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\nPOINT_DATA 8\n";
    char text[512];
    snprintf(text, sizeof text, "%sSCALARS s short 1\nLOOKUP_TABLE default\n-32768 2 3 32767\n5 6 7 8\n", head);
    puts_("limits.vtk", text);
    v = load("limits.vtk", NULL, 0, 0);
    CHECK(v && lc_grid_get_info(v, &gi) == LC_OK && gi.type == LC_VALUE_INT16 && sample(v, 0, 0, 0) == -32768.0f &&
              sample(v, 1, 1, 0) == 32767.0f,
          "limits.vtk: short's limits -32768 and 32767 load exactly");
    lc_volume_destroy(v);
    snprintf(text, sizeof text, "%sSCALARS s short 1\nLOOKUP_TABLE default\n1 2 3 4\n5 6 444444 8\n", head);
    puts_("wrap.vtk", text);
    must_fail("wrap.vtk", ":10: ", "value 6 of array s is '444444', outside short's range -32768..32767",
              LC_ERROR_FORMAT, NULL);
    snprintf(text, sizeof text, "%sSCALARS s short 1\nLOOKUP_TABLE default\n1 2 3 32768\n5 6 7 8\n", head);
    puts_("wrap1.vtk", text);
    must_fail("wrap1.vtk", ":9: ", "'32768', outside short's range", LC_ERROR_FORMAT, NULL);
    snprintf(text, sizeof text, "%sSCALARS s unsigned_char 1\nLOOKUP_TABLE default\n1 2 3 -1\n5 6 7 8\n", head);
    puts_("neg.vtk", text);
    must_fail("neg.vtk", ":9: ", "'-1', outside unsigned_char's range 0..255", LC_ERROR_FORMAT, NULL);
    snprintf(text, sizeof text, "%sSCALARS s unsigned_short 1\nLOOKUP_TABLE default\n1 2 3 4\n5 6.5 7 8\n", head);
    puts_("frac.vtk", text);
    must_fail("frac.vtk", ":10: ", "'6.5', not an integer, as unsigned_short values are", LC_ERROR_FORMAT, NULL);
    snprintf(text, sizeof text, "%sSCALARS s double 1\nLOOKUP_TABLE default\n1 2 3 4\n5 6 7 1e300\n", head);
    puts_("huge.vtk", text);
    must_fail("huge.vtk", ":10: ", "'1e300', beyond float32's range", LC_ERROR_FORMAT, NULL);
    /* BINARY double beyond float32 (stored as float32: it would become infinite) */
    n = 0;
    const char *hd = "# vtk DataFile Version 3.0\nbinary\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 2 2 2\n"
                     "POINT_DATA 8\nSCALARS d double 1\nLOOKUP_TABLE default\n";
    memcpy(b, hd, strlen(hd));
    n = strlen(hd);
    double big[8] = {1.0, 1e300, 1, 1, 1, 1, 1, 1};
    for (int i = 0; i < 8; i++) {
        uint64_t u;
        memcpy(&u, &big[i], 8);
        be32(b + n, (uint32_t)(u >> 32)), be32(b + n + 4, (uint32_t)u);
        n += 8;
    }
    b[n++] = '\n';
    put("bigd.vtk", b, n);
    snprintf(where, sizeof where, ": byte %zu: ", strlen(hd) + 8);
    must_fail("bigd.vtk", where, "value 1 is beyond float32's range", LC_ERROR_FORMAT, NULL);
}

/* ------------------------------------------------------------------ HDF5 */

#if LC_HAVE_HDF5
static void h5_attr(hid_t g, const char *name, hid_t type, const void *v, hsize_t count)
{
    hid_t sp = H5Screate_simple(1, &count, NULL);
    hid_t a = H5Acreate2(g, name, type, sp, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, type, v);
    H5Aclose(a);
    H5Sclose(sp);
}

static void h5_data(hid_t g, const char *name, hid_t ftype, hid_t mtype, int rank, const hsize_t *dims, const void *v)
{
    hid_t sp = H5Screate_simple(rank, dims, NULL);
    hid_t d = H5Dcreate2(g, name, ftype, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    H5Dwrite(d, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, v);
    H5Dclose(d);
    H5Sclose(sp);
}

/* A GADGET-style snapshot: 3 gas (double positions, hsml, density, masses)
 * and 2 halo particles (float positions, mass from MassTable). bad: 1 = halo
 * positions N x 2, 2 = NumPart disagrees, 3 = SWIFT's 7-type header and a
 * NumFilesPerSnapshot of 64 values (both fine), 4 = a MassTable of 20, 5 =
 * SWIFT's: SmoothingLengths (h) and a /HydroScheme recording Wendland C2. */
static void h5_snapshot(const char *name, int bad)
{
    hid_t f = H5Fcreate(tpath(name), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    hid_t h = H5Gcreate2(f, "Header", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    int np[64] = {3, bad == 2 ? 7 : 2, 0, 0, 0, 0};
    double mt[20] = {0, 0.5, 0, 0, 0, 0};
    h5_attr(h, "NumPart_ThisFile", H5T_NATIVE_INT, np, bad == 3 ? 7 : 6);
    h5_attr(h, "MassTable", H5T_NATIVE_DOUBLE, mt, bad == 3 ? 7 : bad == 4 ? 20 : 6);
    if (bad == 3) h5_attr(h, "NumFilesPerSnapshot", H5T_NATIVE_INT, np, 64);
    H5Gclose(h);
    hid_t g = H5Gcreate2(f, "PartType0", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    double x0[9] = {0, 0, 0, 1, 0, 0, 0, 2, 0};
    double m0[3] = {1, 2, 3}, h0[3] = {0.5, 0.6, 0.7}, r0[3] = {10, 20, 30};
    hsize_t d3[2] = {3, 3}, d1 = 3;
    h5_data(g, "Coordinates", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 2, d3, x0);
    h5_data(g, "Masses", H5T_IEEE_F32LE, H5T_NATIVE_DOUBLE, 1, &d1, m0);
    h5_data(g, bad == 5 ? "SmoothingLengths" : "SmoothingLength", H5T_IEEE_F32LE, H5T_NATIVE_DOUBLE, 1, &d1, h0);
    if (bad == 5) {
        hid_t hs = H5Gcreate2(f, "HydroScheme", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        hid_t st = H5Tcopy(H5T_C_S1);
        H5Tset_size(st, 12);
        h5_attr(hs, "Kernel function", st, "Wendland C2", 1);
        H5Tclose(st);
        H5Gclose(hs);
    }
    h5_data(g, "Density", H5T_IEEE_F32LE, H5T_NATIVE_DOUBLE, 1, &d1, r0);
    H5Gclose(g);
    g = H5Gcreate2(f, "PartType1", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    float x1[6] = {5, 5, 5, 6, 6, 6};
    hsize_t d2[2] = {2, bad == 1 ? 2 : 3};
    h5_data(g, "Coordinates", H5T_IEEE_F32LE, H5T_NATIVE_FLOAT, 2, d2, x1);
    H5Gclose(g);
    /* a grid and a point set for dataset = PATH */
    uint16_t vox[24];
    for (int i = 0; i < 24; i++) vox[i] = (uint16_t)(i * 100);
    hsize_t dg[3] = {4, 3, 2}; /* z y x */
    hid_t fields = H5Gcreate2(f, "fields", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    h5_data(fields, "rho", H5T_STD_U16LE, H5T_NATIVE_USHORT, 3, dg, vox);
    double pts[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    hsize_t dp[2] = {4, 3};
    h5_data(fields, "points", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 2, dp, pts);
    h5_data(fields, "line", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, 1, &d1, m0);
    H5Gclose(fields);
    H5Fclose(f);
}
#endif

static void hdf5(void)
{
#if LC_HAVE_HDF5
    h5_snapshot("snap.hdf5", 0);
    lc_file_info fi;
    CHECK(lc_file_probe(dev, tpath("snap.hdf5"), NULL, &fi) == LC_OK && !strcmp(fi.format, "hdf5") &&
              fi.kind == LC_KIND_PARTICLES,
          "probe snap.hdf5: hdf5 holding particles (kind_of)");
    lci_loaded l;
    const lc_particles_desc *d = read_with(&lci_format_hdf5, tpath("snap.hdf5"), 0, (lc_option[]){{"value", "mass"}}, 1, &l);
    CHECK(d && d->count == 5 && d->nfields == 2 && d->positions[7] == 2.0f && d->positions[9] == 5.0f &&
              d->radii[2] == 0.7f && d->values[1] == 2.0f && d->values[3] == 0.5f && d->fields[4] == 1,
          "snap.hdf5, value = mass: 5 particles, 2 fields, gas hsml as radii, Masses then MassTable 0.5");
    lci_loaded_free(&l);
    d = read_with(&lci_format_hdf5, tpath("snap.hdf5"), 0, (lc_option[]){{"value", "rho"}}, 1, &l);
    CHECK(d && d->count == 3 && d->values[2] == 30.0f, "snap.hdf5, value = rho: the gas only (halo has no Density)");
    lci_loaded_free(&l);
    d = read_with(&lci_format_hdf5, tpath("snap.hdf5"), 0, (lc_option[]){{"types", "1"}, {"radius", "0.25"}}, 2, &l);
    CHECK(d && d->count == 2 && d->radii[0] == 0.25f && d->positions[5] == 6.0f, "snap.hdf5, types = 1, radius = 0.25");
    lci_loaded_free(&l);
    lc_volume *v = load("snap.hdf5", (lc_option[]){{"dataset", "/fields/rho"}, {"spacing", "1,2,3"}}, 2, 0);
    lc_grid_info gi;
    CHECK(v && lc_grid_get_info(v, &gi) == LC_OK && gi.size[0] == 2 && gi.size[1] == 3 && gi.size[2] == 4 &&
              gi.type == LC_VALUE_UINT16 && sample(v, 1, 2, 3) == 900.0f && sample(v, 1, 4, 9) == 2300.0f,
          "dataset = /fields/rho: a 2 x 3 x 4 uint16 grid (x = the last dimension), spacing 1 2 3");
    lc_volume_destroy(v);
    lc_load_desc pd = {.options = (lc_option[]){{"dataset", "/fields/points"}}, .noptions = 1};
    CHECK(lc_file_probe(dev, tpath("snap.hdf5"), &pd, &fi) == LC_OK && fi.kind == LC_KIND_PARTICLES,
          "probe with dataset = /fields/points: particles");
    v = load("snap.hdf5", (lc_option[]){{"dataset", "/fields/points"}, {"radius", "0.5"}}, 2, 0);
    lc_particles_info pi;
    CHECK(v && lc_particles_get_info(v, &pi) == LC_OK && pi.count == 4 && pi.bounds.hi.z == 1.0f,
          "dataset = /fields/points: 4 particles");
    lc_volume_destroy(v);
    /* malformed */
    h5_snapshot("n2.hdf5", 1);
    must_fail("n2.hdf5", ": /PartType1/Coordinates (byte ", "shape 2 x 2, expected N x 3", LC_ERROR_FORMAT, NULL);
    h5_snapshot("swift.hdf5", 3);
    d = read_with(&lci_format_hdf5, tpath("swift.hdf5"), 0, (lc_option[]){{"value", "mass"}}, 1, &l);
    CHECK(d && d->count == 5 && d->values[3] == 0.5f,
          "swift.hdf5: 7-type header, a 64-value NumFilesPerSnapshot: loads (no fixed buffer overrun)");
    lci_loaded_free(&l);
    /* SPH (issue 27): SmoothingLength is H; SWIFT's SmoothingLengths are h, H = gamma h with the
       rendered kernel's gamma, else the recorded kernel's; k = m / rho A with an SPH kernel */
    d = read_with(&lci_format_hdf5, tpath("snap.hdf5"), 0, (lc_option[]){{"value", "rho"}, {"kernel", "m4"}}, 2, &l);
    CHECK(d && d->count == 3 && d->values[0] == 1.0f && d->values[2] == 3.0f && d->radii[2] == 0.7f && d->radius_note &&
              strstr(d->radius_note, "SmoothingLength"),
          "snap.hdf5, kernel = m4, value = rho: k = m / rho rho = m, H = SmoothingLength (%s)",
          d && d->radius_note ? d->radius_note : "no note");
    lci_loaded_free(&l);
    must_fail("snap.hdf5", ": /PartType1: ", "no Density dataset", LC_ERROR_FORMAT,
              &(lc_load_desc){.options = (lc_option[]){{"value", "mass"}, {"kernel", "m4"}, {"types", "1"}}, .noptions = 3});
    h5_snapshot("swift_h.hdf5", 5);
    d = read_with(&lci_format_hdf5, tpath("swift_h.hdf5"), 0, (lc_option[]){{"types", "0"}}, 1, &l);
    CHECK(d && fabsf(d->radii[0] - 0.5f * 1.936492f) < 1e-6f && d->radius_note && strstr(d->radius_note, "wendland-c2"),
          "SWIFT's h with a recorded Wendland C2: H = 1.936492 h (%s)", d && d->radius_note ? d->radius_note : "no note");
    lci_loaded_free(&l);
    d = read_with(&lci_format_hdf5, tpath("swift_h.hdf5"), 0, (lc_option[]){{"types", "0"}, {"kernel", "m4"}}, 2, &l);
    CHECK(d && fabsf(d->radii[0] - 0.5f * 1.825742f) < 1e-6f, "SWIFT's h rendered with M4: H = 1.825742 h");
    lci_loaded_free(&l);
    d = read_with(&lci_format_hdf5, tpath("swift_h.hdf5"), 0, (lc_option[]){{"types", "0"}, {"hsml_is", "H"}}, 2, &l);
    CHECK(d && d->radii[0] == 0.5f, "SWIFT's smoothing lengths with hsml_is = H: as read");
    lci_loaded_free(&l);
    h5_snapshot("mt20.hdf5", 4);
    must_fail("mt20.hdf5", ": /Header/MassTable: ", "20 values, expected 1 to 16", LC_ERROR_FORMAT, NULL);
    h5_snapshot("np.hdf5", 2);
    must_fail("np.hdf5", ": /PartType1/Coordinates (byte ", "NumPart_ThisFile[1] says 7", LC_ERROR_FORMAT, NULL);
    FILE *f = fopen(tpath("snap.hdf5"), "rb");
    unsigned char buf[1 << 16];
    size_t n = f ? fread(buf, 1, sizeof buf, f) : 0;
    if (f) fclose(f);
    put("cut.hdf5", buf, n / 3);
    must_fail("cut.hdf5", ": byte 0: ", "libhdf5 cannot open it", LC_ERROR_FORMAT, NULL);
    puts_("not.h5", "this is text, not HDF5\n");
    must_fail("not.h5", ": byte 0: ", "not an HDF5 file", LC_ERROR_FORMAT, NULL);
    must_fail("snap.hdf5", ": /fields/line (byte ", "rank 1, expected a 3-D dataset",
              LC_ERROR_FORMAT, &(lc_load_desc){.options = (lc_option[]){{"dataset", "/fields/line"}}, .noptions = 1});
    hid_t e = H5Fcreate(tpath("empty.h5"), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    H5Fclose(e);
    must_fail("empty.h5", ": ", "no PartType0..5 groups", LC_ERROR_FORMAT, NULL);
#else
    static const unsigned char sig[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};
    put("snap.hdf5", sig, 8);
    must_fail("snap.hdf5", ": ", "install libhdf5-dev and rebuild", LC_ERROR_UNSUPPORTED, NULL);
#endif
}

/* ------------------------------------------------------------------ mmCIF */

static void mmcif(const char *data)
{
    /* the first five ATOM records of 1tii.pdb, read here by columns */
    char p[1024], line[256];
    snprintf(p, sizeof p, "%s/particles/1tii.pdb", data);
    FILE *f = fopen(p, "r");
    if (!f) {
        printf("skip mmCIF against 1tii.pdb: %s not found\n", p);
        return;
    }
    double ref[5][3];
    char names[5][8], res[5][8], el[5][4];
    int seq[5], k = 0;
    while (k < 5 && fgets(line, sizeof line, f))
        if (!strncmp(line, "ATOM  ", 6)) {
            char c[9];
            for (int a = 0; a < 3; a++) {
                memcpy(c, line + 30 + 8 * a, 8), c[8] = 0;
                ref[k][a] = atof(c);
            }
            sscanf(line + 12, "%4s", names[k]);
            sscanf(line + 17, "%3s", res[k]);
            sscanf(line + 76, "%2s", el[k]);
            seq[k] = atoi(line + 22);
            k++;
        }
    fclose(f);
    char cif[8192];
    int m = snprintf(cif, sizeof cif,
                     "data_1TII\n#\n_entry.id 1TII\n#\nloop_\n_atom_type.symbol\nC\nN\nO\n#\nloop_\n"
                     "_atom_site.group_PDB\n_atom_site.id\n_atom_site.type_symbol\n_atom_site.label_atom_id\n"
                     "_atom_site.label_alt_id\n_atom_site.label_comp_id\n_atom_site.label_asym_id\n"
                     "_atom_site.label_seq_id\n_atom_site.pdbx_PDB_ins_code\n_atom_site.Cartn_x\n_atom_site.Cartn_y\n"
                     "_atom_site.Cartn_z\n_atom_site.occupancy\n_atom_site.auth_seq_id\n_atom_site.pdbx_PDB_model_num\n");
    for (int i = 0; i < 5; i++)
        m += snprintf(cif + m, sizeof cif - (size_t)m, "ATOM %d %s %s %c %s D %d ? %.3f %.3f %.3f %s %d 1\n", i + 1,
                      el[i], names[i], i == 4 ? 'A' : '.', res[i], seq[i], ref[i][0], ref[i][1], ref[i][2],
                      i == 4 ? "0.5" : "1.00", seq[i]);
    /* an alternate of atom 5 (skipped), a quoted name, a ;text-free HETATM, then model 2 */
    m += snprintf(cif + m, sizeof cif - (size_t)m,
                  "ATOM 6 %s %s B %s D %d ? 0.000 0.000 0.000 0.5 %d 1\n"
                  "HETATM 7 O \"O'\" . HOH E . ? 19.099 9.698(3) -13.097 1.00 1 1\n"
                  "ATOM 8 N N . GLY D 1 ? 1.0 2.0 3.0 1.00 1 2\n#\n",
                  el[4], names[4], res[4], seq[4], seq[4]);
    puts_("1tii.cif", cif);
    lc_file_info fi;
    CHECK(lc_file_probe(dev, tpath("1tii.cif"), NULL, &fi) == LC_OK && !strcmp(fi.format, "mmcif") && fi.frames == 2,
          "probe 1tii.cif: mmcif, 2 models as frames (got %lld)", (long long)fi.frames);
    lci_loaded l;
    const lc_particles_desc *d = read_with(&lci_format_mmcif, tpath("1tii.cif"), 0, (lc_option[]){{"fields", "element"}}, 1, &l);
    int same = d && d->count == 6;
    for (int i = 0; same && i < 5; i++)
        for (int a = 0; a < 3; a++) same &= d->positions[3 * i + a] == (float)ref[i][a];
    CHECK(same && d->positions[16] == 9.698f && d->radii[0] == 0.71f && d->radii[1] == 0.76f && d->nfields == 3,
          "1tii.cif model 1: 6 atoms (altloc B skipped), the 5 positions of 1tii.pdb's first ATOM records, N/C radii, "
          "3 elements");
    lci_loaded_free(&l);
    d = read_with(&lci_format_mmcif, tpath("1tii.cif"), 1, NULL, 0, &l);
    CHECK(d && d->count == 1 && d->positions[2] == 3.0f, "1tii.cif frame 1: model 2's one atom");
    lci_loaded_free(&l);
    /* malformed */
    puts_("quote.cif", "data_x\nloop_\n_atom_site.type_symbol\n_atom_site.Cartn_x\n_atom_site.Cartn_y\n"
                       "_atom_site.Cartn_z\nC 1 2 3\n'C 1 2 3\n");
    must_fail("quote.cif", ":8: ", "never closes", LC_ERROR_FORMAT, NULL);
    puts_("noz.cif", "data_x\n#\nloop_\n_atom_site.type_symbol\n_atom_site.Cartn_x\n_atom_site.Cartn_y\nC 1 2\n");
    must_fail("noz.cif", ":3: ", "no _atom_site.Cartn_z column", LC_ERROR_FORMAT, NULL);
    puts_("row.cif", "data_x\nloop_\n_atom_site.type_symbol\n_atom_site.Cartn_x\n_atom_site.Cartn_y\n"
                     "_atom_site.Cartn_z\nC 1 2 3\nN 4 5\n_other.tag 1\n");
    must_fail("row.cif", ":8: ", "middle of a row (3 of its 4 values)", LC_ERROR_FORMAT, NULL);
    puts_("num.cif", "data_x\nloop_\n_atom_site.type_symbol\n_atom_site.Cartn_x\n_atom_site.Cartn_y\n"
                     "_atom_site.Cartn_z\nC 1 2 3\nC 1 ? 3\n");
    must_fail("num.cif", ":8: ", "Cartn_y is '?', expected a number", LC_ERROR_FORMAT, NULL);
    puts_("none.cif", "data_x\n_cell.length_a 10\n");
    must_fail("none.cif", ":2: ", "no _atom_site loop", LC_ERROR_FORMAT, NULL);
}

/* ------------------------------------------------------------------ CSV */

static void csv(void)
{
    puts_("p.csv", "# a comment\n"
                   "X, y ,z,radius,Mass,temp,type\n"
                   "0,0,0,0.5,1,300,gas\n"
                   "1,0,0,0.5,2,400,star\n"
                   "\n"
                   "0,\"2\",0,0.25,3,500,gas\n");
    lc_file_info fi;
    CHECK(lc_file_probe(dev, tpath("p.csv"), NULL, &fi) == LC_OK && !strcmp(fi.format, "csv") &&
              fi.kind == LC_KIND_PARTICLES,
          "probe p.csv: csv particles");
    lci_loaded l;
    const lc_particles_desc *d = read_with(&lci_format_csv, tpath("p.csv"), 0, NULL, 0, &l);
    CHECK(d && d->count == 3 && d->positions[7] == 2.0f && d->radii[2] == 0.25f && d->values && d->values[1] == 2.0f &&
              d->nfields == 2 && d->fields[0] == 0 && d->fields[1] == 1 && d->fields[2] == 0,
          "p.csv: 3 particles, radius column, value = mass by default, type names as fields 0 1 0");
    lci_loaded_free(&l);
    d = read_with(&lci_format_csv, tpath("p.csv"), 0, (lc_option[]){{"value", "temp"}, {"fields", "none"}}, 2, &l);
    CHECK(d && d->values[2] == 500.0f && d->nfields == 1, "p.csv, value = temp, fields = none");
    lci_loaded_free(&l);
    puts_("knn.csv", "x y z\n0 0 0\n1 0 0\n0 3 0\n");
    d = read_with(&lci_format_csv, tpath("knn.csv"), 0, (lc_option[]){{"knn", "1"}}, 1, &l);
    CHECK(d && d->count == 3 && d->radii[0] == 1.0f && d->radii[2] == 3.0f && !d->values,
          "knn.csv (white space): radii from the nearest neighbour, no values");
    lci_loaded_free(&l);
    /* malformed */
    puts_("noz.csv", "x,y,w\n1,2,3\n");
    must_fail("noz.csv", ":1: ", "must name columns x, y and z", LC_ERROR_FORMAT, NULL);
    puts_("count.csv", "x,y,z\n1,2,3\n1,2\n");
    must_fail("count.csv", ":3: ", "2 values, but the header (line 1) names 3 columns", LC_ERROR_FORMAT, NULL);
    puts_("num.csv", "x,y,z,radius\n1,2,3,1\n\n1,2,3,-1\n");
    must_fail("num.csv", ":4: ", "column 4 (radius) is '-1', expected a radius > 0", LC_ERROR_FORMAT, NULL);
    puts_("word.csv", "x,y,z\n1,two,3\n");
    must_fail("word.csv", ":2: ", "column 2 (y) is 'two'", LC_ERROR_FORMAT, NULL);
    /* ids above 7 merge into field 7 with a warning (test_formats_opts.c); a word among ids fails */
    puts_("field.csv", "x,y,z,type\n1,2,3,0\n1,2,3,C\n");
    must_fail("field.csv", ":3: ", "is 'C', expected a field id >= 0", LC_ERROR_FORMAT, NULL);
    must_fail("p.csv", ":2: ", "option value = 'nope'", LC_ERROR_INVALID_ARGUMENT,
              &(lc_load_desc){.options = (lc_option[]){{"value", "nope"}}, .noptions = 1});
}

/* ------------------------------------------------------------------ PDB altlocs */

static void pdb_altlocs(void)
{
    /* SER 5: OG at A and B (keep A); LYS 6: NZ only at B and C (keep B); a blank-altloc atom */
    puts_("alt.pdb",
          "ATOM      1  CA  SER A   5       1.000   1.000   1.000  1.00 10.00           C  \n"
          "ATOM      2  OG ASER A   5       2.000   2.000   2.000  0.60 10.00           O  \n"
          "ATOM      3  OG BSER A   5       9.000   9.000   9.000  0.40 10.00           O  \n"
          "ATOM      4  NZ BLYS A   6       3.000   3.000   3.000  0.50 10.00           N  \n"
          "ATOM      5  NZ CLYS A   6       8.000   8.000   8.000  0.50 10.00           N  \n"
          "ATOM      6  CA  LYS A   6       4.000   4.000   4.000  1.00 10.00           C  \n"
          "ATOM      7  OG ASER A   7       5.000   5.000   5.000  0.60 10.00           O  \n");
    lci_loaded l;
    const lc_particles_desc *d = read_with(&lci_format_pdb, tpath("alt.pdb"), 0, NULL, 0, &l);
    int ok = d && d->count == 5;
    const float want[5] = {1, 2, 3, 4, 5};
    for (int i = 0; ok && i < 5; i++) ok &= d->positions[3 * i] == want[i];
    CHECK(ok, "alt.pdb: 5 of 7 atoms, the first altloc of each (A of SER 5, B of LYS 6 NZ), blanks kept (got %zu)",
          d ? d->count : 0);
    lci_loaded_free(&l);
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: test_vformats DATA_DIR TMP_DIR\n");
        return 2;
    }
    tmp = argv[2];
    if (lc_device_create(&(lc_device_desc){.threads = 2, .log = on_log}, &dev) != LC_OK) return 1;
    nifti();
    vtk();
    hdf5();
    mmcif(argv[1]);
    csv();
    pdb_altlocs();
    lc_device_destroy(dev);
    return check_summary("vformats");
}
