/* Colour maps, ParaView presets, the histogram default TF (lc_tf_auto), the
 * default camera (lc_camera_frame) and atom selections (lc_select_check),
 * through the public API. The last part renders HeadMRVolume.mhd with the
 * old default (heat preset, 8 / diagonal, looking down -z) and the new one,
 * and checks that the new image shows structure where the old one was a dim
 * glow (skipped without the shared data). usage: test_tf_defaults [DATA_DIR] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "host/api/tf.h"

static double tf_at(const lc_tf *tf, int f, double v, int c)
{
    double rgb[3], tau;
    lci_tf_eval(tf, f, v, rgb, &tau);
    return c < 3 ? rgb[c] : tau;
}

static void colormaps(lc_device *dev)
{
    /* endpoints of the published maps (matplotlib: viridis #440154 .. #fde725,
     * inferno #000004 .. #fcffa4, magma #000004 .. #fcfdbf, plasma #0d0887 ..
     * #f0f921; Moreland's cool-warm (59, 76, 192) .. (180, 4, 38), 221 grey in the middle) */
    static const struct { const char *name; double v; int rgb[3]; } pts[] = {
        {"viridis", 0, {0x44, 0x01, 0x54}},  {"viridis", 1, {0xfd, 0xe7, 0x25}}, {"inferno", 0, {0x00, 0x00, 0x04}},
        {"inferno", 1, {0xfc, 0xff, 0xa4}},  {"magma", 0, {0x00, 0x00, 0x04}},   {"magma", 1, {0xfc, 0xfd, 0xbf}},
        {"plasma", 0, {0x0d, 0x08, 0x87}},   {"plasma", 1, {0xf0, 0xf9, 0x21}},  {"cool-warm", 0, {59, 76, 192}},
        {"cool-warm", 1, {180, 4, 38}},      {"cool-warm", 0.5, {221, 221, 221}}, {"grayscale", 0.5, {128, 128, 128}},
        /* viridis at 0.5: halfway between entries 127 and 128, #21918c and #21918d */
        {"viridis", 0.5, {0x21, 0x91, 0x8c}}};
    for (size_t i = 0; i < sizeof pts / sizeof pts[0]; i++) {
        lc_tf *tf = NULL;
        lc_status s = lc_tf_preset(dev, pts[i].name, 2, 3.0f, &tf);
        double err = 0.0;
        for (int c = 0; s == LC_OK && c < 3; c++) {
            double e = fabs(255.0 * tf_at(tf, 1, pts[i].v, c) - pts[i].rgb[c]);
            err = e > err ? e : err;
        }
        CHECK(s == LC_OK && err <= 1.0, "preset %s at v = %.3f: within %.2f/255 of (%d, %d, %d)", pts[i].name, pts[i].v,
              err, pts[i].rgb[0], pts[i].rgb[1], pts[i].rgb[2]);
        CHECK(s == LC_OK && tf_at(tf, 0, 0.05, 3) == 0.0 && fabs(tf_at(tf, 0, 1.0, 3) - 3.0) < 1e-6,
              "preset %s keeps the preset ramp (tau 0 below 0.1, 3 at 1)", pts[i].name);
        lc_tf_destroy(tf);
    }
    int n = 0;
    while (lc_tf_preset_name(n)) n++;
    CHECK(n >= 10 && lc_tf_preset_name(-1) == NULL, "lc_tf_preset_name lists %d presets", n);
    lc_tf *tf = NULL;
    CHECK(lc_tf_preset(dev, "virdis", 1, 1.0f, &tf) == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "viridis"),
          "an unknown preset lists the known ones: %s", lc_last_error());
}

