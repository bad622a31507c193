/* LAMMPS text dumps (`dump atom` and `dump custom`; LAMMPS manual, "dump
 * command"). Each frame (snapshot) is a run of ITEM sections:
 *
 *     ITEM: TIMESTEP                   one line: the step
 *     ITEM: NUMBER OF ATOMS            one line: N
 *     ITEM: BOX BOUNDS [xy xz yz] pp pp pp    three lines: lo hi [tilt]
 *     ITEM: ATOMS id type x y z ...    N lines of the named columns
 *
 * (ITEM: TIME and ITEM: UNITS, one line each, are read past). Positions come
 * from x y z (or the unwrapped xu yu zu), else from the scaled xs ys zs (or
 * xsu ysu zsu), which map through the box: orthogonal x = xlo + xs (xhi -
 * xlo); triclinic boxes (bounds lines with a tilt) through the box matrix,
 * with the bounding-box corners turned back into xlo..xhi as the manual
 * shows. Options: `fields` (alias field_by) = `type` (field = type - 1; types
 * above 8 share field 7, with a warning), `element` (by an element column),
 * `column:NAME` (any column's distinct values, the first 8 as fields) or
 * `none` (the default); `select` (type = atom type, index; element with an
 * element column); `value = COLUMN` takes any
 * per-atom column as k_i; radius from the `radius` option, else a radius
 * column, else a diameter column (halved), else the element column's
 * covalent radius, else 0.5 (LJ sigma = 1). `radius_scale` scales them.
 * lc_load_desc.frame picks a frame. Plain or gzip; errors name the line. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "host/formats/elements.h"
#include "host/formats/plist.h"
#include "host/formats/text_reader.h"

#define LMP_MAX_ATOMS ((long long)INT32_MAX / 2)
#define LMP_MAX_COLS 64
#define LMP_DEFAULT_RADIUS 0.5f

typedef struct opts {
    float radius, radius_scale;
    int fields; /* 0 none, 1 type, 2 element, 3 column */
    const char *value, *column;
    lci_psel sel;
    lci_fieldmap fm;
} opts;

typedef struct frame_head {
    long long natoms;
    double lo[3], hi[3], tilt[3]; /* xy xz yz */
    int triclinic, have_n, have_box;
    char cols[LMP_MAX_COLS][32];
    int ncols;
    long atoms_line;
} frame_head;

static int trim_len(const char *s) { size_t n = strcspn(s, "\r\n"); return (int)(n < 60 ? n : 60); }

/* "ITEM: NAME" -> NAME, else NULL. */
static const char *item(const char *line)
{
    if (strncmp(line, "ITEM:", 5)) return NULL;
    line += 5;
    while (*line == ' ' || *line == '\t') line++;
    return line;
}

static int starts(const char *s, const char *w) { return !strncmp(s, w, strlen(w)); }

/* One number line of the header: n numbers (2 or 3 for bounds). Returns
 * how many were read. */
static int numbers(const char *s, double *v, int max)
{
    int k = 0;
    for (char *end; k < max; s = end, k++) {
        errno = 0;
        v[k] = strtod(s, &end);
        if (end == s || errno || !isfinite(v[k])) break;
    }
    while (isspace((unsigned char)*s)) s++;
    return *s ? -1 : k;
}

/* Reads the ITEM sections up to and including ITEM: ATOMS. 1 a frame
 * follows, 0 the file ended before one, or a negative status. */
