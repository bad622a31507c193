/* Scalar double-precision reference renderer for structured grids, written
 * straight from SPEC.md (tests only). */
#ifndef LC_TEST_GRID_REF_H
#define LC_TEST_GRID_REF_H

#include "lanecast/lanecast.h"

typedef struct ref_grid {
    int n[3];
    double origin[3], spacing[3];
    const double *v; /* x fastest */
} ref_grid;

typedef struct ref_params {
    int width, height;
    double eye[3], at[3], up[3], fovy;
    const lc_tf *tf;
    double lo, hi;
    double dt, alpha_stop;
    int shade; /* 0 none, 1 diffuse, 2 phong */
    double rda; /* differential sampling: t_k = dt (k + rda k (k-1) / 2) */
} ref_params;

/* rgba: premultiplied (C, A), width * height * 4 floats. */
void ref_render(const ref_grid *g, const ref_params *p, float *rgba);
double ref_sample(const ref_grid *g, const double x[3], double grad[3]);

#endif
