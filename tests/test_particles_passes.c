/* The coherent particle kernel's pass length (issue 8,
 * kernels/particles_coherent.c pass_end, pass_adapt). How many samples a
 * pass buffers changes which work is done, never a term or the order of the
 * terms a sample sums, so on every compiled and supported target, for dvr
 * (1 and 2 fields, diffuse shading: the gradient components, opaque spheres,
 * early termination at alpha_stop 0.6 and 0.9), mip and iso, 8x8 groups,
 * lane-width packets and 64x64 groups (whose adaptive buffer is capped by
 * its size per worker):
 * - the image with the adaptive pass length (buffer_samples 0, the default)
 *   is bit-identical (memcmp) to fixed buffers of 8, 12 (not a multiple of
 *   the recurrence's anchor block: passes not aligned), 32 and 128 samples;
 * - the adaptive length really runs its own passes (its pass count differs
 *   from the fixed 32's somewhere, else the check above is vacuous);
 * - an image is not vacuous (mean alpha > 0.05).
 * 96x96 pixels in tiles of 32: 144 groups, so the per-group adaptation
 * changes the length several times. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "lanecast/lanecast.h"
#include "check.h"
#include "pclusters.h"

#define W 96
#define H 96
#define NCL 220 /* per cluster */
#define NBG 160
#define N (3 * NCL + NBG)
#define DT 0.05f

static float xyz[3 * N], rad[N], val[N];
static uint8_t fid[N];

/* three dense clusters in a sparse background (as tests/test_particles_group.c) */
static void make_data(void)
{
    static const float cc[3][3] = {{3, 3, 4}, {6.5f, 5.5f, 5}, {4, 6.5f, 6.5f}};
    pclusters_make(0x9e3779b97f4a7c15ull, NCL, NBG, cc, 0.8f, 0.3f, 0.15f, xyz, rad, val, fid);
}

typedef struct pcase {
    const char *name;
    lc_mode mode;
    int nfields;
    lc_shading shading;
    float kappa, scale; /* scale > 0: opaque spheres */
    float alpha_stop;
    float iso;
} pcase;

static const pcase cases[] = {
    {"dvr_stop06", LC_MODE_DVR, 1, LC_SHADE_NONE, 3.0f, 0.0f, 0.6f, 0.0f},
    {"dvr_f2_diffuse", LC_MODE_DVR, 2, LC_SHADE_DIFFUSE, 2.0f, 0.0f, 0.9f, 0.0f},
    {"dvr_spheres", LC_MODE_DVR, 1, LC_SHADE_NONE, 1.0f, 0.35f, 1.0f, 0.0f},
    {"dvr_through", LC_MODE_DVR, 1, LC_SHADE_NONE, 1.0f, 0.0f, 1.0f, 0.0f},
    {"mip_f2", LC_MODE_MIP, 2, LC_SHADE_NONE, 1.0f, 0.0f, 1.0f, 0.0f},
    {"iso", LC_MODE_ISO, 1, LC_SHADE_DIFFUSE, 1.0f, 0.0f, 1.0f, 0.6f},
};
#define NCASES ((int)(sizeof cases / sizeof cases[0]))

static const float colr[] = {0.0f, 0.9f, 0.3f, 0.1f, 0.5f, 0.2f, 0.8f, 0.3f, 1.0f, 1.0f, 1.0f, 0.6f};
static const float opa[] = {0.0f, 0.0f, 0.15f, 0.0f, 1.0f, 3.0f};

static const lc_camera cam = {LC_PERSPECTIVE, {5, 5, 20}, {5, 5, 5}, {0, 1, 0}, 42.0f, 0.0f};

