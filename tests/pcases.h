/* The clustered particle scene and render cases two bit-identity tests share
 * (tests/test_particles_cstep.c, test_particles_gsize.c, test_particles_cone.c): 3 clusters of NCL
 * particles and NBG background ones (pclusters.h), radii that differ from one
 * particle to the next, and dvr (1 and 2 fields, diffuse and phong shading,
 * opaque spheres, sigma and kappa changed, early termination), mip and iso
 * cases under one TF and camera. */
#ifndef LANECAST_TESTS_PCASES_H
#define LANECAST_TESTS_PCASES_H
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include "lanecast/lanecast.h"
#include "check.h"
#include "pclusters.h"

#define NCL 140
#define NBG 100
#define N (3 * NCL + NBG)

static float xyz[3 * N], rad[N], val[N];
static uint8_t fid[N];

/* The scene from seed: its three clusters, spread and radii, the same in every test that shares it. */
static void pcases_scene(uint64_t seed)
{
    pclusters_make(seed, NCL, NBG, (const float[3][3]){{3, 3, 4}, {6.5f, 5.5f, 5}, {4, 6.5f, 6.5f}}, 0.8f, 0.3f, 0.2f,
                   xyz, rad, val, fid);
}

typedef struct ccase {
    const char *name;
    lc_mode mode;
    int nfields;
    lc_shading shading;
    float sigma, kappa, scale, alpha_stop, iso;
} ccase;

static const ccase cases[] = {
    {"dvr", LC_MODE_DVR, 1, LC_SHADE_NONE, 2.0f, 1.0f, 0.0f, 1.0f, 0.0f},
    {"dvr_f2_diffuse", LC_MODE_DVR, 2, LC_SHADE_DIFFUSE, 2.0f, 1.0f, 0.0f, 1.0f, 0.0f},
    {"dvr_spheres", LC_MODE_DVR, 1, LC_SHADE_NONE, 2.0f, 1.0f, 0.35f, 1.0f, 0.0f},
    {"dvr_sigma_kappa_phong", LC_MODE_DVR, 2, LC_SHADE_PHONG, 2.6f, 1.7f, 0.0f, 1.0f, 0.0f},
    {"dvr_alpha_stop", LC_MODE_DVR, 1, LC_SHADE_NONE, 2.0f, 3.0f, 0.0f, 0.9f, 0.0f},
    {"mip_f2", LC_MODE_MIP, 2, LC_SHADE_NONE, 2.0f, 1.0f, 0.0f, 1.0f, 0.0f},
    {"iso", LC_MODE_ISO, 1, LC_SHADE_DIFFUSE, 2.0f, 1.0f, 0.0f, 1.0f, 0.6f},
};
#define NCASES ((int)(sizeof cases / sizeof cases[0]))

static const float colr[] = {0.0f, 0.9f, 0.3f, 0.1f, 0.5f, 0.2f, 0.8f, 0.3f, 1.0f, 1.0f, 1.0f, 0.6f};
static const float opa[] = {0.0f, 0.0f, 0.15f, 0.0f, 1.0f, 3.0f};
static const lc_camera cam = {LC_PERSPECTIVE, {5, 5, 20}, {5, 5, 5}, {0, 1, 0}, 42.0f, 0.0f};

/* The device of target t (2 threads), or NULL: not compiled in or not
 * supported here (said on stdout), or a CHECK failure. */
static lc_device *pcases_device(int t)
{
    const char *tn = lc_target_name((lc_target)t);
    if (!lc_target_compiled((lc_target)t) || !lc_target_supported((lc_target)t)) {
        printf("skip target %s: not compiled in or not supported here\n", tn);
        return NULL;
    }
    lc_device *dev = NULL;
    if (lc_device_create(&(lc_device_desc){.target = (lc_target)t, .threads = 2}, &dev) != LC_OK) {
        CHECK(0, "lc_device_create(%s): %s", tn, lc_last_error());
        return NULL;
    }
    return dev;
}

/* Case c's particles (the scene above) with its parameters, or NULL (a CHECK failure). */
static lc_volume *pcases_volume(lc_device *dev, const ccase *c)
{
    lc_volume *p = NULL;
    lc_particles_desc pd = {.count = N, .positions = xyz, .radii = rad, .values = val,
                            .fields = c->nfields > 1 ? fid : NULL, .nfields = c->nfields};
    if (lc_particles_create(dev, &pd, &p) != LC_OK) {
        CHECK(0, "lc_particles_create: %s", lc_last_error());
        return NULL;
    }
    lc_particle_params pp = {.sigma = c->sigma, .kappa = c->kappa, .sphere_scale = c->scale};
    CHECK(lc_particles_set_params(p, &pp) == LC_OK, "set_params: %s", lc_last_error());
    return p;
}

/* Case c of p, coherent, w x h under camera cm into img (0, or -1 with the
 * error printed), with the A/B knobs: LANECAST_PARTICLE_GROUP = side (NULL:
 * unset) and, when cone is 0, LANECAST_PARTICLE_CONE=0. */
/* The render desc's tile side for pcases_render (0: the kind's choice). */
static int pcases_tile;

static __attribute__((unused)) int pcases_render(lc_device *dev, lc_volume *p, const ccase *c, const lc_camera *cm,
                                                int w, int h, int packet, const char *side, int cone, float *img,
                                                lc_render_stats *st)
{
    lc_tf_field f[2] = {{colr, 3, opa, 3, 1, {0.0f, 3.0f}}, {colr, 3, opa, 3, 1, {0.0f, 3.0f}}};
    lc_tf *tf = NULL;
    if (lc_tf_create(dev, f, c->nfields, &tf) != LC_OK) return -1;
    if (side) setenv("LANECAST_PARTICLE_GROUP", side, 1);
    if (!cone) setenv("LANECAST_PARTICLE_CONE", "0", 1);
    lc_render_desc d = {.width = w, .height = h, .camera = *cm, .tf = tf, .volume = p, .mode = c->mode,
                        .iso = c->iso, .dt = 0.06f, .alpha_stop = c->alpha_stop, .shading = c->shading,
                        .method = LC_METHOD_COHERENT, .packet = packet, .tile = pcases_tile};
    lc_status s = lc_render(dev, &d, img, st);
    unsetenv("LANECAST_PARTICLE_GROUP");
    unsetenv("LANECAST_PARTICLE_CONE");
    lc_tf_destroy(tf);
    if (s != LC_OK) printf("lc_render: %s\n", lc_last_error());
    return s == LC_OK ? 0 : -1;
}

#endif
