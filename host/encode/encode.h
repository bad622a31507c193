/* The RBF encoder's internals (Jang et al. 2004 sec. 4): the samples object
 * and its readers (CSV, VTK legacy; structured volumes come through the
 * formats registry), the RBF lookup grid used to evaluate a set at many
 * points, and the least-squares pieces built on LAPACKE. Host code only. */
#ifndef LC_HOST_ENCODE_H
#define LC_HOST_ENCODE_H

#include <stdint.h>
#include "host/internal.h"

/* At most this many samples (float32 x y z value each). */
#define LCI_MAX_SAMPLES ((size_t)INT32_MAX)

struct lc_samples {
    size_t n;
    float *p; /* 3n */
    float *v; /* n */
    lc_samples_info info;
    char format[16];
};

/* Makes a samples object of p (3n floats) and v (n floats), taking both
 * (freed on failure); checks every value is finite, naming `name` and the
 * first bad sample (index + 1 = `what` number) and the count of bad ones. */
lc_status lci_samples_adopt(lc_device *dev, const char *name, float *p, float *v, size_t n, const char *format,
                            uint64_t input_bytes, lc_samples **out);

/* The readers (samples_csv.c, samples_vtk.c): one message naming the file
 * and the line (or the byte offset in binary VTK data). */
lc_status lci_samples_read_csv(lc_device *dev, const char *path, lc_samples **out);
lc_status lci_samples_read_vtk(lc_device *dev, const char *path, lc_samples **out);
int lci_vtk_magic(const unsigned char *head, size_t n);

/* An RBF set under evaluation: centres, widths, weights (double) and the
 * radius past which each term is cut. */
typedef struct lci_rbfs {
    size_t m, cap;
    double *c, *s, *w, *cut; /* 3m, m, m, m */
    double bias;
} lci_rbfs;

int lci_rbfs_reserve(lci_rbfs *r, size_t cap);
void lci_rbfs_free(lci_rbfs *r);

/* A uniform grid of cells over a box, each cell listing the RBFs whose cut
 * sphere's box reaches it (CSR), for evaluating the set at any point. */
typedef struct lci_rbf_grid {
    double lo[3], cell;
    int nc[3];
    uint32_t *start; /* ncells + 1 */
    uint32_t *list;
} lci_rbf_grid;

lc_status lci_rbf_grid_build(lc_device *dev, lci_rbf_grid *g, const lci_rbfs *r, const double lo[3],
                             const double hi[3]);
void lci_rbf_grid_free(lci_rbf_grid *g);
/* f(x) - bias: the sum of the terms whose cut sphere holds x. */
double lci_rbf_grid_eval(const lci_rbf_grid *g, const lci_rbfs *r, const float x[3]);
/* out[j] = v[j] - f(p_j) for n points, on the device's threads. */
lc_status lci_rbf_residuals(lc_device *dev, const lci_rbfs *r, const double lo[3], const double hi[3], size_t n,
                            const float *p, const float *v, double *out);

/* Least squares through LAPACKE (encode_fit.c). */
/* min |A x - b| for A m x k (column major, lda = m), b of m; x in b[0..k).
 * SVD-based (dgelsd), so a rank-deficient A gives the minimum-norm answer.
 * 0 ok, -1 LAPACK failed. */
int lci_lls(int m, int k, double *a, double *b);
/* Solves the symmetric positive definite k x k system (row major, upper
 * triangle used) A x = b; a tiny ridge is added when the Cholesky factor
 * fails. x in b. 0 ok, -1 failed. */
int lci_spd_solve(int k, double *a, double *b);
/* The unit principal axis of a symmetric 3x3 covariance (row major). */
void lci_principal_axis(const double cov[9], double axis[3]);

/* The relative cut the encoder uses for every term: exp(-d^2 / (2 s^2)) >= 1e-4,
 * i.e. d^2 < 2 ln(1e4) s^2 (SPEC.md's support with eps = 1e-4 |w|). */
#define LCI_ENC_CUT2 18.420680743952367

#endif
