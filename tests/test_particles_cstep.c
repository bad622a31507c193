/* The coherent particle kernel's recurrence ratios from the volume's cache
 * (issue 8, host/kinds/particles_cstep.c): c_i = exp(2 nir_i dt^2)
 * per particle, computed once per volume and step instead of in the kernel.
 * On every compiled and supported target, with radii that differ from one
 * particle to the next, for dvr (1 and 2 fields, diffuse and phong shading,
 * opaque spheres, sigma and kappa changed after the build, early
 * termination), mip and iso, with 8x8 groups and lane-width packets:
 * - the image with the cache (the default) is bit-identical to the kernel's
 *   own ratios (LANECAST_PARTICLE_CSTEP=0);
 * - a sequence of frames changing dt (the cache rebuilt) and back gives
 *   each step's image, bit for bit, and the steps really differ;
 * - two threads rendering one volume at once with alternating steps get the
 *   single-threaded images (the cache is shared and replaced under them).
 * Scratch images are kept only on failure (none are written here). */
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "lanecast/lanecast.h"
#include "check.h"
#include "pcases.h"

#define W 36
#define H 36

static const float steps[3] = {0.06f, 0.045f, 0.071f};

static int render(lc_device *dev, lc_volume *p, const ccase *c, int packet, float dt, float *img)
{
    lc_tf_field f[2] = {{colr, 3, opa, 3, 1, {0.0f, 3.0f}}, {colr, 3, opa, 3, 1, {0.0f, 3.0f}}};
    lc_tf *tf = NULL;
    if (lc_tf_create(dev, f, c->nfields, &tf) != LC_OK) return -1;
    lc_render_desc d = {.width = W, .height = H, .camera = cam, .tf = tf, .volume = p, .mode = c->mode,
                        .iso = c->iso, .dt = dt, .alpha_stop = c->alpha_stop, .shading = c->shading,
                        .method = LC_METHOD_COHERENT, .packet = packet};
    lc_status s = lc_render(dev, &d, img, NULL);
    lc_tf_destroy(tf);
    if (s != LC_OK) printf("lc_render: %s\n", lc_last_error());
    return s == LC_OK ? 0 : -1;
}

static int same_bits(const float *a, const float *b) { return memcmp(a, b, sizeof(float) * 4 * W * H) == 0; }

static int visible(const float *img)
{
    double a = 0.0;
    for (int i = 0; i < W * H; i++) a += img[4 * i + 3];
    return a / (W * H) > 0.02;
}

/* Two threads on one volume, alternating steps (lc_render may run on one
 * volume from several threads; the device is per thread). */
typedef struct tjob {
    lc_target target;
    lc_volume *p;
    const ccase *c;
    int first; /* index into steps of the first frame */
    const float (*want)[W * H * 4];
    int bad;
} tjob;

static void *thread_main(void *arg)
{
    tjob *j = arg;
    static _Thread_local float img[W * H * 4];
    lc_device *dev = NULL;
    if (lc_device_create(&(lc_device_desc){.target = j->target, .threads = 1}, &dev) != LC_OK) {
        j->bad = 1;
        return NULL;
    }
    for (int it = 0; it < 12; it++) {
        int si = (j->first + it) % 3;
        if (render(dev, j->p, j->c, 8, steps[si], img) || !same_bits(img, j->want[si])) j->bad++;
    }
    lc_device_destroy(dev);
    return NULL;
}

int main(void)
{
    pcases_scene(0x9e3779b97f4a7c15ull);
    int distinct = 0;
    for (int i = 1; i < N; i++) distinct += rad[i] != rad[i - 1];
    CHECK(distinct > N / 2, "neighbouring radii differ (%d of %d)", distinct, N - 1);
    static float with[W * H * 4], without[W * H * 4], seq[3][W * H * 4];
    int tested = 0;
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        const char *tn = lc_target_name((lc_target)t);
        lc_device *dev = pcases_device(t);
        if (!dev) continue;
        for (int ci = 0; ci < NCASES; ci++) {
            const ccase *c = &cases[ci];
            lc_volume *p = pcases_volume(dev, c);
            if (!p) continue;
            for (int packet = 8; packet >= 1; packet -= 7) {
                /* each step with the cache and without; then the steps again, the cache rebuilt each time */
                for (int si = 0; si < 3; si++) {
                    int ok = render(dev, p, c, packet, steps[si], with) == 0;
                    setenv("LANECAST_PARTICLE_CSTEP", "0", 1);
                    ok = ok && render(dev, p, c, packet, steps[si], without) == 0;
                    unsetenv("LANECAST_PARTICLE_CSTEP");
                    CHECK(ok, "%s %s packet %d dt %g: renders", tn, c->name, packet, (double)steps[si]);
                    CHECK(same_bits(with, without), "%s %s packet %d dt %g: cached ratios = the kernel's, bit for bit",
                          tn, c->name, packet, (double)steps[si]);
                    CHECK(visible(with), "%s %s packet %d: the scene is visible", tn, c->name, packet);
                    memcpy(seq[si], with, sizeof with);
                }
                CHECK(!same_bits(seq[0], seq[1]) && !same_bits(seq[0], seq[2]),
                      "%s %s packet %d: the steps give different images", tn, c->name, packet);
                for (int it = 0; it < 4; it++) {
                    int si = (it * 2) % 3;
                    CHECK(render(dev, p, c, packet, steps[si], with) == 0 && same_bits(with, seq[si]),
                          "%s %s packet %d: frame %d (dt %g) after a step change = its first image", tn, c->name,
                          packet, it, (double)steps[si]);
                }
            }
            if (ci == 1 || ci == 5) { /* packet 8 images of seq are the thread's reference */
                for (int si = 0; si < 3; si++) render(dev, p, c, 8, steps[si], seq[si]);
                tjob jobs[2] = {{(lc_target)t, p, c, 0, (const float (*)[W * H * 4])seq, 0},
                                {(lc_target)t, p, c, 1, (const float (*)[W * H * 4])seq, 0}};
                pthread_t th[2];
                int started = 0;
                for (int k = 0; k < 2; k++) started += pthread_create(&th[k], NULL, thread_main, &jobs[k]) == 0;
                CHECK(started == 2, "%s: threads started", tn);
                for (int k = 0; k < started; k++) pthread_join(th[k], NULL);
                CHECK(jobs[0].bad == 0 && jobs[1].bad == 0,
                      "%s %s: two threads on one volume, alternating steps = single-threaded (%d, %d bad)", tn,
                      c->name, jobs[0].bad, jobs[1].bad);
            }
            lc_volume_destroy(p);
        }
        lc_device_destroy(dev);
        tested++;
    }
    CHECK(tested > 0, "%d targets tested", tested);
    return check_summary("test_particles_cstep");
}
