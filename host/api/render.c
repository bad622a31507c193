/* lc_render: validation, the frame (camera, TFs, shading, mode), tiles over
 * the device's threads, stats. One implementation for every data kind: the
 * volume's row (host/kinds/kind.h) supplies its frame info and kernel. A
 * render is a pass (render.h); render jobs (job.c) run two of them. */
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/api/render.h"
#include "host/api/tf.h"


/* The parameters of iso and slice (lc_render_desc.iso, field, planes). */
static lc_status mode_params(lc_device *dev, const lc_render_desc *d, int nfields, lc_kframe *f)
{
    static const char *const names[] = {"dvr", "mip", "iso", "slice"};
    if (d->mode != LC_MODE_ISO && d->mode != LC_MODE_SLICE) return LC_OK;
    const char *m = names[d->mode];
    if (d->field < 0 || d->field >= nfields)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: field = %d, the data has %d field%s (0 .. %d)", m,
                         d->field, nfields, nfields == 1 ? "" : "s", nfields - 1);
    f->field = d->field;
    if (d->mode == LC_MODE_ISO) {
        if (!isfinite(d->iso))
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "iso: iso = %g, expected a finite value", (double)d->iso);
        f->iso = d->iso;
        return LC_OK;
    }
    if (d->nplanes < 1 || d->nplanes > LC_MAX_PLANES)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "slice: nplanes = %d, expected 1 to %d", d->nplanes,
                         LC_MAX_PLANES);
    f->nplanes = d->nplanes;
    for (int i = 0; i < d->nplanes; i++) {
        const lc_plane *pl = &d->planes[i];
        double p[3] = {pl->point.x, pl->point.y, pl->point.z}, n[3] = {pl->normal.x, pl->normal.y, pl->normal.z};
        double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2])))
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "slice: planes[%d].point is not finite", i);
        if (!(len > 0.0) || !isfinite(len) || !(isfinite(n[0]) && isfinite(n[1]) && isfinite(n[2])))
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                             "slice: planes[%d].normal = (%g, %g, %g), expected a finite non-zero vector", i, n[0],
                             n[1], n[2]);
        for (int a = 0; a < 3; a++) {
            f->planes[i].point[a] = (float)p[a];
            f->planes[i].normal[a] = (float)(n[a] / len);
        }
    }
    return LC_OK;
}

/* Everything in lc_kframe from the desc, the data's frame info and the TF;
 * the TF tables go into `tables` (FRAME_TABLE_FLOATS: per field the TF and
 * its step table for dt). One implementation for every kind and mode. */
#define FRAME_TABLE_FLOATS ((size_t)LC_MAX_FIELDS * (LC_TF_TABLE_SIZE * 4 + (LC_TF_TABLE_SIZE + 1) * 4))

