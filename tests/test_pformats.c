/* Trajectory and particle formats (host/formats/dcd.c, psf.c, lammps.c,
 * gadget.c, xyz.c frames, pdb.c MODELs): the shared adk.dcd + adk.psf and
 * the two GADGET snapshots checked against values this test reads from the
 * files itself (its own few lines of record walking, not the library's);
 * files the test writes in every flavour (DCD: both byte orders, CHARMM with
 * unit cells, X-PLOR, fixed atoms; GADGET format 2 big-endian with HSML;
 * LAMMPS orthogonal, scaled and triclinic; extended XYZ; PDB MODELs); and
 * malformed variants of each that must fail with one message naming the
 * file and the byte or line. Args: DATA_DIR TMP_DIR. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "tmpfiles.h"
#include "host/formats/format.h"

static lc_device *dev;
static char warned[2048];

static void on_log(void *user, lc_log_level level, const char *msg)
{
    (void)user;
    if (level == LC_LOG_WARNING) snprintf(warned, sizeof warned, "%s", msg);
}

static unsigned char *slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long len = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *b = malloc((size_t)len);
    if (b && fread(b, 1, (size_t)len, f) != (size_t)len) free(b), b = NULL;
    fclose(f);
    *n = (size_t)len;
    return b;
}

/* Reads through a format's reader: the descriptor or NULL. */
static const lc_particles_desc *read_with(const lci_format *fmt, const char *path, int64_t frame, const char *companion,
                                          const lc_option *o, int n, lci_loaded *l)
{
    memset(l, 0, sizeof *l);
    lc_load_desc d = {.frame = frame, .companion = companion, .options = o, .noptions = n};
    lci_read_args a = {path, &d, o, n, NULL};
    return fmt->read(dev, &a, l) == LC_OK ? l->desc : NULL;
}

/* lc_volume_load must fail with LC_ERROR_FORMAT (or want) and one line starting "FILE: byte N" / "FILE:LINE:". */
static void must_fail(const char *name, const char *where, const char *says, lc_status want, const lc_load_desc *d)
{
    load_must_fail(dev, tpath(name), where, says, NULL, want, d);
}

/* ------------------------------------------------------------------ DCD */

static uint32_t rd32(const unsigned char *p) { uint32_t v; memcpy(&v, p, 4); return v; }

