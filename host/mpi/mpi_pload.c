/* lc_mpi_volume_load of particle sets (dp.h "Particle parts"): every rank
 * gets a share of the particles (raw float32 files, and HDF5 and GADGET
 * snapshots whose quantities are all per particle: rows [a, b) read by the
 * rank itself, lci_read_volume_share; other formats, and loads that need
 * the whole set such as k-nearest-neighbour radii: read by rank 0, which
 * holds them all),
 * the ranks reduce the share's bounds and radii, build the kd-tree balanced
 * by particle count with a distributed selection of each split
 * (lci_kd_build_dist: the same floats as one process's sort), and one
 * MPI_Alltoallv sends every particle to each rank whose region its support
 * (grown by two steps) reaches: its owner and the ranks it is a ghost of.
 * Each rank's part is a particle volume whose bounds, radii and value range
 * are the whole set's (lci_particles_set_global). Every step ends in an
 * agreement (lc_mpi_agree). */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/format.h"
#include "host/mpi/mpi_internal.h"
#include "lanecast/lanecast_mpi.h"

/* A rank's particles as arrays of their own (SoA; field ids as bytes). */
typedef struct share {
    size_t n;
    float *x, *y, *z, *r, *k;
    float *w;      /* the norm weights m_i / rho_i of --normalise, or NULL */
    uint8_t *f;
    size_t offset; /* its first particle's index in the file */
} share;

/* What every rank needs of the desc rank 0 read. */
typedef struct shape {
    float radius;
    int nfields, leaf_size, drop_invalid;
    int has_w; /* the particles carry norm weights */
    lc_particle_params params;
    char note[256];
} shape;

static void share_free(share *s)
{
    free(s->x), free(s->y), free(s->z), free(s->r), free(s->k), free(s->w), free(s->f);
    memset(s, 0, sizeof *s);
}

static int share_alloc(share *s, size_t n, int has_w)
{
    size_t m = n ? n : 1;
    s->x = malloc(4 * m), s->y = malloc(4 * m), s->z = malloc(4 * m), s->r = malloc(4 * m), s->k = malloc(4 * m);
    s->w = has_w ? malloc(4 * m) : NULL;
    s->f = malloc(m);
    s->n = n;
    return s->x && s->y && s->z && s->r && s->k && s->f && (!has_w || s->w) ? 0 : -1;
}

static lc_status sum_u64(void *user, uint64_t *v, int n)
{
    MPI_Comm *c = user;
    return MPI_Allreduce(MPI_IN_PLACE, v, n, MPI_UINT64_T, MPI_SUM, *c) == MPI_SUCCESS ? LC_OK : LC_ERROR_INTERNAL;
}

static lc_status agree_comm(lc_device *dev, void *user, lc_status s) { return lc_mpi_agree(dev, *(MPI_Comm *)user, s); }

const lci_kd_peers *lci_mpi_kd_peers(MPI_Comm *comm, lci_kd_peers *p)
{
    p->sum = sum_u64, p->agree = agree_comm, p->user = comm;
    return p;
}

/* ---------------------------------------------------------------- reading a share */

/* Raw float32 triples read as rows [a, b) by each rank, when the options
 * are the ones this path knows (else 0: rank 0 reads the file). */
static int raw_plain(const char *path, const char *format, const lc_load_desc *ld)
{
    if (strcmp(format, "raw-particles") || ld->frame != 0) return 0;
    int count = 0, radius = 0;
    for (int i = 0; i < ld->noptions; i++) {
        const char *k = ld->options[i].key;
        if (!k || !ld->options[i].value) return 0;
        count |= !strcmp(k, "count"), radius |= !strcmp(k, "radius");
        if (strcmp(k, "count") && strcmp(k, "radius") && strcmp(k, "leaf_size") && strcmp(k, "drop_invalid") &&
            strcmp(k, "kernel") && strcmp(k, "max_memory") && strcmp(k, "canonical_order"))
            return 0;
    }
    FILE *f = fopen(path, "rb");
    unsigned char m[2] = {0, 0};
    int gz = f && fread(m, 1, 2, f) == 2 && m[0] == 0x1f && m[1] == 0x8b;
    if (f) fclose(f);
    return f && !gz && count && radius; /* errors of every other kind: the reader's messages */
}

