/* Particle file formats: XYZ, PDB and raw float32, read through zlib (so
 * gzip-compressed files work too). Molecules get covalent radii by element
 * (Knoll 2014 §3.1; radii from Cordero et al. 2008, Dalton Trans.). Every
 * error names the file and line. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <zlib.h>
#include "host/formats/format.h"

/* The options these readers take (lci_format.options). */
typedef struct popts {
    size_t raw_count;
    float radius, radius_scale;
    int fields_by_element;
} popts;

typedef struct element {
    const char *sym;
    float r; /* covalent radius, Angstrom */
} element;

static const element elements[] = {
    {"H", 0.31f},  {"He", 0.28f}, {"Li", 1.28f}, {"Be", 0.96f}, {"B", 0.84f},  {"C", 0.76f},  {"N", 0.71f},
    {"O", 0.66f},  {"F", 0.57f},  {"Ne", 0.58f}, {"Na", 1.66f}, {"Mg", 1.41f}, {"Al", 1.21f}, {"Si", 1.11f},
    {"P", 1.07f},  {"S", 1.05f},  {"Cl", 1.02f}, {"Ar", 1.06f}, {"K", 2.03f},  {"Ca", 1.76f}, {"Sc", 1.70f},
    {"Ti", 1.60f}, {"V", 1.53f},  {"Cr", 1.39f}, {"Mn", 1.39f}, {"Fe", 1.32f}, {"Co", 1.26f}, {"Ni", 1.24f},
    {"Cu", 1.32f}, {"Zn", 1.22f}, {"Ga", 1.22f}, {"Ge", 1.20f}, {"As", 1.19f}, {"Se", 1.20f}, {"Br", 1.20f},
    {"Kr", 1.16f}, {"Rb", 2.20f}, {"Sr", 1.95f}, {"Y", 1.90f},  {"Zr", 1.75f}, {"Mo", 1.54f}, {"Ru", 1.46f},
    {"Rh", 1.42f}, {"Pd", 1.39f}, {"Ag", 1.45f}, {"Cd", 1.44f}, {"In", 1.42f}, {"Sn", 1.39f}, {"Sb", 1.39f},
    {"Te", 1.38f}, {"I", 1.39f},  {"Xe", 1.40f}, {"Cs", 2.44f}, {"Ba", 2.15f}, {"La", 2.07f}, {"Gd", 1.96f},
    {"W", 1.62f},  {"Pt", 1.36f}, {"Au", 1.36f}, {"Hg", 1.32f}, {"Pb", 1.46f}, {"U", 1.96f},
};
#define DEFAULT_RADIUS 1.5f

/* Radius of an element symbol (case-insensitive), or 0 if unknown. */
static float element_radius(const char *sym)
{
    for (size_t i = 0; i < sizeof elements / sizeof elements[0]; i++)
        if (!strcasecmp(sym, elements[i].sym)) return elements[i].r;
    return 0.0f;
}

typedef struct plist {
    float *xyz, *r;
    uint8_t *field;
    size_t n, cap;
    char names[LC_MAX_FIELDS][16]; /* element of each field (fields_by_element) */
    int nnames;
} plist;

static int plist_push(plist *p, float x, float y, float z, float r, uint8_t f)
{
    if (p->n == p->cap) {
        size_t cap = p->cap ? p->cap * 2 : 4096;
        float *a = realloc(p->xyz, cap * 3 * sizeof(float));
        if (!a) return -1;
        p->xyz = a;
        float *b = realloc(p->r, cap * sizeof(float));
        if (!b) return -1;
        p->r = b;
        uint8_t *c = realloc(p->field, cap);
        if (!c) return -1;
        p->field = c;
        p->cap = cap;
    }
    p->xyz[3 * p->n] = x, p->xyz[3 * p->n + 1] = y, p->xyz[3 * p->n + 2] = z;
    p->r[p->n] = r;
    p->field[p->n] = f;
    p->n++;
    return 0;
}

static void plist_free(plist *p)
{
    free(p->xyz);
    free(p->r);
    free(p->field);
}

static uint8_t field_of(plist *p, const char *sym, int by_element)
{
    if (!by_element) return 0;
    for (int i = 0; i < p->nnames; i++)
        if (!strcasecmp(p->names[i], sym)) return (uint8_t)i;
    if (p->nnames < LC_MAX_FIELDS) {
        snprintf(p->names[p->nnames], sizeof p->names[0], "%s", sym);
        return (uint8_t)p->nnames++;
    }
    return LC_MAX_FIELDS - 1;
}

