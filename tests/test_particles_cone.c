/* The coherent particle kernel's per-vector cone pre-test (issue 8;
 * kernels/particles_walk.h vcone_bits): a list deposit tests each particle
 * against the cones of its entry's vectors, LC_W vectors at once, before the
 * per-vector support test, and skips the vectors whose cones its support
 * cannot reach (compiled in on avx2 and avx512; elsewhere both renders take
 * the same path). The pre-test must be conservative: on every compiled and
 * supported target, for dvr (1 and 2 fields, diffuse and phong shading,
 * opaque spheres, sigma and kappa changed after the build, early
 * termination), mip and iso, with the eye outside the particles and inside
 * them (centres behind the eye), on a 70x50 image (groups cut by the image's
 * edges and by 32x32 tiles), default (16x16), 8x8 and 4x4 groups give the
 * same image, bit for bit, and the same term count (kernel_evals) with the
 * pre-test as without it (LANECAST_PARTICLE_CONE=0). A cone 3% too narrow
 * fails this test (the check is not vacuous). */
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

int main(void)
{
    pcases_scene(0x2545f4914f6cdd1dull);
    static float on[W * H * 4], off[W * H * 4];
    /* outside the particles (pcases' camera), and inside a cluster looking across the others */
    const lc_camera cams[2] = {cam, {LC_PERSPECTIVE, {4.2f, 3.8f, 4.5f}, {6.5f, 5.5f, 5}, {0, 1, 0}, 70.0f, 0.0f}};
    static const struct {
        int packet;
        const char *side;
    } groups[] = {{0, NULL}, {8, NULL}, {0, "4"}};
    int tested = 0;
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        const char *tn = lc_target_name((lc_target)t);
        lc_device *dev = pcases_device(t);
        if (!dev) continue;
        for (int ci = 0; ci < NCASES; ci++) {
            const ccase *c = &cases[ci];
            lc_volume *p = pcases_volume(dev, c);
            if (!p) continue;
            for (int vi = 0; vi < 2; vi++) {
                for (size_t k = 0; k < sizeof groups / sizeof groups[0]; k++) {
                    lc_render_stats so, sf;
                    int ok = pcases_render(dev, p, c, &cams[vi], W, H, groups[k].packet, groups[k].side, 1, on, &so) == 0 &&
                             pcases_render(dev, p, c, &cams[vi], W, H, groups[k].packet, groups[k].side, 0, off, &sf) == 0;
                    if (k == 0 && ok) {
                        double a = 0.0;
                        for (int i = 0; i < W * H; i++) a += on[4 * i + 3];
                        CHECK(a / (W * H) > 0.02, "%s %s view %d: the scene is visible (mean A %.3f)", tn, c->name,
                              vi, a / (W * H));
                    }
                    CHECK(ok && same_bits(on, off), "%s %s view %d packet %d side %s: cone pre-test on = off, bit for bit",
                          tn, c->name, vi, groups[k].packet, groups[k].side ? groups[k].side : "-");
                    CHECK(ok && so.kernel_evals == sf.kernel_evals,
                          "%s %s view %d packet %d side %s: the same terms (%llu, %llu)", tn, c->name, vi,
                          groups[k].packet, groups[k].side ? groups[k].side : "-",
                          (unsigned long long)so.kernel_evals, (unsigned long long)sf.kernel_evals);
                }
            }
            lc_volume_destroy(p);
        }
        lc_device_destroy(dev);
        tested++;
    }
    CHECK(tested > 0, "%d targets tested", tested);
    return check_summary("test_particles_cone");
}
