/* The per-atom options of the particle formats (issue 11): `value = COLUMN`
 * (k_i) and `fields = column:NAME` (field ids by first appearance, the 9th
 * distinct value and beyond sharing field 7 with one warning) for PDB,
 * mmCIF, DCD + PSF and CSV; `select` for mmCIF, CSV and HDF5 snapshots.
 * Small files the test writes, the shared 1tii.pdb, 1tw7_solvated.pdb and
 * adk.psf + adk.dcd (their columns read here with the test's own few lines,
 * not the library's), and the error cases: a column the file lacks names
 * the file and the column, a value that is not a number names the line, a
 * selection keyword a format cannot answer names the keyword and the
 * format. Args: DATA_DIR TMP_DIR. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "tmpfiles.h"
#include "host/formats/format.h"
#if LC_HAVE_HDF5
#include <hdf5.h>
#endif

static lc_device *dev;
static int nwarn;
static char warned[2048];

static void on_log(void *user, lc_log_level level, const char *msg)
{
    (void)user;
    if (level != LC_LOG_WARNING) return;
    nwarn++;
    snprintf(warned, sizeof warned, "%s", msg);
}

/* Reads path through fmt's reader (the format named, as the registry does):
 * the descriptor or NULL; nwarn counts this read's warnings. */
static const lc_particles_desc *read_with(const lci_format *fmt, const char *path, const char *companion,
                                          const lc_option *o, int n, lci_loaded *l)
{
    memset(l, 0, sizeof *l);
    nwarn = 0;
    warned[0] = 0;
    lc_load_desc d = {.companion = companion, .options = o, .noptions = n};
    lci_read_args a = {path, &d, o, n, fmt->name};
    return fmt->read(dev, &a, l) == LC_OK ? l->desc : NULL;
}

/* lc_volume_load fails with want and one line starting with the file (and
 * where) and containing says (and says2 when not NULL). */
static void must_fail(const char *path, const char *where, const char *says, const char *says2, lc_status want,
                      const lc_load_desc *d)
{
    load_must_fail(dev, path, where, says, says2, want, d);
}

#define OPT(k, v) ((lc_option[]){{k, v}})
#define LOAD(...) (&(lc_load_desc){.options = (lc_option[]){__VA_ARGS__}, .noptions = sizeof((lc_option[]){__VA_ARGS__}) / sizeof(lc_option)})

/* Field ids by first appearance, the 9th distinct value on sharing field 7:
 * the test's own map. */
typedef struct idmap {
    char names[64][16];
    int n;
} idmap;
static int idmap_id(idmap *m, const char *v)
{
    int i = 0;
    while (i < m->n && strcmp(m->names[i], v)) i++;
    if (i == m->n && m->n < 64) snprintf(m->names[m->n++], sizeof m->names[0], "%s", v);
    return i < LC_MAX_FIELDS - 1 ? i : LC_MAX_FIELDS - 1;
}

/* Columns a..b (1-based) of line, blanks trimmed. */
static void cols(const char *line, int a, int b, char *out, size_t n)
{
    size_t len = strlen(line), k = 0;
    for (int c = a; c <= b && (size_t)c <= len && k + 1 < n; c++) out[k++] = line[c - 1];
    out[k] = 0;
    while (k && (out[k - 1] == ' ' || out[k - 1] == '\n' || out[k - 1] == '\r')) out[--k] = 0;
    size_t s = 0;
    while (out[s] == ' ') s++;
    memmove(out, out + s, k - s + 1);
}

/* ------------------------------------------------------------------ PDB */

static int pdb_line(char *out, size_t n, int serial, const char *name, const char *resname, char chain, int resid,
                    double x, double occ, double b, const char *segid, const char *el, const char *charge)
{
    return snprintf(out, n, "ATOM  %5d %-4s %-4s%c%4d    %8.3f%8.3f%8.3f%6.2f%6.2f      %-4s%2s%-2s\n", serial, name,
                    resname, chain, resid, x, 0.0, 0.0, occ, b, segid, el, charge);
}

