/* Real volumes against the independent reference: the raw-encoded volumes of
 * ../shared/data/volumes (neghip uint8, HeadMRVolume uint8 with spacing 4,
 * headsq uint16 with anisotropic spacing, hydrogen float32) are read here by
 * the test itself (the header keys it needs, the raw little-endian voxels),
 * independently of the library's loaders, and rendered by the reference core
 * (tests/ref: ref_core with ref_fields' trilinear grid). The library loads the
 * same files through lc_volume_load and renders them with its BVH (heuristics
 * off, alpha_stop 1) and brute force, unlit, diffuse and Phong with SPEC's
 * default lighting and with other coefficients, on every target this CPU
 * supports; images must agree within SPEC.md's tolerances (imgcmp: 2/255,
 * 50 dB; NaN or Inf fails). Guards shading (gradients, lighting) on real
 * data, which test_grid_data's BVH-against-brute-force checks cannot. Skips
 * (77) when the data is absent. usage: test_grid_data_ref DATA_DIR */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "lanecast/lanecast.h"

#include "check.h"
#include "imgcmp.h"
#include "ref/ref_core.h"
#include "ref/ref_fields.h"

enum { W = 72, H = 64 };

typedef struct rawvol {
    int n[3];
    double spacing[3];
    int bytes; /* 1 uint8, 2 uint16, 4 float32 */
    char data[256];
} rawvol;

/* The keys this test needs from an NRRD or MetaImage header (both name their
 * data file next to the header); -1 when a key is missing or unexpected. */
static int read_header(const char *path, rawvol *v)
{
    FILE *f = fopen(path, "r");
    if (!f) return -1;
    char line[512], type[64] = "", file[200] = "";
    int ok_enc = 0, sizes = 0, spac = 0;
    while (fgets(line, sizeof line, f)) {
        if (sscanf(line, "sizes: %d %d %d", &v->n[0], &v->n[1], &v->n[2]) == 3) sizes = 1;
        if (sscanf(line, "DimSize = %d %d %d", &v->n[0], &v->n[1], &v->n[2]) == 3) sizes = 1;
        if (sscanf(line, "spacings: %lf %lf %lf", &v->spacing[0], &v->spacing[1], &v->spacing[2]) == 3) spac = 1;
        if (sscanf(line, "ElementSpacing = %lf %lf %lf", &v->spacing[0], &v->spacing[1], &v->spacing[2]) == 3) spac = 1;
        if (sscanf(line, "type: %63s", type) == 1 || sscanf(line, "ElementType = %63s", type) == 1) continue;
        if (sscanf(line, "data file: %199s", file) == 1 || sscanf(line, "ElementDataFile = %199s", file) == 1) continue;
        if (strstr(line, "encoding: raw") || strstr(line, "ElementByteOrderMSB = False")) ok_enc = 1;
    }
    fclose(f);
    v->bytes = !strcmp(type, "uint8") || !strcmp(type, "MET_UCHAR") ? 1 : !strcmp(type, "uint16") ? 2
             : !strcmp(type, "float") ? 4 : 0;
    const char *slash = strrchr(path, '/');
    snprintf(v->data, sizeof v->data, "%.*s/%s", slash ? (int)(slash - path) : 1, slash ? path : ".", file);
    return sizes && spac && ok_enc && v->bytes && file[0] ? 0 : -1;
}

/* The voxels as doubles, x fastest (little-endian, as the headers say). */
static double *read_voxels(const rawvol *v, double *lo, double *hi)
{
    size_t count = (size_t)v->n[0] * v->n[1] * v->n[2];
    unsigned char *raw = malloc(count * v->bytes);
    double *out = malloc(count * sizeof *out);
    FILE *f = fopen(v->data, "rb");
    size_t got = f ? fread(raw, v->bytes, count, f) : 0;
    if (f) fclose(f);
    if (got != count) {
        free(raw), free(out);
        return NULL;
    }
    *lo = INFINITY, *hi = -INFINITY;
    for (size_t i = 0; i < count; i++) {
        const unsigned char *p = raw + i * v->bytes;
        double x;
        if (v->bytes == 1) x = p[0];
        else if (v->bytes == 2) x = p[0] | p[1] << 8;
        else {
            uint32_t u = p[0] | p[1] << 8 | p[2] << 16 | (uint32_t)p[3] << 24;
            float fl;
            memcpy(&fl, &u, 4);
            x = fl;
        }
        out[i] = x;
        if (x < *lo) *lo = x;
        if (x > *hi) *hi = x;
    }
    free(raw);
    return out;
}

