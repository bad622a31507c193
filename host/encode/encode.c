/* lc_rbf_encode: fitting an RBF set to samples (Jang et al. 2004 sec. 4).
 *
 * The samples are split into clusters by PCA: each iteration takes the
 * cluster of largest squared error, centres a new Gaussian in it (the
 * |residual|-weighted mean, or the sample of largest |residual|), splits it
 * in two across its principal axis, and refits locally: weights of the new
 * RBF and its nearest overlapping neighbours by linear least squares
 * (LAPACKE dgelsd), the widths of those inside the neighbourhood by
 * Levenberg-Marquardt on the mean squared error (weights fixed), then the
 * weights again. The residuals change only inside the supports of the
 * refitted RBFs. Whenever the count has grown by an eighth and at the end,
 * all weights and the bias are refitted together (normal equations, LAPACKE
 * dposv, up to 4096 RBFs). Whenever it has grown by a quarter, a polish
 * sweep (encode_polish.c) refits every RBF's weight, width and centre in
 * turn against the residual: the greedy step alone leaves each centre where
 * it was placed and never revisits old widths, and plateaus (neghip: 3.8 %
 * RMS at 2048 RBFs without, 2 % at 1106 with; docs/bench/rbf.md). When
 * max_rbfs is reached short of the target, up to 8 more sweeps run while
 * each still lowers the error by 0.5 %.
 *
 * Bounded cost per iteration: the fit sees at most fit_samples samples (a
 * fixed-seed uniform subsample), LM at most lm_samples of the neighbourhood
 * and the local least squares at most 4 lm_samples, the local set at most
 * local_rbfs RBFs; only the residual update touches every sample in the
 * refitted supports. A polish sweep's LM sees at most lm_samples samples
 * per RBF. The report is over every fitted sample. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "host/encode/encode_local.h"

#define DEFAULT_MAX_ERROR 0.02f
#define DEFAULT_MAX_RBFS 4096 /* as lanecast.h and `lanecast encode --help` say */
#define DEFAULT_FIT_SAMPLES ((size_t)1 << 21)
#define DEFAULT_LM_SAMPLES 2048
#define DEFAULT_LOCAL 4
#define GLOBAL_SAMPLES ((size_t)1 << 18)
#define GLOBAL_MAX_RBFS 4096 /* normal equations of (m+1)^2 doubles */
#define FINAL_SWEEPS 8

static uint64_t rng_next(uint64_t *s)
{
    uint64_t x = *s;
    x ^= x << 13, x ^= x >> 7, x ^= x << 17;
    return *s = x;
}

double lci_enc_rand01(uint64_t *state) { return (double)(rng_next(state) >> 11) * (1.0 / 9007199254740992.0); }

double lci_enc_rand(lci_enc *e) { return lci_enc_rand01(&e->rng); }

static int in_fit(const lc_rbf_encode_desc *d, float v)
{
    return !d->fit_range_set || (v >= d->fit_range[0] && v <= d->fit_range[1]);
}

/* ---------------------------------------------------------------- setup */

