/* The structured-volume part of `lanecast render` (issue 4): which inputs are
 * volumes, the volume flags, loading and the --stats lines. Kept apart from
 * cmd_render.c so the shared options stay in one place. */
#ifndef LC_CLI_RENDER_GRID_H
#define LC_CLI_RENDER_GRID_H

#include <stdio.h>
#include "lanecast/lanecast.h"

typedef struct grid_opts {
    lc_grid_load_options load;
    int dims_given;
    int preintegrated, no_bvh;
    float rda;
    float delta_c, delta_p, delta_sv; /* 0 = default, < 0 = off */
} grid_opts;

extern const char grid_render_help[];

/* 1 if INPUT is a volume: .nrrd/.nhdr/.mhd/.mha, or any file with --dims. */
int grid_is_volume(const grid_opts *g, const char *input);
/* Parses argv[*i] if it is a volume flag: 1 consumed (advancing *i past a
 * value), 0 not a volume flag, -1 bad value (message printed). */
int grid_parse_flag(grid_opts *g, const char *cmd, int argc, char **argv, int *i);
/* Applies the volume flags to the render desc (method, grid params). */
void grid_apply(const grid_opts *g, lc_render_desc *rd);
/* Loads the volume, builds its BVH. */
lc_status grid_load(lc_device *dev, const grid_opts *g, const char *input, lc_grid **out, lc_grid_info *info);
void grid_print_stats(const lc_grid_info *in, FILE *f);

#endif
