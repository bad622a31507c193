/* GROMACS .gro coordinates (GROMACS manual, "File formats: gro"). Each frame
 * is a title line, a line with the atom count, one fixed-column line per
 * atom and a box line:
 *
 *     columns  1-5  residue number    11-15 atom name      21-... x y z (nm)
 *              6-10 residue name      16-20 atom number    then optional velocities
 *
 * x, y and z are %8.3f in 8-wide columns; like GROMACS we take the width from
 * the distance between the first two decimal points of a frame's first atom
 * line, so higher-precision files read too. The box line holds 3 (or 9)
 * numbers in nm. Frames are concatenated (trajectories); lc_load_desc.frame
 * picks one. Positions become Angstrom (x10) so the element radii apply.
 *
 * The element is the first letter of the atom name after leading digits
 * (OW -> O, HW1 -> H, 1HB -> H, CA -> C), except that a residue named like
 * its atom (an ion: NA/NA, CL/CL, CA/CA, ZN/ZN; charge signs ignored) gives
 * its two-letter element when the table knows it (CA/CA -> Ca).
 * Plain or gzip. Every error is one line naming the file and the line. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "host/formats/elements.h"
#include "host/formats/text_reader.h"
#include "host/formats/topology.h"

#define GRO_MAX_ATOMS ((long)INT32_MAX / 2)

/* Length of the line without its line end. */
static size_t line_len(const char *s) { return strcspn(s, "\r\n"); }

/* Reads a frame's title and count lines: 1 a frame follows (*natoms set), 0
 * the file ended before a title, or a negative status (reported). */
static int frame_header(lci_text *t, long *natoms)
{
    int rc = lci_text_line(t); /* title */
    if (rc <= 0) return rc < 0 ? LC_ERROR_IO : 0;
    if ((rc = lci_text_line(t)) < 0) return LC_ERROR_IO;
    if (rc == 0)
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: the file ends after a title line; expected the atom count",
                         t->path, t->lineno + 1);
    char *end;
    errno = 0;
    long n = strtol(t->line, &end, 10);
    while (isspace((unsigned char)*end)) end++;
    if (end == t->line || *end || errno || n < 0 || n > GRO_MAX_ATOMS)
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: expected the atom count (0 to %ld), got '%.*s'", t->path,
                         t->lineno, GRO_MAX_ATOMS, (int)(line_len(t->line) < 60 ? line_len(t->line) : 60), t->line);
    *natoms = n;
    return 1;
}

/* The box line: 3 or 9 numbers. 1 if s is one. */
static int is_box(const char *s)
{
    double v[10];
    int n = 0;
    for (char *end; n < 10; s = end, n++) {
        v[n] = strtod(s, &end);
        if (end == s || !isfinite(v[n])) break;
    }
    while (isspace((unsigned char)*s)) s++;
    return !*s && (n == 3 || n == 9);
}

static lc_status end_error(lci_text *t, long i, long natoms)
{
    if (i < natoms)
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: the file ends after %ld of the %ld atoms the count on line %ld gives",
                         t->path, t->lineno + 1, i, natoms, t->lineno - i);
    return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: the file ends where the box line should be (after %ld atoms)",
                     t->path, t->lineno + 1, natoms);
}

static lc_status box_line(lci_text *t, long natoms)
{
    if (is_box(t->line)) return LC_OK;
    return lci_error(t->dev, LC_ERROR_FORMAT,
                     "%s:%ld: expected the box line (3 or 9 numbers) after %ld atoms, got '%.*s'; does the count on line "
                     "%ld match?",
                     t->path, t->lineno, natoms, (int)(line_len(t->line) < 60 ? line_len(t->line) : 60), t->line,
                     t->lineno - natoms - 1);
}

/* Skips a frame's atom and box lines without parsing them. */
static lc_status skip_frame(lci_text *t, long natoms)
{
    for (long i = 0; i <= natoms; i++) {
        int rc = lci_text_line(t);
        if (rc < 0) return LC_ERROR_IO;
        if (rc == 0) return end_error(t, i, natoms);
    }
    return box_line(t, natoms);
}

/* Column width of x, y and z from the first atom line: the distance between
 * its first two decimal points after column 20 (GROMACS's own rule); 8 when
 * that finds nothing sensible (the line is then checked at that width). */
static int coord_width(const char *line)
{
    size_t len = line_len(line);
    if (len <= 20) return 8;
    const char *a = memchr(line + 20, '.', len - 20);
    const char *b = a ? memchr(a + 1, '.', len - (size_t)(a + 1 - line)) : NULL;
    long w = b ? (long)(b - a) : 8;
    return w >= 5 && w <= 20 ? (int)w : 8;
}

static void gro_element(const char *resname, const char *atom, char *el, size_t n)
{
    const char *s = atom;
    while (isdigit((unsigned char)*s)) s++;
    if (!isalpha((unsigned char)s[0])) {
        snprintf(el, n, "X");
        return;
    }
    size_t la = 0, lr = 0;
    while (isalpha((unsigned char)s[la])) la++;
    while (isalpha((unsigned char)resname[lr])) lr++;
    if (la == 2 && lr == 2 && !strncasecmp(s, resname, 2)) {
        char two[3] = {(char)toupper((unsigned char)s[0]), (char)tolower((unsigned char)s[1]), 0};
        if (lci_element_radius(two) > 0.0f) {
            snprintf(el, n, "%s", two);
            return;
        }
    }
    snprintf(el, n, "%c", (char)toupper((unsigned char)s[0]));
}

