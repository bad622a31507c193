/* The encoder's samples in buckets and the local refit that adds one RBF
 * (encode_local.h; the paper's sec. 4 step, with its cost bounded). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "host/encode/encode_local.h"

#define MAX_BUCKETS_AXIS 256

lc_status lci_enc_buckets(lci_enc *e, const float *p, const float *v, const uint32_t *pick)
{
    size_t n = e->n;
    for (int a = 0; a < 3; a++) e->lo[a] = INFINITY, e->hi[a] = -INFINITY;
    for (size_t k = 0; k < n; k++)
        for (int a = 0; a < 3; a++) {
            double x = p[3 * (size_t)pick[k] + a];
            e->lo[a] = fmin(e->lo[a], x), e->hi[a] = fmax(e->hi[a], x);
        }
    double vol = 1.0, diag2 = 0.0;
    int dims = 0;
    for (int a = 0; a < 3; a++) {
        double ext = e->hi[a] - e->lo[a];
        diag2 += ext * ext;
        if (ext > 0.0) vol *= ext, dims++;
    }
    /* sample spacing h, buckets of about 8 samples */
    double h = dims ? pow(vol / (double)n, 1.0 / dims) : 1.0;
    e->bcell = dims ? pow(vol / fmax(1.0, (double)n / 8.0), 1.0 / dims) : 1.0;
    size_t nb = 1;
    for (int a = 0; a < 3; a++) {
        e->bn[a] = (int)fmin(MAX_BUCKETS_AXIS, floor((e->hi[a] - e->lo[a]) / e->bcell) + 1.0);
        nb *= (size_t)e->bn[a];
    }
    e->smin = 0.25 * h;
    e->smax = fmax(sqrt(diag2), h);
    e->p = malloc(sizeof(float) * 3 * n), e->v = malloc(sizeof(float) * n), e->r = malloc(sizeof(double) * n);
    e->cid = malloc(sizeof(uint32_t) * n), e->idx = malloc(sizeof(uint32_t) * n);
    e->bstart = calloc(nb + 1, sizeof(uint32_t));
    e->capcl = 64, e->cl = malloc(sizeof(lci_cluster) * e->capcl);
    if (!e->p || !e->v || !e->r || !e->cid || !e->idx || !e->bstart || !e->cl || lci_rbfs_reserve(&e->R, 64))
        return lci_error(e->dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_encode: out of memory for %zu samples", n);
    for (size_t k = 0; k < n; k++) { /* counting sort by bucket; cid holds the bucket for now */
        const float *x = p + 3 * (size_t)pick[k];
        size_t c = 0;
        for (int a = 2; a >= 0; a--) {
            int i = (int)((x[a] - e->lo[a]) / e->bcell);
            c = c * (size_t)e->bn[a] + (size_t)(i < 0 ? 0 : i >= e->bn[a] ? e->bn[a] - 1 : i);
        }
        e->cid[k] = (uint32_t)c;
        e->bstart[c + 1]++;
    }
    for (size_t c = 0; c < nb; c++) e->bstart[c + 1] += e->bstart[c];
    for (size_t k = 0; k < n; k++) e->idx[k] = e->bstart[e->cid[k]]++;
    for (size_t c = nb; c > 0; c--) e->bstart[c] = e->bstart[c - 1];
    e->bstart[0] = 0;
    double mean = 0.0;
    for (size_t k = 0; k < n; k++) {
        uint32_t j = e->idx[k];
        memcpy(e->p + 3 * (size_t)j, p + 3 * (size_t)pick[k], sizeof(float) * 3);
        e->v[j] = v[pick[k]];
        mean += v[pick[k]];
    }
    /* the bias starts as the least-squares constant, the mean */
    e->R.bias = mean / (double)n;
    for (size_t j = 0; j < n; j++) e->r[j] = e->v[j] - e->R.bias, e->cid[j] = 0, e->idx[j] = (uint32_t)j;
    e->ncl = 1;
    e->cl[0] = (lci_cluster){.a = 0, .b = n};
    for (size_t j = 0; j < n; j++) e->cl[0].sse += e->r[j] * e->r[j];
    return LC_OK;
}

void lci_enc_free(lci_enc *e)
{
    free(e->p), free(e->v), free(e->r), free(e->cid), free(e->idx), free(e->bstart), free(e->cl);
    lci_rbfs_free(&e->R);
}

