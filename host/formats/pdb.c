/* Protein Data Bank files (wwPDB format 3.3): ATOM and HETATM records,
 * element from columns 77-78 or else the atom name. MODEL records are
 * frames: lc_load_desc.frame N reads the (N+1)-th MODEL of the file (MODEL
 * N+1 in a file numbered from 1), up to its ENDMDL; a file without MODEL
 * records is one frame. Alternate locations (column 17): the first of each
 * atom is kept (altloc.h). The `select` option sees name (13-16), resname
 * (18-21), chain (22), resid (23-26) and segid (73-76). `value = COLUMN`
 * (occupancy, bfactor, ...) sets k_i and `fields = column:NAME` maps any
 * named column's distinct values to fields (pdb_cols below). Plain or gzip.
 * Every error names the file and line. */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "host/formats/altloc.h"
#include "host/formats/elements.h"
#include "host/formats/text_reader.h"
#include "host/formats/topology.h"

static void pdb_element(const char *line, char *el, size_t n)
{
    lci_column(line, 77, 78, el, n);
    if (el[0] && isalpha((unsigned char)el[0])) return;
    /* no element column: the atom name (cols 13-16); a name starting in column
     * 13 may be a two-letter element (e.g. "FE  "), else the first letter */
    char name[8];
    lci_column(line, 13, 16, name, sizeof name);
    const char *s = name;
    while (*s && !isalpha((unsigned char)*s)) s++;
    int starts_at_13 = strlen(line) > 12 && isalpha((unsigned char)line[12]);
    /* a four-character name starting with H in column 13 is a hydrogen (HG23,
     * HE22, HD11 in CHARMM and PDB files), not mercury or helium */
    int h4 = starts_at_13 && toupper((unsigned char)s[0]) == 'H' && strlen(name) == 4;
    if (starts_at_13 && !h4 && isalpha((unsigned char)s[0]) && isalpha((unsigned char)s[1])) {
        char two[3] = {s[0], (char)tolower((unsigned char)s[1]), 0};
        if (lci_element_radius(two) > 0.0f) {
            snprintf(el, n, "%s", two);
            return;
        }
    }
    snprintf(el, n, "%c", s[0] ? s[0] : 'X');
}

/* The named columns of an ATOM/HETATM record (wwPDB 3.3 columns; names
 * after VMD's and MDAnalysis's, with aliases) that `fields = column:NAME`
 * and `value = COLUMN` can name. element is the element lanecast gives the
 * atom (columns 77-78, else from the name); charge reads "2+" and "1-",
 * blank as 0. */
typedef struct pdb_col {
    const char *names; /* the name, then aliases */
    int a, b;
} pdb_col;
static const pdb_col pdb_cols[] = {
    {"record", 1, 6},        {"serial", 7, 11},   {"name atomname", 13, 16},         {"altloc", 17, 17},
    {"resname", 18, 21},     {"chain chainid", 22, 22}, {"resid resseq resnum", 23, 26}, {"icode", 27, 27},
    {"x", 31, 38},           {"y", 39, 46},       {"z", 47, 54},                     {"occupancy occ", 55, 60},
    {"bfactor tempfactor beta b", 61, 66}, {"segid", 73, 76}, {"element", 77, 78},   {"charge", 79, 80}};
#define PDB_NCOLS ((int)(sizeof pdb_cols / sizeof pdb_cols[0]))
#define PDB_ELEMENT 14
#define PDB_CHARGE 15

/* The column of name (case-insensitive, aliases too), or -1. */
static int pdb_col_find(const char *name)
{
    size_t n = strlen(name);
    for (int k = 0; k < PDB_NCOLS; k++)
        for (const char *w = pdb_cols[k].names; *w; w += strcspn(w, " "), w += *w == ' ')
            if (strcspn(w, " ") == n && !strncasecmp(w, name, n)) return k;
    return -1;
}

static lc_status pdb_col_error(lc_device *dev, const char *path, const char *what, const char *name)
{
    return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                     "%s: %s '%s': PDB records have no such column (they have record, serial, name, altloc, resname, "
                     "chain, resid, icode, x, y, z, occupancy, bfactor (tempfactor, beta), segid, element, charge)",
                     path, what, name);
}

