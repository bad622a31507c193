/* The encoder's polish sweep (encode_local.h): every RBF in turn gets its
 * weight, width and centre refitted by Levenberg-Marquardt against the
 * residual with its own term added back (block coordinate descent on all
 * 5m parameters of the set).
 *
 * Why (docs/bench/rbf.md, "What limited the greedy fit"): the greedy step
 * fixes each centre where it was placed (the cluster's weighted mean or its
 * point of largest error) and refits only the widths and weights of a few
 * neighbours. On neghip, at 2048 RBFs, refitting every width and weight
 * lowers the RMS from 4.9 % to 4.4 % in three sweeps, letting the centres
 * move too lowers it to 2.1 % in six: the placement, not the count, was
 * the limit.
 *
 * Each RBF's problem is exact and local: the term may move and widen only
 * as far as its cut sphere stays inside a region of radius grow * its cut
 * radius (REGION_GROW) around the old centre, so the error outside it
 * does not change. LM runs on a uniform subsample of at most lm_samples of
 * the region's samples; the new term is kept only if the error over every
 * sample of the region drops. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "host/encode/encode_local.h"

#define NP 5            /* w, ln s, centre x y z */
#define LM_ITERS 8
#define REGION_GROW 1.3 /* region radius / old cut radius */
#define MAX_CELLS_AXIS 128

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

/* Refits RBF i (its residuals updated without the cluster errors);
 * *improved = 1 when it changed. Reads and writes residuals only inside
 * the region, a sphere of radius region_radius(i) around its centre. */
static double region_radius(const lci_rbfs *R, size_t i) { return REGION_GROW * sqrt(LCI_ENC_CUT2) * R->s[i]; }

/* Replaces term (c0, s0, w0) by (c1, s1, w1) in the residuals (not the
 * cluster errors: recomputed after the sweep); returns the change of the
 * squared error. */
static double swap_term(lci_enc *e, const double *c0, double s0, double w0, const double *c1, double s1, double w1)
{
    double cut0 = LCI_ENC_CUT2 * s0 * s0, cut1 = LCI_ENC_CUT2 * s1 * s1, i0 = 0.5 / (s0 * s0), i1 = 0.5 / (s1 * s1);
    double dc = sqrt((c1[0] - c0[0]) * (c1[0] - c0[0]) + (c1[1] - c0[1]) * (c1[1] - c0[1]) + (c1[2] - c0[2]) * (c1[2] - c0[2]));
    double delta = 0.0;
    LCI_FOR_SAMPLES_NEAR(e, c0, fmax(sqrt(cut0), dc + sqrt(cut1)), j)
    {
        const float *x = e->p + 3 * j;
        double a0 = x[0] - c0[0], b0 = x[1] - c0[1], z0 = x[2] - c0[2], d0 = a0 * a0 + b0 * b0 + z0 * z0;
        double a1 = x[0] - c1[0], b1 = x[1] - c1[1], z1 = x[2] - c1[2], d1 = a1 * a1 + b1 * b1 + z1 * z1;
        if (d0 >= cut0 && d1 >= cut1) continue;
        double r = e->r[j] + (d0 < cut0 ? w0 * exp(-d0 * i0) : 0.0) - (d1 < cut1 ? w1 * exp(-d1 * i1) : 0.0);
        delta += r * r - e->r[j] * e->r[j];
        e->r[j] = r;
    }
    return delta;
}

static lc_status polish_one(lci_enc *e, size_t i, float *xs, double *ts, uint64_t *rng, int *improved)
{
    lci_rbfs *R = &e->R;
    double *c = R->c + 3 * i, s = R->s[i], w = R->w[i];
    *improved = 0;
    double rreg = region_radius(R, i);
    uint32_t *sel = NULL;
    size_t m = lci_enc_region(e, c, rreg, e->d.lm_samples, rng, &sel);
    if (m == (size_t)-1) return LC_ERROR_OUT_OF_MEMORY;
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
    /* exact over every sample the terms reach: kept only if the error drops
       (LM saw a subsample; rarely it does not), else swapped back */
    if (swap_term(e, c, s, w, nc, ns, nw) < 0.0) {
        memcpy(c, nc, sizeof nc);
        R->s[i] = ns, R->w[i] = nw, R->cut[i] = sqrt(LCI_ENC_CUT2) * ns;
        *improved = 1;
    } else
        swap_term(e, nc, ns, nw, c, s, w);
    return LC_OK;
}

/* ---------------------------------------------------------------- the sweep, in parallel */

/* The RBFs are sorted into cubic cells of edge L, at least twice the region
 * radius of each of them (the others, the widest tenth and those centred
 * outside the samples' box, go first, one by one). Cells of one colour
 * (the parity of their three indices) are two cells apart on some axis, so
 * their RBFs' regions are disjoint: the cells of a colour are refitted in
 * parallel, each cell's RBFs in index order, each cell with its own random
 * state (the result does not depend on the thread count). */
typedef struct sweep {
    lci_enc *e;
    int nc[3];
    size_t *order, *cstart; /* RBFs of cell c: order[cstart[c] .. cstart[c + 1]) */
    size_t *tasks;          /* the cells of the current colour */
    float *xs;              /* per worker: 3 lm_samples */
    double *ts;             /* per worker: lm_samples */
    size_t *changed;        /* per worker */
    int *failed;            /* per worker */
    uint64_t seed;
} sweep;

static uint64_t mix(uint64_t x)
{
    x ^= x >> 33, x *= 0xff51afd7ed558ccdull, x ^= x >> 33, x *= 0xc4ceb9fe1a85ec53ull, x ^= x >> 33;
    return x ? x : 1;
}

