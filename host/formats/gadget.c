/* GADGET snapshots, format 1 and format 2 (Springel 2005, GADGET-2 user
 * guide §6), either byte order. A snapshot is Fortran records (4-byte length
 * markers around each block, checked here); format 2 puts before each block
 * a label record of 8 bytes ("POS " and the next block's size + 8).
 *
 *   HEAD  256 bytes: int32 npart[6] @0, double mass[6] @24 (the mass table),
 *         double time @72, redshift @80, ..., int32 flag_cooling @120,
 *         int32 num_files @124, double BoxSize @128, ...
 *   POS   3 floats per particle, types 0..5 one after another (double
 *         precision when the block is twice that size)
 *   VEL, ID (read past)
 *   MASS  one per particle of the types whose mass-table entry is 0
 *   U, RHO, (NE, NH when cooling,) HSML: gas (type 0) only, when present
 *
 * Format 1 names blocks by their position in that order; format 2 by label.
 * Particle types become fields (the f-th type present and chosen is field
 * f; `fields = none`: one field); `types = 0,1` picks types; `select`
 * takes `type T...` (particle types) and `index A:B` (over the file's
 * particles, types in order). Radius: the gas
 * smoothing length (HSML) when present, else the distance to the k-th
 * nearest particle of the same type (`knn = K`, default 32, like GADGET's
 * neighbour number); `radius = R` for all; `radius_scale` scales.
 * `value = ` picks k_i: none, mass (the mass table or MASS), u, rho, hsml
 * (aliases of U, RHO, HSML), or any block by its label (format 2; format 1:
 * the standard blocks by position), `NAME:K` a component of a block of C
 * values per particle, `|NAME|` the magnitude of its rows. A block covers
 * every particle when it holds a multiple of the header's total, else the
 * gas when a multiple of the gas count (gas blocks load the gas only). A
 * multi-file snapshot (num_files > 1) is read one file at a time.
 * SPH (host/sph/sph_load.h): HSML is the support radius H (GADGET's
 * convention; `hsml_is = h` converts H = gamma h with the kernel's gamma);
 * with `kernel = ` an SPH kernel and a value A, k_i = m_i / rho_i A_i from
 * the gas masses (table or MASS) and RHO (gas only). Errors name the file
 * and the byte. With an lci_share (host/mpi/ under mpirun) each block is
 * read from the share's first row on, after scan's checks of every size. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/binfile.h"
#include "host/formats/plist.h"
#include "host/sph/sph_kernel.h"
#include "host/sph/sph_load.h"

#define G_MAX_PARTICLES ((int64_t)INT32_MAX / 2)
#define G_MAX_BLOCKS 64

typedef struct gblock {
    char name[5];
    int64_t at, off, len; /* record start, data offset, data bytes */
} gblock;

typedef struct gsnap {
    lci_bin b;
    int format; /* 1 or 2 */
    int64_t npart[6], ntot, nmass, wide; /* wide: 8-byte floats */
    double mass[6];
    int cooling, num_files;
    gblock blk[G_MAX_BLOCKS];
    int nblk;
} gsnap;

enum { V_NONE, V_MASS, V_BLOCK };
/* the aliases of value = and their blocks */
static const char *const aliases[][2] = {{"u", "U"}, {"rho", "RHO"}, {"hsml", "HSML"}, {"mass", "MASS"}};

static const gblock *block(const gsnap *g, const char *name)
{
    for (int i = 0; i < g->nblk; i++)
        if (!memcmp(g->blk[i].name, name, 4)) return &g->blk[i];
    return NULL;
}

/* Positional names of format-1 blocks after the header. */
static void name_f1(gsnap *g, int i, char *out)
{
    const char *order[10];
    int n = 0;
    order[n++] = "POS ", order[n++] = "VEL ", order[n++] = "ID  ";
    if (g->nmass > 0) order[n++] = "MASS";
    if (g->npart[0] > 0) {
        order[n++] = "U   ", order[n++] = "RHO ";
        if (g->cooling) order[n++] = "NE  ", order[n++] = "NH  ";
        order[n++] = "HSML";
    }
    memcpy(out, i - 1 < n ? order[i - 1] : "?   ", 5);
}