typedef struct reader {
    lc_device *dev;
    const char *path;
    const popts *o;
    gzFile gz;
    char line[4096];
    long lineno;
    int unknown_elements;
    char first_unknown[16];
} reader;

/* Reads the next line; 1 ok, 0 end, -1 error (reported). */
static int next_line(reader *r)
{
    if (!gzgets(r->gz, r->line, sizeof r->line)) {
        int err;
        const char *msg = gzerror(r->gz, &err);
        if (err != Z_OK && err != Z_STREAM_END) {
            lci_error(r->dev, LC_ERROR_IO, "%s:%ld: read error: %s", r->path, r->lineno + 1, msg);
            return -1;
        }
        return 0;
    }
    r->lineno++;
    size_t len = strlen(r->line);
    if (len == sizeof r->line - 1 && r->line[len - 1] != '\n') {
        lci_error(r->dev, LC_ERROR_FORMAT, "%s:%ld: line longer than %zu characters", r->path, r->lineno,
                  sizeof r->line - 2);
        return -1;
    }
    return 1;
}

static float radius_for(reader *r, const char *sym)
{
    if (r->o->radius > 0.0f) return r->o->radius;
    float rad = element_radius(sym);
    if (rad == 0.0f) {
        if (!r->unknown_elements++) snprintf(r->first_unknown, sizeof r->first_unknown, "%s", sym);
        rad = DEFAULT_RADIUS;
    }
    return rad * (r->o->radius_scale > 0.0f ? r->o->radius_scale : 1.0f);
}

static int parse_float(const char *s, float *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || errno == ERANGE) return -1;
    while (*end && isspace((unsigned char)*end)) end++;
    if (*end) return -1;
    *out = (float)v;
    return 0;
}

