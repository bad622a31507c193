/* lc_samples: what the RBF encoder fits. Scattered points with values (from
 * arrays, CSV or VTK legacy files) or the nodes of a structured volume (from
 * an lc_grid_desc, or any volume file the formats registry reads), held as
 * float32 x y z and value. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "host/encode/encode.h"
#include "host/formats/format.h"
#include "host/formats/text_reader.h"

lc_status lci_samples_adopt(lc_device *dev, const char *name, float *p, float *v, size_t n, const char *format,
                            uint64_t input_bytes, lc_samples **out)
{
    *out = NULL;
    size_t bad = 0, first = 0;
    for (size_t j = 0; j < n; j++)
        if (!isfinite(p[3 * j]) || !isfinite(p[3 * j + 1]) || !isfinite(p[3 * j + 2]) || !isfinite(v[j]))
            if (!bad++) first = j;
    lc_samples *s = bad || !n ? NULL : calloc(1, sizeof *s);
    if (!s) {
        free(p), free(v);
        if (!n) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: no samples", name);
        if (bad) {
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                             "%s: sample %zu has a non-finite position or value (%zu bad samples)", name, first, bad);
        }
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory", name);
    }
    s->n = n, s->p = p, s->v = v;
    lc_samples_info *in = &s->info;
    in->count = n;
    in->bounds.lo = in->bounds.hi = (lc_vec3){p[0], p[1], p[2]};
    in->value_min = in->value_max = v[0];
    for (size_t j = 0; j < n; j++) {
        const float *q = p + 3 * j;
        in->bounds.lo.x = fminf(in->bounds.lo.x, q[0]), in->bounds.hi.x = fmaxf(in->bounds.hi.x, q[0]);
        in->bounds.lo.y = fminf(in->bounds.lo.y, q[1]), in->bounds.hi.y = fmaxf(in->bounds.hi.y, q[1]);
        in->bounds.lo.z = fminf(in->bounds.lo.z, q[2]), in->bounds.hi.z = fmaxf(in->bounds.hi.z, q[2]);
        in->value_min = fminf(in->value_min, v[j]), in->value_max = fmaxf(in->value_max, v[j]);
    }
    in->input_bytes = input_bytes ? input_bytes : 16 * (uint64_t)n;
    snprintf(s->format, sizeof s->format, "%s", format ? format : "");
    in->format = s->format;
    *out = s;
    return LC_OK;
}

static size_t type_size(lc_value_type t)
{
    return t == LC_VALUE_UINT8 ? 1 : t == LC_VALUE_FLOAT32 ? 4 : t == LC_VALUE_UINT16 || t == LC_VALUE_INT16 ? 2 : 0;
}

static float voxel(const void *data, lc_value_type t, size_t j)
{
    switch (t) {
    case LC_VALUE_UINT8: return (float)((const uint8_t *)data)[j];
    case LC_VALUE_UINT16: return (float)((const uint16_t *)data)[j];
    case LC_VALUE_INT16: return (float)((const int16_t *)data)[j];
    default: return ((const float *)data)[j];
    }
}

/* The nodes of a grid as samples; NaN voxels are named by (i, j, k). */
static lc_status from_grid(lc_device *dev, const char *name, const lc_grid_desc *g, const char *format,
                           lc_samples **out)
{
    size_t ts = type_size(g->type);
    if (!ts || !g->data)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: the grid needs a value type and data", name);
    uint64_t n = 1;
    for (int a = 0; a < 3; a++) {
        if (g->size[a] < 2) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: grid size %d on axis %d, expected >= 2",
                                             name, g->size[a], a);
        n *= (uint64_t)g->size[a];
        if (n > LCI_MAX_SAMPLES)
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: more than %zu grid nodes", name, LCI_MAX_SAMPLES);
    }
    lc_vec3 sp = g->spacing;
    if (sp.x == 0.0f && sp.y == 0.0f && sp.z == 0.0f) sp = (lc_vec3){1.0f, 1.0f, 1.0f};
    if (!(sp.x > 0.0f && sp.y > 0.0f && sp.z > 0.0f && isfinite(sp.x) && isfinite(sp.y) && isfinite(sp.z)))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: grid spacing must be > 0 and finite", name);
    if (g->type == LC_VALUE_FLOAT32) {
        size_t bad = 0, first = 0;
        for (size_t j = 0; j < n; j++)
            if (!isfinite(((const float *)g->data)[j]) && !bad++) first = j;
        if (bad) {
            size_t nx = (size_t)g->size[0], ny = (size_t)g->size[1];
            return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                             "%s: voxel (%zu, %zu, %zu) is not finite (%zu non-finite voxels)", name, first % nx,
                             first / nx % ny, first / (nx * ny), bad);
        }
    }
    float *p = malloc(sizeof(float) * 3 * n), *v = malloc(sizeof(float) * n);
    if (!p || !v) {
        free(p), free(v);
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %llu samples", name, (unsigned long long)n);
    }
    size_t j = 0;
    for (int k = 0; k < g->size[2]; k++)
        for (int y = 0; y < g->size[1]; y++)
            for (int x = 0; x < g->size[0]; x++, j++) {
                p[3 * j] = g->origin.x + (float)x * sp.x;
                p[3 * j + 1] = g->origin.y + (float)y * sp.y;
                p[3 * j + 2] = g->origin.z + (float)k * sp.z;
                v[j] = voxel(g->data, g->type, j);
            }
    lc_status s = lci_samples_adopt(dev, name, p, v, n, format, n * ts, out);
    if (s == LC_OK) {
        (*out)->info.grid = 1;
        memcpy((*out)->info.size, g->size, sizeof g->size);
    }
    return s;
}

