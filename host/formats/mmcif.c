/* PDBx/mmCIF (wwPDB): the _atom_site loop of the first data block. CIF 1.1
 * syntax as far as a loop needs it: bare, 'single' and "double" quoted
 * values (a quote closes only before white space), ;text fields; between
 * lines, # comments. Element from type_symbol (else the first letter of the
 * atom name), position from Cartn_x/y/z (standard uncertainties "(n)" cut).
 * Models (pdbx_PDB_model_num, contiguous runs of one number) are frames:
 * lc_load_desc.frame N reads the (N+1)-th; a loop without model numbers is
 * one frame. Alternate locations (label_alt_id): the first of each atom is
 * kept (altloc.h). `select` sees name (label_atom_id), resname
 * (label_comp_id), chain (auth_asym_id, else label_asym_id), resid
 * (auth_seq_id, else label_seq_id) and index; segid and type fail naming
 * the keyword. `value = COLUMN` takes k_i from any numeric _atom_site item
 * (occupancy, B_iso_or_equiv alias bfactor, ...) and `fields =
 * column:NAME` maps any item's distinct values to fields (col_alias below).
 * Plain or gzip; every error names the file and line. */
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "host/formats/altloc.h"
#include "host/formats/elements.h"
#include "host/formats/text_reader.h"

#define TOK_MAX 256

typedef struct ctok {
    lci_text t;
    const char *p; /* next character in t.line, NULL: read a line first */
    int eof;
} ctok;

/* Copies n bytes of s into out (TOK_MAX), cut to fit. */
static void put_tok(char *out, const char *s, size_t n)
{
    if (n > TOK_MAX - 1) n = TOK_MAX - 1;
    memcpy(out, s, n);
    out[n] = 0;
}

/* The next value or keyword into out; *quoted = 1 when it was quoted (so
 * never a keyword or tag), *line = the line it started on. 1 ok, 0 end of
 * file, -1 error (reported). */
static int next_token(ctok *c, char *out, int *quoted, long *line)
{
    for (;;) {
        if (!c->p) {
            int rc = lci_text_line(&c->t);
            if (rc <= 0) return c->eof = 1, rc;
            c->p = c->t.line;
            if (c->t.line[0] == ';') { /* a text field up to a line starting with ';' */
                *line = c->t.lineno;
                put_tok(out, c->t.line + 1, strlen(c->t.line + 1));
                while ((rc = lci_text_line(&c->t)) == 1 && c->t.line[0] != ';') {
                    size_t n = strlen(out);
                    put_tok(out + n, c->t.line, strlen(c->t.line) < TOK_MAX - 1 - n ? strlen(c->t.line) : TOK_MAX - 1 - n);
                }
                if (rc < 0) return -1;
                if (rc == 0) {
                    lci_error(c->t.dev, LC_ERROR_FORMAT, "%s:%ld: a ;text field never closes (no line starting with ';')",
                              c->t.path, *line);
                    return -1;
                }
                c->p = c->t.line + 1;
                size_t n = strlen(out);
                while (n && isspace((unsigned char)out[n - 1])) out[--n] = 0;
                *quoted = 1;
                return 1;
            }
        }
        while (*c->p && isspace((unsigned char)*c->p)) c->p++;
        if (!*c->p || *c->p == '#') {
            c->p = NULL;
            continue;
        }
        *line = c->t.lineno;
        const char *s = c->p;
        if (*s == '\'' || *s == '"') {
            const char *e = s + 1;
            while (*e && !(*e == *s && (!e[1] || isspace((unsigned char)e[1])))) e++;
            if (!*e) {
                lci_error(c->t.dev, LC_ERROR_FORMAT, "%s:%ld: a value opened with %c never closes on its line",
                          c->t.path, *line, *s);
                return -1;
            }
            put_tok(out, s + 1, (size_t)(e - s - 1));
            c->p = e + 1;
            *quoted = 1;
            return 1;
        }
        const char *e = s;
        while (*e && !isspace((unsigned char)*e)) e++;
        put_tok(out, s, (size_t)(e - s));
        c->p = e;
        *quoted = 0;
        return 1;
    }
}

static int keyword(const char *s, int quoted)
{
    return !quoted && (s[0] == '_' || !strncasecmp(s, "loop_", 5) || !strncasecmp(s, "data_", 5) ||
                       !strncasecmp(s, "save_", 5) || !strncasecmp(s, "global_", 7) || !strncasecmp(s, "stop_", 5));
}

enum { C_TYPE, C_X, C_Y, C_Z, C_MODEL, C_ALT, C_ATOM, C_ASYM, C_SEQ, C_INS, C_AUTH_ASYM, C_AUTH_SEQ, C_COMP,
       C_AUTH_COMP, C_NCOLS };