static void pdb_small(void)
{
    /* 10 atoms, 9 residue names: the 9th (and the 10th atom, a repeat of the first name) checks the merge */
    static const char *const res[10] = {"ALA", "GLY", "SER", "LYS", "HOH", "NA", "CL", "TRP", "MET", "ALA"};
    char text[4096];
    int m = 0;
    for (int i = 0; i < 10; i++)
        m += pdb_line(text + m, sizeof text - (size_t)m, i + 1, i % 2 ? " CA" : " N", res[i], i < 5 ? 'A' : 'B', i + 1,
                      i * 2.0, 0.1 * (i + 1), 10.0 + i, i < 3 ? "P1" : "W1", i % 2 ? "C" : "N", i == 4 ? "2-" : "");
    puts_("opts.pdb", text);
    lci_loaded l;
    const lc_particles_desc *d = read_with(&lci_format_pdb, tpath("opts.pdb"), NULL, OPT("value", "occupancy"), 1, &l);
    int ok = d && d->count == 10 && d->values;
    for (int i = 0; ok && i < 10; i++) ok = fabsf(d->values[i] - 0.1f * (float)(i + 1)) < 1e-6f;
    CHECK(ok, "opts.pdb value = occupancy: k_i = columns 55-60 (0.10 .. 1.00)");
    lci_loaded_free(&l);
    d = read_with(&lci_format_pdb, tpath("opts.pdb"), NULL, OPT("value", "tempfactor"), 1, &l);
    CHECK(d && d->values && d->values[0] == 10.0f && d->values[9] == 19.0f, "opts.pdb value = tempfactor (bfactor alias)");
    lci_loaded_free(&l);
    d = read_with(&lci_format_pdb, tpath("opts.pdb"), NULL, OPT("value", "charge"), 1, &l);
    CHECK(d && d->values && d->values[4] == -2.0f && d->values[0] == 0.0f,
          "opts.pdb value = charge: '2-' is -2, a blank charge 0 (got %g, %g)",
          d && d->values ? (double)d->values[4] : -99.0, d && d->values ? (double)d->values[0] : -99.0);
    lci_loaded_free(&l);
    d = read_with(&lci_format_pdb, tpath("opts.pdb"), NULL, OPT("fields", "column:resname"), 1, &l);
    ok = d && d->nfields == 8;
    for (int i = 0; ok && i < 10; i++) ok = d->fields[i] == (i < 8 ? i : i == 8 ? 7 : 0);
    CHECK(ok && nwarn == 1 && strstr(warned, "share field 7") && strstr(warned, "column resname"),
          "opts.pdb fields = column:resname: ids 0..7 by first appearance, MET (9th) shares 7, ALA again 0, one "
          "warning: %s",
          warned);
    lci_loaded_free(&l);
    d = read_with(&lci_format_pdb, tpath("opts.pdb"), NULL, OPT("fields", "column:segid"), 1, &l);
    CHECK(d && d->nfields == 2 && d->fields[2] == 0 && d->fields[3] == 1 && nwarn == 0,
          "opts.pdb fields = column:segid: P1 0, W1 1, no warning");
    lci_loaded_free(&l);
    d = read_with(&lci_format_pdb, tpath("opts.pdb"), NULL,
                  (lc_option[]){{"fields", "column:element"}, {"value", "bfactor"}}, 2, &l);
    CHECK(d && d->nfields == 2 && d->fields[0] == 0 && d->fields[1] == 1 && d->values && d->values[3] == 13.0f,
          "opts.pdb fields = column:element with value = bfactor");
    lci_loaded_free(&l);
    d = read_with(&lci_format_pdb, tpath("opts.pdb"), NULL, OPT("fields", "column:chain"), 1, &l);
    CHECK(d && d->nfields == 2 && d->fields[4] == 0 && d->fields[5] == 1, "opts.pdb fields = column:chain");
    lci_loaded_free(&l);
    /* through the registry: the options reach the reader, info says the fields */
    lc_volume *v = NULL;
    lc_particles_info pi;
    CHECK(lc_volume_load(dev, tpath("opts.pdb"), LOAD({"field_by", "column:bfactor"}, {"value", "occ"}), &v) == LC_OK &&
              lc_particles_get_info(v, &pi) == LC_OK && pi.count == 10 && pi.nfields == 8,
          "lc_volume_load opts.pdb field_by = column:bfactor: 10 distinct values in 8 fields");
    lc_volume_destroy(v);
    /* errors */
    must_fail(tpath("opts.pdb"), ": ", "value = 'mass'", "no such column", LC_ERROR_INVALID_ARGUMENT,
              LOAD({"value", "mass"}));
    must_fail(tpath("opts.pdb"), ": ", "fields by column 'colour'", "no such column", LC_ERROR_INVALID_ARGUMENT,
              LOAD({"fields", "column:colour"}));
    char bad[4096];
    snprintf(bad, sizeof bad, "%s", text);
    char *l3 = bad;
    for (int k = 0; k < 2; k++) l3 = strchr(l3, '\n') + 1;
    memcpy(l3 + 54, "  n/a ", 6); /* occupancy of line 3 */
    puts_("occ.pdb", bad);
    must_fail(tpath("occ.pdb"), ":3: ", "value = occupancy: columns 55-60 are 'n/a', not a number", NULL,
              LC_ERROR_FORMAT, LOAD({"value", "occupancy"}));
    /* xyz has no columns to map */
    puts_("two.xyz", "2\n\nC 0 0 0\nO 1 0 0\n");
    must_fail(tpath("two.xyz"), ": ", "fields by column 'name'", "xyz files have no per-atom columns",
              LC_ERROR_INVALID_ARGUMENT, LOAD({"fields", "column:name"}));
}