static lc_status raw_share(lc_device *dev, const char *path, const lc_load_desc *ld, int rank, int P, share *sh,
                           shape *sp)
{
    size_t count = 0;
    float radius = 0.0f;
    lc_particles_desc d;
    memset(&d, 0, sizeof d);
    lc_status s = LC_OK;
    for (int i = 0; i < ld->noptions && s == LC_OK; i++) {
        const lc_option *o = &ld->options[i];
        if (!strcmp(o->key, "count")) s = lci_option_size(dev, path, o, (size_t)INT32_MAX / 2, &count);
        else if (!strcmp(o->key, "radius")) s = lci_option_float(dev, path, o, 1e-30f, 1e30f, &radius);
        else if (strcmp(o->key, "max_memory")) s = lci_particles_ops.set_option(dev, &d, o, path);
    }
    if (s == LC_OK && count == 0) s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: raw particles need a count", path);
    if (s != LC_OK) return s;
    sp->radius = radius, sp->nfields = 1, sp->leaf_size = d.leaf_size, sp->drop_invalid = d.drop_invalid;
    sp->params = d.params;
    size_t a = (size_t)((uint64_t)count * (uint64_t)rank / (uint64_t)P);
    size_t b = (size_t)((uint64_t)count * (uint64_t)(rank + 1) / (uint64_t)P);
    sh->offset = a;
    if (share_alloc(sh, b - a, 0) != 0)
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %zu particles", path, b - a);
    FILE *f = fopen(path, "rb");
    if (!f) return lci_error(dev, LC_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    float buf[3 * 1024];
    if (fseeko(f, (off_t)(12 * (uint64_t)a), SEEK_SET) != 0) s = LC_ERROR_IO;
    for (size_t i = a; i < b && s == LC_OK; i += 1024) {
        size_t n = b - i < 1024 ? b - i : 1024;
        if (fread(buf, 12, n, f) != n) {
            s = LC_ERROR_IO;
            break;
        }
        for (size_t j = 0; j < n; j++) {
            size_t o = i - a + j;
            sh->x[o] = buf[3 * j], sh->y[o] = buf[3 * j + 1], sh->z[o] = buf[3 * j + 2];
            sh->r[o] = radius, sh->k[o] = 1.0f, sh->f[o] = 0;
        }
    }
    char extra;
    if (s == LC_OK && b == count && fread(&extra, 1, 1, f) == 1)
        s = lci_error(dev, LC_ERROR_FORMAT, "%s: longer than %zu particles x 12 bytes; wrong count?", path, count);
    else if (s == LC_ERROR_IO) {
        fseeko(f, 0, SEEK_END);
        long long size = (long long)ftello(f);
        s = lci_error(dev, LC_ERROR_FORMAT,
                      "%s: holds %lld bytes, but particles %zu .. %zu of a count of %zu need %llu (12 bytes each); "
                      "truncated or wrong count?",
                      path, size, a, b - 1, count, (unsigned long long)(12 * (uint64_t)b));
    }
    fclose(f);
    return s;
}

/* The particles the format's reader returns: the whole file (part NULL:
 * rank 0) or the share *part (every rank). The test fault "whole" fails the
 * whole read (tests: a load that must be by shares never reads whole). */
static lc_status read_share(lc_device *dev, const char *path, const lc_load_desc *ld, lci_share *part, share *sh,
                            shape *sp)
{
    lci_loaded l;
    lc_kind kind;
    const char *fmt;
    if (!part && lci_test_fault("whole"))
        return lci_error(dev, LC_ERROR_IO, "%s: test fault 'whole': the whole file read by one rank", path);
    lc_status s = lci_read_volume_share(dev, path, ld, part, &kind, &fmt, &l);
    if (s != LC_OK) return s;
    if (part) sh->offset = part->offset;
    const lc_particles_desc *d = l.desc;
    if (kind != LC_KIND_PARTICLES) s = lci_error(dev, LC_ERROR_INTERNAL, "%s: not a particle set", path);
    if (s == LC_OK && d->count > 0 && !d->positions)
        s = lci_error(dev, LC_ERROR_INTERNAL, "%s: %zu particles without positions", path, d->count);
    if (s == LC_OK && share_alloc(sh, d->count, d->norm_weights != NULL) != 0)
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %zu particles", path, d->count);
    for (size_t i = 0; s == LC_OK && i < d->count; i++) {
        sh->x[i] = d->positions[3 * i], sh->y[i] = d->positions[3 * i + 1], sh->z[i] = d->positions[3 * i + 2];
        /* an invalid radius or value stays as it is for the check */
        sh->r[i] = d->radii ? d->radii[i] : d->radius;
        sh->k[i] = d->values ? d->values[i] : 1.0f;
        if (sh->w) sh->w[i] = d->norm_weights[i];
        sh->f[i] = d->fields ? d->fields[i] : 0;
    }
    if (s == LC_OK) {
        sp->radius = d->radius, sp->nfields = d->nfields, sp->leaf_size = d->leaf_size;
        sp->drop_invalid = d->drop_invalid, sp->params = d->params, sp->has_w = d->norm_weights != NULL;
        if (d->radius_note) snprintf(sp->note, sizeof sp->note, "%s", d->radius_note);
    }
    lci_loaded_free(&l);
    return s;
}

/* HDF5 and GADGET snapshots: each rank reads its share (lci_share) unless
 * some rank's says the load needs the whole set; then rank 0 reads it
 * (the reason logged). 1 when the shares were read. Collective. */
static int by_shares(lc_device *dev, MPI_Comm comm, const char *path, const lc_load_desc *ld, share *sh, shape *sp,
                     lc_status *s, char *why, size_t whylen)
{
    int rank, P;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &P);
    lci_share part = {.rank = rank, .parts = P};
    *s = read_share(dev, path, ld, &part, sh, sp);
    int whole = *s == LC_OK && part.whole;
    *s = lc_mpi_agree(dev, comm, *s);
    MPI_Allreduce(MPI_IN_PLACE, &whole, 1, MPI_INT, MPI_MAX, comm);
    if (*s == LC_OK && whole) {
        if (part.whole) {
            lci_log(dev, LC_LOG_INFO, "%s: read whole by rank 0: the load needs %s", path, part.whole);
            snprintf(why, whylen, "the load needs %s", part.whole);
        }
        share_free(sh), memset(sp, 0, sizeof *sp);
        return 0;
    }
    if (*s == LC_OK)
        lci_log(dev, LC_LOG_INFO, "%s: rank %d read particles %zu .. %zu of %zu", path, rank, part.a, part.b, part.total);
    return *s == LC_OK;
}