static void run_cell(sweep *w, size_t cell, int worker)
{
    uint64_t rng = mix(w->seed ^ (cell + 1) * 0x9E3779B97F4A7C15ull);
    size_t cap = w->e->d.lm_samples;
    for (size_t k = w->cstart[cell]; k < w->cstart[cell + 1] && !w->failed[worker]; k++) {
        int imp = 0;
        if (polish_one(w->e, w->order[k], w->xs + 3 * cap * (size_t)worker, w->ts + cap * (size_t)worker, &rng, &imp))
            w->failed[worker] = 1;
        w->changed[worker] += (size_t)imp;
    }
}

static void cell_task(void *ctx, int task, int worker)
{
    sweep *w = ctx;
    run_cell(w, w->tasks[task], worker);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Cell edge: twice the 90th percentile of the region radii, at least a
 * bucket and 1/MAX_CELLS_AXIS of the box. */
static double cell_edge(const lci_enc *e, double *tmp)
{
    size_t m = e->R.m;
    for (size_t i = 0; i < m; i++) tmp[i] = region_radius(&e->R, i);
    qsort(tmp, m, sizeof(double), cmp_double);
    double ext = 0.0;
    for (int a = 0; a < 3; a++) ext = fmax(ext, e->hi[a] - e->lo[a]);
    return fmax(fmax(2.0 * tmp[(m * 9) / 10], e->bcell), ext / MAX_CELLS_AXIS);
}

lc_status lci_enc_polish(lci_enc *e, size_t *changed)
{
    size_t m = e->R.m, cap = e->d.lm_samples;
    int nw = lci_pool_threads(e->dev->pool);
    sweep w = {.e = e, .seed = mix(e->rng += 0x9E3779B97F4A7C15ull)};
    double *tmp = malloc(sizeof(double) * (m ? m : 1));
    size_t *cell = malloc(sizeof(size_t) * (m ? m : 1));
    w.order = malloc(sizeof(size_t) * (m ? m : 1));
    w.xs = malloc(sizeof(float) * 3 * cap * (size_t)nw), w.ts = malloc(sizeof(double) * cap * (size_t)nw);
    w.changed = calloc((size_t)nw, sizeof(size_t)), w.failed = calloc((size_t)nw, sizeof(int));
    lc_status st = LC_OK;
    if (!tmp || !cell || !w.order || !w.xs || !w.ts || !w.changed || !w.failed) goto oom;
    double L = m ? cell_edge(e, tmp) : 1.0;
    size_t ncells = 1;
    for (int a = 0; a < 3; a++) {
        w.nc[a] = (int)fmin(MAX_CELLS_AXIS + 1.0, floor((e->hi[a] - e->lo[a]) / L) + 1.0);
        ncells *= (size_t)w.nc[a];
    }
    /* cell ncells: the serial list */
    w.cstart = calloc(ncells + 2, sizeof(size_t)), w.tasks = malloc(sizeof(size_t) * ncells);
    if (!w.cstart || !w.tasks) goto oom;
    for (size_t i = 0; i < m; i++) {
        const double *c = e->R.c + 3 * i;
        size_t id = 0;
        int inside = 2.0 * region_radius(&e->R, i) <= L;
        for (int a = 2; a >= 0 && inside; a--) {
            double t = (c[a] - e->lo[a]) / L;
            inside = t >= 0.0 && t < (double)w.nc[a];
            id = id * (size_t)w.nc[a] + (size_t)(inside ? (int)t : 0);
        }
        cell[i] = inside ? id : ncells;
        w.cstart[cell[i] + 1]++;
    }
    for (size_t c = 0; c <= ncells; c++) w.cstart[c + 1] += w.cstart[c];
    for (size_t i = 0; i < m; i++) w.order[w.cstart[cell[i]]++] = i; /* stable: index order per cell */
    for (size_t c = ncells + 1; c > 0; c--) w.cstart[c] = w.cstart[c - 1];
    w.cstart[0] = 0;
    run_cell(&w, ncells, 0);
    for (int colour = 0; colour < 8 && !w.failed[0]; colour++) {
        size_t nt = 0;
        for (size_t c = 0; c < ncells; c++) {
            size_t x = c % (size_t)w.nc[0], y = c / (size_t)w.nc[0] % (size_t)w.nc[1], z = c / ((size_t)w.nc[0] * (size_t)w.nc[1]);
            if ((int)((x & 1) | (y & 1) << 1 | (z & 1) << 2) == colour && w.cstart[c + 1] > w.cstart[c]) w.tasks[nt++] = c;
        }
        if (nt) lci_pool_run(e->dev->pool, (int)nt, cell_task, &w);
        for (int k = 1; k < nw; k++) w.failed[0] |= w.failed[k];
    }
    if (w.failed[0]) goto oom;
    /* the cluster errors, from the residuals */
    for (size_t c = 0; c < e->ncl; c++) e->cl[c].sse = 0.0;
    for (size_t j = 0; j < e->n; j++) e->cl[e->cid[j]].sse += e->r[j] * e->r[j];
    if (changed) {
        *changed = 0;
        for (int k = 0; k < nw; k++) *changed += w.changed[k];
    }
    goto done;
oom:
    st = lci_error(e->dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_encode: out of memory");
done:
    free(tmp), free(cell), free(w.order), free(w.xs), free(w.ts), free(w.changed), free(w.failed), free(w.cstart), free(w.tasks);
    return st;
}
