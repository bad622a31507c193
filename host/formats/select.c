/* Atom selections: parser and evaluator (select.h). */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "host/formats/select.h"

enum op { OP_ALL, OP_NONE, OP_NOT, OP_AND, OP_OR, OP_PROTEIN, OP_BACKBONE, OP_WATER, OP_ION, OP_SOLVENT,
          OP_ELEMENT, OP_NAME, OP_RESNAME, OP_CHAIN, OP_SEGID, OP_TYPE, OP_INDEX, OP_RESID };

typedef struct node {
    enum op op;
    int a, b;        /* children (NOT: a; AND/OR: a, b) */
    int w0, nw;      /* words: s->words[w0 .. w0+nw) */
    int r0, nr;      /* ranges: s->ranges[r0 .. r0+nr) */
} node;

struct lci_select {
    node *nodes;
    int nnodes, root;
    char **words;
    int nwords;
    long (*ranges)[2];
    int nranges;
};

/* ---- residue classes */

static int in(const char *s, const char *const *list)
{
    if (!s) return 0;
    for (; *list; list++)
        if (!strcasecmp(s, *list)) return 1;
    return 0;
}

int lci_resname_water(const char *r)
{
    static const char *const w[] = {"HOH", "WAT", "SOL", "H2O", "DOD", "TIP", "TIP3", "TIP3P", "TIP4", "TIP4P", "TIP5",
                                    "TIP5P", "T3P", "T4P", "T5P", "SPC", "SPCE", "SWM4", "OPC", NULL};
    return in(r, w);
}

int lci_resname_ion(const char *r)
{
    static const char *const w[] = {"NA", "NA+", "CL", "CL-", "K", "K+", "MG", "CA", "ZN", "LI", "RB", "CS", "F", "BR",
                                    "IOD", "MN", "CU", "CU1", "FE", "FE2", "NI", "CO", "CD", "SOD", "CLA", "POT", "CAL",
                                    "CES", "LIT", "RUB", "BAR", "ZN2", "MG2", NULL};
    return in(r, w);
}

int lci_resname_protein(const char *r)
{
    static const char *const w[] = {
        "ALA", "ARG", "ASN", "ASP", "CYS", "GLN", "GLU", "GLY", "HIS", "ILE", "LEU", "LYS", "MET", "PHE", "PRO",
        "SER", "THR", "TRP", "TYR", "VAL", "HSD", "HSE", "HSP", "HID", "HIE", "HIP", "HSC", "CYX", "CYM", "CYN",
        "ASH", "GLH", "LYN", "LSN", "ASPP", "GLUP", "MSE", "SEC", "PYL", "NALA", "CALA", NULL};
    return in(r, w);
}

/* ---- parser */

typedef struct parser {
    lc_device *dev;
    const char *what, *src, *p;
    lci_select *s;
    lc_status err;
} parser;

static const char *const keywords[] = {"and", "or", "not", "all", "none", "protein", "backbone", "water", "ion",
                                       "solvent", "element", "name", "resname", "chain", "segid", "type", "index",
                                       "resid", NULL};

static void skip(parser *ps)
{
    while (isspace((unsigned char)*ps->p)) ps->p++;
}

/* The next token's extent (a parenthesis or a run of other non-space characters). */
static size_t token(parser *ps)
{
    skip(ps);
    if (*ps->p == '(' || *ps->p == ')') return 1;
    size_t n = 0;
    while (ps->p[n] && !isspace((unsigned char)ps->p[n]) && ps->p[n] != '(' && ps->p[n] != ')') n++;
    return n;
}

static int is_kw(parser *ps, const char *kw)
{
    size_t n = token(ps);
    return n == strlen(kw) && !strncasecmp(ps->p, kw, n);
}

static int fail(parser *ps, const char *at, const char *msg)
{
    if (ps->err == LC_OK) {
        int pos = (int)(at - ps->src) + 1;
        if (*at)
            ps->err = lci_error(ps->dev, LC_ERROR_INVALID_ARGUMENT, "%s: position %d ('%.12s'): %s in '%s'", ps->what,
                                pos, at, msg, ps->src);
        else
            ps->err = lci_error(ps->dev, LC_ERROR_INVALID_ARGUMENT, "%s: position %d (the end): %s in '%s'", ps->what,
                                pos, msg, ps->src);
    }
    return -1;
}

static int add_node(parser *ps, node n)
{
    lci_select *s = ps->s;
    node *nn = realloc(s->nodes, sizeof *nn * (size_t)(s->nnodes + 1));
    if (!nn) return fail(ps, ps->p, "out of memory");
    s->nodes = nn;
    nn[s->nnodes] = n;
    return s->nnodes++;
}

static int parse_expr(parser *ps, int depth);