static lc_status frame_build(lc_device *dev, const lc_render_desc *d, const lci_frame_info *info, const lc_tf *tf,
                             int scale, float *tables, lc_kframe *f)
{
    memset(f, 0, sizeof *f);
    lc_status s = lci_camera_build(dev, &d->camera, d->width, d->height, &info->bounds, &f->cam);
    if (s != LC_OK) return s;
    if (scale > 1) lci_camera_subsample(&f->cam, scale);
    f->dt = d->dt == 0.0f ? info->default_dt : d->dt;
    if (!(f->dt > 0.0f) || !isfinite(f->dt))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "dt = %g, expected a finite step > 0", (double)f->dt);
    float step = d->step_scale == 0.0f ? 1.0f : d->step_scale;
    if (!(step >= 1.0f) || !isfinite(step))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "step_scale = %g, expected a finite factor >= 1 (0 = 1)",
                         (double)d->step_scale);
    f->dt *= step;
    if (!isfinite(f->dt))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "dt %g times step_scale %g is not finite", (double)d->dt,
                         (double)step);
    f->alpha_stop = d->alpha_stop == 0.0f ? 0.97f : d->alpha_stop;
    if (!(f->alpha_stop > 0.0f && f->alpha_stop <= 1.0f))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "alpha_stop = %g, expected (0, 1]", (double)d->alpha_stop);
    if ((int)d->shading < LC_SHADE_NONE || (int)d->shading > LC_SHADE_PHONG)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "shading = %d is not none, diffuse or phong", (int)d->shading);
    f->shade = (int32_t)d->shading;
    if ((int)d->mode < 0 || d->mode >= LC_MODE_COUNT)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "mode = %d is not a render mode (dvr, mip, iso, slice)",
                         (int)d->mode);
    f->mode = (int32_t)d->mode;
    s = mode_params(dev, d, info->nfields, f);
    if (s != LC_OK) return s;
    const lc_lighting *l = &d->lighting;
    int custom = l->ka != 0.0f || l->kd != 0.0f || l->ks != 0.0f || l->phong_exp != 0;
    f->ka = custom ? l->ka : 0.2f;
    f->kd = custom ? l->kd : 0.8f;
    f->ks = custom ? l->ks : 0.4f;
    f->phong_exp = custom ? l->phong_exp : 16;
    if (!(isfinite(f->ka) && isfinite(f->kd) && isfinite(f->ks)) || f->ka < 0 || f->kd < 0 || f->ks < 0)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lighting: ka, kd, ks must be finite and >= 0");
    if (f->phong_exp < 1 || f->phong_exp > 256)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lighting: phong exponent %d, expected 1 to 256",
                         f->phong_exp);
    f->packet = d->packet == 0 ? 8 : d->packet;
    if (f->packet < 1 || f->packet > 64)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "packet = %d rays per side, expected 1 (lane-width) to 64",
                         d->packet);
    int nf = info->nfields;
    if (tf->nfields != 1 && tf->nfields < nf)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "the transfer function has %d fields but the data has %d (give 1 to share it, or one per field)",
                         tf->nfields, nf);
    int have_range = d->range[0] != 0.0f || d->range[1] != 0.0f;
    if (have_range && !(isfinite(d->range[0]) && isfinite(d->range[1]) && d->range[1] > d->range[0]))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "range [%g, %g]: expected finite lo < hi",
                         (double)d->range[0], (double)d->range[1]);
    f->nfields = nf;
    f->zero_transparent = 1;
    for (int k = 0; k < nf; k++) {
        int src = tf->nfields == 1 ? 0 : k;
        float lo = info->default_range[0], hi = info->default_range[1];
        if (have_range) lo = d->range[0], hi = d->range[1];
        else if (tf->field[src].has_range) lo = tf->field[src].range[0], hi = tf->field[src].range[1];
        if (!(hi > lo)) hi = lo + 1.0f;
        lci_tf_fill(tf, src, lo, hi, tables + (size_t)k * LC_TF_TABLE_SIZE * 4, &f->tf[k]);
        f->tf[k].grad_eps = 1e-6f * (hi - lo) / f->dt;
        lci_tf_step_table(f->dt, tables + (size_t)LC_MAX_FIELDS * LC_TF_TABLE_SIZE * 4 +
                                     (size_t)k * (LC_TF_TABLE_SIZE + 1) * 4, &f->tf[k]);
        /* extinction at value 0, interpolated as the kernels do */
        float x = fminf(fmaxf((0.0f - lo) * f->tf[k].inv_range, 0.0f), 1.0f) * (LC_TF_TABLE_SIZE - 1);
        int i0 = (int)fminf(floorf(x), LC_TF_TABLE_SIZE - 2);
        const float *t = tables + (size_t)k * LC_TF_TABLE_SIZE * 4;
        if (t[4 * i0 + 3] != 0.0f || t[4 * i0 + 7] != 0.0f) f->zero_transparent = 0;
    }
    /* a zero sample may be a ray's maximum (negative kappa) or one side of an iso crossing:
       only dvr skips them (slice takes no lattice sample) */
    if (f->mode != LC_KMODE_DVR) f->zero_transparent = 0;
    return LC_OK;
}

/* Each worker's counters on their own cache lines: kernels bump them in hot
 * loops, and two workers sharing a line would ping-pong it between cores. */
struct lci_pass_stats {
    lc_kstats s;
    unsigned char pad[128 - sizeof(lc_kstats)];
};

