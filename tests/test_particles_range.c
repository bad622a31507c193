/* The coherent particle kernel's range test from the eye (issue 8;
 * kernels/particles_walk.h eye_range_misses, called by deposit_entry): with perspective rays from
 * the eye, a list deposit skips a particle whose support, |t - |oc|| < R
 * along any ray, misses the entry's samples ka..kb of the pass. The test
 * must be conservative. It runs only where the kernel takes the eye once per
 * group; LANECAST_PARTICLE_EYE=0 (the per-lane arithmetic, no range test)
 * is the reference. On every compiled and supported target, for dvr (1 and
 * 2 fields, diffuse and phong shading, opaque spheres, sigma and kappa
 * changed after the build, early termination), mip and iso, with the eye
 * outside the particles, inside a cluster (centres behind the eye) and far
 * away (|oc| ~ 400 against radii ~ 0.4: the round-off margin), default,
 * 8x8 and 4x4 groups and 8-sample passes (many passes, so most particles
 * lie outside most of them): the same image, bit for bit, and the same
 * term count (kernel_evals) with the range test as without it. A support
 * radius 3% too small in the range test fails this test (it is not
 * vacuous). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "lanecast/lanecast.h"
#include "check.h"
#include "pcases.h"

#define W 70
#define H 50

static int same_bits(const float *a, const float *b) { return memcmp(a, b, sizeof(float) * 4 * W * H) == 0; }

/* Case c (with `buffer` samples per pass, 0: the default) with the range
 * test (eye 1) or with the per-lane arithmetic (eye 0). */
static int render(lc_device *dev, lc_volume *p, const ccase *c, const lc_camera *cm, int packet, const char *side,
                  int buffer, int eye, float *img, lc_render_stats *st)
{
    lc_particle_params pp = {.sigma = c->sigma, .kappa = c->kappa, .sphere_scale = c->scale,
                             .buffer_samples = buffer};
    if (lc_particles_set_params(p, &pp) != LC_OK) return -1;
    if (!eye) setenv("LANECAST_PARTICLE_EYE", "0", 1);
    int r = pcases_render(dev, p, c, cm, W, H, packet, side, 1, img, st);
    unsetenv("LANECAST_PARTICLE_EYE");
    return r;
}

int main(void)
{
    pcases_scene(0x9e3779b97f4a7c15ull);
    static float on[W * H * 4], off[W * H * 4];
    const lc_camera cams[3] = {cam,
                               {LC_PERSPECTIVE, {4.2f, 3.8f, 4.5f}, {6.5f, 5.5f, 5}, {0, 1, 0}, 70.0f, 0.0f},
                               {LC_PERSPECTIVE, {5, 5, 400}, {5, 5, 5}, {0, 1, 0}, 1.6f, 0.0f}};
    static const struct {
        int packet, buffer;
        const char *side;
    } groups[] = {{0, 0, NULL}, {8, 0, NULL}, {0, 0, "4"}, {0, 8, NULL}, {8, 8, NULL}};
    int tested = 0;
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        const char *tn = lc_target_name((lc_target)t);
        lc_device *dev = pcases_device(t);
        if (!dev) continue;
        for (int ci = 0; ci < NCASES; ci++) {
            const ccase *c = &cases[ci];
            lc_volume *p = pcases_volume(dev, c);
            if (!p) continue;
            for (int vi = 0; vi < 3; vi++) {
                for (size_t k = 0; k < sizeof groups / sizeof groups[0]; k++) {
                    lc_render_stats so, sf;
                    const char *sd = groups[k].side ? groups[k].side : "-";
                    int ok = render(dev, p, c, &cams[vi], groups[k].packet, groups[k].side, groups[k].buffer, 1, on,
                                    &so) == 0 &&
                             render(dev, p, c, &cams[vi], groups[k].packet, groups[k].side, groups[k].buffer, 0, off,
                                    &sf) == 0;
                    if (k == 0 && ok) {
                        double a = 0.0;
                        for (int i = 0; i < W * H; i++) a += on[4 * i + 3];
                        CHECK(a / (W * H) > 0.02, "%s %s view %d: the scene is visible (mean A %.3f)", tn, c->name,
                              vi, a / (W * H));
                    }
                    CHECK(ok && same_bits(on, off),
                          "%s %s view %d packet %d side %s buffer %d: range test on = off, bit for bit", tn, c->name,
                          vi, groups[k].packet, sd, groups[k].buffer);
                    CHECK(ok && so.kernel_evals == sf.kernel_evals,
                          "%s %s view %d packet %d side %s buffer %d: the same terms (%llu, %llu)", tn, c->name, vi,
                          groups[k].packet, sd, groups[k].buffer, (unsigned long long)so.kernel_evals,
                          (unsigned long long)sf.kernel_evals);
                }
            }
            lc_volume_destroy(p);
        }
        lc_device_destroy(dev);
        tested++;
    }
    CHECK(tested > 0, "%d targets tested", tested);
    return check_summary("test_particles_range");
}
