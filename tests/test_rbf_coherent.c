/* RBF sets through the coherent method (issue 10: the particle kind's
 * coherent buffered kernel over the set, kparticles.h): on every supported
 * target, in dvr (unshaded, diffuse, phong), mip, iso and slice, with
 * weights of both signs and a non-zero bias, once visible in the TF and
 * once transparent (where the kernel skips the bias-only samples and the
 * nodes whose bound lies in the TF's transparent range), against the
 * independent reference core (tests/ref) at SPEC.md tolerances, and against
 * the BVH gather and the octree at the same tolerances. The skipping must
 * be active where the bias is transparent (fewer samples integrated than
 * the BVH gather's), the default method must be the coherent one, the
 * kernel's cone pre-test (LANECAST_PARTICLE_CONE=0 turns it off) must change
 * no bit and no term count, and a set whose bias was dropped must fail the
 * comparison. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "imgcmp.h"
#include "lanecast/lanecast.h"

#define W 64
#define H 48
#include "rbf_scene.h"

static const char *outdir = ".";
static lc_target targets[LC_TARGET_COUNT];
static int ntargets;
static imgcmp_worst worst_ref = IMGCMP_WORST_INIT, worst_methods = IMGCMP_WORST_INIT;

/* Transparent up to v = 0.45 (the TF range's lower part, holding the bias
 * values below), opaque above: clear_below lies above the bias. */
static const float clear_tf[] = {0.0f, 0.0f, 0.45f, 0.0f, 0.6f, 0.8f, 1.0f, 3.0f};

enum { NSCENES = 9 };

static void make_scenes(scene *sc)
{
    memset(sc, 0, sizeof *sc * NSCENES);
    const lc_box3 dom = {{-2.5f, -1.8f, -2.2f}, {2.2f, 2.4f, 1.9f}};
    /* the default TF (tf_opacity) has tau > 0 at the bias (v = 0.42) and below (negative terms) */
    sc[0].name = "bias_visible_diffuse";
    fill(&sc[0], 12, 0, 0.3f, 1.0f, -1.0f, 1.5f, 7u, 0.3f);
    sc[0].range[0] = -1.0f, sc[0].range[1] = 2.0f, sc[0].dt = 0.075f, sc[0].bias = 0.25f, sc[0].domain = dom;
    sc[0].shade = LC_SHADE_DIFFUSE;
    sc[1] = sc[0], sc[1].name = "bias_clear_phong", sc[1].shade = LC_SHADE_PHONG;
    sc[1].opacity = clear_tf, sc[1].nopacity = 4;
    sc[2].name = "dense_clustered_bias_clear";
    fill(&sc[2], 300, 1, 0.08f, 0.3f, -0.4f, 0.6f, 11u, 0.2f);
    sc[2].range[0] = -1.0f, sc[2].range[1] = 2.0f, sc[2].dt = 0.02f, sc[2].bias = 0.1f;
    sc[2].opacity = clear_tf, sc[2].nopacity = 4; /* no domain: the supports' box */
    sc[3] = sc[0], sc[3].name = "mip_negative_bias", sc[3].mode = LC_MODE_MIP, sc[3].bias = -0.3f;
    sc[3].shade = LC_SHADE_NONE;
    sc[4] = sc[0], sc[4].name = "iso_bias_phong", sc[4].mode = LC_MODE_ISO, sc[4].iso = 0.8f;
    sc[4].shade = LC_SHADE_PHONG;
    sc[5] = sc[4], sc[5].name = "iso_negative", sc[5].iso = 0.0f, sc[5].shade = LC_SHADE_DIFFUSE;
    sc[6] = sc[0], sc[6].name = "slice_bias", sc[6].mode = LC_MODE_SLICE, sc[6].shade = LC_SHADE_NONE;
    sc[6].nplanes = 2;
    const float pl[2][6] = {{0.1f, 0.2f, -0.35f, 0.0f, 0.0f, 1.0f}, {0.33f, 0.0f, 0.0f, 0.8f, 0.0f, 0.6f}};
    memcpy(sc[6].planes, pl, sizeof pl);
    /* bias 0 with tau(0) = 0: the particle kernel's own zero_transparent path */
    sc[7].name = "many_sizes_eps_zero_bias";
    fill(&sc[7], 80, 0, 0.12f, 0.7f, -0.8f, 1.2f, 99u, 0.3f);
    sc[7].eps = 1e-3f, sc[7].leaf = 2, sc[7].shade = LC_SHADE_DIFFUSE, sc[7].dt = 0.03f;
    sc[7].range[0] = -1.0f, sc[7].range[1] = 1.5f, sc[7].opacity = clear_tf, sc[7].nopacity = 4;
    sc[8] = sc[2], sc[8].name = "dense_mip", sc[8].mode = LC_MODE_MIP, sc[8].opacity = NULL;
}