/* 1tii.pdb and 1tw7_solvated.pdb: values and fields against the test's own
 * reading of the columns. */
static void pdb_shared(const char *data)
{
    char path[1024], line[256];
    snprintf(path, sizeof path, "%s/particles/1tii.pdb", data);
    FILE *f = fopen(path, "r");
    if (!f) {
        printf("skip: %s absent\n", path);
        return;
    }
    float *b = malloc(sizeof *b * 60000);
    uint8_t *ids = malloc(60000);
    idmap chains = {0};
    size_t n = 0;
    while (fgets(line, sizeof line, f) && n < 60000)
        if (!strncmp(line, "ATOM  ", 6) || !strncmp(line, "HETATM", 6)) {
            char s[16];
            cols(line, 61, 66, s, sizeof s);
            b[n] = strtof(s, NULL);
            cols(line, 22, 22, s, sizeof s);
            ids[n++] = (uint8_t)idmap_id(&chains, s);
        }
    fclose(f);
    lci_loaded l;
    const lc_particles_desc *d = read_with(&lci_format_pdb, path, NULL,
                                           (lc_option[]){{"value", "bfactor"}, {"fields", "column:chain"}}, 2, &l);
    int ok = d && d->count == n && d->values && d->nfields == (chains.n < 8 ? chains.n : 8), bad = -1;
    for (size_t i = 0; ok && i < n; i++)
        if (d->values[i] != b[i] || d->fields[i] != ids[i]) ok = 0, bad = (int)i;
    CHECK(ok, "1tii.pdb value = bfactor, fields = column:chain: %zu atoms, %d chains, every k_i and id as the file "
              "says (first bad %d; e.g. atom 100 b = %g)", n, chains.n, bad, n > 100 ? (double)b[100] : 0.0);
    lci_loaded_free(&l);
    snprintf(path, sizeof path, "%s/particles/1tw7_solvated.pdb", data);
    if (!(f = fopen(path, "r"))) {
        printf("skip: %s absent\n", path);
        free(b), free(ids);
        return;
    }
    idmap seg = {0}, res = {0};
    uint8_t *rids = malloc(60000);
    n = 0;
    size_t protein = 0;
    while (fgets(line, sizeof line, f) && n < 60000)
        if (!strncmp(line, "ATOM  ", 6) || !strncmp(line, "HETATM", 6)) {
            char s[16];
            cols(line, 73, 76, s, sizeof s);
            ids[n] = (uint8_t)idmap_id(&seg, s);
            protein += !strncmp(s, "PRO", 3);
            cols(line, 18, 21, s, sizeof s);
            rids[n++] = (uint8_t)idmap_id(&res, s);
        }
    fclose(f);
    d = read_with(&lci_format_pdb, path, NULL, OPT("fields", "column:segid"), 1, &l);
    ok = d && d->count == n && d->nfields == seg.n && nwarn == 0;
    for (size_t i = 0; ok && i < n; i++) ok = d->fields[i] == ids[i];
    CHECK(ok, "1tw7_solvated.pdb fields = column:segid: %zu atoms in %d fields (%s %s %s ...) by first appearance", n,
          seg.n, seg.names[0], seg.names[1], seg.names[2]);
    lci_loaded_free(&l);
    d = read_with(&lci_format_pdb, path, NULL, OPT("fields", "column:resname"), 1, &l);
    ok = d && d->count == n && d->nfields == 8 && res.n > 8;
    for (size_t i = 0; ok && i < n; i++) ok = d->fields[i] == rids[i];
    CHECK(ok && nwarn == 1 && strstr(warned, "share field 7"),
          "1tw7_solvated.pdb fields = column:resname: %d residue names, the 9th on in field 7, one warning: %s", res.n,
          warned);
    lci_loaded_free(&l);
    d = read_with(&lci_format_pdb, path, NULL,
                  (lc_option[]){{"select", "segid PRO*"}, {"fields", "column:segid"}, {"value", "occupancy"}}, 3, &l);
    CHECK(d && d->count == protein && d->nfields == 2 && d->values && d->values[0] == 1.0f,
          "1tw7_solvated.pdb select segid PRO* with fields by segid: %zu atoms (got %zu), 2 fields",
          protein, d ? d->count : 0);
    lci_loaded_free(&l);
    free(b), free(ids), free(rids);
}

