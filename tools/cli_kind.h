/* One data kind's part of `lanecast render`: its flags (which become load
 * options of lc_volume_load and parameters of the volume), its help section
 * with its own defaults, its default transfer function and its --stats
 * lines. cmd_render.c knows no kind: it decides the kind once from the
 * input (lc_file_probe) and loops over the rows of cli_kinds. A new kind adds
 * one file like cli_particles.c and a row in cli_kinds (cmd_render.c). */
#ifndef LC_CLI_KIND_H
#define LC_CLI_KIND_H

#include <stdio.h>
#include "lanecast/lanecast.h"

/* Load options the flags collect: values are copied here. */
#define CLI_MAX_OPTIONS 16
typedef struct cli_load {
    const char *format; /* NULL = detect */
    lc_option opt[CLI_MAX_OPTIONS];
    char val[CLI_MAX_OPTIONS][1024]; /* a --select expression may be long */
    int n;
} cli_load;

/* Adds option key = value; -1 (message printed) when full. */
int cli_load_add(cli_load *l, const char *cmd, const char *key, const char *value);
/* Several inputs (a DICOM series given file by file): appends path to *files
 * (one per line, malloc'd; the caller frees it) and, for the second path,
 * points option files at it. -1 (message printed) when out of room. */
int cli_load_file(cli_load *l, const char *cmd, char **files, const char *first, const char *path);
/* Appends path to *files (one per line; first before it when *files is
 * NULL); -1 when out of memory. */
int cli_files_append(char **files, const char *first, const char *path);

typedef struct cli_tf_req {
    const char *preset;   /* --tf NAME, or NULL */
    const char *colormap; /* --colormap NAME, or NULL */
    float tau;            /* --tau, 0 = default */
} cli_tf_req;

typedef struct cli_kind {
    lc_kind kind;
    const char *help; /* the kind's section of `lanecast render --help` */
    /* Parses argv[*i] if it is this kind's flag: 1 consumed (advancing *i past
     * its value), 0 not this kind's, -1 bad value (message printed). Records
     * the first flag seen in *first (for "does not apply" errors). */
    int (*parse_flag)(const char *cmd, int argc, char **argv, int *i, cli_load *load, const char **first);
    /* After loading: the kind's parameters onto the volume and the desc. */
    lc_status (*apply)(lc_volume *v, lc_render_desc *rd);
    /* Before loading: load options the kind adds by default for a file of
     * this format (its option keys in format_options), knowing whether the
     * user chose the classification (tf_given: --tf, --colormap, --opacity).
     * NULL = none. 0 ok, -1 error (message printed). */
    int (*defaults)(const char *cmd, cli_load *load, const char *format_options, int tf_given);
    /* The default TF: a preset (--tf NAME: the preset's own ramp, as it
     * always was), else the colour map (--colormap, NULL = the kind's) on the
     * kind's default opacity; tau = --tau (0 = the kind's default). */
    lc_status (*default_tf)(lc_device *dev, const lc_volume *v, const cli_tf_req *req, lc_tf **out);
    void (*print_stats)(const lc_volume *v, double load_seconds, FILE *f);
    const char *evals; /* --stats label of lc_render_stats.kernel_evals, 13 characters */
} cli_kind;

extern const cli_kind cli_particles, cli_grid, cli_rbf;

/* The row of a kind (cmd_render.c's table), or NULL. */
const cli_kind *cli_kind_of(lc_kind kind);

#endif
