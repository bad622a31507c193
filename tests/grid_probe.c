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
