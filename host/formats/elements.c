/* Element radii, per-element fields and the atom list (elements.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "host/formats/elements.h"
#include "host/formats/topology.h"

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

float lci_element_radius(const char *sym)
{
    for (size_t i = 0; i < sizeof elements / sizeof elements[0]; i++)
        if (!strcasecmp(sym, elements[i].sym)) return elements[i].r;
    return 0.0f;
}

/* 1 if word is one of list's space-separated words. */
static int word_in(const char *list, const char *word)
{
    size_t n = strlen(word);
    for (const char *p = list; (p = strstr(p, word)); p += n)
        if ((p == list || p[-1] == ' ') && (!p[n] || p[n] == ' ')) return 1;
    return 0;
}

lc_status lci_atom_options(lc_device *dev, const lci_read_args *a, lci_atom_opts *o)
{
    memset(o, 0, sizeof *o);
    const lc_option *x;
    lc_status s = LC_OK;
    if ((x = lci_option_find(a, "radius"))) s = lci_option_float(dev, a->path, x, 1e-30f, 1e30f, &o->radius);
    if (s == LC_OK && (x = lci_option_find(a, "radius_scale")))
        s = lci_option_float(dev, a->path, x, 1e-30f, 1e30f, &o->radius_scale);
    o->format = a->format ? a->format : "molecular";
    if (s == LC_OK && (x = lci_option_find(a, "fields"))) {
        lci_field_by by;
        const char *col;
        if (lci_field_by_parse(x->value, &by, &col))
            s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                          "%s: option fields = '%s', expected none, element, cpk, type, chain or residue", a->path, x->value);
        else if (by == LCI_BY_COLUMN && !word_in(LCI_COLUMN_FORMATS, o->format) && a->format)
            s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: fields by column '%s': %s files have no per-atom columns "
                          "to map (use element, type, chain or residue)", a->path, col, o->format);
        o->fields_by_element = by == LCI_BY_ELEMENT;
        o->cpk = by == LCI_BY_CPK;
        if (by == LCI_BY_TYPE || by == LCI_BY_CHAIN || by == LCI_BY_RESIDUE || by == LCI_BY_COLUMN) o->by_attr = by;
        if (by == LCI_BY_COLUMN) o->column = col;
    }
    if (s == LC_OK && (x = lci_option_find(a, "value")) && strcmp(x->value, "none")) o->value = x->value;
    if (s == LC_OK && (x = lci_option_find(a, "select"))) {
        char what[512];
        snprintf(what, sizeof what, "%s: select", a->path);
        lci_select *sel = NULL;
        if (strlen(x->value) >= sizeof o->select)
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: longer than %zu characters", what, sizeof o->select - 1);
        s = lci_select_parse(dev, what, x->value, &sel); /* check now; parsed again for the atoms */
        lci_select_free(sel);
        if (s == LC_OK) snprintf(o->select, sizeof o->select, "%s", x->value);
    }
    return s;
}

static float radius_for(lci_atoms *p, const char *sym)
{
    if (p->o.radius > 0.0f) return p->o.radius;
    float rad = lci_element_radius(sym);
    if (rad == 0.0f) {
        if (!p->unknown++) snprintf(p->first_unknown, sizeof p->first_unknown, "%s", sym);
        rad = LCI_DEFAULT_RADIUS;
    }
    return rad * (p->o.radius_scale > 0.0f ? p->o.radius_scale : 1.0f);
}

static uint8_t field_of(lci_atoms *p, const char *sym, const lci_atom_attr *attr)
{
    if (p->o.fields_by_element) return (uint8_t)lci_fieldmap_id(&p->fm, sym, 1);
    if (!p->o.by_attr) return 0;
    const char *v = !attr                               ? NULL
                     : p->o.by_attr == LCI_BY_TYPE      ? attr->type
                     : p->o.by_attr == LCI_BY_CHAIN     ? attr->chain
                     : p->o.by_attr == LCI_BY_COLUMN    ? attr->column
                                                        : attr->resname;
    if (!v) {
        p->field_missing++;
        return 0;
    }
    return (uint8_t)lci_fieldmap_id(&p->fm, v, p->o.by_attr != LCI_BY_CHAIN);
}

static int cpk_class(const char *sym)
{
    static const char *const cls[] = {"C", "N", "O", "S", "P", "H"};
    for (int i = 0; i < 6; i++)
        if (!strcasecmp(sym, cls[i])) return i;
    return 6;
}

int lci_atoms_add(lci_atoms *p, float x, float y, float z, const char *sym)
{
    return lci_atoms_add_attr(p, x, y, z, sym, NULL);
}

