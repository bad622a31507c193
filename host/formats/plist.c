/* Particle lists and nearest-neighbour radii (plist.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/plist.h"

int lci_plist_reserve(lci_plist *p, size_t n)
{
    if (p->n + n <= p->cap) return 0;
    size_t cap = p->cap ? p->cap : 1024;
    while (cap < p->n + n) cap *= 2;
    float *a = realloc(p->xyz, cap * 3 * sizeof(float));
    if (!a) return -1;
    p->xyz = a;
    float *b = realloc(p->r, cap * sizeof(float));
    if (!b) return -1;
    p->r = b;
    float *c = realloc(p->v, cap * sizeof(float));
    if (!c) return -1;
    p->v = c;
    uint8_t *d = realloc(p->f, cap);
    if (!d) return -1;
    p->f = d;
    p->cap = cap;
    return 0;
}

int lci_plist_add(lci_plist *p, float x, float y, float z, float r, float v, uint8_t f)
{
    if (p->n == p->cap && lci_plist_reserve(p, 1)) return -1;
    p->xyz[3 * p->n] = x, p->xyz[3 * p->n + 1] = y, p->xyz[3 * p->n + 2] = z;
    p->r[p->n] = r;
    p->v[p->n] = v;
    p->f[p->n] = f;
    p->n++;
    return 0;
}

void lci_plist_free(lci_plist *p)
{
    free(p->xyz);
    free(p->r);
    free(p->v);
    free(p->f);
    memset(p, 0, sizeof *p);
}

lc_status lci_plist_finish(lc_device *dev, const char *path, lc_status s, lci_plist *p, int nfields, int with_values,
                           lci_loaded *out)
{
    lc_particles_desc *d = s == LC_OK ? calloc(1, sizeof *d) : NULL;
    if (s == LC_OK && !d) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    if (s != LC_OK) {
        lci_plist_free(p);
        return s;
    }
    d->count = p->n;
    d->positions = p->xyz;
    d->radii = p->r;
    d->values = with_values ? p->v : NULL;
    d->fields = p->f;
    d->nfields = nfields > 0 ? nfields : 1;
    out->desc = d;
    lci_loaded_keep(out, p->xyz);
    lci_loaded_keep(out, p->r);
    lci_loaded_keep(out, p->v);
    lci_loaded_keep(out, p->f);
    memset(p, 0, sizeof *p);
    return LC_OK;
}

/* k nearest neighbours through a uniform grid of about two points per cell:
 * cells are visited in growing cubic shells around the point's cell, and the
 * search stops once the shell's nearest possible distance exceeds the current
 * k-th distance (a bounded max-heap of the k best). */
typedef struct grid {
    float lo[3], inv;
    int dim[3];
    size_t *start; /* cell c holds idx[start[c] .. start[c + 1]) */
    size_t *idx;
} grid;

/* Clamped before the conversion: a non-finite position (rejected later, when
 * the particles are created) or an infinite extent gives NaN or inf here,
 * whose conversion to int is undefined (UBSan, found by fuzz_gadget). */
static int cell_coord(const grid *g, const float *x, int a)
{
    float f = (x[a] - g->lo[a]) * g->inv;
    if (!(f >= 0.0f)) return 0;
    return f >= (float)g->dim[a] ? g->dim[a] - 1 : (int)f;
}