/* One view: the camera outside, looking at the centre. */
typedef struct view {
    double eye[3], at[3], dt;
} view;

static const double tf_color[] = {0, 0.2, 0.3, 0.9, 0.5, 0.9, 0.5, 0.2, 1, 1, 1, 0.9};
static const double tf_opacity[] = {0, 0, 0.03, 0, 0.4, 0.5, 1, 1.0};

static void ref_image(const ref_source *src, const ref_tf *tf, const view *vw, int shade, const lc_lighting *l,
                      float *out)
{
    ref_params p = {0};
    p.width = W, p.height = H;
    p.camera = (ref_camera){REF_PERSPECTIVE, {vw->eye[0], vw->eye[1], vw->eye[2]}, {vw->at[0], vw->at[1], vw->at[2]},
                            {0, 1, 0}, 40.0, 0.0};
    p.mode = REF_MODE_DVR;
    p.tf = tf;
    p.dt = vw->dt;
    p.alpha_stop = 1.0;
    p.shading = (ref_shading)shade;
    p.ka = l->ka, p.kd = l->kd, p.ks = l->ks, p.p = l->phong_exp;
    CHECK_QUIET(ref_render_f(src, &p, out) == 0, "reference render");
}

/* The library's BVH (heuristics off) and brute force against the reference
 * image r on every supported target. */
static void check_targets(const char *path, const char *name, const view *vw, const float *op, double lo, double hi,
                          int shade, const lc_lighting *l, const float *r, float *a)
{
    float color[12];
    for (int i = 0; i < 12; i++) color[i] = (float)tf_color[i];
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        if (!lc_target_compiled((lc_target)t) || !lc_target_supported((lc_target)t)) continue;
        lc_device *dev = NULL;
        if (lc_device_create(&(lc_device_desc){.target = (lc_target)t, .threads = 2}, &dev) != LC_OK) continue;
        lc_volume *g = NULL;
        lc_tf *tf = NULL;
        CHECK_QUIET(lc_volume_load(dev, path, NULL, &g) == LC_OK, "%s: %s", name, lc_last_error());
        lc_tf_field f = {.color = color, .ncolor = 3, .opacity = op, .nopacity = 4};
        CHECK_QUIET(lc_tf_create(dev, &f, 1, &tf) == LC_OK, "%s", lc_last_error());
        if (g && tf) {
            CHECK_QUIET(lc_grid_set_params(g, &(lc_grid_params){.delta_c = -1, .delta_p = -1, .delta_sv = -1}) == LC_OK,
                        "%s", lc_last_error());
            lc_render_desc d = {.width = W, .height = H, .tf = tf, .volume = g, .shading = (lc_shading)shade,
                                .lighting = *l, .range = {(float)lo, (float)hi}, .dt = (float)vw->dt, .alpha_stop = 1.0f};
            d.camera.eye = (lc_vec3){(float)vw->eye[0], (float)vw->eye[1], (float)vw->eye[2]};
            d.camera.at = (lc_vec3){(float)vw->at[0], (float)vw->at[1], (float)vw->at[2]};
            for (int m = 0; m < 2; m++) {
                d.method = m ? LC_METHOD_BRUTE : LC_METHOD_BVH;
                CHECK_QUIET(lc_render(dev, &d, a, NULL) == LC_OK, "%s", lc_last_error());
                char label[128];
                snprintf(label, sizeof label, "%s_%s_shade%d_p%d_%s", name, m ? "brute" : "bvh", shade, l->phong_exp,
                         lc_target_name((lc_target)t));
                imgcmp_result res;
                int rc = imgcmp_check_ex(label, a, r, W, H, 0, 0, NULL, 1, &res); /* SPEC.md: 2/255, 50 dB */
                CHECK_QUIET(rc == 0, "%s: max %.3f/255 PSNR %.1f dB", label, res.max_diff_255, res.psnr_db);
                printf("%-30s max %.3f/255 PSNR %6.1f dB\n", label, res.max_diff_255, res.psnr_db);
            }
        }
        lc_tf_destroy(tf);
        lc_volume_destroy(g);
        lc_device_destroy(dev);
    }
}

