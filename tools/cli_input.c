/* The input flags of every command that reads a data file (lanecast render,
 * view, info, encode): one table, the kind rows of cli_kinds (render_opts.c),
 * whose parse_flag functions turn --dims/--type/--spacing/--big-endian,
 * --raw-particles, --radius, --select, ... into load options; so a command
 * cannot take an input other than render takes it. */
#include <string.h>
#include "render_opts.h"

int cli_input_flag(const char *cmd, int argc, char **argv, int *i, cli_load *load, const char **first)
{
    int r = 0;
    for (int k = 0; k < NKINDS && !r; k++) r = cli_kinds[k]->parse_flag(cmd, argc, argv, i, load, &first[k]);
    return r;
}

int cli_input_merge(const char *cmd, const cli_load *load, const lc_option *extra, int nextra, lc_option *out,
                    int cap)
{
    if (load->n + nextra > cap) {
        fprintf(stderr, "%s: more than %d load options\n", cmd, cap);
        return -1;
    }
    memcpy(out, load->opt, sizeof *out * (size_t)load->n);
    memcpy(out + load->n, extra, sizeof *out * (size_t)nextra);
    return load->n + nextra;
}
