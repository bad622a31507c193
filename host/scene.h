/* What a data kind (particles, grids, later RBF sets) provides to lc_render:
 * its bounds and defaults, then a prepared kernel scene for one frame. The
 * camera, transfer functions, tiles, threads and images are shared. */
#ifndef LC_HOST_SCENE_H
#define LC_HOST_SCENE_H

#include "internal.h"
#include "tf.h"
#include "../kernels/shared/kparticles.h"

typedef struct lci_scene_info {
    lc_box3 bounds;         /* where samples may be non-zero (SPEC.md lattice clip box) */
    float default_dt;
    float default_range[2]; /* value range when neither the desc nor the TF gives one */
    int nfields;            /* fields the data has */
} lci_scene_info;

/* A scene prepared for one frame: exactly one of the tile functions is set. */
typedef struct lci_prepared {
    lc_particles_tile_fn particles_fn;
    const struct lc_kparticles *particles;
    lc_grid_tile_fn grid_fn;
    const struct lc_kgrid *grid;
    uint64_t scratch_bytes; /* per worker */
    void *owned;            /* freed with free() after the frame */
} lci_prepared;

lc_status lci_particles_info(lc_device *dev, const lc_particles *p, const lc_render_desc *desc, lci_scene_info *out);
lc_status lci_particles_prepare(lc_device *dev, const lc_particles *p, const lc_render_desc *desc,
                                const lc_kframe *frame, lci_prepared *out);
/* The kernel view of particles (no frame-specific fields), for tests and sampling. */
void lci_particles_kscene(const lc_particles *p, float sigma, float kappa, struct lc_kparticles *out);

lc_status lci_grid_info(lc_device *dev, const lc_grid *g, const lc_render_desc *desc, lci_scene_info *out);
lc_status lci_grid_prepare(lc_device *dev, const lc_grid *g, const lc_render_desc *desc, const lc_kframe *frame,
                           lci_prepared *out);

/* host/camera.c: the kernel camera for the desc (default framing of bounds). */
lc_status lci_camera_build(lc_device *dev, const lc_camera *cam, int width, int height, const lc_box3 *bounds,
                           lc_kcamera *out);

/* host/frame.c: everything in lc_kframe from the desc, info and TF; the TF
 * tables go into `tables` (LC_MAX_FIELDS * LC_TF_TABLE_SIZE * 4 floats). */
lc_status lci_frame_build(lc_device *dev, const lc_render_desc *desc, const lci_scene_info *info, const lc_tf *tf,
                          float *tables, lc_kframe *out);

#endif
