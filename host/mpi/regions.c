/* The regions of a render (dp.h): the partition of a volume, one region's
 * image, and a whole data-parallel render in one process. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/api/render.h"
#include "host/mpi/dp.h"

lc_status lci_dp_partition(lc_device *dev, const lc_render_desc *d, int P, lci_kdtree *t)
{
    memset(t, 0, sizeof *t);
    const lc_volume *v = d->volume;
    if (!v) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "data-parallel render: desc->volume is NULL");
    lci_frame_info info;
    memset(&info, 0, sizeof info);
    lc_status s = v->ops->frame_info(dev, v, &info);
    if (s != LC_OK) return s;
    size_t n = 0;
    const float *x = NULL, *y = NULL, *z = NULL;
    int cells[3] = {1, 1, 1};
    switch (lc_volume_kind(v)) {
    case LC_KIND_PARTICLES: {
        lc_particles_info pi;
        lc_particles_get_info(v, &pi);
        if (pi.params.sphere_scale > 0.0f)
            return lci_error(dev, LC_ERROR_UNSUPPORTED,
                             "data-parallel render: opaque particle spheres (sphere_scale %g) are not split by regions",
                             (double)pi.params.sphere_scale);
        s = lci_particles_centres(v, &n, &x, &y, &z);
        break;
    }
    case LC_KIND_RBF:
        s = lci_rbf_centres(v, &n, &x, &y, &z);
        break;
    case LC_KIND_GRID: {
        lc_grid_info gi;
        lc_grid_get_info(v, &gi);
        if (gi.params.rda != 0.0f)
            return lci_error(dev, LC_ERROR_UNSUPPORTED,
                             "data-parallel render: differential sampling (rda %g) leaves the global lattice",
                             (double)gi.params.rda);
        for (int a = 0; a < 3; a++) cells[a] = gi.size[a] - 1;
        break;
    }
    default:
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "data-parallel render: unknown volume kind");
    }
    if (s != LC_OK) return s;
    const lci_dp_ppart *pp = lci_dp_part_of(v);
    if (pp) { /* a part: the tree its load built over the whole set */
        if (pp->parts != P)
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                             "data-parallel render: this part was loaded for %d regions, not %d", pp->parts, P);
        return lci_kd_copy(dev, &pp->tree, t);
    }
    return lci_kd_build(dev, &info.bounds, P, n, x, y, z, x ? NULL : cells, t);
}

int lci_dp_op(const lc_render_desc *d) { return d->mode == LC_MODE_DVR ? LCI_COMP_OVER : LCI_COMP_DEPTH; }

lc_status lci_dp_camera(lc_device *dev, const lc_render_desc *d, lc_kcamera *cam)
{
    lci_frame_info info;
    memset(&info, 0, sizeof info);
    lc_status s = d->volume->ops->frame_info(dev, d->volume, &info);
    if (s != LC_OK) return s;
    return lci_camera_build(dev, &d->camera, d->width, d->height, &info.bounds, cam);
}

void lci_cimage_free(lci_cimage *img)
{
    free(img->rgba);
    free(img->depth);
    img->rgba = img->depth = NULL;
}

lc_status lci_dp_render_region(lc_device *dev, const lc_render_desc *d, const lci_kdtree *t, int leaf,
                               lci_cimage *img, lc_render_stats *stats)
{
    memset(img, 0, sizeof *img);
    const float probe = 0.0f; /* lci_render_check asks for an image pointer; img's come below */
    lc_status s = lci_render_check(dev, d, &probe, "data-parallel render");
    if (s == LC_OK) s = lci_dp_grid_check(dev, d, t->nleaves, leaf);
    if (s == LC_OK) s = lci_dp_particles_check(dev, d, t->nleaves, leaf);
    if (s != LC_OK) return s;
    if (d->pixel_scale > 1)
        return lci_error(dev, LC_ERROR_UNSUPPORTED, "data-parallel render: pixel_scale %d (previews are one process's)",
                         d->pixel_scale);
    int op = lci_dp_op(d);
    size_t np = (size_t)d->width * (size_t)d->height;
    img->w = d->width, img->h = d->height;
    img->rgba = malloc(sizeof(float) * 4 * np);
    img->depth = malloc(sizeof(float) * np); /* the kernels' depth hook; kept for DEPTH only */
    if (!img->rgba || !img->depth) {
        lci_cimage_free(img);
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "data-parallel render: out of memory for a %dx%d image",
                         d->width, d->height);
    }
    s = lci_render_region(dev, d, &t->cell[leaf], img->rgba, img->depth, stats);
    if (s != LC_OK) {
        lci_cimage_free(img);
        return s;
    }
    if (op != LCI_COMP_DEPTH) {
        free(img->depth);
        img->depth = NULL;
    }
    lci_cimage_rect(img, op);
    return LC_OK;
}

/* A region render's counters added to *a (the target and threads: the last's). */
static void stats_add(lc_render_stats *a, const lc_render_stats *b)
{
    a->rays += b->rays, a->samples += b->samples, a->kernel_evals += b->kernel_evals;
    a->nodes += b->nodes, a->leaves += b->leaves, a->passes += b->passes;
    a->seconds += b->seconds, a->target = b->target, a->threads = b->threads;
}

/* The P regions of desc and their visibility order (malloc'ed), for the
 * renders in one process below. */
static lc_status local_plan(lc_device *dev, const lc_render_desc *d, int P, lci_kdtree *t, int **order)
{
    *order = NULL;
    lc_status s = lci_dp_partition(dev, d, P, t);
    if (s != LC_OK) return s;
    lc_kcamera cam;
    s = lci_dp_camera(dev, d, &cam);
    if (s == LC_OK && !(*order = malloc(sizeof(int) * (size_t)P)))
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "data-parallel render: out of memory");
    if (s == LC_OK) lci_kd_order(t, &cam, *order);
    if (s != LC_OK) lci_kd_release(t);
    return s;
}

