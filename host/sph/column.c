/* Column kernels and their separable cumulative tables (column.h). Every
 * integral here is Gauss-Legendre quadrature in double, split at the radii
 * where a kernel's pieces meet, so that each piece is a polynomial (SPH) or
 * smooth (Gaussian) along the line of sight. */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include "host/internal.h"
#include "host/sph/column.h"
#include "host/sph/sph_kernel.h"

#define NB 2048   /* intervals of the Hermite table of F over b used while building */
#define NNYS 128  /* Nystrom nodes on [0, 1] */
#define GL_N 24   /* points per piece of a line-of-sight integral */
#define TOL 2e-7  /* rank: the smallest K whose check-grid error is below TOL * F(0) */

typedef struct shape {
    const lci_sph_kernel *k;
    double norm;
    double kinks[2];
    int nkinks;
} shape;

static double f_of(const shape *s, double u) { return u < 1.0 ? s->k->f(u) : 0.0; }
static double df_of(const shape *s, double u) { return u < 1.0 ? s->k->df(u) : 0.0; }

/* Gauss-Legendre nodes and weights on [0, 1] (Newton on P_n). */
static void gauss_legendre(int n, double *x, double *w)
{
    for (int i = 0; i < n; i++) {
        double z = cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
        for (int it = 0; it < 100; it++) {
            double p0 = 1.0, p1 = z;
            for (int k = 2; k <= n; k++) {
                double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
                p0 = p1, p1 = p2;
            }
            dp = n * (z * p1 - p0) / (z * z - 1.0);
            double dz = p1 / dp;
            z -= dz;
            if (fabs(dz) < 1e-16) break;
        }
        x[i] = 0.5 * (1.0 - z);
        w[i] = 1.0 / ((1.0 - z * z) * dp * dp);
    }
}

static double glx[GL_N], glw[GL_N];
static double g8x[8], g8w[8];
static pthread_once_t gl_once = PTHREAD_ONCE_INIT;
static void gl_init(void)
{
    gauss_legendre(GL_N, glx, glw);
    gauss_legendre(8, g8x, g8w);
}

/* norm int_{z0}^{z1} f(sqrt(b^2 + z^2)) dz (or of the b-derivative with
 * deriv), 0 <= z0 <= z1 <= sqrt(1 - b^2), split where a kink radius is crossed. */
static double line(const shape *s, double b, double z0, double z1, int deriv)
{
    double cut[4] = {z0};
    int nc = 1;
    for (int k = 0; k < s->nkinks; k++) {
        double r = s->kinks[k];
        if (r > b) {
            double z = sqrt(r * r - b * b);
            if (z > z0 && z < z1) cut[nc++] = z;
        }
    }
    cut[nc++] = z1;
    double sum = 0.0;
    for (int p = 0; p + 1 < nc; p++) {
        double a = cut[p], h = cut[p + 1] - a, part = 0.0;
        for (int i = 0; i < GL_N; i++) {
            double z = a + h * glx[i], u = sqrt(b * b + z * z);
            part += glw[i] * (deriv ? (u > 0.0 ? df_of(s, u) * b / u : 0.0) : f_of(s, u));
        }
        sum += h * part;
    }
    return s->norm * sum;
}

/* The column F(b) (and dF/db) in units of 1 / S^2. */
static double column(const shape *s, double b, double *deriv)
{
    if (!(b < 1.0)) {
        if (deriv) *deriv = 0.0;
        return 0.0;
    }
    double c = sqrt(1.0 - b * b);
    if (deriv) *deriv = 2.0 * line(s, b, 0.0, c, 1);
    return 2.0 * line(s, b, 0.0, c, 0);
}

typedef struct ftab {
    double v[NB + 2], d[NB + 2];
} ftab;

/* Cubic Hermite lookup of F at b (0 beyond 1). */
static double ftab_at(const ftab *t, double b)
{
    if (!(b < 1.0)) return 0.0;
    double x = b * NB;
    int j = (int)x;
    double r = x - j, h = 1.0 / NB, r2 = r * r, r3 = r2 * r;
    return (2 * r3 - 3 * r2 + 1) * t->v[j] + (r3 - 2 * r2 + r) * h * t->d[j] + (-2 * r3 + 3 * r2) * t->v[j + 1] +
           (r3 - r2) * h * t->d[j + 1];
}

static double g_at(const ftab *t, double u, double v) { return ftab_at(t, sqrt(u * u + v * v)); }

