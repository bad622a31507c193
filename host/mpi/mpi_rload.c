/* lc_mpi_volume_load of RBF sets (dp.h "Particle parts", for RBF terms):
 * rank 0 reads the file (text or binary RBF files are read whole), builds
 * the whole set once for what depends on every term (eps, the default
 * range's peaks at the centres, the widths, the range bound) and keeps the
 * terms with support; the kd-tree over their centres (rank 0 holds them
 * all: lci_kd_build_dist gives lci_kd_build's splits) and one exchange
 * send each term to every rank whose region its support R_i, grown by two
 * steps, reaches. Each rank's part is an RBF set over those terms with the
 * whole set's eps and domain (so the same supports and lattice clip box)
 * and its globals (lci_rbf_set_global). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/format.h"
#include "host/kinds/rbf.h"
#include "host/mpi/mpi_internal.h"
#include "lanecast/lanecast_mpi.h"

enum { TERM = 5 }; /* floats a term: x y z s w */

/* What every rank needs of rank 0's set. */
typedef struct rhead {
    lci_rbf_global g;
    lc_box3 bounds;
    float bias, eps, default_dt;
    int leaf_size, cell_max, significant, canonical;
    lc_rbf_accel accel;
} rhead;

/* Rank 0: the whole set's globals, and its terms with support as items
 * (TERM floats) with their supports R_i. */
static lc_status read_terms(lc_device *dev, const char *path, const lc_load_desc *ld, rhead *h, float **items,
                            float **R, size_t *n)
{
    lci_loaded l;
    lc_kind kind;
    const char *fmt;
    lc_status s = lci_read_volume_desc(dev, path, ld, &kind, &fmt, &l);
    if (s != LC_OK) return s;
    const lc_rbf_desc *d = l.desc;
    lc_volume *whole = NULL;
    if (kind != LC_KIND_RBF) s = lci_error(dev, LC_ERROR_INTERNAL, "%s: not an RBF set", path);
    /* the whole set in the parts' order: its globals (the range bound's node sums, the values
       at the centres) are then those of one process rendering in that order */
    lc_rbf_desc wd;
    memset(&wd, 0, sizeof wd);
    if (s == LC_OK) {
        wd = *d;
        wd.canonical_order = lci_mpi_canonical(ld);
        s = lc_rbf_create(dev, &wd, &whole);
    }
    lc_rbf_info info;
    lci_frame_info fi;
    memset(&fi, 0, sizeof fi);
    if (s == LC_OK) s = lc_rbf_get_info(whole, &info);
    if (s == LC_OK) s = whole->ops->frame_info(dev, whole, &fi);
    size_t m = d && d->count ? d->count : 1;
    float *xyz = malloc(12 * m);
    size_t *src = malloc(sizeof(size_t) * m);
    *R = malloc(4 * m), *items = malloc(sizeof(float) * TERM * m);
    if (s == LC_OK && (!xyz || !src || !*R || !*items))
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %zu RBFs", path, d->count);
    if (s == LC_OK) {
        lci_rbf_global_of(whole, &h->g);
        h->bounds = info.bounds, h->bias = info.bias, h->eps = info.eps, h->default_dt = fi.default_dt;
        h->leaf_size = info.leaf_size, h->cell_max = info.cell_max, h->significant = info.significant;
        h->accel = info.accel;
        h->canonical = wd.canonical_order;
        lc_box3 sb;
        *n = lci_rbf_keep(d, info.eps, xyz, *R, src, &sb);
        for (size_t j = 0; j < *n; j++) {
            float *o = *items + TERM * j;
            memcpy(o, xyz + 3 * j, 12);
            o[3] = d->widths[src[j]], o[4] = d->weights[src[j]];
        }
    }
    free(xyz), free(src);
    lc_volume_destroy(whole);
    lci_loaded_free(&l);
    return s;
}

