/* lc_render: validation, the frame (camera, TFs, shading, mode), tiles over
 * the device's threads, stats. One implementation for every data kind: the
 * volume's row (host/kinds/kind.h) supplies its frame info and kernel. */
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include "host/kinds/kind.h"
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
                             float *tables, lc_kframe *f)
{
    memset(f, 0, sizeof *f);
    lc_status s = lci_camera_build(dev, &d->camera, d->width, d->height, &info->bounds, &f->cam);
    if (s != LC_OK) return s;
    f->dt = d->dt == 0.0f ? info->default_dt : d->dt;
    if (!(f->dt > 0.0f) || !isfinite(f->dt))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "dt = %g, expected a finite step > 0", (double)f->dt);
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
typedef struct padded_stats {
    lc_kstats s;
    unsigned char pad[128 - sizeof(lc_kstats)];
} padded_stats;

typedef struct job {
    const lci_prepared *prep;
    const lc_kframe *frame;
    float *rgba, *depth;
    int width, height, tile, ntx;
    unsigned char *scratch;
    uint64_t scratch_bytes;
    padded_stats *stats; /* one per worker */
    atomic_int done;
    int ntasks;
    void (*progress)(void *user, float fraction);
    void *progress_user;
} job;

static void run_tile(void *ctx, int task, int worker)
{
    job *j = ctx;
    lc_ktile t;
    t.x0 = (task % j->ntx) * j->tile;
    t.y0 = (task / j->ntx) * j->tile;
    t.x1 = t.x0 + j->tile < j->width ? t.x0 + j->tile : j->width;
    t.y1 = t.y0 + j->tile < j->height ? t.y0 + j->tile : j->height;
    t.stride = j->width;
    t.pad = 0;
    t.rgba = j->rgba;
    t.depth = j->depth;
    lc_kscratch sc = {j->scratch + (size_t)worker * j->scratch_bytes, j->scratch_bytes};
    j->prep->tile(j->prep->kscene, j->frame, &t, &sc, &j->stats[worker].s);
    int done = atomic_fetch_add_explicit(&j->done, 1, memory_order_relaxed) + 1;
    if (j->progress && worker == 0) j->progress(j->progress_user, (float)done / (float)j->ntasks);
}

lc_status lc_render(lc_device *dev, const lc_render_desc *d, float *rgba, lc_render_stats *stats)
{
    return lci_render(dev, d, rgba, NULL, stats);
}

lc_status lci_render(lc_device *dev, const lc_render_desc *d, float *rgba, float *depth, lc_render_stats *stats)
{
    if (!dev) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_render: device is NULL");
    if (!d) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_render: desc is NULL");
    if (!rgba) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_render: rgba is NULL");
    if (d->width < 1 || d->height < 1 || d->width > LC_MAX_IMAGE_SIDE || d->height > LC_MAX_IMAGE_SIDE)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_render: image size %dx%d, expected 1 to %d per side",
                         d->width, d->height, LC_MAX_IMAGE_SIDE);
    if (!d->volume) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_render: desc->volume is NULL");
    const lc_volume *vol = d->volume;
    if (d->tile < 0 || d->tile > 4096)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_render: tile = %d pixels, expected 1 to 4096", d->tile);
    double t0 = lci_now();
    lci_frame_info info;
    memset(&info, 0, sizeof info);
    lc_status s = vol->ops->frame_info(dev, vol, &info);
    if (s != LC_OK) return s;
    lc_tf *own_tf = NULL;
    const lc_tf *tf = d->tf;
    if (!tf) {
        s = lc_tf_preset(dev, "heat", 1, 1.0f, &own_tf);
        if (s != LC_OK) return s;
        tf = own_tf;
    }
    float *tables = lci_aligned_alloc(64, sizeof(float) * FRAME_TABLE_FLOATS);
    lc_kframe *frame = lci_aligned_alloc(64, sizeof *frame);
    lci_prepared prep;
    memset(&prep, 0, sizeof prep);
    unsigned char *scratch = NULL;
    padded_stats *ws = NULL;
    if (!tables || !frame) {
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_render: out of memory");
        goto done;
    }
    s = frame_build(dev, d, &info, tf, tables, frame);
    if (s != LC_OK) goto done;
    s = vol->ops->prepare(dev, vol, d, frame, &prep);
    if (s != LC_OK) goto done;
    int tile = d->tile ? d->tile : prep.tile_side ? prep.tile_side : 32;
    int nthreads = lci_pool_threads(dev->pool);
    uint64_t sb = (prep.scratch_bytes + 63) & ~(uint64_t)63;
    scratch = lci_aligned_alloc(64, (size_t)sb * (size_t)nthreads);
    ws = lci_aligned_alloc(128, (size_t)nthreads * sizeof *ws);
    if (!scratch || !ws) {
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_render: out of memory for %d x %llu bytes of scratch", nthreads,
                      (unsigned long long)sb);
        goto done;
    }
    memset(rgba, 0, sizeof(float) * 4 * (size_t)d->width * (size_t)d->height);
    if (depth)
        for (size_t i = 0; i < (size_t)d->width * (size_t)d->height; i++) depth[i] = INFINITY;
    job j = {&prep, frame, rgba, depth, d->width, d->height, tile, (d->width + tile - 1) / tile, scratch, sb, ws,
             0, 0, d->progress, d->progress_user};
    j.ntasks = j.ntx * ((d->height + tile - 1) / tile);
    lci_pool_run(dev->pool, j.ntasks, run_tile, &j);
    if (d->progress) d->progress(d->progress_user, 1.0f);
    if (stats) {
        memset(stats, 0, sizeof *stats);
        for (int w = 0; w < nthreads; w++) {
            stats->rays += ws[w].s.rays;
            stats->samples += ws[w].s.samples;
            stats->kernel_evals += ws[w].s.kernel_evals;
            stats->nodes += ws[w].s.nodes;
            stats->leaves += ws[w].s.leaves;
            stats->passes += ws[w].s.passes;
        }
        stats->target = dev->target;
        stats->threads = nthreads;
        stats->seconds = lci_now() - t0;
    }
done:
    lci_aligned_free(ws);
    lci_aligned_free(scratch);
    if (prep.release) prep.release(prep.owned);
    else free(prep.owned);
    lci_aligned_free(frame);
    lci_aligned_free(tables);
    lc_tf_destroy(own_tf);
    return s;
}
