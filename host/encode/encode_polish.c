/* The encoder's polish sweep (encode_local.h): every RBF in turn gets its
 * weight, width and centre refitted by Levenberg-Marquardt against the
 * residual with its own term added back (block coordinate descent on all
 * 5m parameters of the set).
 *
 * Why (docs/bench/rbf.md, "What limits the greedy fit"): the greedy step
 * fixes each centre where it was placed (the cluster's weighted mean or its
 * point of largest error) and refits only the widths and weights of a few
 * neighbours. On neghip, at 2048 RBFs, refitting every width and weight
 * lowers the RMS from 4.9 % to 4.4 % in three sweeps, letting the centres
 * move too lowers it to 2.1 % in six: the placement, not the count, was
 * the limit.
 *
 * Each RBF's problem is exact and local: the term may move and widen only
 * as far as its cut sphere stays inside a region of radius grow * its cut
 * radius around the old centre, so the squared error outside that region
 * does not change. LM runs on a uniform subsample of at most lm_samples of
 * the region's samples; the new term is kept only if the error over every
 * sample of the region (measured while applying it) drops. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "host/encode/encode_local.h"

#define NP 5            /* w, ln s, centre x y z */
#define LM_ITERS 8
#define REGION_GROW 1.3 /* region radius / old cut radius */

typedef struct one {
    size_t m;
    const float *x; /* 3m, relative to the old centre */
    const double *t; /* m targets: residual plus the old term */
    double rreg, smin, smax, wmax;
} one;

/* The squared error of term p over the subsample. */
static double one_sse(const one *o, const double *p)
{
    double s2 = exp(2.0 * p[1]), cut2 = LCI_ENC_CUT2 * s2, inv = 0.5 / s2, sse = 0.0;
    for (size_t j = 0; j < o->m; j++) {
        const float *x = o->x + 3 * j;
        double dx = x[0] - p[2], dy = x[1] - p[3], dz = x[2] - p[4], d2 = dx * dx + dy * dy + dz * dz;
        double r = o->t[j] - (d2 < cut2 ? p[0] * exp(-d2 * inv) : 0.0);
        sse += r * r;
    }
    return sse;
}

/* Keeps the term inside the region and its weight and width in bounds. */
static void one_clamp(const one *o, double *p)
{
    p[0] = fmin(fmax(p[0], -o->wmax), o->wmax);
    p[1] = fmin(fmax(p[1], log(o->smin)), log(o->smax));
    double room = o->rreg - sqrt(LCI_ENC_CUT2) * exp(p[1]);
    double d = sqrt(p[2] * p[2] + p[3] * p[3] + p[4] * p[4]);
    if (d > room) {
        double k = room > 0.0 ? room / d : 0.0;
        p[2] *= k, p[3] *= k, p[4] *= k;
    }
}

/* LM on p (NP parameters, centre relative to the old one). */
static void one_lm(const one *o, double *p)
{
    double lam = 1e-3, sse = one_sse(o, p);
    for (int it = 0; it < LM_ITERS; it++) {
        double H[NP * NP] = {0}, g[NP] = {0};
        double s2 = exp(2.0 * p[1]), cut2 = LCI_ENC_CUT2 * s2, inv = 0.5 / s2, is2 = 1.0 / s2;
        for (size_t j = 0; j < o->m; j++) {
            const float *x = o->x + 3 * j;
            double dx = x[0] - p[2], dy = x[1] - p[3], dz = x[2] - p[4], d2 = dx * dx + dy * dy + dz * dz;
            if (d2 >= cut2) continue;
            double G = exp(-d2 * inv), wg = p[0] * G * is2, r = o->t[j] - p[0] * G;
            double J[NP] = {G, wg * d2, wg * dx, wg * dy, wg * dz}; /* d model / d p */
            for (int a = 0; a < NP; a++) {
                g[a] += J[a] * r;
                for (int b = a; b < NP; b++) H[a * NP + b] += J[a] * J[b];
            }
        }
        for (int a = 0; a < NP; a++)
            for (int b = 0; b < a; b++) H[a * NP + b] = H[b * NP + a];
        int better = 0;
        while (!better && lam < 1e8) {
            double A[NP * NP], q[NP];
            memcpy(A, H, sizeof A), memcpy(q, g, sizeof q);
            for (int a = 0; a < NP; a++) A[a * NP + a] += lam * fmax(H[a * NP + a], 1e-300);
            if (lci_spd_solve(NP, A, q)) {
                lam *= 10.0;
                continue;
            }
            double trial[NP];
            for (int a = 0; a < NP; a++) trial[a] = p[a] + q[a];
            one_clamp(o, trial);
            double t = one_sse(o, trial);
            if (t < sse) {
                double gain = (sse - t) / fmax(sse, 1e-300);
                memcpy(p, trial, sizeof trial);
                sse = t, lam *= 0.3, better = 1;
                if (gain < 1e-5) return;
            } else
                lam *= 10.0;
        }
        if (!better) return;
    }
}