/* ---------------------------------------------------------------- checks and extremes */

/* The field count over every share (d's rule: nfields, or 1 + the largest
 * id), then each invalid particle dropped or reported (lc_particles_create's
 * rules and message, with the index in the whole file). */
static lc_status validate(lc_device *dev, MPI_Comm comm, const char *path, shape *sp, share *sh)
{
    int mx = 0;
    for (size_t i = 0; i < sh->n; i++) mx = sh->f[i] > mx ? sh->f[i] : mx;
    MPI_Allreduce(MPI_IN_PLACE, &mx, 1, MPI_INT, MPI_MAX, comm);
    lc_status s = LC_OK;
    if (sp->nfields == 0 && mx >= LC_MAX_FIELDS)
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: a particle has field id %d; at most %d fields", path, mx,
                      LC_MAX_FIELDS);
    if (sp->nfields == 0) sp->nfields = mx + 1;
    s = lc_mpi_agree(dev, comm, s);
    if (s != LC_OK) return s;
    lc_particles_desc one = {.count = 1, .radius = sp->radius};
    uint64_t bad = 0;
    size_t first = 0, j = 0;
    const char *why = NULL;
    for (size_t i = 0; i < sh->n; i++) {
        float xyz[3] = {sh->x[i], sh->y[i], sh->z[i]};
        one.positions = xyz, one.radii = &sh->r[i], one.values = &sh->k[i], one.fields = &sh->f[i];
        one.norm_weights = sh->w ? &sh->w[i] : NULL;
        const char *w = lci_particles_invalid(&one, 0, sp->nfields);
        if (w) {
            if (!bad++) first = i, why = w;
            continue;
        }
        sh->x[j] = sh->x[i], sh->y[j] = sh->y[i], sh->z[j] = sh->z[i];
        sh->r[j] = sh->r[i], sh->k[j] = sh->k[i], sh->f[j] = sh->f[i];
        if (sh->w) sh->w[j] = sh->w[i];
        j++;
    }
    uint64_t total_bad = bad, total = sh->n;
    MPI_Allreduce(MPI_IN_PLACE, &total_bad, 1, MPI_UINT64_T, MPI_SUM, comm);
    MPI_Allreduce(MPI_IN_PLACE, &total, 1, MPI_UINT64_T, MPI_SUM, comm);
    if (bad && !sp->drop_invalid) /* the lowest failing rank holds the lowest index */
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                      "%s: lc_particles_create: %llu of %llu particles are invalid; the first is particle %zu (%s)", path,
                      (unsigned long long)total_bad, (unsigned long long)total, sh->offset + first, why);
    sh->n = j;
    return lc_mpi_agree(dev, comm, s);
}