static int read_head(lci_text *t, frame_head *h, int64_t k)
{
    memset(h, 0, sizeof *h);
    int rc;
    int seen = 0;
    while ((rc = lci_text_line(t)) == 1) {
        const char *s = t->line;
        while (isspace((unsigned char)*s)) s++;
        if (!*s && !seen) continue; /* blank lines between frames */
        const char *it = item(t->line);
        if (!it)
            return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: expected an 'ITEM:' line (frame %lld), got '%.*s'",
                             t->path, t->lineno, (long long)k, trim_len(t->line), t->line);
        seen = 1;
        if (starts(it, "TIMESTEP") || starts(it, "TIME") || starts(it, "UNITS")) {
            if ((rc = lci_text_line(t)) <= 0) break;
            continue;
        }
        if (starts(it, "NUMBER OF ATOMS")) {
            if ((rc = lci_text_line(t)) <= 0) break;
            char *end;
            errno = 0;
            long long n = strtoll(t->line, &end, 10);
            while (isspace((unsigned char)*end)) end++;
            if (end == t->line || *end || errno || n < 0 || n > LMP_MAX_ATOMS)
                return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: expected the number of atoms (0 to %lld), got '%.*s'",
                                 t->path, t->lineno, LMP_MAX_ATOMS, trim_len(t->line), t->line);
            h->natoms = n;
            h->have_n = 1;
            continue;
        }
        if (starts(it, "BOX BOUNDS")) {
            h->triclinic = strstr(it, "xy") != NULL;
            for (int a = 0; a < 3; a++) {
                if ((rc = lci_text_line(t)) <= 0) break;
                double v[3];
                int n = numbers(t->line, v, 3);
                if (n != (h->triclinic ? 3 : 2))
                    return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: expected %s of the box's %c bounds, got '%.*s'",
                                     t->path, t->lineno, h->triclinic ? "lo hi tilt" : "lo hi", "xyz"[a],
                                     trim_len(t->line), t->line);
                h->lo[a] = v[0], h->hi[a] = v[1], h->tilt[a] = h->triclinic ? v[2] : 0.0;
            }
            if (rc <= 0) break;
            h->have_box = 1;
            continue;
        }
        if (starts(it, "ATOMS")) {
            if (!h->have_n)
                return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: ITEM: ATOMS before ITEM: NUMBER OF ATOMS", t->path,
                                 t->lineno);
            const char *c = it + 5;
            int n = 0, off;
            char name[32];
            while (sscanf(c, "%31s%n", name, &off) == 1) {
                if (n == LMP_MAX_COLS)
                    return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: more than %d atom columns", t->path, t->lineno,
                                     LMP_MAX_COLS);
                snprintf(h->cols[n++], sizeof h->cols[0], "%s", name);
                c += off;
            }
            h->ncols = n;
            h->atoms_line = t->lineno;
            return 1;
        }
        return lci_error(t->dev, LC_ERROR_FORMAT,
                         "%s:%ld: unknown section 'ITEM: %.*s' (expected TIMESTEP, NUMBER OF ATOMS, BOX BOUNDS or ATOMS)",
                         t->path, t->lineno, trim_len(it), it);
    }
    if (rc < 0) return LC_ERROR_IO;
    if (seen)
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: the file ends inside the header of frame %lld", t->path,
                         t->lineno + 1, (long long)k);
    return 0;
}

static int col(const frame_head *h, const char *name)
{
    for (int i = 0; i < h->ncols; i++)
        if (!strcmp(h->cols[i], name)) return i;
    return -1;
}

static lc_status skip_atoms(lci_text *t, const frame_head *h)
{
    for (long long i = 0; i < h->natoms; i++) {
        int rc = lci_text_line(t);
        if (rc < 0) return LC_ERROR_IO;
        if (rc == 0)
            return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: the file ends after %lld of the %lld atoms of line %ld",
                             t->path, t->lineno + 1, i, h->natoms, h->atoms_line);
    }
    return LC_OK;
}

