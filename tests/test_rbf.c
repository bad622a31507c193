/* RBF sets (Jang 2004): images of every supported target and the three
 * methods (bvh, brute, coherent; tests/test_rbf_coherent.c has the rest of
 * coherent) against the independent reference core (tests/ref) at SPEC.md tolerances, a
 * perturbed weight that must fail the same comparison, lc_volume_sample
 * against the double-precision evaluator, text and binary files that round
 * trip, malformed files with one message each, and bad descriptors. */
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
static double worst_255, worst_psnr = INFINITY;

static void make_scenes(scene *sc, int *n)
{
    memset(sc, 0, sizeof *sc * 5);
    sc[0].name = "signed";
    fill(&sc[0], 12, 0, 0.3f, 1.0f, -1.0f, 1.5f, 7u, 0.3f);
    sc[0].range[0] = -1.0f, sc[0].range[1] = 2.0f, sc[0].dt = 0.075f;
    sc[1] = sc[0], sc[1].name = "signed_phong", sc[1].shade = LC_SHADE_PHONG;
    sc[2] = sc[0], sc[2].name = "bias_domain_diffuse", sc[2].bias = 0.25f, sc[2].shade = LC_SHADE_DIFFUSE;
    sc[2].domain = (lc_box3){{-2.5f, -1.8f, -2.2f}, {2.2f, 2.4f, 1.9f}};
    sc[3].name = "many_sizes_eps";
    fill(&sc[3], 80, 0, 0.12f, 0.7f, -0.8f, 1.2f, 99u, 0.3f);
    sc[3].eps = 1e-3f, sc[3].leaf = 2, sc[3].shade = LC_SHADE_DIFFUSE, sc[3].dt = 0.03f;
    sc[3].range[0] = -1.0f, sc[3].range[1] = 1.5f;
    sc[4].name = "bias_only", sc[4].bias = 0.5f, sc[4].dt = 0.05f, sc[4].range[1] = 1.0f;
    sc[4].domain = (lc_box3){{-1.5f, -1.0f, -2.0f}, {1.0f, 1.5f, 0.5f}};
    *n = 5;
}

/* ---------------------------------------------------------------- images */

