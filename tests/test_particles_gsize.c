/* The coherent particle kernel's group size (issue 8):
 * with the render desc's packet left at 0 the particle kind picks 16x16
 * groups, 32x32 with a perspective camera on 16-lane targets (the eye outside
 * the particles' box or inside it; both checked here;
 * host/kinds/particles.c group_side), LANECAST_PARTICLE_GROUP=N another side.
 * A 32x32 group alone in a 32-pixel tile keeps its first pass length
 * (particles_coherent.c pass_first: 24 samples with the eye outside, 16
 * inside): with the eye outside the default's pass count is that of fixed
 * passes of 24, and with 32-pixel tiles inside that of fixed passes of 16.
 * With the eye inside the default tile is 64 pixels (host/kinds/particles.c
 * tile_side), where the length adapts from group to group: the default's
 * pass count is that of explicit 64-pixel tiles. Groups and tiles change
 * the work, not the image: on every compiled and
 * supported target, for dvr (1 and 2 fields, diffuse and phong shading,
 * opaque spheres, sigma and kappa changed after the build, early
 * termination), mip and iso, on a 70x50 image (groups cut by the image's
 * edges and by 32x32 tiles), the default is bit-identical to explicit 8x8
 * groups, lane-width packets and sides 4, 12, 16 and 32; the default walks
 * visit other node counts than 8x8 (the setting is not ignored). */
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
    static float def[W * H * 4], other[W * H * 4];
    /* outside the particles (pcases' camera), and inside a cluster looking across the
       others (32x32 groups there too, with a first pass of 16 samples) */
    const lc_camera cams[2] = {cam, {LC_PERSPECTIVE, {4.2f, 3.8f, 4.5f}, {6.5f, 5.5f, 5}, {0, 1, 0}, 70.0f, 0.0f}};
    static const char *where[2] = {"outside", "inside"};
    static const struct {
        int packet;
        const char *side;
    } alts[] = {{8, NULL}, {1, NULL}, {0, "4"}, {0, "12"}, {0, "16"}, {0, "32"}, {0, "8"}};
    int tested = 0;
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        const char *tn = lc_target_name((lc_target)t);
        lc_device *dev = pcases_device(t);
        if (!dev) continue;
        /* 32x32 where a group is at most 64 vectors (16 lanes), else 16x16 */
        const char *want = lc_target_lanes((lc_target)t) >= 16 ? "32" : "16";
        for (int ci = 0; ci < NCASES; ci++) {
            const ccase *c = &cases[ci];
            lc_volume *p = pcases_volume(dev, c);
            if (!p) continue;
            for (int e = 0; e < 2; e++) {
                lc_render_stats sd, so;
                if (pcases_render(dev, p, c, &cams[e], W, H, 0, NULL, 1, def, &sd)) {
                    CHECK(0, "%s %s %s: default render", tn, c->name, where[e]);
                    continue;
                }
                double a = 0.0;
                for (int i = 0; i < W * H; i++) a += def[4 * i + 3];
                CHECK(a / (W * H) > 0.02, "%s %s %s: the scene is visible (mean A %.3f)", tn, c->name, where[e],
                      a / (W * H));
                for (size_t k = 0; k < sizeof alts / sizeof alts[0]; k++) {
                    int ok = pcases_render(dev, p, c, &cams[e], W, H, alts[k].packet, alts[k].side, 1, other, &so) == 0;
                    CHECK(ok && same_bits(def, other), "%s %s %s: default groups = packet %d side %s, bit for bit", tn,
                          c->name, where[e], alts[k].packet, alts[k].side ? alts[k].side : "-");
                    if (alts[k].side && !strcmp(alts[k].side, want))
                        CHECK(so.nodes == sd.nodes, "%s %s: with the eye %s the default side is %s (nodes %llu, %llu)",
                              tn, c->name, where[e], want, (unsigned long long)sd.nodes, (unsigned long long)so.nodes);
                    if (k == 0)
                        CHECK(so.nodes != sd.nodes, "%s %s %s: the default and 8x8 groups walk differently (nodes %llu, %llu)",
                              tn, c->name, where[e], (unsigned long long)sd.nodes, (unsigned long long)so.nodes);
                }
                if (lc_target_lanes((lc_target)t) >= 16) {
                    /* 32-pixel tiles: one group a tile, fixed passes of the first length */
                    lc_render_stats s32;
                    pcases_tile = 32;
                    int ok = pcases_render(dev, p, c, &cams[e], W, H, 0, NULL, 1, other, &s32) == 0;
                    CHECK(ok && same_bits(def, other), "%s %s %s: 32-pixel tiles, bit for bit", tn, c->name, where[e]);
                    const char *len = e ? "16" : "24";
                    setenv("LANECAST_PARTICLE_BUFFER_K", len, 1);
                    ok = pcases_render(dev, p, c, &cams[e], W, H, 0, NULL, 1, other, &so) == 0;
                    unsetenv("LANECAST_PARTICLE_BUFFER_K");
                    CHECK(ok && same_bits(def, other) && so.passes == s32.passes,
                          "%s %s %s: 32-pixel tiles = fixed passes of %s samples (passes %llu, %llu)", tn, c->name,
                          where[e], len, (unsigned long long)s32.passes, (unsigned long long)so.passes);
                    /* the default tile: 32 outside, 64 inside */
                    pcases_tile = e ? 64 : 32;
                    ok = pcases_render(dev, p, c, &cams[e], W, H, 0, NULL, 1, other, &so) == 0;
                    CHECK(ok && same_bits(def, other) && so.passes == sd.passes,
                          "%s %s %s: the default tile is %d pixels (passes %llu, %llu)", tn, c->name, where[e],
                          pcases_tile, (unsigned long long)sd.passes, (unsigned long long)so.passes);
                    pcases_tile = 0;
                }
            }
            lc_volume_destroy(p);
        }
        lc_device_destroy(dev);
        tested++;
    }
    CHECK(tested > 0, "%d targets tested", tested);
    return check_summary("test_particles_gsize");
}
