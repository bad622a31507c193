/* The adaptive octree of Jang et al. 2004, §5, on the host.
 *
 * Non-uniform subdivision on the centres: a cell splits at the per-axis
 * median of the RBF centres inside it (the midpoint when it holds fewer than
 * two), kept at least 1/16 of the cell from its faces. Each cell lists the
 * RBFs whose support (eq. 3, R_i) reaches it; a child's list is filtered from
 * its parent's. A cell stays a leaf when its list has at most cell_max
 * entries, or when splitting would not help: the children's lists, weighted
 * by the children's volumes (the expected terms per uniformly placed sample),
 * keep more than 90% of the parent's ("further subdivision does not
 * significantly reduce the number of basis functions"), when its longest
 * edge is below twice the mean support of its list (splitting would otherwise
 * go on along the supports' boundary surfaces), or at depth 20.
 *
 * Significant mode (the paper's interactive variant): a leaf with more than
 * cell_max entries keeps the cell_max most significant, ranked by the largest
 * magnitude the term takes in the cell, |w_j| exp(-d_j^2 / 2 s_j^2) with d_j
 * the distance from the centre to the cell; the sum of the dropped terms is
 * stored at the 8 corners and the kernels add its trilinear interpolation.
 * Error bound: inside the cell the dropped sum and its interpolation both lie
 * in [-N, P], N and P the sums of those largest magnitudes of the dropped
 * negative and positive terms, so the error is at most P + N; the largest
 * such bound over the leaves is err_bound.
 *
 * Lists hold indices in ascending order, the order the BVH's leaves visit the
 * RBFs, so with every list exact a sample sums the same terms in the same
 * order through either structure. */
#include "rbf_octree.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_DEPTH 20
#define MIN_CELL 2.0 /* a cell whose longest edge is below this times its list's mean R stays a leaf */

typedef struct ctx {
    const lci_octree_in *in;
    lci_octree *o;
    int32_t cap_cells;
    int64_t cap_list;
    float root_lo[3], root_hi[3];
    float *tmp;   /* n floats: median selection */
    struct ranked *rk; /* n: significance ranking, significant mode */
    char *err;
    size_t errlen;
} ctx;

/* Supports grow as the kernels' box tests do (kernels/rbf_common.h grow()),
 * so round-off never drops a term the exact test d2 < R^2 keeps. */
static double grown(float r) { return (double)r * 1.0001 + 1e-6; }

static double box_d2(const lci_octree_in *in, int32_t i, const float lo[3], const float hi[3])
{
    const float c[3] = {in->cx[i], in->cy[i], in->cz[i]};
    double d2 = 0.0;
    for (int k = 0; k < 3; k++) {
        double e = c[k] < lo[k] ? (double)lo[k] - c[k] : c[k] > hi[k] ? (double)c[k] - hi[k] : 0.0;
        d2 += e * e;
    }
    return d2;
}

static int reaches(const lci_octree_in *in, int32_t i, const float lo[3], const float hi[3])
{
    double g = grown(in->R[i]);
    return box_d2(in, i, lo, hi) <= g * g;
}

static int fail(ctx *c, const char *msg)
{
    snprintf(c->err, c->errlen, "%s", msg);
    return -1;
}

static int32_t new_cells(ctx *c, int32_t k)
{
    lci_octree *o = c->o;
    if (o->ncells > INT32_MAX - k - 8) return -1;
    if (o->ncells + k > c->cap_cells) {
        int32_t cap = c->cap_cells > INT32_MAX / 2 - 16 ? INT32_MAX - 8 : 2 * c->cap_cells + 16;
        lc_kcell *n = realloc(o->cells, sizeof(lc_kcell) * (size_t)cap);
        if (!n) return -1;
        o->cells = n, c->cap_cells = cap;
    }
    int32_t first = o->ncells;
    o->ncells += k;
    memset(o->cells + first, 0, sizeof(lc_kcell) * (size_t)k);
    return first;
}