/* Cyclic Jacobi rotations of the symmetric n x n matrix a (destroyed):
 * eigenvalues in d, eigenvectors in the columns of v. */
static void jacobi(int n, double *a, double *v, double *d)
{
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) v[i * n + j] = i == j;
    for (int sweep = 0; sweep < 60; sweep++) {
        double off = 0.0, diag = 0.0;
        for (int i = 0; i < n; i++) {
            diag += a[i * n + i] * a[i * n + i];
            for (int j = i + 1; j < n; j++) off += a[i * n + j] * a[i * n + j];
        }
        if (off < 1e-30 * diag) break;
        for (int p = 0; p < n; p++)
            for (int q = p + 1; q < n; q++) {
                double apq = a[p * n + q];
                if (fabs(apq) < 1e-300) continue;
                double theta = (a[q * n + q] - a[p * n + p]) / (2.0 * apq);
                double t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
                double c = 1.0 / sqrt(t * t + 1.0), sn = t * c;
                for (int k = 0; k < n; k++) { /* columns p, q */
                    double akp = a[k * n + p], akq = a[k * n + q];
                    a[k * n + p] = c * akp - sn * akq;
                    a[k * n + q] = sn * akp + c * akq;
                }
                for (int k = 0; k < n; k++) { /* rows p, q */
                    double apk = a[p * n + k], aqk = a[q * n + k];
                    a[p * n + k] = c * apk - sn * aqk;
                    a[q * n + k] = sn * apk + c * aqk;
                }
                for (int k = 0; k < n; k++) {
                    double vkp = v[k * n + p], vkq = v[k * n + q];
                    v[k * n + p] = c * vkp - sn * vkq;
                    v[k * n + q] = sn * vkp + c * vkq;
                }
            }
    }
    for (int i = 0; i < n; i++) d[i] = a[i * n + i];
}

/* The kernels' tables from A_k and phi_k on the fine nodes (cum[j * ld + k],
 * phi[j * ld + k]): tab padded to kpad terms, the marginal M and its
 * derivative as the same combination of A_k and phi_k, so that M is the
 * separable form's marginal up to rounding. */
static int tables(lci_column *c, int rank, const double *cum, const double *phi, int ld)
{
    enum { NT = LCI_COL_NT, NK = LCI_COL_NK, ST = LCI_COL_NT / LCI_COL_NK };
    int kp = (rank + LC_KPROJ_KPAD - 1) / LC_KPROJ_KPAD * LC_KPROJ_KPAD;
    c->tab = calloc((size_t)(NK + 1) * 2 * (size_t)kp, sizeof(double));
    c->marg = malloc(sizeof(double) * 2 * (NK + 1));
    if (!c->tab || !c->marg) return 0;
    for (int n = 0; n <= NK; n++) {
        int j = n * ST;
        double m = 0.0, dm = 0.0;
        for (int k = 0; k < rank; k++) {
            c->tab[(size_t)n * 2 * kp + k] = cum[j * ld + k];
            c->tab[(size_t)n * 2 * kp + kp + k] = phi[j * ld + k] / NK;
            m += 2.0 * c->mu[k] * cum[NT * ld + k] * cum[j * ld + k];
            dm += 2.0 * c->mu[k] * cum[NT * ld + k] * phi[j * ld + k] / NK;
        }
        c->marg[2 * n] = m, c->marg[2 * n + 1] = dm;
    }
    c->kt = (lc_kproj_table){.rank = rank, .kpad = kp, .nt = NK, .tab = c->tab, .mu = c->mu, .marg = c->marg};
    return 1;
}

/* Lower ranks for small supports: a support of s pixels truncated to K' < K
 * terms (K' a multiple of 4; the lookups fill K' rounded up to
 * LC_KPROJ_KPAD), mu_0 then carrying the dropped terms' mass (d0 = sum_{k >=
 * K'} mu_k A_k(1)^2 / A_0(1)^2), changes a pixel by at most
 *     B = sum_{K' <= k < K} |mu_k| D_k^2 + |d0| D_0^2,
 * D_k = the largest difference of A_k across a pixel (width 1 / s, on the
 * fine nodes, A_k odd and constant beyond the support), while the smallest
 * largest pixel of the support (centred on a pixel corner) is P = sum_k mu_k
 * A_k(1 / s)^2. K' is kept up to the largest s (on a grid of ratios 1.05)
 * with 1.5 B <= TOL P: the full rank's tolerance again, relative to the
 * map's peak (tests/test_sph_project.c's measure). */