static void dcd_shared(const char *data)
{
    char dcd[1024], psf[1024];
    snprintf(dcd, sizeof dcd, "%s/particles/adk.dcd", data);
    snprintf(psf, sizeof psf, "%s/particles/adk.psf", data);
    size_t n;
    unsigned char *b = slurp(dcd, &n);
    CHECK(b != NULL, "read adk.dcd");
    if (!b) return;
    /* the test's own walk: three header records, then X Y Z records per frame */
    size_t off = 0;
    int32_t icntrl10 = (int32_t)rd32(b + 4 + 4 + 40);
    off += 8 + rd32(b);             /* CORD */
    off += 8 + rd32(b + off);       /* title */
    uint32_t natom = rd32(b + off + 4);
    off += 8 + rd32(b + off);       /* natom */
    size_t frame = 3 * (8 + 4 * (size_t)natom);
    size_t nframes = (n - off) / frame;
    CHECK(natom == 3341 && icntrl10 == 0 && nframes == 98 && (n - off) % frame == 0,
          "adk.dcd by hand: %u atoms, %zu frames, no unit cell", natom, nframes);
    lc_file_info fi;
    CHECK(lc_file_probe(dev, dcd, NULL, &fi) == LC_OK && !strcmp(fi.format, "dcd") && fi.frames == 98,
          "probe adk.dcd: dcd, 98 frames (got %lld; the header's NSET says 500)", (long long)fi.frames);
    lci_loaded l;
    const int64_t k = 57;
    const lc_particles_desc *d = read_with(&lci_format_dcd, dcd, k, psf, NULL, 0, &l);
    int same = d && d->count == natom;
    const unsigned char *fr = b + off + (size_t)k * frame;
    for (uint32_t i = 0; same && i < natom; i++)
        for (int c = 0; c < 3; c++) {
            float v;
            memcpy(&v, fr + (size_t)c * (8 + 4 * (size_t)natom) + 4 + 4 * (size_t)i, 4);
            same &= d->positions[3 * i + c] == v;
        }
    CHECK(same, "frame %lld of adk.dcd: all 3341 positions equal the file's X, Y, Z records", (long long)k);
    /* adk.psf atom 1 is N (14.007), 2 is HT1 (1.008), and a CA (12.011) is carbon, not calcium */
    CHECK(d && d->radii[0] == 0.71f && d->radii[1] == 0.31f && d->radii[4] == 0.76f,
          "radii from the PSF masses: N 0.71, H 0.31, CA = C 0.76 (got %g %g %g)", d ? (double)d->radii[0] : 0.0,
          d ? (double)d->radii[1] : 0.0, d ? (double)d->radii[4] : 0.0);
    lci_loaded_free(&l);
    /* STEM.psf is found next to the DCD without a companion */
    d = read_with(&lci_format_dcd, dcd, 97, NULL, (lc_option[]){{"fields", "element"}}, 1, &l);
    CHECK(d && d->count == 3341 && d->radii[1] == 0.31f && d->nfields >= 4, "adk.psf found by the stem, fields = element: %d fields",
          d ? d->nfields : 0);
    lci_loaded_free(&l);
    /* without a topology: one radius and a warning */
    put("lonely.dcd", b, n);
    warned[0] = 0;
    d = read_with(&lci_format_dcd, tpath("lonely.dcd"), 0, NULL, NULL, 0, &l);
    CHECK(d && d->count == 3341 && d->radii[0] == 1.5f && d->radii[100] == 1.5f && strstr(warned, "lonely.psf does not exist") &&
              strstr(warned, "radius 1.5"),
          "no topology: radius 1.5 and a warning: %s", warned);
    lci_loaded_free(&l);
    /* malformed: each names the file and the byte */
    put("cut.dcd", b, off + 40100); /* inside frame 0 (40116 bytes) */
    must_fail("cut.dcd", ": byte 356: ", "ends inside frame 0", LC_ERROR_FORMAT, NULL);
    unsigned char *c = malloc(n);
    memcpy(c, b, n);
    c[4] = 'X'; /* not CORD */
    put("notcord.dcd", c, 400);
    must_fail("notcord.dcd", ": byte 0: ", "CORD", LC_ERROR_FORMAT, &(lc_load_desc){.format = "dcd"});
    memcpy(c, b, n);
    uint32_t lie = 0x40000000u; /* a lying atom count */
    memcpy(c + off - 8, &lie, 4);
    put("natom.dcd", c, n);
    must_fail("natom.dcd", ": byte 348: ", "atom count 1073741824", LC_ERROR_FORMAT, NULL);
    memcpy(c, b, n);
    uint32_t bad = 9999; /* the end marker of the title record */
    memcpy(c + off - 16, &bad, 4);
    put("marker.dcd", c, n);
    must_fail("marker.dcd", ": byte 340: ", "end marker says 9999", LC_ERROR_FORMAT, NULL);
    memcpy(c, b, n);
    float nan = NAN; /* atom 11's y in frame 3 */
    memcpy(c + off + 3 * frame + (8 + 4 * (size_t)natom) + 4 + 40, &nan, 4);
    put("nan.dcd", c, n);
    must_fail("nan.dcd", ": byte ", "atom 11 of frame 3: y = nan", LC_ERROR_FORMAT,
              &(lc_load_desc){.frame = 3, .companion = psf});
    free(c);
    /* topology mismatches */
    puts_("three.psf", "PSF\n\n       1 !NTITLE\n* t\n\n       3 !NATOM\n"
                       "       1 A    1    MET  N      56  -0.300000       14.0070           0\n"
                       "       2 A    1    MET  HT1     2   0.330000       1.00800           0\n"
                       "       3 A    1    MET  HT2     2   0.330000       1.00800           0\n");
    CHECK(lc_volume_load(dev, dcd, &(lc_load_desc){.companion = tpath("three.psf")}, &(lc_volume *){0}) == LC_ERROR_FORMAT &&
              strstr(lc_last_error(), "holds 3341 atoms but its topology") && strstr(lc_last_error(), "three.psf has 3"),
          "a 3-atom PSF for adk.dcd: %s", lc_last_error());
    puts_("badline.psf", "PSF\n\n       1 !NTITLE\n* t\n\n       2 !NATOM\n"
                         "       1 A    1    MET  N      56  -0.300000       14.0070           0\n"
                         "       2 A    1    MET  HT1     2   0.330000\n");
    lc_volume *v = NULL;
    CHECK(lc_volume_load(dev, dcd, &(lc_load_desc){.companion = tpath("badline.psf")}, &v) == LC_ERROR_FORMAT &&
              strstr(lc_last_error(), "badline.psf:8: expected atom 2 of 2"),
          "a PSF atom line without its mass: %s", lc_last_error());
    puts_("notpsf.psf", "REMARK something else\n");
    CHECK(lc_volume_load(dev, dcd, &(lc_load_desc){.companion = tpath("notpsf.psf")}, &v) == LC_ERROR_FORMAT &&
              strstr(lc_last_error(), "notpsf.psf:1: not a PSF file"),
          "not a PSF: %s", lc_last_error());
    CHECK(lc_volume_load(dev, dcd, &(lc_load_desc){.frame = 98, .companion = psf}, &v) == LC_ERROR_INVALID_ARGUMENT &&
              strstr(lc_last_error(), "frame 98 is past the end: the file holds 98 frames"),
          "frame 98: %s", lc_last_error());
    free(b);
}