static int reserve_list(ctx *c, int64_t more)
{
    lci_octree *o = c->o;
    if (o->nlist + more > LCI_OCTREE_MAX_LIST)
        return fail(c, "the octree's cell lists would exceed 2^30 entries (supports overlap too much for this "
                       "cell_max; raise it or use the BVH)");
    if (o->nlist + more <= c->cap_list) return 0;
    int64_t cap = 2 * c->cap_list + more + 1024;
    if (cap > LCI_OCTREE_MAX_LIST) cap = LCI_OCTREE_MAX_LIST;
    int32_t *n = realloc(o->list, sizeof(int32_t) * (size_t)cap);
    if (!n) return fail(c, "out of memory for the octree's cell lists");
    o->list = n, c->cap_list = cap;
    return 0;
}

/* k-th smallest of v[0..n) (quickselect; reorders v). */
static float select_kth(float *v, int64_t n, int64_t k)
{
    int64_t l = 0, r = n - 1;
    while (l < r) {
        float p = v[l + (r - l) / 2];
        int64_t i = l, j = r;
        while (i <= j) {
            while (v[i] < p) i++;
            while (v[j] > p) j--;
            if (i <= j) {
                float t = v[i];
                v[i] = v[j], v[j] = t;
                i++, j--;
            }
        }
        if (k <= j) r = j;
        else if (k >= i) l = i;
        else break;
    }
    return v[k];
}

static void choose_split(ctx *c, const int32_t *ids, int64_t n, const float lo[3], const float hi[3], float s[3])
{
    const lci_octree_in *in = c->in;
    const float *cc[3] = {in->cx, in->cy, in->cz};
    for (int k = 0; k < 3; k++) {
        int64_t m = 0;
        for (int64_t j = 0; j < n; j++) {
            int32_t i = ids[j];
            if (in->cx[i] >= lo[0] && in->cx[i] <= hi[0] && in->cy[i] >= lo[1] && in->cy[i] <= hi[1] &&
                in->cz[i] >= lo[2] && in->cz[i] <= hi[2])
                c->tmp[m++] = cc[k][i];
        }
        float e = hi[k] - lo[k];
        float v = m >= 2 ? select_kth(c->tmp, m, m / 2) : lo[k] + 0.5f * e;
        s[k] = fminf(fmaxf(v, lo[k] + e / 16.0f), hi[k] - e / 16.0f);
    }
}

static void child_box(const float lo[3], const float hi[3], const float s[3], int oct, float clo[3], float chi[3])
{
    for (int k = 0; k < 3; k++) {
        int up = (oct >> k) & 1;
        clo[k] = up ? s[k] : lo[k];
        chi[k] = up ? hi[k] : s[k];
    }
}


typedef struct ranked {
    double sig;
    int32_t j; /* position in the cell's list */
} ranked;

static int cmp_ranked(const void *a, const void *b)
{
    const ranked *x = a, *y = b;
    if (x->sig != y->sig) return x->sig > y->sig ? -1 : 1;
    return x->j < y->j ? -1 : x->j > y->j;
}

/* Ranks ids by significance in the box (largest first, ties by index). */
static void rank(ctx *c, const int32_t *ids, int64_t n, const float lo[3], const float hi[3])
{
    const lci_octree_in *in = c->in;
    for (int64_t j = 0; j < n; j++) {
        int32_t i = ids[j];
        c->rk[j].sig = fabs((double)in->w[i]) * exp((double)in->nis[i] * box_d2(in, i, lo, hi));
        c->rk[j].j = (int32_t)j;
    }
    qsort(c->rk, (size_t)n, sizeof(ranked), cmp_ranked);
}

static int cmp_i32(const void *a, const void *b)
{
    int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
    return x < y ? -1 : x > y;
}

