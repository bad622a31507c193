/* One scene of each kind (particles, grid, RBF set) with a fixed seed, for
 * the concurrency and determinism tests: small enough to render often,
 * with structure in every tile (several fields, overlapping particles,
 * signed RBF weights) so that an ordering difference would show. */
#ifndef LC_TEST_SCENES3_H
#define LC_TEST_SCENES3_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "lanecast/lanecast.h"

#define S3_NP 400
#define S3_G 24
#define S3_NR 40

typedef struct scenes3 {
    lc_volume *vol[3];        /* particles, grid, rbf */
    const char *name[3];
    lc_tf *tf;                /* 2 fields, shared by all renders */
    float pos[3 * S3_NP], rad[S3_NP], val[S3_NP];
    uint8_t field[S3_NP];
    float grid[S3_G * S3_G * S3_G];
    float rc[3 * S3_NR], rs[S3_NR], rw[S3_NR];
} scenes3;

static uint32_t s3_seed;
static float s3_rnd(float a, float b)
{
    s3_seed = s3_seed * 1664525u + 1013904223u;
    return a + (b - a) * (float)(s3_seed >> 8) / 16777216.0f;
}

static const float s3_col[] = {0.0f, 0.1f, 0.2f, 0.9f, 0.5f, 0.9f, 0.3f, 0.2f, 1.0f, 1.0f, 1.0f, 0.6f};
static const float s3_opa[] = {0.0f, 0.0f, 0.2f, 0.8f, 1.0f, 3.0f};

/* Creates the three volumes and the TF on dev; 0 ok, -1 with a message. */
static int scenes3_create(lc_device *dev, scenes3 *s)
{
    memset(s, 0, sizeof *s);
    s3_seed = 12345u;
    for (int i = 0; i < S3_NP; i++) {
        for (int k = 0; k < 3; k++) s->pos[3 * i + k] = s3_rnd(-1.5f, 1.5f);
        s->rad[i] = s3_rnd(0.08f, 0.3f);
        s->val[i] = s3_rnd(0.2f, 1.0f);
        s->field[i] = (uint8_t)(i % 2);
    }
    for (int z = 0; z < S3_G; z++)
        for (int y = 0; y < S3_G; y++)
            for (int x = 0; x < S3_G; x++) {
                float fx = (float)x / (S3_G - 1) - 0.5f, fy = (float)y / (S3_G - 1) - 0.5f,
                      fz = (float)z / (S3_G - 1) - 0.5f;
                s->grid[(z * S3_G + y) * S3_G + x] =
                    0.5f + 0.5f * sinf(9.0f * fx) * cosf(7.0f * fy) * sinf(5.0f * fz + 0.3f) + s3_rnd(0.0f, 0.05f);
            }
    for (int i = 0; i < S3_NR; i++) {
        for (int k = 0; k < 3; k++) s->rc[3 * i + k] = s3_rnd(-1.5f, 1.5f);
        s->rs[i] = s3_rnd(0.2f, 0.6f);
        s->rw[i] = s3_rnd(-0.5f, 1.0f);
    }
    lc_particles_desc pd = {.count = S3_NP, .positions = s->pos, .radii = s->rad, .values = s->val,
                            .fields = s->field, .nfields = 2};
    lc_grid_desc gd = {.size = {S3_G, S3_G, S3_G}, .type = LC_VALUE_FLOAT32, .data = s->grid,
                       .spacing = {0.125f, 0.125f, 0.125f}, .origin = {-1.4f, -1.4f, -1.4f}};
    lc_rbf_desc rd = {.count = S3_NR, .centres = s->rc, .widths = s->rs, .weights = s->rw,
                      .domain = {{-1.8f, -1.8f, -1.8f}, {1.8f, 1.8f, 1.8f}}};
    lc_tf_field tff[2] = {{s3_col, 3, s3_opa, 3, 0, {0, 0}}, {s3_col + 4, 2, s3_opa, 3, 0, {0, 0}}};
    s->name[0] = "particles", s->name[1] = "grid", s->name[2] = "rbf";
    if (lc_particles_create(dev, &pd, &s->vol[0]) != LC_OK || lc_grid_create(dev, &gd, &s->vol[1]) != LC_OK ||
        lc_rbf_create(dev, &rd, &s->vol[2]) != LC_OK || lc_tf_create(dev, tff, 2, &s->tf) != LC_OK)
        return -1;
    return 0;
}

static void scenes3_destroy(scenes3 *s)
{
    for (int k = 0; k < 3; k++) lc_volume_destroy(s->vol[k]);
    lc_tf_destroy(s->tf);
}

/* The render of scene k (phong-shaded DVR; the grid also in MIP when
 * mode = 1): camera oblique so that rays cross tiles at many angles. */
static lc_render_desc scenes3_desc(const scenes3 *s, int k, int w, int h, int tile)
{
    lc_render_desc d = {.width = w, .height = h, .tf = s->tf, .volume = s->vol[k], .tile = tile,
                        .shading = LC_SHADE_PHONG, .alpha_stop = 0.99f};
    d.camera = (lc_camera){LC_PERSPECTIVE, {2.5f, 1.7f, 4.2f}, {0.05f, -0.1f, 0.0f}, {0, 1, 0}, 45.0f, 0.0f};
    if (k == 2) d.range[0] = 0.0f, d.range[1] = 1.2f; /* negative sums clamp to v = 0: transparent */
    return d;
}

/* 1 when the image has some opaque-ish pixel and some empty one: a render
 * that shows the scene (an all-black pair of images would compare equal). */
static int scenes3_nontrivial(const float *img, int w, int h)
{
    int seen = 0, empty = 0;
    for (long i = 0; i < (long)w * h; i++) {
        if (img[4 * i + 3] > 0.3f) seen = 1;
        if (img[4 * i + 3] == 0.0f) empty = 1;
    }
    return seen && empty;
}

#endif