static lc_status read_atoms(lci_text *t, const frame_head *h, opts *o, lci_plist *p, int *nfields)
{
    int c[3], scaled = 0;
    static const char *const sets[4][3] = {{"x", "y", "z"}, {"xu", "yu", "zu"}, {"xs", "ys", "zs"}, {"xsu", "ysu", "zsu"}};
    int set = -1;
    for (int s = 0; s < 4 && set < 0; s++) {
        for (int a = 0; a < 3; a++) c[a] = col(h, sets[s][a]);
        if (c[0] >= 0 && c[1] >= 0 && c[2] >= 0) set = s;
    }
    if (set < 0)
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: ITEM: ATOMS has no x y z, xu yu zu, xs ys zs or xsu ysu zsu columns",
                         t->path, h->atoms_line);
    scaled = set >= 2;
    if (scaled && !h->have_box)
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: scaled coordinates but no ITEM: BOX BOUNDS", t->path,
                         h->atoms_line);
    int ctype = col(h, "type"), cel = col(h, "element"), crad = col(h, "radius"), cdia = col(h, "diameter");
    int cval = o->value ? col(h, o->value) : -1;
    if (o->value && cval < 0) {
        char list[LMP_MAX_COLS * 33] = "";
        for (int i = 0; i < h->ncols; i++) snprintf(list + strlen(list), sizeof list - strlen(list), " %s", h->cols[i]);
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: option value = '%s', but the atom columns are:%s", t->path,
                         h->atoms_line, o->value, list);
    }
    if (o->fields == 1 && ctype < 0)
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: fields = type, but ITEM: ATOMS has no type column", t->path,
                         h->atoms_line);
    int ccol = o->column ? col(h, o->column) : -1;
    if (o->fields == 3 && ccol < 0)
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: fields by column '%s', but ITEM: ATOMS has no such column",
                         t->path, h->atoms_line, o->column);
    if (o->fields == 2 && cel < 0)
        return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: fields = element, but ITEM: ATOMS has no element column",
                         t->path, h->atoms_line);
    /* the box: lo and the edge vectors a = (lx,0,0), b = (xy,ly,0), c = (xz,yz,lz) */
    double lo[3] = {h->lo[0], h->lo[1], h->lo[2]}, hi[3] = {h->hi[0], h->hi[1], h->hi[2]};
    double xy = h->tilt[0], xz = h->tilt[1], yz = h->tilt[2];
    if (h->triclinic) { /* the bounds given are of the bounding box: undo that */
        lo[0] -= fmin(fmin(0.0, xy), fmin(xz, xy + xz));
        hi[0] -= fmax(fmax(0.0, xy), fmax(xz, xy + xz));
        lo[1] -= fmin(0.0, yz);
        hi[1] -= fmax(0.0, yz);
    }
    double len[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    int maxf = 0, merged_types = 0;
    if (lci_plist_reserve(p, (size_t)(h->natoms < 65536 ? h->natoms : 65536)))
        return lci_error(t->dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", t->path);
    for (long long i = 0; i < h->natoms; i++) {
        int rc = lci_text_line(t);
        if (rc < 0) return LC_ERROR_IO;
        if (rc == 0)
            return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: the file ends after %lld of the %lld atoms of line %ld",
                             t->path, t->lineno + 1, i, h->natoms, h->atoms_line);
        char *tok[LMP_MAX_COLS];
        int n = 0;
        for (char *s = strtok(t->line, " \t\r\n"); s && n < LMP_MAX_COLS; s = strtok(NULL, " \t\r\n")) tok[n++] = s;
        if (n != h->ncols)
            return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: atom %lld has %d columns, ITEM: ATOMS on line %ld names %d",
                             t->path, t->lineno, i + 1, n, h->atoms_line, h->ncols);
        lci_atom_attr attr = {.type = ctype >= 0 ? tok[ctype] : NULL};
        if (!lci_psel_keep(&o->sel, (size_t)i, cel >= 0 ? tok[cel] : NULL, &attr)) continue;
        double x[3];
        for (int a = 0; a < 3; a++) {
            float f;
            if (lci_parse_float(tok[c[a]], &f) || !isfinite(f))
                return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: column %d (%s) = '%s' is not a number", t->path,
                                 t->lineno, c[a] + 1, h->cols[c[a]], tok[c[a]]);
            x[a] = f;
        }
        if (scaled) {
            double s0 = x[0], s1 = x[1], s2 = x[2];
            x[0] = lo[0] + s0 * len[0] + s1 * xy + s2 * xz;
            x[1] = lo[1] + s1 * len[1] + s2 * yz;
            x[2] = lo[2] + s2 * len[2];
        }
        float v = 1.0f, r = o->radius;
        if (cval >= 0 && (lci_parse_float(tok[cval], &v) || !isfinite(v)))
            return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: column %d (%s) = '%s' is not a number", t->path,
                             t->lineno, cval + 1, h->cols[cval], tok[cval]);
        if (!(r > 0.0f)) {
            int cr = crad >= 0 ? crad : cdia;
            if (cr >= 0) {
                if (lci_parse_float(tok[cr], &r) || !(r > 0.0f) || !isfinite(r))
                    return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: column %d (%s) = '%s' is not a positive number",
                                     t->path, t->lineno, cr + 1, h->cols[cr], tok[cr]);
                if (cr == cdia) r *= 0.5f;
            } else if (cel >= 0) {
                r = lci_element_radius(tok[cel]);
                if (!(r > 0.0f)) r = LCI_DEFAULT_RADIUS;
            } else {
                r = LMP_DEFAULT_RADIUS;
            }
        }
        if (o->radius_scale > 0.0f) r *= o->radius_scale;
        int f = 0;
        if (o->fields == 1) {
            char *end;
            long ty = strtol(tok[ctype], &end, 10);
            if (*end || ty < 1)
                return lci_error(t->dev, LC_ERROR_FORMAT, "%s:%ld: atom type '%s' with fields = type: expected an integer >= 1",
                                 t->path, t->lineno, tok[ctype]);
            if (ty > LC_MAX_FIELDS) { /* shares the last field */
                (void)lci_fieldmap_id(&o->fm, tok[ctype], 0); /* counts the distinct ones */
                merged_types++;
                ty = LC_MAX_FIELDS;
            }
            f = (int)ty - 1;
        } else if (o->fields == 2) {
            f = lci_fieldmap_id(&o->fm, tok[cel], 1);
        } else if (o->fields == 3) {
            f = lci_fieldmap_id(&o->fm, tok[ccol], 0);
        }
        if (f + 1 > maxf) maxf = f + 1;
        if (lci_plist_add(p, (float)x[0], (float)x[1], (float)x[2], r, v, (uint8_t)f))
            return lci_error(t->dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory at line %ld", t->path, t->lineno);
    }
    *nfields = maxf;
    if (merged_types) /* o->fm counted the distinct types above 8 */
        lci_log(t->dev, LC_LOG_WARNING, "%s: fields by type: %d atom types above %d (first '%s') share field %d with type %d (%d atoms)",
                t->path, o->fm.n + o->fm.nextra, LC_MAX_FIELDS, o->fm.names[0], LC_MAX_FIELDS - 1, LC_MAX_FIELDS,
                merged_types);
    else if (o->fields >= 2)
        lci_fieldmap_warn(t->dev, t->path, o->fields == 2 ? "element" : o->column, &o->fm);
    return LC_OK;
}