lc_status lci_render_check(lc_device *dev, const lc_render_desc *d, const float *rgba, const char *fn)
{
    if (!dev) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "%s: device is NULL", fn);
    if (!d) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: desc is NULL", fn);
    if (!rgba) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: rgba is NULL", fn);
    if (d->width < 1 || d->height < 1 || d->width > LC_MAX_IMAGE_SIDE || d->height > LC_MAX_IMAGE_SIDE)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: image size %dx%d, expected 1 to %d per side", fn,
                         d->width, d->height, LC_MAX_IMAGE_SIDE);
    if (!d->volume) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: desc->volume is NULL", fn);
    if (d->tile < 0 || d->tile > 4096)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: tile = %d pixels, expected 1 to 4096", fn, d->tile);
    if (d->pixel_scale < 0 || d->pixel_scale > 16)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: pixel_scale = %d, expected 0 or 1 (every pixel) to 16",
                         fn, d->pixel_scale);
    return LC_OK;
}

lc_status lci_pass_prepare(lc_device *dev, const lc_render_desc *d, const lc_tf *tf, int scale, int depth,
                           lci_pass *p)
{
    return lci_pass_prepare_region(dev, d, tf, scale, depth, NULL, p);
}

lc_status lci_pass_prepare_region(lc_device *dev, const lc_render_desc *d, const lc_tf *tf, int scale, int depth,
                                  const lc_kregion *region, lci_pass *p)
{
    memset(p, 0, sizeof *p);
    const lc_volume *vol = d->volume;
    lci_frame_info info;
    memset(&info, 0, sizeof info);
    lc_status s = vol->ops->frame_info(dev, vol, &info);
    if (s != LC_OK) return s;
    p->scale = scale;
    p->width = d->width;
    p->height = d->height;
    p->pw = (d->width + scale - 1) / scale;
    p->ph = (d->height + scale - 1) / scale;
    p->tables = lci_aligned_alloc(64, sizeof(float) * FRAME_TABLE_FLOATS);
    p->frame = lci_aligned_alloc(64, sizeof *p->frame);
    if (!p->tables || !p->frame) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_render: out of memory");
    s = frame_build(dev, d, &info, tf, scale, p->tables, p->frame);
    if (s != LC_OK) return s;
    if (region) p->frame->has_region = 1, p->frame->region = *region;
    s = vol->ops->prepare(dev, vol, d, p->frame, &p->prep);
    if (s != LC_OK) return s;
    p->tile = d->tile ? d->tile : p->prep.tile_side ? p->prep.tile_side : 32;
    p->ntx = (p->pw + p->tile - 1) / p->tile;
    p->ntasks = p->ntx * ((p->ph + p->tile - 1) / p->tile);
    p->nthreads = lci_pool_threads(dev->pool);
    p->scratch_bytes = (p->prep.scratch_bytes + 63) & ~(uint64_t)63;
    p->scratch = lci_aligned_alloc(64, (size_t)p->scratch_bytes * (size_t)p->nthreads);
    p->ws = lci_aligned_alloc(128, (size_t)p->nthreads * sizeof *p->ws);
    if (!p->scratch || !p->ws)
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_render: out of memory for %d x %llu bytes of scratch",
                         p->nthreads, (unsigned long long)p->scratch_bytes);
    if (scale > 1) {
        size_t n = (size_t)p->pw * (size_t)p->ph;
        p->small = lci_aligned_alloc(64, sizeof(float) * 4 * n);
        p->small_depth = depth ? lci_aligned_alloc(64, sizeof(float) * n) : NULL;
        if (!p->small || (depth && !p->small_depth))
            return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_render: out of memory for a %dx%d pass", p->pw, p->ph);
    }
    return LC_OK;
}

void lci_pass_release(lci_pass *p)
{
    lci_aligned_free(p->small_depth);
    lci_aligned_free(p->small);
    lci_aligned_free(p->ws);
    lci_aligned_free(p->scratch);
    if (p->prep.release) p->prep.release(p->prep.owned);
    else free(p->prep.owned);
    lci_aligned_free(p->frame);
    lci_aligned_free(p->tables);
    memset(p, 0, sizeof *p);
}

typedef struct pass_run {
    lci_pass *p;
    const lci_pass_ctl *ctl;
    float *rgba, *depth;  /* the full image */
    atomic_int stopped;   /* a tile saw the stop flag or the cancel callback */
    int task0;            /* the first tile (ctl's rows) */
} pass_run;

