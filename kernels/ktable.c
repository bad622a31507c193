/* The one kernel table of this target: a row per data kind. */
#include "kernels.h"

const lc_ktable LC_KFN(lc_ktable) = {
    .name = LC_TARGET_NAME,
    .lanes = LC_W,
    .lane_apply = LC_KFN(lc_lane_apply),
    .kind = {
        [LC_KKIND_PARTICLES] = &LC_KFN(lc_kkind_particles),
        [LC_KKIND_GRID] = &LC_KFN(lc_kkind_grid),
        [LC_KKIND_RBF] = &LC_KFN(lc_kkind_rbf),
    },
    .resample_brick = LC_KFN(lc_resample_brick),
};
