/* Render modes through the mode seam (kernels/mode.h): MIP images of
 * particles (both methods), grids (BVH with its default heuristics, and
 * brute force) and RBF sets (BVH and brute force) on every target this CPU runs, against the independent
 * reference core (tests/ref) at SPEC.md's tolerances; bad modes refused. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "imgcmp.h"
#include "lanecast/lanecast.h"
#include "ref/ref_core.h"
#include "ref/ref_fields.h"
#include "modes_scene.h"

static ref_params ref_view(const ref_tf *tf, double eye_z)
{
    ref_params p = {0};
    p.width = W, p.height = H;
    p.camera = (ref_camera){REF_PERSPECTIVE, {0.7, 0.9, eye_z}, {0.05, 0.1, 0.0}, {0, 1, 0}, 38.0, 0.0};
    p.mode = REF_MODE_MIP;
    p.tf = tf;
    p.dt = 0.07;
    p.alpha_stop = 1.0;
    return p;
}

static lc_render_desc lib_view(const lc_volume *v, const lc_tf *tf, float eye_z)
{
    lc_render_desc d = {0};
    d.width = W, d.height = H;
    d.camera = (lc_camera){LC_PERSPECTIVE, {0.7f, 0.9f, eye_z}, {0.05f, 0.1f, 0.0f}, {0, 1, 0}, 38.0f, 0.0f};
    d.mode = LC_MODE_MIP;
    d.tf = tf;
    d.volume = v;
    d.dt = 0.07f;
    d.alpha_stop = 1.0f;
    return d;
}

static void run_target(lc_target t, const scene *s, const float *want_p, const float *want_g, const float *want_r)
{
    lc_device *dev;
    if (lc_device_create(&(lc_device_desc){.target = t, .threads = 2}, &dev) != LC_OK) {
        CHECK(0, "%s: device: %s", lc_target_name(t), lc_last_error());
        return;
    }
    lc_tf_field tff[2] = {{col0, 3, opa, 2, 1, {0.0f, 1.0f}}, {col1, 2, opa, 2, 1, {0.0f, 1.0f}}};
    lc_tf *tf2 = NULL, *tf1 = NULL;
    lc_tf_create(dev, tff, 2, &tf2);
    lc_tf_create(dev, tff, 1, &tf1);
    lc_volume *pv = NULL, *gv = NULL;
    lc_particles_desc pd = {.count = NP, .positions = s->pos, .radii = s->rad, .fields = s->field, .nfields = 2};
    CHECK(lc_particles_create(dev, &pd, &pv) == LC_OK, "%s: particles", lc_target_name(t));
    lc_grid_desc gd = {.size = {GX, GY, GZ}, .type = LC_VALUE_FLOAT32, .data = s->grid,
                       .spacing = {0.25f, 0.25f, 0.25f}, .origin = {-2.0f, -1.5f, -1.25f}};
    CHECK(lc_grid_create(dev, &gd, &gv) == LC_OK, "%s: grid", lc_target_name(t));
    lc_volume *rv = NULL;
    lc_rbf_desc rd = {.count = NR, .centres = s->rc, .widths = s->rs, .weights = s->rw, .bias = RBF_BIAS,
                      .eps = RBF_EPS, .domain = rbf_domain};
    CHECK(lc_rbf_create(dev, &rd, &rv) == LC_OK, "%s: rbf", lc_target_name(t));
    float *img = malloc(sizeof(float) * 4 * W * H);
    char label[96];
    static const lc_method pm[] = {LC_METHOD_COHERENT, LC_METHOD_DIRECT}, gm[] = {LC_METHOD_BVH, LC_METHOD_BRUTE};
    static const char *const pn[] = {"coherent", "direct"}, *const gn[] = {"bvh", "brute"};
    for (int m = 0; m < 2 && pv && gv && img; m++) {
        lc_render_desc d = lib_view(pv, tf2, 9.0f);
        d.method = pm[m];
        snprintf(label, sizeof label, "mip-particles-%s-%s", lc_target_name(t), pn[m]);
        CHECK(lc_render(dev, &d, img, NULL) == LC_OK && imgcmp_check(label, img, want_p, W, H, 0, 0, NULL) == 0, "%s",
              label);
        d = lib_view(gv, tf1, 8.0f);
        d.method = gm[m];
        snprintf(label, sizeof label, "mip-grid-%s-%s", lc_target_name(t), gn[m]);
        CHECK(lc_render(dev, &d, img, NULL) == LC_OK && imgcmp_check(label, img, want_g, W, H, 0, 0, NULL) == 0, "%s",
              label);
        if (!rv) continue;
        d = lib_view(rv, tf1, 8.0f);
        d.method = gm[m];
        d.range[0] = -0.5f, d.range[1] = 1.2f;
        snprintf(label, sizeof label, "mip-rbf-%s-%s", lc_target_name(t), gn[m]);
        CHECK(lc_render(dev, &d, img, NULL) == LC_OK && imgcmp_check(label, img, want_r, W, H, 0, 0, NULL) == 0, "%s",
              label);
    }
    if (pv && img) { /* a bad mode is refused with a message naming it */
        lc_render_desc d = lib_view(pv, tf2, 9.0f);
        d.mode = (lc_mode)7;
        CHECK(lc_render(dev, &d, img, NULL) == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "mode"),
              "%s: mode 7 refused (%s)", lc_target_name(t), lc_last_error());
    }
    free(img);
    lc_volume_destroy(pv);
    lc_volume_destroy(gv);
    lc_volume_destroy(rv);
    lc_tf_destroy(tf1);
    lc_tf_destroy(tf2);
    lc_device_destroy(dev);
}

