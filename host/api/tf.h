/* Transfer functions (host/tf.c): one implementation for every data kind. */
#ifndef LC_HOST_TF_H
#define LC_HOST_TF_H

#include "host/internal.h"

typedef struct lci_tf_points {
    float *color; /* [v, r, g, b] */
    int ncolor;
    float *opacity; /* [v, tau] */
    int nopacity;
    int has_range;
    float range[2];
    int default_opacity; /* the source gave no opacity (lc_tf_field.default_opacity) */
} lci_tf_points;

struct lc_tf {
    int nfields;
    lci_tf_points field[LC_MAX_FIELDS];
};

/* Piecewise-linear evaluation at normalised v (clamped), in double: the
 * reference renderer and the table builder both use it. */
void lci_tf_eval(const lc_tf *tf, int field, double v, double rgb[3], double *tau);
/* Fills a kernel TF (LC_TF_TABLE_SIZE x rgbt table into `table`) for field f
 * with the value range [lo, hi]. */
void lci_tf_fill(const lc_tf *tf, int field, float lo, float hi, float *table, lc_ktf *out);
/* Builds the TF's step table for step dt into cls ((LC_TF_TABLE_SIZE + 1) * 4
 * floats) and points tf->cls at it (kframe.h lc_ktf). */
void lci_tf_step_table(float dt, float *cls, lc_ktf *tf);
/* The largest field value a dvr sample may have and still be fully
 * transparent in the TF, or -inf (+inf: transparent everywhere). */
float lci_tf_clear_below(const lc_ktf *tf);

/* The control points [v, r, g, b] of a built-in colour map by name (the
 * lc_tf_preset names); an unknown name fails, listing the known ones. */
lc_status lci_colormap(lc_device *device, const char *name, const float **points, int *n);

#endif