static void paraview(lc_device *dev)
{
#if LC_HAVE_JSON
    /* x from -10 to 30: v = (x + 10) / 40; alpha 0.5 -> tau = ln 2 */
    const char *pv = "[{\"Name\": \"test\", \"ColorSpace\": \"RGB\", \"RGBPoints\": [-10, 0, 0, 1,  10, 0, 1, 0,  30, 1, 0, 0],"
                     " \"Points\": [-10, 0, 0.5, 0,  30, 0.5, 0.5, 0]}]";
    lc_tf *tf = NULL;
    lc_status s = lc_tf_parse(dev, pv, "pv.json", &tf);
    CHECK(s == LC_OK, "ParaView preset parses: %s", s == LC_OK ? "" : lc_last_error());
    if (s == LC_OK) {
        lc_tf_field f;
        lc_tf_get_field(tf, 0, &f);
        CHECK(f.ncolor == 3 && f.color[4] == 0.5f && f.color[6] == 1.0f && !f.has_range,
              "RGBPoints x -10..30 become v 0, 0.5, 1 (no range: the data's, as ParaView rescales)");
        CHECK(fabs(tf_at(tf, 0, 1.0, 3) - log(2.0)) < 1e-6 && tf_at(tf, 0, 0.0, 3) == 0.0 && !lc_tf_default_opacity(tf, 0),
              "Points alpha 0.5 becomes tau = ln 2 = %.6f (got %.6f)", log(2.0), tf_at(tf, 0, 1.0, 3));
        lc_tf_destroy(tf);
    }
    s = lc_tf_parse(dev, "[{\"Name\": \"c\", \"RGBPoints\": [0, 0, 0, 0, 1, 1, 1, 1]}]", "c.json", &tf);
    CHECK(s == LC_OK && lc_tf_default_opacity(tf, 0) == 1, "a preset without Points says its opacity is a stand-in");
    lc_tf_destroy(tf);
    s = lc_tf_parse(dev, "[{\"Name\": \"c\", \"RGBPoints\": [0, 0, 0, 0, 1, 1, 1]}]", "bad.json", &tf);
    CHECK(s == LC_ERROR_FORMAT && strstr(lc_last_error(), "bad.json") && strstr(lc_last_error(), "RGBPoints"),
          "RGBPoints not in groups of 4: %s", lc_last_error());
    s = lc_tf_parse(dev, "[{\"Name\": \"c\"}]", "none.json", &tf);
    CHECK(s == LC_ERROR_FORMAT && strstr(lc_last_error(), "none.json"), "no preset in the array: %s", lc_last_error());
    s = lc_tf_parse(dev, "{\"color\": [[0, 1, 1, 1]], \"opacity\": [[0, 0.5]]}", "spec.json", &tf);
    CHECK(s == LC_OK && !lc_tf_default_opacity(tf, 0), "SPEC.md's JSON still parses");
    lc_tf_destroy(tf);
#else
    (void)dev;
    printf("skip ParaView presets: built without json-c\n");
#endif
}

/* A 32^3 uint8 grid: value 0 (background) in most voxels, a sphere of
 * values 100..199 rising towards its centre. */
static lc_volume *sphere_grid(lc_device *dev, int invert)
{
    enum { N = 32 };
    static uint8_t v[N * N * N];
    for (int z = 0; z < N; z++)
        for (int y = 0; y < N; y++)
            for (int x = 0; x < N; x++) {
                double r = sqrt((x - 15.5) * (x - 15.5) + (y - 15.5) * (y - 15.5) + (z - 15.5) * (z - 15.5));
                int val = r < 10.0 ? 199 - (int)(r * 10.0) : 0;
                v[(z * N + y) * N + x] = (uint8_t)(invert ? 255 - val : val);
            }
    lc_grid_desc d = {.size = {N, N, N}, .type = LC_VALUE_UINT8, .data = v};
    lc_volume *g = NULL;
    lc_grid_create(dev, &d, &g);
    return g;
}

static int cmp_int(const void *a, const void *b) { return *(const int *)a - *(const int *)b; }

/* The 99th percentile of the sphere's values (1st when inverted), computed
 * here from the same formula as sphere_grid. */
