/* Exact pixel averages of projected particles, one target (kernels/sph_project.h
 * has the method). Plain C with the lane vocabulary; -ffp-contract=off (meson's
 * kernel flags) keeps every sum in the order written, on every target. */
#include <math.h>
#include "lane/lane.h"
#include "sph_project.h"

typedef struct scr {
    float *C;        /* kpad rows of cs columns: A_k differences per pixel column */
    float *R;        /* rows x kpad: mu_k times the A_k differences per pixel row */
    float *tmp;      /* LC_KPROJ_MR x 2 LC_W */
    double *e0, *e1; /* kpad: A_k at two edges */
    int32_t *lo, *hi;
    size_t cs;
} scr;

/* Field by field: no struct copy (GCC copies those with zmm moves even on avx512_8). */
static void carve(const lc_kproj_band *b, int kp, scr *s)
{
    char *m = b->scratch;
    int rows = b->b1 - b->b0;
    s->cs = (size_t)b->W + LC_KPROJ_CPAD;
    s->e0 = (double *)m, m += sizeof(double) * (size_t)kp;
    s->e1 = (double *)m, m += sizeof(double) * (size_t)kp;
    s->C = (float *)m, m += sizeof(float) * (size_t)kp * s->cs;
    s->R = (float *)m, m += sizeof(float) * (size_t)(rows + LC_KPROJ_MR) * (size_t)kp;
    s->tmp = (float *)m, m += sizeof(float) * LC_KPROJ_MR * 32;
    s->lo = (int32_t *)m, m += sizeof(int32_t) * (size_t)(rows + LC_KPROJ_MR);
    s->hi = (int32_t *)m;
}

static inline int clampi(double x) { return x < -1e9 ? -1000000000 : x > 1e9 ? 1000000000 : (int)x; }
static inline int ifloor(double x) { return clampi(floor(x)); }

/* A_k(u) for k < kp <= kpad (odd in u, +-A_k(1) beyond the support): cubic Hermite. */
static inline void cum_k(const lc_kproj_table *t, double u, double *out, const int kpe)
{
    const int kp = t->kpad, nt = t->nt;
    /* without branches (the sign flips once along a footprint's edges and
       mispredicted): beyond the support j = nt - 1, r = 1 gives A_k(1) exactly */
    double sg = copysign(1.0, u), x = fabs(u) * nt;
    int j = x < nt ? (int)x : nt - 1;
    double r = fmin(x - j, 1.0), r2 = r * r, r3 = r2 * r;
    double h00 = sg * (2 * r3 - 3 * r2 + 1), h10 = sg * (r3 - 2 * r2 + r), h01 = sg * (-2 * r3 + 3 * r2),
           h11 = sg * (r3 - r2);
    const double *n0 = t->tab + (size_t)j * 2 * (size_t)kp, *n1 = n0 + 2 * kp;
    for (int k = 0; k < kpe; k++) out[k] = h00 * n0[k] + h10 * n0[kp + k] + h01 * n1[k] + h11 * n1[kp + k];
}

static inline void cum(const lc_kproj_table *t, double u, double *out) { cum_k(t, u, out, t->kpad); }

/* M(u) = int_0^u int_{-1}^1 g (odd; +-1/2 beyond the support). */
static inline double marg(const lc_kproj_table *t, double u)
{
    double sg = u < 0.0 ? -1.0 : 1.0, x = u < 0.0 ? -u : u;
    if (!(x < 1.0)) return sg * t->marg[2 * (size_t)t->nt];
    x *= t->nt;
    int j = (int)x;
    double r = x - j, r2 = r * r, r3 = r2 * r;
    const double *m = t->marg + 2 * (size_t)j;
    return sg * ((2 * r3 - 3 * r2 + 1) * m[0] + (r3 - 2 * r2 + r) * m[1] + (-2 * r3 + 3 * r2) * m[2] + (r3 - r2) * m[3]);
}

static inline void put(const lc_kproj_band *b, const lc_kproj_particle *p, int i, int j, double f, uint64_t *n)
{
    if (i < 0 || i >= b->W || j < b->b0 || j >= b->b1) return;
    size_t o = (size_t)(j - b->b0) * (size_t)b->W + (size_t)i;
    b->num[o] += p->a * f;
    if (b->weighted) b->den[o] += p->w * f;
    ++*n;
}