static lc_status scan(lc_device *dev, const char *path, gsnap *g)
{
    memset(g, 0, sizeof *g);
    lc_status s = lci_bin_open(dev, path, "GADGET snapshots", &g->b);
    if (s != LC_OK) return s;
    lci_bin *b = &g->b;
    unsigned char m[4];
    if ((s = lci_bin_read(b, 0, m, 4, "the first record marker")) != LC_OK) return s;
    int little = 1;
    little = *(unsigned char *)&little;
    int32_t le = (int32_t)((uint32_t)m[0] | (uint32_t)m[1] << 8 | (uint32_t)m[2] << 16 | (uint32_t)m[3] << 24);
    int32_t be = (int32_t)((uint32_t)m[3] | (uint32_t)m[2] << 8 | (uint32_t)m[1] << 16 | (uint32_t)m[0] << 24);
    if (le == 256 || le == 8) g->format = le == 256 ? 1 : 2, b->swap = !little;
    else if (be == 256 || be == 8) g->format = be == 256 ? 1 : 2, b->swap = little;
    else
        return lci_error(dev, LC_ERROR_FORMAT,
                         "%s: byte 0: not a GADGET snapshot: the first record marker is %d, expected 256 (format 1) or "
                         "8 (format 2) in either byte order",
                         path, le);
    int64_t off = 0, len, next;
    for (int i = 0; off < b->size; i++) {
        if (g->nblk == G_MAX_BLOCKS)
            return lci_error(dev, LC_ERROR_FORMAT, "%s: byte %lld: more than %d blocks", path, (long long)off, G_MAX_BLOCKS);
        gblock *k = &g->blk[g->nblk];
        if (g->format == 2) {
            unsigned char lab[8];
            if ((s = lci_bin_record(b, off, 8, "a block label (format 2)", &len, &next)) != LC_OK ||
                (s = lci_bin_read(b, off + 4, lab, 8, "a block label")) != LC_OK)
                return s;
            memcpy(k->name, lab, 4);
            k->name[4] = 0;
            int64_t said = lci_bin_i32(b, lab + 4);
            off = next;
            char what[48];
            snprintf(what, sizeof what, "block %s", k->name);
            if ((s = lci_bin_record(b, off, i == 0 ? 256 : -1, what, &len, &next)) != LC_OK) return s;
            if (said != len + 8)
                return lci_error(dev, LC_ERROR_FORMAT, "%s: byte %lld: the label of block %s says %lld bytes follow, "
                                 "the block holds %lld + 8", path, (long long)(off - 8), k->name, (long long)said,
                                 (long long)len);
        } else {
            if (i == 0) memcpy(k->name, "HEAD", 5);
            else name_f1(g, i, k->name);
            char what[48];
            snprintf(what, sizeof what, "block %d (%s)", i + 1, k->name);
            if ((s = lci_bin_record(b, off, i == 0 ? 256 : -1, what, &len, &next)) != LC_OK) return s;
        }
        k->at = off, k->off = off + 4, k->len = len;
        g->nblk++;
        off = next;
        if (i == 0) { /* the header */
            unsigned char h[256];
            if (g->format == 2 && memcmp(k->name, "HEAD", 4))
                return lci_error(dev, LC_ERROR_FORMAT, "%s: byte 0: the first block is '%s', expected HEAD", path, k->name);
            if (len != 256)
                return lci_error(dev, LC_ERROR_FORMAT, "%s: byte %lld: a header of %lld bytes, expected 256", path,
                                 (long long)k->at, (long long)len);
            if ((s = lci_bin_read(b, k->off, h, 256, "the header")) != LC_OK) return s;
            for (int t = 0; t < 6; t++) {
                g->npart[t] = lci_bin_i32(b, h + 4 * t);
                g->mass[t] = lci_bin_f64(b, h + 24 + 8 * t);
                if (g->npart[t] < 0 || g->npart[t] > G_MAX_PARTICLES || !isfinite(g->mass[t]) || g->mass[t] < 0.0)
                    return lci_error(dev, LC_ERROR_FORMAT,
                                     "%s: byte %lld: type %d: %lld particles of mass %g; expected 0 to %lld and a mass >= 0",
                                     path, (long long)(k->off + 4 * t), t, (long long)g->npart[t], g->mass[t],
                                     (long long)G_MAX_PARTICLES);
                g->ntot += g->npart[t];
                if (g->mass[t] == 0.0) g->nmass += g->npart[t];
            }
            g->cooling = lci_bin_i32(b, h + 120) != 0;
            g->num_files = lci_bin_i32(b, h + 124);
            if (g->ntot > G_MAX_PARTICLES || g->ntot * 12 > b->size)
                return lci_error(dev, LC_ERROR_FORMAT,
                                 "%s: byte %lld: the header counts %lld particles, more than a %lld-byte file holds",
                                 path, (long long)k->off, (long long)g->ntot, (long long)b->size);
        }
    }
    const gblock *pos = block(g, "POS ");
    if (!pos)
        return lci_error(dev, LC_ERROR_FORMAT, "%s: byte %lld: no POS block after the header", path,
                         (long long)(g->nblk > 1 ? g->blk[1].at : b->size));
    if (pos->len != 12 * g->ntot && pos->len != 24 * g->ntot)
        return lci_error(dev, LC_ERROR_FORMAT,
                         "%s: byte %lld: a POS block of %lld bytes, but the header's %lld particles need %lld (float) or "
                         "%lld (double)",
                         path, (long long)pos->at, (long long)pos->len, (long long)g->ntot, (long long)(12 * g->ntot),
                         (long long)(24 * g->ntot));
    g->wide = pos->len == 24 * g->ntot && g->ntot > 0;
    /* the blocks this reader uses must have the header's sizes */
    static const char *const per[] = {"MASS", "U   ", "RHO ", "HSML"};
    for (int i = 0; i < 4; i++) {
        const gblock *k = block(g, per[i]);
        int64_t n = i == 0 ? g->nmass : g->npart[0];
        int64_t w = g->wide ? 8 : 4;
        if (k && k->len != n * w)
            return lci_error(dev, LC_ERROR_FORMAT, "%s: byte %lld: a %.4s block of %lld bytes, expected %lld (%lld %s x %lld)",
                             path, (long long)k->at, k->name, (long long)k->len, (long long)(n * w), (long long)n,
                             i == 0 ? "particles without a mass-table entry" : "gas particles", (long long)w);
    }
    return LC_OK;
}