/* Bounds of the centres and the radius range over every share. */
static void share_extremes(MPI_Comm comm, const share *sh, lci_particles_global *g)
{
    float lo[4] = {INFINITY, INFINITY, INFINITY, INFINITY}, hi[4] = {-INFINITY, -INFINITY, -INFINITY, 0.0f};
    for (size_t i = 0; i < sh->n; i++) {
        lo[0] = fminf(lo[0], sh->x[i]), lo[1] = fminf(lo[1], sh->y[i]), lo[2] = fminf(lo[2], sh->z[i]);
        hi[0] = fmaxf(hi[0], sh->x[i]), hi[1] = fmaxf(hi[1], sh->y[i]), hi[2] = fmaxf(hi[2], sh->z[i]);
        lo[3] = fminf(lo[3], sh->r[i]), hi[3] = fmaxf(hi[3], sh->r[i]);
    }
    MPI_Allreduce(MPI_IN_PLACE, lo, 4, MPI_FLOAT, MPI_MIN, comm);
    MPI_Allreduce(MPI_IN_PLACE, hi, 4, MPI_FLOAT, MPI_MAX, comm);
    uint64_t n = sh->n;
    MPI_Allreduce(MPI_IN_PLACE, &n, 1, MPI_UINT64_T, MPI_SUM, comm);
    memset(g, 0, sizeof *g);
    g->count = (size_t)n;
    g->bounds = (lc_box3){{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
    g->min_radius = lo[3], g->max_radius = hi[3];
}

/* The part's value ranges united (MIN / MAX; ghosts are some rank's owners too). */
static lc_status unite(MPI_Comm *c, lci_particles_global *g)
{
    float f[4] = {-g->kmin, g->kmax, -g->amin, g->amax};
    double d[2] = {-g->kh3min, g->kh3max};
    if (MPI_Allreduce(MPI_IN_PLACE, f, 4, MPI_FLOAT, MPI_MAX, *c) != MPI_SUCCESS ||
        MPI_Allreduce(MPI_IN_PLACE, d, 2, MPI_DOUBLE, MPI_MAX, *c) != MPI_SUCCESS)
        return LC_ERROR_INTERNAL;
    g->kmin = -f[0], g->kmax = f[1], g->kh3min = -d[0], g->kh3max = d[1], g->amin = -f[2], g->amax = f[3];
    return LC_OK;
}

/* ---------------------------------------------------------------- the exchange */

typedef struct dests {
    uint64_t *count; /* per rank: floats */
    float *buf;
    int *at;         /* per rank: the next float to write */
    const float *item;
    int nf;
} dests;

static void count_dest(void *u, int leaf)
{
    dests *d = u;
    d->count[leaf] += (uint64_t)d->nf;
}

static void pack_dest(void *u, int leaf)
{
    dests *d = u;
    memcpy(d->buf + d->at[leaf], d->item, sizeof(float) * (size_t)d->nf);
    d->at[leaf] += d->nf;
}

lc_status lci_mpi_exchange(lc_device *dev, MPI_Comm comm, const lci_kdtree *t, size_t n, float **itemsp, int nf,
                           const float *reach, float **recv, size_t *nrecv)
{
    const float *items = *itemsp;
    int P;
    MPI_Comm_size(comm, &P);
    *recv = NULL, *nrecv = 0;
    int *sc = calloc((size_t)P, sizeof(int)), *sd = calloc((size_t)P, sizeof(int));
    int *rc = calloc((size_t)P, sizeof(int)), *rd = calloc((size_t)P, sizeof(int)), *at = calloc((size_t)P, sizeof(int));
    uint64_t *c64 = calloc((size_t)P, sizeof(uint64_t));
    lc_status s = sc && sd && rc && rd && at && c64 ? LC_OK
                                                    : lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "exchange: out of memory");
    dests d = {c64, NULL, at, NULL, nf};
    for (size_t i = 0; s == LC_OK && i < n; i++) {
        const float *c = items + (size_t)nf * i;
        lci_dp_regions_near(t, c[0], c[1], c[2], reach[i], count_dest, &d);
    }
    uint64_t total = 0;
    for (int p = 0; s == LC_OK && p < P; p++) total += c64[p], sc[p] = (int)(c64[p] < INT_MAX ? c64[p] : 0);
    if (s == LC_OK && total > INT_MAX) /* MPI counts and displacements are ints */
        s = lci_error(dev, LC_ERROR_UNSUPPORTED, "exchange: %llu floats to send from one rank, at most %d",
                      (unsigned long long)total, INT_MAX);
    if (s == LC_OK && !(d.buf = malloc(sizeof(float) * (total ? total : 1))))
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "exchange: out of memory for %llu floats", (unsigned long long)total);
    if (s == LC_OK) {
        for (int p = 0, o = 0; p < P; p++) sd[p] = at[p] = o, o += sc[p];
        for (size_t i = 0; i < n; i++) {
            d.item = items + (size_t)nf * i;
            lci_dp_regions_near(t, d.item[0], d.item[1], d.item[2], reach[i], pack_dest, &d);
        }
    }
    free(*itemsp); /* packed: not held through the exchange */
    *itemsp = NULL, items = NULL;
    s = lc_mpi_agree(dev, comm, s);
    if (s == LC_OK && MPI_Alltoall(sc, 1, MPI_INT, rc, 1, MPI_INT, comm) != MPI_SUCCESS)
        s = lci_error(dev, LC_ERROR_INTERNAL, "exchange: MPI_Alltoall of the counts failed");
    uint64_t in = 0;
    for (int p = 0; s == LC_OK && p < P; p++) rd[p] = (int)(in < INT_MAX ? in : 0), in += (uint64_t)rc[p];
    if (s == LC_OK && in > INT_MAX)
        s = lci_error(dev, LC_ERROR_UNSUPPORTED, "exchange: %llu floats for one rank, at most %d", (unsigned long long)in,
                      INT_MAX);
    if (s == LC_OK && (!(*recv = malloc(sizeof(float) * (in ? in : 1))) || lci_test_fault("exchange")))
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "exchange: out of memory for %llu floats", (unsigned long long)in);
    s = lc_mpi_agree(dev, comm, s);
    if (s == LC_OK && MPI_Alltoallv(d.buf, sc, sd, MPI_FLOAT, *recv, rc, rd, MPI_FLOAT, comm) != MPI_SUCCESS)
        s = lci_error(dev, LC_ERROR_INTERNAL, "exchange: MPI_Alltoallv failed");
    s = lc_mpi_agree(dev, comm, s);
    if (s == LC_OK) *nrecv = (size_t)(in / (uint64_t)nf);
    else free(*recv), *recv = NULL;
    free(d.buf), free(sc), free(sd), free(rc), free(rd), free(at), free(c64);
    return s;
}

