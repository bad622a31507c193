/* Projections' per-pixel inner loop (project_dot.c), chosen per target. */
#ifndef LC_SPH_PROJECT_H
#define LC_SPH_PROJECT_H

#include <stddef.h>
#include "lanecast/lanecast.h"

/* out[i] = sum_k row[k] * col[k * stride + i] for i in [0, n). */
typedef void (*lci_dot_fn)(int K, const float *row, const float *col, size_t stride, int n, float *out);

typedef struct lci_column lci_column;
/* lci_column_cumulative (column.h) compiled per target as the dot product. */
typedef void (*lci_cum_fn)(const lci_column *c, double u, double *out);

/* The loops compiled for the device's target: AVX2 + FMA on avx2 and the
 * AVX-512 targets, the baseline (SSE2) build otherwise. */
lci_dot_fn lci_project_dot(lc_target target);
lci_cum_fn lci_project_cum(lc_target target);

#endif