static void heap_push(float *h, int *n, int k, float d)
{
    if (*n == k) {
        if (d >= h[0]) return;
        /* replace the root, sift down */
        int i = 0;
        for (;;) {
            int l = 2 * i + 1, r = l + 1, m = i;
            float hv = d;
            if (l < k && h[l] > hv) m = l, hv = h[l];
            if (r < k && h[r] > hv) m = r;
            if (m == i) break;
            h[i] = h[m];
            i = m;
        }
        h[i] = d;
        return;
    }
    int i = (*n)++;
    while (i > 0 && h[(i - 1) / 2] < d) {
        h[i] = h[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    h[i] = d;
}

int lci_knn_radii(const float *xyz, size_t n, int k, float *r)
{
    if (n < 2) {
        for (size_t i = 0; i < n; i++) r[i] = 0.0f;
        return 0;
    }
    if ((size_t)k > n - 1) k = (int)(n - 1);
    grid g;
    float hi[3];
    for (int a = 0; a < 3; a++) g.lo[a] = hi[a] = xyz[a];
    for (size_t i = 1; i < n; i++)
        for (int a = 0; a < 3; a++) {
            g.lo[a] = fminf(g.lo[a], xyz[3 * i + a]);
            hi[a] = fmaxf(hi[a], xyz[3 * i + a]);
        }
    double ext = 0.0;
    for (int a = 0; a < 3; a++) ext = fmax(ext, (double)hi[a] - (double)g.lo[a]);
    if (!(ext > 0.0)) ext = 1.0;
    /* about n/2 cells over the bounding box (at most 2^24), cubic */
    double vol = 1.0;
    for (int a = 0; a < 3; a++) vol *= fmax((double)hi[a] - (double)g.lo[a], ext * 1e-3);
    double ncells = fmin((double)n / 2.0, 16777216.0);
    double side = cbrt(vol / fmax(ncells, 1.0));
    size_t total = 1;
    for (int a = 0; a < 3; a++) {
        double d = ceil(((double)hi[a] - (double)g.lo[a]) / side);
        g.dim[a] = d < 1.0 ? 1 : d > 1024.0 ? 1024 : (int)d;
        total *= (size_t)g.dim[a];
    }
    /* one cell side for all axes: the largest the clamps allow */
    double cs = side;
    for (int a = 0; a < 3; a++) cs = fmax(cs, ((double)hi[a] - (double)g.lo[a]) / g.dim[a]);
    g.inv = (float)(1.0 / cs);
    g.start = calloc(total + 1, sizeof *g.start);
    g.idx = malloc(n * sizeof *g.idx);
    size_t *cellof = malloc(n * sizeof *cellof);
    float *heap = malloc((size_t)k * sizeof *heap);
    int rc = -1;
    if (!g.start || !g.idx || !cellof || !heap) goto out;
    for (size_t i = 0; i < n; i++) {
        const float *x = xyz + 3 * i;
        size_t c = ((size_t)cell_coord(&g, x, 2) * (size_t)g.dim[1] + (size_t)cell_coord(&g, x, 1)) * (size_t)g.dim[0] +
                   (size_t)cell_coord(&g, x, 0);
        cellof[i] = c;
        g.start[c + 1]++;
    }
    for (size_t c = 0; c < total; c++) g.start[c + 1] += g.start[c];
    {
        size_t *fill = cellof; /* reused: placed in cell order */
        size_t *pos = malloc(total * sizeof *pos);
        if (!pos) goto out;
        memcpy(pos, g.start, total * sizeof *pos);
        for (size_t i = 0; i < n; i++) g.idx[pos[fill[i]]++] = i;
        free(pos);
    }
    int maxd = g.dim[0] > g.dim[1] ? g.dim[0] : g.dim[1];
    maxd = maxd > g.dim[2] ? maxd : g.dim[2];
    for (size_t i = 0; i < n; i++) {
        const float *x = xyz + 3 * i;
        int c[3] = {cell_coord(&g, x, 0), cell_coord(&g, x, 1), cell_coord(&g, x, 2)};
        int nh = 0;
        for (int s = 0; s <= maxd; s++) {
            /* every point outside shell s-1 is at least (s - 1) * cs away... more exactly, the
               distance to the boundary of the cube of cells within s-1 of c */
            if (nh == k && s > 0) {
                double m = 1e300;
                for (int a = 0; a < 3; a++) {
                    double lo = g.lo[a] + (c[a] - (s - 1)) * cs, hi2 = g.lo[a] + (c[a] + s) * cs;
                    m = fmin(m, fmin((double)x[a] - lo, hi2 - (double)x[a]));
                }
                if (m >= 0.0 && m * m >= (double)heap[0]) break;
            }
            /* shell s, clipped to the grid: a long thin grid (one far point
               stretches it to 1 x 1 x 1024 cells) costs O(s) per shell, not O(s^2) */
            int zlo = -s > -c[2] ? -s : -c[2], zhi = s < g.dim[2] - 1 - c[2] ? s : g.dim[2] - 1 - c[2];
            int ylo = -s > -c[1] ? -s : -c[1], yhi = s < g.dim[1] - 1 - c[1] ? s : g.dim[1] - 1 - c[1];
            int xlo = -s > -c[0] ? -s : -c[0], xhi = s < g.dim[0] - 1 - c[0] ? s : g.dim[0] - 1 - c[0];
            for (int dz = zlo; dz <= zhi; dz++) {
                int z = c[2] + dz;
                for (int dy = ylo; dy <= yhi; dy++) {
                    int y = c[1] + dy;
                    int onshell = dz == -s || dz == s || dy == -s || dy == s;
                    for (int dx = onshell ? xlo : -s; dx <= (onshell ? xhi : s); dx += onshell ? 1 : 2 * s) {
                        int xx = c[0] + dx;
                        if (xx >= 0 && xx < g.dim[0]) {
                            size_t cc = ((size_t)z * (size_t)g.dim[1] + (size_t)y) * (size_t)g.dim[0] + (size_t)xx;
                            for (size_t q = g.start[cc]; q < g.start[cc + 1]; q++) {
                                size_t j = g.idx[q];
                                if (j == i) continue;
                                float ddx = xyz[3 * j] - x[0], ddy = xyz[3 * j + 1] - x[1], ddz = xyz[3 * j + 2] - x[2];
                                heap_push(heap, &nh, k, ddx * ddx + ddy * ddy + ddz * ddz);
                            }
                        }
                        if (s == 0) break;
                    }
                }
            }
            /* every cell seen: nothing further to find */
            if (xlo == -c[0] && ylo == -c[1] && zlo == -c[2] && xhi == g.dim[0] - 1 - c[0] &&
                yhi == g.dim[1] - 1 - c[1] && zhi == g.dim[2] - 1 - c[2])
                break;
        }
        r[i] = sqrtf(heap[0]);
    }
    rc = 0;
out:
    free(g.start);
    free(g.idx);
    free(cellof);
    free(heap);
    return rc;
}

lc_status lci_psel_open(lc_device *dev, const lci_read_args *a, lci_psel *ps)
{
    memset(ps, 0, sizeof *ps);
    const lc_option *x = lci_option_find(a, "select");
    if (!x) return LC_OK;
    char what[512];
    snprintf(what, sizeof what, "%s: select", a->path);
    ps->expr = x->value;
    return lci_select_parse(dev, what, x->value, &ps->sel);
}

int lci_psel_keep(lci_psel *ps, size_t index, const char *element, const lci_atom_attr *attr)
{
    ps->seen++;
    return !ps->sel || lci_select_match(ps->sel, index, element, attr, &ps->missing);
}

lc_status lci_psel_close(lc_device *dev, const lci_read_args *a, lci_psel *ps, size_t kept, lc_status s)
{
    if (s == LC_OK && ps->sel && ps->missing && ps->gives)
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: select = '%s': keyword '%s' does not apply to %s files (they "
                      "give %s)", a->path, ps->expr, ps->missing, a->format ? a->format : "these", ps->gives);
    else if (s == LC_OK && ps->sel && ps->missing)
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: select = '%s': %s files cannot answer '%s' (they give type and "
                      "index%s)", a->path, ps->expr, a->format ? a->format : "these", ps->missing,
                      a->format && !strcmp(a->format, "lammps") ? ", and element with an element column" : "");
    if (s == LC_OK && ps->sel && kept == 0)
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: select = '%s' matches none of the %zu particles", a->path,
                      ps->expr, ps->seen);
    lci_select_free(ps->sel);
    ps->sel = NULL;
    return s;
}