static lc_status check_desc(lc_device *dev, const lc_samples *sm, const lc_rbf_encode_desc *in, lc_rbf_encode_desc *d,
                            size_t *nfit)
{
    *d = in ? *in : (lc_rbf_encode_desc){0};
    const char *f = "lc_rbf_encode";
    if (!(d->max_error >= 0.0f && d->max_error < 1.0f))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: max_error %g is not in [0, 1)", f, (double)d->max_error);
    if (d->centre != LC_RBF_CENTRE_MEAN && d->centre != LC_RBF_CENTRE_MAXERR)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: centre %d is not mean (0) or maxerr (1)", f, (int)d->centre);
    if (d->fit_range_set && !(isfinite(d->fit_range[0]) && isfinite(d->fit_range[1]) && d->fit_range[0] <= d->fit_range[1]))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: fit range %g,%g: expected finite LO <= HI", f,
                         (double)d->fit_range[0], (double)d->fit_range[1]);
    if (d->local_rbfs < 0 || d->local_rbfs > LCI_ENC_MAX_LOCAL)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: local_rbfs %d is not in 0..%d", f, d->local_rbfs,
                         LCI_ENC_MAX_LOCAL);
    if (d->lm_samples > ((size_t)1 << 20) || (d->lm_samples && d->lm_samples < 16))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: lm_samples %zu is not in 16..2^20 (or 0)", f, d->lm_samples);
    if (d->fit_samples && d->fit_samples < 16)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: fit_samples %zu is below 16", f, d->fit_samples);
    size_t n = 0;
    for (size_t j = 0; j < sm->n; j++) n += (size_t)in_fit(d, sm->v[j]);
    if (n == 0)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "%s: no sample has a value in the fit range %g,%g (the values span %g..%g)", f,
                         (double)d->fit_range[0], (double)d->fit_range[1], (double)sm->info.value_min,
                         (double)sm->info.value_max);
    if (d->max_rbfs && d->max_rbfs > n - 1)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "%s: %zu samples to fit, fewer than max_rbfs %zu + 1 (one more for the bias)", f, n,
                         d->max_rbfs);
    if (!d->max_error) d->max_error = DEFAULT_MAX_ERROR;
    if (!d->max_rbfs) d->max_rbfs = n - 1 < DEFAULT_MAX_RBFS ? n - 1 : DEFAULT_MAX_RBFS;
    if (!d->fit_samples) d->fit_samples = DEFAULT_FIT_SAMPLES;
    if (!d->lm_samples) d->lm_samples = DEFAULT_LM_SAMPLES;
    if (!d->local_rbfs) d->local_rbfs = DEFAULT_LOCAL;
    if (!d->seed) d->seed = 1;
    *nfit = n;
    return LC_OK;
}

/* The fitted samples (in the fit range; a uniform subsample of fit_samples
 * when there are more, Knuth's selection sampling), sorted into buckets. */
static lc_status setup(lci_enc *e, const lc_samples *sm, size_t nfit)
{
    size_t want = nfit < e->d.fit_samples ? nfit : e->d.fit_samples;
    uint32_t *pick = malloc(sizeof(uint32_t) * want);
    if (!pick) return lci_error(e->dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_encode: out of memory");
    size_t seen = 0, k = 0;
    e->vlo = INFINITY, e->vhi = -INFINITY;
    for (size_t j = 0; j < sm->n && k < want; j++) {
        if (!in_fit(&e->d, sm->v[j])) continue;
        if ((double)(nfit - seen) * lci_enc_rand(e) < (double)(want - k)) pick[k++] = (uint32_t)j;
        seen++;
    }
    for (size_t j = 0; j < sm->n; j++)
        if (in_fit(&e->d, sm->v[j])) e->vlo = fmin(e->vlo, sm->v[j]), e->vhi = fmax(e->vhi, sm->v[j]);
    e->n = k;
    lc_status s = lci_enc_buckets(e, sm->p, sm->v, pick);
    free(pick);
    return s;
}

/* ---------------------------------------------------------------- clusters */

static double cluster_sse(const lci_enc *e, const lci_cluster *c)
{
    double s = 0.0;
    for (size_t t = c->a; t < c->b; t++) s += e->r[e->idx[t]] * e->r[e->idx[t]];
    return s;
}

double lci_enc_total_sse(const lci_enc *e)
{
    double s = 0.0;
    for (size_t c = 0; c < e->ncl; c++) s += e->cl[c].sse;
    return s;
}

/* Splits cluster ci across its principal axis through its mean (PCA of
 * the positions); 0 ok, -1 out of memory. A cluster whose points all fall
 * on one side stays whole. */
static int split(lci_enc *e, size_t ci)
{
    lci_cluster *c = &e->cl[ci];
    size_t n = c->b - c->a;
    if (n < 2) return 0;
    double m[3] = {0, 0, 0}, cov[9] = {0};
    for (size_t t = c->a; t < c->b; t++)
        for (int a = 0; a < 3; a++) m[a] += e->p[3 * (size_t)e->idx[t] + a];
    for (int a = 0; a < 3; a++) m[a] /= (double)n;
    for (size_t t = c->a; t < c->b; t++) {
        const float *p = e->p + 3 * (size_t)e->idx[t];
        double d[3] = {p[0] - m[0], p[1] - m[1], p[2] - m[2]};
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) cov[3 * a + b] += d[a] * d[b];
    }
    double ax[3];
    lci_principal_axis(cov, ax);
    size_t lo = c->a, hi = c->b; /* partition: [a, lo) below the plane */
    while (lo < hi) {
        const float *p = e->p + 3 * (size_t)e->idx[lo];
        if ((p[0] - m[0]) * ax[0] + (p[1] - m[1]) * ax[1] + (p[2] - m[2]) * ax[2] < 0.0) lo++;
        else {
            uint32_t t = e->idx[lo];
            e->idx[lo] = e->idx[--hi], e->idx[hi] = t;
        }
    }
    if (lo == c->a || lo == c->b) return 0;
    if (e->ncl == e->capcl) {
        size_t cap = e->capcl * 2;
        lci_cluster *nc = realloc(e->cl, sizeof *nc * cap);
        if (!nc) return -1;
        e->cl = nc, e->capcl = cap, c = &e->cl[ci];
    }
    lci_cluster *d = &e->cl[e->ncl];
    *d = (lci_cluster){.a = lo, .b = c->b};
    c->b = lo;
    for (size_t t = d->a; t < d->b; t++) e->cid[e->idx[t]] = (uint32_t)e->ncl;
    c->sse = cluster_sse(e, c), d->sse = cluster_sse(e, d);
    e->ncl++;
    return 0;
}

