/* PSF topology (psf.h). The file starts with "PSF" (and flags such as EXT,
 * CMAP, CHEQ, XPLOR), then "N !NTITLE" with N title lines, then "N !NATOM"
 * with one line per atom:
 *
 *     id segid resid resname name type charge mass imove [...]
 *
 * (fixed columns I8/A4 in the standard layout, I10/A8 with EXT; CHARMM
 * writes the type as a number, X-PLOR as a name). Fields are read split at
 * white space, which reads both layouts. Only the !NATOM section is read;
 * bonds and the rest are not needed for rendering.
 *
 * A PSF has no element column. The element is the one whose standard atomic
 * mass lies within 0.1 u of the atom's mass (CHARMM's masses: 1.008 H,
 * 12.011 C, 14.007 N, 15.999 O, 32.06 S, ...), else (hydrogen mass
 * repartitioning, lone pairs, united atoms) the atom name's first letter. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/psf.h"
#include "host/formats/text_reader.h"

#define PSF_MAX_ATOMS ((long)INT32_MAX / 2)

static const struct {
    const char *sym;
    float mass;
} masses[] = {
    {"H", 1.008f},   {"He", 4.003f},  {"Li", 6.94f},   {"B", 10.81f},   {"C", 12.011f},  {"N", 14.007f},
    {"O", 15.999f},  {"F", 18.998f},  {"Na", 22.990f}, {"Mg", 24.305f}, {"Al", 26.982f}, {"Si", 28.085f},
    {"P", 30.974f},  {"S", 32.06f},   {"Cl", 35.45f},  {"K", 39.098f},  {"Ca", 40.078f}, {"Mn", 54.938f},
    {"Fe", 55.845f}, {"Co", 58.933f}, {"Ni", 58.693f}, {"Cu", 63.546f}, {"Zn", 65.38f},  {"Se", 78.971f},
    {"Br", 79.904f}, {"Rb", 85.468f}, {"Sr", 87.62f},  {"Cd", 112.41f}, {"I", 126.90f},  {"Cs", 132.91f},
    {"Ba", 137.33f},
};

static void element_of(const char *name, float mass, char *el, size_t n)
{
    for (size_t i = 0; i < sizeof masses / sizeof masses[0]; i++)
        if (fabsf(mass - masses[i].mass) < 0.1f) {
            snprintf(el, n, "%s", masses[i].sym);
            return;
        }
    const char *s = name;
    while (*s && !isalpha((unsigned char)*s)) s++;
    snprintf(el, n, "%c", *s ? (char)toupper((unsigned char)*s) : 'X');
}

static size_t trim_len(const char *s) { size_t n = strcspn(s, "\r\n"); return n < 60 ? n : 60; }

/* The leading count of a "N !WORD" line, or -1 if the line is not one. */
static long section_count(const char *line, const char *word)
{
    const char *bang = strstr(line, word);
    if (!bang) return -1;
    char *end;
    errno = 0;
    long n = strtol(line, &end, 10);
    if (end == line || errno || n < 0) return -2;
    return n;
}

static lc_status read_atoms(lci_text *t, lci_psf *p)
{
    int rc = lci_text_line(t);
    if (rc < 0) return LC_ERROR_IO;
    if (rc == 0 || strncmp(t->line, "PSF", 3))
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s:1: not a PSF file: expected the line to start with 'PSF'", t->path);
    long natom = -1;
    while ((rc = lci_text_line(t)) == 1) {
        long n = section_count(t->line, "!NTITLE");
        if (n >= 0) { /* skip the title lines (they may contain anything) */
            for (long i = 0; i < n && (rc = lci_text_line(t)) == 1; i++) {}
            if (rc <= 0) break;
            continue;
        }
        n = section_count(t->line, "!NATOM");
        if (n == -2 || n > PSF_MAX_ATOMS)
            return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: expected the atom count (0 to %ld) before !NATOM, got '%.*s'",
                             t->path, t->lineno, PSF_MAX_ATOMS, (int)trim_len(t->line), t->line);
        if (n >= 0) {
            natom = n;
            break;
        }
    }
    if (rc < 0) return LC_ERROR_IO;
    if (natom < 0) return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: the file ends before its !NATOM section", t->path, t->lineno);
    long cap = 0;
    for (long i = 0; i < natom; i++) {
        if ((rc = lci_text_line(t)) < 0) return LC_ERROR_IO;
        if (rc == 0)
            return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: the file ends after %ld of the %ld atoms of !NATOM",
                             t->path, t->lineno + 1, i, natom);
        char tok[9][32];
        int k = sscanf(t->line, "%31s %31s %31s %31s %31s %31s %31s %31s %31s", tok[0], tok[1], tok[2], tok[3], tok[4],
                       tok[5], tok[6], tok[7], tok[8]);
        float charge, mass;
        char *end;
        long id = k >= 8 ? strtol(tok[0], &end, 10) : 0;
        if (k < 8 || *end || id <= 0 || lci_parse_float(tok[6], &charge) || lci_parse_float(tok[7], &mass) ||
            !isfinite(mass) || mass < 0.0f)
            return lci_error(t->dev, LC_ERROR_FORMAT,
                             "%s:%ld: expected atom %ld of %ld as 'id segid resid resname name type charge mass imove', "
                             "got '%.*s'",
                             t->path, t->lineno, i + 1, natom, (int)trim_len(t->line), t->line);
        if (i == cap) {
            cap = cap ? 2 * cap : 4096;
            lci_psf_atom *a = realloc(p->atom, sizeof *a * (size_t)cap);
            if (!a) return lci_error(t->dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory at line %ld", t->path, t->lineno);
            p->atom = a;
        }
        lci_psf_atom *a = &p->atom[i];
        snprintf(a->name, sizeof a->name, "%.8s", tok[4]);
        snprintf(a->type, sizeof a->type, "%.8s", tok[5]);
        snprintf(a->segid, sizeof a->segid, "%.8s", tok[1]);
        snprintf(a->resname, sizeof a->resname, "%.8s", tok[3]);
        a->resid = strtol(tok[2], NULL, 10);
        a->charge = charge;
        a->mass = mass;
        element_of(a->name, mass, a->element, sizeof a->element);
        p->natom = i + 1;
    }
    return LC_OK;
}

lc_status lci_psf_read(lc_device *dev, const char *path, lci_psf *out)
{
    memset(out, 0, sizeof *out);
    lci_text t;
    lc_status s = lci_text_open(dev, path, &t);
    if (s != LC_OK) return s;
    s = read_atoms(&t, out);
    lci_text_close(&t);
    if (s != LC_OK) lci_psf_free(out);
    return s;
}

void lci_psf_free(lci_psf *p)
{
    free(p->atom);
    p->atom = NULL;
    p->natom = 0;
}