/* ------------------------------------------------------------------ mmCIF */

static void mmcif(void)
{
    static const char head[] = "data_t\n#\nloop_\n_atom_site.group_PDB\n_atom_site.id\n_atom_site.type_symbol\n"
                               "_atom_site.label_atom_id\n_atom_site.label_comp_id\n_atom_site.label_asym_id\n"
                               "_atom_site.label_seq_id\n_atom_site.Cartn_x\n_atom_site.Cartn_y\n_atom_site.Cartn_z\n"
                               "_atom_site.occupancy\n_atom_site.B_iso_or_equiv\n_atom_site.auth_asym_id\n"
                               "_atom_site.pdbx_PDB_model_num\n";
    char text[4096];
    int m = snprintf(text, sizeof text, "%s", head);
    static const char *const comp[6] = {"ALA", "ALA", "GLY", "HOH", "HOH", "SER"};
    for (int i = 0; i < 6; i++) /* rows from line 18 */
        m += snprintf(text + m, sizeof text - (size_t)m, "ATOM %d %c %s %s %c %d %d.0 0.0 0.0 0.%d %d.5 %c 1\n", i + 1,
                      i % 2 ? 'C' : 'N', i % 2 ? "CA" : "N", comp[i], i < 3 ? 'A' : 'W', i / 2 + 1, i, i + 1, 20 + i,
                      i < 3 ? 'X' : 'Y');
    puts_("opts.cif", text);
    lci_loaded l;
    const lc_particles_desc *d = read_with(&lci_format_mmcif, tpath("opts.cif"), NULL, OPT("value", "occupancy"), 1, &l);
    int ok = d && d->count == 6 && d->values;
    for (int i = 0; ok && i < 6; i++) ok = fabsf(d->values[i] - 0.1f * (float)(i + 1)) < 1e-6f;
    CHECK(ok, "opts.cif value = occupancy");
    lci_loaded_free(&l);
    d = read_with(&lci_format_mmcif, tpath("opts.cif"), NULL, OPT("value", "bfactor"), 1, &l);
    CHECK(d && d->values && d->values[5] == 25.5f, "opts.cif value = bfactor (B_iso_or_equiv)");
    lci_loaded_free(&l);
    d = read_with(&lci_format_mmcif, tpath("opts.cif"), NULL, OPT("value", "_atom_site.label_seq_id"), 1, &l);
    CHECK(d && d->values && d->values[5] == 3.0f, "opts.cif value = _atom_site.label_seq_id (any numeric item)");
    lci_loaded_free(&l);
    d = read_with(&lci_format_mmcif, tpath("opts.cif"), NULL, OPT("fields", "column:label_comp_id"), 1, &l);
    CHECK(d && d->nfields == 4 && d->fields[1] == 0 && d->fields[2] == 1 && d->fields[4] == 2 && d->fields[5] == 3,
          "opts.cif fields = column:label_comp_id: ALA ALA GLY HOH HOH SER -> 0 0 1 2 2 3");
    lci_loaded_free(&l);
    d = read_with(&lci_format_mmcif, tpath("opts.cif"), NULL, OPT("fields", "column:chain"), 1, &l);
    CHECK(d && d->nfields == 2 && d->fields[2] == 0 && d->fields[3] == 1, "opts.cif fields = column:chain (auth_asym_id)");
    lci_loaded_free(&l);
    /* select: resname, chain (auth_asym_id), name, resid, index, protein, water */
    static const struct { const char *expr; size_t n; } sel[] = {
        {"resname ALA", 2}, {"chain Y", 3}, {"name CA", 3}, {"resid 2", 2}, {"index 4:5", 2}, {"protein", 4},
        {"water", 2}, {"protein and not name N", 2}};
    for (size_t k = 0; k < sizeof sel / sizeof sel[0]; k++) {
        d = read_with(&lci_format_mmcif, tpath("opts.cif"), NULL, OPT("select", sel[k].expr), 1, &l);
        CHECK(d && d->count == sel[k].n, "opts.cif select '%s': %zu atoms (got %zu)", sel[k].expr, sel[k].n,
              d ? d->count : 0);
        lci_loaded_free(&l);
    }
    must_fail(tpath("opts.cif"), ": ", "keyword 'segid'", "mmcif", LC_ERROR_INVALID_ARGUMENT, LOAD({"select", "segid A"}));
    must_fail(tpath("opts.cif"), ":3: ", "value = 'charge'", "no such column (it has: group_PDB id", LC_ERROR_INVALID_ARGUMENT,
              LOAD({"value", "charge"}));
    must_fail(tpath("opts.cif"), ":3: ", "fields by column 'segment'", "no such column", LC_ERROR_INVALID_ARGUMENT,
              LOAD({"fields", "column:segment"}));
    char bad[4096];
    snprintf(bad, sizeof bad, "%s", text);
    char *q = strstr(bad, " 0.3 "); /* row 3 (line 20): occupancy unknown */
    memcpy(q, "   ? ", 5);
    puts_("occ.cif", bad);
    must_fail(tpath("occ.cif"), ":20: ", "_atom_site.occupancy is '?', not a number (unknown)", NULL, LC_ERROR_FORMAT,
              LOAD({"value", "occupancy"}));
    q = strstr(bad, " 21.5 ");
    memcpy(q, " 2x.5 ", 6);
    puts_("b.cif", bad);
    must_fail(tpath("b.cif"), ":19: ", "value = bfactor: _atom_site.B_iso_or_equiv is '2x.5'", NULL, LC_ERROR_FORMAT,
              LOAD({"value", "bfactor"}));
}