/* Reads n reals of block k starting at element `first` into out (float). */
static lc_status reals(gsnap *g, const gblock *k, int64_t first, int64_t n, float *out)
{
    int64_t w = g->wide ? 8 : 4;
    char what[48];
    snprintf(what, sizeof what, "block %.4s", k->name);
    if (!g->wide) {
        lc_status s = lci_bin_read(&g->b, k->off + first * w, out, (size_t)(n * w), what);
        lci_bin_fix(&g->b, out, (size_t)n, 4);
        return s;
    }
    double buf[1024];
    for (int64_t i = 0; i < n; i += 1024) {
        int64_t m = n - i < 1024 ? n - i : 1024;
        lc_status s = lci_bin_read(&g->b, k->off + (first + i) * w, buf, (size_t)(m * w), what);
        if (s != LC_OK) return s;
        lci_bin_fix(&g->b, buf, (size_t)m, 8);
        for (int64_t j = 0; j < m; j++) out[i + j] = (float)buf[j];
    }
    return LC_OK;
}

/* Whom block k covers: 0 every particle (types in order), 1 the gas, with
 * *c values per particle; -1 when neither count divides its size. */
static int coverage(const gsnap *g, const gblock *k, int64_t *c)
{
    int64_t w = g->wide ? 8 : 4, vals = k->len / w;
    if (!memcmp(k->name, "MASS", 4)) return *c = 1, g->nmass == g->ntot ? 0 : 2;
    if (k->len % w || vals == 0) return -1;
    if (g->ntot > 0 && vals % g->ntot == 0) return *c = vals / g->ntot, 0;
    if (g->npart[0] > 0 && vals % g->npart[0] == 0) return *c = vals / g->npart[0], 1;
    return -1;
}

