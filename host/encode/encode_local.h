/* The encoder's state and its local refit (encode.c drives, encode_local.c
 * adds one RBF): the fit samples sorted into buckets, their residuals and
 * clusters, and the RBFs so far. */
#ifndef LC_HOST_ENCODE_LOCAL_H
#define LC_HOST_ENCODE_LOCAL_H

#include "host/encode/encode.h"

#define LCI_ENC_MAX_LOCAL 32
/* A weight beyond this many value ranges is a cancelling pair of nearly
 * equal Gaussians, not data: such a fit is refused (float32 weights and
 * the eps truncation of a loaded set would not reproduce it). */
#define LCI_ENC_MAX_WEIGHT 4.0

/* A cluster owns idx[a, b). */
typedef struct lci_cluster {
    size_t a, b;
    double sse;
    int done; /* an RBF here no longer lowers the error */
} lci_cluster;

typedef struct lci_enc {
    lc_device *dev;
    lc_rbf_encode_desc d; /* defaults filled in */
    size_t n;             /* fit samples */
    float *p, *v;         /* 3n, n: in bucket order */
    double *r;            /* residuals v - f */
    uint32_t *cid;        /* cluster of each sample */
    uint32_t *idx;        /* sample indices, clusters own ranges */
    /* buckets: a uniform grid of cells over the samples' box; the samples
       of cell c are p[bstart[c] .. bstart[c + 1]) */
    double lo[3], hi[3], bcell;
    int bn[3];
    uint32_t *bstart;
    lci_cluster *cl;
    size_t ncl, capcl;
    lci_rbfs R;
    double vlo, vhi;      /* value range of the fitted samples */
    double smin, smax;    /* width bounds: a quarter of the sample spacing, the box diagonal */
    uint64_t rng;
} lci_enc;

double lci_enc_rand(lci_enc *e); /* uniform in [0, 1) */
double lci_enc_rand01(uint64_t *state); /* the same on a state of one's own (xorshift, not 0) */
double lci_enc_total_sse(const lci_enc *e);

/* Copies the picked samples into bucket order and sets up one cluster,
 * the bias (their mean) and the residuals. */
lc_status lci_enc_buckets(lci_enc *e, const float *p, const float *v, const uint32_t *pick);
void lci_enc_free(lci_enc *e);

/* Adds one RBF at mu with starting width s0 and refits locally; *added = 0
 * when it would not lower the error (nothing changed then). */
lc_status lci_enc_add(lci_enc *e, const double mu[3], double s0, int *added);

/* Term i at x, cut where it falls below 1e-4 of its weight's magnitude
 * (LCI_ENC_CUT2), without its weight. */
static inline double lci_enc_phi(const lci_rbfs *r, size_t i, const float *x)
{
    const double *m = r->c + 3 * i;
    double dx = x[0] - m[0], dy = x[1] - m[1], dz = x[2] - m[2];
    double d2 = dx * dx + dy * dy + dz * dz, s2 = r->s[i] * r->s[i];
    return d2 < LCI_ENC_CUT2 * s2 ? exp(-d2 / (2.0 * s2)) : 0.0;
}

/* The bucket box reached by a sphere. */
static inline void lci_enc_bucket_box(const lci_enc *e, const double *c, double rad, int i0[3], int i1[3])
{
    for (int a = 0; a < 3; a++) {
        double t0 = (c[a] - rad - e->lo[a]) / e->bcell, t1 = (c[a] + rad - e->lo[a]) / e->bcell;
        i0[a] = t0 < 0.0 ? 0 : t0 >= e->bn[a] ? e->bn[a] - 1 : (int)t0;
        i1[a] = t1 < 0.0 ? 0 : t1 >= e->bn[a] ? e->bn[a] - 1 : (int)t1;
    }
}

#define LCI_FOR_SAMPLES_NEAR(e, c, rad, j)                                                                               \
    int i0_[3], i1_[3];                                                                                              \
    lci_enc_bucket_box(e, c, rad, i0_, i1_);                                                                                 \
    for (int z_ = i0_[2]; z_ <= i1_[2]; z_++)                                                                        \
        for (int y_ = i0_[1]; y_ <= i1_[1]; y_++)                                                                    \
            for (size_t b_ = ((size_t)z_ * (size_t)e->bn[1] + (size_t)y_) * (size_t)e->bn[0], j = e->bstart[b_ + (size_t)i0_[0]]; \
                 j < e->bstart[b_ + (size_t)i1_[0] + 1]; j++)

/* r -= sign * w phi over term (c, s)'s cut sphere, keeping the cluster
 * errors when clusters is 1 (0: they are recomputed later; what parallel
 * sweeps do); returns the change of the squared error. Touches the
 * residuals inside the cut sphere only. */
double lci_enc_apply_term(lci_enc *e, const double *c, double s, double w, double sign, int clusters);
/* Samples within rreg of mu: at most cap of them, a uniform subsample
 * (strided from a random offset, then reservoir sampling on the state
 * rng; cost O(cap) plus the buckets, whatever the region's size) in *out
 * (malloc'd). Returns the count, or (size_t)-1 when out of memory. */
size_t lci_enc_region(const lci_enc *e, const double *mu, double rreg, size_t cap, uint64_t *rng, uint32_t **out);

/* One polish sweep (encode_polish.c): every RBF's weight, width and
 * centre refitted in turn by LM against the residual; *changed (may be
 * NULL) counts the RBFs that moved. */
lc_status lci_enc_polish(lci_enc *e, size_t *changed);

/* The cell of x in an RBF grid (clamped). */
size_t lci_rbf_grid_cell(const lci_rbf_grid *g, const float x[3]);

#endif