/* A DCD writer for the flavours: swap = big-endian on this (little-endian) host. */
typedef struct wbuf {
    unsigned char b[1 << 16];
    size_t n;
    int swap;
} wbuf;

static void w4(wbuf *w, uint32_t v)
{
    if (w->swap) v = __builtin_bswap32(v);
    memcpy(w->b + w->n, &v, 4);
    w->n += 4;
}
static void wf(wbuf *w, float f) { uint32_t v; memcpy(&v, &f, 4); w4(w, v); }
static void wd(wbuf *w, double f)
{
    uint64_t v;
    memcpy(&v, &f, 8);
    if (w->swap) v = __builtin_bswap64(v);
    memcpy(w->b + w->n, &v, 8);
    w->n += 8;
}
static void wraw(wbuf *w, const void *p, size_t n) { memcpy(w->b + w->n, p, n); w->n += n; }

/* natom atoms, nframes frames, atom i of frame k at (i + k/10, -i, 2i + k); xplor: no version,
 * charmm: cell records; nfixed: the last atoms fixed. */
static void write_dcd(const char *name, int swap, int charmm, int cell, int natom, int nframes, int nfixed)
{
    wbuf *w = calloc(1, sizeof *w);
    w->swap = swap;
    w4(w, 84);
    wraw(w, "CORD", 4);
    for (int i = 0; i < 20; i++)
        w4(w, i == 0 ? (uint32_t)nframes : i == 8 ? (uint32_t)nfixed : i == 10 ? (uint32_t)cell : i == 19 ? (uint32_t)(charmm ? 24 : 0) : 0u);
    w4(w, 84);
    w4(w, 84), w4(w, 1), wraw(w, "* a test trajectory                                                              ", 80), w4(w, 84);
    w4(w, 4), w4(w, (uint32_t)natom), w4(w, 4);
    int nfree = natom - nfixed;
    if (nfixed) {
        w4(w, 4u * (uint32_t)nfree);
        for (int i = 0; i < nfree; i++) w4(w, (uint32_t)i + 1);
        w4(w, 4u * (uint32_t)nfree);
    }
    for (int k = 0; k < nframes; k++) {
        if (cell) {
            w4(w, 48);
            for (int i = 0; i < 6; i++) wd(w, 10.0 + i);
            w4(w, 48);
        }
        int m = k == 0 ? natom : nfree;
        for (int c = 0; c < 3; c++) {
            w4(w, 4u * (uint32_t)m);
            for (int i = 0; i < m; i++) wf(w, c == 0 ? (float)i + (float)k / 10.0f : c == 1 ? (float)-i : 2.0f * (float)i + (float)k);
            w4(w, 4u * (uint32_t)m);
        }
    }
    put(name, w->b, w->n);
    free(w);
}

static void dcd_flavours(void)
{
    static const struct {
        const char *name;
        int swap, charmm, cell, fixed;
    } f[] = {{"le_charmm_cell.dcd", 0, 1, 1, 0}, {"be_charmm_cell.dcd", 1, 1, 1, 0}, {"be_xplor.dcd", 1, 0, 0, 0},
             {"le_fixed.dcd", 0, 1, 0, 2}, {"be_fixed_cell.dcd", 1, 1, 1, 2}};
    for (size_t i = 0; i < sizeof f / sizeof f[0]; i++) {
        write_dcd(f[i].name, f[i].swap, f[i].charmm, f[i].cell, 5, 4, f[i].fixed);
        lc_file_info fi;
        CHECK(lc_file_probe(dev, tpath(f[i].name), NULL, &fi) == LC_OK && !strcmp(fi.format, "dcd") && fi.frames == 4,
              "%s: dcd by its magic, 4 frames (got %lld)", f[i].name, (long long)fi.frames);
        lci_loaded l;
        const lc_particles_desc *d = read_with(&lci_format_dcd, tpath(f[i].name), 3, NULL, NULL, 0, &l);
        int ok = d && d->count == 5;
        for (int a = 0; ok && a < 5; a++) {
            int moved = a < 5 - f[i].fixed; /* fixed atoms keep frame 0's place */
            float kk = moved ? 3.0f : 0.0f;
            ok &= d->positions[3 * a] == (float)a + kk / 10.0f && d->positions[3 * a + 1] == (float)-a &&
                  d->positions[3 * a + 2] == 2.0f * (float)a + kk;
        }
        CHECK(ok, "%s frame 3: positions as written%s", f[i].name, f[i].fixed ? " (fixed atoms from frame 0)" : "");
        lci_loaded_free(&l);
    }
}