static int create(lc_device *dev, const scene *s, lc_rbf_accel a, lc_volume **v, lc_rbf_info *info)
{
    lc_rbf_desc d = desc_of(s, a, 0);
    return lc_rbf_create(dev, &d, v) == LC_OK && lc_rbf_get_info(*v, info) == LC_OK ? 0 : -1;
}

/* The reference of scene s (and, for iso and slice, that no pixel is a knife
 * edge float round-off may tip, as tests/test_modes_iso.c). */
static void reference(const scene *s, float eps, float *want)
{
    static double depth[W * H], margin[W * H];
    double amax = 0.0, mmin = INFINITY;
    int hits = 0;
    int rc = ref_image_depth(s, eps, want, depth, margin);
    for (int p = 0; p < W * H; p++) {
        amax = fmax(amax, want[4 * p + 3]);
        mmin = fmin(mmin, margin[p]);
        hits += isfinite(depth[p]);
    }
    if (s->mode == LC_MODE_ISO || s->mode == LC_MODE_SLICE)
        CHECK(rc == 0 && hits > W * H / 20 && hits < W * H && mmin > (s->mode == LC_MODE_ISO ? 1e-6 : 1e-5),
              "%s: reference hits %d of %d pixels, closest call %.2e", s->name, hits, W * H, mmin);
    else CHECK(rc == 0 && amax > 0.2, "%s: reference image (alpha max %.2f)", s->name, amax);
}

static void compare(const char *label, const float *got, const float *want, imgcmp_worst *w)
{
    imgcmp_result r;
    int bad = imgcmp_check_ex(label, got, want, W, H, 0, 0, outdir, 1, &r);
    imgcmp_worst_add(w, &r);
    CHECK_QUIET(bad == 0, "%s: max %.3f/255, PSNR %.1f dB", label, r.max_diff_255, r.psnr_db);
}