static void check_volume(const char *data, const char *name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/volumes/%s", data, name);
    rawvol v = {0};
    CHECK_QUIET(read_header(path, &v) == 0, "%s: the test could not read its header", path);
    double lo, hi, *vals = read_voxels(&v, &lo, &hi);
    CHECK_QUIET(vals != NULL, "%s: the test could not read %s", name, v.data);
    if (!vals) return;
    ref_grid_field rg = {{v.n[0], v.n[1], v.n[2]}, {0, 0, 0}, {v.spacing[0], v.spacing[1], v.spacing[2]}, vals};
    ref_source src;
    CHECK_QUIET(ref_grid_source(&rg, &src) == 0, "reference grid source");
    double ext[3], diag = 0, smin = fmin(v.spacing[0], fmin(v.spacing[1], v.spacing[2]));
    for (int k = 0; k < 3; k++) ext[k] = (v.n[k] - 1) * v.spacing[k], diag += ext[k] * ext[k];
    diag = sqrt(diag);
    /* transparent below 3% of the range; the densest material stops a ray in ~1/8 of the diagonal */
    double dop[8];
    float op[8];
    for (int i = 0; i < 8; i++) dop[i] = tf_opacity[i] * (i & 1 ? 16.0 / diag : 1.0), op[i] = (float)dop[i];
    ref_tf rtf = {lo, hi, tf_color, 3, dop, 4};
    /* from (0.6, 0.4, 0.8) / |.|, one diagonal from the centre: the box fills most of the frame */
    double u = diag / sqrt(0.36 + 0.16 + 0.64);
    view vw = {{0.5 * ext[0] + 0.6 * u, 0.5 * ext[1] + 0.4 * u, 0.5 * ext[2] + 0.8 * u},
               {0.5 * ext[0], 0.5 * ext[1], 0.5 * ext[2]}, 0.5 * smin};
    float *r = malloc(sizeof(float) * W * H * 4), *a = malloc(sizeof(float) * W * H * 4);
    const lc_lighting lights[2] = {{0, 0, 0, 0}, {0.1f, 0.6f, 0.7f, 40}}; /* SPEC's defaults; others */
    for (int shade = 0; shade <= 2; shade++)
        for (int li = 0; li < (shade ? 2 : 1); li++) {
            ref_image(&src, &rtf, &vw, shade, &lights[li], r);
            int covered = 0; /* the view must show something for the comparison to mean anything */
            for (int i = 0; i < W * H; i++) covered += r[4 * i + 3] > 0.1f;
            CHECK_QUIET(covered > W * H / 10, "%s: the reference image covers only %d of %d pixels", name, covered, W * H);
            if (shade == 0) printf("%s: %d x %d x %d, %d-byte values in [%g, %g], %d%% of pixels covered\n", name,
                                   v.n[0], v.n[1], v.n[2], v.bytes, lo, hi, 100 * covered / (W * H));
            check_targets(path, name, &vw, op, lo, hi, shade, &lights[li], r, a);
        }
    free(r), free(a), free(vals);
}

int main(int argc, char **argv)
{
    const char *data = argc > 1 ? argv[1] : "../shared/data";
    char p[1024];
    snprintf(p, sizeof p, "%s/volumes/neghip.nhdr", data);
    if (access(p, R_OK) != 0) {
        printf("SKIP: real volumes not found under %s/volumes (set -Ddata_dir=...)\n", data);
        return 77;
    }
    /* self-check: an all-NaN image must fail the comparison used above */
    float *nan_img = malloc(sizeof(float) * W * H * 4), *zero = calloc((size_t)W * H * 4, sizeof(float));
    for (int i = 0; i < W * H * 4; i++) nan_img[i] = NAN;
    imgcmp_result res;
    printf("self-check: an all-NaN image through the comparison (the FAIL line below is expected)\n");
    CHECK(imgcmp_check_ex("self-check_all-NaN", nan_img, zero, W, H, 0, 0, NULL, 0, &res) == 1,
          "self-check: an all-NaN image fails the image check");
    free(nan_img), free(zero);
    const char *vols[] = {"neghip.nhdr", "HeadMRVolume.mhd", "headsq.nhdr", "hydrogen.nhdr"};
    for (size_t v = 0; v < sizeof vols / sizeof *vols; v++) check_volume(data, vols[v]);
    printf("%s: %d failure(s)\n", check_failures ? "FAIL" : "ok", check_failures);
    return check_failures ? 1 : 0;
}
