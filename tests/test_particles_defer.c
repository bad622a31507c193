/* Particle sets created with defer_bvh (the projection's load, issue 27):
 * the same set created both ways must give
 * (a) before any render: no BVH (info: 0 nodes, 0 build seconds), and a
 *     projection map bit for bit the immediate set's. The values mix
 *     pairs of +1e12 and -1e12 at one place with particles of 1, so a
 *     pixel's double sum rounds differently in another order (a float map
 *     of about 1 with errors of ~1e-4): the maps are equal only if both sum
 *     in the desc's order;
 * (b) a render (dvr) and point samples bit for bit the immediate set's, the
 *     BVH then reported with the immediate set's node count and depth;
 * (c) the projection after the render bit for bit the one before it;
 * (d) a kernel chosen by lc_particles_set_params before the deferred build
 *     reaches the render (iso, direct method, and dvr; values 1 here);
 * (e) an invalid particle dropped (drop_invalid) in both, src order kept;
 * (a)-(e) with Embree's build (canonical_order -1); (f) with the canonical
 *     tree (main's, its ties from the kept arrays): the same BVH and render
 *     as an immediate canonical set's. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "lanecast/lanecast.h"

#define NP 3000
#define S 96

static float xyz[3 * NP], rad[NP], val[NP];

static lc_volume *make_c(lc_device *dev, int defer, lc_kernel k, const float *values, int canonical)
{
    lc_particles_desc d = {.count = NP, .positions = xyz, .radii = rad, .values = values, .drop_invalid = 1,
                           .params = {.kernel = k}, .defer_bvh = defer, .canonical_order = canonical};
    lc_volume *v = NULL;
    if (lc_particles_create(dev, &d, &v) != LC_OK) printf("create: %s\n", lc_last_error());
    return v;
}

static lc_volume *make_v(lc_device *dev, int defer, lc_kernel k, const float *values)
{
    return make_c(dev, defer, k, values, -1);
}

static lc_volume *make(lc_device *dev, int defer, lc_kernel k) { return make_v(dev, defer, k, val); }

static int project(lc_device *dev, const lc_volume *v, float *map)
{
    lc_project_desc d = {.width = S, .height = S,
                         .camera = {LC_ORTHOGRAPHIC, {0.1f, -0.2f, 5.0f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 0.0f, 2.6f}};
    lc_status s = lc_particles_project(dev, v, &d, map, NULL);
    if (s != LC_OK) printf("project: %s\n", lc_last_error());
    return s == LC_OK;
}

static int render_m(lc_device *dev, const lc_volume *v, const lc_tf *tf, float *rgba, lc_mode mode, lc_method method)
{
    lc_render_desc d = {0};
    d.width = S, d.height = S;
    d.camera = (lc_camera){LC_PERSPECTIVE, {0.6f, 0.8f, 4.5f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 40.0f, 0.0f};
    d.mode = mode;
    d.method = method;
    d.iso = 0.5f;
    d.tf = tf;
    d.volume = v;
    lc_status s = lc_render(dev, &d, rgba, NULL);
    if (s != LC_OK) printf("render: %s\n", lc_last_error());
    return s == LC_OK;
}

static int render(lc_device *dev, const lc_volume *v, const lc_tf *tf, float *rgba)
{
    return render_m(dev, v, tf, rgba, LC_MODE_DVR, LC_METHOD_DEFAULT);
}

int main(void)
{
    srand(7);
    for (int i = 0; i < NP; i++) { /* +1e12 and -1e12 at the same place, then a 1 */
        for (int a = 0; a < 3; a++) xyz[3 * i + a] = i % 3 == 1 ? xyz[3 * i - 3 + a] : (float)rand() / RAND_MAX * 2.0f - 1.0f;
        rad[i] = i % 3 == 1 ? rad[i - 1] : 0.02f + 0.4f * (float)rand() / RAND_MAX;
        val[i] = i % 3 == 0 ? 1e12f : i % 3 == 1 ? -1e12f : 1.0f;
    }
    rad[17] = -1.0f; /* dropped */
    lc_device *dev = NULL;
    lc_device_desc dd = {.threads = 2};
    if (lc_device_create(&dd, &dev) != LC_OK) return printf("device: %s\n", lc_last_error()), 1;
    lc_tf *tf = NULL;
    if (lc_tf_preset(dev, lc_tf_preset_name(0), 1, 1.0f, &tf) != LC_OK) return printf("tf: %s\n", lc_last_error()), 1;
    static float m0[S * S], m1[S * S], m2[S * S], i0[4 * S * S], i1[4 * S * S];
    lc_volume *a = make(dev, 0, LC_KERNEL_M4), *b = make(dev, 1, LC_KERNEL_M4);
    if (!a || !b) return 1;
    lc_particles_info ia, ib;
    lc_particles_get_info(a, &ia), lc_particles_get_info(b, &ib);
    CHECK(ia.bvh_nodes > 1 && ib.bvh_nodes == 0 && ib.build_seconds == 0.0 && ib.count == NP - 1 && ib.dropped == 1,
          "(a) deferred: no BVH before a render (%d nodes; the immediate set %d), %zu kept, %zu dropped", ib.bvh_nodes,
          ia.bvh_nodes, ib.count, ib.dropped);
    int ok = project(dev, a, m0) && project(dev, b, m1);
    int differ = 0;
    for (int i = 0; i < S * S; i++) differ += m0[i] != m1[i];
    CHECK(ok && differ == 0, "(a) projection of the deferred set = the immediate set's, bit for bit (%d pixels differ)",
          differ);
    ok = render(dev, a, tf, i0) && render(dev, b, tf, i1);
    lc_particles_get_info(b, &ib);
    CHECK(ok && !memcmp(i0, i1, sizeof i0) && ib.bvh_nodes == ia.bvh_nodes && ib.bvh_depth == ia.bvh_depth &&
              ib.build_seconds > 0.0,
          "(b) dvr render of the deferred set = the immediate set's, bit for bit; BVH %d nodes depth %d built on demand",
          ib.bvh_nodes, ib.bvh_depth);
    float pts[3 * 64], va[64], vb[64], ga[3 * 64], gb[3 * 64];
    for (int i = 0; i < 3 * 64; i++) pts[i] = (float)(i % 7) * 0.13f - 0.4f;
    lc_volume *c = make(dev, 1, LC_KERNEL_M4); /* sampled first: the sample builds */
    lc_status sa = lc_volume_sample(dev, a, 64, pts, va, ga), sc = c ? lc_volume_sample(dev, c, 64, pts, vb, gb) : -1;
    CHECK(sa == LC_OK && sc == LC_OK && !memcmp(va, vb, sizeof va) && !memcmp(ga, gb, sizeof ga),
          "(b) point values and gradients of a deferred set (built by the sample) = the immediate set's");
    ok = project(dev, b, m2);
    CHECK(ok && !memcmp(m1, m2, sizeof m1), "(c) projection after the render (leaf order) = the one before, bit for bit");
    lc_volume *e = make_v(dev, 0, LC_KERNEL_WENDLAND_C2, NULL), *f = make_v(dev, 1, LC_KERNEL_M4, NULL);
    lc_particle_params pp = {.kernel = LC_KERNEL_WENDLAND_C2};
    lc_status sp = f ? lc_particles_set_params(f, &pp) : -1;
    ok = e && f && sp == LC_OK && render_m(dev, e, tf, i0, LC_MODE_ISO, LC_METHOD_DIRECT) &&
         render_m(dev, f, tf, i1, LC_MODE_ISO, LC_METHOD_DIRECT);
    int same = ok && !memcmp(i0, i1, sizeof i0);
    ok = ok && render(dev, e, tf, i0) && render(dev, f, tf, i1);
    CHECK(ok && same && !memcmp(i0, i1, sizeof i0),
          "(d) kernel set before the deferred build: iso (direct) and dvr = an immediate C2 set's");
    lc_volume *g = make_c(dev, 0, LC_KERNEL_M4, val, 1), *h = make_c(dev, 1, LC_KERNEL_M4, val, 1);
    ok = g && h && render(dev, g, tf, i0) && render(dev, h, tf, i1);
    lc_particles_get_info(g, &ia), lc_particles_get_info(h, &ib);
    CHECK(ok && !memcmp(i0, i1, sizeof i0) && ia.bvh_nodes == ib.bvh_nodes,
          "(f) canonical_order: the deferred set's BVH and render = the immediate set's, bit for bit");
    lc_volume_destroy(g), lc_volume_destroy(h);
    lc_volume_destroy(a), lc_volume_destroy(b), lc_volume_destroy(c), lc_volume_destroy(e), lc_volume_destroy(f);
    lc_tf_destroy(tf);
    lc_device_destroy(dev);
    return check_summary("particles_defer");
}