static const char *const col_names[C_NCOLS] = {
    "type_symbol", "Cartn_x", "Cartn_y", "Cartn_z", "pdbx_PDB_model_num", "label_alt_id", "label_atom_id",
    "label_asym_id", "label_seq_id", "pdbx_PDB_ins_code", "auth_asym_id", "auth_seq_id", "label_comp_id",
    "auth_comp_id"};

/* `fields = column:NAME` and `value = COLUMN` name any _atom_site item (with
 * or without the "_atom_site." prefix), or one of the PDB-style names below
 * (the first item of the list the loop has). */
static const char *const col_alias[][2] = {
    {"bfactor", "B_iso_or_equiv"}, {"tempfactor", "B_iso_or_equiv"}, {"beta", "B_iso_or_equiv"},
    {"resname", "label_comp_id auth_comp_id"}, {"chain", "auth_asym_id label_asym_id"},
    {"name", "label_atom_id auth_atom_id"}, {"resid", "auth_seq_id label_seq_id"}, {"element", "type_symbol"},
    {"charge", "pdbx_formal_charge"}, {"altloc", "label_alt_id"}, {"record", "group_PDB"}, {"serial", "id"},
    {"x", "Cartn_x"}, {"y", "Cartn_y"}, {"z", "Cartn_z"}};

/* The rank of item among the candidates for the user's name (0 best), or -1. */
static int alias_rank(const char *user, const char *item)
{
    if (!user) return -1;
    if (!strncasecmp(user, "_atom_site.", 11)) user += 11;
    const char *cands = user;
    for (size_t i = 0; i < sizeof col_alias / sizeof col_alias[0]; i++)
        if (!strcasecmp(user, col_alias[i][0])) cands = col_alias[i][1];
    int rank = 0;
    for (const char *w = cands; *w; rank++) {
        size_t n = cands == user ? strlen(w) : strcspn(w, " ");
        if (strlen(item) == n && !strncasecmp(w, item, n)) return rank;
        w += n;
        while (*w == ' ') w++;
    }
    return -1;
}

#define MAX_COLS 128

typedef struct walk_state {
    int64_t frame;   /* the model to read */
    lci_atoms *p;    /* NULL: count models only */
    int64_t models;  /* models seen */
    lci_altlocs alt;
    int fcol, vcol;  /* loop columns of fields = column:NAME and value = COLUMN, -1: none */
    char vitem[TOK_MAX]; /* the value column's item name */
} walk_state;

static int unknown(const char *v) { return !v[0] || ((v[0] == '?' || v[0] == '.') && !v[1]); }

/* A coordinate: a number, its standard uncertainty "(n)" cut off. */
static int coordinate(const char *v, float *out)
{
    char b[TOK_MAX];
    snprintf(b, sizeof b, "%s", v);
    char *paren = strchr(b, '(');
    if (paren) *paren = 0;
    return lci_parse_float(b, out);
}

/* The element symbol of a row: type_symbol, else the atom name's first letter. */
static void element_of(const char *type, const char *atom, char *el, size_t n)
{
    const char *s = !unknown(type) ? type : atom;
    size_t k = 0;
    while (*s && !isalpha((unsigned char)*s)) s++;
    for (; *s && isalpha((unsigned char)*s) && k + 1 < n && k < 2; s++, k++)
        el[k] = (char)(k ? tolower((unsigned char)*s) : toupper((unsigned char)*s));
    if (unknown(type) && k > 1) k = 1; /* "CA" as an atom name is carbon alpha */
    el[k] = 0;
    if (!k) snprintf(el, n, "X");
}