int lci_atoms_add_attr(lci_atoms *p, float x, float y, float z, const char *sym, const lci_atom_attr *attr)
{
    size_t index = p->seen++;
    if (p->capture) return lci_topo_capture(p->capture, sym, attr);
    if (p->o.select[0]) {
        if (!p->sel && lci_select_parse(NULL, "select", p->o.select, &p->sel) != LC_OK) return -1;
        if (!lci_select_match(p->sel, index, sym, attr, &p->sel_missing)) return 0;
    }
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
        if (p->o.value) {
            float *v = realloc(p->v, cap * sizeof(float));
            if (!v) return -1;
            p->v = v;
        }
        if (p->o.cpk) {
            uint8_t *sv = realloc(p->solvent, cap);
            if (!sv) return -1;
            p->solvent = sv;
        }
        p->cap = cap;
    }
    p->xyz[3 * p->n] = x, p->xyz[3 * p->n + 1] = y, p->xyz[3 * p->n + 2] = z;
    p->r[p->n] = radius_for(p, sym);
    p->field[p->n] = field_of(p, sym, attr);
    if (p->o.value) p->v[p->n] = attr ? attr->value : 1.0f;
    if (p->o.cpk) {
        const char *res = attr ? attr->resname : NULL;
        int solv = res && (lci_resname_water(res) || lci_resname_ion(res));
        p->field[p->n] = (uint8_t)cpk_class(sym);
        p->solvent[p->n] = (uint8_t)solv;
        p->nsolvent += (size_t)solv;
    }
    p->n++;
    return 0;
}

void lci_atoms_free(lci_atoms *p)
{
    free(p->xyz);
    free(p->r);
    free(p->field);
    free(p->v);
    free(p->solvent);
    lci_select_free(p->sel);
    lci_fieldmap_free(&p->fm);
    p->xyz = p->r = p->v = NULL;
    p->field = p->solvent = NULL;
    p->sel = NULL;
    p->n = p->cap = 0;
}

lc_status lci_atoms_finish(lc_device *dev, const char *path, lc_status s, lci_atoms *p, lci_loaded *out)
{
    if (s == LC_OK && p->sel_missing)
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                      "%s: select = '%s': keyword '%s' needs %s, which this %s file does not give", path, p->o.select,
                      p->sel_missing,
                      !strcmp(p->sel_missing, "name") || !strcmp(p->sel_missing, "backbone") ? "atom names"
                      : !strcmp(p->sel_missing, "chain")   ? "chain identifiers"
                      : !strcmp(p->sel_missing, "segid")   ? "segment identifiers"
                      : !strcmp(p->sel_missing, "type")    ? "atom types"
                      : !strcmp(p->sel_missing, "resid")   ? "residue numbers"
                                                           : "residue names", p->o.format);
    if (s == LC_OK && p->field_missing)
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: fields by %s: this %s file gives no %s (%d atoms without)", path,
                      lci_field_by_name(p->o.by_attr), p->o.format,
                      p->o.by_attr == LCI_BY_TYPE     ? "atom types"
                      : p->o.by_attr == LCI_BY_CHAIN  ? "chain identifiers"
                      : p->o.by_attr == LCI_BY_COLUMN ? "such column"
                                                      : "residue names",
                      p->field_missing);
    if (s == LC_OK) {
        char what[300];
        snprintf(what, sizeof what, "%s%s", p->o.fields_by_element ? "element" : lci_field_by_name(p->o.by_attr),
                 p->o.by_attr == LCI_BY_COLUMN ? p->o.column - 1 : "");
        if (p->o.by_attr == LCI_BY_COLUMN) what[6] = ' '; /* "column NAME" */
        lci_fieldmap_warn(dev, path, what, &p->fm);
    }
    if (s == LC_OK && p->o.select[0] && p->n == 0)
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: select = '%s' matches none of the %zu atoms", path,
                      p->o.select, p->seen);
    if (s == LC_OK && p->o.cpk) { /* solvent gets its own field when something else is there */
        int top = 0;
        for (size_t i = 0; i < p->n; i++) {
            if (p->nsolvent < p->n && p->solvent[i]) p->field[i] = LCI_CPK_SOLVENT;
            if (p->field[i] > top) top = p->field[i];
        }
        p->o.fields_by_element = 0;
        p->nnames = top + 1;
    }
    if (s == LC_OK && p->unknown)
        lci_log(dev, LC_LOG_WARNING, "%s: %d atoms of unknown elements (first '%s') got radius %.2f", path, p->unknown,
                p->first_unknown, (double)LCI_DEFAULT_RADIUS);
    lc_particles_desc *d = s == LC_OK ? calloc(1, sizeof *d) : NULL;
    if (s == LC_OK && !d) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    if (s != LC_OK) {
        lci_atoms_free(p);
        return s;
    }
    d->count = p->n;
    d->positions = p->xyz;
    d->radii = p->r;
    d->fields = p->field;
    d->values = p->v;
    d->nfields = p->o.cpk ? (p->nnames ? p->nnames : 1) : p->fm.n ? p->fm.n : 1;
    free(p->solvent);
    lci_select_free(p->sel);
    lci_fieldmap_free(&p->fm);
    p->solvent = NULL;
    p->sel = NULL;
    out->desc = d;
    lci_loaded_keep(out, p->xyz);
    lci_loaded_keep(out, p->r);
    lci_loaded_keep(out, p->field);
    if (p->v) lci_loaded_keep(out, p->v);
    return LC_OK;
}