static lc_status parse_opts(lc_device *dev, const lci_read_args *a, opts *o)
{
    memset(o, 0, sizeof *o);
    const lc_option *x;
    lc_status s = LC_OK;
    if ((x = lci_option_find(a, "radius"))) s = lci_option_float(dev, a->path, x, 1e-30f, 1e30f, &o->radius);
    if (s == LC_OK && (x = lci_option_find(a, "radius_scale")))
        s = lci_option_float(dev, a->path, x, 1e-30f, 1e30f, &o->radius_scale);
    if (s == LC_OK && (x = lci_option_find(a, "fields"))) {
        lci_field_by by;
        if (lci_field_by_parse(x->value, &by, &o->column) == 0 && by != LCI_BY_CPK && by != LCI_BY_CHAIN &&
            by != LCI_BY_RESIDUE)
            o->fields = by == LCI_BY_TYPE ? 1 : by == LCI_BY_ELEMENT ? 2 : by == LCI_BY_COLUMN ? 3 : 0;
        else if (lci_field_by_parse(x->value, &by, &o->column) == 0)
            s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: fields by %s: lammps files give no %s (they give type, "
                          "element with an element column, and column:NAME)", a->path, x->value,
                          by == LCI_BY_CHAIN ? "chain identifiers" : by == LCI_BY_RESIDUE ? "residue names" : "element classes");
        else
            s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: option fields = '%s', expected none, type, element or "
                          "column:NAME", a->path, x->value);
    }
    if (s == LC_OK) s = lci_psel_open(dev, a, &o->sel);
    if (s == LC_OK && (x = lci_option_find(a, "value"))) o->value = x->value;
    return s;
}

static lc_status lammps_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    opts o;
    lc_status s = parse_opts(dev, a, &o);
    if (s != LC_OK) return s;
    lci_text t;
    if ((s = lci_text_open(dev, a->path, &t)) != LC_OK) return s;
    lci_plist p;
    memset(&p, 0, sizeof p);
    int nfields = 1;
    for (int64_t k = 0;; k++) {
        frame_head h;
        int rc = read_head(&t, &h, k);
        if (rc < 0) {
            s = (lc_status)rc;
            break;
        }
        if (rc == 0) {
            s = k == 0 ? lci_error(dev, LC_ERROR_FORMAT, "%s: empty file, expected 'ITEM: TIMESTEP'", a->path)
                       : lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: frame %lld is past the end: the file holds %lld frame%s",
                                   a->path, (long long)a->desc->frame, (long long)k, k == 1 ? "" : "s");
            break;
        }
        if (k < a->desc->frame) {
            if ((s = skip_atoms(&t, &h)) != LC_OK) break;
            continue;
        }
        s = read_atoms(&t, &h, &o, &p, &nfields);
        break;
    }
    lci_text_close(&t);
    s = lci_psel_close(dev, a, &o.sel, p.n, s);
    lci_fieldmap_free(&o.fm);
    return lci_plist_finish(dev, a->path, s, &p, o.fields ? nfields : 1, o.value != NULL, out);
}

static lc_status lammps_frames(lc_device *dev, const char *path, int64_t *out)
{
    lci_text t;
    lc_status s = lci_text_open(dev, path, &t);
    *out = 0;
    if (s != LC_OK) return s;
    for (int64_t k = 0;; k++) {
        frame_head h;
        int rc = read_head(&t, &h, k);
        if (rc <= 0) {
            s = (lc_status)rc;
            break;
        }
        if ((s = skip_atoms(&t, &h)) != LC_OK) break;
        *out = k + 1;
    }
    lci_text_close(&t);
    return s;
}

static int lammps_magic(const unsigned char *h, size_t n)
{
    static const char m[] = "ITEM:";
    return n >= 5 && !memcmp(h, m, 5);
}

const lci_format lci_format_lammps = {
    .name = "lammps", .kind = LC_KIND_PARTICLES, .extensions = ".lammpstrj .lammpsdump .dump",
    .options = "radius radius_scale fields value select",
    .description = "LAMMPS text dump (ITEM: sections; x y z or scaled xs ys zs, orthogonal or triclinic box), frames "
                   "concatenated; fields = type, value = any atom column",
    .magic = lammps_magic, .read = lammps_read, .frames = lammps_frames};