/* One _atom_site row (its values in row[]). */
static lc_status row_done(ctok *c, walk_state *w, char row[][TOK_MAX], const int *col, char *model_id, long line)
{
    const char *model = col[C_MODEL] >= 0 ? row[col[C_MODEL]] : "1";
    if (w->models == 0 || strcmp(model, model_id)) {
        w->models++;
        put_tok(model_id, model, strlen(model));
        w->alt.residue[0] = 0;
        w->alt.n = 0;
    }
    if (!w->p || w->models - 1 != w->frame) return LC_OK;
    float x[3];
    for (int a = 0; a < 3; a++)
        if (coordinate(row[col[C_X + a]], &x[a]))
            return lci_error(c->t.dev, LC_ERROR_FORMAT, "%s:%ld: _atom_site.%s is '%s', expected a number", c->t.path,
                             line, col_names[C_X + a], row[col[C_X + a]]);
    char res[40], el[4];
    int asym = col[C_AUTH_ASYM] >= 0 ? col[C_AUTH_ASYM] : col[C_ASYM];
    int seq = col[C_AUTH_SEQ] >= 0 ? col[C_AUTH_SEQ] : col[C_SEQ];
    snprintf(res, sizeof res, "%.12s %.12s %.8s", asym >= 0 ? row[asym] : "", seq >= 0 ? row[seq] : "",
             col[C_INS] >= 0 ? row[col[C_INS]] : "");
    const char *atom = col[C_ATOM] >= 0 ? row[col[C_ATOM]] : "";
    int keep = lci_altloc_keep(&w->alt, res, atom, col[C_ALT] < 0 || unknown(row[col[C_ALT]]));
    if (keep == 0) return LC_OK;
    element_of(col[C_TYPE] >= 0 ? row[col[C_TYPE]] : "?", atom, el, sizeof el);
    int comp = col[C_COMP] >= 0 ? col[C_COMP] : col[C_AUTH_COMP];
    char *rend = NULL;
    long resid = seq >= 0 ? strtol(row[seq], &rend, 10) : 0;
    lci_atom_attr at = {.name = col[C_ATOM] >= 0 ? atom : NULL, .resname = comp >= 0 ? row[comp] : NULL,
                        .chain = asym >= 0 ? row[asym] : NULL, .resid = resid,
                        .has_resid = rend && rend != row[seq] && !*rend};
    if (w->fcol >= 0) at.column = row[w->fcol];
    if (w->vcol >= 0 && (unknown(row[w->vcol]) || coordinate(row[w->vcol], &at.value) || !isfinite(at.value)))
        return lci_error(c->t.dev, LC_ERROR_FORMAT, "%s:%ld: value = %s: _atom_site.%s is '%s', not a number%s",
                         c->t.path, line, w->p->o.value, w->vitem, row[w->vcol],
                         unknown(row[w->vcol]) ? " (unknown)" : "");
    if (keep < 0 || lci_atoms_add_attr(w->p, x[0], x[1], x[2], el, &at))
        return lci_error(c->t.dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory at line %ld", c->t.path, line);
    return LC_OK;
}

/* Walks the first data block to its _atom_site loop and reads it. */
static lc_status walk(ctok *c, walk_state *w)
{
    char tok[TOK_MAX], model_id[TOK_MAX] = "";
    int quoted, rc, blocks = 0;
    long line = 0, loop_line = 0;
    char(*row)[TOK_MAX] = malloc(sizeof(char[MAX_COLS][TOK_MAX]));
    if (!row) return lci_error(c->t.dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", c->t.path);
    lc_status s = LC_OK;
    int found = 0;
    rc = next_token(c, tok, &quoted, &line);
    while (rc == 1 && !found) {
        if (!quoted && !strncasecmp(tok, "data_", 5) && ++blocks > 1) break;
        if (quoted || strcasecmp(tok, "loop_")) {
            rc = next_token(c, tok, &quoted, &line);
            continue;
        }
        loop_line = line;
        /* the loop's tags */
        int ncols = 0, col[C_NCOLS], site = 0, frank = 1 << 20, vrank = 1 << 20;
        char items[1000] = "";
        for (int k = 0; k < C_NCOLS; k++) col[k] = -1;
        w->fcol = w->vcol = -1;
        while ((rc = next_token(c, tok, &quoted, &line)) == 1 && !quoted && tok[0] == '_') {
            int is_site = !strncasecmp(tok, "_atom_site.", 11);
            if (ncols == 0) site = is_site;
            else if (is_site != site) {
                s = lci_error(c->t.dev, LC_ERROR_FORMAT, "%s:%ld: tag %s in a loop of %s tags", c->t.path, line, tok,
                              site ? "_atom_site" : "other");
                goto out;
            }
            if (site) {
                if (ncols == MAX_COLS) {
                    s = lci_error(c->t.dev, LC_ERROR_FORMAT, "%s:%ld: more than %d _atom_site columns", c->t.path, line,
                                  MAX_COLS);
                    goto out;
                }
                for (int k = 0; k < C_NCOLS; k++)
                    if (!strcasecmp(tok + 11, col_names[k])) col[k] = ncols;
                int r = w->p ? alias_rank(w->p->o.column, tok + 11) : -1;
                if (r >= 0 && r < frank) frank = r, w->fcol = ncols;
                r = w->p ? alias_rank(w->p->o.value, tok + 11) : -1;
                if (r >= 0 && r < vrank) vrank = r, w->vcol = ncols, put_tok(w->vitem, tok + 11, strlen(tok + 11));
                if (strlen(items) + strlen(tok + 11) + 8 < sizeof items)
                    snprintf(items + strlen(items), sizeof items - strlen(items), "%s%s", ncols ? " " : "", tok + 11);
                else if (!strstr(items, "..."))
                    snprintf(items + strlen(items), sizeof items - strlen(items), " ...");
            }
            ncols++;
        }
        if (rc < 0) break;
        if (!site) continue; /* another category's loop: its values are skipped as tokens */
        found = 1;
        if (w->p && ((w->p->o.column && w->fcol < 0) || (w->p->o.value && w->vcol < 0))) {
            int f = w->p->o.column && w->fcol < 0;
            s = lci_error(c->t.dev, LC_ERROR_INVALID_ARGUMENT, "%s:%ld: %s '%s': the _atom_site loop has no such "
                          "column (it has: %s)", c->t.path, loop_line, f ? "fields by column" : "value =",
                          f ? w->p->o.column : w->p->o.value, items);
            goto out;
        }
        for (int a = 0; a < 3; a++)
            if (col[C_X + a] < 0) {
                s = lci_error(c->t.dev, LC_ERROR_FORMAT, "%s:%ld: the _atom_site loop has no _atom_site.%s column",
                              c->t.path, loop_line, col_names[C_X + a]);
                goto out;
            }
        long row_line = line;
        int k = 0;
        while (rc == 1 && !keyword(tok, quoted)) {
            if (k == 0) row_line = line;
            put_tok(row[k], tok, strlen(tok));
            if (++k == ncols) {
                if ((s = row_done(c, w, row, col, model_id, row_line)) != LC_OK) goto out;
                k = 0;
            }
            rc = next_token(c, tok, &quoted, &line);
        }
        if (rc >= 0 && k != 0) {
            s = lci_error(c->t.dev, LC_ERROR_FORMAT,
                          "%s:%ld: the _atom_site loop ends in the middle of a row (%d of its %d values)", c->t.path,
                          row_line, k, ncols);
            goto out;
        }
    }
    if (rc < 0) s = LC_ERROR_FORMAT;
    else if (!found)
        s = lci_error(c->t.dev, LC_ERROR_FORMAT, "%s:%ld: no _atom_site loop in the first data block", c->t.path,
                      c->t.lineno);
    else if (w->models == 0)
        s = lci_error(c->t.dev, LC_ERROR_FORMAT, "%s:%ld: the _atom_site loop (line %ld) has no rows", c->t.path,
                      c->t.lineno, loop_line);
    else if (w->p && w->frame >= w->models)
        s = lci_error(c->t.dev, LC_ERROR_INVALID_ARGUMENT, "%s: frame %lld is past the end: the file holds %lld model%s",
                      c->t.path, (long long)w->frame, (long long)w->models, w->models > 1 ? "s" : "");
    else if (w->p && w->p->n == 0 && !w->p->o.select[0]) /* a selection: lci_atoms_finish says why */
        s = lci_error(c->t.dev, LC_ERROR_FORMAT, "%s:%ld: the _atom_site loop has no atoms in the model read", c->t.path,
                      loop_line);
out:
    free(row);
    return s;
}

static lc_status mmcif_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    lci_atoms p;
    memset(&p, 0, sizeof p);
    lc_status s = lci_atom_options(dev, a, &p.o);
    if (s != LC_OK) return s;
    ctok c;
    memset(&c, 0, sizeof c);
    if ((s = lci_text_open(dev, a->path, &c.t)) != LC_OK) return s;
    walk_state w;
    memset(&w, 0, sizeof w);
    w.frame = a->desc->frame;
    w.p = &p;
    s = walk(&c, &w);
    lci_text_close(&c.t);
    if (s == LC_OK && w.alt.skipped)
        lci_log(dev, LC_LOG_INFO, "%s: %zu alternate-location rows skipped (the first of each atom kept)", a->path,
                w.alt.skipped);
    lci_altlocs_free(&w.alt);
    return lci_atoms_finish(dev, a->path, s, &p, out);
}

static lc_status mmcif_frames(lc_device *dev, const char *path, int64_t *out)
{
    *out = 0;
    ctok c;
    memset(&c, 0, sizeof c);
    lc_status s = lci_text_open(dev, path, &c.t);
    if (s != LC_OK) return s;
    walk_state w;
    memset(&w, 0, sizeof w);
    s = walk(&c, &w);
    lci_text_close(&c.t);
    lci_altlocs_free(&w.alt);
    if (s == LC_OK) *out = w.models;
    return s;
}

/* A CIF file starts with data_ (perhaps after comments and blank lines). */
static int mmcif_magic(const unsigned char *h, size_t n)
{
    size_t i = 0;
    while (i < n) {
        while (i < n && isspace(h[i])) i++;
        if (i < n && h[i] == '#') {
            while (i < n && h[i] != '\n') i++;
            continue;
        }
        return i + 5 <= n && !strncasecmp((const char *)h + i, "data_", 5);
    }
    return 0;
}

const lci_format lci_format_mmcif = {
    .name = "mmcif", .kind = LC_KIND_PARTICLES, .extensions = ".cif .mmcif", .options = "radius radius_scale fields select value",
    .description = "PDBx/mmCIF: the _atom_site loop (type_symbol, Cartn_x/y/z), first altloc of each atom; models "
                   "as frames",
    .magic = mmcif_magic, .read = mmcif_read, .frames = mmcif_frames};
