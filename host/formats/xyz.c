/* XYZ and extended XYZ: "element x y z" lines, either bare (one frame) or in
 * frames of a count line, a comment line and that many atom lines, repeated
 * (trajectories; lc_load_desc.frame picks one, lc_file_probe counts them).
 * Extended XYZ puts key=value pairs in the comment line; Lattice and the
 * rest are read past, and Properties=species:S:1:pos:R:3:... (name:type:
 * columns triples) says in which columns the element and the position are
 * (default: element first, then x y z; more columns are allowed). Blank
 * lines and lines starting with '#' are skipped outside the comment line.
 * Plain or gzip. Every error names the file and line. */
#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/elements.h"
#include "host/formats/text_reader.h"

#define XYZ_MAX_COLS 64

static int trim_len(const char *s) { size_t n = strcspn(s, "\r\n"); return (int)(n < 60 ? n : 60); }

static int blank(const char *s)
{
    while (isspace((unsigned char)*s)) s++;
    return !*s || *s == '#';
}

/* 1 if s is a lone count (0 .. INT32_MAX/2), 0 if not, -1 if it is a lone
 * integer out of that range (negative or too large: an error, not atoms). */
static int count_line(const char *s, long *n)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (end == s) return 0;
    const char *e = end;
    while (isspace((unsigned char)*e)) e++;
    if (*e) return 0;
    if (errno || v < 0 || v > (long)INT32_MAX / 2) return -1;
    *n = v;
    return 1;
}

static lc_status bad_count(const lci_text *t)
{
    return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: atom count '%.*s' is not a count from 0 to %ld", t->path,
                     t->lineno, trim_len(t->line), t->line, (long)INT32_MAX / 2);
}

/* The next line that is not blank: 1, 0 at the end, -1 error. */
static int next_line(lci_text *t)
{
    int rc;
    while ((rc = lci_text_line(t)) == 1 && blank(t->line)) {}
    return rc;
}

/* Columns of the element and of x from an extended-XYZ comment line. */
static void properties(const char *comment, int *sp, int *pos)
{
    *sp = 0, *pos = 1;
    const char *p = strstr(comment, "Properties=");
    if (!p) return;
    p += 11;
    if (*p == '"') p++;
    int column = 0;
    while (*p && !isspace((unsigned char)*p) && *p != '"') {
        char name[32] = "", type[8] = "";
        int cols = 0, used = 0;
        if (sscanf(p, "%31[^:]:%7[^:]:%d%n", name, type, &cols, &used) != 3 || cols < 1) return;
        if (!strcmp(name, "species")) *sp = column;
        if (!strcmp(name, "pos") && cols == 3) *pos = column;
        column += cols;
        p += used;
        if (*p == ':') p++;
    }
}

static lc_status atom_line(lci_text *t, int sp, int pos, lci_atoms *p)
{
    char *tok[XYZ_MAX_COLS];
    int n = 0;
    char copy[LCI_LINE_MAX];
    snprintf(copy, sizeof copy, "%s", t->line);
    for (char *s = strtok(copy, " \t\r\n"); s && n < XYZ_MAX_COLS; s = strtok(NULL, " \t\r\n")) tok[n++] = s;
    int need = (sp > pos + 2 ? sp : pos + 2) + 1;
    if (n < need)
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: expected 'element x y z'%s, got '%.*s'", t->path, t->lineno,
                         sp || pos != 1 ? " in the columns Properties gives" : "", trim_len(t->line), t->line);
    float x, y, z;
    if (lci_parse_float(tok[pos], &x) || lci_parse_float(tok[pos + 1], &y) || lci_parse_float(tok[pos + 2], &z))
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: coordinates '%s %s %s' are not numbers", t->path, t->lineno,
                         tok[pos], tok[pos + 1], tok[pos + 2]);
    char el[16];
    snprintf(el, sizeof el, "%s", tok[sp]);
    if (lci_atoms_add(p, x, y, z, el))
        return lci_error(t->dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory at line %ld", t->path, t->lineno);
    return LC_OK;
}

/* A frame's comment and atom lines after its count line (parsed when p is
 * not NULL, else skipped). */