/* Parses atom i of natoms from t->line (coordinates in columns of width w). */
static lc_status atom_line(lci_text *t, long i, long natoms, int w, lci_atoms *p)
{
    size_t len = line_len(t->line);
    if (len < (size_t)(20 + 3 * w)) {
        if (is_box(t->line))
            return lci_error(t->dev, LC_ERROR_FORMAT,
                             "%s:%ld: a box line where atom %ld of %ld should be; the count on line %ld is too large",
                             t->path, t->lineno, i + 1, natoms, t->lineno - i - 1);
        return lci_error(t->dev, LC_ERROR_FORMAT,
                         "%s:%ld: atom line of %zu characters, expected at least %d (x y z in columns 21-%d)", t->path,
                         t->lineno, len, 20 + 3 * w, 20 + 3 * w);
    }
    float xyz[3];
    for (int c = 0; c < 3; c++) {
        char num[24];
        lci_column(t->line, 21 + c * w, 20 + (c + 1) * w, num, sizeof num);
        char *end;
        errno = 0;
        double v = strtod(num, &end);
        if (end == num || *end || errno || !isfinite(v))
            return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: %c coordinate '%s' in columns %d-%d is not a number",
                             t->path, t->lineno, "xyz"[c], num, 21 + c * w, 20 + (c + 1) * w);
        xyz[c] = (float)(v * 10.0); /* nm -> Angstrom */
    }
    char resname[8], atom[8], el[4], resid[8];
    lci_column(t->line, 1, 5, resid, sizeof resid);
    lci_column(t->line, 6, 10, resname, sizeof resname);
    lci_column(t->line, 11, 15, atom, sizeof atom);
    gro_element(resname, atom, el, sizeof el);
    char *rend;
    long rnum = strtol(resid, &rend, 10);
    lci_atom_attr at = {.name = atom, .resname = resname, .resid = rnum, .has_resid = rend != resid && !*rend};
    if (lci_atoms_add_attr(p, xyz[0], xyz[1], xyz[2], el, &at))
        return lci_error(t->dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory at line %ld", t->path, t->lineno);
    return LC_OK;
}

static lc_status read_frame(lci_text *t, long natoms, lci_atoms *p)
{
    int w = 8;
    for (long i = 0; i <= natoms; i++) {
        int rc = lci_text_line(t);
        if (rc < 0) return LC_ERROR_IO;
        if (rc == 0) return end_error(t, i, natoms);
        if (i == natoms) return box_line(t, natoms);
        if (i == 0) w = coord_width(t->line);
        lc_status s = atom_line(t, i, natoms, w, p);
        if (s != LC_OK) return s;
    }
    return LC_OK;
}

/* Reads frame `frame` (skipping the ones before it). */
static lc_status read_atoms(lci_text *t, int64_t frame, lci_atoms *p)
{
    for (int64_t k = 0;; k++) {
        long natoms = 0;
        int rc = frame_header(t, &natoms);
        if (rc < 0) return (lc_status)rc;
        if (rc == 0 && k == 0) return lci_error(t->dev, LC_ERROR_FORMAT, "%s: empty file, expected a title line", t->path);
        if (rc == 0)
            return lci_error(t->dev, LC_ERROR_FORMAT, "%s: frame %lld is past the end: the file holds %lld frame%s",
                             t->path, (long long)frame, (long long)k, k == 1 ? "" : "s");
        lc_status s = k == frame ? read_frame(t, natoms, p) : skip_frame(t, natoms);
        if (s != LC_OK || k == frame) return s;
    }
}

static lc_status gro_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    lci_atoms p;
    memset(&p, 0, sizeof p);
    lc_status s = lci_atom_options(dev, a, &p.o);
    if (s != LC_OK) return s;
    lci_text t;
    s = lci_text_open(dev, a->path, &t);
    if (s != LC_OK) return s;
    s = read_atoms(&t, a->desc->frame, &p);
    lci_text_close(&t);
    return lci_atoms_finish(dev, a->path, s, &p, out);
}

lc_status lci_gro_topology(lc_device *dev, const char *path, lci_atoms *p)
{
    lci_text t;
    lc_status s = lci_text_open(dev, path, &t);
    if (s != LC_OK) return s;
    s = read_atoms(&t, 0, p);
    lci_text_close(&t);
    return s;
}

/* Counts the frames by their count lines, skipping the atom lines unparsed. */
static lc_status gro_frames(lc_device *dev, const char *path, int64_t *out)
{
    lci_text t;
    lc_status s = lci_text_open(dev, path, &t);
    if (s != LC_OK) return s;
    int64_t k = 0;
    for (;; k++) {
        long natoms = 0;
        int rc = frame_header(&t, &natoms);
        if (rc <= 0) {
            s = (lc_status)rc;
            break;
        }
        if ((s = skip_frame(&t, natoms)) != LC_OK) break;
    }
    lci_text_close(&t);
    *out = k;
    return s;
}

const lci_format lci_format_gro = {
    .name = "gro", .kind = LC_KIND_PARTICLES, .extensions = ".gro", .options = "radius radius_scale fields select",
    .description = "GROMACS .gro: fixed columns in nm (read as Angstrom), frames concatenated; element from the atom "
                   "name's first letter (ions: residue = atom name)",
    .read = gro_read, .frames = gro_frames};
