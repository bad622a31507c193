/* Trajectory topologies (topology.h): a companion PSF, .gro or PDB read
 * into one atom table, joined to a frame's coordinates. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "host/formats/psf.h"
#include "host/formats/text_reader.h"
#include "host/formats/topology.h"

static const char *const kind_names[] = {"", "PSF", "GRO", "PDB"};

int lci_topo_capture(lci_topo *t, const char *element, const lci_atom_attr *at)
{
    if (t->natom == t->cap) {
        long cap = t->cap ? t->cap * 2 : 1024;
        lci_topo_atom *a = realloc(t->atom, sizeof *a * (size_t)cap);
        if (!a) return t->oom = 1, -1;
        t->atom = a;
        t->cap = cap;
    }
    lci_topo_atom *d = &t->atom[t->natom++];
    memset(d, 0, sizeof *d);
    snprintf(d->element, sizeof d->element, "%s", element ? element : "X");
    if (at) {
        snprintf(d->name, sizeof d->name, "%s", at->name ? at->name : "");
        snprintf(d->resname, sizeof d->resname, "%s", at->resname ? at->resname : "");
        snprintf(d->chain, sizeof d->chain, "%s", at->chain ? at->chain : "");
        snprintf(d->segid, sizeof d->segid, "%s", at->segid ? at->segid : "");
        snprintf(d->type, sizeof d->type, "%s", at->type ? at->type : "");
        d->resid = at->resid;
        d->has_resid = at->has_resid;
    }
    return 0;
}

/* The kind a topology file's name says (".gz" looked through). */
static lci_topo_kind kind_of(const char *path)
{
    size_t n = strlen(path);
    if (n > 3 && !strcasecmp(path + n - 3, ".gz")) n -= 3;
    static const char *const ext[] = {NULL, ".psf", ".gro", ".pdb"};
    for (int k = LCI_TOPO_PSF; k <= LCI_TOPO_PDB; k++)
        if (n > 4 && !strncasecmp(path + n - 4, ext[k], 4)) return (lci_topo_kind)k;
    if (n > 4 && !strncasecmp(path + n - 4, ".ent", 4)) return LCI_TOPO_PDB;
    return LCI_TOPO_NONE;
}

/* A topology whose name says nothing: "PSF" starts a PSF, a PDB record name
 * a PDB file, anything else is read as .gro. */
static lc_status sniff(lc_device *dev, const char *path, lci_topo_kind *k)
{
    unsigned char head[512];
    size_t n = 0;
    int gz;
    lc_status s = lci_file_head(dev, path, head, sizeof head, &n, &gz);
    if (s != LC_OK) return s;
    *k = n >= 3 && !memcmp(head, "PSF", 3) ? LCI_TOPO_PSF : lci_format_pdb.magic(head, n) ? LCI_TOPO_PDB : LCI_TOPO_GRO;
    return LC_OK;
}

static lc_status read_psf(lc_device *dev, lci_topo *t)
{
    lci_psf psf = {0};
    lc_status s = lci_psf_read(dev, t->path, &psf);
    if (s != LC_OK) return s;
    t->atom = calloc((size_t)(psf.natom > 0 ? psf.natom : 1), sizeof *t->atom);
    if (!t->atom) {
        lci_psf_free(&psf);
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", t->path);
    }
    for (long i = 0; i < psf.natom; i++) {
        const lci_psf_atom *p = &psf.atom[i];
        lci_topo_atom *d = &t->atom[i];
        snprintf(d->name, sizeof d->name, "%s", p->name);
        snprintf(d->resname, sizeof d->resname, "%s", p->resname);
        snprintf(d->segid, sizeof d->segid, "%s", p->segid);
        snprintf(d->type, sizeof d->type, "%s", p->type);
        snprintf(d->element, sizeof d->element, "%s", p->element);
        d->resid = p->resid;
        d->has_resid = 1;
        d->charge = p->charge;
        d->mass = p->mass;
    }
    t->natom = t->cap = psf.natom;
    lci_psf_free(&psf);
    return LC_OK;
}

static lc_status read_topo(lc_device *dev, lci_topo *t)
{
    if (t->kind == LCI_TOPO_PSF) return read_psf(dev, t);
    lci_atoms p;
    memset(&p, 0, sizeof p);
    p.capture = t;
    lc_status s = t->kind == LCI_TOPO_GRO ? lci_gro_topology(dev, t->path, &p) : lci_pdb_topology(dev, t->path, &p);
    lci_atoms_free(&p);
    if (s == LC_OK && t->oom) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", t->path);
    return s;
}

