/* Stage-profile variants of the grid kernels (lanecast bench --profile,
 * tools/bench_profile.c): kernels/grid_bvh.c and grid_brute.c compiled again
 * for a target (avx2, avx512) with GRID_PROF = PROF_MASK (stages replaced by
 * stand-ins, kernels/grid_common.h) and entry points renamed
 * grid_bvh_prof<PROF_ID> / grid_brute_prof<PROF_ID> (PROF_ID = _<target>_<i>).
 * Linked into the benchmark only; no render but --profile's calls them. */
#include "lane/lane.h"
#undef LC_KFN
#define PROF_CAT2(a, b) a##_prof##b
#define PROF_CAT(a, b) PROF_CAT2(a, b)
#define LC_KFN(name) PROF_CAT(name, PROF_ID)
#define GRID_PROF PROF_MASK
#include "grid_brute.c"
#include "grid_bvh.c"