/* The share as records (x y z r k field, and the norm weight w with
 * has_w) and their reaches, then the exchange. */
enum { REC = 6 };

static lc_status exchange(lc_device *dev, MPI_Comm comm, const lci_kdtree *t, share *sh, int has_w, float support,
                          float dt, float **recv, size_t *nrecv)
{
    size_t n = sh->n, m = n ? n : 1, nf = REC + (has_w ? 1 : 0);
    float *items = malloc(sizeof(float) * nf * m), *reach = malloc(sizeof(float) * m);
    lc_status s = items && reach ? LC_OK : lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "out of memory for %zu particles", n);
    for (size_t i = 0; s == LC_OK && i < n; i++) {
        float *o = items + nf * i;
        o[0] = sh->x[i], o[1] = sh->y[i], o[2] = sh->z[i], o[3] = sh->r[i], o[4] = sh->k[i], o[5] = (float)sh->f[i];
        if (has_w) o[REC] = sh->w[i];
        reach[i] = lci_dp_reach(support, sh->r[i], dt);
    }
    share_free(sh); /* the records hold it now */
    s = lc_mpi_agree(dev, comm, s);
    if (s == LC_OK) s = lci_mpi_exchange(dev, comm, t, n, &items, (int)nf, reach, recv, nrecv);
    free(items), free(reach);
    return s;
}