static double sphere_q99(int invert)
{
    static int vals[32 * 32 * 32];
    int n = 0;
    for (int z = 0; z < 32; z++)
        for (int y = 0; y < 32; y++)
            for (int x = 0; x < 32; x++) {
                double r = sqrt((x - 15.5) * (x - 15.5) + (y - 15.5) * (y - 15.5) + (z - 15.5) * (z - 15.5));
                if (r < 10.0) vals[n++] = invert ? 255 - (199 - (int)(r * 10.0)) : 199 - (int)(r * 10.0);
            }
    qsort(vals, (size_t)n, sizeof vals[0], cmp_int);
    return invert ? vals[n / 100] : vals[n - 1 - n / 100];
}

static void auto_tf(lc_device *dev)
{
    lc_volume *g = sphere_grid(dev, 0);
    uint64_t h[256];
    CHECK(g && lc_grid_histogram(g, 256, h) == LC_OK, "lc_grid_histogram");
    uint64_t total = 0;
    for (int i = 0; i < 256; i++) total += h[i];
    CHECK(total == 32 * 32 * 32 && h[0] > total / 2 && h[255] > 0, "histogram counts every node (%llu), background in bin 0",
          (unsigned long long)total);
    lc_tf *tf = NULL;
    lc_status s = lc_tf_auto(dev, g, NULL, 0.0f, &tf);
    lc_tf_field f;
    if (s == LC_OK) lc_tf_get_field(tf, 0, &f);
    /* the background edge lies between 0 and the smallest sphere value 100; the top at the 99th percentile
     * of the sphere's values, within a bin (199 / 1024) */
    double q = sphere_q99(0);
    CHECK(s == LC_OK && f.has_range && f.range[0] > 0.0f && f.range[0] <= 100.0f && fabs(f.range[1] - q) <= 0.5,
          "auto range %.1f..%.1f skips the background 0 and ends at the 99th percentile %.0f of the rest",
          s == LC_OK ? f.range[0] : 0.0, s == LC_OK ? f.range[1] : 0.0, q);
    double tau_max = 16.0 / sqrt(3.0 * 31.0 * 31.0);
    CHECK(s == LC_OK && tf_at(tf, 0, 0.0, 3) == 0.0 && fabs(tf_at(tf, 0, 1.0, 3) - tau_max) < 1e-5,
          "auto opacity: 0 at the background edge, 16 / diagonal = %.4f at the top", tau_max);
    CHECK(s == LC_OK && fabs(255.0 * tf_at(tf, 0, 0.0, 0) - 0x44) <= 1.0, "auto colours: viridis by default");
    lc_tf_destroy(tf);
    s = lc_tf_auto(dev, g, "magma", 2.0f, &tf);
    CHECK(s == LC_OK && fabs(tf_at(tf, 0, 1.0, 3) - 2.0) < 1e-6 && fabs(255.0 * tf_at(tf, 0, 1.0, 2) - 0xbf) <= 1.0,
          "auto with magma and max_tau 2");
    lc_tf_destroy(tf);
    CHECK(lc_tf_auto(dev, g, "nope", 0.0f, &tf) == LC_ERROR_INVALID_ARGUMENT, "auto: unknown colour map fails");
    lc_volume_destroy(g);
    /* background at the top (255): the informative side lies below */
    g = sphere_grid(dev, 1);
    s = lc_tf_auto(dev, g, NULL, 1.0f, &tf);
    if (s == LC_OK) lc_tf_get_field(tf, 0, &f);
    q = sphere_q99(1);
    CHECK(s == LC_OK && fabs(f.range[0] - q) <= 0.5 && f.range[1] >= 155.0f && f.range[1] < 255.0f &&
              tf_at(tf, 0, 1.0, 3) == 0.0 && tf_at(tf, 0, 0.0, 3) == 1.0,
          "inverted data: range %.1f..%.1f from the 1st percentile %.0f up to the background, opacity falling towards it",
          s == LC_OK ? f.range[0] : 0.0, s == LC_OK ? f.range[1] : 0.0, q);
    lc_tf_destroy(tf);
    lc_volume_destroy(g);
}