/* lanecast info: the snapshot's per-particle blocks. */
static lc_status gadget_describe(lc_device *dev, const lci_read_args *a, char *text, size_t size)
{
    gsnap g;
    lc_status s = scan(dev, a->path, &g);
    lci_bin_close(&g.b);
    if (s != LC_OK) return s;
    size_t n = (size_t)snprintf(text, size, "blocks        format %d (%s):", g.format,
                                g.format == 2 ? "by label" : "the standard blocks by position");
    for (int i = 1; i < g.nblk && n < size; i++) {
        const gblock *k = &g.blk[i];
        char name[5];
        memcpy(name, k->name, 5);
        for (int j = 3; j >= 0 && name[j] == ' '; j--) name[j] = 0;
        int64_t c = 1;
        int cov = coverage(&g, k, &c);
        const char *who = cov == 0 ? "all" : cov == 1 ? "gas" : cov == 2 ? "no mass-table entry" : "size unmatched";
        if (cov < 0) n += (size_t)snprintf(text + n, size - n, " %s (%s)", name, who);
        else n += (size_t)snprintf(text + n, size - n, " %s (%s x %lld)", name, who, (long long)c);
    }
    if (n < size) snprintf(text + n, size - n, "\n");
    return LC_OK;
}

typedef struct gopts {
    int types[6], types_given, by_type, value, knn;
    char label[5];     /* value = a block: its label, padded with spaces */
    lci_value_spec vs; /* and the component */
    const char *vtext; /* the option as given (messages) */
    float radius, radius_scale;
    lci_psel sel;
    lci_sph_opts sph;
} gopts;

static lc_status parse_opts(lc_device *dev, const lci_read_args *a, gopts *o)
{
    memset(o, 0, sizeof *o);
    o->by_type = 1;
    o->knn = 32;
    const lc_option *x;
    lc_status s = LC_OK;
    if ((x = lci_option_find(a, "radius"))) s = lci_option_float(dev, a->path, x, 1e-30f, 1e30f, &o->radius);
    if (s == LC_OK && (x = lci_option_find(a, "radius_scale")))
        s = lci_option_float(dev, a->path, x, 1e-30f, 1e30f, &o->radius_scale);
    if (s == LC_OK && (x = lci_option_find(a, "knn"))) s = lci_option_int(dev, a->path, x, 1, 1024, &o->knn);
    if (s == LC_OK && (x = lci_option_find(a, "fields"))) {
        lci_field_by by;
        const char *c;
        if (!strcmp(x->value, "none")) o->by_type = 0;
        else if (strcmp(x->value, "type") && lci_field_by_parse(x->value, &by, &c) == 0)
            s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: fields by %s: gadget files give only particle types "
                          "(fields = type or none)", a->path, x->value);
        else if (strcmp(x->value, "type"))
            s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: option fields = '%s', expected type or none", a->path,
                          x->value);
    }
    o->vtext = "none";
    if (s == LC_OK && (x = lci_option_find(a, "value")) && strcmp(x->value, "none")) {
        o->vtext = x->value;
        const char *name = x->value;
        for (size_t i = 0; i < sizeof aliases / sizeof aliases[0]; i++)
            if (!strcmp(name, aliases[i][0])) name = aliases[i][1];
        if (lci_value_spec_parse(name, &o->vs) || strlen(o->vs.name) > 4 || strchr(o->vs.name, ' ') != NULL)
            s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                          "%s: option value = '%s', expected none, mass, u, rho, hsml or a block label of 1-4 "
                          "characters (e.g. TEMP), NAME:K (component K) or |NAME| (the magnitude)", a->path, x->value);
        snprintf(o->label, sizeof o->label, "%-4s", o->vs.name);
        o->value = !strcmp(o->label, "MASS") && o->vs.comp == -1 ? V_MASS : V_BLOCK;
    }
    if (s == LC_OK && (x = lci_option_find(a, "types"))) {
        o->types_given = 1;
        const char *p = x->value;
        for (;;) {
            if (*p < '0' || *p > '5' || (p[1] && p[1] != ',')) {
                s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                              "%s: option types = '%s': expected particle types 0 to 5, comma-separated", a->path,
                              x->value);
                break;
            }
            o->types[*p - '0'] = 1;
            if (!p[1]) break;
            p += 2;
        }
    }
    if (!o->types_given)
        for (int t = 0; t < 6; t++) o->types[t] = 1;
    if (s == LC_OK) s = lci_sph_opts_parse(dev, a, &o->sph);
    if (s == LC_OK) s = lci_psel_open(dev, a, &o->sel);
    return s;
}

