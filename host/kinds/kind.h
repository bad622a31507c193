/* A data kind as lc_render, lc_volume_* and the file loaders see it: one row
 * of operations per kind (Open VKL's volume interface in C). Every kind's
 * object starts with struct lc_volume, whose ops point at its row; the
 * renderer, the volume calls and the loaders never ask which kind they hold.
 * Adding a kind: one host file with its row, one kernel file with its
 * kernel sub-table, one shared struct, a row in kinds.c and in the kernel
 * table (docs/DEVELOPERS.md "A new data kind"). */
#ifndef LC_HOST_KIND_H
#define LC_HOST_KIND_H

#include "host/internal.h"

/* What a frame needs to know of the data before it is prepared. */
typedef struct lci_frame_info {
    lc_box3 bounds;         /* where samples may be non-zero (SPEC.md lattice clip box) */
    float default_dt;
    float default_range[2]; /* value range when neither the desc nor the TF gives one */
    int nfields;            /* fields the data has */
} lci_frame_info;

/* A volume prepared for one frame: the kernel to run per tile and its scene. */
typedef struct lci_prepared {
    lc_ktile_fn tile;
    const void *kscene;
    uint64_t scratch_bytes; /* per worker */
    void *owned;            /* freed with free() after the frame, or */
    void (*release)(void *owned); /* if not NULL, passed to this instead */
    int tile_side;          /* the kind's tile side in pixels when the desc leaves tile at 0 (0: 32) */
} lci_prepared;

typedef struct lci_kind_ops {
    lc_kind kind;
    const char *name;  /* lc_kind_name */
    int krow;          /* its sub-table in lc_ktable.kind[] (LC_KKIND_*) */
    /* option keys the kind's build takes from lc_load_desc (space-separated) */
    const char *option_keys;
    /* creates the volume from the kind's public descriptor (lc_*_desc) */
    lc_status (*create)(lc_device *dev, const void *desc, lc_volume **out);
    /* applies one build option (one of option_keys) to a descriptor a reader filled */
    lc_status (*set_option)(lc_device *dev, void *desc, const lc_option *opt, const char *file);
    void (*destroy)(lc_volume *v);
    /* bounds, default step and range, fields under the current parameters */
    lc_status (*frame_info)(lc_device *dev, const lc_volume *v, lci_frame_info *out);
    /* the kernel scene and tile function for one frame */
    lc_status (*prepare)(lc_device *dev, const lc_volume *v, const lc_render_desc *desc, const lc_kframe *frame,
                         lci_prepared *out);
    /* the kernel scene for point sampling (lc_volume_sample), with its scratch */
    lc_status (*sample_scene)(lc_device *dev, const lc_volume *v, void **kscene, uint64_t *scratch_bytes);
} lci_kind_ops;

struct lc_volume {
    const lci_kind_ops *ops;
    lc_device *device;
    char read_note[128]; /* lc_mpi_volume_load: what this rank read ("" otherwise; lc_mpi_stats.read) */
};

/* host/kinds/kinds.c: the rows, indexed by lc_kind (NULL for none). */
const lci_kind_ops *lci_kind(lc_kind kind);
extern const lci_kind_ops lci_particles_ops;
extern const lci_kind_ops lci_grid_ops;
extern const lci_kind_ops lci_rbf_ops;

/* The volume as kind k, or NULL (with an error naming fn) if it is another kind. */
void *lci_volume_as(const lc_volume *v, lc_kind k, const char *fn);

/* The centres of a particle set or an RBF set (the kind's arrays, leaf
 * order), for balancing a data-parallel partition (host/mpi/). */
lc_status lci_particles_centres(const lc_volume *v, size_t *n, const float **x, const float **y, const float **z);
/* A particle set's arrays in leaf order (projections, host/sph/project.c):
 * src[j] is particle j's index in the lc_particles_desc it was created from
 * (total = kept + dropped indices). Errors name fn. */
typedef struct lci_particle_view {
    size_t n, total;
    const float *x, *y, *z, *r, *k;
    const uint8_t *field; /* field ids */
    const uint32_t *src;
    lc_particle_params params;
    lc_box3 bounds; /* of the centres */
    float max_radius;
} lci_particle_view;
lc_status lci_particles_view(const lc_volume *v, const char *fn, lci_particle_view *out);
/* Data-parallel parts (host/mpi/): why particle i of d is invalid (NULL:
 * valid; lc_particles_create's rule); a set's extremes (an empty set gives
 * +-inf bounds, so they reduce by MIN / MAX over parts); and a part made
 * the whole set to the frame (bounds, radii, value range and the
 * empty-space bounds' cells from g), holding `part` (freed with
 * part_free on destroy). */
typedef struct lci_particles_global {
    size_t count;
    lc_box3 bounds;
    float min_radius, max_radius, kmin, kmax;
    double kh3min, kh3max;
    float amin, amax; /* of the A_i = k_i / w_i with norm_weights w_i (amin > amax: none) */
} lci_particles_global;
const char *lci_particles_invalid(const lc_particles_desc *d, size_t i, int nfields);
void lci_particles_extremes(const lc_volume *v, lci_particles_global *g);
void lci_particles_set_global(lc_volume *v, const lci_particles_global *g, void *part, void (*part_free)(void *));
void *lci_particles_part(const lc_volume *v); /* NULL: a whole set, or another kind */
/* The same for RBF sets: what a part takes from the whole set (the default
 * range's peaks at the centres, the widths, the largest support, the range
 * bound, the count). */
typedef struct lci_rbf_global {
    size_t count;
    float peak[2], min_width, max_width, max_support, range[2];
} lci_rbf_global;
void lci_rbf_global_of(const lc_volume *v, lci_rbf_global *g);
void lci_rbf_set_global(lc_volume *v, const lci_rbf_global *g, void *part, void (*part_free)(void *));
void *lci_rbf_part(const lc_volume *v); /* NULL: a whole set, or another kind */
lc_status lci_rbf_centres(const lc_volume *v, size_t *n, const float **x, const float **y, const float **z);

/* host/api/camera.c: the kernel camera for the desc (default framing of bounds). */
lc_status lci_camera_build(lc_device *dev, const lc_camera *cam, int width, int height, const lc_box3 *bounds,
                           lc_kcamera *out);
/* The camera of an image every s-th pixel of the built one (pixel_scale). */
void lci_camera_subsample(lc_kcamera *cam, int s);


#endif
