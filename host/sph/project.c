/* lc_particles_project: column maps of particle sets (issue 27; SPEC.md "SPH
 * kernels and projections"). Each particle is projected once onto the image
 * plane; the image is cut into bands of rows, each band a task of the
 * device's pool that deposits, in the particles' own order, every particle
 * reaching it into a double accumulator, so a map's bytes do not depend on
 * the thread count. A particle's exact pixel averages come from the
 * separable cumulative table of its kernel (column.h) through the target's
 * projection kernel (kernels/sph_project.c): one 1-D difference of A_k per
 * pixel column and row of its footprint, then their rank-K matrix product. */
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include "host/kinds/kind.h"
#include "host/sph/column.h"
#include "host/sph/project.h"

#define BAND 64 /* rows per task */

typedef struct prep {
    size_t n;         /* particles that reach the image (and the slab) */
    double *X, *Y;    /* centre in pixel units (x right, y down from the top edge) */
    float *s;         /* support in pixels */
    float *a, *w;     /* amount per pixel area: numerator (A w or A), denominator (w; weighted only) */
    float *z0, *z1;   /* cut by a slab face: the slab's heights in units of the support, else z0 > z1 */
    float *scale;     /* cut particles: the factor of their partial column */
} prep;

typedef struct ctx {
    const lci_column *col;
    int square;                  /* the Gaussian's support is a square, not a disk */
    int W, H, K, weighted, centre;
    const prep *pp;
    const uint32_t *list;        /* particle indices per band */
    const size_t *start;         /* band b: list[start[b] .. start[b + 1]) */
    float *map;
    const lc_kproj *kp;
    char *scratch;               /* per worker */
    size_t scratch_bytes;
    double *band_mass;
    uint64_t *band_evals;
    int (*cancel)(void *);
    void *cancel_user;
    void (*progress)(void *, float);
    void *progress_user;
    atomic_int stopped, done;
    int nbands;
} ctx;

typedef struct scratch {
    double *num, *den;  /* BAND x W accumulators */
    float *tmp;         /* W + 8: a row of centre samples */
    void *kernel;       /* the projection kernel's (lc_kproj_scratch_bytes) */
} scratch;

static size_t acc_bytes(int W) { return (sizeof(double) * 2 * BAND * (size_t)W + sizeof(float) * ((size_t)W + 8) + 63) & ~(size_t)63; }

static scratch carve(const ctx *c, int worker)
{
    char *b = c->scratch + (size_t)worker * c->scratch_bytes;
    size_t W = (size_t)c->W;
    scratch s;
    s.num = (double *)b, s.den = s.num + BAND * W;
    s.tmp = (float *)(s.den + BAND * W);
    s.kernel = b + acc_bytes(c->W);
    return s;
}

static size_t scratch_size(int W, int kpad) { return acc_bytes(W) + lc_kproj_scratch_bytes(W, BAND, kpad); }

/* floor and ceil as ints, clamped first: a particle far larger than the
 * image has edges far outside int (callers clip to the image). */
static inline int clampi(double x) { return x < -1e9 ? -1000000000 : x > 1e9 ? 1000000000 : (int)x; }
static inline int ifloor(double x) { return clampi(floor(x)); }
static inline int iceil(double x) { return clampi(ceil(x)); }

/* Adds t[0 .. n) times the amounts at row r, columns i0 .. into the accumulators. */
static void add_row(const ctx *c, scratch *s, int r, int i0, int n, const float *t, double a, double w)
{
    double *num = s->num + (size_t)r * c->W + i0;
    for (int i = 0; i < n; i++) num[i] += a * (double)t[i];
    if (c->weighted) {
        double *den = s->den + (size_t)r * c->W + i0;
        for (int i = 0; i < n; i++) den[i] += w * (double)t[i];
    }
}

/* The exact pixel averages of particle p over rows [b0, b1) of the image. */
static uint64_t deposit_exact(const ctx *c, scratch *s, size_t p, int b0, int b1, double frac)
{
    const prep *pp = c->pp;
    lc_kproj_band band = {.W = c->W, .H = c->H, .b0 = b0, .b1 = b1, .disk = !c->square, .weighted = c->weighted,
                          .num = s->num, .den = s->den, .scratch = s->kernel};
    lc_kproj_particle q = {pp->X[p], pp->Y[p], pp->s[p], pp->a[p] * frac, c->weighted ? pp->w[p] * frac : 0.0};
    return c->kp->deposit(&c->col->kt, &band, &q);
}

