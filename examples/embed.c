/* Embedding lanecast: create a device, print its target and the library
 * version, destroy it. Built against the installed library with
 *   cc embed.c $(pkg-config --cflags --libs lanecast) */
#include <stdio.h>
#include <lanecast/lanecast.h>

int main(void)
{
    lc_device *dev = NULL;
    lc_status s = lc_device_create(NULL, &dev);
    if (s != LC_OK) {
        fprintf(stderr, "embed: %s: %s\n", lc_status_string(s), lc_last_error());
        return 1;
    }
    lc_target t = LC_TARGET_AUTO;
    lc_device_target(dev, &t);
    printf("lanecast %s, target %s (%d lanes)\n", lc_version_string(), lc_target_name(t), lc_target_lanes(t));
    lc_device_destroy(dev);
    return 0;
}
