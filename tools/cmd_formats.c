/* lanecast formats: every file format of the registry (lc_format_get) and
 * the optional features of this build (lc_feature_get). */
#include <stdio.h>
#include <string.h>
#include "cli.h"

static const char formats_help[] =
    "usage: lanecast formats\n"
    "\n"
    "Lists every file format lanecast reads: its name (for the library's lc_load_desc.format),\n"
    "the kind of data it makes, its extensions (\".gz\" is looked through: file.pdb.gz is PDB),\n"
    "the option keys it takes (lc_option; the kind adds its own, e.g. leaf_size for particles\n"
    "and brick for grids), and what it reads. A format compiled out of this build says which\n"
    "Debian package enables it. Then the optional features and whether this build has them.\n"
    "A file's format is decided by its magic bytes first, then its extension.\n"
    "\n"
    "example:\n"
    "  lanecast formats\n"
    "  lanecast formats | grep particles      # the particle formats\n";

int cli_formats(int argc, char **argv)
{
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            fputs(formats_help, stdout);
            return 0;
        }
        fprintf(stderr, "lanecast formats: unexpected argument '%s'\n", argv[i]);
        return CLI_EXIT_USAGE;
    }
    printf("%-14s %-10s %-14s %s\n", "format", "kind", "extensions", "description");
    for (int i = 0; i < lc_format_count(); i++) {
        lc_format_info f;
        if (lc_format_get(i, &f) != LC_OK) {
            fprintf(stderr, "lanecast formats: %s\n", lc_last_error());
            return CLI_EXIT_FAIL;
        }
        printf("%-14s %-10s %-14s %s\n", f.name, lc_kind_name(f.kind), f.extensions, f.description);
        printf("%-14s %-10s %-14s options: %s\n", "", "", "", f.options[0] ? f.options : "(none)");
        if (!f.available) printf("%-14s %-10s %-14s not in this build: install %s\n", "", "", "", f.package);
    }
    printf("\noptional features:\n");
    for (int i = 0; i < lc_feature_count(); i++) {
        lc_feature_info f;
        if (lc_feature_get(i, &f) != LC_OK) {
            fprintf(stderr, "lanecast formats: %s\n", lc_last_error());
            return CLI_EXIT_FAIL;
        }
        printf("  %-6s %-4s %s (%s)\n", f.name, f.available ? "yes" : "no", f.description, f.library);
        if (!f.available) printf("  %-6s %-4s not in this build: install %s and rebuild\n", "", "", f.package);
    }
    /* the program's own: lanecast view (viewer/) */
    printf("  %-6s %-4s lanecast view, an interactive window (GLFW, Dear ImGui, OpenGL 2.1)\n", "viewer",
           cli_view_available() ? "yes" : "no");
    if (!cli_view_available())
        printf("  %-6s %-4s not in this build: install libglfw3-dev libimgui-dev libstb-dev and rebuild\n", "", "");
    return 0;
}