static int parse_words(parser *ps, node *n, const char *kw)
{
    n->w0 = ps->s->nwords;
    for (;;) {
        size_t len = token(ps);
        if (!len || *ps->p == '(' || *ps->p == ')') break;
        int iskw = 0;
        for (int k = 0; keywords[k] && !iskw; k++) iskw = strlen(keywords[k]) == len && !strncasecmp(ps->p, keywords[k], len);
        if (iskw) break;
        char **w = realloc(ps->s->words, sizeof *w * (size_t)(ps->s->nwords + 1));
        if (!w) return fail(ps, ps->p, "out of memory");
        ps->s->words = w;
        if (!(w[ps->s->nwords] = strndup(ps->p, len))) return fail(ps, ps->p, "out of memory");
        ps->s->nwords++;
        n->nw++;
        ps->p += len;
    }
    if (!n->nw) {
        char msg[64];
        snprintf(msg, sizeof msg, "expected at least one value after '%s'", kw);
        return fail(ps, ps->p, msg);
    }
    return 0;
}

static int parse_ranges(parser *ps, node *n, const char *kw)
{
    n->r0 = ps->s->nranges;
    for (;;) {
        size_t len = token(ps);
        if (!len || !isdigit((unsigned char)*ps->p)) break;
        char *end;
        long a = strtol(ps->p, &end, 10), b = a;
        if (*end == ':') {
            const char *q = end + 1;
            if (!isdigit((unsigned char)*q)) return fail(ps, q, "expected a number after ':'");
            b = strtol(q, &end, 10);
        }
        if ((size_t)(end - ps->p) != len) return fail(ps, end, "expected N or N:M");
        if (b < a) return fail(ps, ps->p, "a range N:M needs N <= M");
        long(*r)[2] = realloc(ps->s->ranges, sizeof *r * (size_t)(ps->s->nranges + 1));
        if (!r) return fail(ps, ps->p, "out of memory");
        ps->s->ranges = r;
        r[ps->s->nranges][0] = a, r[ps->s->nranges][1] = b;
        ps->s->nranges++;
        n->nr++;
        ps->p += len;
    }
    if (!n->nr) {
        char msg[80];
        snprintf(msg, sizeof msg, "expected a number or a range N:M after '%s'", kw);
        return fail(ps, ps->p, msg);
    }
    return 0;
}

static int parse_factor(parser *ps, int depth)
{
    if (depth > 100) return fail(ps, ps->p, "nested too deeply");
    size_t len = token(ps);
    if (!len) return fail(ps, ps->p, "expected a selection");
    if (*ps->p == '(') {
        ps->p++;
        int e = parse_expr(ps, depth + 1);
        if (e < 0) return e;
        token(ps);
        if (*ps->p != ')') return fail(ps, ps->p, "expected ')'");
        ps->p++;
        return e;
    }
    if (*ps->p == ')') return fail(ps, ps->p, "unexpected ')'");
    if (is_kw(ps, "not")) {
        ps->p += 3;
        int a = parse_factor(ps, depth + 1);
        if (a < 0) return a;
        return add_node(ps, (node){.op = OP_NOT, .a = a});
    }
    static const struct { const char *kw; enum op op; int args; } kws[] = {
        {"all", OP_ALL, 0},         {"none", OP_NONE, 0},      {"protein", OP_PROTEIN, 0}, {"backbone", OP_BACKBONE, 0},
        {"water", OP_WATER, 0},     {"ion", OP_ION, 0},        {"solvent", OP_SOLVENT, 0}, {"element", OP_ELEMENT, 1},
        {"name", OP_NAME, 1},       {"resname", OP_RESNAME, 1}, {"chain", OP_CHAIN, 1},    {"segid", OP_SEGID, 1},
        {"type", OP_TYPE, 1},       {"index", OP_INDEX, 2},    {"resid", OP_RESID, 2}};
    for (size_t k = 0; k < sizeof kws / sizeof kws[0]; k++) {
        if (!is_kw(ps, kws[k].kw)) continue;
        ps->p += len;
        node n = {.op = kws[k].op};
        if (kws[k].args == 1 && parse_words(ps, &n, kws[k].kw)) return -1;
        if (kws[k].args == 2 && parse_ranges(ps, &n, kws[k].kw)) return -1;
        return add_node(ps, n);
    }
    return fail(ps, ps->p,
                "unknown keyword (known: all none protein backbone water ion solvent element name resname chain segid "
                "type index resid, and/or/not, parentheses)");
}

static int parse_binary(parser *ps, int depth, const char *kw, enum op op)
{
    int a = op == OP_AND ? parse_factor(ps, depth) : parse_binary(ps, depth, "and", OP_AND);
    while (a >= 0 && is_kw(ps, kw)) {
        ps->p += strlen(kw);
        int b = op == OP_AND ? parse_factor(ps, depth) : parse_binary(ps, depth, "and", OP_AND);
        if (b < 0) return b;
        a = add_node(ps, (node){.op = op, .a = a, .b = b});
    }
    return a;
}

static int parse_expr(parser *ps, int depth) { return parse_binary(ps, depth, "or", OP_OR); }

