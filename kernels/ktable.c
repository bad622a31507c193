/* The one kernel table of this target. */
#include "lane/lane.h"
#include "shared/ktable.h"

void LC_KFN(lc_lane_apply)(const lc_lane_args *args);

const lc_ktable LC_KFN(lc_ktable) = {
    .name = LC_TARGET_NAME,
    .lanes = LC_W,
    .lane_apply = LC_KFN(lc_lane_apply),
};