double lci_enc_apply_term(lci_enc *e, const double *c, double s, double w, double sign, int clusters)
{
    double cut2 = LCI_ENC_CUT2 * s * s, inv = 1.0 / (2.0 * s * s), delta = 0.0;
    LCI_FOR_SAMPLES_NEAR(e, c, sqrt(cut2), j)
    {
        const float *x = e->p + 3 * j;
        double dx = x[0] - c[0], dy = x[1] - c[1], dz = x[2] - c[2];
        double d2 = dx * dx + dy * dy + dz * dz;
        if (d2 >= cut2) continue;
        double old = e->r[j], r = old - sign * w * exp(-d2 * inv);
        e->r[j] = r;
        if (clusters) e->cl[e->cid[j]].sse += r * r - old * old;
        delta += r * r - old * old;
    }
    return delta;
}

/* ---------------------------------------------------------------- the local problem */

typedef struct local {
    int k;              /* RBFs in the local set */
    size_t id[LCI_ENC_MAX_LOCAL];
    int free_w[LCI_ENC_MAX_LOCAL]; /* 1: LM varies its width */
    double s[LCI_ENC_MAX_LOCAL], w[LCI_ENC_MAX_LOCAL], smax[LCI_ENC_MAX_LOCAL];
    size_t m;           /* samples of the least squares */
    double *d2;         /* m x k squared distances */
    double *t;          /* m targets: residual plus the local set's terms */
    size_t stride;      /* LM uses every stride-th of them */
} local;

static double gauss(double d2, double s) { return d2 < LCI_ENC_CUT2 * s * s ? exp(-d2 / (2.0 * s * s)) : 0.0; }

/* The local set: the new RBF q and up to K-1 RBFs nearest to mu in units
 * of their joint width, among those whose cut sphere lies inside the region
 * (a sphere of radius rreg at mu): changing them changes the residuals of
 * region samples only, so the least squares over the region is the whole
 * problem. Wider RBFs wait for the global refit. smax[a] keeps each cut
 * sphere inside the region while LM varies the widths. */
static void pick_local(const lci_enc *e, size_t q, const double *mu, double rreg, local *L)
{
    const lci_rbfs *R = &e->R;
    double key[LCI_ENC_MAX_LOCAL], dist[LCI_ENC_MAX_LOCAL];
    L->k = 1, L->id[0] = q, key[0] = -1.0, dist[0] = 0.0;
    int K = e->d.local_rbfs;
    for (size_t i = 0; i < q; i++) {
        const double *c = R->c + 3 * i;
        double d = sqrt((c[0] - mu[0]) * (c[0] - mu[0]) + (c[1] - mu[1]) * (c[1] - mu[1]) + (c[2] - mu[2]) * (c[2] - mu[2]));
        if (d + R->cut[i] >= rreg) continue;
        double kv = d / (R->s[i] + R->s[q]);
        if (L->k == K && kv >= key[K - 1]) continue;
        int at = L->k < K ? L->k++ : K - 1;
        while (at > 1 && key[at - 1] > kv) key[at] = key[at - 1], dist[at] = dist[at - 1], L->id[at] = L->id[at - 1], at--;
        key[at] = kv, dist[at] = d, L->id[at] = i;
    }
    for (int a = 0; a < L->k; a++) {
        size_t i = L->id[a];
        L->free_w[a] = 1;
        L->smax[a] = fmin(e->smax, (rreg - dist[a]) / sqrt(LCI_ENC_CUT2));
        L->s[a] = fmin(R->s[i], L->smax[a]), L->w[a] = R->w[i];
    }
}

/* Samples of the region (a sphere of radius rreg): all of them up to cap,
 * else a uniform subsample of cap. The cost is bounded whatever the
 * region's size: when its bucket box holds B > 4 cap samples, only every
 * (B / 4 cap)-th of the box's samples (from a random offset) is looked at
 * (about 2 cap of them fall inside the sphere), and reservoir sampling
 * keeps cap of those. Returns the count. */
size_t lci_enc_region(const lci_enc *e, const double *mu, double rreg, size_t cap, uint64_t *rng, uint32_t **out)
{
    int i0[3], i1[3];
    lci_enc_bucket_box(e, mu, rreg, i0, i1);
    size_t box = 0;
    for (int z = i0[2]; z <= i1[2]; z++)
        for (int y = i0[1]; y <= i1[1]; y++) {
            size_t b = ((size_t)z * (size_t)e->bn[1] + (size_t)y) * (size_t)e->bn[0];
            box += e->bstart[b + (size_t)i1[0] + 1] - e->bstart[b + (size_t)i0[0]];
        }
    size_t step = box > 4 * cap ? box / (4 * cap) : 1, skip = (size_t)(lci_enc_rand01(rng) * (double)step);
    size_t want = box < cap ? box : cap, k = 0, seen = 0;
    uint32_t *sel = malloc(sizeof(uint32_t) * (want ? want : 1));
    if (!sel) return (size_t)-1;
    double r2 = rreg * rreg;
    for (int z = i0[2]; z <= i1[2]; z++)
        for (int y = i0[1]; y <= i1[1]; y++) {
            size_t b = ((size_t)z * (size_t)e->bn[1] + (size_t)y) * (size_t)e->bn[0];
            size_t j = e->bstart[b + (size_t)i0[0]] + skip, end = e->bstart[b + (size_t)i1[0] + 1];
            for (; j < end; j += step) {
                const float *x = e->p + 3 * j;
                double dx = x[0] - mu[0], dy = x[1] - mu[1], dz = x[2] - mu[2];
                if (dx * dx + dy * dy + dz * dz >= r2) continue;
                seen++;
                if (k < want) sel[k++] = (uint32_t)j;
                else {
                    size_t t = (size_t)(lci_enc_rand01(rng) * (double)seen);
                    if (t < want) sel[t] = (uint32_t)j;
                }
            }
            skip = j - end;
        }
    *out = sel;
    return k;
}