/* Centre sampling of particle p over rows [b0, b1): the column (or, cut by a
 * slab face, the partial column times its scale) at each pixel centre. */
static uint64_t deposit_centre(const ctx *c, scratch *s, size_t p, int b0, int b1)
{
    const prep *pp = c->pp;
    double X = pp->X[p], Y = pp->Y[p], sp = pp->s[p];
    int cut = pp->z0[p] <= pp->z1[p];
    double a = pp->a[p] / (sp * sp), w = c->weighted ? pp->w[p] / (sp * sp) : 0.0;
    if (cut) a *= pp->scale[p], w *= pp->scale[p];
    int i0 = iceil(X - sp - 0.5), i1 = ifloor(X + sp - 0.5), j0 = iceil(Y - sp - 0.5), j1 = ifloor(Y + sp - 0.5);
    i0 = i0 < 0 ? 0 : i0, i1 = i1 >= c->W ? c->W - 1 : i1;
    j0 = j0 < b0 ? b0 : j0, j1 = j1 >= b1 ? b1 - 1 : j1;
    if (i0 > i1 || j0 > j1) return 0;
    float q2 = (float)(1.0 / (sp * sp));
    int n = i1 - i0 + 1;
    for (int j = j0; j <= j1; j++) {
        float dy = (float)(j + 0.5 - Y);
        for (int i = i0; i <= i1; i++) {
            float dx = (float)(i + 0.5 - X), q = (dx * dx + dy * dy) * q2;
            s->tmp[i - i0] = cut ? lci_column_partial(c->col, sqrtf(q), pp->z0[p], pp->z1[p]) : lci_column_fq(c->col, q);
        }
        add_row(c, s, j - b0, i0, n, s->tmp, a, w);
    }
    return (uint64_t)n * (uint64_t)(j1 - j0 + 1);
}

static void band_task(void *vc, int b, int worker)
{
    ctx *c = vc;
    if (atomic_load_explicit(&c->stopped, memory_order_relaxed)) return;
    if (c->cancel && c->cancel(c->cancel_user)) {
        atomic_store(&c->stopped, 1);
        return;
    }
    scratch s = carve(c, worker);
    int b0 = b * BAND, b1 = b0 + BAND > c->H ? c->H : b0 + BAND;
    size_t cells = (size_t)(b1 - b0) * (size_t)c->W;
    memset(s.num, 0, sizeof(double) * cells);
    if (c->weighted) memset(s.den, 0, sizeof(double) * cells);
    const prep *pp = c->pp;
    uint64_t evals = 0;
    for (size_t l = c->start[b]; l < c->start[b + 1]; l++) {
        size_t p = c->list[l];
        int cut = pp->z0[p] <= pp->z1[p];
        if (c->centre || (cut && pp->scale[p] > 0.0f)) evals += deposit_centre(c, &s, p, b0, b1);
        else evals += deposit_exact(c, &s, p, b0, b1, cut ? -(double)pp->scale[p] : 1.0);
    }
    double mass = 0.0;
    for (size_t i = 0; i < cells; i++) {
        double v = s.num[i];
        mass += v;
        if (c->weighted) v = s.den[i] != 0.0 ? v / s.den[i] : 0.0;
        c->map[(size_t)b0 * c->W + i] = (float)v;
    }
    c->band_mass[b] = mass;
    c->band_evals[b] = evals;
    int done = atomic_fetch_add(&c->done, 1) + 1;
    if (c->progress && worker == 0) c->progress(c->progress_user, (float)done / (float)c->nbands);
}

/* --------------------------------------------------------------- set-up */

static void prep_free(prep *p)
{
    free(p->X), free(p->Y), free(p->s), free(p->a), free(p->w), free(p->z0), free(p->z1), free(p->scale);
}