static void camera(void)
{
    lc_box3 b = {{0, 0, 0}, {2, 4, 6}};
    lc_camera c = {0};
    CHECK(lc_camera_frame(&b, 0.0f, 0.0f, &c) == LC_OK, "lc_camera_frame");
    float r = 0.5f * sqrtf(4 + 16 + 36), dist = r / sinf(20.0f * 3.14159265f / 180.0f) * 1.05f;
    CHECK(c.eye.x == 1.0f && c.eye.y == 2.0f && fabsf(c.eye.z - (3.0f + dist)) < 1e-4f && c.at.z == 3.0f && c.up.y == 1.0f,
          "azimuth 0, elevation 0 is the old default: down -z from z = %.3f (got %.3f)", 3.0 + dist, c.eye.z);
    lc_camera_frame(&b, LC_CAMERA_AZIMUTH, LC_CAMERA_ELEVATION, &c);
    float dx = c.eye.x - 1.0f, dy = c.eye.y - 2.0f, dz = c.eye.z - 3.0f;
    CHECK(dx > 0.0f && dy > 0.0f && dz > 0.0f && fabsf(sqrtf(dx * dx + dy * dy + dz * dz) - dist) < 1e-3f &&
              fabsf(atan2f(dx, dz) * 180.0f / 3.14159265f - 35.0f) < 1e-3f,
          "the default view is oblique (from +x, +y, +z) at the same distance, azimuth 35");
    CHECK(lc_camera_frame(&b, 0.0f, 90.0f, &c) == LC_ERROR_INVALID_ARGUMENT, "elevation 90 is refused");
}

static void selections(void)
{
    static const char *const good[] = {"protein", "not water", "element C N O", "resname ALA", "chain A", "type 1 2",
                                       "index 0:999", "(protein or water) and not element H", "name C*", "resid 1 5:9",
                                       "NOT (ion OR solvent)", "all", "segid PROA and backbone"};
    for (size_t i = 0; i < sizeof good / sizeof good[0]; i++)
        CHECK(lc_select_check(good[i]) == LC_OK, "select '%s' parses", good[i]);
    static const struct { const char *expr; const char *needle; } bad[] = {
        {"protein and", "position 12"},         {"(protein or water", "position 18"}, {"resname", "position 8"},
        {"protien", "position 1"},              {"index 5:2", "position 7"},          {"protein water", "position 9"},
        {"index a", "position 7"},              {"protein )", "position 9"}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        lc_status s = lc_select_check(bad[i].expr);
        CHECK(s == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), bad[i].needle), "select '%s' fails at %s: %s",
              bad[i].expr, bad[i].needle, lc_last_error());
    }
}

/* Fraction of pixels with alpha > 0.05 and the median of their brightest
 * channel (composited on black). */
static void image_measure(const float *rgba, int n, double *covered, double *median)
{
    float *lum = malloc(sizeof(float) * (size_t)n);
    int k = 0;
    for (int i = 0; i < n; i++)
        if (rgba[4 * i + 3] > 0.05f) {
            float m = rgba[4 * i];
            for (int c = 1; c < 3; c++) m = rgba[4 * i + c] > m ? rgba[4 * i + c] : m;
            lum[k++] = m;
        }
    *covered = (double)k / n;
    int cmp_i = 0;
    /* partial sort: count above thresholds */
    double lo = 0.0, hi = 1.0;
    for (int it = 0; it < 30 && k; it++) {
        double mid = 0.5 * (lo + hi);
        cmp_i = 0;
        for (int i = 0; i < k; i++) cmp_i += lum[i] > mid;
        if (cmp_i > k / 2) lo = mid;
        else hi = mid;
    }
    *median = k ? lo : 0.0;
    free(lum);
}

