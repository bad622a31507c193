/* lanecast view in a build without the `viewer` feature: one line naming
 * the Debian packages it needs. */
#include <stdio.h>

int cli_view(int argc, char **argv);
int cli_view_available(void);

int cli_view(int argc, char **argv)
{
    (void)argc, (void)argv;
    fprintf(stderr, "lanecast view: this build has no viewer: install libglfw3-dev libimgui-dev libstb-dev "
                    "(Debian) and rebuild\n");
    return 1;
}

int cli_view_available(void) { return 0; }