static int prep_alloc(prep *p, size_t n)
{
    size_t m = n ? n : 1;
    p->X = malloc(sizeof(double) * m), p->Y = malloc(sizeof(double) * m);
    p->s = malloc(sizeof(float) * m), p->a = malloc(sizeof(float) * m), p->w = malloc(sizeof(float) * m);
    p->z0 = malloc(sizeof(float) * m), p->z1 = malloc(sizeof(float) * m), p->scale = malloc(sizeof(float) * m);
    return p->X && p->Y && p->s && p->a && p->w && p->z0 && p->z1 && p->scale;
}

/* Exact mode, particle cut by a slab face: resolved (support >= 2 pixels) it
 * is spread as its partial column at pixel centres scaled to its exact mass
 * fraction inside the slab (scale > 0); smaller, as its full kernel's exact
 * pixel averages times that fraction (scale = -fraction). */
static void cut_scale(const lci_column *col, prep *pp, size_t q, int centre)
{
    double sp = pp->s[q], frac = lci_column_slab_mass(col, pp->z0[q], pp->z1[q]);
    if (centre) {
        pp->scale[q] = 1.0f;
        return;
    }
    if (sp < 2.0 || sp > 2048.0) { /* beyond 2048 pixels the shape is its full kernel's too (cost) */
        pp->scale[q] = -(float)frac;
        return;
    }
    double X = pp->X[q], Y = pp->Y[q], sum = 0.0;
    int i0 = iceil(X - sp - 0.5), i1 = ifloor(X + sp - 0.5), j0 = iceil(Y - sp - 0.5), j1 = ifloor(Y + sp - 0.5);
    for (int j = j0; j <= j1; j++)
        for (int i = i0; i <= i1; i++) {
            double dx = i + 0.5 - X, dy = j + 0.5 - Y, b = sqrt(dx * dx + dy * dy) / sp;
            if (b < 1.0) sum += lci_column_partial(col, (float)b, pp->z0[q], pp->z1[q]);
        }
    /* pixels hold a / s^2 scale P: their sum is a * frac when scale = frac s^2 / sum P */
    pp->scale[q] = sum > 0.0 ? (float)(frac * sp * sp / sum) : -(float)frac;
}

typedef struct view {
    double eye[3], right[3], up[3], fwd[3], at[3];
    double sx, sy, pix;
} view;

static double dot3(const double *a, const float *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static lc_status make_view(lc_device *dev, const lc_project_desc *d, const lci_particle_view *pv, view *v)
{
    lc_camera cam = d->camera;
    lc_box3 b = pv->bounds;
    int deflt = cam.eye.x == cam.at.x && cam.eye.y == cam.at.y && cam.eye.z == cam.at.z;
    if (deflt) { /* down -z at the centres' centre, framing their x, y extent */
        lc_vec3 c = {0.5f * (b.lo.x + b.hi.x), 0.5f * (b.lo.y + b.hi.y), 0.5f * (b.lo.z + b.hi.z)};
        float ex = b.hi.x - b.lo.x, ey = b.hi.y - b.lo.y, h = fmaxf(ey, ex * (float)d->height / (float)d->width);
        cam = (lc_camera){LC_ORTHOGRAPHIC, {c.x, c.y, c.z + 1.0f + (b.hi.z - b.lo.z)}, c, {0.0f, 1.0f, 0.0f}, 0.0f,
                          h > 0.0f ? h : 1.0f};
    } else if (cam.projection == LC_PERSPECTIVE) {
        return lci_error(dev, LC_ERROR_UNSUPPORTED,
                         "lc_particles_project: camera.projection is perspective; projections are orthographic "
                         "(a column along diverging rays has no pixel area to average over): use LC_ORTHOGRAPHIC");
    }
    lc_kcamera kc;
    lc_status s = lci_camera_build(dev, &cam, d->width, d->height, &b, &kc);
    if (s != LC_OK) return s;
    double sy = 0.0, sx = 0.0;
    for (int k = 0; k < 3; k++) sy += (double)kc.up[k] * kc.up[k], sx += (double)kc.right[k] * kc.right[k];
    sy = sqrt(sy), sx = sqrt(sx);
    for (int k = 0; k < 3; k++) {
        v->eye[k] = kc.eye[k], v->fwd[k] = kc.forward[k];
        v->right[k] = kc.right[k] / sx, v->up[k] = kc.up[k] / sy;
    }
    v->at[0] = cam.at.x, v->at[1] = cam.at.y, v->at[2] = cam.at.z;
    v->sx = sx, v->sy = sy, v->pix = 2.0 * sy / d->height;
    return LC_OK;
}

/* The weight set's kappa k_i in the order of the main set's particles;
 * NULL after an error when the sets differ. */
static float *pair_weights(lc_device *dev, const lci_particle_view *pv, const lc_volume *wv)
{
    lci_particle_view q;
    if (lci_particles_view(wv, "lc_particles_project: weight", &q) != LC_OK) return NULL;
    if (q.total != pv->total || q.n != pv->n) {
        lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                  "lc_particles_project: weight holds %zu particles (%zu kept), the projected set %zu (%zu kept): "
                  "not the same particles", q.total, q.n, pv->total, pv->n);
        return NULL;
    }
    size_t m = pv->total ? pv->total : 1;
    uint32_t *where = malloc(sizeof(uint32_t) * m);
    float *out = malloc(sizeof(float) * (pv->n ? pv->n : 1));
    if (!where || !out) {
        free(where), free(out);
        lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_particles_project: out of memory pairing the weight's particles");
        return NULL;
    }
    for (size_t i = 0; i < m; i++) where[i] = UINT32_MAX;
    for (size_t j = 0; j < q.n; j++) where[q.src[j]] = (uint32_t)j;
    float kw = q.params.kappa;
    for (size_t j = 0; j < pv->n; j++) {
        uint32_t o = where[pv->src[j]];
        if (o == UINT32_MAX || q.x[o] != pv->x[j] || q.y[o] != pv->y[j] || q.z[o] != pv->z[j] || q.r[o] != pv->r[j]) {
            lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                      "lc_particles_project: weight: particle %u differs from the projected set's (position, radius "
                      "or kept/dropped): not the same particles", pv->src[j]);
            free(where), free(out);
            return NULL;
        }
        out[j] = kw * q.k[o];
    }
    free(where);
    return out;
}

