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
    char *files; /* several inputs (a DICOM series' files): them all, one per line (load option files) */
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

/* cmd_render.c's steps, shared with lanecast view (viewer/view_main.c). */
/* The kind of the input, decided once through the formats registry (forced:
 * LC_KIND_PARTICLES for the demo); NULL after a message (*usage set when the
 * flags were at fault). *frames: the input's frame count; *fopts: its
 * format's option keys. */
const cli_kind *render_decide_kind(ropts *o, lc_device *dev, lc_kind forced, int *usage, int64_t *frames,
                                   const char **fopts);
/* Loads frame `frame` (or makes the demo scene), applies the kind's flags,
 * and builds the TF into *tf unless *tf is already set. */
lc_status render_load(ropts *o, lc_device *dev, int demo, const cli_kind *kind, int64_t frame, lc_volume **vol,
                      lc_tf **tf);
/* The camera of orbit image i (i = 0 without --orbit): the flags' camera,
 * else the data framed from --view. */
lc_status render_view_camera(const ropts *o, const lc_volume *vol, int i, lc_camera *cam);
/* v rotated about the unit axis k through the origin by a radians. */
lc_vec3 render_rotate(lc_vec3 v, lc_vec3 k, float a);

#endif
