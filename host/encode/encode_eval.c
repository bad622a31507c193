/* Evaluating an RBF set at many points for the encoder: a uniform grid of
 * cells, each listing the RBFs whose cut sphere's box reaches it, and the
 * residuals v - f(p) of every sample on the device's threads. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "host/encode/encode_local.h"

int lci_rbfs_reserve(lci_rbfs *r, size_t cap)
{
    if (cap <= r->cap) return 0;
    double *c = realloc(r->c, sizeof(double) * 3 * cap);
    if (!c) return -1;
    r->c = c;
    double **arr[3] = {&r->s, &r->w, &r->cut};
    for (int i = 0; i < 3; i++) {
        double *p = realloc(*arr[i], sizeof(double) * cap);
        if (!p) return -1;
        *arr[i] = p;
    }
    r->cap = cap;
    return 0;
}

void lci_rbfs_free(lci_rbfs *r)
{
    free(r->c), free(r->s), free(r->w), free(r->cut);
    memset(r, 0, sizeof *r);
}

static int cell_of(const lci_rbf_grid *g, double x, int a)
{
    double t = (x - g->lo[a]) / g->cell;
    int i = t < 0.0 ? 0 : t >= (double)g->nc[a] ? g->nc[a] - 1 : (int)t;
    return i;
}

/* The cell box [i0, i1] reached by a sphere. */
static void cell_box(const lci_rbf_grid *g, const double *c, double rad, int i0[3], int i1[3])
{
    for (int a = 0; a < 3; a++) i0[a] = cell_of(g, c[a] - rad, a), i1[a] = cell_of(g, c[a] + rad, a);
}

lc_status lci_rbf_grid_build(lc_device *dev, lci_rbf_grid *g, const lci_rbfs *r, const double lo[3],
                             const double hi[3])
{
    memset(g, 0, sizeof *g);
    double ext = 0.0;
    for (int a = 0; a < 3; a++) ext = fmax(ext, hi[a] - lo[a]);
    if (!(ext > 0.0)) ext = 1.0;
    /* cells about half the mean cut radius, at most 64 per axis: few cells
       per RBF, few RBFs per cell */
    double mean = ext;
    if (r->m) {
        mean = 0.0;
        for (size_t i = 0; i < r->m; i++) mean += r->cut[i];
        mean /= (double)r->m;
    }
    g->cell = fmax(ext / 64.0, 0.5 * mean);
    size_t ncells = 1;
    for (int a = 0; a < 3; a++) {
        g->lo[a] = lo[a];
        g->nc[a] = (int)fmin(64.0, floor((hi[a] - lo[a]) / g->cell) + 1.0);
        ncells *= (size_t)g->nc[a];
    }
    g->start = calloc(ncells + 1, sizeof(uint32_t));
    if (!g->start) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_encode: out of memory");
    uint64_t total = 0;
    for (int pass = 0; pass < 2; pass++) {
        for (size_t i = 0; i < r->m; i++) {
            int i0[3], i1[3];
            cell_box(g, r->c + 3 * i, r->cut[i], i0, i1);
            for (int z = i0[2]; z <= i1[2]; z++)
                for (int y = i0[1]; y <= i1[1]; y++)
                    for (int x = i0[0]; x <= i1[0]; x++) {
                        size_t c = ((size_t)z * (size_t)g->nc[1] + (size_t)y) * (size_t)g->nc[0] + (size_t)x;
                        if (pass == 0) g->start[c + 1]++, total++;
                        else g->list[g->start[c]++] = (uint32_t)i;
                    }
        }
        if (pass == 0) {
            if (total > UINT32_MAX) {
                lci_rbf_grid_free(g);
                return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_encode: too many RBF-cell pairs");
            }
            for (size_t c = 0; c < ncells; c++) g->start[c + 1] += g->start[c];
            g->list = malloc(sizeof(uint32_t) * (total ? total : 1));
            if (!g->list) {
                lci_rbf_grid_free(g);
                return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_rbf_encode: out of memory");
            }
        }
    }
    for (size_t c = ncells; c > 0; c--) g->start[c] = g->start[c - 1]; /* undo the fill's advance */
    g->start[0] = 0;
    return LC_OK;
}

void lci_rbf_grid_free(lci_rbf_grid *g)
{
    free(g->start), free(g->list);
    memset(g, 0, sizeof *g);
}

size_t lci_rbf_grid_cell(const lci_rbf_grid *g, const float x[3])
{
    return ((size_t)cell_of(g, x[2], 2) * (size_t)g->nc[1] + (size_t)cell_of(g, x[1], 1)) * (size_t)g->nc[0] +
           (size_t)cell_of(g, x[0], 0);
}

double lci_rbf_grid_eval(const lci_rbf_grid *g, const lci_rbfs *r, const float x[3])
{
    size_t c = lci_rbf_grid_cell(g, x);
    double f = 0.0;
    for (uint32_t k = g->start[c]; k < g->start[c + 1]; k++) {
        uint32_t i = g->list[k];
        const double *m = r->c + 3 * i;
        double dx = x[0] - m[0], dy = x[1] - m[1], dz = x[2] - m[2];
        double d2 = dx * dx + dy * dy + dz * dz;
        if (d2 < r->cut[i] * r->cut[i]) f += r->w[i] * exp(-d2 / (2.0 * r->s[i] * r->s[i]));
    }
    return f;
}

typedef struct resid_job {
    const lci_rbf_grid *g;
    const lci_rbfs *r;
    const float *p, *v;
    double *out;
    size_t n;
} resid_job;

#define CHUNK 16384

static void resid_task(void *ctx, int task, int worker)
{
    (void)worker;
    const resid_job *j = ctx;
    size_t a = (size_t)task * CHUNK, b = a + CHUNK < j->n ? a + CHUNK : j->n;
    for (size_t i = a; i < b; i++) j->out[i] = (double)j->v[i] - j->r->bias - lci_rbf_grid_eval(j->g, j->r, j->p + 3 * i);
}

lc_status lci_rbf_residuals(lc_device *dev, const lci_rbfs *r, const double lo[3], const double hi[3], size_t n,
                            const float *p, const float *v, double *out)
{
    lci_rbf_grid g;
    lc_status s = lci_rbf_grid_build(dev, &g, r, lo, hi);
    if (s != LC_OK) return s;
    resid_job j = {&g, r, p, v, out, n};
    lci_pool_run(dev->pool, (int)((n + CHUNK - 1) / CHUNK), resid_task, &j);
    lci_rbf_grid_free(&g);
    return LC_OK;
}