/* ------------------------------------------------------------------ GADGET */

static void gadget_shared(const char *data)
{
    char p[1024];
    snprintf(p, sizeof p, "%s/particles/gadget_galaxy.dat", data);
    size_t n;
    unsigned char *b = slurp(p, &n);
    CHECK(b && rd32(b) == 256, "read gadget_galaxy.dat (format 1, little-endian)");
    if (!b) return;
    int32_t np[6];
    for (int t = 0; t < 6; t++) np[t] = (int32_t)rd32(b + 4 + 4 * t);
    CHECK(np[0] == 0 && np[1] == 40000 && np[2] == 20000 && rd32(b + 264) == 12u * 60000u,
          "galaxy header by hand: 0 gas, 40000 halo, 20000 disk; POS block of 720000 bytes");
    lci_loaded l;
    const lc_particles_desc *d = read_with(&lci_format_gadget, p, 0, NULL, NULL, 0, &l);
    int ok = d && d->count == 60000 && d->nfields == 2 && d->fields[0] == 0 && d->fields[39999] == 0 &&
             d->fields[40000] == 1 && d->values == NULL;
    const int spot[] = {0, 1, 12345, 39999, 40000, 59999};
    for (size_t s = 0; ok && s < sizeof spot / sizeof spot[0]; s++)
        for (int c = 0; c < 3; c++) {
            float v;
            memcpy(&v, b + 268 + 12 * (size_t)spot[s] + 4 * (size_t)c, 4);
            ok &= d->positions[3 * spot[s] + c] == v;
        }
    float rmin = 1e30f, rmax = 0;
    for (size_t i = 0; d && i < d->count; i++) rmin = fminf(rmin, d->radii[i]), rmax = fmaxf(rmax, d->radii[i]);
    CHECK(ok && rmin > 0.0f && rmax < 1000.0f, "galaxy: 60000 particles, halo field 0, disk field 1, spot positions equal "
          "the POS block, k-NN radii %g..%g", (double)rmin, (double)rmax);
    lci_loaded_free(&l);
    /* malformed copies */
    unsigned char *c = malloc(n);
    put("cut.gadget", b, 5000); /* fewer bytes than the header's particles need */
    must_fail("cut.gadget", ": byte 4: ", "60000 particles, more than a 5000-byte file holds", LC_ERROR_FORMAT, NULL);
    put("cut2.gadget", b, 720100); /* inside POS */
    must_fail("cut2.gadget", ": byte 264: ", "a record of 720000 bytes, but only 719832 bytes remain", LC_ERROR_FORMAT, NULL);
    memcpy(c, b, n);
    uint32_t lie = 2000000000u; /* npart[1] */
    memcpy(c + 8, &lie, 4);
    put("lie.gadget", c, n);
    must_fail("lie.gadget", ": byte 8: ", "type 1: 2000000000 particles", LC_ERROR_FORMAT, NULL);
    memcpy(c, b, n);
    lie = 39000; /* a smaller count that no longer matches the POS block */
    memcpy(c + 8, &lie, 4);
    put("pos.gadget", c, n);
    must_fail("pos.gadget", ": byte 264: ", "a POS block of 720000 bytes", LC_ERROR_FORMAT, NULL);
    memcpy(c, b, n);
    uint32_t bad = 720004u; /* POS end marker */
    memcpy(c + 268 + 720000, &bad, 4);
    put("endmark.gadget", c, n);
    must_fail("endmark.gadget", ": byte 720268: ", "end marker says 720004", LC_ERROR_FORMAT, NULL);
    free(c);
    free(b);

    snprintf(p, sizeof p, "%s/particles/gadget_lcdm_gas.dat", data);
    b = slurp(p, &n);
    if (!b) return;
    for (int t = 0; t < 6; t++) np[t] = (int32_t)rd32(b + 4 + 4 * t);
    double mass[6];
    memcpy(mass, b + 4 + 24, sizeof mass);
    /* walk the records by hand: HEAD POS VEL ID [MASS] U */
    size_t off = 0;
    int need_mass = 0;
    for (int t = 0; t < 6; t++) need_mass |= np[t] > 0 && mass[t] == 0.0;
    for (int r = 0; r < 4 + need_mass; r++) off += 8 + rd32(b + off);
    uint32_t ulen = rd32(b + off);
    CHECK(np[0] == 32768 && np[1] == 32768 && ulen == 4u * 32768u, "lcdm by hand: 32768 gas + 32768 dm, U block of %u bytes",
          ulen);
    d = read_with(&lci_format_gadget, p, 0, NULL, (lc_option[]){{"value", "u"}}, 1, &l);
    ok = d && d->count == 32768 && d->values && d->nfields == 1;
    for (int i = 0; ok && i < 32768; i += 4097) {
        float u, x;
        memcpy(&u, b + off + 4 + 4 * (size_t)i, 4);
        memcpy(&x, b + 268 + 12 * (size_t)i, 4);
        ok &= d->values[i] == u && d->positions[3 * i] == x;
    }
    CHECK(ok, "lcdm value = u: the gas only, k_i = the U block, positions the POS block");
    lci_loaded_free(&l);
    d = read_with(&lci_format_gadget, p, 0, NULL, (lc_option[]){{"value", "mass"}, {"types", "1"}}, 2, &l);
    CHECK(d && d->count == 32768 && d->values[7] == (float)(mass[1] > 0 ? mass[1] : d->values[7]),
          "lcdm types = 1, value = mass: 32768 dark-matter particles");
    lci_loaded_free(&l);
    lc_volume *v = NULL;
    CHECK(lc_volume_load(dev, p, &(lc_load_desc){.options = (lc_option[]){{"value", "hsml"}}, .noptions = 1}, &v) ==
                  LC_ERROR_FORMAT && strstr(lc_last_error(), "no HSML block"),
          "value = hsml without an HSML block: %s", lc_last_error());
    CHECK(lc_volume_load(dev, p, &(lc_load_desc){.options = (lc_option[]){{"value", "u"}, {"types", "0,1"}}, .noptions = 2},
                         &v) == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "gas quantity"),
          "value = u with types = 0,1: %s", lc_last_error());
    free(b);
}

