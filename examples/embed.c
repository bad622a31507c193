/* Embedding lanecast: a device, a volume of any kind (here particles, the
 * README's example), a render, and the numbers a caller checks. Built against
 * the installed library with
 *   cc embed.c $(pkg-config --cflags --libs lanecast) */
#include <stdio.h>
#include <stdlib.h>
#include <lanecast/lanecast.h>

#define N 64
#define W 48

static int fail(const char *what, lc_status s)
{
    fprintf(stderr, "embed: %s: %s: %s\n", what, lc_status_string(s), lc_last_error());
    return 1;
}

int main(void)
{
    lc_device *dev = NULL;
    lc_status s = lc_device_create(NULL, &dev); /* widest target, all cores */
    if (s != LC_OK) return fail("lc_device_create", s);
    lc_target t = LC_TARGET_AUTO;
    lc_device_target(dev, &t);
    printf("lanecast %s, target %s (%d lanes)\n", lc_version_string(), lc_target_name(t), lc_target_lanes(t));

    /* a ring of particles; any kind's create (or lc_volume_load) gives an lc_volume */
    float xyz[3 * N];
    for (int i = 0; i < N; i++) {
        float a = 6.2831853f * (float)i / N;
        xyz[3 * i] = 4.0f * (a < 3.1415927f ? a / 3.1415927f - 0.5f : 1.5f - a / 3.1415927f);
        xyz[3 * i + 1] = (float)(i % 8) - 3.5f;
        xyz[3 * i + 2] = 0.0f;
    }
    lc_volume *v = NULL;
    s = lc_particles_create(dev, &(lc_particles_desc){.count = N, .positions = xyz, .radius = 1.0f}, &v);
    if (s != LC_OK) return fail("lc_particles_create", s);
    float *rgba = malloc(sizeof(float) * 4 * W * W);
    s = rgba ? lc_render(dev, &(lc_render_desc){.width = W, .height = W, .volume = v}, rgba, NULL) : LC_ERROR_OUT_OF_MEMORY;
    if (s != LC_OK) return fail("lc_render", s);
    int covered = 0;
    for (int p = 0; p < W * W; p++) covered += rgba[4 * p + 3] > 0.01f;
    printf("rendered %dx%d, %s\n", W, W, covered > W * W / 10 ? "the volume is visible" : "NOTHING VISIBLE");
    free(rgba);
    lc_volume_destroy(v);
    lc_device_destroy(dev);
    return covered > W * W / 10 ? 0 : 1;
}