static int stop_asked(const lci_pass_ctl *c)
{
    return (c->stop && atomic_load_explicit(c->stop, memory_order_relaxed)) || (c->cancel && c->cancel(c->cancel_user));
}

/* A tile is cleared before its kernel runs, so a pass does not depend on
 * what the buffer held (depth is written only in iso and slice modes) and
 * a job's full pass replaces its preview tile by tile, with no clear of the
 * whole image between them. */
static void clear_tile(const lc_ktile *t)
{
    for (int y = t->y0; y < t->y1; y++) {
        memset(t->rgba + ((size_t)y * (size_t)t->stride + (size_t)t->x0) * 4, 0, sizeof(float) * 4 * (size_t)(t->x1 - t->x0));
        if (t->depth)
            for (int x = t->x0; x < t->x1; x++) t->depth[(size_t)y * (size_t)t->stride + (size_t)x] = INFINITY;
    }
}

/* A scaled pass's tile into the full image: pixel (i, j) fills the block
 * [s i, s i + s) x [s j, s j + s), clipped to the image. */
static void fill_blocks(const pass_run *r, const lc_ktile *t)
{
    const lci_pass *p = r->p;
    int s = p->scale;
    for (int j = t->y0; j < t->y1; j++) {
        for (int y = j * s; y < (j + 1) * s && y < p->height; y++) {
            float *row = r->rgba + (size_t)y * (size_t)p->width * 4;
            float *drow = r->depth ? r->depth + (size_t)y * (size_t)p->width : NULL;
            for (int i = t->x0; i < t->x1; i++) {
                const float *src = t->rgba + ((size_t)j * (size_t)p->pw + (size_t)i) * 4;
                for (int x = i * s; x < (i + 1) * s && x < p->width; x++) {
                    memcpy(row + (size_t)x * 4, src, sizeof(float) * 4);
                    if (drow) drow[x] = t->depth[(size_t)j * (size_t)p->pw + (size_t)i];
                }
            }
        }
    }
}

static void run_tile(void *ctx, int task, int worker)
{
    pass_run *r = ctx;
    lci_pass *p = r->p;
    const lci_pass_ctl *c = r->ctl;
    if (atomic_load_explicit(&r->stopped, memory_order_relaxed)) return;
    if (stop_asked(c)) {
        atomic_store_explicit(&r->stopped, 1, memory_order_relaxed);
        return;
    }
    lc_ktile t;
    task += r->task0;
    t.x0 = (task % p->ntx) * p->tile;
    t.y0 = (task / p->ntx) * p->tile;
    t.x1 = t.x0 + p->tile < p->pw ? t.x0 + p->tile : p->pw;
    t.y1 = t.y0 + p->tile < p->ph ? t.y0 + p->tile : p->ph;
    if (c->row1 > c->row0) { /* a band of rows: the tiles it cuts are cut too */
        t.y0 = t.y0 > c->row0 ? t.y0 : c->row0;
        t.y1 = t.y1 < c->row1 ? t.y1 : c->row1;
    }
    t.stride = p->pw;
    t.carry = p->carry;
    t.rgba = p->scale > 1 ? p->small : r->rgba;
    t.depth = p->scale > 1 ? p->small_depth : r->depth;
    t.stop = (const int32_t *)c->stop; /* atomic_int, read by the kernels with __atomic_load_n */
    if (!t.carry) clear_tile(&t);
    lc_kscratch sc = {p->scratch + (size_t)worker * p->scratch_bytes, p->scratch_bytes};
    p->prep.tile(p->prep.kscene, p->frame, &t, &sc, &p->ws[worker].s);
    /* the kernel may have returned early on the flag (it is never cleared, so
       this load sees what the kernel saw): the tile is then incomplete */
    if (c->stop && atomic_load_explicit(c->stop, memory_order_relaxed)) {
        atomic_store_explicit(&r->stopped, 1, memory_order_relaxed);
        return;
    }
    if (p->scale > 1) fill_blocks(r, &t);
    int done = atomic_fetch_add_explicit(c->done, 1, memory_order_relaxed) + 1;
    if (c->progress && worker == 0) c->progress(c->progress_user, c->base + c->span * (float)done / (float)p->ntasks);
}