static lc_status read_xyz(reader *r, plist *p)
{
    int rc;
    long declared = -1;
    int header_done = 0;
    while ((rc = next_line(r)) == 1) {
        char el[16], xs[64], ys[64], zs[64];
        char *s = r->line;
        while (isspace((unsigned char)*s)) s++;
        if (!*s || *s == '#') continue;
        /* optional "count" + comment header (possibly repeated per frame: we read the first frame) */
        if (!header_done) {
            char *end;
            long c = strtol(s, &end, 10);
            while (isspace((unsigned char)*end)) end++;
            header_done = 1;
            if (end != s && !*end) {
                declared = c;
                if ((rc = next_line(r)) != 1) break; /* comment line */
                continue;
            }
        }
        if (declared >= 0 && (long)p->n == declared) break; /* next frame */
        if (sscanf(s, "%15s %63s %63s %63s", el, xs, ys, zs) != 4)
            return lci_error(r->dev, LC_ERROR_FORMAT, "%s:%ld: expected 'element x y z', got '%.*s'", r->path,
                             r->lineno, (int)(strcspn(s, "\r\n") < 60 ? strcspn(s, "\r\n") : 60), s);
        float x, y, z;
        if (parse_float(xs, &x) || parse_float(ys, &y) || parse_float(zs, &z))
            return lci_error(r->dev, LC_ERROR_FORMAT, "%s:%ld: coordinates '%s %s %s' are not numbers", r->path,
                             r->lineno, xs, ys, zs);
        if (plist_push(p, x, y, z, radius_for(r, el), field_of(p, el, r->o->fields_by_element)))
            return lci_error(r->dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory at line %ld", r->path, r->lineno);
    }
    if (rc < 0) return LC_ERROR_IO;
    if (declared >= 0 && (long)p->n < declared)
        return lci_error(r->dev, LC_ERROR_FORMAT, "%s: header declares %ld atoms but only %zu follow", r->path,
                         declared, p->n);
    return LC_OK;
}

/* PDB columns are 1-based and fixed (wwPDB format 3.3). */
static void column(const char *line, int a, int b, char *out, size_t n)
{
    size_t len = strlen(line), k = 0;
    for (int c = a - 1; c < b && (size_t)c < len && k + 1 < n; c++) {
        char ch = line[c];
        if (ch == '\n' || ch == '\r') break;
        out[k++] = ch;
    }
    out[k] = '\0';
    /* trim */
    char *s = out;
    while (isspace((unsigned char)*s)) s++;
    memmove(out, s, strlen(s) + 1);
    k = strlen(out);
    while (k && isspace((unsigned char)out[k - 1])) out[--k] = '\0';
}

static void pdb_element(const char *line, char *el, size_t n)
{
    column(line, 77, 78, el, n);
    if (el[0] && isalpha((unsigned char)el[0])) return;
    /* no element column: the atom name (cols 13-16); a name starting in column
     * 13 may be a two-letter element (e.g. "FE  "), else the first letter */
    char name[8];
    column(line, 13, 16, name, sizeof name);
    const char *s = name;
    while (*s && !isalpha((unsigned char)*s)) s++;
    int starts_at_13 = strlen(line) > 12 && isalpha((unsigned char)line[12]);
    if (starts_at_13 && isalpha((unsigned char)s[0]) && isalpha((unsigned char)s[1])) {
        char two[3] = {s[0], (char)tolower((unsigned char)s[1]), 0};
        if (element_radius(two) > 0.0f) {
            snprintf(el, n, "%s", two);
            return;
        }
    }
    snprintf(el, n, "%c", s[0] ? s[0] : 'X');
}

static lc_status read_pdb(reader *r, plist *p)
{
    int rc;
    while ((rc = next_line(r)) == 1) {
        if (!strncmp(r->line, "ENDMDL", 6)) break; /* first model only */
        if (strncmp(r->line, "ATOM  ", 6) && strncmp(r->line, "HETATM", 6)) continue;
        char xs[16], ys[16], zs[16], el[8];
        column(r->line, 31, 38, xs, sizeof xs);
        column(r->line, 39, 46, ys, sizeof ys);
        column(r->line, 47, 54, zs, sizeof zs);
        float x, y, z;
        if (parse_float(xs, &x) || parse_float(ys, &y) || parse_float(zs, &z))
            return lci_error(r->dev, LC_ERROR_FORMAT,
                             "%s:%ld: ATOM record with coordinates '%s' '%s' '%s' in columns 31-54 that are not numbers",
                             r->path, r->lineno, xs, ys, zs);
        pdb_element(r->line, el, sizeof el);
        if (plist_push(p, x, y, z, radius_for(r, el), field_of(p, el, r->o->fields_by_element)))
            return lci_error(r->dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory at line %ld", r->path, r->lineno);
    }
    if (rc < 0) return LC_ERROR_IO;
    if (p->n == 0) return lci_error(r->dev, LC_ERROR_FORMAT, "%s: no ATOM or HETATM records", r->path);
    return LC_OK;
}

static lc_status read_raw(reader *r, plist *p)
{
    size_t n = r->o->raw_count;
    if (n == 0) return lci_error(r->dev, LC_ERROR_INVALID_ARGUMENT, "%s: raw particles need a count", r->path);
    if (!(r->o->radius > 0.0f))
        return lci_error(r->dev, LC_ERROR_INVALID_ARGUMENT, "%s: raw particles need a radius (> 0)", r->path);
    if (n > (size_t)INT32_MAX / 2)
        return lci_error(r->dev, LC_ERROR_INVALID_ARGUMENT, "%s: %zu particles is too many", r->path, n);
    p->xyz = malloc(n * 3 * sizeof(float));
    p->r = malloc(n * sizeof(float));
    p->field = calloc(n, 1);
    if (!p->xyz || !p->r || !p->field)
        return lci_error(r->dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %zu particles", r->path, n);
    size_t want = n * 3 * sizeof(float), got = 0;
    unsigned char *dst = (unsigned char *)p->xyz;
    while (got < want) {
        unsigned chunk = want - got > (1u << 30) ? (1u << 30) : (unsigned)(want - got);
        int k = gzread(r->gz, dst + got, chunk);
        if (k < 0) return lci_error(r->dev, LC_ERROR_IO, "%s: read error", r->path);
        if (k == 0) break;
        got += (size_t)k;
    }
    if (got != want)
        return lci_error(r->dev, LC_ERROR_FORMAT, "%s: holds %zu bytes, but %zu particles need %zu (12 bytes each)",
                         r->path, got, n, want);
    char extra;
    if (gzread(r->gz, &extra, 1) == 1)
        return lci_error(r->dev, LC_ERROR_FORMAT, "%s: longer than %zu particles x 12 bytes; wrong count?", r->path, n);
    for (size_t i = 0; i < n; i++) p->r[i] = r->o->radius;
    p->n = p->cap = n;
    return LC_OK;
}

static lc_status parse_options(lc_device *dev, const lci_read_args *a, popts *o)
{
    memset(o, 0, sizeof *o);
    const lc_option *x;
    lc_status s = LC_OK;
    if ((x = lci_option_find(a, "radius"))) s = lci_option_float(dev, a->path, x, 1e-30f, 1e30f, &o->radius);
    if (s == LC_OK && (x = lci_option_find(a, "radius_scale")))
        s = lci_option_float(dev, a->path, x, 1e-30f, 1e30f, &o->radius_scale);
    if (s == LC_OK && (x = lci_option_find(a, "count")))
        s = lci_option_size(dev, a->path, x, (size_t)INT32_MAX / 2, &o->raw_count);
    if (s == LC_OK && (x = lci_option_find(a, "fields"))) {
        if (!strcmp(x->value, "element")) o->fields_by_element = 1;
        else if (strcmp(x->value, "none"))
            s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: option fields = '%s', expected none or element", a->path,
                          x->value);
    }
    return s;
}

typedef lc_status (*read_fn)(reader *r, plist *p);

/* Reads with fn and hands the lists over as an lc_particles_desc. */
static lc_status read_with(lc_device *dev, const lci_read_args *a, lci_loaded *out, read_fn fn)
{
    popts o;
    lc_status s = parse_options(dev, a, &o);
    if (s != LC_OK) return s;
    reader r;
    memset(&r, 0, sizeof r);
    r.dev = dev;
    r.path = a->path;
    r.o = &o;
    r.gz = gzopen(a->path, "rb");
    if (!r.gz) return lci_error(dev, LC_ERROR_IO, "%s: cannot open: %s", a->path, strerror(errno));
    gzbuffer(r.gz, 1 << 18);
    plist p;
    memset(&p, 0, sizeof p);
    s = fn(&r, &p);
    gzclose(r.gz);
    if (s == LC_OK && r.unknown_elements)
        lci_log(dev, LC_LOG_WARNING, "%s: %d atoms of unknown elements (first '%s') got radius %.2f", a->path,
                r.unknown_elements, r.first_unknown, (double)DEFAULT_RADIUS);
    lc_particles_desc *d = s == LC_OK ? calloc(1, sizeof *d) : NULL;
    if (s == LC_OK && !d) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", a->path);
    if (s != LC_OK) {
        plist_free(&p);
        return s;
    }
    d->count = p.n;
    d->positions = p.xyz;
    d->radii = p.r;
    d->fields = p.field;
    d->nfields = o.fields_by_element ? (p.nnames ? p.nnames : 1) : 1;
    out->desc = d;
    lci_loaded_keep(out, p.xyz);
    lci_loaded_keep(out, p.r);
    lci_loaded_keep(out, p.field);
    return LC_OK;
}

static lc_status xyz_read(lc_device *dev, const lci_read_args *a, lci_loaded *out) { return read_with(dev, a, out, read_xyz); }
static lc_status pdb_read(lc_device *dev, const lci_read_args *a, lci_loaded *out) { return read_with(dev, a, out, read_pdb); }
static lc_status raw_read(lc_device *dev, const lci_read_args *a, lci_loaded *out) { return read_with(dev, a, out, read_raw); }

/* A PDB file starts with one of its record names in columns 1-6. */
static int pdb_magic(const unsigned char *h, size_t n)
{
    static const char *const rec[] = {"HEADER", "ATOM  ", "HETATM", "CRYST1", "REMARK", "MODEL ", "TITLE ", "COMPND"};
    if (n < 6) return 0;
    for (size_t i = 0; i < sizeof rec / sizeof rec[0]; i++)
        if (!memcmp(h, rec[i], 6)) return 1;
    return 0;
}

const lci_format lci_format_xyz = {
    .name = "xyz", .kind = LC_KIND_PARTICLES, .extensions = ".xyz", .options = "radius radius_scale fields",
    .description = "XYZ: element x y z lines; the count and comment header is optional", .read = xyz_read};
const lci_format lci_format_pdb = {
    .name = "pdb", .kind = LC_KIND_PARTICLES, .extensions = ".pdb .ent", .options = "radius radius_scale fields",
    .description = "Protein Data Bank: ATOM/HETATM records, element from columns 77-78 or the atom name",
    .magic = pdb_magic, .read = pdb_read};
const lci_format lci_format_raw_particles = {
    .name = "raw-particles", .kind = LC_KIND_PARTICLES, .extensions = ".f32", .options = "count radius",
    .description = "raw little-endian float32 x y z triples; count and radius required", .read = raw_read};