static void levels(lci_column *c, const double *cum, int ld, int rank)
{
    enum { NT = LCI_COL_NT, NA = 2 * LCI_COL_NT + 1 };
    double *A = malloc(sizeof(double) * NA);
    c->kt.nlev = 0;
    if (!A) return;
    /* candidates: multiples of 4 below the rank, the largest LC_KPROJ_LEVELS of them, from the smallest up */
    int top = (rank - 1) / 4 * 4, first = top - 4 * (LC_KPROJ_LEVELS - 1);
    for (int kl = first < 4 ? 4 : first; kl <= top; kl += 4) {
        double d0 = 0.0;
        for (int k = kl; k < rank; k++) d0 += c->mu[k] * cum[NT * ld + k] * cum[NT * ld + k];
        d0 /= cum[NT * ld] * cum[NT * ld];
        double smax = 0.0;
        for (double sp = 2.0; sp < 512.0; sp *= 1.05) {
            int m = (int)(NT / sp); /* the pixel's width in fine nodes (rounded down: A_k's differences grow with it) */
            if (m < 1) break;
            double B = 0.0, P = 0.0;
            for (int k = 0; k < rank; k++) {
                double a = cum[m * ld + k];
                P += c->mu[k] * a * a;
                if (k != 0 && k < kl) continue;
                for (int j = 0; j < NA; j++) A[j] = j >= NT ? cum[(j - NT) * ld + k] : -cum[(NT - j) * ld + k];
                double D = 0.0;
                for (int j = -m; j < NA; j++) {
                    double lo = j < 0 ? A[0] : A[j], hi = j + m >= NA ? A[NA - 1] : A[j + m];
                    D = fmax(D, fabs(hi - lo));
                }
                B += (k == 0 ? fabs(d0) : fabs(c->mu[k])) * D * D;
            }
            if (!(1.5 * B <= TOL * P)) break;
            smax = sp;
        }
        if (smax <= 0.0) continue; /* fails at 2 pixels: the next K' may not */
        int l = c->kt.nlev++;
        c->kt.lev_k[l] = kl, c->kt.lev_smax[l] = smax, c->kt.lev_mu0[l] = c->mu[0] + d0;
    }
    free(A);
}

/* The separable tables: Nystrom eigenpairs of g on [0, 1]^2, the Nystrom
 * interpolants phi_k and A_k on the fine nodes, the rank and the mass. */
