/* The part of a grid one rank of a data-parallel render holds (dp.h
 * "Partial grids"): its region's cells plus ghost nodes, read from the
 * file's bytes of those nodes only (raw, NRRD, MetaImage, NIfTI without
 * compression), or cut from a grid one rank read whole. Everything here is
 * without MPI; host/mpi/mpi_load.c runs it on every rank and reduces the
 * brick ranges and histograms. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "host/formats/checked.h"
#include "bvh/grid_bvh.h"
#include "host/formats/volume_data.h"
#include "host/kinds/grid.h"
#include "host/mpi/dp.h"

void lci_dp_grid_ghosts(const lc_grid_desc *g, float dt, int ghost[3])
{
    float sp[3] = {g->spacing.x, g->spacing.y, g->spacing.z};
    if (sp[0] == 0.0f && sp[1] == 0.0f && sp[2] == 0.0f) sp[0] = sp[1] = sp[2] = 1.0f;
    float mn = fminf(sp[0], fminf(sp[1], sp[2]));
    if (!(dt > 0.0f)) dt = 0.5f * mn; /* the grid's default step (grid.c frame_info) */
    /* one node for a sample's stencil next to a split (its float cell index
     * may round to the neighbouring cell), one more (gradient shading's
     * rule), and the step before a region's first sample (iso's crossing
     * test and pre-integration take the sample before) */
    for (int a = 0; a < 3; a++) ghost[a] = 2 + (int)ceilf(dt / sp[a]);
}

lc_status lci_dp_grid_tree(lc_device *dev, const lc_grid_desc *g, int P, lci_kdtree *t)
{
    lc_vec3 sp = g->spacing;
    if (sp.x == 0.0f && sp.y == 0.0f && sp.z == 0.0f) sp = (lc_vec3){1.0f, 1.0f, 1.0f};
    const float o[3] = {g->origin.x, g->origin.y, g->origin.z}, s[3] = {sp.x, sp.y, sp.z};
    float hi[3];
    for (int a = 0; a < 3; a++) hi[a] = o[a] + (float)(g->size[a] - 1) * s[a]; /* grid.c's bounds */
    lc_box3 b = {{o[0], o[1], o[2]}, {hi[0], hi[1], hi[2]}};
    int cells[3] = {g->size[0] - 1, g->size[1] - 1, g->size[2] - 1};
    return lci_kd_build(dev, &b, P, 0, NULL, NULL, NULL, cells, t);
}

void lci_dp_grid_window(const lci_kdtree *t, int leaf, const int32_t full[3], const int ghost[3], lci_dp_window *w)
{
    for (int a = 0; a < 3; a++) {
        int32_t c0 = t->crange[6 * leaf + a], c1 = t->crange[6 * leaf + 3 + a];
        int32_t lo = c0 - ghost[a], hi = c1 + ghost[a]; /* cells c0 .. c1 - 1 use nodes c0 .. c1 */
        if (lo < 0) lo = 0;
        if (hi > full[a] - 1) hi = full[a] - 1;
        lo &= ~3; /* a brick row of the bricked layout (grid.c) */
        if (hi - lo < 1) lo = hi - 1 < 0 ? 0 : (hi - 1) & ~3;
        w->start[a] = lo, w->count[a] = hi - lo + 1;
        /* nodes c0 .. c1 - 1, and the last node with the last cells */
        w->own0[a] = c0, w->own1[a] = c1 + (c1 == full[a] - 1);
    }
}

int lci_dp_window_covers(const lci_dp_window *have, const lci_dp_window *need)
{
    for (int a = 0; a < 3; a++)
        if (have->start[a] > need->start[a] || have->start[a] + have->count[a] < need->start[a] + need->count[a])
            return 0;
    return 1;
}