/* ------------------------------------------------------------------ DCD + PSF */

static void w32(FILE *f, int32_t v) { fwrite(&v, 4, 1, f); }

/* An X-PLOR DCD of natom atoms, one frame, atom i at (i, 2i, 3i). */
static void write_dcd(const char *name, int natom)
{
    FILE *f = fopen(tpath(name), "wb");
    if (!f) return;
    w32(f, 84);
    fwrite("CORD", 1, 4, f);
    for (int i = 0; i < 20; i++) w32(f, i == 0 ? 1 : 0);
    w32(f, 84);
    w32(f, 84);
    w32(f, 1);
    char title[80];
    memset(title, ' ', sizeof title);
    fwrite(title, 1, 80, f);
    w32(f, 84);
    w32(f, 4), w32(f, natom), w32(f, 4);
    for (int c = 0; c < 3; c++) {
        w32(f, 4 * natom);
        for (int i = 0; i < natom; i++) {
            float x = (float)(i * (c + 1));
            fwrite(&x, 4, 1, f);
        }
        w32(f, 4 * natom);
    }
    fclose(f);
}

static void dcd_psf(const char *data)
{
    puts_("t.psf", "PSF\n\n       1 !NTITLE\n* test\n\n       4 !NATOM\n"
                   "       1 PROA     1 ALA  N    NH3   -0.300000       14.0070           0\n"
                   "       2 PROA     1 ALA  CA   CT1    0.210000       12.0110           0\n"
                   "       3 SOLV     2 TIP3 OH2  OT    -0.834000       15.9994           0\n"
                   "       4 SOLV     2 TIP3 H1   HT     0.417000        1.0080           0\n");
    write_dcd("t.dcd", 4);
    lci_loaded l;
    const lc_particles_desc *d = read_with(&lci_format_dcd, tpath("t.dcd"), tpath("t.psf"), OPT("value", "charge"), 1, &l);
    CHECK(d && d->count == 4 && d->values && d->values[0] == -0.3f && d->values[2] == -0.834f && d->values[3] == 0.417f,
          "t.dcd + t.psf value = charge");
    lci_loaded_free(&l);
    d = read_with(&lci_format_dcd, tpath("t.dcd"), tpath("t.psf"),
                  (lc_option[]){{"value", "mass"}, {"fields", "column:segid"}}, 2, &l);
    CHECK(d && d->values && d->values[1] == 12.011f && d->nfields == 2 && d->fields[1] == 0 && d->fields[2] == 1,
          "t.dcd + t.psf value = mass, fields = column:segid (PROA 0, SOLV 1)");
    lci_loaded_free(&l);
    d = read_with(&lci_format_dcd, tpath("t.dcd"), tpath("t.psf"), OPT("fields", "column:type"), 1, &l);
    CHECK(d && d->nfields == 4 && d->fields[3] == 3, "t.dcd + t.psf fields = column:type");
    lci_loaded_free(&l);
    must_fail(tpath("t.dcd"), ": ", "value = 'occupancy'", "(it has resid, charge, mass)", LC_ERROR_INVALID_ARGUMENT,
              &(lc_load_desc){.companion = tpath("t.psf"), .options = OPT("value", "occupancy"), .noptions = 1});
    must_fail(tpath("t.dcd"), ": ", "fields by column 'chain'", "PSF topology has no such column",
              LC_ERROR_INVALID_ARGUMENT,
              &(lc_load_desc){.companion = tpath("t.psf"), .options = OPT("fields", "column:chain"), .noptions = 1});
    puts_("badq.psf", "PSF\n\n       1 !NTITLE\n* test\n\n       1 !NATOM\n"
                      "       1 PROA     1 ALA  N    NH3   minus        14.0070           0\n");
    write_dcd("one.dcd", 1);
    must_fail(tpath("one.dcd"), ": topology: ", ":7: expected atom 1 of 1", NULL, LC_ERROR_FORMAT,
              &(lc_load_desc){.companion = tpath("badq.psf"), .options = OPT("value", "charge"), .noptions = 1});
    write_dcd("nopsf.dcd", 4); /* no nopsf.psf next to it */
    must_fail(tpath("nopsf.dcd"), ": ", "value = 'mass' needs the topology", NULL, LC_ERROR_INVALID_ARGUMENT,
              LOAD({"value", "mass"}));

    /* adk.psf: masses, charges and types against the test's own reading */
    char psf[1024], dcd[1024], line[256];
    snprintf(psf, sizeof psf, "%s/particles/adk.psf", data);
    snprintf(dcd, sizeof dcd, "%s/particles/adk.dcd", data);
    FILE *f = fopen(psf, "r");
    if (!f) {
        printf("skip: %s absent\n", psf);
        return;
    }
    float mass[4000], charge[4000];
    uint8_t ids[4000];
    idmap types = {0};
    int n = 0, natom = -1;
    while (fgets(line, sizeof line, f)) {
        if (natom < 0) {
            if (strstr(line, "!NATOM")) natom = atoi(line);
            continue;
        }
        if (n == natom || n == 4000) break;
        char type[16];
        if (sscanf(line, "%*d %*s %*s %*s %*s %15s %f %f", type, &charge[n], &mass[n]) != 3) break;
        ids[n++] = (uint8_t)idmap_id(&types, type);
    }
    fclose(f);
    d = read_with(&lci_format_dcd, dcd, psf, (lc_option[]){{"value", "mass"}, {"fields", "column:type"}}, 2, &l);
    int ok = d && (int)d->count == n && n == natom && d->values && d->nfields == 8, bad = -1;
    for (int i = 0; ok && i < n; i++)
        if (d->values[i] != mass[i] || d->fields[i] != ids[i]) ok = 0, bad = i;
    CHECK(ok && nwarn == 1 && strstr(warned, "column type"),
          "adk.dcd + adk.psf value = mass, fields = column:type: %d atoms, %d types (the 9th on in field 7, one "
          "warning), as the PSF says (first bad %d)", n, types.n, bad);
    lci_loaded_free(&l);
    d = read_with(&lci_format_dcd, dcd, psf, OPT("value", "charge"), 1, &l);
    ok = d && (int)d->count == n && d->values;
    for (int i = 0; ok && i < n; i++) ok = d->values[i] == charge[i];
    CHECK(ok, "adk.dcd + adk.psf value = charge: every k_i the PSF's charge (atom 5: %g)", (double)charge[4]);
    lci_loaded_free(&l);
}

