/* The encoder's linear algebra through LAPACKE (Debian liblapacke-dev; the
 * meson feature `lapacke`): least squares by SVD (dgelsd), symmetric
 * positive definite solves by Cholesky (dposv), and the principal axis of a
 * covariance (dsyev). No hand-written solver. Compiled out, these are never
 * called: lc_rbf_encode fails first (encode.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "host/encode/encode.h"
#if LC_HAVE_LAPACKE
#include <lapacke.h>

int lci_lls(int m, int k, double *a, double *b)
{
    if (m < 1 || k < 1) return -1;
    double *sv = malloc(sizeof(double) * (size_t)k);
    if (!sv) return -1;
    lapack_int rank;
    /* rcond: singular values below 1e-6 of the largest count as zero, so
       nearly coincident Gaussians get the minimum-norm split of their weight
       instead of a huge cancelling pair */
    lapack_int info = LAPACKE_dgelsd(LAPACK_COL_MAJOR, m, k, 1, a, m, b, m > k ? m : k, sv, 1e-6, &rank);
    free(sv);
    return info == 0 ? 0 : -1;
}

int lci_spd_solve(int k, double *a, double *b)
{
    size_t kk = (size_t)k * (size_t)k;
    double *copy = malloc(sizeof(double) * kk), *rhs = malloc(sizeof(double) * (size_t)k);
    if (!copy || !rhs) {
        free(copy), free(rhs);
        return -1;
    }
    double dmax = 0.0;
    for (int i = 0; i < k; i++) dmax = fmax(dmax, a[(size_t)i * k + i]);
    int rc = -1;
    /* a ridge of 1e-9 of the largest diagonal (Tikhonov: damps directions
       of singular value below ~3e-5 of the largest, the cancelling pairs of
       nearly equal Gaussians), 1e-6 and 1e-3 when Cholesky still fails */
    for (int attempt = 0; attempt < 3 && rc; attempt++) {
        memcpy(copy, a, sizeof(double) * kk);
        memcpy(rhs, b, sizeof(double) * (size_t)k);
        double ridge = dmax * pow(10.0, -9.0 + 3.0 * attempt);
        for (int i = 0; i < k; i++) copy[(size_t)i * k + i] += ridge + (dmax == 0.0 && attempt ? 1.0 : 0.0);
        if (LAPACKE_dposv(LAPACK_ROW_MAJOR, 'U', k, 1, copy, k, rhs, 1) == 0) rc = 0;
    }
    if (!rc) memcpy(b, rhs, sizeof(double) * (size_t)k);
    free(copy), free(rhs);
    return rc;
}

void lci_principal_axis(const double cov[9], double axis[3])
{
    double a[9], w[3];
    memcpy(a, cov, sizeof a);
    if (LAPACKE_dsyev(LAPACK_ROW_MAJOR, 'V', 'U', 3, a, 3, w) != 0) {
        axis[0] = 1.0, axis[1] = axis[2] = 0.0;
        return;
    }
    /* eigenvalues ascending: the last column is the principal axis */
    for (int i = 0; i < 3; i++) axis[i] = a[3 * i + 2];
}
#else
int lci_lls(int m, int k, double *a, double *b) { return (void)m, (void)k, (void)a, (void)b, -1; }
int lci_spd_solve(int k, double *a, double *b) { return (void)k, (void)a, (void)b, -1; }
void lci_principal_axis(const double cov[9], double axis[3])
{
    (void)cov;
    axis[0] = 1.0, axis[1] = axis[2] = 0.0;
}
#endif