static void swap_values(unsigned char *b, size_t n, int es)
{
    for (size_t i = 0; i < n; i++, b += es)
        for (int x = 0; x < es / 2; x++) {
            unsigned char c = b[x];
            b[x] = b[es - 1 - x], b[es - 1 - x] = c;
        }
}

/* Reads the box of file nodes fb0 .. fb0 + fbn - 1 (file axes) into dst, x fastest. */
static lc_status read_box(lc_device *dev, const char *path, const lci_vol_layout *l, const int64_t fb0[3],
                          const int64_t fbn[3], unsigned char *dst)
{
    int es = lci_value_size(l->type);
    FILE *f = fopen(l->data_path, "rb");
    if (!f) return lci_error(dev, LC_ERROR_IO, "%s: cannot open %s: %s", path, l->data_path, strerror(errno));
    /* runs of whole rows, whole planes or the whole box where the box spans the file's axes */
    int64_t rows = fbn[0] == l->fsize[0] ? (fbn[1] == l->fsize[1] ? fbn[1] * fbn[2] : fbn[1]) : 1;
    size_t run = (size_t)(rows * fbn[0]) * (size_t)es;
    lc_status s = LC_OK;
    size_t o = 0;
    for (int64_t k = 0; k < fbn[2] && s == LC_OK; k++)
        for (int64_t j = 0; j < fbn[1] && s == LC_OK; j += rows) {
            if (rows > fbn[1] && (k > 0 || j > 0)) break; /* the whole box went in one run */
            long long at = l->offset + (((fb0[2] + k) * l->fsize[1] + fb0[1] + j) * l->fsize[0] + fb0[0]) * es;
            if (fseeko(f, (off_t)at, SEEK_SET) != 0 || fread(dst + o, 1, run, f) != run)
                s = lci_error(dev, LC_ERROR_IO, "%s: byte %lld of %s: read of %zu bytes failed", path, at, l->data_path,
                              run);
            o += run;
        }
    fclose(f);
    return s;
}

lc_status lci_dp_grid_read(lc_device *dev, const char *path, const lci_vol_layout *l, const int32_t start[3],
                           const int32_t count[3], void **out)
{
    *out = NULL;
    int es = lci_value_size(l->type);
    uint64_t n = (uint64_t)count[0] * (uint64_t)count[1] * (uint64_t)count[2];
    /* the grid box's nodes in the file's axes */
    int64_t fb0[3], fbn[3];
    int ident = 1;
    for (int w = 0; w < 3; w++) {
        int fa = l->perm[w];
        int64_t s0 = start[w], s1 = start[w] + count[w] - 1, on = l->fsize[fa];
        fb0[fa] = l->flip[w] ? on - 1 - s1 : s0;
        fbn[fa] = count[w];
        ident &= fa == w && !l->flip[w];
    }
    unsigned char *data = lci_alloc_checked(dev, path, n, (uint64_t)es, 64, "voxels", 0);
    unsigned char *box = ident || !data ? data : lci_alloc_checked(dev, path, n, (uint64_t)es, 64, "voxels", 0);
    if (!data || !box) {
        free(data);
        return LC_ERROR_OUT_OF_MEMORY;
    }
    lc_status s = l->dataset[0] ? lci_hdf5_read_box(dev, l, fb0, fbn, box) : read_box(dev, path, l, fb0, fbn, box);
    if (s == LC_OK && l->swap) swap_values(box, n, es);
    if (s == LC_OK && l->type == LC_VALUE_FLOAT32)
        for (uint64_t i = 0; i < n && s == LC_OK; i++) {
            float v;
            memcpy(&v, box + 4 * i, 4);
            if (!isfinite(v))
                s = lci_error(dev, LC_ERROR_FORMAT, "%s: voxel %llu of the part read is %g, expected a finite float32",
                              path, (unsigned long long)i, (double)v);
        }
    if (s == LC_OK && !ident) { /* onto the grid's axes: world x, y, z increasing */
        uint64_t stride[3] = {1, (uint64_t)fbn[0], (uint64_t)fbn[0] * (uint64_t)fbn[1]}, o = 0;
        for (int32_t u2 = 0; u2 < count[2]; u2++)
            for (int32_t u1 = 0; u1 < count[1]; u1++)
                for (int32_t u0 = 0; u0 < count[0]; u0++, o++) {
                    int32_t u[3] = {u0, u1, u2};
                    uint64_t si = 0;
                    for (int w = 0; w < 3; w++)
                        si += (uint64_t)(l->flip[w] ? count[w] - 1 - u[w] : u[w]) * stride[l->perm[w]];
                    memcpy(data + o * (uint64_t)es, box + si * (uint64_t)es, (size_t)es);
                }
    }
    if (box != data) free(box);
    if (s != LC_OK) {
        free(data);
        return s;
    }
    *out = data;
    return LC_OK;
}