/* The new RBF's centre and starting width in cluster c (sec. 4: the
 * value-weighted mean, the value still to fit being |residual|, or the
 * point of largest error). 0 ok, -1 nothing left to fit. */
static int place(const lci_enc *e, const lci_cluster *c, double mu[3], double *s0)
{
    double wsum = 0.0, m[3] = {0, 0, 0}, best = -1.0;
    for (size_t t = c->a; t < c->b; t++) {
        uint32_t j = e->idx[t];
        double w = fabs(e->r[j]);
        const float *p = e->p + 3 * (size_t)j;
        wsum += w;
        for (int a = 0; a < 3; a++) m[a] += w * p[a];
        if (e->d.centre == LC_RBF_CENTRE_MAXERR && w > best)
            best = w, mu[0] = p[0], mu[1] = p[1], mu[2] = p[2];
    }
    if (!(wsum > 0.0)) return -1;
    if (e->d.centre == LC_RBF_CENTRE_MEAN)
        for (int a = 0; a < 3; a++) mu[a] = m[a] / wsum;
    double spread = 0.0;
    for (size_t t = c->a; t < c->b; t++) {
        uint32_t j = e->idx[t];
        const float *p = e->p + 3 * (size_t)j;
        double dx = p[0] - mu[0], dy = p[1] - mu[1], dz = p[2] - mu[2];
        spread += fabs(e->r[j]) * (dx * dx + dy * dy + dz * dz);
    }
    /* the |residual|-weighted RMS distance per axis; the maximum-error
       point sits on a peak, so half of it there */
    double s = sqrt(spread / (3.0 * wsum)) * (e->d.centre == LC_RBF_CENTRE_MAXERR ? 0.5 : 1.0);
    *s0 = fmin(fmax(s, e->smin), e->smax);
    return 0;
}

/* ---------------------------------------------------------------- global refit */

/* All weights and the bias by least squares over at most GLOBAL_SAMPLES
 * samples (normal equations, sparse accumulation through the RBF grid);
 * kept only if the error over all fit samples drops. */