/* ---------------------------------------------------------------- the load */

/* The load option sigma (the render's support in radii, so the ghosts
 * reach as far; not the reader's): taken out of ld's options into *sigma. */
static lc_status take_sigma(lc_device *dev, const char *path, const lc_load_desc *ld, lc_option *keep,
                            lc_load_desc *out, float *sigma)
{
    *out = *ld;
    out->options = keep, out->noptions = 0;
    *sigma = 0.0f;
    for (int i = 0; i < ld->noptions; i++) {
        const lc_option *o = &ld->options[i];
        if (o->key && !strcmp(o->key, "sigma")) {
            lc_status s = lci_option_float(dev, path, o, 1e-3f, 100.0f, sigma);
            if (s != LC_OK) return s;
        } else
            keep[out->noptions++] = *o;
    }
    return LC_OK;
}

static lc_status make_part(lc_device *dev, MPI_Comm *comm, const shape *sp, float **recp, size_t n,
                           const lci_particles_global *g, int canonical, lci_dp_ppart *pp, lc_volume **out)
{
    const float *rec = *recp;
    size_t m = n ? n : 1, nf = REC + (sp->has_w ? 1 : 0);
    float *xyz = malloc(12 * m), *r = malloc(4 * m), *k = malloc(4 * m), *w = sp->has_w ? malloc(4 * m) : NULL;
    uint8_t *f = malloc(m);
    lc_status s = xyz && r && k && f && (!sp->has_w || w) && !lci_test_fault("part")
                      ? LC_OK
                      : lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "out of memory for %zu particles", n);
    for (size_t i = 0; s == LC_OK && i < n; i++) {
        const float *o = rec + nf * i;
        xyz[3 * i] = o[0], xyz[3 * i + 1] = o[1], xyz[3 * i + 2] = o[2];
        r[i] = o[3], k[i] = o[4], f[i] = (uint8_t)o[5];
        if (w) w[i] = o[REC];
    }
    free(*recp); /* unpacked: not held through the build */
    *recp = NULL, rec = NULL;
    lc_particles_desc d = {.count = n, .positions = xyz, .radii = r, .radius = sp->radius, .values = k, .fields = f,
                           .nfields = sp->nfields, .leaf_size = sp->leaf_size, .params = sp->params,
                           .radius_note = sp->note[0] ? sp->note : NULL, .norm_weights = w,
                           .canonical_order = canonical, .order_box = g->bounds};
    if (s == LC_OK) s = lc_particles_create(dev, &d, out);
    free(xyz), free(r), free(k), free(w), free(f);
    s = lc_mpi_agree(dev, *comm, s);
    lci_particles_global e, all = *g;
    if (s == LC_OK) {
        lci_particles_extremes(*out, &e);
        s = unite(comm, &e);
        all.kmin = e.kmin, all.kmax = e.kmax, all.kh3min = e.kh3min, all.kh3max = e.kh3max;
        all.amin = e.amin, all.amax = e.amax;
    }
    if (s == LC_OK) s = lci_dp_particles_attach(dev, *out, &all, pp);
    else lci_kd_release(&pp->tree);
    s = lc_mpi_agree(dev, *comm, s);
    if (s != LC_OK && *out) lc_volume_destroy(*out), *out = NULL;
    return s;
}