void *lci_dp_grid_cut(const lc_grid_desc *whole, const int32_t start[3], const int32_t count[3])
{
    int es = lci_value_size(whole->type);
    size_t row = (size_t)count[0] * (size_t)es;
    unsigned char *d = malloc(row * (size_t)count[1] * (size_t)count[2] + 1);
    if (!d) return NULL;
    const unsigned char *src = whole->data;
    for (int32_t k = 0; k < count[2]; k++)
        for (int32_t j = 0; j < count[1]; j++) {
            size_t from = (((size_t)(start[2] + k) * (size_t)whole->size[1] + (size_t)(start[1] + j)) *
                               (size_t)whole->size[0] + (size_t)start[0]) * (size_t)es;
            memcpy(d + ((size_t)k * (size_t)count[1] + (size_t)j) * row, src + from, row);
        }
    return d;
}

lc_status lci_dp_grid_layout(lc_device *dev, const char *path, const lc_load_desc *ld, const char *format,
                             lci_vol_layout *l)
{
    static const lc_load_desc none = {0};
    if (!ld) ld = &none;
    lci_read_args a = {path, ld, ld->options, ld->noptions, format};
    lci_vol_opts o;
    lc_status s = lci_vol_options(dev, &a, &o);
    if (s != LC_OK) return s;
    if (!strcmp(format, "nrrd")) return lci_vol_layout_of(dev, path, &o, lci_nrrd_header, l);
    if (!strcmp(format, "metaimage")) return lci_vol_layout_of(dev, path, &o, lci_mhd_header, l);
    if (!strcmp(format, "nifti")) return lci_nifti_layout(dev, &a, &o, l);
    if (!strcmp(format, "hdf5")) return lci_hdf5_grid_layout(dev, &a, &o, l);
    if (!strcmp(format, "raw-volume")) {
        if (o.size[0] <= 0 || o.size[1] <= 0 || o.size[2] <= 0 || o.type == LC_VALUE_DEFAULT)
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                             "%s: a raw volume needs its sizes and value type (--dims X,Y,Z --type T)", path);
        lci_vol_header h;
        memset(&h, 0, sizeof h);
        for (int i = 0; i < 3; i++) h.size[i] = o.size[i];
        h.type = o.type;
        h.big_endian = o.big_endian;
        return lci_vol_layout_from_header(dev, path, path, 0, &h, &o, l);
    }
    return lci_error(dev, LC_ERROR_UNSUPPORTED, "%s: %s grids are read whole", path, format);
}

lc_status lci_dp_grid_plan(lc_device *dev, const lc_grid_desc *shape, int P, int leaf, float dt, lci_dp_window *w)
{
    lci_kdtree t;
    lc_status s = lci_dp_grid_tree(dev, shape, P, &t);
    if (s != LC_OK) return s;
    int ghost[3];
    lci_dp_grid_ghosts(shape, dt, ghost);
    lci_dp_grid_window(&t, leaf, shape->size, ghost, w);
    lci_kd_release(&t);
    return LC_OK;
}

