/* What tests/test_dp.c (regions in one process) and tests/test_mpi.c
 * (lc_mpi_render over ranks) share: the views, the desc of a case and the
 * rule an image composited from regions must meet against the one render
 * (SPEC.md "Regions"): mip, iso and slice to the bit; dvr within float
 * round-off of the "over" (2e-5) with alpha_stop = 1, within 1 - alpha_stop
 * otherwise. Include after check.h and imgcmp.h. */
#ifndef LC_TEST_DP_SCENE_H
#define LC_TEST_DP_SCENE_H

#include <math.h>
#include <string.h>
#include "lanecast/lanecast.h"

static const lc_camera dp_views[] = {
    {LC_PERSPECTIVE, {0.7f, 0.9f, 7.5f}, {0.05f, 0.1f, 0.0f}, {0, 1, 0}, 38.0f, 0.0f},
    {LC_PERSPECTIVE, {0.15f, -0.1f, 0.3f}, {1.0f, 0.4f, -0.8f}, {0, 1, 0}, 70.0f, 0.0f},
    {LC_ORTHOGRAPHIC, {-6.0f, 2.0f, 3.0f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 0.0f, 5.0f},
    {LC_PERSPECTIVE, {0.0f, 0.0f, 8.0f}, {0.0f, 0.0f, 0.0f}, {0, 1, 0}, 35.0f, 0.0f},
};
static const char *const dp_view_names[] = {"outside", "eye-inside", "ortho", "axis"};
#define DP_NVIEWS 4
static const char *const dp_mode_names[] = {"dvr", "mip", "iso", "slice"};

static inline lc_render_desc dp_desc(const lc_volume *v, const lc_tf *tf, lc_mode mode, int vi, float alpha_stop,
                                     int w, int h, float iso)
{
    lc_render_desc d = {0};
    d.width = w, d.height = h, d.volume = v, d.tf = tf, d.mode = mode, d.dt = 0.05f, d.alpha_stop = alpha_stop;
    d.camera = dp_views[vi];
    d.iso = iso;
    d.nplanes = 2;
    d.planes[0] = (lc_plane){{0.1f, 0.0f, 0.0f}, {1.0f, 0.2f, 0.1f}};
    d.planes[1] = (lc_plane){{0.0f, -0.3f, 0.2f}, {0.1f, 1.0f, -0.3f}};
    return d;
}

static inline void dp_check_image(const char *label, const float *got, const float *want, const lc_render_desc *d)
{
    size_t n = 4 * (size_t)d->width * (size_t)d->height;
    if (d->mode != LC_MODE_DVR) {
        CHECK_QUIET(memcmp(got, want, sizeof(float) * n) == 0, "%s: not the one render's image to the bit", label);
    } else if (d->alpha_stop == 1.0f) {
        double e = 0.0;
        for (size_t i = 0; i < n; i++) e = fmax(e, fabs((double)got[i] - (double)want[i]));
        CHECK_QUIET(e <= 2e-5, "%s: max |diff| %.3g > 2e-5 (float round-off of over)", label, e);
    } else {
        CHECK_QUIET(imgcmp_check_ex(label, got, want, d->width, d->height, (1.0 - d->alpha_stop) * 255.0,
                                    IMGCMP_NO_PSNR_BOUND, NULL, 1, NULL) == 0, "%s: beyond 1 - alpha_stop", label);
    }
}

#ifdef LC_HOST_MPI_DP_H
/* The regions of d rendered each from its part (parts[region]) over the
 * tree parts' partition gives (lci_dp_partition of the part's desc),
 * composited in the view's order into got (w x h RGBA). At most 16 regions. */
static inline lc_status dp_render_parts(lc_device *dev, const lc_render_desc *d, lc_volume *const *parts, int P,
                                        float *got)
{
    lci_kdtree t;
    lc_kcamera cam;
    int order[16];
    lci_cimage imgs[16];
    memset(imgs, 0, sizeof imgs);
    lc_render_desc dp = *d;
    dp.volume = parts[0];
    lc_status s = P > 16 ? LC_ERROR_INVALID_ARGUMENT : lci_dp_partition(dev, &dp, P, &t);
    if (s != LC_OK) return s;
    lci_dp_camera(dev, d, &cam);
    lci_kd_order(&t, &cam, order);
    for (int i = 0; i < P && s == LC_OK; i++) {
        lc_render_desc dr = *d;
        dr.volume = parts[order[i]];
        s = lci_dp_render_region(dev, &dr, &t, order[i], &imgs[i], NULL);
    }
    if (s == LC_OK) s = lci_dp_composite_local(dev, P, imgs, lci_dp_op(d), got, NULL, NULL, NULL);
    lci_kd_release(&t);
    for (int i = 0; i < P; i++) lci_cimage_free(&imgs[i]);
    return s;
}
#endif

#endif