/* ------------------------------------------------------------------ CSV */

static void csv(void)
{
    /* 10 rows, kinds a..i (9 distinct) then a again; ids 0..9 */
    char text[2048];
    int m = snprintf(text, sizeof text, "x,y,z,kind,id,element,resname,chain,energy\n");
    for (int i = 0; i < 10; i++)
        m += snprintf(text + m, sizeof text - (size_t)m, "%d,0,0,%c,%d,%s,%s,%c,%d.25\n", i, i < 9 ? 'a' + i : 'a', i,
                      i % 3 ? "C" : "O", i < 4 ? "ALA" : "HOH", i < 5 ? 'A' : 'B', -i);
    puts_("opts.csv", text);
    lci_loaded l;
    const lc_particles_desc *d = read_with(&lci_format_csv, tpath("opts.csv"), NULL,
                                           (lc_option[]){{"fields", "column:kind"}, {"radius", "1"}}, 2, &l);
    int ok = d && d->count == 10 && d->nfields == 8;
    for (int i = 0; ok && i < 10; i++) ok = d->fields[i] == (i < 8 ? i : i == 8 ? 7 : 0);
    CHECK(ok && nwarn == 1 && strstr(warned, "column kind") && strstr(warned, "first 'i'"),
          "opts.csv fields = column:kind: 9 names, 'i' shares field 7, one warning: %s", warned);
    lci_loaded_free(&l);
    d = read_with(&lci_format_csv, tpath("opts.csv"), NULL, (lc_option[]){{"fields", "column:id"}, {"radius", "1"}}, 2,
                  &l);
    ok = d && d->count == 10 && d->nfields == 8;
    for (int i = 0; ok && i < 10; i++) ok = d->fields[i] == (i < 8 ? i : 7);
    CHECK(ok && nwarn == 1 && strstr(warned, "2 more distinct values"),
          "opts.csv fields = column:id: ids 0..7 as they are, 8 and 9 share field 7, one warning: %s", warned);
    lci_loaded_free(&l);
    d = read_with(&lci_format_csv, tpath("opts.csv"), NULL, (lc_option[]){{"value", "energy"}, {"radius", "1"}}, 2, &l);
    CHECK(d && d->values && d->values[3] == -3.25f, "opts.csv value = energy (row 4: '-3.25')");
    lci_loaded_free(&l);
    static const struct { const char *expr; size_t n; } sel[] = {
        {"index 2:4", 3}, {"element O", 4}, {"resname ALA and chain A", 4}, {"water", 6}, {"chain B or index 0", 6},
        {"not element C", 4}};
    for (size_t k = 0; k < sizeof sel / sizeof sel[0]; k++) {
        d = read_with(&lci_format_csv, tpath("opts.csv"), NULL, (lc_option[]){{"select", sel[k].expr}, {"radius", "1"}},
                      2, &l);
        CHECK(d && d->count == sel[k].n, "opts.csv select '%s': %zu rows (got %zu)", sel[k].expr, sel[k].n,
              d ? d->count : 0);
        lci_loaded_free(&l);
    }
    d = read_with(&lci_format_csv, tpath("opts.csv"), NULL,
                  (lc_option[]){{"select", "index 5:9"}, {"value", "energy"}, {"radius", "1"}}, 3, &l);
    CHECK(d && d->count == 5 && d->positions[0] == 5.0f && d->values[0] == -5.25f,
          "opts.csv select index 5:9 keeps rows 5..9 with their values");
    lci_loaded_free(&l);
    must_fail(tpath("opts.csv"), ": ", "keyword 'type' does not apply to csv files", "(they give index, element, resname, chain)",
              LC_ERROR_INVALID_ARGUMENT, LOAD({"select", "type 1"}, {"radius", "1"}));
    must_fail(tpath("opts.csv"), ": ", "select = 'index 50:60' matches none of the 10", NULL, LC_ERROR_INVALID_ARGUMENT,
              LOAD({"select", "index 50:60"}, {"radius", "1"}));
    puts_("bare.csv", "x y z type\n0 0 0 1\n1 0 0 2\n");
    must_fail(tpath("bare.csv"), ": ", "keyword 'protein' does not apply to csv files", "(they give index, type)",
              LC_ERROR_INVALID_ARGUMENT, LOAD({"select", "protein"}));
    must_fail(tpath("opts.csv"), ":1: ", "option value = 'mass'", "it names: x, y, z, kind", LC_ERROR_INVALID_ARGUMENT,
              LOAD({"value", "mass"}));
    must_fail(tpath("opts.csv"), ":1: ", "option fields = 'colour'", "no such column", LC_ERROR_INVALID_ARGUMENT,
              LOAD({"fields", "column:colour"}));
    puts_("e.csv", "x,y,z,energy\n0,0,0,1\n1,0,0,high\n");
    must_fail(tpath("e.csv"), ":3: ", "column 4 (energy) is 'high', expected a finite number", NULL, LC_ERROR_FORMAT,
              LOAD({"value", "energy"}));
}