/* Format 2, big-endian, with gas HSML: 3 gas + 27 dm on a unit lattice. */
static void gadget_format2(void)
{
    wbuf *w = calloc(1, sizeof *w);
    w->swap = 1;
    const char *labels[] = {"HEAD", "POS ", "VEL ", "ID  ", "MASS", "U   ", "RHO ", "HSML"};
    int sizes[] = {256, 30 * 12, 30 * 12, 30 * 4, 3 * 4, 3 * 4, 3 * 4, 3 * 4};
    for (int blk = 0; blk < 8; blk++) {
        w4(w, 8), wraw(w, labels[blk], 4), w4(w, (uint32_t)sizes[blk] + 8), w4(w, 8);
        w4(w, (uint32_t)sizes[blk]);
        if (blk == 0) {
            size_t at = w->n;
            w4(w, 3), w4(w, 27);
            for (int t = 2; t < 6; t++) w4(w, 0);
            wd(w, 0.0), wd(w, 0.5);
            for (int t = 2; t < 6; t++) wd(w, 0.0);
            while (w->n < at + 256) w4(w, 0);
        } else if (blk == 1) {
            for (int i = 0; i < 3; i++) wf(w, 100.0f + i), wf(w, 0), wf(w, 0);
            for (int i = 0; i < 27; i++) wf(w, (float)(i % 3)), wf(w, (float)(i / 3 % 3)), wf(w, (float)(i / 9));
        } else {
            for (int i = 0; i < sizes[blk] / 4; i++) {
                if (blk == 3) w4(w, (uint32_t)i);
                else wf(w, blk == 4 ? 2.0f + i : blk == 5 ? 10.0f + i : blk == 6 ? 20.0f + i : blk == 7 ? 0.25f * (1 + i) : 0.0f);
            }
        }
        w4(w, (uint32_t)sizes[blk]);
    }
    put("f2.g2", w->b, w->n);
    lci_loaded l;
    const lc_particles_desc *d = read_with(&lci_format_gadget, tpath("f2.g2"), 0, NULL, (lc_option[]){{"knn", "6"}}, 1, &l);
    /* gas radii = HSML; dm: the lattice centre (index 3 + 13) has its 6th neighbour at 1 */
    CHECK(d && d->count == 30 && d->nfields == 2 && d->radii[0] == 0.25f && d->radii[2] == 0.75f &&
              d->positions[3] == 101.0f && d->positions[3 * 29 + 2] == 2.0f && d->radii[3 + 13] == 1.0f &&
              d->fields[2] == 0 && d->fields[3] == 1,
          "format 2, big-endian: gas radius = HSML, dm radius = 6th-neighbour distance (centre %g)",
          d ? (double)d->radii[16] : -1.0);
    lci_loaded_free(&l);
    d = read_with(&lci_format_gadget, tpath("f2.g2"), 0, NULL, (lc_option[]){{"value", "mass"}, {"knn", "1"}}, 2, &l);
    int ok = d && d->values[1] == 3.0f && d->values[3] == 0.5f;
    for (int i = 3; ok && i < 30; i++) ok &= d->radii[i] == 1.0f;
    CHECK(ok, "value = mass: gas from the MASS block, dm from the mass table; knn = 1 on a unit lattice: radius 1");
    lci_loaded_free(&l);
    d = read_with(&lci_format_gadget, tpath("f2.g2"), 0, NULL, (lc_option[]){{"value", "rho"}}, 1, &l);
    CHECK(d && d->count == 3 && d->values[2] == 22.0f, "value = rho: the gas only, RHO block");
    lci_loaded_free(&l);
    /* SPH (issue 27): HSML is H; hsml_is = h makes H = gamma h; with an SPH kernel a value is
       interpolated: k = m / rho * A (MASS 2, 3, 4; RHO 20, 21, 22; U 10, 11, 12) */
    d = read_with(&lci_format_gadget, tpath("f2.g2"), 0, NULL, (lc_option[]){{"value", "u"}, {"kernel", "m4"}}, 2, &l);
    ok = d && d->count == 3 && d->radii[1] == 0.5f && d->radius_note && strstr(d->radius_note, "H = HSML");
    for (int i = 0; ok && i < 3; i++) ok &= fabsf(d->values[i] - (2.0f + i) / (20.0f + i) * (10.0f + i)) < 1e-6f;
    CHECK(ok, "kernel = m4, value = u: k = m / rho u for the gas, radii = HSML (%s)",
          d && d->radius_note ? d->radius_note : "no note");
    lci_loaded_free(&l);
    d = read_with(&lci_format_gadget, tpath("f2.g2"), 0, NULL, (lc_option[]){{"hsml_is", "h"}, {"kernel", "wendland-c2"}},
                  2, &l);
    CHECK(d && fabsf(d->radii[0] - 0.25f * 1.936492f) < 1e-6f && d->values == NULL && d->radius_note &&
              strstr(d->radius_note, "wendland-c2"),
          "hsml_is = h, kernel = wendland-c2: H = 1.936492 h (%s)", d && d->radius_note ? d->radius_note : "no note");
    lci_loaded_free(&l);
    must_fail("f2.g2", ": option hsml_is = 'x'", "expected h", LC_ERROR_INVALID_ARGUMENT,
              &(lc_load_desc){.options = (lc_option[]){{"hsml_is", "x"}}, .noptions = 1});
    must_fail("f2.g2", ": option kernel = 'm7'", "expected gaussian, m4", LC_ERROR_INVALID_ARGUMENT,
              &(lc_load_desc){.options = (lc_option[]){{"kernel", "m7"}}, .noptions = 1});
    /* a label that lies about the next block's size */
    size_t lab = 8 + 8 + 256 + 8; /* the POS label record */
    uint32_t lie = __builtin_bswap32(999);
    memcpy(w->b + lab + 8, &lie, 4);
    put("f2_label.g2", w->b, w->n);
    must_fail("f2_label.g2", ": byte ", "the label of block POS  says 999 bytes", LC_ERROR_FORMAT, NULL);
    free(w);
}