static int build_separable(lci_column *c, const ftab *ft)
{
    enum { M = NNYS, NT = LCI_COL_NT };
    double x[M], w[M], sw[M], d[M];
    gauss_legendre(M, x, w);
    double *a = malloc(sizeof(double) * M * M), *v = malloc(sizeof(double) * M * M);
    double *phi = malloc(sizeof(double) * (NT + 1) * LCI_COL_KMAX), *cum = malloc(sizeof(double) * (NT + 1) * LCI_COL_KMAX);
    double *gn = malloc(sizeof(double) * M), *g1 = malloc(sizeof(double) * M);
    int ok = a && v && phi && cum && gn && g1;
    if (ok) {
        for (int i = 0; i < M; i++) sw[i] = sqrt(w[i]);
        for (int i = 0; i < M; i++)
            for (int j = 0; j <= i; j++) a[i * M + j] = a[j * M + i] = sw[i] * g_at(ft, x[i], x[j]) * sw[j];
        jacobi(M, a, v, d);
        /* order by |eigenvalue| */
        int ord[M];
        for (int i = 0; i < M; i++) ord[i] = i;
        for (int i = 1; i < M; i++)
            for (int j = i; j > 0 && fabs(d[ord[j]]) > fabs(d[ord[j - 1]]); j--) {
                int t = ord[j];
                ord[j] = ord[j - 1], ord[j - 1] = t;
            }
        int K = LCI_COL_KMAX;
        double ev[LCI_COL_KMAX][M]; /* phi_k(x_n) w_n / mu_k: the Nystrom weights */
        for (int k = 0; k < K; k++) {
            double mu = d[ord[k]];
            c->mu[k] = mu;
            for (int n = 0; n < M; n++) ev[k][n] = mu != 0.0 ? v[n * M + ord[k]] / sw[n] * w[n] / mu : 0.0;
        }
        /* phi_k(u_j) = sum_n g(u_j, x_n) ev_kn; A_k(u_j) the same with G1 = int_0^u g */
        for (int n = 0; n < M; n++) g1[n] = 0.0;
        for (int j = 0; j <= NT; j++) {
            double u = (double)j / NT;
            if (j > 0)
                for (int n = 0; n < M; n++) {
                    double sum = 0.0, u0 = (double)(j - 1) / NT;
                    for (int q = 0; q < 8; q++) sum += g8w[q] * g_at(ft, u0 + g8x[q] / NT, x[n]);
                    g1[n] += sum / NT;
                }
            for (int n = 0; n < M; n++) gn[n] = g_at(ft, u, x[n]);
            for (int k = 0; k < K; k++) {
                double p = 0.0, q = 0.0;
                for (int n = 0; n < M; n++) p += gn[n] * ev[k][n], q += g1[n] * ev[k][n];
                phi[j * K + k] = p, cum[j * K + k] = q;
            }
        }
        /* the rank: error of the first K terms against g on a check grid of the fine nodes */
        double f0 = c->f0, err[LCI_COL_KMAX];
        for (int k = 0; k < K; k++) err[k] = 0.0;
        for (int j = 0; j <= NT; j += 8)
            for (int l = 0; l <= j; l += 8) {
                double g = g_at(ft, (double)j / NT, (double)l / NT), sum = 0.0;
                for (int k = 0; k < K; k++) {
                    sum += c->mu[k] * phi[j * K + k] * phi[l * K + k];
                    double e = fabs(sum - g) / f0;
                    if (e > err[k]) err[k] = e;
                }
            }
        int rank = K;
        for (int k = 0; k < K; k++)
            if (err[k] < TOL) {
                rank = k + 1;
                break;
            }
        c->rank = rank;
        c->err = err[rank - 1];
        /* the mass of the kept terms, 4 sum mu_k A_k(1)^2, made exactly 1 through mu_0 */
        double mass = 0.0;
        for (int k = 0; k < rank; k++) mass += 4.0 * c->mu[k] * cum[NT * K + k] * cum[NT * K + k];
        c->mu[0] += (1.0 - mass) / (4.0 * cum[NT * K] * cum[NT * K]);
        for (int k = rank; k < LCI_COL_KMAX; k++) c->mu[k] = 0.0;
        ok = tables(c, rank, cum, phi, K);
        /* LANECAST_PROJECT_FULL_RANK=1: every support takes the full rank (A/B runs) */
        if (ok && !lci_env_long("LANECAST_PROJECT_FULL_RANK", 0, 1, 0)) levels(c, cum, K, rank);
    }
    free(a), free(v), free(phi), free(cum), free(gn), free(g1);
    return ok;
}

/* rho(t) = 2 pi norm int_|t|^1 f(u) u du: the kernel's mass per unit height
 * at height t, split at the kinks. */
static double rho_at(const shape *s, double t)
{
    double lo = fabs(t), sum = 0.0, cuts[3];
    int nc = 0;
    for (int k = 0; k < s->nkinks; k++)
        if (s->kinks[k] > lo) cuts[nc++] = s->kinks[k];
    cuts[nc++] = 1.0;
    for (int p = 0; p < nc && lo < 1.0; p++) {
        double h = cuts[p] - lo, part = 0.0;
        for (int q = 0; q < GL_N; q++) {
            double u = lo + h * glx[q];
            part += glw[q] * f_of(s, u) * u;
        }
        sum += h * part;
        lo = cuts[p];
    }
    return 2.0 * M_PI * s->norm * sum;
}

/* The slab tables: T(b, s) and the mass fraction mz with its density. */
static int build_slab(lci_column *c, const shape *s)
{
    enum { N = LCI_COL_NZ };
    c->slab = malloc(sizeof(float) * (N + 1) * (N + 1));
    c->mz = malloc(sizeof(double) * 2 * (2 * N + 1));
    if (!c->slab || !c->mz) return 0;
    for (int i = 0; i <= N; i++) {
        double b = (double)i / N, ch = b < 1.0 ? sqrt(1.0 - b * b) : 0.0, acc = 0.0;
        c->slab[i * (N + 1)] = 0.0f;
        for (int l = 1; l <= N; l++) {
            acc += b < 1.0 ? line(s, b, ch * (l - 1) / N, ch * l / N, 0) : 0.0;
            c->slab[i * (N + 1) + l] = (float)acc;
        }
    }
    /* mz by Gauss-Legendre per interval of the density (a polynomial or smooth on each piece) */
    double acc = 0.0;
    for (int l = 0; l <= 2 * N; l++) {
        double t1 = -1.0 + (double)l / N;
        if (l > 0) {
            double t0 = t1 - 1.0 / N, part = 0.0;
            for (int q = 0; q < 8; q++) part += g8w[q] * rho_at(s, t0 + g8x[q] / N);
            acc += part / N;
        }
        c->mz[2 * l] = acc;
        c->mz[2 * l + 1] = rho_at(s, t1) / N; /* derivative per node spacing */
    }
    /* the total is 1 up to quadrature: scaled so the whole kernel is exactly 1 */
    double total = c->mz[2 * (2 * N)];
    for (int l = 0; l <= 2 * N; l++) c->mz[2 * l] /= total, c->mz[2 * l + 1] /= total;
    return 1;
}