/* A share's rows (lci_share) of the chosen particles (types in order): the
 * total and [a, b) of it, or in sh->whole why the set is needed whole
 * (then no rows). scan() has checked every block's size against the
 * header's counts, so the share's offsets are inside the blocks. */
static void share_plan(const gsnap *g, const gopts *o, int64_t chosen, lci_share *sh)
{
    if (o->sel.sel) sh->whole = "a selection (select = ...) over the whole file's indices";
    for (int t = 0; t < 6; t++)
        if (o->types[t] && g->npart[t] > 0 && !(o->radius > 0.0f) && !(t == 0 && block(g, "HSML")))
            sh->whole = "k-nearest-neighbour radii (particles without HSML and no radius option)";
    sh->total = (size_t)chosen;
    sh->a = (size_t)((uint64_t)chosen * (uint64_t)sh->rank / (uint64_t)sh->parts);
    sh->b = (size_t)((uint64_t)chosen * (uint64_t)(sh->rank + 1) / (uint64_t)sh->parts);
    if (sh->whole) sh->a = sh->b = 0;
    sh->offset = 0;
}

static lc_status gadget_read(lc_device *dev, const lci_read_args *a, lci_loaded *out)
{
    lci_share *sh = lci_read_share(dev);
    gopts o;
    lc_status s = parse_opts(dev, a, &o);
    if (s != LC_OK) return s;
    gsnap g;
    lci_plist p;
    memset(&p, 0, sizeof p);
    int nfields = 0;
    const int weighted = lci_sph_weighted(&o.sph, o.value != V_NONE);
    float *wn = NULL; /* normalise: the m_i / rho_i, as the particles */
    const char *gwhy = "";
    lc_kernel gk = lci_sph_gamma_kernel(&o.sph, LC_KERNEL_GAUSSIAN, &gwhy);
    const double gamma = o.sph.hsml_is == LCI_HSML_SMALL_H ? lci_sph_kernel_get(gk)->swift_gamma : 1.0;
    if ((s = scan(dev, a->path, &g)) != LC_OK) goto out;
    if (o.sph.normalise && !weighted) {
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: normalise = 1 is the normalised SPH interpolant: it needs an "
                      "SPH kernel (kernel = m4, ...) and the quantity interpolated (value = A)", a->path);
        goto out;
    }
    const gblock *vb = o.value != V_NONE ? block(&g, o.label) : NULL;
    int64_t vc = 1; /* values per particle of block vb */
    int vcov = vb ? coverage(&g, vb, &vc) : 0;
    if (o.value == V_BLOCK && !vb) {
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: value = %s, but the snapshot has no %.4s block (%s; lanecast info "
                      "lists its blocks)", a->path, o.vtext, o.label, g.npart[0] ? "gas present" : "no gas particles");
        goto out;
    }
    if (o.value == V_BLOCK && !memcmp(o.label, "ID  ", 4)) {
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: value = %s: block ID holds integer particle ids, not a "
                      "quantity", a->path, o.vtext);
        goto out;
    }
    if (o.value == V_BLOCK && (vcov < 0 || vcov == 2)) {
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: byte %lld: value = %s: block %.4s holds %lld bytes, a multiple of "
                      "neither the %lld particles nor the %lld gas particles (x %d bytes)", a->path, (long long)vb->at,
                      o.vtext, o.label, (long long)vb->len, (long long)g.ntot, (long long)g.npart[0], g.wide ? 8 : 4);
        goto out;
    }
    if (o.value == V_BLOCK && ((vc > 1 && o.vs.comp == -1) || (vc == 1 && o.vs.comp != -1) || o.vs.comp >= vc)) {
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                      "%s: value = %s: block %.4s holds %lld value%s per particle%s", a->path, o.vtext, o.label,
                      (long long)vc, vc > 1 ? "s" : "", vc > 1 ? "; name a component NAME:0.. or the magnitude |NAME|"
                      : " (no components)");
        goto out;
    }
    const int gas_only = o.value == V_BLOCK && vcov == 1;
    if (gas_only || weighted) { /* gas quantities and SPH interpolation: the gas only */
        for (int t = 1; t < 6; t++)
            if (o.types_given && o.types[t] && g.npart[t] > 0) {
                s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                              "%s: value = %s is a gas quantity%s, but types = includes type %d (%lld particles); use "
                              "types = 0",
                              a->path, o.vtext, weighted && !gas_only ? " (SPH interpolation)" : "", t,
                              (long long)g.npart[t]);
                goto out;
            }
        for (int t = 1; t < 6; t++) o.types[t] = 0;
    }
    if (o.value == V_MASS && g.nmass > 0 && !vb) {
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: value = mass, but the mass table leaves %lld particles without a mass "
                      "and there is no MASS block", a->path, (long long)g.nmass);
        goto out;
    }
    const gblock *rhob = block(&g, "RHO "), *massb = block(&g, "MASS");
    if (weighted && (!rhob || (g.mass[0] == 0.0 && g.npart[0] > 0 && !massb))) {
        s = lci_error(dev, LC_ERROR_FORMAT,
                      "%s: value = %s with kernel %s is SPH interpolation (k = m / rho * %s), but the snapshot has no %s",
                      a->path, o.vtext, lc_kernel_name(o.sph.kernel), o.vtext,
                      !rhob ? "RHO block (gas densities)" : "gas masses (mass table entry 0 and no MASS block)");
        goto out;
    }
    const gblock *pos = block(&g, "POS "), *hsml = block(&g, "HSML");
    int64_t first = 0, mfirst = 0, chosen = 0;
    for (int t = 0; t < 6; t++) chosen += o.types[t] ? g.npart[t] : 0;
    if (chosen == 0) {
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: no particles of the chosen types (the header counts %lld %lld %lld %lld "
                      "%lld %lld of types 0-5)", a->path, (long long)g.npart[0], (long long)g.npart[1],
                      (long long)g.npart[2], (long long)g.npart[3], (long long)g.npart[4], (long long)g.npart[5]);
        goto out;
    }
    if (sh) share_plan(&g, &o, chosen, sh);
    const int64_t held = sh ? (int64_t)(sh->b - sh->a) + 1 : chosen; /* the particles this read returns, at most */
    if (o.sph.normalise && !(wn = malloc(sizeof(float) * (size_t)held))) {
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %lld weights", a->path, (long long)held);
        goto out;
    }
    if (lci_plist_reserve(&p, (size_t)held)) {
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %lld particles", a->path, (long long)held);
        goto out;
    }
    int64_t cfirst = 0; /* the chosen particles before type t (a share's index) */
    for (int t = 0; t < 6; first += g.npart[t], mfirst += g.mass[t] == 0.0 ? g.npart[t] : 0, t++) {
        int64_t whole_n = g.npart[t];
        if (!o.types[t] || whole_n == 0) continue;
        /* the rows read: all, or the share's [a, b) of the chosen particles' order in this type */
        int64_t lo = 0, n = whole_n;
        if (sh) {
            int64_t sa = (int64_t)sh->a - cfirst, sb = (int64_t)sh->b - cfirst;
            lo = sa < 0 ? 0 : sa > whole_n ? whole_n : sa, n = (sb < 0 ? 0 : sb > whole_n ? whole_n : sb) - lo;
            sh->offset += (size_t)lo;
        }
        cfirst += whole_n;
        size_t base = p.n;
        float *x = p.xyz + 3 * base, *r = p.r + base, *v = p.v + base;
        if ((s = reals(&g, pos, 3 * (first + lo), 3 * n, x)) != LC_OK) goto out;
        for (int64_t i = 0; i < 3 * n; i++)
            if (!isfinite(x[i])) {
                s = lci_error(dev, LC_ERROR_FORMAT, "%s: byte %lld: particle %lld (type %d) has a non-finite position",
                              a->path, (long long)(pos->off + (3 * (first + lo) + i) * (g.wide ? 8 : 4)),
                              (long long)(first + lo + i / 3), t);
                goto out;
            }
        /* radii */
        if (o.radius > 0.0f) {
            for (int64_t i = 0; i < n; i++) r[i] = o.radius;
        } else if (t == 0 && hsml) {
            if ((s = reals(&g, hsml, lo, n, r)) != LC_OK) goto out;
            for (int64_t i = 0; gamma != 1.0 && i < n; i++) r[i] = (float)(gamma * (double)r[i]);
            for (int64_t i = 0; sh && i < n; i++) /* replaced by the type's smallest: the whole type's */
                if (!(r[i] > 0.0f) || !isfinite(r[i])) sh->whole = "an HSML <= 0 (replaced by its type's smallest)";
        } else {
            if (lci_knn_radii(x, (size_t)n, o.knn, r)) {
                s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for the neighbour search", a->path);
                goto out;
            }
        }
        float rmin = INFINITY;
        for (int64_t i = 0; i < n; i++)
            if (r[i] > 0.0f && r[i] < rmin) rmin = r[i];
        for (int64_t i = 0; i < n; i++) {
            if (!(r[i] > 0.0f) || !isfinite(r[i])) r[i] = isfinite(rmin) ? rmin : 1.0f; /* coincident points */
            if (o.radius_scale > 0.0f) r[i] *= o.radius_scale;
        }
        /* values */
        if (o.value == V_MASS && g.mass[t] == 0.0) {
            if ((s = reals(&g, vb, mfirst + lo, n, v)) != LC_OK) goto out;
        } else if (o.value == V_MASS) {
            for (int64_t i = 0; i < n; i++) v[i] = (float)g.mass[t];
        } else if (o.value != V_NONE) {
            float *row = vc > 1 ? malloc(sizeof(float) * (size_t)(n * vc + 1)) : v;
            if (!row) {
                s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for block %.4s", a->path, o.label);
                goto out;
            }
            s = reals(&g, vb, ((gas_only ? 0 : first) + lo) * vc, n * vc, row);
            if (s == LC_OK) lci_value_spec_reduce(&o.vs, row, n, (int)vc, v);
            if (row != v) free(row);
            if (s != LC_OK) goto out;
        } else {
            for (int64_t i = 0; i < n; i++) v[i] = 1.0f;
        }
        if (weighted) { /* t == 0: k_i = m_i / rho_i A_i */
            float *m = NULL, *rho = malloc(sizeof(float) * ((size_t)n * 2 + 1));
            if (!rho) {
                s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %lld densities", a->path, (long long)n);
                goto out;
            }
            if (g.mass[0] == 0.0) m = rho + n, s = reals(&g, massb, lo, n, m);
            if (s == LC_OK) s = reals(&g, rhob, lo, n, rho);
            if (s == LC_OK) s = lci_sph_weigh(dev, a->path, "block RHO", lo, n, m, g.mass[0], rho, v);
            if (s == LC_OK && wn) lci_sph_norm_weights(n, m, g.mass[0], rho, wn + base);
            free(rho);
            if (s != LC_OK) goto out;
        }
        for (int64_t i = 0; i < n; i++) p.f[base + (size_t)i] = (uint8_t)(o.by_type ? nfields : 0);
        if (o.sel.sel) { /* select: type = the particle type, index over the file's particles */
            char ty[2] = {(char)('0' + t), 0};
            lci_atom_attr attr = {.type = ty};
            size_t w = base;
            for (int64_t i = 0; i < n; i++) {
                size_t q = base + (size_t)i;
                if (!lci_psel_keep(&o.sel, (size_t)(first + i), NULL, &attr)) continue;
                memmove(p.xyz + 3 * w, p.xyz + 3 * q, 3 * sizeof(float));
                p.r[w] = p.r[q], p.v[w] = p.v[q], p.f[w] = p.f[q];
                if (wn) wn[w] = wn[q];
                w++;
            }
            n = (int64_t)(w - base);
            if (n == 0) continue; /* no field for a type the selection left empty */
        }
        p.n += (size_t)n; /* a share's type keeps its field when the share holds none of it */
        nfields++;
    }
    if (g.num_files > 1)
        lci_log(dev, LC_LOG_INFO, "%s: one file of a %d-file snapshot (its own particles only)", a->path, g.num_files);
