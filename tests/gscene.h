/* The grid copy tests' shared scene (tests/test_grid_copies.c,
 * tests/test_grid_padded.c): one TF, a view (eye, target, shading), the
 * library's render desc for it and the reference core's dvr image of the
 * same grid values (tests/ref), 40-degree perspective, dt 0.4, no early
 * termination. Include after check.h, ref/ref_core.h and ref/ref_fields.h. */
#ifndef TESTS_GSCENE_H
#define TESTS_GSCENE_H

static const float gscene_color[12] = {0, 0.1f, 0.2f, 0.9f, 0.5f, 0.9f, 0.3f, 0.1f, 1, 1, 1, 0.3f};
static const float gscene_opacity[8] = {0, 0, 0.1f, 0, 0.6f, 0.1f, 1, 0.25f};

typedef struct gview {
    double eye[3], at[3];
    int shade;
} gview;

/* The library's desc for view vw over the TF range [lo, hi] (dvr). */
static inline lc_render_desc gscene_desc(lc_volume *g, const lc_tf *tf, const gview *vw, int w, int h, lc_method m,
                                         double lo, double hi)
{
    lc_render_desc d = {.width = w,
                        .height = h,
                        .tf = tf,
                        .volume = g,
                        .dt = 0.4f,
                        .alpha_stop = 1.0f,
                        .shading = (lc_shading)vw->shade,
                        .method = m};
    d.camera.eye = (lc_vec3){(float)vw->eye[0], (float)vw->eye[1], (float)vw->eye[2]};
    d.camera.at = (lc_vec3){(float)vw->at[0], (float)vw->at[1], (float)vw->at[2]};
    d.camera.up = (lc_vec3){0, 1, 0};
    d.camera.fovy = 40;
    d.range[0] = (float)lo, d.range[1] = (float)hi;
    return d;
}

/* The reference core's dvr image of the n[0] x n[1] x n[2] values (unit
 * spacing, origin 0) for view vw over the TF range [lo, hi]. */
static inline void gscene_ref(const int n[3], const double *values, double lo, double hi, const gview *vw, int w, int h,
                              float *out)
{
    double dc[12], dop[8];
    for (int i = 0; i < 12; i++)
        dc[i] = gscene_color[i];
    for (int i = 0; i < 8; i++)
        dop[i] = gscene_opacity[i];
    ref_tf rtf = {lo, hi, dc, 3, dop, 4};
    ref_grid_field rg = {{n[0], n[1], n[2]}, {0, 0, 0}, {1, 1, 1}, values};
    ref_source src;
    CHECK_QUIET(ref_grid_source(&rg, &src) == 0, "reference grid source");
    ref_params p = {0};
    p.width = w, p.height = h;
    p.camera = (ref_camera){
        REF_PERSPECTIVE, {vw->eye[0], vw->eye[1], vw->eye[2]}, {vw->at[0], vw->at[1], vw->at[2]}, {0, 1, 0}, 40.0, 0.0};
    p.mode = REF_MODE_DVR;
    p.tf = &rtf;
    p.dt = 0.4;
    p.alpha_stop = 1.0;
    p.shading = (ref_shading)vw->shade;
    CHECK_QUIET(ref_render_f(&src, &p, out) == 0, "reference render");
}

#endif