lc_status lci_topo_load(lc_device *dev, const lci_read_args *a, const char *exts, lci_topo *t, char *why, size_t n)
{
    memset(t, 0, sizeof *t);
    why[0] = '\0';
    const char *c = a->desc->companion;
    if (c && c[0]) {
        snprintf(t->path, sizeof t->path, "%s", c);
        t->kind = kind_of(c);
        lc_status s = t->kind == LCI_TOPO_NONE ? sniff(dev, c, &t->kind) : LC_OK;
        if (s != LC_OK) {
            char msg[LCI_MSG_MAX];
            snprintf(msg, sizeof msg, "%s", lc_last_error());
            return lci_error(dev, s, "%s: topology: %s", a->path, msg);
        }
    } else {
        const char *slash = strrchr(a->path, '/');
        const char *dot = strrchr(slash ? slash + 1 : a->path, '.');
        int stem = (int)(dot ? (size_t)(dot - a->path) : strlen(a->path));
        char tried[3200] = "";
        for (const char *e = exts; *e && t->kind == LCI_TOPO_NONE;) {
            while (*e == ' ') e++;
            int len = (int)strcspn(e, " ");
            snprintf(t->path, sizeof t->path, "%.*s%.*s", stem, a->path, len, e);
            FILE *f = fopen(t->path, "rb");
            if (f) fclose(f), t->kind = kind_of(t->path);
            else snprintf(tried + strlen(tried), sizeof tried - strlen(tried), "%s%.1000s", tried[0] ? ", " : "", t->path);
            e += len;
        }
        if (t->kind == LCI_TOPO_NONE) {
            snprintf(why, n, "no topology: %s %s and none was given (--topology FILE, lc_load_desc.companion)", tried,
                     strchr(tried, ',') ? "do not exist" : "does not exist");
            return LC_OK;
        }
    }
    lc_status s = read_topo(dev, t);
    if (s != LC_OK) {
        char msg[LCI_MSG_MAX];
        snprintf(msg, sizeof msg, "%s", lc_last_error());
        lci_topo_free(t);
        return lci_error(dev, s, "%s: topology: %s", a->path, msg);
    }
    return LC_OK;
}

void lci_topo_free(lci_topo *t)
{
    free(t->atom);
    t->atom = NULL;
    t->natom = t->cap = 0;
}

/* The columns `fields = column:NAME` and `value = NAME` can name. */
enum { C_SEGID, C_RESID, C_RESNAME, C_NAME, C_TYPE, C_CHAIN, C_CHARGE, C_MASS, C_ELEMENT, C_N };
static const char *const col_names[C_N] = {"segid", "resid", "resname", "name", "type", "chain", "charge", "mass",
                                           "element"};

/* 1 if a topology of kind k has column c. */
static int has_col(lci_topo_kind k, int c)
{
    switch (c) {
    case C_SEGID: case C_TYPE: return k == LCI_TOPO_PSF || (k == LCI_TOPO_PDB && c == C_SEGID);
    case C_CHAIN: return k == LCI_TOPO_PDB;
    case C_CHARGE: case C_MASS: return k == LCI_TOPO_PSF;
    default: return 1;
    }
}

static lc_status columns(lc_device *dev, const char *path, const lci_topo *t, const lci_atom_opts *o, int *fcol, int *vcol)
{
    for (int k = 0; k < C_N; k++) {
        if (!has_col(t->kind, k)) continue;
        if (o->column && !strcasecmp(o->column, col_names[k])) *fcol = k;
        if (o->value && !strcasecmp(o->value, col_names[k]) && (k == C_RESID || k == C_CHARGE || k == C_MASS)) *vcol = k;
    }
    if ((!o->column || *fcol >= 0) && (!o->value || *vcol >= 0)) return LC_OK;
    char cols[128] = "", nums[64] = "";
    for (int k = 0; k < C_N; k++) {
        if (!has_col(t->kind, k)) continue;
        snprintf(cols + strlen(cols), sizeof cols - strlen(cols), "%s%s", cols[0] ? ", " : "", col_names[k]);
        if (k == C_RESID || k == C_CHARGE || k == C_MASS)
            snprintf(nums + strlen(nums), sizeof nums - strlen(nums), "%s%s", nums[0] ? ", " : "", col_names[k]);
    }
    if (o->column && *fcol < 0)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: fields by column '%s': the %s topology has no such column "
                         "(it has %s)", path, o->column, kind_names[t->kind], cols);
    return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: value = '%s': the %s topology has no such numeric column (it "
                     "has %s)", path, o->value, kind_names[t->kind], nums);
}

