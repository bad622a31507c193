#ifndef LC_CLI_H
#define LC_CLI_H

#include "lanecast/lanecast.h"

#define CLI_EXIT_FAIL 1
#define CLI_EXIT_USAGE 2

int cli_targets(int argc, char **argv);
int cli_formats(int argc, char **argv);
int cli_render(int argc, char **argv);
int cli_demo(int argc, char **argv);
int cli_info(int argc, char **argv);
int cli_encode(int argc, char **argv);
int cli_bench(int argc, char **argv);
int cli_resample(int argc, char **argv);
/* A particle set's field at the nodes of d (cmd_resample.c): a dry run that
 * checks the sizes, then the values into *values (malloc'd; NULL and a
 * message on stderr after an error), with a progress bar when asked. */
lc_status cli_resample_values(const char *cmd, lc_device *dev, const lc_volume *particles, const lc_resample_desc *d,
                              int progress, float **values, lc_resample_info *info);
int cli_view(int argc, char **argv);   /* viewer/ (view_missing.c without the feature) */
int cli_view_available(void);

/* The procedural scene of lanecast demo and its TF (cli_particles.c). */
lc_status cli_demo_scene(lc_device *dev, lc_volume **out, lc_tf **tf);

#endif
