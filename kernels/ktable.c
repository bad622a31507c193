/* The one kernel table of this target. */
#include "kernels.h"

const lc_ktable LC_KFN(lc_ktable) = {
    .name = LC_TARGET_NAME,
    .lanes = LC_W,
    .lane_apply = LC_KFN(lc_lane_apply),
    .particles_coherent = LC_KFN(particles_coherent),
    .particles_direct = LC_KFN(particles_direct),
    .particles_scratch_bytes = LC_KFN(particles_scratch_bytes),
    .particles_sample = LC_KFN(particles_sample),
    .grid_bvh = LC_KFN(grid_bvh),
    .grid_brute = LC_KFN(grid_brute),
    .grid_scratch_bytes = LC_KFN(grid_scratch_bytes),
};