/* The part's RBF set from the terms it received. */
static lc_status make_part(lc_device *dev, const rhead *h, const float *rec, size_t n, lci_dp_ppart *pp,
                           lc_volume **out)
{
    size_t m = n ? n : 1;
    float *c = malloc(12 * m), *sw = malloc(4 * m), *w = malloc(4 * m);
    lc_status s = c && sw && w && !lci_test_fault("part")
                      ? LC_OK
                      : lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "out of memory for %zu RBFs", n);
    for (size_t i = 0; s == LC_OK && i < n; i++) {
        const float *o = rec + TERM * i;
        memcpy(c + 3 * i, o, 12);
        sw[i] = o[3], w[i] = o[4];
    }
    /* the whole set's eps and clip box: the same supports and lattice */
    lc_rbf_desc d = {.count = n, .centres = c, .widths = sw, .weights = w, .bias = h->bias, .eps = h->eps,
                     .domain = h->bounds, .leaf_size = h->leaf_size, .accel = h->accel,
                     .cell_max = h->accel == LC_RBF_ACCEL_OCTREE ? h->cell_max : 0,
                     .significant = h->significant, .canonical_order = h->canonical};
    if (s == LC_OK) s = lc_rbf_create(dev, &d, out);
    free(c), free(sw), free(w);
    lci_dp_ppart *keep = s == LC_OK ? lci_dp_ppart_keep(dev, pp) : NULL;
    if (s == LC_OK && !keep) s = LC_ERROR_OUT_OF_MEMORY;
    if (s == LC_OK) lci_rbf_set_global(*out, &h->g, keep, lci_dp_ppart_free);
    else lci_kd_release(&pp->tree);
    return s;
}

lc_status lci_mpi_load_rbf(lc_device *dev, MPI_Comm comm, const char *path, const lc_load_desc *ld, float dt,
                           lc_volume **out)
{
    int rank, P;
    MPI_Comm_rank(comm, &rank);
    MPI_Comm_size(comm, &P);
    rhead h;
    memset(&h, 0, sizeof h);
    float *items = NULL, *R = NULL;
    size_t n = 0;
    lc_status s = rank == 0 ? read_terms(dev, path, ld, &h, &items, &R, &n) : LC_OK;
    s = lc_mpi_agree(dev, comm, s);
    lci_dp_ppart pp;
    memset(&pp, 0, sizeof pp);
    float *x = NULL, *y = NULL, *z = NULL;
    if (s == LC_OK) {
        MPI_Bcast(&h, (int)sizeof h, MPI_BYTE, 0, comm);
        pp.parts = P, pp.part = rank, pp.support = 1.0f;
        pp.dt = dt > 0.0f ? dt : h.default_dt;
        size_t m = n ? n : 1;
        x = malloc(4 * m), y = malloc(4 * m), z = malloc(4 * m);
        if (!x || !y || !z) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %zu RBFs", path, n);
        for (size_t i = 0; s == LC_OK && i < n; i++) {
            x[i] = items[TERM * i], y[i] = items[TERM * i + 1], z[i] = items[TERM * i + 2];
            R[i] = R[i] * 1.01f + 1e-6f + 2.0f * pp.dt; /* the reach: the support and two steps */
        }
    }
    s = lc_mpi_agree(dev, comm, s);
    lci_kd_peers peers;
    if (s == LC_OK) s = lci_kd_build_dist(dev, &h.bounds, P, n, x, y, z, lci_mpi_kd_peers(&comm, &peers), &pp.tree);
    free(x), free(y), free(z);
    s = lc_mpi_agree(dev, comm, s);
    float *rec = NULL;
    size_t nrec = 0;
    if (s == LC_OK) s = lci_mpi_exchange(dev, comm, &pp.tree, n, &items, TERM, R, &rec, &nrec);
    free(items), free(R);
    if (s == LC_OK) s = make_part(dev, &h, rec, nrec, &pp, out);
    else lci_kd_release(&pp.tree);
    if (s == LC_OK) /* RBF files have no format read in parts */
        snprintf((*out)->read_note, sizeof (*out)->read_note, "keeps %zu terms of rank 0's whole read (RBF files)", nrec);
    free(rec);
    s = lc_mpi_agree(dev, comm, s);
    if (s != LC_OK && *out) lc_volume_destroy(*out), *out = NULL;
    return s;
}
