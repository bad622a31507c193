/* lanecast render / demo: the command's options and their parsing
 * (render_opts.c); cmd_render.c runs them. */
#ifndef LC_TOOLS_RENDER_OPTS_H
#define LC_TOOLS_RENDER_OPTS_H

#include <stdint.h>
#include "cli_kind.h"

/* The kinds the command line knows, one row each (cli_kind.h). */
#define NKINDS 3
extern const cli_kind *const cli_kinds[NKINDS];
/* The input flags of every command that reads a file (tools/cli_input.c): argv[*i] parsed by the kind
 * rows into load (first[NKINDS]: each kind's first flag seen); 1 consumed, 0 none of them, -1 bad. */
int cli_input_flag(const char *cmd, int argc, char **argv, int *i, cli_load *load, const char **first);
/* load's options then extra[0..nextra) into out (cap entries); their count, or -1 (message printed). */
int cli_input_merge(const char *cmd, const cli_load *load, const lc_option *extra, int nextra, lc_option *out,
                    int cap);

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
    int composite, bands;   /* under mpirun: --composite (0 auto, 1 chain, 2 swap: lc_mpi_compositing), --bands */
    /* trajectories: --frame, or --frames first:end:step (end -1 = to the last) */
    int64_t frame, first, end, step;
    int seq;
    const char *topology;
    int iso_set, field_set; /* --iso, --field given */
    int resample;           /* --resample N: particles through an N^3 deposited grid, 0 = off */
    uint64_t max_memory;    /* --max-memory in bytes, 0 = not given */
    struct {                /* --mode project (cli_project.c) */
        int on, linear, colorbar;
        lc_project_sample sample;
        const char *weight;
        float depth;
        const char *first; /* the first projection flag given */
    } pj;
} ropts;

/* --mode project (cli_project.c): its help section, flags (1 consumed, 0 not
 * one, -1 bad), their check after parsing (0 ok, -1 message printed), and
 * the run once the input's kind is known (an exit status). */
extern const char cli_project_help[];
int cli_project_flag(ropts *o, int argc, char **argv, int *i);
int cli_project_check(const ropts *o);
int cli_project_run(ropts *o, lc_device *dev, const cli_kind *kind);

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
