/* lc_particles_resample: a particle set's field at the nodes of a grid
 * (issue 28), the field the particle renderer evaluates (kernels/resample.c).
 * The grid is cut into bricks of BRICK^3 nodes; each particle is listed, in
 * the set's order, with every brick its support reaches (a counting pass,
 * then a filling pass, so the lists are allocated once at their exact size
 * and checked against the memory limit first); the bricks are tasks of the
 * device's pool, each clearing and filling its own nodes. No node is written
 * by two workers and every node sums its terms in the particles' order, so
 * the values do not depend on the thread count. */
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/checked.h"
#include "host/kinds/kind.h"
#include "host/sph/sph_kernel.h"
#include "kernels/shared/kresample.h"

#define BRICK 32         /* nodes per brick side */
#define MAX_SIDE (1 << 24)

typedef struct job {
    lc_kresample ks;
    const lc_ktable *kt;
    int64_t nb[3];     /* bricks per axis */
    const uint32_t *list;
    const uint64_t *start; /* brick b: list[start[b] .. start[b + 1]) */
    float *scratch;
    uint64_t scratch_floats;
    float *bmin, *bmax;
    uint64_t *bevals;
    int nbricks;
    int (*cancel)(void *);
    void *cancel_user;
    void (*progress)(void *, float);
    void *progress_user;
    atomic_int stopped, done;
} job;

static void brick_nodes(const job *j, int b, int32_t lo[3], int32_t hi[3])
{
    int64_t c[3] = {b % j->nb[0], (b / j->nb[0]) % j->nb[1], b / (j->nb[0] * j->nb[1])};
    for (int a = 0; a < 3; a++) {
        lo[a] = (int32_t)(c[a] * BRICK);
        hi[a] = (int32_t)(c[a] * BRICK + BRICK < j->ks.size[a] ? c[a] * BRICK + BRICK : j->ks.size[a]);
    }
}

static void brick_task(void *vj, int b, int worker)
{
    job *j = vj;
    if (atomic_load_explicit(&j->stopped, memory_order_relaxed)) return;
    if (j->cancel && j->cancel(j->cancel_user)) {
        atomic_store(&j->stopped, 1);
        return;
    }
    lc_kresample_brick kb = {.list = j->list + j->start[b], .n = (int64_t)(j->start[b + 1] - j->start[b]),
                             .scratch = j->scratch + (size_t)worker * j->scratch_floats};
    brick_nodes(j, b, kb.lo, kb.hi);
    const int64_t nx = j->ks.size[0], ny = j->ks.size[1], w = kb.hi[0] - kb.lo[0];
    for (int64_t z = kb.lo[2]; z < kb.hi[2]; z++)
        for (int64_t y = kb.lo[1]; y < kb.hi[1]; y++)
            memset(j->ks.values + (z * ny + y) * nx + kb.lo[0], 0, sizeof(float) * (size_t)w);
    j->kt->resample_brick(&j->ks, &kb);
    float mn = INFINITY, mx = -INFINITY;
    for (int64_t z = kb.lo[2]; z < kb.hi[2]; z++)
        for (int64_t y = kb.lo[1]; y < kb.hi[1]; y++) {
            const float *row = j->ks.values + (z * ny + y) * nx + kb.lo[0];
            for (int64_t x = 0; x < w; x++) { /* comparisons, not fminf/fmaxf calls: the values are finite */
                mn = row[x] < mn ? row[x] : mn;
                mx = row[x] > mx ? row[x] : mx;
            }
        }
    j->bmin[b] = mn, j->bmax[b] = mx, j->bevals[b] = kb.evals;
    int done = atomic_fetch_add(&j->done, 1) + 1;
    if (j->progress && worker == 0) j->progress(j->progress_user, (float)done / (float)j->nbricks);
}

