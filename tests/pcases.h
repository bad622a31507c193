/* The clustered particle scene and render cases two bit-identity tests share
 * (tests/test_particles_cstep.c, test_particles_gsize.c): 3 clusters of NCL
 * particles and NBG background ones (pclusters.h), radii that differ from one
 * particle to the next, and dvr (1 and 2 fields, diffuse and phong shading,
 * opaque spheres, sigma and kappa changed, early termination), mip and iso
 * cases under one TF and camera. */
#ifndef LANECAST_TESTS_PCASES_H
#define LANECAST_TESTS_PCASES_H
#include <stdint.h>
#include "lanecast/lanecast.h"
#include "pclusters.h"

#define NCL 140
#define NBG 100
#define N (3 * NCL + NBG)

static float xyz[3 * N], rad[N], val[N];
static uint8_t fid[N];

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

#endif