lc_status lc_samples_create(lc_device *dev, const lc_samples_desc *d, lc_samples **out)
{
    const char *name = "lc_samples_create";
    if (!dev) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "%s: device is NULL", name);
    if (!d || !out) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: desc and out must not be NULL", name);
    *out = NULL;
    if (!d->points && d->grid) return from_grid(dev, name, d->grid, "", out);
    if (!d->points || !d->values)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: give points and values, or a grid", name);
    if (d->count == 0 || d->count > LCI_MAX_SAMPLES)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: count %zu is not in 1..%zu", name, d->count,
                         LCI_MAX_SAMPLES);
    float *p = malloc(sizeof(float) * 3 * d->count), *v = malloc(sizeof(float) * d->count);
    if (!p || !v) {
        free(p), free(v);
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "%s: out of memory for %zu samples", name, d->count);
    }
    memcpy(p, d->points, sizeof(float) * 3 * d->count);
    memcpy(v, d->values, sizeof(float) * d->count);
    return lci_samples_adopt(dev, name, p, v, d->count, "", 0, out);
}

/* The extension of path (".gz" looked through), lower case compare. */
static int has_ext(const char *path, const char *ext)
{
    size_t n = strlen(path), e = strlen(ext);
    if (n > 3 && !strcasecmp(path + n - 3, ".gz")) n -= 3;
    return n > e && !strncasecmp(path + n - e, ext, e);
}

lc_status lc_samples_load(lc_device *dev, const char *path, const lc_load_desc *desc, lc_samples **out)
{
    if (!dev) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_samples_load: device is NULL");
    if (!path || !out) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_samples_load: path and out must not be NULL");
    *out = NULL;
    const char *fmt = desc && desc->format && desc->format[0] ? desc->format : NULL;
    int csv = fmt ? !strcmp(fmt, "csv") : 0, vtk = fmt ? !strcmp(fmt, "vtk") : 0;
    if (!fmt) {
        unsigned char head[512];
        size_t n = 0;
        int gz;
        lc_status s = lci_file_head(dev, path, head, sizeof head, &n, &gz);
        if (s != LC_OK) return s;
        vtk = lci_vtk_magic(head, n);
        csv = !vtk && has_ext(path, ".csv");
    }
    if ((csv || vtk) && desc && (desc->noptions || desc->frame || (desc->companion && desc->companion[0])))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "%s: %s files take no options, frame or companion", path,
                         csv ? "csv" : "vtk");
    if (csv) return lci_samples_read_csv(dev, path, out);
    if (vtk) return lci_samples_read_vtk(dev, path, out);
    lci_loaded l;
    const char *format = "";
    lc_status s = lci_read_grid(dev, path, desc, &format, &l);
    if (s != LC_OK) return s;
    s = from_grid(dev, path, l.desc, format, out);
    lci_loaded_free(&l);
    return s;
}

lc_status lc_samples_get_info(const lc_samples *s, lc_samples_info *out)
{
    if (!s || !out) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_samples_get_info: samples and out must not be NULL");
    *out = s->info;
    return LC_OK;
}

void lc_samples_destroy(lc_samples *s)
{
    if (!s) return;
    free(s->p), free(s->v), free(s);
}