/* The grid's nodes along each axis from the desc's box (or the particles' bounds). */
static lc_status geometry(lc_device *dev, const lc_volume *particles, const lc_resample_desc *d,
                                float origin[3], float spacing[3])
{
    const char *fn = "lc_particles_resample";
    lc_volume_info vi;
    lc_status s = lc_volume_get_info(particles, &vi);
    if (s != LC_OK) return lci_error(dev, s, "%s: %s", fn, lc_last_error());
    for (int a = 0; a < 3; a++)
        if (d->size[a] < 1 || d->size[a] > MAX_SIDE)
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: size[%d] = %d, expected 1 to %d nodes", fn, a,
                             d->size[a], MAX_SIDE);
    const float *lo = &d->box.lo.x, *hi = &d->box.hi.x;
    int given = 0;
    for (int a = 0; a < 3; a++) given |= lo[a] != 0.0f || hi[a] != 0.0f;
    if (!given) lo = &vi.bounds.lo.x, hi = &vi.bounds.hi.x;
    for (int a = 0; a < 3; a++) {
        const char axis = (char)('x' + a);
        if (!isfinite(lo[a]) || !isfinite(hi[a]) || hi[a] < lo[a])
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: box %c from %g to %g: expected finite lo <= hi", fn,
                             axis, (double)lo[a], (double)hi[a]);
        if (d->size[a] > 1 && !(hi[a] > lo[a]))
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                             "%s: box %c from %g to %g is empty but holds %d nodes%s", fn, axis, (double)lo[a],
                             (double)hi[a], d->size[a],
                             given ? "" : " (the particles' bounds: give a box)");
        if (d->size[a] > 1) {
            origin[a] = lo[a], spacing[a] = (float)(((double)hi[a] - lo[a]) / (d->size[a] - 1));
        } else { /* one node, at the centre; the spacing is the box's extent (1 for a flat box) */
            origin[a] = (float)(0.5 * ((double)lo[a] + hi[a]));
            spacing[a] = hi[a] > lo[a] ? hi[a] - lo[a] : 1.0f;
        }
        if (!(spacing[a] > 0.0f) || !isfinite(spacing[a]))
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: box %c: a spacing of %g between nodes", fn, axis,
                             (double)spacing[a]);
    }
    return LC_OK;
}

static lc_status too_big(lc_device *dev, uint64_t need, uint64_t lim, const lc_resample_desc *d, const char *what)
{
    return lci_error(dev, LC_ERROR_OUT_OF_MEMORY,
                     "lc_particles_resample: a %dx%dx%d grid needs %.1f MiB (%s), more than the memory limit of "
                     "%.1f MiB (%s)",
                     d->size[0], d->size[1], d->size[2], (double)need / 1048576.0, what, (double)lim / 1048576.0,
                     d->max_memory ? "max_memory, as set" : "3/4 of the physical memory");
}

/* The brick range [b0, b1] per axis that particle p reaches; 0 if none. */
static int particle_bricks(const job *j, const lci_particle_view *v, size_t p, float R, int64_t b0[3], int64_t b1[3])
{
    float c[3] = {v->x[p], v->y[p], v->z[p]};
    for (int a = 0; a < 3; a++) {
        int64_t i0, i1;
        if (!lc_kresample_range(j->ks.origin[a], j->ks.spacing[a], 0, j->ks.size[a], c[a], R, &i0, &i1)) return 0;
        b0[a] = i0 / BRICK, b1[a] = i1 / BRICK;
    }
    return 1;
}

/* Counts (list == NULL) or lists each particle of field `field` (-1: all)
 * with the bricks it reaches; start[b] advances past brick b's entries. */
static void bin(const job *j, const lci_particle_view *v, int field, int sph, uint64_t *start, uint32_t *list)
{
    for (size_t p = 0; p < v->n; p++) {
        if (field >= 0 && v->field[p] != field) continue;
        float R = sph ? v->r[p] : v->params.sigma * v->r[p];
        int64_t b0[3], b1[3];
        if (!particle_bricks(j, v, p, R, b0, b1)) continue;
        for (int64_t z = b0[2]; z <= b1[2]; z++)
            for (int64_t y = b0[1]; y <= b1[1]; y++)
                for (int64_t x = b0[0]; x <= b1[0]; x++) {
                    int64_t b = (z * j->nb[1] + y) * j->nb[0] + x;
                    if (list) list[start[b]] = (uint32_t)p;
                    start[b]++;
                }
    }
}