static lc_status check_desc(lc_device *dev, const lc_project_desc *d, const float *map)
{
    if (!d) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_particles_project: desc is NULL");
    if (!map) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_particles_project: map is NULL");
    if (d->width < 1 || d->height < 1 || d->width > LC_MAX_IMAGE_SIDE || d->height > LC_MAX_IMAGE_SIDE)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_particles_project: size %dx%d, expected 1 to %d per side",
                         d->width, d->height, LC_MAX_IMAGE_SIDE);
    if (d->sample != LC_PROJECT_EXACT && d->sample != LC_PROJECT_CENTRE)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "lc_particles_project: sample = %d, expected LC_PROJECT_EXACT or LC_PROJECT_CENTRE", (int)d->sample);
    if (!(d->depth >= 0.0f) || !isfinite(d->depth))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_particles_project: depth = %g, expected 0 (all) or > 0",
                         (double)d->depth);
    return LC_OK;
}

/* The view's particles in the desc's order (NULL: they are in it): the
 * sums run in that order, so a map's bytes do not depend on whether a render
 * has put the set into its BVH's leaf order (lc_particles_desc.defer_bvh). */
static lc_status desc_order(lc_device *dev, const lci_particle_view *pv, uint32_t **out)
{
    *out = NULL;
    size_t i = 1;
    while (i < pv->n && pv->src[i - 1] < pv->src[i]) i++;
    if (i >= pv->n) return LC_OK;
    uint32_t *where = malloc(sizeof(uint32_t) * (pv->total ? pv->total : 1));
    uint32_t *ord = malloc(sizeof(uint32_t) * pv->n);
    if (!where || !ord) {
        free(where), free(ord);
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_particles_project: out of memory ordering %zu particles", pv->n);
    }
    for (size_t t = 0; t < pv->total; t++) where[t] = UINT32_MAX;
    for (size_t j = 0; j < pv->n; j++) where[pv->src[j]] = (uint32_t)j;
    size_t m = 0;
    for (size_t t = 0; t < pv->total; t++)
        if (where[t] != UINT32_MAX) ord[m++] = where[t];
    free(where);
    *out = ord;
    return LC_OK;
}

