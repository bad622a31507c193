/* Test-only probe compiled per target: trilinear value and eq. 9 gradient of
 * the grid kernels at given points (the conformance test checks them exact on
 * a linear field). */
#include "grid_common.h"

void LC_KFN(lc_test_grid_sample)(const lc_kgrid *g, const float *xyz, int n, float *val, float *grad);

void LC_KFN(lc_test_grid_sample)(const lc_kgrid *g, const float *xyz, int n, float *val, float *grad)
{
    for (int i = 0; i < n; i++) {
        vfloat gx, gy, gz;
        vfloat v = grid_sample(g, vf_set1(xyz[3 * i]), vf_set1(xyz[3 * i + 1]), vf_set1(xyz[3 * i + 2]), 1, &gx, &gy, &gz);
        val[i] = vf_lane(v, 0);
        grad[3 * i] = vf_lane(gx, 0);
        grad[3 * i + 1] = vf_lane(gy, 0);
        grad[3 * i + 2] = vf_lane(gz, 0);
    }
}

/* Test-only: the step-table classification (dvr.h dvr_classify_step) of n values
 * phi, LC_W distinct lanes at a time (so the row-load transpose is exercised
 * with a different table row per lane): out[4 i ..] = (a r, a g, a b, a). */
void LC_KFN(lc_test_classify_step)(const lc_ktf *tf, const float *phi, int n, float *out);

void LC_KFN(lc_test_classify_step)(const lc_ktf *tf, const float *phi, int n, float *out)
{
    for (int base = 0; base < n; base += LC_W) {
        float p[LC_W];
        for (int l = 0; l < LC_W; l++) p[l] = phi[base + l < n ? base + l : n - 1];
        vfloat r, gg, b, a;
        dvr_classify_step(tf, vf_load(p), &r, &gg, &b, &a);
        for (int l = 0; l < LC_W && base + l < n; l++) {
            float *o = out + 4 * (base + l);
            o[0] = vf_lane(r, l), o[1] = vf_lane(gg, l), o[2] = vf_lane(b, l), o[3] = vf_lane(a, l);
        }
    }
}
