/* The scene the mode tests share (tests/test_modes.c: MIP; test_modes_iso.c:
 * iso and slice): 160 particles in two fields, a 17 x 13 x 11 grid of two
 * blobs and a ramp, 24 RBFs of both signs over a bias; float copies for the
 * library and double copies for the reference core. */
#ifndef LC_TEST_MODES_SCENE_H
#define LC_TEST_MODES_SCENE_H

#include <math.h>
#include <stdint.h>
#include "lanecast/lanecast.h"

enum { W = 48, H = 40, NP = 160, GX = 17, GY = 13, GZ = 11, NR = 24 };

/* Colour ramps that make the colour tell which value (and field) won. */
static const float col0[] = {0.0f, 0.0f, 0.0f, 0.2f, 0.5f, 1.0f, 0.3f, 0.0f, 1.0f, 1.0f, 1.0f, 0.6f};
static const float col1[] = {0.0f, 0.1f, 0.0f, 0.0f, 1.0f, 0.2f, 1.0f, 0.9f};
static const float opa[] = {0.0f, 0.0f, 1.0f, 1.0f};
static double dcol0[12], dcol1[8], dopa[4];

static void to_double(const float *f, double *d, int n)
{
    for (int i = 0; i < n; i++) d[i] = f[i];
}

static uint32_t seed = 7u;
static double rnd(void)
{
    seed = seed * 1664525u + 1013904223u;
    return (double)(seed >> 8) / 16777216.0;
}

typedef struct scene {
    float pos[3 * NP], rad[NP];
    uint8_t field[NP];
    double dpos[3 * NP], drad[NP];
    int dfield[NP];
    float grid[GX * GY * GZ];
    double dgrid[GX * GY * GZ];
    float rc[3 * NR], rs[NR], rw[NR];
    double drc[3 * NR], drs[NR], drw[NR];
} scene;

#define RBF_BIAS 0.1f
#define RBF_EPS 1e-3f

static void make_scene(scene *s)
{
    for (int i = 0; i < NP; i++) {
        for (int a = 0; a < 3; a++) s->dpos[3 * i + a] = s->pos[3 * i + a] = (float)(4.0 * rnd() - 2.0);
        s->drad[i] = s->rad[i] = (float)(0.25 + 0.35 * rnd());
        s->dfield[i] = s->field[i] = (uint8_t)(i % 2);
    }
    /* RBFs of both signs over a bias */
    for (int i = 0; i < NR; i++) {
        for (int a = 0; a < 3; a++) s->drc[3 * i + a] = s->rc[3 * i + a] = (float)(3.0 * rnd() - 1.5);
        s->drs[i] = s->rs[i] = (float)(0.2 + 0.4 * rnd());
        s->drw[i] = s->rw[i] = (float)(i % 3 == 0 ? -0.4 * rnd() : 0.3 + 0.6 * rnd());
    }
    /* two blobs and a ramp, so maxima vary across the image */
    for (int k = 0; k < GZ; k++)
        for (int j = 0; j < GY; j++)
            for (int i = 0; i < GX; i++) {
                double x = i / (GX - 1.0), y = j / (GY - 1.0), z = k / (GZ - 1.0);
                double v = exp(-((x - 0.3) * (x - 0.3) + (y - 0.4) * (y - 0.4) + (z - 0.5) * (z - 0.5)) * 30.0) +
                           0.7 * exp(-((x - 0.7) * (x - 0.7) + (y - 0.6) * (y - 0.6) + (z - 0.3) * (z - 0.3)) * 20.0) +
                           0.2 * x;
                size_t o = ((size_t)k * GY + (size_t)j) * GX + (size_t)i;
                s->grid[o] = (float)v;
                s->dgrid[o] = (double)s->grid[o];
            }
}

static const lc_box3 rbf_domain = {{-1.8f, -1.8f, -1.8f}, {1.8f, 1.8f, 1.8f}};

#endif