/* ------------------------------------------------------------------ LAMMPS */

static void lammps(void)
{
    puts_("two.lammpstrj", "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n3\nITEM: BOX BOUNDS pp pp pp\n0 10\n0 20\n-5 5\n"
                           "ITEM: ATOMS id type x y z c_pe\n1 1 1.0 2.0 3.0 -4.5\n2 2 4 5 -1 -3.25\n3 3 9.5 0.5 0 0.125\n"
                           "ITEM: TIMESTEP\n100\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp pp pp\n0 10\n0 20\n-5 5\n"
                           "ITEM: ATOMS id type xs ys zs\n1 1 0.5 0.25 0.5\n2 2 0.1 1.0 0.0\n");
    lc_file_info fi;
    CHECK(lc_file_probe(dev, tpath("two.lammpstrj"), NULL, &fi) == LC_OK && !strcmp(fi.format, "lammps") && fi.frames == 2,
          "probe: lammps, 2 frames (got %lld)", (long long)fi.frames);
    lci_loaded l;
    const lc_particles_desc *d =
        read_with(&lci_format_lammps, tpath("two.lammpstrj"), 0, NULL,
                  (lc_option[]){{"fields", "type"}, {"value", "c_pe"}}, 2, &l);
    CHECK(d && d->count == 3 && d->nfields == 3 && d->fields[2] == 2 && d->values && d->values[1] == -3.25f &&
              d->positions[3] == 4.0f && d->positions[5] == -1.0f && d->radii[0] == 0.5f,
          "frame 0: x y z, fields = type (type 3 -> field 2), value = c_pe, default radius 0.5");
    lci_loaded_free(&l);
    d = read_with(&lci_format_lammps, tpath("two.lammpstrj"), 1, NULL, NULL, 0, &l);
    CHECK(d && d->count == 2 && d->positions[0] == 5.0f && d->positions[1] == 5.0f && d->positions[2] == 0.0f &&
              d->positions[4] == 20.0f && d->positions[5] == -5.0f && d->nfields == 1,
          "frame 1: scaled xs ys zs mapped through the box");
    lci_loaded_free(&l);
    /* triclinic: bounding-box bounds with tilts xy=2, xz=0, yz=0; xs=1, ys=1 -> x = xlo + lx + xy */
    puts_("tri.dump", "ITEM: TIMESTEP\n5\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS xy xz yz pp pp pp\n0 12 2\n0 10 0\n0 10 0\n"
                      "ITEM: ATOMS id type xs ys zs diameter\n1 1 1 1 0.5 3\n");
    d = read_with(&lci_format_lammps, tpath("tri.dump"), 0, NULL, NULL, 0, &l);
    CHECK(d && d->positions[0] == 12.0f && d->positions[1] == 10.0f && d->positions[2] == 5.0f && d->radii[0] == 1.5f,
          "triclinic scaled: x = 12, y = 10, z = 5; radius = diameter / 2 (got %g %g %g)", d ? (double)d->positions[0] : 0.0,
          d ? (double)d->positions[1] : 0.0, d ? (double)d->positions[2] : 0.0);
    lci_loaded_free(&l);
    CHECK(lc_volume_load(dev, tpath("two.lammpstrj"), &(lc_load_desc){.frame = 2}, &(lc_volume *){0}) ==
                  LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "holds 2 frames"),
          "frame 2: %s", lc_last_error());
    static const struct {
        const char *name, *text, *where, *says;
    } bad[] = {
        {"count.dump", "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\nthree\n", ":4: ", "number of atoms"},
        {"cols.dump", "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n2\nITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n"
                      "ITEM: ATOMS id type x y z\n1 1 0 0 0\n2 1 0 0\n", ":11: ", "has 4 columns"},
        {"short.dump", "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n3\nITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n"
                       "ITEM: ATOMS id type x y z\n1 1 0 0 0\n", ":11: ", "ends after 1 of the 3 atoms"},
        {"nan.dump", "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n"
                     "ITEM: ATOMS id type x y z\n1 1 0 0x 0\n", ":10: ", "column 4 (y) = '0x'"},
        {"box.dump", "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp pp\n0 1\n0\n", ":7: ",
         "lo hi of the box's y bounds"},
        {"nopos.dump", "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n"
                       "ITEM: ATOMS id type vx vy vz\n1 1 0 0 0\n", ":9: ", "no x y z"},
        {"junk.dump", "ITEM: TIMESTEP\n0\nITEM: NUMBER OF ATOMS\n1\nITEM: BOX BOUNDS pp pp pp\n0 1\n0 1\n0 1\n"
                      "ITEM: ATOMS id type x y z\n1 1 0 0 0\nhello\n", ":11: ", "expected an 'ITEM:' line (frame 1)"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        puts_(bad[i].name, bad[i].text);
        must_fail(bad[i].name, bad[i].where, bad[i].says, LC_ERROR_FORMAT, &(lc_load_desc){.frame = i == 6});
    }
    must_fail("two.lammpstrj", ":9: ", "value = 'c_ke', but the atom columns are: id type x y z c_pe", LC_ERROR_FORMAT,
              &(lc_load_desc){.options = (lc_option[]){{"value", "c_ke"}}, .noptions = 1});
}

