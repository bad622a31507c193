/* A scalar double-precision reference renderer for particle data, written
 * straight from SPEC.md for the tests. It shares nothing with the library's
 * camera, transfer-function or kernel code: its own rays, its own
 * piecewise-linear TF evaluation from the lc_tf_field points, brute force over
 * the particles (with a per-ray cull of particles whose sigma*r sphere the ray
 * misses) and exp from libm. Explicit cameras only (no default framing). */
#ifndef LC_TEST_REF_PARTICLES_H
#define LC_TEST_REF_PARTICLES_H

#include <stddef.h>
#include <stdint.h>
#include "lanecast/lanecast.h"

typedef struct ref_particles {
    size_t count;
    const float *positions; /* 3 * count */
    const float *radii;     /* count */
    const float *values;    /* count, or NULL for 1 */
    const uint8_t *fields;  /* count, or NULL for field 0 */
    int nfields;
} ref_particles;

typedef struct ref_params {
    int width, height;
    lc_camera camera;         /* eye != at required; up zero = +y; fovy zero = 40 */
    const lc_tf_field *tf;    /* ntf fields: 1 (shared by every data field) or one per data field */
    int ntf;
    float range[2];           /* both 0: the TF field's range, else [0, |kappa|] */
    float dt;
    float alpha_stop;         /* 1 = never stop */
    lc_shading shading;
    lc_lighting lighting;     /* all zero = ka 0.2, kd 0.8, ks 0.4, p 16 */
    float sigma, kappa;       /* explicit, no defaults */
    float sphere_scale;       /* > 0: opaque spheres of radius scale * r_i */
} ref_params;

/* Writes width*height*4 doubles: premultiplied C, A, row 0 at the top.
 * Returns 0, or -1 on bad parameters or out of memory. */
int ref_render(const ref_particles *p, const ref_params *q, double *rgba);

/* Field values phi[f] and gradients grad[3 f + c] of every field at x
 * (SPEC.md "Fields"), double precision, brute force. Also returns per field
 * the sum of |terms| (abs_sum) and an error budget for float position
 * round-off (pos_sens: sum |dphi/dx| * (|x| + |x_i|), same for the gradient
 * in gpos_sens), and sets *near_cut when a term lies within a relative 1e-5 of
 * the truncation radius (float and double may then disagree on inclusion). */
void ref_field(const ref_particles *p, double sigma, double kappa, const double x[3], double *phi, double *grad,
               double *abs_sum, double *gabs_sum, double *pos_sens, double *gpos_sens, int *near_cut);

#endif