static void test_images(void)
{
    printf("-- images: every target and method against the reference core\n");
    static scene sc[5];
    int ns;
    make_scenes(sc, &ns);
    float *want = malloc(sizeof(float) * 4 * W * H), *got = malloc(sizeof(float) * 4 * W * H);
    float *first = malloc(sizeof(float) * 4 * W * H);
    for (int i = 0; i < ns; i++) {
        for (int ti = 0; ti < ntargets; ti++) {
            lc_device_desc dd = {.target = targets[ti], .threads = 2};
            lc_device *dev = NULL;
            lc_volume *v = NULL;
            lc_rbf_desc d = desc_of(&sc[i], LC_RBF_ACCEL_DEFAULT, 0);
            if (lc_device_create(&dd, &dev) != LC_OK || lc_rbf_create(dev, &d, &v) != LC_OK) {
                CHECK(0, "%s: create on %s: %s", sc[i].name, lc_target_name(targets[ti]), lc_last_error());
                lc_device_destroy(dev);
                continue;
            }
            lc_rbf_info info;
            lc_rbf_get_info(v, &info);
            if (ti == 0) {
                double amax = 0.0, asum = 0.0;
                int rc = ref_image(&sc[i], info.eps, want);
                for (int p = 0; p < W * H; p++) amax = fmax(amax, want[4 * p + 3]), asum += want[4 * p + 3];
                CHECK(rc == 0 && amax > 0.2, "%s: reference image (alpha max %.2f, mean %.3f)", sc[i].name, amax,
                      asum / (W * H));
            }
            static const lc_method methods[] = {LC_METHOD_BVH, LC_METHOD_BRUTE, LC_METHOD_COHERENT};
            static const char *const mname[] = {"bvh", "brute", "coherent"};
            for (int m = 0; m < 3; m++) {
                char label[128];
                snprintf(label, sizeof label, "rbf_%s_%s_%s", sc[i].name, lc_target_name(targets[ti]), mname[m]);
                lc_render_stats st;
                if (render(dev, v, &sc[i], methods[m], got, &st)) {
                    CHECK(0, "%s: lc_render: %s", label, lc_last_error());
                    continue;
                }
                imgcmp_result r;
                imgcmp_stats(got, want, W, H, 2.0, &r);
                worst_255 = fmax(worst_255, r.max_diff_255), worst_psnr = fmin(worst_psnr, r.psnr_db);
                CHECK(imgcmp_check(label, got, want, W, H, 0, 0, outdir) == 0, "%s (%llu gaussians)", label,
                      (unsigned long long)st.kernel_evals);
                /* same terms in the same (leaf) order: bvh and brute agree to the bit (coherent
                   steps each term along the ray and sums per buffer: within the tolerances) */
                if (m == 0) memcpy(first, got, sizeof(float) * 4 * W * H);
                else if (m == 1) CHECK(!memcmp(first, got, sizeof(float) * 4 * W * H), "%s: bit-identical to bvh", label);
            }
            lc_volume_destroy(v);
            lc_device_destroy(dev);
        }
    }
    /* the comparison can fail: the strongest weight 10% off */
    lc_device *dev = NULL;
    lc_device_create(NULL, &dev);
    int strongest = 0;
    for (int i = 1; i < sc[0].n; i++) strongest = fabsf(sc[0].w[i]) > fabsf(sc[0].w[strongest]) ? i : strongest;
    scene bad = sc[0];
    bad.w[strongest] *= 1.1f;
    lc_rbf_info info;
    lc_volume *v = NULL;
    lc_rbf_desc d = desc_of(&sc[0], LC_RBF_ACCEL_DEFAULT, 0), db = desc_of(&bad, LC_RBF_ACCEL_DEFAULT, 0);
    lc_rbf_create(dev, &d, &v);
    lc_rbf_get_info(v, &info);
    lc_volume_destroy(v);
    ref_image(&sc[0], info.eps, want);
    db.eps = info.eps; /* same supports apart from the one weight */
    int failed = lc_rbf_create(dev, &db, &v) == LC_OK && render(dev, v, &bad, LC_METHOD_BVH, got, NULL) == 0 &&
                 imgcmp_check("rbf_expected_fail_perturbed_weight", got, want, W, H, 0, 0, NULL) == 1;
    CHECK(failed, "a weight perturbed by 10%% fails the image comparison (the FAIL line above is expected)");
    lc_volume_destroy(v);
    lc_device_destroy(dev);
    free(want), free(got), free(first);
}

/* ---------------------------------------------------------------- sampling */

/* Each term w exp(-d2 / 2s^2) with d2 / 2s^2 <= ln(|w| / eps) <= ~10 carries a
 * few ulps of the exponent (~1e-6 relative) and exp's 1e-6; summing in float
 * adds N * 6e-8 of sum |w|: 1e-5 * (|w0| + sum |w|) bounds both here. Points
 * within 1e-4 R of a support's edge are skipped (the term there is ~eps, and
 * float and double may disagree on which side they lie). */