/* ------------------------------------------------------------------ XYZ frames, PDB models */

static void xyz_pdb(void)
{
    puts_("three.extxyz", "2\nLattice=\"10 0 0 0 10 0 0 0 10\" Properties=species:S:1:pos:R:3 energy=-1.5 pbc=\"T T T\"\n"
                          "O 0 0 0\nH 1 0 0\n"
                          "2\nProperties=id:I:1:pos:R:3:species:S:1\n7 0 0 1 H\n8 0 0 2 O\n"
                          "1\nframe 2\nC 5 6 7 extra columns\n");
    lc_file_info fi;
    CHECK(lc_file_probe(dev, tpath("three.extxyz"), NULL, &fi) == LC_OK && !strcmp(fi.format, "xyz") && fi.frames == 3,
          "probe extended XYZ: 3 frames (got %lld)", (long long)fi.frames);
    lci_loaded l;
    const lc_particles_desc *d = read_with(&lci_format_xyz, tpath("three.extxyz"), 0, NULL, NULL, 0, &l);
    CHECK(d && d->count == 2 && d->radii[0] == 0.66f && d->positions[3] == 1.0f, "frame 0: Lattice read past, O and H");
    lci_loaded_free(&l);
    d = read_with(&lci_format_xyz, tpath("three.extxyz"), 1, NULL, NULL, 0, &l);
    CHECK(d && d->count == 2 && d->radii[0] == 0.31f && d->radii[1] == 0.66f && d->positions[2] == 1.0f &&
              d->positions[5] == 2.0f,
          "frame 1: Properties puts pos in columns 2-4 and species in 5");
    lci_loaded_free(&l);
    d = read_with(&lci_format_xyz, tpath("three.extxyz"), 2, NULL, NULL, 0, &l);
    CHECK(d && d->count == 1 && d->positions[2] == 7.0f, "frame 2: extra columns allowed");
    lci_loaded_free(&l);
    must_fail("three.extxyz", ": frame 3 is past the end", "holds 3 frames", LC_ERROR_INVALID_ARGUMENT,
              &(lc_load_desc){.frame = 3});
    puts_("mismatch.xyz", "2\nc\nO 0 0 0\nH 1 0 0\nH 2 0 0\n1\nc\nO 0 0 0\n");
    must_fail("mismatch.xyz", ":5: ", "expected the atom count of frame 1", LC_ERROR_FORMAT, &(lc_load_desc){.frame = 1});
    puts_("short2.xyz", "1\nc\nO 0 0 0\n3\nc\nO 0 0 0\n");
    must_fail("short2.xyz", ":7: ", "declares 3 atoms but only 1 follow", LC_ERROR_FORMAT, &(lc_load_desc){.frame = 1});
    puts_("nocomment.xyz", "1\nc\nO 0 0 0\n1\n");
    must_fail("nocomment.xyz", ":5: ", "expected a comment line", LC_ERROR_FORMAT, &(lc_load_desc){.frame = 1});

    puts_("models.pdb", "HEADER    NMR\nMODEL        1\n"
                        "ATOM      1  N   ALA A   1       1.000   2.000   3.000  1.00  0.00           N\n"
                        "ENDMDL\nMODEL        2\n"
                        "ATOM      1  N   ALA A   1       4.000   5.000   6.000  1.00  0.00           N\n"
                        "ATOM      2  S   CYS A   2       7.000   8.000   9.000  1.00  0.00           S\n"
                        "ENDMDL\nEND\n");
    CHECK(lc_file_probe(dev, tpath("models.pdb"), NULL, &fi) == LC_OK && fi.frames == 2, "probe PDB: 2 MODELs = 2 frames");
    d = read_with(&lci_format_pdb, tpath("models.pdb"), 1, NULL, NULL, 0, &l);
    CHECK(d && d->count == 2 && d->positions[0] == 4.0f && d->radii[1] == 1.05f, "frame 1 = MODEL 2: 2 atoms");
    lci_loaded_free(&l);
    d = read_with(&lci_format_pdb, tpath("models.pdb"), 0, NULL, NULL, 0, &l);
    CHECK(d && d->count == 1 && d->positions[2] == 3.0f, "frame 0 = MODEL 1: 1 atom");
    lci_loaded_free(&l);
    must_fail("models.pdb", ": frame 2 is past the end", "holds 2 MODELs", LC_ERROR_INVALID_ARGUMENT,
              &(lc_load_desc){.frame = 2});
}

int main(int argc, char **argv)
{
    const char *data = argc > 1 ? argv[1] : "../shared/data";
    tmp = argc > 2 ? argv[2] : ".";
    lc_device_desc dd = {.threads = 2, .log = on_log};
    if (lc_device_create(&dd, &dev) != LC_OK) return printf("device: %s\n", lc_last_error()), 1;
    dcd_flavours();
    gadget_format2();
    lammps();
    xyz_pdb();
    char probe[1024];
    snprintf(probe, sizeof probe, "%s/particles/adk.dcd", data);
    FILE *f = fopen(probe, "rb");
    if (f) {
        fclose(f);
        dcd_shared(data);
        gadget_shared(data);
    } else {
        printf("skip: %s is absent (the shared data); the tests on real files did not run\n", probe);
    }
    lc_device_destroy(dev);
    return check_summary("test_pformats");
}
