/* lanecast targets: every compiled target, CPU support, and the active one. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cli.h"

int cli_targets(int argc, char **argv)
{
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            puts("usage: lanecast targets\n\n"
                 "Lists the SIMD targets lanecast knows, whether kernels for each are compiled in,\n"
                 "whether this CPU (and OS) can run them, and which one a device would use now:\n"
                 "the widest supported one, or the one LANECAST_TARGET forces.\n\n"
                 "examples: lanecast targets\n"
                 "          LANECAST_TARGET=sse4 lanecast targets    (sse4 marked active, forced)\n\n"
                 "exit status: 0 ok, 1 no device could be created, 2 bad usage");
            return 0;
        }
        fprintf(stderr, "lanecast targets: unexpected argument '%s'\n", argv[i]);
        return CLI_EXIT_USAGE;
    }
    const char *env = getenv("LANECAST_TARGET");
    int forced = env && *env && strcmp(env, "auto") != 0;
    lc_device *dev = NULL;
    lc_status s = lc_device_create(&(lc_device_desc){.threads = 1}, &dev);
    if (s != LC_OK) {
        fprintf(stderr, "lanecast targets: %s\n", lc_last_error());
        return CLI_EXIT_FAIL;
    }
    lc_target active = LC_TARGET_AUTO;
    lc_device_target(dev, &active);
    printf("%-8s %-6s %-9s %-10s %s\n", "target", "lanes", "compiled", "supported", "active");
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        printf("%-8s %-6d %-9s %-10s %s\n", lc_target_name((lc_target)t), lc_target_lanes((lc_target)t),
               lc_target_compiled((lc_target)t) ? "yes" : "no", lc_target_supported((lc_target)t) ? "yes" : "no",
               t == (int)active ? (forced ? "* (forced by LANECAST_TARGET)" : "* (auto)") : "");
    }
    lc_device_destroy(dev);
    return 0;
}