/* A value from columns a..b: a number, or a charge "2+" / "1-" / "+1". */
static int pdb_number(const char *s, int charge, float *out)
{
    if (charge && !s[0]) return *out = 0.0f, 0; /* blank: neutral */
    if (charge && s[0] && (s[1] == '+' || s[1] == '-') && !s[2] && s[0] >= '0' && s[0] <= '9')
        return *out = (float)((s[0] - '0') * (s[1] == '-' ? -1 : 1)), 0;
    return lci_parse_float(s, out);
}

static int is_model(const char *s) { return !strncmp(s, "MODEL", 5) && (!s[5] || strchr(" \r\n", s[5])); }

/* Reads the atoms of frame `frame`: the frame-th MODEL (in file order), or,
 * in a file without MODEL records, every ATOM/HETATM record as frame 0. */
static lc_status read_atoms(lci_text *t, int64_t frame, lci_atoms *p, lci_altlocs *alt, int fcol, int vcol)
{
    int rc;
    int64_t model = -1; /* index of the MODEL we are in, -1 before the first */
    while ((rc = lci_text_line(t)) == 1) {
        if (is_model(t->line)) {
            model++;
            if (model == frame) /* atoms before the first MODEL belong to no model */
                p->n = p->seen = p->nsolvent = 0, alt->residue[0] = 0, alt->n = 0;
            continue;
        }
        if (!strncmp(t->line, "ENDMDL", 6)) {
            if (model == frame) break;
            continue;
        }
        if (strncmp(t->line, "ATOM  ", 6) && strncmp(t->line, "HETATM", 6)) continue;
        if (model != frame && !(model < 0 && frame == 0)) continue;
        char xs[16], ys[16], zs[16], el[8];
        lci_column(t->line, 31, 38, xs, sizeof xs);
        lci_column(t->line, 39, 46, ys, sizeof ys);
        lci_column(t->line, 47, 54, zs, sizeof zs);
        float x, y, z;
        if (lci_parse_float(xs, &x) || lci_parse_float(ys, &y) || lci_parse_float(zs, &z))
            return lci_error(t->dev, LC_ERROR_FORMAT,
                             "%s:%ld: ATOM record with coordinates '%s' '%s' '%s' in columns 31-54 that are not numbers",
                             t->path, t->lineno, xs, ys, zs);
        /* the atom: residue = chain (22), number (23-26), insertion code (27); name 13-16 */
        char res[16], name[8];
        lci_column(t->line, 22, 27, res, sizeof res);
        lci_column(t->line, 13, 16, name, sizeof name);
        int blank = strlen(t->line) < 17 || t->line[16] == ' ';
        int keep = lci_altloc_keep(alt, res, name, blank);
        if (keep == 0) continue;
        pdb_element(t->line, el, sizeof el);
        char resname[8], chain[4], resid[8], segid[8];
        lci_column(t->line, 18, 21, resname, sizeof resname); /* 18-20, and 21 for CHARMM's TIP3 */
        lci_column(t->line, 22, 22, chain, sizeof chain);
        lci_column(t->line, 23, 26, resid, sizeof resid);
        lci_column(t->line, 73, 76, segid, sizeof segid);
        char *rend;
        long rnum = strtol(resid, &rend, 10);
        lci_atom_attr at = {.name = name, .resname = resname, .chain = chain, .segid = segid, .resid = rnum,
                            .has_resid = rend != resid && !*rend};
        char colv[16], vs[16];
        if (fcol >= 0) {
            if (fcol == PDB_ELEMENT) snprintf(colv, sizeof colv, "%s", el);
            else lci_column(t->line, pdb_cols[fcol].a, pdb_cols[fcol].b, colv, sizeof colv);
            at.column = colv;
        }
        if (vcol >= 0) {
            lci_column(t->line, pdb_cols[vcol].a, pdb_cols[vcol].b, vs, sizeof vs);
            if (pdb_number(vs, vcol == PDB_CHARGE, &at.value) || !isfinite(at.value))
                return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: value = %s: columns %d-%d are '%s', not a number",
                                 t->path, t->lineno, p->o.value, pdb_cols[vcol].a, pdb_cols[vcol].b, vs);
        }
        if (keep < 0 || lci_atoms_add_attr(p, x, y, z, el, &at))
            return lci_error(t->dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory at line %ld", t->path, t->lineno);
    }
    if (rc < 0) return LC_ERROR_IO;
    if (frame > 0 && model < frame)
        return lci_error(t->dev, LC_ERROR_INVALID_ARGUMENT, "%s: frame %lld is past the end: the file holds %lld MODEL%s",
                         t->path, (long long)frame, (long long)(model + 1 > 1 ? model + 1 : 1),
                         model + 1 > 1 ? "s" : "");
    if (p->seen == 0)
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s: no ATOM or HETATM records%s", t->path,
                         model >= 0 ? " in the MODEL read" : "");
    return LC_OK;
}