static double mz_at(const lci_column *c, double z)
{
    if (z <= -1.0) return 0.0;
    if (z >= 1.0) return 1.0;
    double x = (z + 1.0) * LCI_COL_NZ;
    int j = (int)x;
    if (j >= 2 * LCI_COL_NZ) j = 2 * LCI_COL_NZ - 1;
    double r = x - j, r2 = r * r, r3 = r2 * r;
    const double *m = c->mz + 2 * j;
    return (2 * r3 - 3 * r2 + 1) * m[0] + (r3 - 2 * r2 + r) * m[1] + (-2 * r3 + 3 * r2) * m[2] + (r3 - r2) * m[3];
}

double lci_column_slab_mass(const lci_column *c, double z0, double z1) { return mz_at(c, z1) - mz_at(c, z0); }

/* sign(z) T(b, min(|z| / c(b), 1)), bilinear in (b, s). */
static float partial_up_to(const lci_column *c, float b, float z)
{
    if (!(b < 1.0f)) return 0.0f;
    float sg = z < 0.0f ? -1.0f : 1.0f, ch = sqrtf(1.0f - b * b), sz = ch > 0.0f ? fabsf(z) / ch : 1.0f;
    sz = sz > 1.0f ? 1.0f : sz;
    float xb = b * LCI_COL_NZ, xs = sz * LCI_COL_NZ;
    int i = (int)xb, l = (int)xs;
    if (i >= LCI_COL_NZ) i = LCI_COL_NZ - 1;
    if (l >= LCI_COL_NZ) l = LCI_COL_NZ - 1;
    float tb = xb - i, ts = xs - l;
    const float *r0 = c->slab + i * (LCI_COL_NZ + 1), *r1 = r0 + LCI_COL_NZ + 1;
    float a = r0[l] + ts * (r0[l + 1] - r0[l]), d = r1[l] + ts * (r1[l + 1] - r1[l]);
    return sg * (a + tb * (d - a));
}

float lci_column_partial(const lci_column *c, float b, float z0, float z1)
{
    if (!c->slab) /* the Gaussian is separable in z too */
        return lci_column_fq(c, b * b) * (float)lci_column_slab_mass(c, z0, z1);
    return partial_up_to(c, b, z1) - partial_up_to(c, b, z0);
}

static int shape_init(shape *s, lc_kernel kernel)
{
    memset(s, 0, sizeof *s);
    s->k = lci_sph_kernel_get(kernel);
    if (!s->k) return 0;
    s->norm = s->k->norm;
    if (kernel == LC_KERNEL_M4) s->kinks[0] = 0.5, s->nkinks = 1;
    if (kernel == LC_KERNEL_M5) s->kinks[0] = 0.2, s->kinks[1] = 0.6, s->nkinks = 2;
    if (kernel == LC_KERNEL_M6) s->kinks[0] = 1.0 / 3.0, s->kinks[1] = 2.0 / 3.0, s->nkinks = 2;
    return 1;
}

double lci_column_exact(const lci_column *c, double b)
{
    pthread_once(&gl_once, gl_init);
    if (c->kernel == LC_KERNEL_GAUSSIAN) return b < 1.0 ? c->f0 * exp(-0.5 * LCI_COL_GAUSS * LCI_COL_GAUSS * b * b) : 0.0;
    shape s;
    if (!shape_init(&s, c->kernel)) return 0.0;
    return column(&s, b, NULL);
}

/* The Gaussian: separable, so its tables are closed form. In units of the
 * support S = LCI_COL_GAUSS r, p(u) = G exp(-(G u)^2 / 2) / (sqrt(2 pi) erf(G / sqrt 2))
 * on [-1, 1] (G = LCI_COL_GAUSS), A(u) = erf(G u / sqrt 2) / (2 erf(G / sqrt 2)), rank 1. */
