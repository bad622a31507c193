/* lanecast render / demo: the command's options and their parsing
 * (render_opts.c); cmd_render.c runs them. */
#ifndef LC_TOOLS_RENDER_OPTS_H
#define LC_TOOLS_RENDER_OPTS_H

#include <stdint.h>
#include "cli_kind.h"

/* The kinds the command line knows, one row each (cli_kind.h). */
#define NKINDS 3
extern const cli_kind *const cli_kinds[NKINDS];

typedef struct ropts {
    const char *cmd;
    const char *input, *output;
    cli_load load;
    const char *first_flag[NKINDS]; /* first flag of each kind given */
    lc_render_desc rd;
    int target_set;
    lc_target target;
    int threads;
    const char *tf, *colormap;
    float tau;
    float opacity[2 * 256]; /* --opacity points [v, tau] */
    int nopacity;
    float view[2];          /* --view azimuth, elevation */
    int orbit;              /* --orbit N, 0 = off */
    int camera_set, view_set;
    lc_vec3 background;
    int alpha, stats, quiet, progress;
    /* trajectories: --frame, or --frames first:end:step (end -1 = to the last) */
    int64_t frame, first, end, step;
    int seq;
    const char *topology;
    int iso_set, field_set; /* --iso, --field given */
} ropts;

/* Returns 0 ok, 1 help printed, -1 usage error (message printed). */
int render_parse(ropts *o, int argc, char **argv, int want_input);
/* The name of image f of a sequence (-o pattern, checked by the parser). */
void render_frame_name(const char *pattern, int64_t f, char *out, size_t n);

#endif
