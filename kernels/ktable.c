/* The one kernel table of this target. */
#include "lane/lane.h"
#include "shared/ktable.h"

void LC_KFN(lc_lane_apply)(const lc_lane_args *args);
void LC_KFN(lc_grid_bvh)(const struct lc_kgrid *g, const lc_kframe *f, const lc_ktile *t, lc_kscratch *scratch,
                         lc_kstats *st);
void LC_KFN(lc_grid_brute)(const struct lc_kgrid *g, const lc_kframe *f, const lc_ktile *t, lc_kscratch *scratch,
                           lc_kstats *st);
uint64_t LC_KFN(lc_grid_scratch_bytes)(const struct lc_kgrid *g, const lc_kframe *f);

const lc_ktable LC_KFN(lc_ktable) = {
    .name = LC_TARGET_NAME,
    .lanes = LC_W,
    .lane_apply = LC_KFN(lc_lane_apply),
    .grid_bvh = LC_KFN(lc_grid_bvh),
    .grid_brute = LC_KFN(lc_grid_brute),
    .grid_scratch_bytes = LC_KFN(lc_grid_scratch_bytes),
};