/* Makes cell ci a leaf over ids (ascending). */
static int leaf(ctx *c, int32_t ci, const int32_t *ids, int64_t n, const float lo[3], const float hi[3])
{
    const lci_octree_in *in = c->in;
    lci_octree *o = c->o;
    int64_t keep = n;
    if (in->significant && n > in->cell_max) keep = in->cell_max;
    if (reserve_list(c, keep)) return -1;
    lc_kcell *cell = &o->cells[ci];
    for (int k = 0; k < 3; k++) {
        cell->lo[k] = lo[k] == c->root_lo[k] ? -INFINITY : lo[k];
        cell->hi[k] = hi[k] == c->root_hi[k] ? INFINITY : hi[k];
    }
    cell->child = -1;
    cell->first = (int32_t)o->nlist;
    cell->count = (int32_t)keep;
    o->nleaves++;
    if (keep == n) {
        if (n) memcpy(o->list + o->nlist, ids, sizeof(int32_t) * (size_t)n); /* an empty cell may have no list yet */
        o->nlist += n;
        o->max_leaf = n > o->max_leaf ? (int32_t)n : o->max_leaf;
        return 0;
    }
    rank(c, ids, n, lo, hi);
    int32_t *dst = o->list + o->nlist;
    for (int64_t j = 0; j < keep; j++) dst[j] = ids[c->rk[j].j];
    qsort(dst, (size_t)keep, sizeof(int32_t), cmp_i32);
    o->nlist += keep;
    o->truncated += n - keep;
    o->max_leaf = keep > o->max_leaf ? (int32_t)keep : o->max_leaf;
    /* the dropped terms at the corners, and their bound in the cell */
    double corner[8] = {0}, pos = 0.0, neg = 0.0;
    for (int64_t j = keep; j < n; j++) {
        int32_t i = ids[c->rk[j].j];
        double w = in->w[i], nis = in->nis[i], R2 = (double)in->R[i] * in->R[i];
        if (w > 0.0) pos += c->rk[j].sig;
        else neg += c->rk[j].sig;
        for (int q = 0; q < 8; q++) {
            double x = (q & 1 ? hi[0] : lo[0]) - (double)in->cx[i], y = (q & 2 ? hi[1] : lo[1]) - (double)in->cy[i],
                   z = (q & 4 ? hi[2] : lo[2]) - (double)in->cz[i];
            double d2 = x * x + y * y + z * z;
            if ((float)d2 < (float)R2) corner[q] += w * exp(nis * d2);
        }
    }
    float *k = o->corr + (size_t)ci * LC_KCORR;
    for (int a = 0; a < 3; a++) k[a] = lo[a], k[3 + a] = 1.0f / (hi[a] - lo[a]);
    k[6] = 1.0f; /* this leaf has a correction */
    for (int q = 0; q < 8; q++) k[8 + q] = (float)corner[q];
    o->err_bound = fmax(o->err_bound, pos + neg);
    return 0;
}