/* Projects every particle, keeps those that reach the image and the slab. */
static lc_status prepare(lc_device *dev, const lc_project_desc *d, const lci_particle_view *pv, const float *wk,
                         const view *v, const lci_column *col, prep *pp)
{
    uint32_t *ord;
    lc_status s = desc_order(dev, pv, &ord);
    if (s != LC_OK) return s;
    if (!prep_alloc(pp, pv->n)) {
        free(ord);
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_particles_project: out of memory");
    }
    double kappa = pv->params.kappa, area = v->pix * v->pix, half = 0.5 * (double)d->depth;
    size_t n = 0;
    for (size_t t = 0; t < pv->n; t++) {
        size_t j = ord ? ord[t] : t;
        float p[3] = {pv->x[j] - (float)v->eye[0], pv->y[j] - (float)v->eye[1], pv->z[j] - (float)v->eye[2]};
        double S = lci_column_support(pv->params.kernel, pv->r[j]), sp = S / v->pix;
        double X = (dot3(v->right, p) + v->sx) / v->pix, Y = (v->sy - dot3(v->up, p)) / v->pix;
        if (X + sp < 0.0 || X - sp > d->width || Y + sp < 0.0 || Y - sp > d->height) continue;
        float z0 = 1.0f, z1 = 0.0f;
        if (half > 0.0) {
            float pa[3] = {pv->x[j] - (float)v->at[0], pv->y[j] - (float)v->at[1], pv->z[j] - (float)v->at[2]};
            double z = dot3(v->fwd, pa);
            if (z - S >= half || z + S <= -half) continue;
            if (z - S < -half || z + S > half) z0 = (float)fmax((-half - z) / S, -1.0), z1 = (float)fmin((half - z) / S, 1.0);
        }
        double w = wk ? wk[j] : 1.0;
        pp->X[n] = X, pp->Y[n] = Y, pp->s[n] = (float)sp;
        pp->a[n] = (float)(kappa * pv->k[j] * w / area);
        pp->w[n] = (float)(w / area);
        pp->z0[n] = z0, pp->z1[n] = z1, pp->scale[n] = 0.0f;
        if (z0 <= z1) cut_scale(col, pp, n, d->sample == LC_PROJECT_CENTRE);
        n++;
    }
    pp->n = n;
    free(ord);
    return LC_OK;
}

/* Particle lists per band of rows. */
static lc_status bin(lc_device *dev, const prep *pp, int H, int nb, uint32_t **list, size_t **start)
{
    size_t *st = calloc((size_t)nb + 1, sizeof *st);
    if (!st) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_particles_project: out of memory");
    for (size_t p = 0; p < pp->n; p++) {
        int a = ifloor(pp->Y[p] - pp->s[p]) / BAND, b = ifloor(pp->Y[p] + pp->s[p]);
        a = a < 0 ? 0 : a, b = b >= H ? H - 1 : b, b = b < 0 ? -1 : b / BAND;
        for (int k = a; k <= b; k++) st[k + 1]++;
    }
    for (int k = 0; k < nb; k++) st[k + 1] += st[k];
    uint32_t *l = malloc(sizeof(uint32_t) * (st[nb] ? st[nb] : 1));
    size_t *fill = malloc(sizeof(size_t) * (size_t)nb);
    if (!l || !fill) {
        free(st), free(l), free(fill);
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_particles_project: out of memory for the band lists");
    }
    memcpy(fill, st, sizeof(size_t) * (size_t)nb);
    for (size_t p = 0; p < pp->n; p++) {
        int a = ifloor(pp->Y[p] - pp->s[p]) / BAND, b = ifloor(pp->Y[p] + pp->s[p]);
        a = a < 0 ? 0 : a, b = b >= H ? H - 1 : b, b = b < 0 ? -1 : b / BAND;
        for (int k = a; k <= b; k++) l[fill[k]++] = (uint32_t)p;
    }
    free(fill);
    *list = l, *start = st;
    return LC_OK;
}

