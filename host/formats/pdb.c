/* Protein Data Bank files (wwPDB format 3.3): ATOM and HETATM records,
 * element from columns 77-78 or else the atom name. MODEL records are
 * frames: lc_load_desc.frame N reads the (N+1)-th MODEL of the file (MODEL
 * N+1 in a file numbered from 1), up to its ENDMDL; a file without MODEL
 * records is one frame. Alternate locations (column 17): the first of each
 * atom is kept (altloc.h). The `select` option sees name (13-16), resname
 * (18-21), chain (22), resid (23-26) and segid (73-76). Plain or gzip. Every
 * error names the file and line. */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/altloc.h"
#include "host/formats/elements.h"
#include "host/formats/text_reader.h"

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

static int is_model(const char *s) { return !strncmp(s, "MODEL", 5) && (!s[5] || strchr(" \r\n", s[5])); }

/* Reads the atoms of frame `frame`: the frame-th MODEL (in file order), or,
 * in a file without MODEL records, every ATOM/HETATM record as frame 0. */
static lc_status read_atoms(lci_text *t, int64_t frame, lci_atoms *p, lci_altlocs *alt)
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
        lci_atom_attr at = {name, resname, chain, segid, NULL, rnum, rend != resid && !*rend};
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
    s = lci_text_open(dev, a->path, &t);
    if (s != LC_OK) return s;
    lci_altlocs alt;
    memset(&alt, 0, sizeof alt);
    s = read_atoms(&t, a->desc->frame, &p, &alt);
    lci_text_close(&t);
    if (s == LC_OK && alt.skipped)
        lci_log(dev, LC_LOG_INFO, "%s: %zu alternate-location records skipped (the first of each atom kept)", a->path,
                alt.skipped);
    lci_altlocs_free(&alt);
    return lci_atoms_finish(dev, a->path, s, &p, out);
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
    .name = "pdb", .kind = LC_KIND_PARTICLES, .extensions = ".pdb .ent", .options = "radius radius_scale fields select",
    .description = "Protein Data Bank: ATOM/HETATM records, element from columns 77-78 or the atom name; MODEL records as frames",
    .magic = pdb_magic, .read = pdb_read, .frames = pdb_frames};
