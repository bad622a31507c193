/* Particles in CSV with named columns: the first line that is not blank or
 * a # comment names the columns (case-insensitive, optionally "quoted");
 * the delimiter is the header's first of , ; or tab, else white space.
 * x, y, z are required. Optional: radius (else the radius option, else the
 * distance to the knn-th neighbour), value or mass (the default value
 * column; `value = NAME` picks any column, `value = none` none), type or
 * field (field ids: integers 0..7 as they are, or names numbered in order of
 * first appearance; `fields = column:NAME | none` picks any column; a 9th
 * distinct name, or an integer id above 7, shares field 7 with one warning,
 * fieldmap.h). `select` (select.h) sees index (the row, from 0) and the
 * columns type (else field), element, name, resname, chain, segid and resid
 * when the header names them; a keyword needing a column the file lacks
 * fails naming it. Plain or gzip. Every error names the file and the line
 * (and the column). Not the RBF encoder's sample input, which reads its CSV
 * through its own path. */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "host/formats/plist.h"
#include "host/formats/text_reader.h"

#define MAX_COLS 256

typedef struct row {
    char *cell[MAX_COLS];
    int n;
} row;

/* Splits line (in place) at delim (0: white space), trimming cells and
 * their quotes; "" inside a quoted cell is one quote. */
static void split(char *line, char delim, row *r)
{
    r->n = 0;
    size_t len = strlen(line);
    while (len && (line[len - 1] == '\n' || line[len - 1] == '\r')) line[--len] = 0;
    char *p = line;
    for (;;) {
        while (*p == ' ' || (*p == '\t' && delim != '\t')) p++;
        if (!delim && !*p) break;
        char *start = p, *w = p;
        if (*p == '"') {
            p++;
            while (*p) {
                if (*p == '"' && p[1] == '"') *w++ = '"', p += 2;
                else if (*p == '"') {
                    p++;
                    break;
                } else *w++ = *p++;
            }
            while (*p && *p != delim && !(delim == 0 && isspace((unsigned char)*p))) p++;
        } else {
            while (*p && *p != delim && !(delim == 0 && isspace((unsigned char)*p))) *w++ = *p++;
        }
        char *end = *p ? p + 1 : p;
        int more = *p != 0;
        while (w > start && isspace((unsigned char)w[-1])) w--;
        *w = 0;
        if (r->n < MAX_COLS) r->cell[r->n] = start;
        r->n++;
        p = end;
        if (!more) break;
    }
}

static int is_blank(const char *s)
{
    while (isspace((unsigned char)*s)) s++;
    return !*s || *s == '#';
}

typedef struct copts {
    float radius, radius_scale;
    int knn;
    const char *value, *fields; /* column names, "none", or NULL = default */
} copts;

static lc_status parse_opts(lc_device *dev, const lci_read_args *a, copts *o)
{
    memset(o, 0, sizeof *o);
    o->knn = 16;
    const lc_option *x;
    lc_status s = LC_OK;
    if ((x = lci_option_find(a, "radius"))) s = lci_option_float(dev, a->path, x, 1e-30f, 1e30f, &o->radius);
    if (s == LC_OK && (x = lci_option_find(a, "radius_scale")))
        s = lci_option_float(dev, a->path, x, 1e-30f, 1e30f, &o->radius_scale);
    if (s == LC_OK && (x = lci_option_find(a, "knn"))) s = lci_option_int(dev, a->path, x, 1, 1024, &o->knn);
    if ((x = lci_option_find(a, "value"))) o->value = x->value;
    if ((x = lci_option_find(a, "fields"))) o->fields = x->value;
    if (o->fields && !strncmp(o->fields, "column:", 7)) o->fields += 7; /* field_by = column:NAME */
    else if (o->fields && !strcmp(o->fields, "type")) o->fields = NULL; /* the type (or field) column */
    return s;
}

static int find_col(const row *h, const char *name)
{
    for (int i = 0; i < h->n && i < MAX_COLS; i++)
        if (!strcasecmp(h->cell[i], name)) return i;
    return -1;
}

/* The column an option names, or the first of the defaults present; -1: none. */
static lc_status pick(lc_device *dev, const char *path, long ln, const row *h, const char *opt, const char *key,
                      const char *d1, const char *d2, int *col)
{
    *col = -1;
    if (opt && !strcmp(opt, "none")) return LC_OK;
    if (opt) {
        if ((*col = find_col(h, opt)) < 0) {
            char list[600] = "";
            for (int i = 0; i < h->n && i < MAX_COLS && strlen(list) < sizeof list - 40; i++)
                snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", i ? ", " : "", h->cell[i]);
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                             "%s:%ld: option %s = '%s', but the header names no such column (it names: %s)", path, ln,
                             key, opt, list);
        }
        return LC_OK;
    }
    *col = find_col(h, d1);
    if (*col < 0) *col = find_col(h, d2);
    return LC_OK;
}