lc_status lci_mpi_load_particles(lc_device *dev, MPI_Comm comm, const char *path, const lc_load_desc *ld,
                                 const char *format, float dt, lc_volume **out)
{
    int rank, P;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &P);
    lc_option *keep = malloc(sizeof *keep * (size_t)(ld->noptions + 1));
    lc_load_desc l2;
    float sigma = 0.0f;
    lc_status s = keep ? take_sigma(dev, path, ld, keep, &l2, &sigma)
                       : lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    share sh;
    memset(&sh, 0, sizeof sh);
    shape sp;
    memset(&sp, 0, sizeof sp);
    int raw = s == LC_OK && raw_plain(path, format, &l2);
    MPI_Allreduce(MPI_IN_PLACE, &raw, 1, MPI_INT, MPI_MIN, comm); /* one way for all */
    int parts = raw; /* every rank read its own share */
    char why[96] = "";
    s = lc_mpi_agree(dev, comm, s);
    if (s == LC_OK && raw) s = raw_share(dev, path, &l2, rank, P, &sh, &sp);
    else if (s == LC_OK && (!strcmp(format, "hdf5") || !strcmp(format, "gadget")))
        parts = by_shares(dev, comm, path, &l2, &sh, &sp, &s, why, sizeof why);
    if (s == LC_OK && !parts && rank == 0) s = read_share(dev, path, &l2, NULL, &sh, &sp);
    size_t nread = sh.n;
    free(keep);
    s = lc_mpi_agree(dev, comm, s);
    if (s == LC_OK && !parts) MPI_Bcast(&sp, (int)sizeof sp, MPI_BYTE, 0, comm);
    if (s == LC_OK) s = validate(dev, comm, path, &sp, &sh);
    lci_particles_global g;
    lci_dp_ppart pp;
    memset(&pp, 0, sizeof pp);
    if (s == LC_OK) {
        share_extremes(comm, &sh, &g);
        const lc_particle_params *q = &sp.params;
        int sph = q->kernel != LC_KERNEL_GAUSSIAN;
        pp.support = sph ? 1.0f : sigma > 0.0f ? sigma : q->sigma > 0.0f ? q->sigma : 2.0f;
        /* the step of the render, else the set's default (particles.c frame_info) */
        pp.dt = dt > 0.0f ? dt : g.count ? (sph ? 0.125f : 0.25f) * g.min_radius : 1.0f;
        pp.parts = P, pp.part = rank;
        lc_box3 b = lci_dp_particle_bounds(&g, pp.support);
        lci_kd_peers peers;
        s = lci_kd_build_dist(dev, &b, P, sh.n, sh.x, sh.y, sh.z, lci_mpi_kd_peers(&comm, &peers), &pp.tree);
    }
    s = lc_mpi_agree(dev, comm, s);
    float *rec = NULL;
    size_t n = 0;
    if (s == LC_OK) s = exchange(dev, comm, &pp.tree, &sh, sp.has_w, pp.support, pp.dt, &rec, &n);
    share_free(&sh);
    if (s == LC_OK) s = make_part(dev, &comm, &sp, &rec, n, &g, lci_mpi_canonical(ld), &pp, out);
    else lci_kd_release(&pp.tree);
    if (s == LC_OK && parts)
        snprintf((*out)->read_note, sizeof (*out)->read_note, "its share of the file, %zu particles; keeps %zu", nread,
                 n);
    else if (s == LC_OK)
        snprintf((*out)->read_note, sizeof (*out)->read_note, "keeps %zu of rank 0's whole read (%s)", n,
                 why[0] ? why : "the format is read by one rank");
    free(rec);
    return lc_mpi_agree(dev, comm, s);
}