static void test_scene(const scene *s, int expect_skip, float *want, float *coh, float *other)
{
    for (int ti = 0; ti < ntargets; ti++) {
        const char *tn = lc_target_name(targets[ti]);
        lc_device_desc dd = {.target = targets[ti], .threads = 2};
        lc_device *dev = NULL;
        lc_volume *v = NULL, *vo = NULL;
        lc_rbf_info info, io;
        if (lc_device_create(&dd, &dev) != LC_OK || create(dev, s, LC_RBF_ACCEL_DEFAULT, &v, &info) ||
            create(dev, s, LC_RBF_ACCEL_OCTREE, &vo, &io)) {
            CHECK(0, "%s: create on %s: %s", s->name, tn, lc_last_error());
            lc_volume_destroy(v), lc_device_destroy(dev);
            continue;
        }
        if (ti == 0) reference(s, info.eps, want);
        char label[160];
        lc_render_stats sc, sb;
        snprintf(label, sizeof label, "rbf_coherent_%s_%s", s->name, tn);
        if (render(dev, v, s, LC_METHOD_COHERENT, coh, &sc)) {
            CHECK(0, "%s: lc_render: %s", label, lc_last_error());
        } else {
            compare(label, coh, want, &worst_ref);
            /* the default method of a set built with the default accel is this one */
            CHECK_QUIET(info.accel == LC_RBF_ACCEL_COHERENT && render(dev, v, s, LC_METHOD_DEFAULT, other, NULL) == 0 &&
                            !memcmp(other, coh, sizeof(float) * 4 * W * H),
                        "%s: the default method renders the same bytes", label);
            snprintf(label, sizeof label, "rbf_coherent_vs_bvh_%s_%s", s->name, tn);
            if (render(dev, v, s, LC_METHOD_BVH, other, &sb) == 0) compare(label, coh, other, &worst_methods);
            else CHECK(0, "%s: %s", label, lc_last_error());
            /* a transparent bias and space no term reaches: its samples are skipped */
            if (expect_skip)
                CHECK_QUIET(sc.samples < sb.samples, "%s: coherent integrates %llu samples, bvh %llu", label,
                            (unsigned long long)sc.samples, (unsigned long long)sb.samples);
            snprintf(label, sizeof label, "rbf_coherent_vs_octree_%s_%s", s->name, tn);
            if (render(dev, vo, s, LC_METHOD_DEFAULT, other, NULL) == 0) compare(label, coh, other, &worst_methods);
            else CHECK(0, "%s: %s", label, lc_last_error());
            /* the particle kernel's cone pre-test changes no bit and no term (as tests/test_particles_cone.c) */
            lc_render_stats sf;
            snprintf(label, sizeof label, "rbf_coherent_cone_%s_%s", s->name, tn);
            setenv("LANECAST_PARTICLE_CONE", "0", 1);
            int rc = render(dev, v, s, LC_METHOD_COHERENT, other, &sf);
            unsetenv("LANECAST_PARTICLE_CONE");
            CHECK_QUIET(rc == 0 && !memcmp(other, coh, sizeof(float) * 4 * W * H) && sf.kernel_evals == sc.kernel_evals,
                        "%s: cone pre-test on = off, bit for bit and term for term (%llu, %llu)", label,
                        (unsigned long long)sc.kernel_evals, (unsigned long long)sf.kernel_evals);
            if (ti == 0)
                printf("%s: %llu samples, %llu gaussians, %llu passes (bvh: %llu samples, %llu gaussians)\n", s->name,
                       (unsigned long long)sc.samples, (unsigned long long)sc.kernel_evals,
                       (unsigned long long)sc.passes, (unsigned long long)sb.samples,
                       (unsigned long long)sb.kernel_evals);
        }
        lc_volume_destroy(v), lc_volume_destroy(vo);
        lc_device_destroy(dev);
    }
}

static void test_images(void)
{
    printf("-- images: coherent on every target against the reference core, the BVH gather and the octree\n");
    static scene sc[NSCENES];
    make_scenes(sc);
    float *want = malloc(sizeof(float) * 4 * W * H), *coh = malloc(sizeof(float) * 4 * W * H);
    float *other = malloc(sizeof(float) * 4 * W * H);
    for (int i = 0; i < NSCENES; i++) test_scene(&sc[i], i == 2, want, coh, other);
    imgcmp_worst_print("coherent against the reference", &worst_ref);
    imgcmp_worst_print("coherent against bvh and octree", &worst_methods);
    /* the comparisons bite: the bias dropped, in dvr (visible bias) and mip */
    lc_device *dev = NULL;
    lc_device_create(NULL, &dev);
    const int which[] = {0, 3};
    for (int k = 0; k < 2; k++) {
        const scene *s = &sc[which[k]];
        scene bad = *s;
        bad.bias = 0.0f;
        lc_volume *v = NULL;
        lc_rbf_info info;
        int failed = 0;
        char label[96];
        snprintf(label, sizeof label, "rbf_coherent_expected_fail_no_bias_%s", s->name);
        if (create(dev, s, LC_RBF_ACCEL_DEFAULT, &v, &info) == 0) {
            ref_image(s, info.eps, want);
            lc_volume_destroy(v), v = NULL;
            failed = create(dev, &bad, LC_RBF_ACCEL_DEFAULT, &v, &info) == 0 &&
                     render(dev, v, &bad, LC_METHOD_COHERENT, coh, NULL) == 0 &&
                     imgcmp_check(label, coh, want, W, H, 0, 0, NULL) == 1;
        }
        CHECK(failed, "%s: the set without its bias fails the comparison (the FAIL line above is expected)",
              s->name);
        lc_volume_destroy(v);
    }
    lc_device_destroy(dev);
    free(want), free(coh), free(other);
}