/* buffer: samples per pass, 0 = adaptive (the default) */
static int render(lc_device *dev, lc_volume *p, const pcase *c, int packet, int buffer, float *img,
                  lc_render_stats *st)
{
    lc_tf_field f[2] = {{colr, 3, opa, 3, 1, {0.0f, 3.0f}}, {colr, 3, opa, 3, 1, {0.0f, 3.0f}}};
    lc_tf *tf = NULL;
    if (lc_tf_create(dev, f, c->nfields, &tf) != LC_OK) return -1;
    lc_particle_params pp = {.sigma = 2.0f, .kappa = c->kappa, .buffer_samples = buffer, .sphere_scale = c->scale};
    if (lc_particles_set_params(p, &pp) != LC_OK) return lc_tf_destroy(tf), -1;
    lc_render_desc d = {.width = W, .height = H, .camera = cam, .tf = tf, .volume = p, .mode = c->mode,
                        .iso = c->iso, .dt = DT, .alpha_stop = c->alpha_stop, .shading = c->shading,
                        .method = LC_METHOD_COHERENT, .packet = packet, .tile = 32};
    lc_status s = lc_render(dev, &d, img, st);
    lc_tf_destroy(tf);
    if (s != LC_OK) printf("lc_render: %s\n", lc_last_error());
    return s == LC_OK ? 0 : -1;
}

static int same_bits(const float *a, const float *b) { return memcmp(a, b, sizeof(float) * 4 * W * H) == 0; }

int main(void)
{
    make_data();
    unsetenv("LANECAST_PARTICLE_BUFFER_K"); /* the default must adapt */
    static float adapt[W * H * 4], fixed[W * H * 4];
    static const int buffers[] = {8, 12, 32, 128};
    int tested = 0, own_passes = 0;
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        const char *tn = lc_target_name((lc_target)t);
        if (!lc_target_compiled((lc_target)t) || !lc_target_supported((lc_target)t)) {
            printf("skip target %s: not compiled in or not supported here\n", tn);
            continue;
        }
        lc_device *dev = NULL;
        if (lc_device_create(&(lc_device_desc){.target = (lc_target)t, .threads = 2}, &dev) != LC_OK) {
            CHECK(0, "lc_device_create(%s): %s", tn, lc_last_error());
            continue;
        }
        lc_volume *pv[2] = {NULL, NULL};
        for (int nf = 1; nf <= 2; nf++) {
            lc_particles_desc pd = {.count = N, .positions = xyz, .radii = rad, .values = val,
                                    .fields = nf > 1 ? fid : NULL, .nfields = nf};
            CHECK(lc_particles_create(dev, &pd, &pv[nf - 1]) == LC_OK, "lc_particles_create: %s", lc_last_error());
        }
        for (int ci = 0; ci < NCASES && pv[0] && pv[1]; ci++) {
            const pcase *c = &cases[ci];
            lc_volume *p = pv[c->nfields - 1];
            static const int packets[] = {8, 1, 64}; /* 64: 4096-ray groups, the buffer capped (24 rows with
                                                        2 fields and gradients) */
            for (int pi = 0; pi < 3; pi++) {
                lc_render_stats sa, sf;
                if (render(dev, p, c, packets[pi], 0, adapt, &sa)) {
                    CHECK(0, "%s %s packet %d: adaptive render failed", tn, c->name, packets[pi]);
                    continue;
                }
                double ma = 0.0;
                for (int i = 0; i < W * H; i++) ma += adapt[4 * i + 3] / (W * H);
                CHECK(ma > 0.05, "%s %s packet %d: visible (mean A %.3f)", tn, c->name, packets[pi], ma);
                for (int bi = 0; bi < 4; bi++) {
                    if (render(dev, p, c, packets[pi], buffers[bi], fixed, &sf)) {
                        CHECK(0, "%s %s packet %d K %d: render failed", tn, c->name, packets[pi], buffers[bi]);
                        continue;
                    }
                    CHECK(same_bits(adapt, fixed),
                          "%s %s packet %d: adaptive passes (%llu) = passes of %d samples (%llu), bit for bit", tn,
                          c->name, packets[pi], (unsigned long long)sa.passes, buffers[bi],
                          (unsigned long long)sf.passes);
                    if (buffers[bi] == 32 && sf.passes != sa.passes) own_passes++;
                }
            }
        }
        lc_volume_destroy(pv[0]);
        lc_volume_destroy(pv[1]);
        lc_device_destroy(dev);
        tested++;
    }
    CHECK(tested > 0, "%d targets tested", tested);
    CHECK(own_passes > 0, "the adaptive length ran its own passes (%d renders differ from 32 in pass count)",
          own_passes);
    return check_summary("test_particles_passes");
}