static lc_status csv_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    copts o;
    lc_status s = parse_opts(dev, a, &o);
    if (s != LC_OK) return s;
    lci_text t;
    if ((s = lci_text_open(dev, a->path, &t)) != LC_OK) return s;
    lci_plist p;
    memset(&p, 0, sizeof p);
    lci_fieldmap fm;
    memset(&fm, 0, sizeof fm);
    lci_psel ps;
    memset(&ps, 0, sizeof ps);
    char header[LCI_LINE_MAX];
    row h, r;
    int rc;
    char delim = 0;
    int cx, cy, cz, cr, cv = -1, cf = -1, maxf = 0;
    while ((rc = lci_text_line(&t)) == 1 && is_blank(t.line)) {}
    if (rc <= 0) {
        s = rc < 0 ? LC_ERROR_IO : lci_error(dev, LC_ERROR_FORMAT, "%s:%ld: no header line naming the columns", a->path, t.lineno);
        goto out;
    }
    long hline = t.lineno;
    snprintf(header, sizeof header, "%s", t.line);
    delim = strchr(header, ',') ? ',' : strchr(header, ';') ? ';' : strchr(header, '\t') ? '\t' : 0;
    split(header, delim, &h);
    if (h.n > MAX_COLS) {
        s = lci_error(dev, LC_ERROR_FORMAT, "%s:%ld: %d columns, at most %d", a->path, hline, h.n, MAX_COLS);
        goto out;
    }
    cx = find_col(&h, "x"), cy = find_col(&h, "y"), cz = find_col(&h, "z"), cr = find_col(&h, "radius");
    if (cx < 0 || cy < 0 || cz < 0) {
        s = lci_error(dev, LC_ERROR_FORMAT, "%s:%ld: the header must name columns x, y and z (it names: %s%s%s...)",
                      a->path, hline, h.cell[0], h.n > 1 ? ", " : "", h.n > 1 ? h.cell[1] : "");
        goto out;
    }
    if ((s = pick(dev, a->path, hline, &h, o.value, "value", "value", "mass", &cv)) != LC_OK ||
        (s = pick(dev, a->path, hline, &h, o.fields, "fields", "type", "field", &cf)) != LC_OK)
        goto out;
    /* select: index, and the attribute columns the header names */
    enum { A_TYPE, A_ELEMENT, A_NAME, A_RESNAME, A_CHAIN, A_SEGID, A_RESID, A_N };
    static const char *const attr_cols[A_N] = {"type", "element", "name", "resname", "chain", "segid", "resid"};
    int ca[A_N];
    char gives[160] = "index";
    for (int k = 0; k < A_N; k++)
        if ((ca[k] = find_col(&h, attr_cols[k])) >= 0)
            snprintf(gives + strlen(gives), sizeof gives - strlen(gives), ", %s", attr_cols[k]);
    if (ca[A_TYPE] < 0 && (ca[A_TYPE] = find_col(&h, "field")) >= 0)
        snprintf(gives + strlen(gives), sizeof gives - strlen(gives), ", type (the field column)");
    if ((s = lci_psel_open(dev, a, &ps)) != LC_OK) goto out;
    ps.gives = gives; /* lci_psel_open clears it */
    int by_name = -1; /* -1 undecided, 0 integer ids (0..7 as they are), 1 names (in order of first appearance) */
    while ((rc = lci_text_line(&t)) == 1) {
        if (is_blank(t.line)) continue;
        split(t.line, delim, &r);
        if (r.n != h.n) {
            s = lci_error(dev, LC_ERROR_FORMAT, "%s:%ld: %d values, but the header (line %ld) names %d columns", a->path,
                          t.lineno, r.n, hline, h.n);
            goto out;
        }
        if (ps.sel) {
            const char *av[A_N];
            for (int k = 0; k < A_N; k++) av[k] = ca[k] >= 0 ? r.cell[ca[k]] : NULL;
            char *rend = NULL;
            long resid = av[A_RESID] ? strtol(av[A_RESID], &rend, 10) : 0;
            lci_atom_attr at = {.name = av[A_NAME], .resname = av[A_RESNAME], .chain = av[A_CHAIN], .segid = av[A_SEGID],
                                .type = av[A_TYPE], .resid = resid, .has_resid = rend && rend != av[A_RESID] && !*rend};
            if (av[A_RESID] && !at.has_resid) {
                s = lci_error(dev, LC_ERROR_FORMAT, "%s:%ld: column %d (resid) is '%s', expected an integer", a->path,
                              t.lineno, ca[A_RESID] + 1, av[A_RESID]);
                goto out;
            }
            if (!lci_psel_keep(&ps, ps.seen, av[A_ELEMENT], &at)) continue;
        }
        float v[5] = {0, 0, 0, o.radius, 1.0f};
        const int cols[5] = {cx, cy, cz, o.radius > 0.0f ? -1 : cr, cv};
        for (int k = 0; k < 5; k++) {
            if (cols[k] < 0) continue;
            if (lci_parse_float(r.cell[cols[k]], &v[k]) || !isfinite(v[k]) || (k == 3 && !(v[k] > 0.0f))) {
                s = lci_error(dev, LC_ERROR_FORMAT, "%s:%ld: column %d (%s) is '%s', expected %s", a->path, t.lineno,
                              cols[k] + 1, h.cell[cols[k]], r.cell[cols[k]],
                              k == 3 ? "a radius > 0" : "a finite number");
                goto out;
            }
        }
        int f = 0;
        if (cf >= 0) {
            const char *c = r.cell[cf];
            char *end;
            long id = strtol(c, &end, 10);
            int is_int = end != c && !*end;
            if (by_name < 0) by_name = !is_int;
            if (!by_name) {
                if (!is_int || id < 0) {
                    s = lci_error(dev, LC_ERROR_FORMAT, "%s:%ld: column %d (%s) is '%s', expected a field id >= 0 like "
                                  "the rows before (a column of names must not start with a number)",
                                  a->path, t.lineno, cf + 1, h.cell[cf], c);
                    goto out;
                }
                /* ids 0..7 as they are; larger ones share the last field (fieldmap.h) */
                f = id < LC_MAX_FIELDS ? (int)id : lci_fieldmap_merge(&fm, c, 0);
            } else {
                f = lci_fieldmap_id(&fm, c, 0);
            }
            maxf = f > maxf ? f : maxf;
        }
        if (lci_plist_add(&p, v[0], v[1], v[2], cols[3] >= 0 || o.radius > 0.0f ? v[3] : 0.0f, v[4], (uint8_t)f)) {
            s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory at line %ld", a->path, t.lineno);
            goto out;
        }
    }
    if (rc < 0) {
        s = LC_ERROR_FORMAT;
        goto out;
    }
    if (p.n == 0 && !ps.sel) { /* with a selection, lci_psel_close says it matched nothing */
        s = lci_error(dev, LC_ERROR_FORMAT, "%s:%ld: no rows after the header (line %ld)", a->path, t.lineno, hline);
        goto out;
    }
    if (cr < 0 && !(o.radius > 0.0f)) { /* k-th neighbour distances, coincident points given the smallest */
        if (lci_knn_radii(p.xyz, p.n, o.knn, p.r)) {
            s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for the neighbour search", a->path);
            goto out;
        }
        float rmin = INFINITY;
        for (size_t i = 0; i < p.n; i++)
            if (p.r[i] > 0.0f && p.r[i] < rmin) rmin = p.r[i];
        for (size_t i = 0; i < p.n; i++)
            if (!(p.r[i] > 0.0f)) p.r[i] = isfinite(rmin) ? rmin : 1.0f;
    }
    if (o.radius_scale > 0.0f)
        for (size_t i = 0; i < p.n; i++) p.r[i] *= o.radius_scale;
    if (cf >= 0) {
        char what[300];
        snprintf(what, sizeof what, "column %s", h.cell[cf]);
        lci_fieldmap_warn(dev, a->path, what, &fm);
    }
out:
    s = lci_psel_close(dev, a, &ps, p.n, s);
    lci_fieldmap_free(&fm);
    lci_text_close(&t);
    return lci_plist_finish(dev, a->path, s, &p, cf >= 0 ? maxf + 1 : 1, cv >= 0, out);
}

const lci_format lci_format_csv = {
    .name = "csv", .kind = LC_KIND_PARTICLES, .extensions = ".csv .tsv",
    .options = "radius radius_scale knn value fields select",
    .description = "particles in CSV with a header: x,y,z; radius (else the knn-th neighbour distance); value = any "
                   "column (default value or mass); type/field column as fields",
    .read = csv_read};