lc_status lci_dp_render_local(lc_device *dev, const lc_render_desc *d, int P, float *rgba, lc_render_stats *stats,
                              uint64_t *region_samples)
{
    lci_kdtree t;
    int *order;
    lc_status s = local_plan(dev, d, P, &t, &order);
    if (s != LC_OK) return s;
    lci_cimage *imgs = calloc((size_t)P, sizeof *imgs);
    if (!imgs) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "data-parallel render: out of memory");
    if (stats) memset(stats, 0, sizeof *stats);
    for (int i = 0; i < P && s == LC_OK; i++) {
        lc_render_stats rs;
        s = lci_dp_render_region(dev, d, &t, order[i], &imgs[i], &rs);
        if (s != LC_OK) break;
        if (region_samples) region_samples[order[i]] = rs.samples;
        if (stats) stats_add(stats, &rs);
    }
    if (s == LC_OK) s = lci_dp_composite_local(dev, P, imgs, lci_dp_op(d), rgba, NULL, NULL, NULL);
    for (int i = 0; imgs && i < P; i++) lci_cimage_free(&imgs[i]);
    free(imgs);
    free(order);
    lci_kd_release(&t);
    return s;
}

lc_status lci_dp_chain_begin(lc_device *dev, const lc_render_desc *d, const lci_kdtree *t, int leaf, lci_dp_chain *c)
{
    memset(c, 0, sizeof *c);
    const float probe = 0.0f;
    lc_status s = lci_render_check(dev, d, &probe, "data-parallel render");
    if (s == LC_OK && d->mode != LC_MODE_DVR)
        s = lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "data-parallel render: the chain composites dvr only (mode %d)",
                      (int)d->mode);
    if (s == LC_OK && d->pixel_scale > 1)
        s = lci_error(dev, LC_ERROR_UNSUPPORTED, "data-parallel render: pixel_scale %d (previews are one process's)",
                      d->pixel_scale);
    if (s == LC_OK) s = lci_dp_grid_check(dev, d, t->nleaves, leaf);
    if (s == LC_OK) s = lci_dp_particles_check(dev, d, t->nleaves, leaf);
    const lc_tf *tf = NULL;
    if (s == LC_OK) s = lci_render_tf(dev, d, &tf, &c->own_tf);
    if (s == LC_OK) s = lci_pass_prepare_region(dev, d, tf, 1, 0, &t->cell[leaf], &c->pass);
    if (s != LC_OK) {
        lci_dp_chain_end(c);
        return s;
    }
    c->pass.carry = 1;
    c->ready = 1;
    return LC_OK;
}

lc_status lci_dp_chain_rows(lc_device *dev, lci_dp_chain *c, const lc_render_desc *d, float *rgba, int row0, int row1)
{
    if (row1 <= row0) return LC_OK; /* an empty band (more bands than rows) */
    double t0 = lci_now();
    lci_pass_ctl ctl = {.cancel = d->cancel, .cancel_user = d->cancel_user, .row0 = row0, .row1 = row1};
    if (!lci_pass_run(dev, &c->pass, &ctl, rgba, NULL)) {
        lci_error(NULL, LC_CANCELLED, "data-parallel render: cancelled by desc->cancel; the image is not complete");
        snprintf(dev->last_error, sizeof dev->last_error, "%s", lc_last_error());
        return LC_CANCELLED;
    }
    lci_pass_stats_add(&c->pass, &c->stats);
    c->stats.seconds += lci_now() - t0;
    c->stats.target = dev->target, c->stats.threads = c->pass.nthreads;
    return LC_OK;
}

void lci_dp_chain_end(lci_dp_chain *c)
{
    lci_pass_release(&c->pass);
    lc_tf_destroy(c->own_tf);
    c->own_tf = NULL, c->ready = 0;
}

lc_status lci_dp_render_chain(lc_device *dev, const lc_render_desc *d, int P, int bands, float *rgba,
                              lc_render_stats *stats, uint64_t *region_samples)
{
    lci_kdtree t;
    int *order;
    lc_status s = local_plan(dev, d, P, &t, &order);
    if (s != LC_OK) return s;
    lci_dp_chain *c = calloc((size_t)P, sizeof *c);
    if (!c) s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "data-parallel render: out of memory");
    if (s == LC_OK) memset(rgba, 0, sizeof(float) * 4 * (size_t)d->width * (size_t)d->height);
    for (int i = 0; i < P && s == LC_OK; i++) s = lci_dp_chain_begin(dev, d, &t, order[i], &c[i]);
    /* band by band, each through the regions in order: what the ranks do */
    for (int b = 0; b < bands && s == LC_OK; b++) {
        int y0 = lci_dp_band_row(d->height, bands, b), y1 = lci_dp_band_row(d->height, bands, b + 1);
        for (int i = 0; i < P && s == LC_OK; i++) s = lci_dp_chain_rows(dev, &c[i], d, rgba, y0, y1);
    }
    if (stats) memset(stats, 0, sizeof *stats);
    for (int i = 0; c && i < P; i++) {
        if (s == LC_OK && region_samples) region_samples[order[i]] = c[i].stats.samples;
        if (s == LC_OK && stats) stats_add(stats, &c[i].stats);
        lci_dp_chain_end(&c[i]);
    }
    free(c);
    free(order);
    lci_kd_release(&t);
    return s;
}

int lci_dp_band_row(int h, int bands, int b) { return (int)((int64_t)h * b / bands); }