static lc_status global_refit(lci_enc *e)
{
    lci_rbfs *R = &e->R;
    if (R->m == 0 || R->m > GLOBAL_MAX_RBFS) return LC_OK;
    size_t k = R->m + 1, stride = (e->n + GLOBAL_SAMPLES - 1) / GLOBAL_SAMPLES;
    double *nm = calloc(k * k, sizeof(double)), *rhs = calloc(k, sizeof(double));
    double *phi = malloc(sizeof(double) * k), *neww = malloc(sizeof(double) * k), *res = malloc(sizeof(double) * e->n);
    uint32_t *act = malloc(sizeof(uint32_t) * k);
    lci_rbf_grid g = {0};
    lc_status s = nm && rhs && phi && neww && res && act ? lci_rbf_grid_build(e->dev, &g, R, e->lo, e->hi)
                                                           : lci_error(e->dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_encode: out of memory");
    for (size_t j = 0; s == LC_OK && j < e->n; j += stride) {
        const float *x = e->p + 3 * j;
        size_t na = 0;
        size_t c = lci_rbf_grid_cell(&g, x);
        for (uint32_t t = g.start[c]; t < g.start[c + 1]; t++) {
            uint32_t i = g.list[t];
            double f = lci_enc_phi(R, i, x);
            if (f != 0.0) act[na] = i, phi[na++] = f;
        }
        act[na] = (uint32_t)R->m, phi[na++] = 1.0; /* the bias */
        for (size_t u = 0; u < na; u++) {
            double *row = nm + (size_t)act[u] * k;
            for (size_t w = 0; w < na; w++) row[act[w]] += phi[u] * phi[w];
            rhs[act[u]] += phi[u] * e->v[j];
        }
    }
    if (s == LC_OK) {
        memcpy(neww, rhs, sizeof(double) * k);
        if (lci_spd_solve((int)k, nm, neww) == 0) {
            double old_bias = R->bias, old_sse = lci_enc_total_sse(e);
            double *oldw = nm; /* reuse: k <= k * k */
            memcpy(oldw, R->w, sizeof(double) * R->m);
            memcpy(R->w, neww, sizeof(double) * R->m);
            R->bias = neww[R->m];
            double sse = 0.0;
            int ok = 1;
            for (size_t i = 0; i < R->m; i++)
                ok &= isfinite(R->w[i]) && fabs(R->w[i]) <= LCI_ENC_MAX_WEIGHT * (e->vhi - e->vlo);
            if (ok) s = lci_rbf_residuals(e->dev, R, e->lo, e->hi, e->n, e->p, e->v, res);
            for (size_t j = 0; ok && s == LC_OK && j < e->n; j++) sse += res[j] * res[j];
            if (ok && s == LC_OK && sse < old_sse) {
                memcpy(e->r, res, sizeof(double) * e->n);
                for (size_t c = 0; c < e->ncl; c++) e->cl[c].sse = cluster_sse(e, &e->cl[c]);
            } else {
                memcpy(R->w, oldw, sizeof(double) * R->m);
                R->bias = old_bias;
            }
        }
    }
    lci_rbf_grid_free(&g);
    free(nm), free(rhs), free(phi), free(neww), free(res), free(act);
    return s;
}

/* ---------------------------------------------------------------- report */

typedef struct final_job {
    const lci_rbf_grid *g;
    const lci_rbfs *r;
    const lc_samples *sm;
    const lc_rbf_encode_desc *d;
    double *sse, *maxe; /* per task */
} final_job;

#define FCHUNK 65536

static void final_task(void *ctx, int task, int worker)
{
    (void)worker;
    const final_job *j = ctx;
    size_t a = (size_t)task * FCHUNK, b = a + FCHUNK < j->sm->n ? a + FCHUNK : j->sm->n;
    double sse = 0.0, mx = 0.0;
    for (size_t i = a; i < b; i++) {
        if (!in_fit(j->d, j->sm->v[i])) continue;
        double r = (double)j->sm->v[i] - j->r->bias - lci_rbf_grid_eval(j->g, j->r, j->sm->p + 3 * i);
        sse += r * r, mx = fmax(mx, fabs(r));
    }
    j->sse[task] = sse, j->maxe[task] = mx;
}

/* RMS and max error over every fitted sample, with the truncation a loaded
 * set uses by default (eps = 1e-4 max |w|, lc_rbf_desc). */
static lc_status final_errors(lci_enc *e, const lc_samples *sm, size_t nfit, lc_rbf_encode_report *rep)
{
    lci_rbfs *R = &e->R;
    double wmax = 0.0;
    for (size_t i = 0; i < R->m; i++) wmax = fmax(wmax, fabs((float)R->w[i]));
    double eps = 1e-4 * wmax;
    for (size_t i = 0; i < R->m; i++) {
        double aw = fabs((float)R->w[i]);
        R->cut[i] = aw > eps ? R->s[i] * sqrt(2.0 * log(aw / eps)) : 0.0;
    }
    int ntask = (int)((sm->n + FCHUNK - 1) / FCHUNK);
    double *acc = calloc(2 * (size_t)ntask, sizeof(double));
    if (!acc) return lci_error(e->dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_encode: out of memory");
    lci_rbf_grid g;
    lc_status s = lci_rbf_grid_build(e->dev, &g, R, e->lo, e->hi);
    if (s == LC_OK) {
        final_job j = {&g, R, sm, &e->d, acc, acc + ntask};
        lci_pool_run(e->dev->pool, ntask, final_task, &j);
        double sse = 0.0, mx = 0.0;
        for (int t = 0; t < ntask; t++) sse += acc[t], mx = fmax(mx, acc[ntask + t]);
        double range = e->vhi > e->vlo ? e->vhi - e->vlo : 1.0;
        rep->rms = sqrt(sse / (double)nfit) / range;
        rep->max_error = mx / range;
        lci_rbf_grid_free(&g);
    }
    free(acc);
    for (size_t i = 0; i < R->m; i++) R->cut[i] = sqrt(LCI_ENC_CUT2) * R->s[i];
    return s;
}

static lc_status hand_over(lci_enc *e, lc_rbf_encoded **out)
{
    lci_rbfs *R = &e->R;
    lc_rbf_encoded *o = calloc(1, sizeof *o);
    float *c = malloc(sizeof(float) * 3 * (R->m ? R->m : 1)), *s = malloc(sizeof(float) * (R->m ? R->m : 1));
    float *w = malloc(sizeof(float) * (R->m ? R->m : 1));
    if (!o || !c || !s || !w) {
        free(o), free(c), free(s), free(w);
        return lci_error(e->dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_encode: out of memory");
    }
    for (size_t i = 0; i < R->m; i++) {
        for (int a = 0; a < 3; a++) c[3 * i + a] = (float)R->c[3 * i + a];
        s[i] = (float)R->s[i], w[i] = (float)R->w[i];
    }
    o->desc = (lc_rbf_desc){.count = R->m, .centres = c, .widths = s, .weights = w, .bias = (float)R->bias};
    *out = o;
    return LC_OK;
}

void lc_rbf_encoded_free(lc_rbf_encoded *o)
{
    if (!o) return;
    free((void *)o->desc.centres), free((void *)o->desc.widths), free((void *)o->desc.weights), free(o);
}

/* ---------------------------------------------------------------- driver */

/* Global refits when the count has grown by an eighth since the last one
 * (and at 4, 8, ...): their cost grows as m^3, so the sum stays a few times
 * the last one's. */
static int refit_due(size_t m, size_t last) { return m >= 4 && m >= last + (last >> 3) + 1; }

/* Polish sweeps (encode_polish.c) when the count has grown by a quarter
 * since the last one: a sweep costs about the same per RBF, so their sum
 * stays about five times the last one's. */
static int polish_due(size_t m, size_t last) { return m >= 8 && 4 * m >= 5 * last + 4; }

static double rms_rel(const lci_enc *e)
{
    double range = e->vhi > e->vlo ? e->vhi - e->vlo : 1.0;
    return sqrt(lci_enc_total_sse(e) / (double)e->n) / range;
}

static lc_status run(lci_enc *e, lc_rbf_encode_report *rep, double t0)
{
    lc_status s = LC_OK;
    int it = 0, refit_at = -1;
    size_t polish_at = 0;
    while (s == LC_OK && rms_rel(e) > e->d.max_error && e->R.m < e->d.max_rbfs) {
        size_t best = e->ncl;
        for (size_t c = 0; c < e->ncl; c++)
            if (!e->cl[c].done && e->cl[c].sse > 0.0 && (best == e->ncl || e->cl[c].sse > e->cl[best].sse)) best = c;
        if (best == e->ncl) break; /* nothing left that an RBF can improve */
        double mu[3], s0;
        if (place(e, &e->cl[best], mu, &s0)) {
            e->cl[best].done = 1;
            continue;
        }
        if (split(e, best)) return lci_error(e->dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_encode: out of memory");
        int added = 0;
        s = lci_enc_add(e, mu, s0, &added);
        if (s != LC_OK) break;
        if (!added) {
            e->cl[best].done = 1;
            continue;
        }
        it++;
        if (refit_due(e->R.m, (size_t)(refit_at < 0 ? 0 : refit_at))) s = global_refit(e), refit_at = (int)e->R.m;
        if (s == LC_OK && polish_due(e->R.m, polish_at)) {
            s = lci_enc_polish(e, NULL), polish_at = e->R.m;
            for (size_t c = 0; c < e->ncl; c++) e->cl[c].done = 0;
        }
        if (e->d.progress) {
            lc_rbf_encode_progress p = {it, e->R.m, rms_rel(e), lci_now() - t0, e->d.max_error, e->d.max_rbfs, 0};
            e->d.progress(e->d.progress_user, &p);
        }
    }
    if (s == LC_OK && refit_at != (int)e->R.m) s = global_refit(e);
    /* at max_rbfs (or with nothing left to split) short of the target:
       polish sweeps while each lowers the error by at least 0.5 % of itself */
    for (int k = 1; s == LC_OK && k <= FINAL_SWEEPS && rms_rel(e) > e->d.max_error; k++) {
        double before = rms_rel(e);
        s = lci_enc_polish(e, NULL);
        if (s == LC_OK && e->d.progress) {
            lc_rbf_encode_progress p = {it, e->R.m, rms_rel(e), lci_now() - t0, e->d.max_error, e->d.max_rbfs, k};
            e->d.progress(e->d.progress_user, &p);
        }
        if (rms_rel(e) > before * 0.995) break;
    }
    rep->iterations = it;
    return s;
}

lc_status lc_rbf_encode(lc_device *dev, const lc_samples *sm, const lc_rbf_encode_desc *desc, lc_rbf_encoded **out,
                        lc_rbf_encode_report *report)
{
    if (!dev) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_rbf_encode: device is NULL");
    if (!sm || !out) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_rbf_encode: samples and out must not be NULL");
    *out = NULL;
    if (!LC_HAVE_LAPACKE) return lci_missing(dev, "lc_rbf_encode", "RBF encoding (least squares)", LCI_FEATURE_LAPACKE);
    double t0 = lci_now();
    lci_enc e;
    memset(&e, 0, sizeof e);
    e.dev = dev;
    size_t nfit = 0;
    lc_status s = check_desc(dev, sm, desc, &e.d, &nfit);
    if (s != LC_OK) return s;
    e.rng = 0x9E3779B97F4A7C15ull ^ e.d.seed;
    s = setup(&e, sm, nfit);
    lc_rbf_encode_report rep = {0};
    if (s == LC_OK) s = run(&e, &rep, t0);
    if (s == LC_OK) s = final_errors(&e, sm, nfit, &rep);
    if (s == LC_OK) s = hand_over(&e, out);
    if (s == LC_OK) {
        rep.rbfs = e.R.m;
        rep.samples = sm->n, rep.fitted = nfit;
        rep.range[0] = (float)e.vlo, rep.range[1] = (float)e.vhi;
        rep.reached = rep.rms <= e.d.max_error;
        rep.seconds = lci_now() - t0;
        if (report) *report = rep;
    }
    lci_enc_free(&e);
    return s;
}