/* Mean absolute difference of the brightest channel between horizontal
 * neighbours where either is covered: edges inside the data, i.e. structure. */
static double image_contrast(const float *rgba, int w, int h)
{
    double sum = 0.0;
    long n = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x + 1 < w; x++) {
            const float *a = rgba + 4 * (y * w + x), *b = a + 4;
            if (a[3] <= 0.05f && b[3] <= 0.05f) continue;
            float ma = fmaxf(a[0], fmaxf(a[1], a[2])), mb = fmaxf(b[0], fmaxf(b[1], b[2]));
            sum += fabs(ma - mb);
            n++;
        }
    return n ? sum / n : 0.0;
}

static void head(lc_device *dev, const char *data)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/volumes/HeadMRVolume.mhd", data);
    FILE *fp = fopen(path, "rb");
    if (!fp) {
        printf("skip HeadMRVolume.mhd: not found under %s (set -Ddata_dir=...)\n", data);
        return;
    }
    fclose(fp);
    lc_volume *v = NULL;
    if (lc_volume_load(dev, path, NULL, &v) != LC_OK) {
        CHECK(0, "load %s: %s", path, lc_last_error());
        return;
    }
    lc_volume_info vi;
    lc_volume_get_info(v, &vi);
    enum { W = 96, H = 96 };
    float *img = malloc(sizeof(float) * 4 * W * H);
    double cov[2], med[2], con[2];
    for (int k = 0; k < 2; k++) {
        lc_tf *tf = NULL;
        lc_render_desc rd = {.width = W, .height = H, .volume = v};
        if (k == 0) { /* the old default: heat at 8 / diagonal, looking down -z */
            float dx = vi.bounds.hi.x - vi.bounds.lo.x, dy = vi.bounds.hi.y - vi.bounds.lo.y,
                  dz = vi.bounds.hi.z - vi.bounds.lo.z;
            lc_tf_preset(dev, "heat", 1, 8.0f / sqrtf(dx * dx + dy * dy + dz * dz), &tf);
            lc_camera_frame(&vi.bounds, 0.0f, 0.0f, &rd.camera);
        } else {
            lc_tf_auto(dev, v, NULL, 0.0f, &tf);
        }
        rd.tf = tf;
        lc_status s = lc_render(dev, &rd, img, NULL);
        image_measure(img, W * H, &cov[k], &med[k]);
        con[k] = image_contrast(img, W, H);
        CHECK(s == LC_OK, "render HeadMRVolume with the %s default: %.0f%% of pixels covered, median brightness %.3f, "
              "neighbour contrast %.4f", k ? "new" : "old", 100.0 * cov[k], med[k], con[k]);
        lc_tf_destroy(tf);
    }
    /* the old image is a dim glow over the head's core; the new one lights
     * more of the head (skin to ventricles), and brighter (measured: 14% and
     * 0.198 before, 21% and 0.248 after at 96x96) */
    CHECK(cov[1] > 1.3 * cov[0], "new default covers over 1.3x the pixels of the old (%.0f%% vs %.0f%%)",
          100.0 * cov[1], 100.0 * cov[0]);
    CHECK(med[1] > 1.15 * med[0], "new default: median brightness over 1.15x the old (%.3f vs %.3f)", med[1], med[0]);
    free(img);
    lc_volume_destroy(v);
}

int main(int argc, char **argv)
{
    const char *data = argc > 1 ? argv[1] : "../shared/data";
    lc_device *dev = NULL;
    if (lc_device_create(NULL, &dev) != LC_OK) {
        printf("FAIL device: %s\n", lc_last_error());
        return 1;
    }
    colormaps(dev);
    paraview(dev);
    auto_tf(dev);
    camera();
    selections();
    head(dev, data);
    lc_device_destroy(dev);
    return check_summary("test_tf_defaults");
}
