/* The data kinds: one row each (kind.h), and the kind-neutral volume calls
 * of the public API, which only dispatch through the rows. */
#include <stdlib.h>
#include <string.h>
#include "host/kinds/kind.h"

static const lci_kind_ops *const rows[LC_KIND_COUNT] = {
    [LC_KIND_PARTICLES] = &lci_particles_ops,
    [LC_KIND_GRID] = &lci_grid_ops,
    [LC_KIND_RBF] = &lci_rbf_ops,
};

const lci_kind_ops *lci_kind(lc_kind kind)
{
    return (int)kind > 0 && kind < LC_KIND_COUNT ? rows[kind] : NULL;
}

const char *lc_kind_name(lc_kind kind)
{
    const lci_kind_ops *k = lci_kind(kind);
    return k ? k->name : NULL;
}

void *lci_volume_as(const lc_volume *v, lc_kind k, const char *fn)
{
    if (!v) {
        lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "%s: volume is NULL", fn);
        return NULL;
    }
    if (v->ops->kind != k) {
        lci_error(v->device, LC_ERROR_INVALID_ARGUMENT, "%s: the volume holds %s, not %s", fn, v->ops->name,
                  lc_kind_name(k));
        return NULL;
    }
    return (void *)v;
}

void lc_volume_destroy(lc_volume *v)
{
    if (v) v->ops->destroy(v);
}

lc_kind lc_volume_kind(const lc_volume *v) { return v ? v->ops->kind : LC_KIND_NONE; }

lc_status lc_volume_get_info(const lc_volume *v, lc_volume_info *out)
{
    if (!v || !out)
        return lci_error(v ? v->device : NULL, LC_ERROR_INVALID_ARGUMENT,
                         "lc_volume_get_info: volume and out must not be NULL");
    lci_frame_info fi;
    memset(&fi, 0, sizeof fi);
    lc_status s = v->ops->frame_info(v->device, v, &fi);
    if (s != LC_OK) return s;
    out->kind = v->ops->kind;
    out->bounds = fi.bounds;
    out->nfields = fi.nfields;
    out->range[0] = fi.default_range[0];
    out->range[1] = fi.default_range[1];
    return LC_OK;
}

lc_status lc_volume_sample(lc_device *dev, const lc_volume *v, size_t n, const float *points, float *values,
                           float *gradients)
{
    if (!dev) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_volume_sample: device is NULL");
    if (!v) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_volume_sample: volume is NULL");
    if (n > 0 && (!points || !values))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_volume_sample: points or values is NULL");
    if (n > (size_t)INT64_MAX / 3)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_volume_sample: %zu points is too many", n);
    void *ks = NULL;
    uint64_t sb = 0;
    lc_status s = v->ops->sample_scene(dev, v, &ks, &sb);
    if (s != LC_OK) return s;
    void *scratch = lci_aligned_alloc(64, (size_t)sb + 64);
    if (!scratch) {
        lci_aligned_free(ks);
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_volume_sample: out of memory");
    }
    unsigned int csr = __builtin_ia32_stmxcsr();
    lci_flush_denormals();
    dev->kt->kind[v->ops->krow]->sample(ks, points, (int64_t)n, values, gradients, scratch);
    __builtin_ia32_ldmxcsr(csr);
    lci_aligned_free(scratch);
    lci_aligned_free(ks);
    return LC_OK;
}