static void test_sample(void)
{
    printf("-- lc_volume_sample against the reference evaluator\n");
    static scene sc[5];
    int ns;
    make_scenes(sc, &ns);
    enum { NP = 600 };
    static float pts[3 * NP], val[NP], grad[3 * NP];
    for (int si = 2; si <= 3; si++) {
        const scene *s = &sc[si];
        static double c[3 * MAXN], sw[MAXN], w[MAXN];
        double sumw = fabs(s->bias), mins = 1e30;
        for (int i = 0; i < 3 * s->n; i++) c[i] = s->c[i];
        for (int i = 0; i < s->n; i++) sw[i] = s->s[i], w[i] = s->w[i], sumw += fabs(w[i]), mins = fmin(mins, sw[i]);
        seed = 5u;
        for (int i = 0; i < NP; i++)
            for (int k = 0; k < 3; k++) pts[3 * i + k] = i < s->n ? s->c[3 * i + k] + rnd(-0.1f, 0.1f) : rnd(-4.0f, 4.0f);
        for (int ti = 0; ti < ntargets; ti++) {
            lc_device_desc dd = {.target = targets[ti], .threads = 1};
            lc_device *dev = NULL;
            lc_volume *v = NULL;
            lc_rbf_desc d = desc_of(s, LC_RBF_ACCEL_DEFAULT, 0);
            lc_rbf_info info;
            if (lc_device_create(&dd, &dev) != LC_OK || lc_rbf_create(dev, &d, &v) != LC_OK ||
                lc_rbf_get_info(v, &info) != LC_OK || lc_volume_sample(dev, v, NP, pts, val, grad) != LC_OK) {
                CHECK(0, "sample %s on %s: %s", s->name, lc_target_name(targets[ti]), lc_last_error());
                lc_volume_destroy(v), lc_device_destroy(dev);
                continue;
            }
            ref_rbf_set set = {(size_t)s->n, c, sw, w, s->bias, info.eps};
            double worst_v = 0.0, worst_g = 0.0;
            int used = 0;
            for (int i = 0; i < NP; i++) {
                const double p[3] = {pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]};
                int edge = 0;
                for (int j = 0; j < s->n; j++) {
                    double R = ref_rbf_support(sw[j], w[j], info.eps);
                    double e = sqrt(pow(p[0] - c[3 * j], 2) + pow(p[1] - c[3 * j + 1], 2) + pow(p[2] - c[3 * j + 2], 2));
                    edge |= R > 0.0 && fabs(e - R) < 1e-4 * R;
                }
                if (edge) continue;
                used++;
                double phi, g[1][3];
                ref_rbf_eval(&set, p, &phi, g);
                worst_v = fmax(worst_v, fabs(val[i] - phi));
                for (int k = 0; k < 3; k++) worst_g = fmax(worst_g, fabs(grad[3 * i + k] - g[0][k]));
            }
            double tv = 1e-5 * sumw, tg = 1e-5 * sumw / mins * 4.0;
            CHECK(worst_v <= tv && worst_g <= tg && used > NP / 2,
                  "sample %s on %s: %d points, |dphi| %.2g (tol %.2g), |dgrad| %.2g (tol %.2g)", s->name,
                  lc_target_name(targets[ti]), used, worst_v, tv, worst_g, tg);
            lc_volume_destroy(v);
            lc_device_destroy(dev);
        }
    }
}

/* ---------------------------------------------------------------- files */

static void path_in(char *buf, size_t n, const char *name) { snprintf(buf, n, "%s/%s", outdir, name); }

static int write_bytes(const char *path, const void *b, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f) return -1;
    size_t k = fwrite(b, 1, n, f);
    return fclose(f) == 0 && k == n ? 0 : -1;
}

/* docs/FORMATS-rbf.md, binary variant (this test runs on little-endian x86). */
static size_t binary_image(const scene *s, unsigned char *out, uint64_t count)
{
    static const unsigned char magic[8] = {0x89, 'L', 'C', 'R', 'B', 'F', '\r', '\n'};
    uint32_t version = 1, zero = 0;
    memcpy(out, magic, 8), memcpy(out + 8, &version, 4), memcpy(out + 12, &zero, 4);
    memcpy(out + 16, &count, 8), memcpy(out + 24, &s->bias, 4), memcpy(out + 28, &zero, 4);
    size_t o = 32;
    for (int i = 0; i < s->n; i++) {
        const float r[5] = {s->c[3 * i], s->c[3 * i + 1], s->c[3 * i + 2], s->s[i], s->w[i]};
        memcpy(out + o, r, 20), o += 20;
    }
    return o;
}

