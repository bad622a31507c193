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

/* The cell of x in an RBF grid (clamped). */
size_t lci_rbf_grid_cell(const lci_rbf_grid *g, const float x[3]);

#endif
