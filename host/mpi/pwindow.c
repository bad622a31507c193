/* The part of a particle set one rank of a data-parallel render holds
 * (dp.h "Particle parts"): the particles whose support, grown by two steps,
 * reaches its region's cell, in a particle volume that is the whole set to
 * the frame (bounds, radii, value range: lci_particles_set_global) and
 * keeps the kd-tree its load built. Without MPI; host/mpi/mpi_pload.c
 * distributes the particles and reduces the extremes. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "host/mpi/dp.h"

float lci_dp_reach(float support, float r, float dt) { return support * r * 1.01f + 1e-6f + 2.0f * dt; }

static void near_node(const lci_kdtree *t, int id, const float c[3], float reach, void (*add)(void *, int), void *user)
{
    const lci_kd_node *n = &t->node[id];
    if (n->leaf >= 0) {
        add(user, n->leaf);
        return;
    }
    /* a sample's float position may round past a plane by an ulp of its coordinates */
    float x = c[n->axis], w = reach + 1e-6f * fabsf(x);
    if (x - w < n->split) near_node(t, n->child[0], c, reach, add, user);
    if (x + w >= n->split) near_node(t, n->child[1], c, reach, add, user);
}

void lci_dp_regions_near(const lci_kdtree *t, float x, float y, float z, float reach, void (*add)(void *, int),
                         void *user)
{
    const float c[3] = {x, y, z};
    near_node(t, 0, c, reach, add, user);
}

lc_box3 lci_dp_particle_bounds(const lci_particles_global *g, float support)
{
    float m = support * g->max_radius;
    if (!g->count) return (lc_box3){{0, 0, 0}, {0, 0, 0}};
    lc_box3 b = g->bounds;
    b.lo.x -= m, b.lo.y -= m, b.lo.z -= m;
    b.hi.x += m, b.hi.y += m, b.hi.z += m;
    return b;
}

void lci_dp_ppart_free(void *p)
{
    lci_dp_ppart *pp = p;
    if (!pp) return;
    lci_kd_release(&pp->tree);
    free(pp);
}

lci_dp_ppart *lci_dp_ppart_keep(lc_device *dev, lci_dp_ppart *pp)
{
    lci_dp_ppart *keep = malloc(sizeof *keep);
    if (!keep) {
        lci_kd_release(&pp->tree);
        lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "data-parallel load: out of memory");
        return NULL;
    }
    *keep = *pp;
    memset(&pp->tree, 0, sizeof pp->tree);
    return keep;
}

lc_status lci_dp_particles_attach(lc_device *dev, lc_volume *v, const lci_particles_global *g, lci_dp_ppart *pp)
{
    lci_dp_ppart *keep = lci_dp_ppart_keep(dev, pp);
    if (!keep) return LC_ERROR_OUT_OF_MEMORY;
    lci_particles_set_global(v, g, keep, lci_dp_ppart_free);
    return LC_OK;
}

lc_status lci_dp_particles_create(lc_device *dev, const lc_particles_desc *d, const lci_particles_global *g,
                                  lci_dp_ppart *pp, lc_volume **out)
{
    /* every part orders over the whole set's centre bounds, as the whole set does (Embree's
       build ignores the box) */
    lc_particles_desc c = *d;
    static const lc_box3 none;
    if (!memcmp(&c.order_box, &none, sizeof none)) c.order_box = g->bounds;
    lc_status s = lc_particles_create(dev, &c, out);
    if (s == LC_OK) s = lci_dp_particles_attach(dev, *out, g, pp);
    else lci_kd_release(&pp->tree);
    if (s != LC_OK && *out) lc_volume_destroy(*out), *out = NULL;
    return s;
}

typedef struct hit {
    int leaf, found;
} hit;

static void hit_add(void *u, int leaf)
{
    hit *h = u;
    h->found |= leaf == h->leaf;
}

void lci_dp_particles_free(lc_particles_desc *d)
{
    free((void *)d->positions), free((void *)d->radii), free((void *)d->values), free((void *)d->fields);
    free((void *)d->norm_weights);
    memset(d, 0, sizeof *d);
}

lc_status lci_dp_particles_cut(lc_device *dev, const lc_particles_desc *whole, const lci_kdtree *t, int leaf,
                               float support, float dt, float margin, lc_particles_desc *out)
{
    *out = *whole;
    out->positions = NULL, out->radii = NULL, out->values = NULL, out->fields = NULL, out->count = 0;
    out->norm_weights = NULL;
    size_t n = whole->count, m = n ? n : 1;
    float *xyz = malloc(12 * m), *r = malloc(4 * m), *k = malloc(4 * m);
    float *w = whole->norm_weights ? malloc(4 * m) : NULL;
    uint8_t *f = malloc(m);
    out->positions = xyz, out->radii = r, out->values = k, out->fields = f, out->norm_weights = w;
    if (!xyz || !r || !k || !f || (whole->norm_weights && !w)) {
        lci_dp_particles_free(out);
        return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "data-parallel cut: out of memory for %zu particles", n);
    }
    size_t j = 0;
    for (size_t i = 0; i < n; i++) {
        const float *p = whole->positions + 3 * i;
        float ri = whole->radii ? whole->radii[i] : whole->radius;
        hit h = {leaf, 0};
        lci_dp_regions_near(t, p[0], p[1], p[2], margin * lci_dp_reach(support, ri, dt), hit_add, &h);
        if (!h.found) continue;
        memcpy(xyz + 3 * j, p, 12);
        r[j] = ri;
        k[j] = whole->values ? whole->values[i] : 1.0f;
        if (w) w[j] = whole->norm_weights[i];
        f[j++] = whole->fields ? whole->fields[i] : 0;
    }
    out->count = j;
    return LC_OK;
}

const lci_dp_ppart *lci_dp_part_of(const lc_volume *v)
{
    const lci_dp_ppart *pp = lci_particles_part(v);
    return pp ? pp : lci_rbf_part(v);
}

lc_status lci_dp_particles_check(lc_device *dev, const lc_render_desc *d, int P, int leaf)
{
    const lci_dp_ppart *pp = lci_dp_part_of(d->volume);
    if (!pp) return LC_OK;
    const char *what = lc_volume_kind(d->volume) == LC_KIND_RBF ? "RBFs" : "particles";
    if (pp->parts != P || pp->part != leaf)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "data-parallel render: these %s are the part of region %d of %d they were loaded for, "
                         "not region %d of %d",
                         what, pp->part, pp->parts, leaf, P);
    lc_particles_info pi;
    lci_frame_info fi;
    memset(&fi, 0, sizeof fi);
    lc_status s = d->volume->ops->frame_info(dev, d->volume, &fi);
    if (s != LC_OK) return s;
    float support = 1.0f; /* an RBF's support R_i is fixed by eps at load */
    if (lc_volume_kind(d->volume) == LC_KIND_PARTICLES && lc_particles_get_info(d->volume, &pi) == LC_OK)
        support = pi.params.kernel == LC_KERNEL_GAUSSIAN ? pi.params.sigma : 1.0f;
    float dt = d->dt > 0.0f ? d->dt : fi.default_dt;
    if (support > pp->support)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "data-parallel render: the particles' support is %g radii, but their ghosts were loaded for %g "
                         "(load with option sigma)",
                         (double)support, (double)pp->support);
    if (dt > pp->dt)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "data-parallel render: step dt = %g is longer than the %g the %s' ghosts were loaded for",
                         (double)dt, (double)pp->dt, what);
    return LC_OK;
}
