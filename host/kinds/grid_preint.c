/* The pre-integrated transfer function (Engel et al.; Knoll et al. 2011 eq. 4):
 * for every pair of quantised normalised values (a, b), the mean extinction of
 * the TF over the values from a to b and the extinction-weighted mean colour.
 * A segment of length dt between samples valued a and b then has opacity
 * 1 - exp(-tau_mean dt), which is eq. 4. Integrals are exact prefix sums of
 * the kernel table's piecewise-linear interpolant, so a zero mean means the
 * kernel would classify every value in [a, b] as fully transparent. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include "host/kinds/grid.h"

#define NT LC_TF_TABLE_SIZE

typedef struct prefix {
    double t[NT];    /* integral of tau from 0 to x_j */
    double c[NT][3]; /* integral of rgb * tau */
} prefix;

static void partial(const float *rgbt, int j, double s, double *t, double c[3])
{
    const double h = 1.0 / (NT - 1);
    const float *e0 = rgbt + 4 * j, *e1 = e0 + 4;
    double t0 = e0[3], dtau = (double)e1[3] - e0[3];
    *t = t0 * s + dtau * s * s / (2 * h);
    for (int k = 0; k < 3; k++) {
        double c0 = e0[k], dc = (double)e1[k] - e0[k];
        c[k] = c0 * t0 * s + (c0 * dtau + t0 * dc) * s * s / (2 * h) + dc * dtau * s * s * s / (3 * h * h);
    }
}

static void eval_prefix(const prefix *p, const float *rgbt, double v, double *t, double c[3])
{
    int j = (int)floor(v * (NT - 1));
    if (j > NT - 2) j = NT - 2;
    if (j < 0) j = 0;
    double pt, pc[3];
    partial(rgbt, j, v - (double)j / (NT - 1), &pt, pc);
    *t = p->t[j] + pt;
    for (int k = 0; k < 3; k++) c[k] = p->c[j][k] + pc[k];
}

static void eval_point(const float *rgbt, double v, double rgb[3], double *tau)
{
    double x = v * (NT - 1);
    int j = (int)floor(x);
    if (j > NT - 2) j = NT - 2;
    double w = x - j;
    for (int k = 0; k < 3; k++) rgb[k] = rgbt[4 * j + k] + w * (rgbt[4 * j + 4 + k] - rgbt[4 * j + k]);
    *tau = rgbt[4 * j + 3] + w * (rgbt[4 * j + 7] - rgbt[4 * j + 3]);
}

static float keep_positive(double x) { return x > 0.0 && (float)x < FLT_MIN ? FLT_MIN : (float)x; }

void lci_grid_preint(const float *rgbt, float *table)
{
    prefix *p = malloc(sizeof *p);
    double qv[LC_PREINT_N], qt[LC_PREINT_N], qc[LC_PREINT_N][3];
    if (p) {
        p->t[0] = 0.0;
        p->c[0][0] = p->c[0][1] = p->c[0][2] = 0.0;
        for (int j = 0; j + 1 < NT; j++) {
            double t, c[3];
            partial(rgbt, j, 1.0 / (NT - 1), &t, c);
            p->t[j + 1] = p->t[j] + t;
            for (int k = 0; k < 3; k++) p->c[j + 1][k] = p->c[j][k] + c[k];
        }
        for (int q = 0; q < LC_PREINT_N; q++) {
            qv[q] = (double)q / (LC_PREINT_N - 1);
            eval_prefix(p, rgbt, qv[q], &qt[q], qc[q]);
        }
    }
    for (int a = 0; a < LC_PREINT_N; a++) {
        for (int b = 0; b < LC_PREINT_N; b++) {
            float *o = table + ((size_t)a * LC_PREINT_N + (size_t)b) * 4;
            double rgb[3], tau;
            if (a == b || !p) {
                eval_point(rgbt, (double)a / (LC_PREINT_N - 1), rgb, &tau);
                if (!p && a != b) { /* out of memory: point classification of the segment's end */
                    eval_point(rgbt, (double)b / (LC_PREINT_N - 1), rgb, &tau);
                }
            } else {
                double dv = qv[b] - qv[a], it = qt[b] - qt[a];
                tau = it / dv;
                if (it != 0.0) {
                    for (int k = 0; k < 3; k++) rgb[k] = (qc[b][k] - qc[a][k]) / it;
                } else {
                    double t2;
                    eval_point(rgbt, 0.5 * (qv[a] + qv[b]), rgb, &t2);
                }
            }
            o[0] = (float)rgb[0];
            o[1] = (float)rgb[1];
            o[2] = (float)rgb[2];
            o[3] = keep_positive(tau);
        }
    }
    free(p);
}