/* ------------------------------------------------------------------ HDF5 */

static void hdf5(void)
{
#if LC_HAVE_HDF5
    hid_t f = H5Fcreate(tpath("sel.hdf5"), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    for (int t = 0; t < 2; t++) { /* PartType0: 3 particles at x = 0, 1, 2; PartType1: 2 at x = 10, 11 */
        char g[16];
        snprintf(g, sizeof g, "PartType%d", t);
        hid_t gr = H5Gcreate2(f, g, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        float x[9] = {0};
        int n = t ? 2 : 3;
        for (int i = 0; i < n; i++) x[3 * i] = (float)(10 * t + i), x[3 * i + 1] = (float)i;
        hsize_t dims[2] = {(hsize_t)n, 3};
        hid_t sp = H5Screate_simple(2, dims, NULL);
        hid_t ds = H5Dcreate2(gr, "Coordinates", H5T_IEEE_F32LE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        H5Dwrite(ds, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, x);
        H5Dclose(ds);
        if (t == 0) {
            ds = H5Dcreate2(gr, "Positions", H5T_IEEE_F32LE, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
            H5Dwrite(ds, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, x);
            H5Dclose(ds);
        }
        H5Sclose(sp);
        H5Gclose(gr);
    }
    H5Fclose(f);
    lci_loaded l;
    const lc_particles_desc *d = read_with(&lci_format_hdf5, tpath("sel.hdf5"), NULL,
                                           (lc_option[]){{"select", "type 1"}, {"radius", "1"}}, 2, &l);
    CHECK(d && d->count == 2 && d->positions[0] == 10.0f && d->nfields == 1 && d->fields[1] == 0,
          "sel.hdf5 select type 1: the 2 PartType1 particles, one field");
    lci_loaded_free(&l);
    d = read_with(&lci_format_hdf5, tpath("sel.hdf5"), NULL, (lc_option[]){{"select", "index 2:3"}, {"radius", "1"}}, 2,
                  &l);
    CHECK(d && d->count == 2 && d->positions[0] == 2.0f && d->positions[3] == 10.0f && d->nfields == 2 &&
              d->fields[0] == 0 && d->fields[1] == 1,
          "sel.hdf5 select index 2:3: the last of type 0 and the first of type 1 (index over the file, types in order)");
    lci_loaded_free(&l);
    d = read_with(&lci_format_hdf5, tpath("sel.hdf5"), NULL,
                  (lc_option[]){{"select", "not (type 0 and index 1)"}, {"radius", "1"}}, 2, &l);
    CHECK(d && d->count == 4, "sel.hdf5 select not (type 0 and index 1): 4 of 5");
    lci_loaded_free(&l);
    d = read_with(&lci_format_hdf5, tpath("sel.hdf5"), NULL,
                  (lc_option[]){{"select", "index 1"}, {"dataset", "/PartType0/Positions"}, {"radius", "1"}}, 3, &l);
    CHECK(d && d->count == 1 && d->positions[0] == 1.0f, "sel.hdf5 dataset = positions, select index 1");
    lci_loaded_free(&l);
    must_fail(tpath("sel.hdf5"), ": ", "keyword 'resname' does not apply to hdf5 files", "index and type",
              LC_ERROR_INVALID_ARGUMENT, LOAD({"select", "resname ALA"}, {"radius", "1"}));
    must_fail(tpath("sel.hdf5"), ": ", "keyword 'type' does not apply to hdf5 files", "a positions dataset has no types",
              LC_ERROR_INVALID_ARGUMENT,
              LOAD({"select", "type 0"}, {"dataset", "/PartType0/Positions"}, {"radius", "1"}));
    must_fail(tpath("sel.hdf5"), ": ", "matches none of the 5", NULL, LC_ERROR_INVALID_ARGUMENT,
              LOAD({"select", "type 4"}, {"radius", "1"}));
#else
    printf("skip: HDF5 select (built without libhdf5)\n");
#endif
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: test_formats_opts DATA_DIR TMP_DIR\n");
        return 2;
    }
    tmp = argv[2];
    lc_device_desc dd = {.threads = 1, .log = on_log};
    if (lc_device_create(&dd, &dev) != LC_OK) return 1;
    pdb_small();
    pdb_shared(argv[1]);
    mmcif();
    dcd_psf(argv[1]);
    csv();
    hdf5();
    lc_device_destroy(dev);
    return check_summary("formats_opts");
}