out:
    /* a share that needs the whole set read no rows: rank 0's whole read checks what the selection kept */
    s = lci_psel_close(dev, a, &o.sel, sh && sh->whole ? 1 : p.n, s);
    lci_bin_close(&g.b);
    int had_hsml = s == LC_OK && o.radius <= 0.0f && o.types[0] && g.npart[0] > 0 && block(&g, "HSML");
    s = lci_plist_finish(dev, a->path, s, &p, o.by_type ? nfields : 1, o.value != V_NONE, out);
    if (s == LC_OK) lci_sph_keep_norm(out, wn);
    else free(wn);
    if (s == LC_OK && had_hsml) {
        if (o.sph.hsml_is == LCI_HSML_SMALL_H)
            lci_sph_note(out, "gas H = %.6g HSML (hsml_is = h: H = gamma h with %s gamma, %s)", gamma,
                         lc_kernel_name(gk), gwhy);
        else
            lci_sph_note(out, "gas H = HSML (GADGET's HSML is the support radius%s)",
                         o.sph.hsml_is == LCI_HSML_BIG_H ? "; hsml_is = H" : "");
    }
    if (s == LC_OK && weighted)
        lci_sph_note(out, "%s; k = m / rho * %s (SPH interpolation with %s)",
                     ((lc_particles_desc *)out->desc)->radius_note ? ((lc_particles_desc *)out->desc)->radius_note
                                                                   : "radii as read",
                     o.vtext, lc_kernel_name(o.sph.kernel));
    return s;
}