/* The accel and method options around the coherent method. */
static void test_options(lc_device *dev)
{
    printf("-- accel and method options\n");
    float c[6] = {0, 0, 0, 1, 0, 0}, s[2] = {1, 0.5f}, w[2] = {1, -1};
    lc_rbf_desc d = {.count = 2, .centres = c, .widths = s, .weights = w, .bias = 0.5f};
    lc_volume *v = NULL;
    lc_rbf_info in;
    CHECK(lc_rbf_create(dev, &d, &v) == LC_OK && lc_rbf_get_info(v, &in) == LC_OK &&
              in.accel == LC_RBF_ACCEL_COHERENT && in.octree_cells == 0,
          "the default accel is coherent, without an octree");
    lc_volume_destroy(v), v = NULL;
    d.significant = 1;
    CHECK(lc_rbf_create(dev, &d, &v) == LC_OK && lc_rbf_get_info(v, &in) == LC_OK &&
              in.accel == LC_RBF_ACCEL_OCTREE && in.octree_cells > 0,
          "significant = 1 with the default accel builds the octree");
    lc_volume_destroy(v), v = NULL;
    d.significant = 0, d.accel = LC_RBF_ACCEL_COHERENT;
    float img[4 * 8 * 8];
    lc_render_desc rd = {.width = 8, .height = 8, .method = LC_METHOD_DIRECT};
    if (lc_rbf_create(dev, &d, &v) == LC_OK) rd.volume = v;
    CHECK(rd.volume && lc_render(dev, &rd, img, NULL) == LC_ERROR_INVALID_ARGUMENT &&
              strstr(lc_last_error(), "coherent, bvh or brute"),
          "direct does not apply: %s", lc_last_error());
    lc_volume_destroy(v), v = NULL;
    d.accel = (lc_rbf_accel)4;
    CHECK(lc_rbf_create(dev, &d, &v) == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "accel = 4"),
          "accel 4: %s", lc_last_error());
    char p[512];
    snprintf(p, sizeof p, "%s/coherent_opts.rbf", outdir);
    FILE *f = fopen(p, "w");
    if (f) fputs("lanecast-rbf 1\nbias 0\ncount 2\n0 0 0 1 1\n1 0 0 0.5 -1\n", f), fclose(f);
    lc_option good = {"accel", "coherent"}, bad = {"accel", "packets"};
    lc_load_desc ld = {.options = &good, .noptions = 1};
    CHECK(f && lc_volume_load(dev, p, &ld, &v) == LC_OK && lc_rbf_get_info(v, &in) == LC_OK &&
              in.accel == LC_RBF_ACCEL_COHERENT,
          "accel=coherent from a load");
    lc_volume_destroy(v), v = NULL;
    ld.options = &bad;
    CHECK(lc_volume_load(dev, p, &ld, &v) == LC_ERROR_INVALID_ARGUMENT && !v &&
              strstr(lc_last_error(), "expected coherent, bvh or octree"),
          "accel=packets refused: %s", lc_last_error());
    /* no term and a domain: the field is the bias there, also through the coherent method */
    lc_rbf_desc none = {.bias = 1.0f, .domain = {{-1, -1, -1}, {1, 1, 1}}, .accel = LC_RBF_ACCEL_COHERENT};
    float a = 0.0f;
    rd.method = LC_METHOD_COHERENT, rd.volume = NULL, rd.range[0] = 0.0f, rd.range[1] = 2.0f; /* the bias at v = 0.5 */
    if (lc_rbf_create(dev, &none, &v) == LC_OK) rd.volume = v;
    lc_status st = rd.volume ? lc_render(dev, &rd, img, NULL) : LC_ERROR_INVALID_ARGUMENT;
    for (int i = 0; i < 8 * 8; i++) a = fmaxf(a, img[4 * i + 3]);
    CHECK(st == LC_OK && a > 0.0f, "a set of only the bias renders its domain (alpha max %.3f)", (double)a);
    lc_volume_destroy(v);
}

int main(int argc, char **argv)
{
    if (argc > 1) outdir = argv[1];
    for (lc_target t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        if (!lc_target_compiled(t)) printf("skip target %s: not compiled in\n", lc_target_name(t));
        else if (!lc_target_supported(t)) printf("skip target %s: this CPU cannot run it\n", lc_target_name(t));
        else targets[ntargets++] = t;
    }
    lc_device *dev = NULL;
    if (lc_device_create(NULL, &dev) != LC_OK) return 1;
    test_options(dev);
    test_images();
    lc_device_destroy(dev);
    return check_summary("test_rbf_coherent");
}