static int write_text(const char *path, const scene *s)
{
    FILE *f = fopen(path, "w");
    if (!f) return -1;
    fprintf(f, "# %s: written by test_rbf\nlanecast-rbf 1\nbias %.9g\n# a comment between items\ncount %d\n",
            s->name, (double)s->bias, s->n);
    for (int i = 0; i < s->n; i++)
        fprintf(f, "%.9g %.9g %.9g %.9g %.9g\n", (double)s->c[3 * i], (double)s->c[3 * i + 1], (double)s->c[3 * i + 2],
                (double)s->s[i], (double)s->w[i]);
    return fclose(f);
}

static void test_round_trip(lc_device *dev)
{
    printf("-- files round trip\n");
    static scene sc[5];
    int ns;
    make_scenes(sc, &ns);
    const scene *s = &sc[2];
    static unsigned char bin[32 + 20 * MAXN];
    char tp[512], bp[512];
    path_in(tp, sizeof tp, "rt_text.rbf"), path_in(bp, sizeof bp, "rt_binary.rbf");
    CHECK(write_text(tp, s) == 0 && write_bytes(bp, bin, binary_image(s, bin, (uint64_t)s->n)) == 0, "write files");
    lc_volume *orig = NULL;
    lc_rbf_desc d = desc_of(s, LC_RBF_ACCEL_DEFAULT, 0);
    d.domain = (lc_box3){{0, 0, 0}, {0, 0, 0}}; /* files carry no domain: compare with the support box */
    lc_rbf_create(dev, &d, &orig);
    enum { NP = 64 };
    float pts[3 * NP], v0[NP], v1[NP], g0[3 * NP], g1[3 * NP];
    seed = 11u;
    for (int i = 0; i < 3 * NP; i++) pts[i] = rnd(-3.0f, 3.0f);
    lc_volume_sample(dev, orig, NP, pts, v0, g0);
    lc_rbf_info io;
    lc_rbf_get_info(orig, &io);
    const char *paths[2] = {tp, bp}, *fmt[2] = {"rbf", "rbf-binary"};
    for (int k = 0; k < 2; k++) {
        lc_file_info fi;
        lc_volume *v = NULL;
        lc_rbf_info in;
        int ok = lc_file_probe(dev, paths[k], NULL, &fi) == LC_OK && !strcmp(fi.format, fmt[k]) &&
                 fi.kind == LC_KIND_RBF && lc_volume_load(dev, paths[k], NULL, &v) == LC_OK &&
                 lc_rbf_get_info(v, &in) == LC_OK && lc_volume_sample(dev, v, NP, pts, v1, g1) == LC_OK;
        CHECK(ok, "%s: detected by magic bytes and loaded%s%s", fmt[k], ok ? "" : ": ", ok ? "" : lc_last_error());
        if (ok)
            CHECK(in.count == io.count && in.bias == io.bias && !memcmp(&in.bounds, &io.bounds, sizeof in.bounds) &&
                      in.range[0] == io.range[0] && in.range[1] == io.range[1] && !memcmp(v0, v1, sizeof v0) &&
                      !memcmp(g0, g1, sizeof g0),
                  "%s: %zu RBFs, bias, bounds, range and samples bit-identical to the arrays", fmt[k], in.count);
        lc_volume_destroy(v);
    }
    /* the kind's build options through lc_volume_load */
    lc_option o[2] = {{"eps", "0.01"}, {"domain", "-1,-1,-1,1,1,1"}};
    lc_load_desc ld = {.options = o, .noptions = 2};
    lc_volume *v = NULL;
    lc_rbf_info in;
    CHECK(lc_volume_load(dev, tp, &ld, &v) == LC_OK && lc_rbf_get_info(v, &in) == LC_OK && in.eps == 0.01f &&
              in.bounds.lo.x == -1.0f && in.bounds.hi.z == 1.0f,
          "load options eps and domain reach the RBF set");
    lc_volume_destroy(v);
    lc_volume_destroy(orig);
}