lc_status lci_dp_grid_ranges(lc_device *dev, const lc_grid_desc *shape, const lci_dp_window *w, const void *data,
                             float **bmin, float **bmax, size_t *nbricks)
{
    int L = shape->brick ? shape->brick : lci_grid_bvh_default_brick(shape->size);
    *nbricks = lci_grid_bvh_bricks(shape->size, L);
    *bmin = malloc(*nbricks * sizeof(float));
    *bmax = malloc(*nbricks * sizeof(float));
    int kv = shape->type == LC_VALUE_UINT8 ? LC_KVAL_U8 : shape->type == LC_VALUE_UINT16 ? LC_KVAL_U16
             : shape->type == LC_VALUE_INT16 ? LC_KVAL_I16 : LC_KVAL_F32;
    if (*bmin && *bmax) {
        lci_grid_bvh_ranges_init(*nbricks, *bmin, *bmax);
        if (lci_grid_bvh_ranges(data, kv, w->start, w->count, shape->size, L, *bmin, *bmax) == 0) return LC_OK;
    }
    free(*bmin), free(*bmax);
    *bmin = *bmax = NULL;
    return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "data-parallel load: out of memory for %zu brick ranges", *nbricks);
}

lc_status lci_dp_grid_create(lc_device *dev, const lc_grid_desc *shape, const lci_dp_window *w, const void *data,
                             const float *bmin, const float *bmax, int P, int leaf,
                             lc_status (*reduce)(void *, uint64_t *, int), void *user, void (*user_free)(void *),
                             lc_volume **out)
{
    lc_grid_desc d = *shape;
    memcpy(d.size, w->count, sizeof d.size);
    d.data = data;
    d.borrow = 0;
    if (!d.brick) d.brick = lci_grid_bvh_default_brick(shape->size);
    lci_grid_window gw;
    memset(&gw, 0, sizeof gw);
    memcpy(gw.full, shape->size, sizeof gw.full);
    memcpy(gw.start, w->start, sizeof gw.start);
    memcpy(gw.own0, w->own0, sizeof gw.own0);
    memcpy(gw.own1, w->own1, sizeof gw.own1);
    gw.bmin = bmin, gw.bmax = bmax;
    gw.reduce = reduce, gw.user = user, gw.user_free = user_free;
    gw.part = leaf, gw.parts = P;
    return lci_grid_create_window(dev, &d, &gw, out);
}

lc_status lci_dp_grid_check(lc_device *dev, const lc_render_desc *d, int P, int leaf)
{
    lci_grid_window gw;
    if (!lci_grid_window_of(d->volume, &gw)) return LC_OK;
    if (gw.parts != P || gw.part != leaf)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "data-parallel render: this grid holds the part of region %d of %d it was loaded for, not "
                         "region %d of %d",
                         gw.part, gw.parts, leaf, P);
    lc_grid_info gi;
    lc_status s = lc_grid_get_info(d->volume, &gi);
    lc_grid_desc shape = {.size = {gi.size[0], gi.size[1], gi.size[2]}, .type = gi.type, .spacing = gi.spacing,
                          .origin = gi.origin};
    lci_dp_window need, have;
    if (s == LC_OK) s = lci_dp_grid_plan(dev, &shape, P, leaf, d->dt, &need);
    if (s != LC_OK) return s;
    memcpy(have.start, gw.start, sizeof have.start);
    memcpy(have.count, gw.count, sizeof have.count);
    if (!lci_dp_window_covers(&have, &need))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "data-parallel render: region %d's part of the grid (nodes %d..%d, %d..%d, %d..%d) lacks nodes "
                         "a step dt = %g needs (it was loaded for a shorter step)",
                         leaf, have.start[0], have.start[0] + have.count[0] - 1, have.start[1],
                         have.start[1] + have.count[1] - 1, have.start[2], have.start[2] + have.count[2] - 1,
                         (double)d->dt);
    return LC_OK;
}