lc_status lci_select_parse(lc_device *dev, const char *what, const char *expr, lci_select **out)
{
    *out = NULL;
    lci_select *s = calloc(1, sizeof *s);
    if (!s) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", what);
    parser ps = {dev, what, expr, expr, s, LC_OK};
    int root = parse_expr(&ps, 0);
    if (root >= 0 && token(&ps)) {
        if (*ps.p == ')') fail(&ps, ps.p, "unexpected ')'");
        else fail(&ps, ps.p, "expected 'and', 'or' or the end");
    }
    if (ps.err != LC_OK) {
        lci_select_free(s);
        return ps.err;
    }
    s->root = root;
    *out = s;
    return LC_OK;
}

void lci_select_free(lci_select *s)
{
    if (!s) return;
    for (int i = 0; i < s->nwords; i++) free(s->words[i]);
    free(s->words);
    free(s->nodes);
    free(s->ranges);
    free(s);
}

/* ---- evaluation */

/* w equal to v, or w = "prefix*" and v starting with prefix */
static int glob(const char *w, const char *v, int fold)
{
    size_t n = strlen(w);
    if (n && w[n - 1] == '*') return fold ? !strncasecmp(w, v, n - 1) : !strncmp(w, v, n - 1);
    return fold ? !strcasecmp(w, v) : !strcmp(w, v);
}

static int word_match(const lci_select *s, const node *n, const char *v, int fold)
{
    for (int i = 0; i < n->nw; i++)
        if (glob(s->words[n->w0 + i], v, fold)) return 1;
    return 0;
}

static int range_match(const lci_select *s, const node *n, long v)
{
    for (int i = 0; i < n->nr; i++)
        if (v >= s->ranges[n->r0 + i][0] && v <= s->ranges[n->r0 + i][1]) return 1;
    return 0;
}

static int eval(const lci_select *s, int k, size_t index, const char *el, const lci_atom_attr *a, const char **missing)
{
    const node *n = &s->nodes[k];
    const char *res = a ? a->resname : NULL;
    switch (n->op) {
    case OP_ALL: return 1;
    case OP_NONE: return 0;
    case OP_NOT: return !eval(s, n->a, index, el, a, missing);
    case OP_AND: return eval(s, n->a, index, el, a, missing) && eval(s, n->b, index, el, a, missing);
    case OP_OR: return eval(s, n->a, index, el, a, missing) || eval(s, n->b, index, el, a, missing);
    case OP_INDEX: return range_match(s, n, (long)index);
    case OP_ELEMENT: return word_match(s, n, el, 1);
    default: break;
    }
    static const char *const names[] = {[OP_PROTEIN] = "protein", [OP_BACKBONE] = "backbone", [OP_WATER] = "water",
                                        [OP_ION] = "ion", [OP_SOLVENT] = "solvent", [OP_NAME] = "name",
                                        [OP_RESNAME] = "resname", [OP_CHAIN] = "chain", [OP_SEGID] = "segid",
                                        [OP_TYPE] = "type", [OP_RESID] = "resid"};
    const char *v = NULL;
    switch (n->op) {
    case OP_PROTEIN: case OP_WATER: case OP_ION: case OP_SOLVENT: case OP_RESNAME: v = res; break;
    case OP_BACKBONE: v = a && a->name && res ? a->name : NULL; break;
    case OP_NAME: v = a ? a->name : NULL; break;
    case OP_CHAIN: v = a ? a->chain : NULL; break;
    case OP_SEGID: v = a ? a->segid : NULL; break;
    case OP_TYPE: v = a ? a->type : NULL; break;
    case OP_RESID: v = a && a->has_resid ? "" : NULL; break;
    default: break;
    }
    if (!v) {
        if (!*missing) *missing = names[n->op];
        return 0;
    }
    switch (n->op) {
    case OP_PROTEIN: return lci_resname_protein(res);
    case OP_WATER: return lci_resname_water(res);
    case OP_ION: return lci_resname_ion(res);
    case OP_SOLVENT: return lci_resname_water(res) || lci_resname_ion(res);
    case OP_BACKBONE: {
        static const char *const bb[] = {"N", "CA", "C", "O", NULL};
        return lci_resname_protein(res) && in(a->name, bb);
    }
    case OP_RESNAME: case OP_NAME: case OP_TYPE: return word_match(s, n, v, 1);
    case OP_CHAIN: case OP_SEGID: return word_match(s, n, v, 0);
    case OP_RESID: return range_match(s, n, a->resid);
    default: return 0;
    }
}

int lci_select_match(const lci_select *s, size_t index, const char *element, const lci_atom_attr *a,
                     const char **missing)
{
    return eval(s, s->root, index, element ? element : "", a, missing);
}

lc_status lc_select_check(const char *expr)
{
    if (!expr) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_select_check: expr is NULL");
    lci_select *s = NULL;
    lc_status st = lci_select_parse(NULL, "select", expr, &s);
    lci_select_free(s);
    return st;
}