static int node(ctx *c, int32_t ci, const int32_t *ids, int64_t n, const float lo[3], const float hi[3], int depth)
{
    const lci_octree_in *in = c->in;
    lci_octree *o = c->o;
    o->depth = depth > o->depth ? depth : o->depth;
    if (n <= in->cell_max || depth >= MAX_DEPTH) return leaf(c, ci, ids, n, lo, hi);
    /* cells well below the supports they list gain little more from a split
       (they lie inside most of them), and splitting on along the supports'
       boundaries alone would never end */
    double rsum = 0.0, ext = fmax(fmax((double)hi[0] - lo[0], (double)hi[1] - lo[1]), (double)hi[2] - lo[2]);
    for (int64_t j = 0; j < n; j++) rsum += in->R[ids[j]];
    if (ext < MIN_CELL * rsum / (double)n) return leaf(c, ci, ids, n, lo, hi);
    float s[3], clo[8][3], chi[8][3];
    choose_split(c, ids, n, lo, hi, s);
    int64_t cnt[8] = {0};
    for (int q = 0; q < 8; q++) child_box(lo, hi, s, q, clo[q], chi[q]);
    for (int64_t j = 0; j < n; j++)
        for (int q = 0; q < 8; q++) cnt[q] += reaches(in, ids[j], clo[q], chi[q]);
    double vol = ((double)hi[0] - lo[0]) * ((double)hi[1] - lo[1]) * ((double)hi[2] - lo[2]), expect = 0.0;
    for (int q = 0; q < 8; q++)
        expect += (double)cnt[q] * ((double)chi[q][0] - clo[q][0]) * ((double)chi[q][1] - clo[q][1]) *
                  ((double)chi[q][2] - clo[q][2]);
    if (!(vol > 0.0) || expect > 0.9 * (double)n * vol) return leaf(c, ci, ids, n, lo, hi);
    int32_t first = new_cells(c, 8);
    if (first < 0) return fail(c, "out of memory for the octree's cells");
    if (in->significant) {
        float *nc = realloc(o->corr, sizeof(float) * LC_KCORR * (size_t)c->cap_cells);
        if (!nc) return fail(c, "out of memory for the octree's corner errors");
        o->corr = nc;
        memset(o->corr + (size_t)first * LC_KCORR, 0, sizeof(float) * LC_KCORR * 8);
    }
    lc_kcell *cell = &o->cells[ci];
    cell->child = first;
    cell->count = 0;
    for (int k = 0; k < 3; k++) cell->split[k] = s[k], cell->lo[k] = lo[k], cell->hi[k] = hi[k];
    int64_t most = 0;
    for (int q = 0; q < 8; q++) most = cnt[q] > most ? cnt[q] : most;
    int32_t *sub = malloc(sizeof(int32_t) * (size_t)(most ? most : 1));
    if (!sub) return fail(c, "out of memory building the octree");
    for (int q = 0; q < 8; q++) {
        int64_t m = 0;
        for (int64_t j = 0; j < n; j++)
            if (reaches(in, ids[j], clo[q], chi[q])) sub[m++] = ids[j];
        if (node(c, first + q, sub, m, clo[q], chi[q], depth + 1)) {
            free(sub);
            return -1;
        }
    }
    free(sub);
    return 0;
}

int lci_octree_build(const lci_octree_in *in, lci_octree *out, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    ctx c = {.in = in, .o = out, .err = err, .errlen = errlen};
    size_t m = in->n ? in->n : 1;
    int32_t *ids = malloc(sizeof(int32_t) * m);
    c.tmp = malloc(sizeof(float) * m);
    c.rk = in->significant ? malloc(sizeof(ranked) * m) : NULL;
    int rc = -1;
    if (!ids || !c.tmp || (in->significant && !c.rk) || new_cells(&c, 1) < 0) {
        fail(&c, "out of memory building the octree");
        goto done;
    }
    if (in->significant && !(out->corr = calloc((size_t)c.cap_cells, sizeof(float) * LC_KCORR))) {
        fail(&c, "out of memory for the octree's corner errors");
        goto done;
    }
    for (size_t i = 0; i < in->n; i++) ids[i] = (int32_t)i;
    for (int k = 0; k < 3; k++) c.root_lo[k] = in->lo[k], c.root_hi[k] = in->hi[k];
    rc = node(&c, 0, ids, (int64_t)in->n, in->lo, in->hi, 0);
done:
    free(ids), free(c.tmp), free(c.rk);
    if (rc) lci_octree_free(out);
    return rc;
}

void lci_octree_free(lci_octree *o)
{
    if (!o) return;
    free(o->cells), free(o->list), free(o->corr);
    memset(o, 0, sizeof *o);
}

size_t lci_octree_bytes(const lci_octree *o)
{
    return (size_t)o->ncells * (sizeof(lc_kcell) + (o->corr ? sizeof(float) * LC_KCORR : 0)) +
           (size_t)o->nlist * sizeof(int32_t);
}