/* Weights of the local set by least squares (dgelsd) on all m samples. */
static int local_lls(local *L, double *a, double *b)
{
    size_t m = L->m;
    for (int i = 0; i < L->k; i++)
        for (size_t j = 0; j < m; j++) a[j + (size_t)i * m] = gauss(L->d2[j * (size_t)L->k + (size_t)i], L->s[i]);
    memcpy(b, L->t, sizeof(double) * m);
    if (lci_lls((int)m, L->k, a, b)) return -1;
    for (int i = 0; i < L->k; i++)
        if (!isfinite(b[i])) return -1;
    memcpy(L->w, b, sizeof(double) * (size_t)L->k);
    return 0;
}

static double local_sse(const local *L, const double *s, size_t stride)
{
    double sse = 0.0;
    for (size_t j = 0; j < L->m; j += stride) {
        double e = L->t[j];
        for (int i = 0; i < L->k; i++) e -= L->w[i] * gauss(L->d2[j * (size_t)L->k + (size_t)i], s[i]);
        sse += e * e;
    }
    return sse;
}

/* Levenberg-Marquardt on the log widths of the free RBFs (weights fixed),
 * minimising the squared error over every stride-th sample. */
static void local_lm(const lci_enc *e, local *L)
{
    int fi[LCI_ENC_MAX_LOCAL], q = 0;
    for (int i = 0; i < L->k; i++)
        if (L->free_w[i]) fi[q++] = i;
    double lam = 1e-3, sse = local_sse(L, L->s, L->stride);
    double lmin = log(e->smin);
    for (int it = 0; it < 20 && lam < 1e10; it++) {
        double H[LCI_ENC_MAX_LOCAL * LCI_ENC_MAX_LOCAL] = {0}, g[LCI_ENC_MAX_LOCAL] = {0}, J[LCI_ENC_MAX_LOCAL];
        for (size_t j = 0; j < L->m; j += L->stride) {
            const double *d2 = L->d2 + j * (size_t)L->k;
            double r = L->t[j];
            for (int i = 0; i < L->k; i++) r -= L->w[i] * gauss(d2[i], L->s[i]);
            for (int u = 0; u < q; u++) { /* d r / d ln s = -w phi d^2 / s^2 */
                int i = fi[u];
                J[u] = -L->w[i] * gauss(d2[i], L->s[i]) * d2[i] / (L->s[i] * L->s[i]);
            }
            for (int u = 0; u < q; u++) {
                g[u] += J[u] * r;
                for (int v = 0; v < q; v++) H[u * q + v] += J[u] * J[v];
            }
        }
        for (;;) {
            double A[LCI_ENC_MAX_LOCAL * LCI_ENC_MAX_LOCAL], delta[LCI_ENC_MAX_LOCAL], s[LCI_ENC_MAX_LOCAL];
            memcpy(A, H, sizeof(double) * (size_t)(q * q));
            for (int u = 0; u < q; u++) A[u * q + u] += lam * fmax(H[u * q + u], 1e-300), delta[u] = -g[u];
            if (lci_spd_solve(q, A, delta)) {
                lam *= 10.0;
                if (lam >= 1e10) return;
                continue;
            }
            memcpy(s, L->s, sizeof(double) * (size_t)L->k);
            for (int u = 0; u < q; u++)
                s[fi[u]] = exp(fmin(fmax(log(L->s[fi[u]]) + delta[u], lmin), log(L->smax[fi[u]])));
            double trial = local_sse(L, s, L->stride);
            if (trial < sse) {
                double gain = (sse - trial) / fmax(sse, 1e-300);
                memcpy(L->s, s, sizeof(double) * (size_t)L->k);
                sse = trial, lam *= 0.3;
                if (gain < 1e-6) return;
                break;
            }
            lam *= 10.0;
            if (lam >= 1e10) return;
        }
    }
}