static void fill_info(const ctx *c, const view *v, const lc_project_desc *d, int threads, size_t nkept, double t0,
                      lc_project_info *info)
{
    memset(info, 0, sizeof *info);
    for (int b = 0; b < c->nbands; b++) info->mass += c->band_mass[b], info->evaluations += c->band_evals[b];
    info->mass *= v->pix * v->pix;
    info->particles = nkept;
    info->pixel = v->pix;
    info->rank = c->K;
    info->threads = threads;
    double ctr[3];
    for (int k = 0; k < 3; k++) ctr[k] = v->eye[k];
    info->centre = (lc_vec3){(float)ctr[0], (float)ctr[1], (float)ctr[2]};
    info->right = (lc_vec3){(float)v->right[0], (float)v->right[1], (float)v->right[2]};
    info->up = (lc_vec3){(float)v->up[0], (float)v->up[1], (float)v->up[2]};
    info->view = (lc_vec3){(float)v->fwd[0], (float)v->fwd[1], (float)v->fwd[2]};
    double cr = ctr[0] * v->right[0] + ctr[1] * v->right[1] + ctr[2] * v->right[2];
    double cu = ctr[0] * v->up[0] + ctr[1] * v->up[1] + ctr[2] * v->up[2];
    info->extent[0] = cr - v->sx, info->extent[1] = cr + v->sx;
    info->extent[2] = cu - v->sy, info->extent[3] = cu + v->sy;
    (void)d;
    info->seconds = lci_now() - t0;
}

lc_status lc_particles_project(lc_device *dev, const lc_volume *particles, const lc_project_desc *d, float *map,
                               lc_project_info *info)
{
    if (!dev) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_particles_project: device is NULL");
    double t0 = lci_now();
    lci_particle_view pv;
    lc_status s = lci_particles_view(particles, "lc_particles_project", &pv);
    if (s == LC_OK) s = check_desc(dev, d, map);
    if (s != LC_OK) return s;
    view v = {0};
    if ((s = make_view(dev, d, &pv, &v)) != LC_OK) return s;
    const lci_column *col = lci_column_get(dev, pv.params.kernel);
    if (!col) return LC_ERROR_OUT_OF_MEMORY;
    float *wk = NULL;
    if (d->weight && !(wk = pair_weights(dev, &pv, d->weight))) return LC_ERROR_INVALID_ARGUMENT;
    prep pp = {0};
    uint32_t *list = NULL;
    size_t *start = NULL;
    int nb = (d->height + BAND - 1) / BAND, threads = lci_pool_threads(dev->pool);
    ctx c = {.col = col, .square = pv.params.kernel == LC_KERNEL_GAUSSIAN, .W = d->width, .H = d->height,
             .K = col->rank, .weighted = d->weight != NULL, .centre = d->sample == LC_PROJECT_CENTRE, .map = map,
             .kp = lci_project_kernels(dev->target), .cancel = d->cancel, .cancel_user = d->cancel_user,
             .progress = d->progress, .progress_user = d->progress_user, .nbands = nb};
    s = c.kp ? prepare(dev, d, &pv, wk, &v, col, &pp)
             : lci_error(dev, LC_ERROR_UNSUPPORTED, "lc_particles_project: target %s has no projection kernel",
                         lc_target_name(dev->target));
    if (s == LC_OK) s = bin(dev, &pp, d->height, nb, &list, &start);
    if (s == LC_OK) {
        c.pp = &pp, c.list = list, c.start = start;
        c.scratch_bytes = scratch_size(d->width, col->kt.kpad);
        c.scratch = lci_aligned_alloc(64, c.scratch_bytes * (size_t)threads);
        c.band_mass = calloc((size_t)nb, sizeof(double));
        c.band_evals = calloc((size_t)nb, sizeof(uint64_t));
        if (!c.scratch || !c.band_mass || !c.band_evals)
            s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_particles_project: out of memory for %d workers' scratch",
                          threads);
    }
    if (s == LC_OK) {
        lci_pool_run(dev->pool, nb, band_task, &c);
        if (atomic_load(&c.stopped))
            s = lci_error(dev, LC_CANCELLED, "lc_particles_project: cancelled by desc->cancel; the map is not complete");
    }
    if (s == LC_OK && info) fill_info(&c, &v, d, threads, pp.n, t0, info);
    if (s == LC_OK && d->progress) d->progress(d->progress_user, 1.0f);
    lci_aligned_free(c.scratch);
    free(c.band_mass), free(c.band_evals), free(list), free(start), free(wk);
    prep_free(&pp);
    return s;
}