static const char *col_text(const lci_topo_atom *ta, int k, char *buf, size_t n)
{
    switch (k) {
    case C_SEGID: return ta->segid;
    case C_RESNAME: return ta->resname;
    case C_NAME: return ta->name;
    case C_TYPE: return ta->type;
    case C_CHAIN: return ta->chain;
    case C_ELEMENT: return ta->element;
    case C_RESID: snprintf(buf, n, "%ld", ta->resid); return buf;
    default: snprintf(buf, n, "%g", (double)(k == C_CHARGE ? ta->charge : ta->mass)); return buf;
    }
}

/* The frame's own value `value = NAME` names: its array, or NULL (not one; *err set when the frame lacks it). */
static const float *frame_value(lc_device *dev, const char *path, const lci_traj_values *vals, const char *name,
                                lc_status *err)
{
    for (int j = 0; vals && j < LCI_TRAJ_VALUES; j++) {
        if (!vals->name[j] || strcasecmp(vals->name[j], name)) continue;
        if (!vals->v[j])
            *err = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: value = '%s': this frame holds no %s", path, name,
                             j ? "forces" : "velocities");
        return vals->v[j];
    }
    return NULL;
}

lc_status lci_topo_atoms(lc_device *dev, const lci_read_args *a, lc_status s, const lci_topo *t, const char *why,
                         const float *xyz, int64_t natom, const lci_traj_values *vals, lci_loaded *out)
{
    lci_atoms p;
    memset(&p, 0, sizeof p);
    if (s != LC_OK) return lci_atoms_finish(dev, a->path, s, &p, out);
    if ((s = lci_atom_options(dev, a, &p.o)) != LC_OK) return s;
    const float *own = p.o.value ? frame_value(dev, a->path, vals, p.o.value, &s) : NULL;
    if (s != LC_OK) return lci_atoms_finish(dev, a->path, s, &p, out);
    const char *value = p.o.value;
    if (own) p.o.value = NULL; /* not a topology column */
    int have = t->kind != LCI_TOPO_NONE;
    if (have && t->natom != natom) {
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: holds %lld atoms but its topology %s has %ld", a->path,
                      (long long)natom, t->path, t->natom);
        return lci_atoms_finish(dev, a->path, s, &p, out);
    }
    if (!have && (p.o.column || p.o.value)) {
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: %s '%s' needs the topology (%s)", a->path,
                      p.o.column ? "fields by column" : "value =", p.o.column ? p.o.column : p.o.value, why);
        return lci_atoms_finish(dev, a->path, s, &p, out);
    }
    if (!have) {
        lci_log(dev, LC_LOG_WARNING, "%s: %s; every atom gets radius %g", a->path, why,
                (double)(p.o.radius > 0.0f ? p.o.radius : LCI_DEFAULT_RADIUS));
        if (!(p.o.radius > 0.0f)) p.o.radius = LCI_DEFAULT_RADIUS;
    }
    int fcol = -1, vcol = -1;
    if (have && (s = columns(dev, a->path, t, &p.o, &fcol, &vcol)) != LC_OK) return lci_atoms_finish(dev, a->path, s, &p, out);
    p.o.value = value;
    for (int64_t i = 0; i < natom && s == LC_OK; i++) {
        const lci_topo_atom *ta = have ? &t->atom[i] : NULL;
        char colv[32];
        lci_atom_attr at = {0};
        if (ta) {
            at = (lci_atom_attr){.name = ta->name, .resname = ta->resname, .resid = ta->resid, .has_resid = ta->has_resid,
                                 .chain = t->kind == LCI_TOPO_PDB ? ta->chain : NULL,
                                 .segid = t->kind != LCI_TOPO_GRO ? ta->segid : NULL,
                                 .type = t->kind == LCI_TOPO_PSF ? ta->type : NULL};
            if (fcol >= 0) at.column = col_text(ta, fcol, colv, sizeof colv);
            if (vcol >= 0) at.value = vcol == C_MASS ? ta->mass : vcol == C_CHARGE ? ta->charge : (float)ta->resid;
        }
        if (own) at.value = own[i];
        if (lci_atoms_add_attr(&p, xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2], ta ? ta->element : "X", ta || own ? &at : NULL))
            s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", a->path);
    }
    return lci_atoms_finish(dev, a->path, s, &p, out);
}