/* Sets the local set's parameters into the RBFs and the residuals (sign 1),
 * or takes the old ones back (old arrays). */
static void commit(lci_enc *e, const local *L, const double *olds, const double *oldw)
{
    lci_rbfs *R = &e->R;
    for (int a = 0; a < L->k; a++) {
        size_t i = L->id[a];
        if (olds[a] == L->s[a] && oldw[a] == L->w[a]) continue;
        if (oldw[a] != 0.0) lci_enc_apply_term(e, R->c + 3 * i, olds[a], oldw[a], -1.0, 1); /* take the old term back */
        R->s[i] = L->s[a], R->w[i] = L->w[a], R->cut[i] = sqrt(LCI_ENC_CUT2) * L->s[a];
        lci_enc_apply_term(e, R->c + 3 * i, L->s[a], L->w[a], 1.0, 1);
    }
}

lc_status lci_enc_add(lci_enc *e, const double mu[3], double s0, int *added)
{
    *added = 0;
    lci_rbfs *R = &e->R;
    if (lci_rbfs_reserve(R, R->m + 1 > R->cap ? 2 * R->cap : R->cap))
        return lci_error(e->dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_encode: out of memory");
    size_t q = R->m;
    memcpy(R->c + 3 * q, mu, sizeof(double) * 3);
    R->s[q] = s0, R->w[q] = 0.0, R->cut[q] = sqrt(LCI_ENC_CUT2) * s0;
    /* the region: twice the new RBF's cut radius, so its width may double */
    double rreg = fmax(2.0 * sqrt(LCI_ENC_CUT2) * s0, 8.0 * e->smin);
    local L = {0};
    pick_local(e, q, mu, rreg, &L);
    uint32_t *sel = NULL;
    size_t m = lci_enc_region(e, mu, rreg, 4 * e->d.lm_samples, &e->rng, &sel);
    if (m == (size_t)-1) return lci_error(e->dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_encode: out of memory");
    if (m < (size_t)L.k + 1) L.k = m > 1 ? (int)m - 1 : 0;
    if (L.k == 0) {
        free(sel);
        return LC_OK;
    }
    L.m = m;
    L.stride = m > e->d.lm_samples ? (m + e->d.lm_samples - 1) / e->d.lm_samples : 1;
    L.d2 = malloc(sizeof(double) * m * (size_t)L.k), L.t = malloc(sizeof(double) * m);
    double *a = malloc(sizeof(double) * m * (size_t)L.k), *b = malloc(sizeof(double) * m);
    if (!L.d2 || !L.t || !a || !b) {
        free(sel), free(L.d2), free(L.t), free(a), free(b);
        return lci_error(e->dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_encode: out of memory");
    }
    for (size_t j = 0; j < m; j++) {
        const float *x = e->p + 3 * (size_t)sel[j];
        L.t[j] = e->r[sel[j]];
        for (int i = 0; i < L.k; i++) {
            const double *c = R->c + 3 * L.id[i];
            double d2 = (x[0] - c[0]) * (x[0] - c[0]) + (x[1] - c[1]) * (x[1] - c[1]) + (x[2] - c[2]) * (x[2] - c[2]);
            L.d2[j * (size_t)L.k + (size_t)i] = d2;
            L.t[j] += L.w[i] * gauss(d2, L.s[i]);
        }
    }
    double olds[LCI_ENC_MAX_LOCAL], oldw[LCI_ENC_MAX_LOCAL];
    memcpy(olds, L.s, sizeof olds), memcpy(oldw, L.w, sizeof oldw);
    double before = local_sse(&L, L.s, 1); /* new weight 0: the current error */
    int ok = local_lls(&L, a, b) == 0;
    if (ok) local_lm(e, &L);
    ok = ok && local_lls(&L, a, b) == 0;
    double after_local = ok ? local_sse(&L, L.s, 1) : -1.0;
    ok = ok && after_local < before * (1.0 - 1e-9) && L.w[0] != 0.0;
    for (int i = 0; ok && i < L.k; i++) ok = fabs(L.w[i]) <= LCI_ENC_MAX_WEIGHT * (e->vhi - e->vlo);
    if (ok) {
        double total = lci_enc_total_sse(e);
        R->m++;
        commit(e, &L, olds, oldw);
        if (lci_enc_total_sse(e) < total) {
            *added = 1;
        } else { /* the neighbours' changes cost more outside the region than they won */
            local back = L;
            memcpy(back.s, olds, sizeof olds), memcpy(back.w, oldw, sizeof oldw);
            commit(e, &back, L.s, L.w);
            R->m--;
        }
    }
    free(sel), free(L.d2), free(L.t), free(a), free(b);
    return LC_OK;
}