static int build_gauss(lci_column *c)
{
    const double G = LCI_COL_GAUSS, e = erf(G / sqrt(2.0));
    c->rank = 1;
    c->mu[0] = 1.0;
    c->err = 0.0;
    c->norm = pow(G / (sqrt(2.0 * M_PI) * e), 3.0);
    c->f0 = G * G / (2.0 * M_PI * e * e);
    c->fq = malloc(sizeof(float) * (LCI_COL_NQ + 2));
    c->mz = malloc(sizeof(double) * 2 * (2 * LCI_COL_NZ + 1));
    double *cum = malloc(sizeof(double) * (LCI_COL_NT + 1)), *phi = malloc(sizeof(double) * (LCI_COL_NT + 1));
    int ok = c->fq && c->mz && cum && phi;
    for (int j = 0; ok && j <= LCI_COL_NT; j++) {
        double u = (double)j / LCI_COL_NT;
        cum[j] = erf(G * u / sqrt(2.0)) / (2.0 * e);
        phi[j] = G * exp(-0.5 * G * G * u * u) / (sqrt(2.0 * M_PI) * e);
    }
    ok = ok && tables(c, 1, cum, phi, 1);
    free(cum), free(phi);
    if (!ok) return 0;
    /* centre sampling: the radial 2-D Gaussian (the corners of the square are beyond b = 1 and below 4e-6 of the peak) */
    for (int i = 0; i <= LCI_COL_NQ; i++) c->fq[i] = (float)(c->f0 * exp(-0.5 * G * G * (double)i / LCI_COL_NQ));
    c->fq[LCI_COL_NQ] = 0.0f, c->fq[LCI_COL_NQ + 1] = 0.0f;
    for (int l = 0; l <= 2 * LCI_COL_NZ; l++) {
        double z = -1.0 + (double)l / LCI_COL_NZ;
        c->mz[2 * l] = 0.5 + erf(G * z / sqrt(2.0)) / (2.0 * e);
        c->mz[2 * l + 1] = G * exp(-0.5 * G * G * z * z) / (sqrt(2.0 * M_PI) * e) / LCI_COL_NZ;
    }
    return 1;
}

static lci_column *build(lc_kernel kernel)
{
    pthread_once(&gl_once, gl_init);
    lci_column *c = calloc(1, sizeof *c);
    ftab *ft = NULL;
    shape s;
    if (!c) return NULL;
    c->kernel = kernel;
    if (kernel == LC_KERNEL_GAUSSIAN) {
        if (!build_gauss(c)) goto fail;
        return c;
    }
    if (!shape_init(&s, kernel) || !(ft = malloc(sizeof *ft))) goto fail;
    c->norm = s.norm;
    for (int j = 0; j <= NB; j++) ft->v[j] = column(&s, (double)j / NB, &ft->d[j]);
    ft->v[NB + 1] = ft->d[NB + 1] = 0.0;
    c->f0 = ft->v[0];
    c->fq = malloc(sizeof(float) * (LCI_COL_NQ + 2));
    if (!c->fq) goto fail;
    for (int i = 0; i <= LCI_COL_NQ; i++) c->fq[i] = (float)ftab_at(ft, sqrt((double)i / LCI_COL_NQ));
    c->fq[LCI_COL_NQ] = 0.0f, c->fq[LCI_COL_NQ + 1] = 0.0f;
    if (!build_separable(c, ft) || !build_slab(c, &s)) goto fail;
    free(ft);
    return c;
fail:
    free(ft);
    free(c->fq), free(c->tab), free(c->marg), free(c->slab), free(c->mz);
    free(c);
    return NULL;
}

/* One table per kernel, built on first use and never freed. */
static pthread_mutex_t cache_mu = PTHREAD_MUTEX_INITIALIZER;
static lci_column *cache[LC_KERNEL_WENDLAND_C6 + 1];

const lci_column *lci_column_get(lc_device *dev, lc_kernel kernel)
{
    if (!lc_kernel_name(kernel)) {
        lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "column kernel: kernel %d is not an lc_kernel value", (int)kernel);
        return NULL;
    }
    pthread_mutex_lock(&cache_mu);
    if (!cache[kernel]) cache[kernel] = build(kernel);
    lci_column *c = cache[kernel];
    pthread_mutex_unlock(&cache_mu);
    if (!c) lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "column kernel %s: out of memory for its tables", lc_kernel_name(kernel));
    return c;
}