/* Footprints of at most 2 x 2 pixels (columns fx0, fx0 + 1 and rows fy0, fy0 + 1). */
static uint64_t small(const lc_kproj_table *t, const lc_kproj_band *b, const lc_kproj_particle *p, int fx0, int fx1,
                      int fy0, int fy1, scr *s)
{
    uint64_t n = 0;
    double inv = 1.0 / p->s;
    if (fx0 == fx1 && fy0 == fy1) {
        put(b, p, fx0, fy0, 1.0, &n);
        return n;
    }
    double ua = (fx0 + 1 - p->X) * inv, vb = (fy0 + 1 - p->Y) * inv;
    if (fy0 == fy1) { /* across one column edge */
        double l = 0.5 + marg(t, ua);
        put(b, p, fx0, fy0, l, &n), put(b, p, fx1, fy0, 1.0 - l, &n);
        return n;
    }
    if (fx0 == fx1) {
        double l = 0.5 + marg(t, vb);
        put(b, p, fx0, fy0, l, &n), put(b, p, fx0, fy1, 1.0 - l, &n);
        return n;
    }
    double mx = 0.5 + marg(t, ua), my = 0.5 + marg(t, vb), q = 0.0;
    cum(t, ua, s->e0);
    cum(t, vb, s->e1);
    for (int k = 0; k < t->rank; k++) q += t->mu[k] * s->e0[k] * s->e1[k];
    double c = 0.5 * (mx + my) - 0.25 + q; /* 1/4 + M(ua) / 2 + M(vb) / 2 + q: columns <= ua, rows <= vb */
    put(b, p, fx0, fy0, c, &n), put(b, p, fx1, fy0, my - c, &n);
    put(b, p, fx0, fy1, mx - c, &n), put(b, p, fx1, fy1, 1.0 - mx - my + c, &n);
    return n;
}

/* The product of rows r0 .. r0 + 3 of R and columns c .. c + nv LC_W of C into s->tmp. */
static inline void block(const float *R, int kp, const float *C, size_t cs, int K, int nv, float *tmp)
{
    vfloat a00 = vf_zero(), a10 = vf_zero(), a20 = vf_zero(), a30 = vf_zero();
    if (nv == 2) {
        vfloat a01 = vf_zero(), a11 = vf_zero(), a21 = vf_zero(), a31 = vf_zero();
        for (int k = 0; k < K; k++) {
            const float *c = C + (size_t)k * cs;
            vfloat c0 = vf_load(c), c1 = vf_load(c + LC_W);
            vfloat r0 = vf_set1(R[k]), r1 = vf_set1(R[kp + k]), r2 = vf_set1(R[2 * kp + k]), r3 = vf_set1(R[3 * kp + k]);
            a00 = vf_madd(r0, c0, a00), a01 = vf_madd(r0, c1, a01);
            a10 = vf_madd(r1, c0, a10), a11 = vf_madd(r1, c1, a11);
            a20 = vf_madd(r2, c0, a20), a21 = vf_madd(r2, c1, a21);
            a30 = vf_madd(r3, c0, a30), a31 = vf_madd(r3, c1, a31);
        }
        vf_store(tmp + LC_W, a01), vf_store(tmp + 2 * LC_W + LC_W, a11);
        vf_store(tmp + 4 * LC_W + LC_W, a21), vf_store(tmp + 6 * LC_W + LC_W, a31);
    } else {
        for (int k = 0; k < K; k++) {
            vfloat c0 = vf_load(C + (size_t)k * cs);
            a00 = vf_madd(vf_set1(R[k]), c0, a00), a10 = vf_madd(vf_set1(R[kp + k]), c0, a10);
            a20 = vf_madd(vf_set1(R[2 * kp + k]), c0, a20), a30 = vf_madd(vf_set1(R[3 * kp + k]), c0, a30);
        }
    }
    vf_store(tmp, a00), vf_store(tmp + 2 * LC_W, a10), vf_store(tmp + 4 * LC_W, a20), vf_store(tmp + 6 * LC_W, a30);
}