static lc_status pdb_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    lci_atoms p;
    memset(&p, 0, sizeof p);
    lc_status s = lci_atom_options(dev, a, &p.o);
    if (s != LC_OK) return s;
    lci_text t;
    int fcol = p.o.column ? pdb_col_find(p.o.column) : -1, vcol = p.o.value ? pdb_col_find(p.o.value) : -1;
    if (p.o.column && fcol < 0) return pdb_col_error(dev, a->path, "fields by column", p.o.column);
    if (p.o.value && vcol < 0) return pdb_col_error(dev, a->path, "value =", p.o.value);
    s = lci_text_open(dev, a->path, &t);
    if (s != LC_OK) return s;
    lci_altlocs alt;
    memset(&alt, 0, sizeof alt);
    s = read_atoms(&t, a->desc->frame, &p, &alt, fcol, vcol);
    lci_text_close(&t);
    if (s == LC_OK && alt.skipped)
        lci_log(dev, LC_LOG_INFO, "%s: %zu alternate-location records skipped (the first of each atom kept)", a->path,
                alt.skipped);
    lci_altlocs_free(&alt);
    return lci_atoms_finish(dev, a->path, s, &p, out);
}

lc_status lci_pdb_topology(lc_device *dev, const char *path, lci_atoms *p)
{
    lci_text t;
    lc_status s = lci_text_open(dev, path, &t);
    if (s != LC_OK) return s;
    lci_altlocs alt;
    memset(&alt, 0, sizeof alt);
    s = read_atoms(&t, 0, p, &alt, -1, -1);
    lci_text_close(&t);
    lci_altlocs_free(&alt);
    return s;
}

/* Frames are MODEL records (1 when there are none). */
static lc_status pdb_frames(lc_device *dev, const char *path, int64_t *out)
{
    lci_text t;
    lc_status s = lci_text_open(dev, path, &t);
    *out = 0;
    if (s != LC_OK) return s;
    int rc;
    int64_t n = 0;
    while ((rc = lci_text_line(&t)) == 1)
        if (is_model(t.line)) n++;
    lci_text_close(&t);
    if (rc < 0) return LC_ERROR_IO;
    *out = n > 0 ? n : 1;
    return LC_OK;
}

/* A PDB file starts with one of its record names in columns 1-6. */
static int pdb_magic(const unsigned char *h, size_t n)
{
    static const char *const rec[] = {"HEADER", "ATOM  ", "HETATM", "CRYST1", "REMARK", "MODEL ", "TITLE ", "COMPND"};
    if (n < 6) return 0;
    for (size_t i = 0; i < sizeof rec / sizeof rec[0]; i++)
        if (!memcmp(h, rec[i], 6)) return 1;
    return 0;
}

const lci_format lci_format_pdb = {
    .name = "pdb", .kind = LC_KIND_PARTICLES, .extensions = ".pdb .ent", .options = "radius radius_scale fields select value",
    .description = "Protein Data Bank: ATOM/HETATM records, element from columns 77-78 or the atom name; MODEL records as frames",
    .magic = pdb_magic, .read = pdb_read, .frames = pdb_frames};