lc_status lc_particles_resample(lc_device *dev, const lc_volume *particles, const lc_resample_desc *d, float *values,
                                lc_resample_info *info)
{
    const char *fn = "lc_particles_resample";
    if (!dev) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "%s: device is NULL", fn);
    if (!particles || !d) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: %s is NULL", fn, !d ? "desc" : "particles");
    if (lc_volume_kind(particles) != LC_KIND_PARTICLES)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: particles is a %s volume, not a particle set", fn,
                         lc_kind_name(lc_volume_kind(particles)));
    double t0 = lci_now();
    lci_particle_view v;
    lc_status s = lci_particles_view(particles, fn, &v);
    if (s != LC_OK) return lci_error(dev, s, "%s", lc_last_error());
    lc_volume_info vi;
    if ((s = lc_volume_get_info(particles, &vi)) != LC_OK) return lci_error(dev, s, "%s", lc_last_error());
    if (d->field < -1 || d->field >= vi.nfields)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: field %d, expected 0 to %d (or -1: every field)", fn,
                         d->field, vi.nfields - 1);
    if (v.n > UINT32_MAX)
        return lci_error(dev, LC_ERROR_UNSUPPORTED, "%s: %zu particles, at most %u", fn, v.n, UINT32_MAX);
    job j;
    memset(&j, 0, sizeof j);
    float origin[3], spacing[3];
    if ((s = geometry(dev, particles, d, origin, spacing)) != LC_OK) return s;
    /* the values alone first, before any allocation */
    uint64_t lim = d->max_memory ? d->max_memory : lci_memory_limit(NULL);
    uint64_t nodes = (uint64_t)d->size[0] * (uint64_t)d->size[1] * (uint64_t)d->size[2];
    uint64_t need = nodes * sizeof(float);
    if (need > lim) return too_big(dev, need, lim, d, "its values");
    for (int a = 0; a < 3; a++) j.nb[a] = (d->size[a] + BRICK - 1) / BRICK;
    uint64_t nbricks = (uint64_t)(j.nb[0] * j.nb[1] * j.nb[2]);
    need += (nbricks + 1) * (sizeof(uint64_t) + 2 * sizeof(float) + sizeof(uint64_t));
    if (need > lim || nbricks > INT32_MAX) return too_big(dev, need, lim, d, "its values and brick tables");
    j.nbricks = (int)nbricks;
    int sph = v.params.kernel != LC_KERNEL_GAUSSIAN;
    const lci_sph_kernel *sk = lci_sph_kernel_get(v.params.kernel);
    j.ks = (lc_kresample){.px = v.x, .py = v.y, .pz = v.z, .r = v.r, .k = v.k, .values = values,
                          .size = {d->size[0], d->size[1], d->size[2]}, .origin = {origin[0], origin[1], origin[2]},
                          .spacing = {spacing[0], spacing[1], spacing[2]},
                          .sigma = v.params.sigma, .kappa = v.params.kappa, .knorm = sk ? (float)sk->norm : 0.0f,
                          .kernel = (int32_t)v.params.kernel};
    j.kt = dev->kt;
    for (int a = 0; a < 3; a++) j.ks.size[a] = d->size[a];
    int threads = lci_pool_threads(dev->pool);
    j.scratch_floats = lc_kresample_scratch_floats(BRICK);
    uint64_t *start = calloc(nbricks + 1, sizeof *start);
    if (!start) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %llu bricks", fn,
                                 (unsigned long long)nbricks);
    bin(&j, &v, d->field, sph, start + 1, NULL); /* start[b + 1] = entries of brick b */
    for (uint64_t b = 0; b < nbricks; b++) start[b + 1] += start[b];
    uint64_t entries = start[nbricks];
    need += entries * sizeof(uint32_t) + (uint64_t)threads * j.scratch_floats * sizeof(float);
    if (info) {
        memset(info, 0, sizeof *info);
        info->origin = (lc_vec3){j.ks.origin[0], j.ks.origin[1], j.ks.origin[2]};
        info->spacing = (lc_vec3){j.ks.spacing[0], j.ks.spacing[1], j.ks.spacing[2]};
        info->bytes = need, info->bricks = j.nbricks, info->threads = threads, info->entries = entries;
    }
    if (need > lim) {
        free(start);
        return too_big(dev, need, lim, d, "its values and particle lists");
    }
    if (!values) { /* a dry run: the sizes checked, nothing deposited */
        free(start);
        if (info) info->seconds = lci_now() - t0;
        return LC_OK;
    }
    uint32_t *list = malloc(entries ? entries * sizeof *list : 1);
    j.scratch = calloc(j.scratch_floats * (size_t)threads, sizeof(float)); /* lanes read past a row are defined */
    j.bmin = malloc(sizeof(float) * 2 * nbricks);
    j.bevals = malloc(sizeof(uint64_t) * nbricks);
    if (!list || !j.scratch || !j.bmin || !j.bevals) {
        free(start), free(list), free(j.scratch), free(j.bmin), free(j.bevals);
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for the particle lists (%.1f MiB)", fn,
                         (double)need / 1048576.0);
    }
    j.bmax = j.bmin + nbricks;
    bin(&j, &v, d->field, sph, start, list); /* start[b] advances to the old start[b + 1] */
    memmove(start + 1, start, sizeof *start * nbricks);
    start[0] = 0;
    j.list = list, j.start = start;
    j.cancel = d->cancel, j.cancel_user = d->cancel_user, j.progress = d->progress, j.progress_user = d->progress_user;
    lci_pool_run(dev->pool, j.nbricks, brick_task, &j);
    s = atomic_load(&j.stopped) ? lci_error(dev, LC_CANCELLED, "%s: cancelled (values incomplete)", fn) : LC_OK;
    if (s == LC_OK && info) {
        float mn = INFINITY, mx = -INFINITY;
        uint64_t ev = 0;
        for (uint64_t b = 0; b < nbricks; b++) mn = fminf(mn, j.bmin[b]), mx = fmaxf(mx, j.bmax[b]), ev += j.bevals[b];
        info->value_min = mn, info->value_max = mx, info->evaluations = ev;
        info->seconds = lci_now() - t0;
    }
    free(start), free(list), free(j.scratch), free(j.bmin), free(j.bevals);
    return s;
}