/* Refits RBF i; *improved = 1 when it changed. */
static lc_status polish_one(lci_enc *e, size_t i, float *xs, double *ts, int *improved)
{
    lci_rbfs *R = &e->R;
    double *c = R->c + 3 * i, s = R->s[i], w = R->w[i];
    *improved = 0;
    double rreg = REGION_GROW * sqrt(LCI_ENC_CUT2) * s;
    uint32_t *sel = NULL;
    size_t m = lci_enc_region(e, c, rreg, e->d.lm_samples, &sel);
    if (m == (size_t)-1) return lci_error(e->dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_encode: out of memory");
    if (m < 2 * NP) {
        free(sel);
        return LC_OK;
    }
    double cut2 = LCI_ENC_CUT2 * s * s, inv = 0.5 / (s * s);
    for (size_t j = 0; j < m; j++) {
        const float *x = e->p + 3 * (size_t)sel[j];
        float *y = xs + 3 * j;
        for (int a = 0; a < 3; a++) y[a] = (float)(x[a] - c[a]);
        double d2 = (double)y[0] * y[0] + (double)y[1] * y[1] + (double)y[2] * y[2];
        ts[j] = e->r[sel[j]] + (d2 < cut2 ? w * exp(-d2 * inv) : 0.0);
    }
    free(sel);
    one o = {m, xs, ts, rreg, e->smin, fmin(e->smax, rreg / sqrt(LCI_ENC_CUT2)),
             LCI_ENC_MAX_WEIGHT * (e->vhi - e->vlo)};
    double p[NP] = {w, log(s), 0.0, 0.0, 0.0};
    one_clamp(&o, p);
    one_lm(&o, p);
    double nc[3] = {c[0] + p[2], c[1] + p[3], c[2] + p[4]}, ns = exp(p[1]), nw = p[0];
    if (nw == w && ns == s && p[2] == 0.0 && p[3] == 0.0 && p[4] == 0.0) return LC_OK;
    /* exact over the region: the old term back, the new one in */
    double delta = lci_enc_apply_term(e, c, s, w, -1.0) + lci_enc_apply_term(e, nc, ns, nw, 1.0);
    if (delta < 0.0) {
        memcpy(c, nc, sizeof nc);
        R->s[i] = ns, R->w[i] = nw, R->cut[i] = sqrt(LCI_ENC_CUT2) * ns;
        *improved = 1;
    } else {
        lci_enc_apply_term(e, nc, ns, nw, -1.0);
        lci_enc_apply_term(e, c, s, w, 1.0);
    }
    return LC_OK;
}

lc_status lci_enc_polish(lci_enc *e, size_t *changed)
{
    size_t cap = e->d.lm_samples;
    float *xs = malloc(sizeof(float) * 3 * cap);
    double *ts = malloc(sizeof(double) * cap);
    lc_status s = xs && ts ? LC_OK : lci_error(e->dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_encode: out of memory");
    size_t n = 0;
    for (size_t i = 0; s == LC_OK && i < e->R.m; i++) {
        int imp = 0;
        s = polish_one(e, i, xs, ts, &imp);
        n += (size_t)imp;
    }
    free(xs), free(ts);
    if (changed) *changed = n;
    return s;
}