static int gadget_magic(const unsigned char *h, size_t n)
{
    static const unsigned char f1le[4] = {0, 1, 0, 0}, f1be[4] = {0, 0, 1, 0};
    static const unsigned char f2le[4] = {8, 0, 0, 0}, f2be[4] = {0, 0, 0, 8};
    if (n >= 264 && ((!memcmp(h, f1le, 4) && !memcmp(h + 260, f1le, 4)) || (!memcmp(h, f1be, 4) && !memcmp(h + 260, f1be, 4))))
        return 1;
    return n >= 20 && (!memcmp(h, f2le, 4) || !memcmp(h, f2be, 4)) && !memcmp(h + 4, "HEAD", 4) &&
           !memcmp(h + 12, h, 4);
}

const lci_format lci_format_gadget = {
    .name = "gadget", .kind = LC_KIND_PARTICLES, .extensions = ".gadget .g2",
    .options = "radius radius_scale fields value types knn select kernel hsml_is normalise",
    .description = "GADGET-1/2 snapshot, format 1 or 2, either byte order: types as fields, radius = HSML or the k-th "
                   "neighbour distance, value = none|mass|u|rho|hsml or any block (LABEL, LABEL:K, |LABEL|)",
    .magic = gadget_magic, .read = gadget_read, .describe = gadget_describe, .shares = 1};