typedef struct bad_file {
    const char *name, *text; /* text file, or NULL for a binary variant */
    int binary;              /* 1 truncated, 2 trailing data, 3 NaN weight, 4 huge count */
    const char *expect;      /* in the message, after the path */
} bad_file;

static void test_bad_files(lc_device *dev)
{
    printf("-- malformed files: one message each, naming the file and the line or byte\n");
    static const bad_file cases[] = {
        {"no_header.rbf", "bias 0\ncount 1\n0 0 0 1 1\n", 0, ":1: missing the header line"},
        {"version.rbf", "lanecast-rbf 2\nbias 0\ncount 0\n", 0, ":1: version '2'"},
        {"no_bias.rbf", "lanecast-rbf 1\ncount 1\n0 0 0 1 1\n", 0, ":2: expected 'bias VALUE'"},
        {"few.rbf", "lanecast-rbf 1\nbias 0\ncount 3\n0 0 0 1 1\n1 0 0 1 1\n", 0, "count 3 but the file ends after 2"},
        {"many.rbf", "lanecast-rbf 1\nbias 0\ncount 1\n0 0 0 1 1\n# c\n1 0 0 1 1\n", 0, ":6: more records than count 1"},
        {"number.rbf", "lanecast-rbf 1\nbias 0\ncount 2\n0 0 0 1 1\n0 0 1e0x 1 1\n", 0, ":5: z '1e0x' is not a finite"},
        {"nan.rbf", "lanecast-rbf 1\nbias 0\ncount 1\n0 0 0 1 nan\n", 0, ":4: weight w 'nan' is not a finite"},
        {"width.rbf", "lanecast-rbf 1\nbias 0\ncount 1\n0 0 0 0 1\n", 0, ":4: width 0, expected > 0"},
        {"fields.rbf", "lanecast-rbf 1\nbias 0\ncount 1\n0 0 0 1\n", 0, ":4: expected 5 numbers"},
        {"count.rbf", "lanecast-rbf 1\nbias 0\ncount -3\n", 0, ":3: count '-3' is not an integer"},
        {"bin_truncated.rbf", NULL, 1, "byte 52: truncated: record 1 of 3"},
        {"bin_trailing.rbf", NULL, 2, "byte 92: data after the 3 records"},
        {"bin_nan.rbf", NULL, 3, "byte 68: weight w is not finite"},
        {"bin_count.rbf", NULL, 4, "byte 16: count 1099511627776 exceeds"},
    };
    scene s = {.name = "three", .n = 3, .c = {0, 0, 0, 1, 0, 0, 0, 1, 0}, .s = {1, 1, 1}, .w = {1, -1, 2}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const bad_file *c = &cases[i];
        char p[512];
        path_in(p, sizeof p, c->name);
        unsigned char b[32 + 20 * 4];
        size_t n = binary_image(&s, b, c->binary == 4 ? (uint64_t)1 << 40 : 3);
        if (c->binary == 1) n = 32 + 20 + 7;
        if (c->binary == 2) memset(b + n, 0, 4), n += 4;
        if (c->binary == 3) memcpy(b + 32 + 20 + 16, &(float){NAN}, 4);
        int wr = c->text ? write_bytes(p, c->text, strlen(c->text)) : write_bytes(p, b, n);
        lc_volume *v = NULL;
        lc_status st = lc_volume_load(dev, p, NULL, &v);
        const char *msg = lc_last_error();
        CHECK(wr == 0 && st == LC_ERROR_FORMAT && !v && strstr(msg, p) == msg && strstr(msg, c->expect) &&
                  !strchr(msg, '\n'),
              "%s: %s", c->name, msg);
    }
}

/* ---------------------------------------------------------------- API */