int main(void)
{
    static scene s;
    make_scene(&s);
    to_double(col0, dcol0, 12), to_double(col1, dcol1, 8), to_double(opa, dopa, 4);
    ref_tf rtf[2] = {{0, 1, dcol0, 3, dopa, 2}, {0, 1, dcol1, 2, dopa, 2}};
    ref_particle_set ps = {NP, s.dpos, s.drad, NULL, s.dfield, 2, 0, 0};
    ref_grid_field gf = {{GX, GY, GZ}, {-2.0, -1.5, -1.25}, {0.25, 0.25, 0.25}, s.dgrid};
    ref_source psrc, gsrc;
    ref_particles_source(&ps, &psrc);
    ref_grid_source(&gf, &gsrc);
    static float want_p[4 * W * H], want_g[4 * W * H];
    ref_params rp = ref_view(rtf, 9.0);
    CHECK(ref_render_f(&psrc, &rp, want_p) == 0, "reference: particles");
    rp = ref_view(rtf, 8.0);
    CHECK(ref_render_f(&gsrc, &rp, want_g) == 0, "reference: grid");
    ref_rbf_set rs = {NR, s.drc, s.drs, s.drw, RBF_BIAS, RBF_EPS};
    ref_source rsrc;
    ref_rbf_source(&rs, &rsrc);
    for (int a = 0; a < 3; a++) rsrc.lo[a] = (&rbf_domain.lo.x)[a], rsrc.hi[a] = (&rbf_domain.hi.x)[a];
    static float want_r[4 * W * H];
    ref_tf rtf_r = rtf[0];
    rtf_r.lo = -0.5, rtf_r.hi = 1.2;
    rp = ref_view(&rtf_r, 8.0);
    CHECK(ref_render_f(&rsrc, &rp, want_r) == 0, "reference: rbf");
    /* the comparison can fail: a reference of the wrong field colours must not pass */
    static float wrong[4 * W * H];
    ref_tf swapped[2] = {rtf[1], rtf[0]};
    rp = ref_view(swapped, 9.0);
    ref_render_f(&psrc, &rp, wrong);
    CHECK(imgcmp_check("mip-swapped-colours", wrong, want_p, W, H, 0, 0, NULL) != 0, "swapped colours are caught");
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        if (!lc_target_compiled((lc_target)t) || !lc_target_supported((lc_target)t)) {
            printf("skip %s: not compiled or not supported by this CPU\n", lc_target_name((lc_target)t));
            continue;
        }
        run_target((lc_target)t, &s, want_p, want_g, want_r);
    }
    return check_summary("modes");
}