static uint64_t deposit(const lc_kproj_table *t, const lc_kproj_band *b, const lc_kproj_particle *p)
{
    double X = p->X, Y = p->Y, sp = p->s, inv = 1.0 / sp;
    int fx0 = ifloor(X - sp), fx1 = ifloor(X + sp), fy0 = ifloor(Y - sp), fy1 = ifloor(Y + sp);
    int i0 = fx0 < 0 ? 0 : fx0, i1 = fx1 >= b->W ? b->W - 1 : fx1;
    int j0 = fy0 < b->b0 ? b->b0 : fy0, j1 = fy1 >= b->b1 ? b->b1 - 1 : fy1;
    if (i0 > i1 || j0 > j1) return 0;
    const int kp = t->kpad;
    scr s;
    carve(b, kp, &s);
    if (fx1 - fx0 <= 1 && fy1 - fy0 <= 1) return small(t, b, p, fx0, fx1, fy0, fy1, &s);
    /* the terms this support needs (lc_kproj_table levels): K' of them, mu_0 carrying the others' mass */
    int K = t->rank, kq = kp;
    double mu0 = t->mu[0];
    for (int l = 0; l < t->nlev; l++)
        if (sp <= t->lev_smax[l]) {
            K = t->lev_k[l], mu0 = t->lev_mu0[l];
            kq = (K + LC_KPROJ_KPAD - 1) / LC_KPROJ_KPAD * LC_KPROJ_KPAD;
            break;
        }
    /* the column differences, once per particle and band */
    int nc = i1 - i0 + 1, nr = j1 - j0 + 1;
    double *ep = s.e0, *ee = s.e1;
    cum_k(t, (i0 - X) * inv, ep, kq);
    for (int i = 0; i < nc; i++) {
        cum_k(t, (i0 + i + 1 - X) * inv, ee, kq);
        for (int k = 0; k < kq; k++) s.C[(size_t)k * s.cs + (size_t)i] = (float)(ee[k] - ep[k]);
        double *x = ep;
        ep = ee, ee = x;
    }
    for (int k = 0; k < kq; k++)
        for (int i = nc; i < nc + 2 * LC_W; i++) s.C[(size_t)k * s.cs + (size_t)i] = 0.0f;
    /* the row differences times mu_k, and each row's columns meeting the support */
    cum_k(t, (j0 - Y) * inv, ep, kq);
    for (int j = 0; j < nr; j++) {
        cum_k(t, (j0 + j + 1 - Y) * inv, ee, kq);
        float *r = s.R + (size_t)j * kp;
        r[0] = (float)(mu0 * (ee[0] - ep[0]));
        for (int k = 1; k < kq; k++) r[k] = k < K ? (float)(t->mu[k] * (ee[k] - ep[k])) : 0.0f;
        double *x = ep;
        ep = ee, ee = x;
        int lo = i0, hi = i1;
        if (b->disk) {
            double vl = (j0 + j - Y) * inv, vh = (j0 + j + 1 - Y) * inv;
            double vmin = vl <= 0.0 && vh >= 0.0 ? 0.0 : fmin(fabs(vl), fabs(vh));
            if (vmin >= 1.0) lo = 1, hi = 0;
            else {
                double hw = sp * sqrt(1.0 - vmin * vmin);
                int l = ifloor(X - hw), h = ifloor(X + hw);
                lo = l > lo ? l : lo, hi = h < hi ? h : hi;
            }
        }
        s.lo[j] = lo, s.hi[j] = hi;
    }
    for (int j = nr; j < nr + LC_KPROJ_MR; j++) {
        for (int k = 0; k < kp; k++) s.R[(size_t)j * kp + k] = 0.0f;
        s.lo[j] = 1, s.hi[j] = 0;
    }
    uint64_t evals = 0;
    for (int jg = 0; jg < nr; jg += LC_KPROJ_MR) {
        int lo = i1 + 1, hi = i0 - 1;
        for (int r = 0; r < LC_KPROJ_MR; r++)
            if (s.lo[jg + r] <= s.hi[jg + r]) lo = s.lo[jg + r] < lo ? s.lo[jg + r] : lo, hi = s.hi[jg + r] > hi ? s.hi[jg + r] : hi;
        for (int c = lo - i0; c <= hi - i0;) {
            int left = hi - i0 + 1 - c, nv = left > LC_W ? 2 : 1, width = nv * LC_W;
            block(s.R + (size_t)jg * kp, kp, s.C + c, s.cs, K, nv, s.tmp);
            for (int r = 0; r < LC_KPROJ_MR; r++) {
                int j = jg + r, a = s.lo[j] - i0, e = s.hi[j] - i0;
                a = a > c ? a : c, e = e < c + width - 1 ? e : c + width - 1;
                if (a > e) continue;
                const float *v = s.tmp + r * 2 * LC_W + (a - c);
                size_t o = (size_t)(j0 + j - b->b0) * (size_t)b->W + (size_t)(i0 + a);
                double *num = b->num + o, am = p->a;
                int n = e - a + 1;
                for (int i = 0; i < n; i++) num[i] += am * (double)v[i];
                if (b->weighted) {
                    double *den = b->den + o, wm = p->w;
                    for (int i = 0; i < n; i++) den[i] += wm * (double)v[i];
                }
                evals += (uint64_t)n;
            }
            c += width;
        }
    }
    return evals;
}

const lc_kproj LC_KFN(lc_kproj) = {.target = LC_TARGET_NAME, .deposit = deposit};