static lc_status frame_body(lci_text *t, long declared, int64_t k, lci_atoms *p)
{
    long countline = t->lineno;
    int rc = lci_text_line(t);
    if (rc < 0) return LC_ERROR_IO;
    if (rc == 0)
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: the file ends after the count line of frame %lld; expected a "
                         "comment line", t->path, t->lineno + 1, (long long)k);
    int sp = 0, pos = 1;
    if (p) properties(t->line, &sp, &pos);
    for (long i = 0; i < declared; i++) {
        if ((rc = next_line(t)) < 0) return LC_ERROR_IO;
        if (rc == 0)
            return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: the header on line %ld declares %ld atoms but only %ld follow",
                             t->path, t->lineno + 1, countline, declared, i);
        if (p) {
            lc_status s = atom_line(t, sp, pos, p);
            if (s != LC_OK) return s;
        }
    }
    return LC_OK;
}

/* Reads frame `frame` (p != NULL) or counts the frames (*nframes). */
static lc_status walk(lci_text *t, int64_t frame, lci_atoms *p, int64_t *nframes)
{
    int rc = next_line(t);
    if (rc < 0) return LC_ERROR_IO;
    long declared;
    int c = rc == 1 ? count_line(t->line, &declared) : 0;
    if (c < 0) return bad_count(t);
    if (rc == 0) /* like an empty PDB file: nothing to render is an error */
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s: no atoms (an empty file, or only blank and comment lines)",
                         t->path);
    if (c == 0) { /* bare atom lines: one frame */
        *nframes = 1;
        if (p && frame > 0)
            return lci_error(t->dev, LC_ERROR_INVALID_ARGUMENT, "%s: frame %lld is past the end: the file holds 1 frame "
                             "(no count lines)", t->path, (long long)frame);
        for (; p && rc == 1; rc = next_line(t)) {
            lc_status s = atom_line(t, 0, 1, p);
            if (s != LC_OK) return s;
        }
        return rc < 0 ? LC_ERROR_IO : LC_OK;
    }
    for (int64_t k = 0;; k++) {
        lc_status s = frame_body(t, declared, k, p && k == frame ? p : NULL);
        if (s != LC_OK) return s;
        *nframes = k + 1;
        if ((rc = next_line(t)) < 0) return LC_ERROR_IO;
        /* the frame read: the next line must start a frame too (else its count was wrong) */
        c = rc == 1 ? count_line(t->line, &declared) : 0;
        if (c < 0) return bad_count(t);
        if (rc == 0 || (p && k == frame && c)) {
            if (p && k == frame) return LC_OK;
            break;
        }
        if (!c)
            return lci_error(t->dev, LC_ERROR_FORMAT,
                             "%s:%ld: expected the atom count of frame %lld, got '%.*s'; does the count of frame %lld match "
                             "its atoms?",
                             t->path, t->lineno, (long long)k + 1, trim_len(t->line), t->line, (long long)k);
    }
    if (p)
        return lci_error(t->dev, LC_ERROR_INVALID_ARGUMENT, "%s: frame %lld is past the end: the file holds %lld frame%s",
                         t->path, (long long)frame, (long long)*nframes, *nframes == 1 ? "" : "s");
    return LC_OK;
}

static lc_status xyz_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    lci_atoms p;
    memset(&p, 0, sizeof p);
    lc_status s = lci_atom_options(dev, a, &p.o);
    if (s != LC_OK) return s;
    lci_text t;
    s = lci_text_open(dev, a->path, &t);
    if (s != LC_OK) return s;
    int64_t n = 0;
    s = walk(&t, a->desc->frame, &p, &n);
    lci_text_close(&t);
    return lci_atoms_finish(dev, a->path, s, &p, out);
}

static lc_status xyz_frames(lc_device *dev, const char *path, int64_t *out)
{
    lci_text t;
    lc_status s = lci_text_open(dev, path, &t);
    *out = 0;
    if (s != LC_OK) return s;
    s = walk(&t, 0, NULL, out);
    lci_text_close(&t);
    return s;
}

const lci_format lci_format_xyz = {
    .name = "xyz", .kind = LC_KIND_PARTICLES, .extensions = ".xyz .extxyz", .options = "radius radius_scale fields select",
    .description = "XYZ and extended XYZ: element x y z lines, bare or in count + comment frames (Properties= gives "
                   "the columns)",
    .read = xyz_read, .frames = xyz_frames};