int lci_pass_run(lc_device *dev, lci_pass *p, const lci_pass_ctl *ctl, float *rgba, float *depth)
{
    atomic_int own_done = 0;
    lci_pass_ctl c = *ctl;
    if (!c.done) c.done = &own_done;
    pass_run r = {p, &c, rgba, depth, 0, 0};
    int ntasks = p->ntasks;
    if (c.row1 > c.row0) { /* the tile rows meeting [row0, row1) */
        int ty0 = c.row0 / p->tile, ty1 = (c.row1 + p->tile - 1) / p->tile;
        r.task0 = ty0 * p->ntx, ntasks = (ty1 - ty0) * p->ntx;
    }
    memset(p->ws, 0, (size_t)p->nthreads * sizeof *p->ws);
    if (!lci_pool_run_until(dev->pool, ntasks, run_tile, &r, c.stop)) return 0;
    return !atomic_load(&r.stopped);
}

void lci_pass_stats_add(const lci_pass *p, lc_render_stats *acc)
{
    for (int w = 0; w < p->nthreads; w++) {
        acc->rays += p->ws[w].s.rays;
        acc->samples += p->ws[w].s.samples;
        acc->kernel_evals += p->ws[w].s.kernel_evals;
        acc->nodes += p->ws[w].s.nodes;
        acc->leaves += p->ws[w].s.leaves;
        acc->passes += p->ws[w].s.passes;
    }
}

int lci_preview_scale(int width, int height)
{
    int side = width > height ? width : height;
    return side < 256 ? 2 : side < 2048 ? 4 : 8;
}

lc_status lc_render(lc_device *dev, const lc_render_desc *d, float *rgba, lc_render_stats *stats)
{
    return lci_render(dev, d, rgba, NULL, stats);
}

lc_status lci_render(lc_device *dev, const lc_render_desc *d, float *rgba, float *depth, lc_render_stats *stats)
{
    return lci_render_region(dev, d, NULL, rgba, depth, stats);
}

lc_status lci_render_tf(lc_device *dev, const lc_render_desc *d, const lc_tf **tf, lc_tf **own)
{
    *own = NULL, *tf = d->tf;
    if (*tf) return LC_OK;
    lc_status s = lc_tf_preset(dev, "heat", 1, 1.0f, own);
    *tf = *own;
    return s;
}

lc_status lci_render_region(lc_device *dev, const lc_render_desc *d, const lc_kregion *region, float *rgba,
                            float *depth, lc_render_stats *stats)
{
    lc_status s = lci_render_check(dev, d, rgba, "lc_render");
    if (s != LC_OK) return s;
    double t0 = lci_now();
    lc_tf *own_tf = NULL;
    const lc_tf *tf = NULL;
    s = lci_render_tf(dev, d, &tf, &own_tf);
    if (s != LC_OK) return s;
    lci_pass p;
    s = lci_pass_prepare_region(dev, d, tf, d->pixel_scale > 1 ? d->pixel_scale : 1, depth != NULL, region, &p);
    if (s == LC_OK) {
        lci_pass_ctl ctl = {.cancel = d->cancel, .cancel_user = d->cancel_user, .progress = d->progress,
                            .progress_user = d->progress_user, .base = 0.0f, .span = 1.0f};
        if (!lci_pass_run(dev, &p, &ctl, rgba, depth)) {
            /* asked for, not a failure: recorded as errors are, logged as information */
            s = lci_error(NULL, LC_CANCELLED, "lc_render: cancelled by desc->cancel; the image is not complete");
            snprintf(dev->last_error, sizeof dev->last_error, "%s", lc_last_error());
            lci_log(dev, LC_LOG_INFO, "%s", dev->last_error);
        } else {
            if (d->progress) d->progress(d->progress_user, 1.0f);
            if (stats) {
                memset(stats, 0, sizeof *stats);
                lci_pass_stats_add(&p, stats);
                stats->target = dev->target;
                stats->threads = p.nthreads;
                stats->seconds = lci_now() - t0;
            }
        }
    }
    lci_pass_release(&p);
    lc_tf_destroy(own_tf);
    return s;
}