static void test_api(lc_device *dev)
{
    printf("-- bad descriptors and methods\n");
    float c[6] = {0, 0, 0, 1, 1, 1}, s[2] = {1, 0}, w[2] = {1, 1}, s_ok[2] = {1, 0.5f}, w_small[2] = {1, 1e-6f};
    lc_volume *v = NULL;
    lc_rbf_desc d = {.count = 2, .centres = c, .widths = s, .weights = w};
    CHECK(lc_rbf_create(dev, &d, &v) == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "RBF 1 (width"),
          "width 0: %s", lc_last_error());
    d.widths = s_ok, d.domain = (lc_box3){{0, 0, 0}, {1, -1, 1}};
    CHECK(lc_rbf_create(dev, &d, &v) == LC_ERROR_INVALID_ARGUMENT, "empty domain: %s", lc_last_error());
    /* finite but huge: refused before the build (Embree's binning aborts on infinite extents) */
    float c_far[6] = {0, 0, 0, 1.7e38f, 1, 1}, s_wide[2] = {1, 3e38f};
    d.domain = (lc_box3){{0, 0, 0}, {0, 0, 0}}, d.centres = c_far;
    CHECK(lc_rbf_create(dev, &d, &v) == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "RBF 1 (a centre"),
          "centre 1.7e38: %s", lc_last_error());
    d.centres = c, d.widths = s_wide;
    CHECK(lc_rbf_create(dev, &d, &v) == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "RBF 1 (width beyond"),
          "width 3e38: %s", lc_last_error());
    d.widths = s_ok, d.domain = (lc_box3){{-3e38f, 0, 0}, {1, 1, 1}};
    CHECK(lc_rbf_create(dev, &d, &v) == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "domain"),
          "domain -3e38: %s", lc_last_error());
    d.domain = (lc_box3){{0, 0, 0}, {0, 0, 0}};
    d.domain = (lc_box3){{0, 0, 0}, {0, 0, 0}}, d.weights = w_small;
    lc_rbf_info in;
    CHECK(lc_rbf_create(dev, &d, &v) == LC_OK && lc_rbf_get_info(v, &in) == LC_OK && in.count == 1 &&
              in.dropped == 1 && fabsf(in.eps - 1e-4f) < 1e-10f && !strcmp(lc_kind_name(lc_volume_kind(v)), "rbf"),
          "|w| <= eps (default 1e-4 max |w|) is dropped and counted; kind name 'rbf'");
    float img[4 * 4 * 4];
    lc_render_desc rd = {.width = 4, .height = 4, .volume = v, .method = LC_METHOD_DIRECT};
    CHECK(lc_render(dev, &rd, img, NULL) == LC_ERROR_INVALID_ARGUMENT, "direct does not apply: %s", lc_last_error());
    rd.method = LC_METHOD_DEFAULT;
    CHECK(lc_render(dev, &rd, img, NULL) == LC_OK, "default method renders");
    lc_particles_info pi;
    CHECK(lc_particles_get_info(v, &pi) == LC_ERROR_INVALID_ARGUMENT, "particle call on an RBF set fails");
    lc_volume_destroy(v);
    lc_rbf_desc none = {.bias = 1.0f};
    float sum = 0.0f, x[3] = {5, 5, 5}, phi = 0.0f;
    rd.volume = NULL;
    if (lc_rbf_create(dev, &none, &v) == LC_OK) {
        rd.volume = v;
        lc_render(dev, &rd, img, NULL);
        lc_volume_sample(dev, v, 1, x, &phi, NULL);
    }
    for (int i = 0; i < 4 * 4 * 4; i++) sum += img[i];
    CHECK(rd.volume && sum == 0.0f && phi == 1.0f, "no RBF, no domain: an empty image; the field is the bias (%g)",
          (double)phi);
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
    test_api(dev);
    test_bad_files(dev);
    test_round_trip(dev);
    test_sample();
    test_images();
    lc_device_destroy(dev);
    printf("worst image difference over all targets, methods and scenes: %.3f/255, PSNR %.1f dB\n", worst_255,
           worst_psnr);
    return check_summary("test_rbf");
}
