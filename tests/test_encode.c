/* The RBF encoder (issue 10): a field that is exactly a bias plus K
 * Gaussians of both signs is recovered (RMS below 1e-3 of its range, checked
 * with the independent evaluator tests/ref, after a write and a load); CSV
 * and VTK legacy samples (ASCII and BINARY, POLYDATA and UNSTRUCTURED_GRID)
 * read back what was written; bad input fails with one message. Without
 * LAPACKE: the encoder's one line naming liblapacke-dev. Arg: a scratch
 * folder. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "lanecast/lanecast.h"
#include "ref/ref_fields.h"

#define K 4
#define N 28
static const double gc[K][3] = {{8, 9, 10}, {18, 17, 12}, {12, 19, 19}, {20, 8, 18}};
static const double gs[K] = {3.0, 2.2, 2.6, 1.8}, gw[K] = {1.0, -0.7, 0.6, -0.45};
static const double gbias = 0.2;
static const char *dir = ".";

static double truth(const double p[3])
{
    double f = gbias;
    for (int i = 0; i < K; i++) {
        double d2 = 0;
        for (int a = 0; a < 3; a++) d2 += (p[a] - gc[i][a]) * (p[a] - gc[i][a]);
        f += gw[i] * exp(-d2 / (2 * gs[i] * gs[i]));
    }
    return f;
}

static int have_lapacke(void)
{
    for (int i = 0; i < lc_feature_count(); i++) {
        lc_feature_info f;
        if (lc_feature_get(i, &f) == LC_OK && !strcmp(f.name, "lapacke")) return f.available;
    }
    return 0;
}

/* The encoded set's RMS error over the grid nodes by the reference evaluator. */
static double ref_rms(const lc_rbf_desc *d, const float *v, double range)
{
    size_t m = d->count;
    double *c = malloc(sizeof(double) * 3 * (m + 1)), *s = malloc(sizeof(double) * (m + 1)), *w = malloc(sizeof(double) * (m + 1));
    double wmax = 0;
    for (size_t i = 0; i < m; i++) {
        for (int a = 0; a < 3; a++) c[3 * i + a] = d->centres[3 * i + a];
        s[i] = d->widths[i], w[i] = d->weights[i], wmax = fmax(wmax, fabs(w[i]));
    }
    ref_rbf_set set = {m, c, s, w, d->bias, wmax > 0 ? 1e-4 * wmax : 1e-30};
    double sse = 0;
    for (int k = 0, j = 0; k < N; k++)
        for (int y = 0; y < N; y++)
            for (int x = 0; x < N; x++, j++) {
                double p[3] = {x, y, k}, f;
                ref_rbf_eval(&set, p, &f, NULL);
                sse += (f - v[j]) * (f - v[j]);
            }
    free(c), free(s), free(w);
    return sqrt(sse / (N * N * N)) / range;
}

static void sum_of_gaussians(lc_device *dev)
{
    static float v[N * N * N];
    float lo = INFINITY, hi = -INFINITY;
    for (int k = 0, j = 0; k < N; k++)
        for (int y = 0; y < N; y++)
            for (int x = 0; x < N; x++, j++) {
                double p[3] = {x, y, k};
                v[j] = (float)truth(p);
                lo = fminf(lo, v[j]), hi = fmaxf(hi, v[j]);
            }
    lc_grid_desc g = {.size = {N, N, N}, .type = LC_VALUE_FLOAT32, .data = v};
    lc_samples *sm = NULL;
    CHECK(lc_samples_create(dev, &(lc_samples_desc){.grid = &g}, &sm) == LC_OK, "samples from a %d^3 grid", N);
    lc_rbf_encode_desc d = {.max_error = 1e-4f, .max_rbfs = 16, .centre = LC_RBF_CENTRE_MAXERR};
    lc_rbf_encoded *set = NULL;
    lc_rbf_encode_report rep;
    lc_status s = lc_rbf_encode(dev, sm, &d, &set, &rep);
    CHECK(s == LC_OK, "encode %s", s == LC_OK ? "" : lc_last_error());
    if (s != LC_OK) return;
    printf("     %d Gaussians + bias: %zu RBFs, RMS %.3g, max %.3g of the range, %.2f s\n", K, rep.rbfs, rep.rms,
           rep.max_error, rep.seconds);
    CHECK(rep.rms < 1e-3, "report: RMS %.3g < 1e-3 of the range", rep.rms);
    double rr = ref_rms(&set->desc, v, hi - lo);
    CHECK(rr < 1e-3, "reference evaluator: RMS %.3g < 1e-3 of the range", rr);
    /* the check bites: a perturbed weight fails it */
    float *wv = (float *)set->desc.weights;
    wv[0] *= 1.1f;
    double bad = ref_rms(&set->desc, v, hi - lo);
    CHECK(bad > 1e-3, "a weight 10%% off fails the same check (RMS %.3g)", bad);
    wv[0] /= 1.1f;
    /* written and loaded back, both variants, sampled through the library */
    for (int text = 0; text < 2; text++) {
        char path[512];
        snprintf(path, sizeof path, "%s/enc_gauss%s.rbf", dir, text ? "_text" : "");
        CHECK(lc_rbf_write(dev, path, &set->desc, text ? LC_RBF_FILE_TEXT : LC_RBF_FILE_BINARY) == LC_OK, "write %s",
              path);
        lc_volume *vol = NULL;
        CHECK(lc_volume_load(dev, path, NULL, &vol) == LC_OK, "load %s%s", path, vol ? "" : lc_last_error());
        if (!vol) continue;
        float pts[3 * 64], got[64];
        double sse = 0;
        for (int i = 0; i < 64; i++) {
            for (int a = 0; a < 3; a++) pts[3 * i + a] = (float)((i * (7 + 3 * a)) % N);
        }
        lc_volume_sample(dev, vol, 64, pts, got, NULL);
        for (int i = 0; i < 64; i++) {
            double p[3] = {pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]};
            sse += (got[i] - truth(p)) * (got[i] - truth(p));
        }
        double rms = sqrt(sse / 64) / (hi - lo);
        CHECK(rms < 1e-3, "%s loaded and sampled: RMS %.3g < 1e-3", text ? "text" : "binary", rms);
        lc_volume_destroy(vol);
    }
    lc_rbf_encoded_free(set);
    lc_samples_destroy(sm);
}

static void write_file(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    fwrite(data, 1, n, f);
    fclose(f);
}

static void be32f(unsigned char *b, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    for (int i = 0; i < 4; i++) b[i] = (unsigned char)(u >> (24 - 8 * i));
}

static void be32i(unsigned char *b, int32_t v)
{
    for (int i = 0; i < 4; i++) b[i] = (unsigned char)((uint32_t)v >> (24 - 8 * i));
}

static lc_status load(lc_device *dev, const char *name, const char *text, size_t n, lc_samples **out)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    write_file(path, text, n ? n : strlen(text));
    return lc_samples_load(dev, path, NULL, out);
}

static void readers(lc_device *dev)
{
    lc_samples *s = NULL;
    lc_samples_info in;
    CHECK(load(dev, "a.csv", "# comment\nid, value ,z,y,x\n0,1.5,3,2,1\n1,-2,6,5,4\n", 0, &s) == LC_OK &&
              lc_samples_get_info(s, &in) == LC_OK && in.count == 2 && in.value_min == -2.0f && in.bounds.hi.x == 4.0f &&
              in.bounds.lo.z == 3.0f,
          "CSV with columns in any order: 2 samples, values -2..1.5");
    lc_samples_destroy(s);
    static const char poly[] = "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0\n0 1 0\n"
                               "VERTICES 1 4\n3 0 1 2\nPOINT_DATA 3\nVECTORS v float\n1 1 1 2 2 2 3 3 3\nSCALARS t float 1\n"
                               "LOOKUP_TABLE default\n0.5 0.25 4\n";
    s = NULL;
    CHECK(load(dev, "p.vtk", poly, 0, &s) == LC_OK && lc_samples_get_info(s, &in) == LC_OK && in.count == 3 &&
              in.value_max == 4.0f && in.bounds.hi.y == 1.0f,
          "VTK ASCII POLYDATA (vertices and vectors skipped): 3 samples, max 4: %s", s ? "" : lc_last_error());
    lc_samples_destroy(s);
    /* BINARY UNSTRUCTURED_GRID: big-endian points, cells, types, a FIELD array */
    unsigned char b[1024];
    size_t n = 0;
    n += (size_t)sprintf((char *)b + n, "# vtk DataFile Version 3.0\nt\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 2 float\n");
    for (int i = 0; i < 6; i++) be32f(b + n + 4 * i, (float)(i + 1)), (void)0;
    n += 24;
    n += (size_t)sprintf((char *)b + n, "\nCELLS 1 3\n");
    be32i(b + n, 2), be32i(b + n + 4, 0), be32i(b + n + 8, 1), n += 12;
    n += (size_t)sprintf((char *)b + n, "\nCELL_TYPES 1\n");
    be32i(b + n, 3), n += 4;
    n += (size_t)sprintf((char *)b + n, "\nPOINT_DATA 2\nFIELD fd 1\nrho 1 2 float\n");
    be32f(b + n, 7.0f), be32f(b + n + 4, -1.0f), n += 8;
    s = NULL;
    CHECK(load(dev, "u.vtk", (const char *)b, n, &s) == LC_OK && lc_samples_get_info(s, &in) == LC_OK &&
              in.count == 2 && in.value_max == 7.0f && in.value_min == -1.0f && in.bounds.hi.z == 6.0f,
          "VTK BINARY UNSTRUCTURED_GRID with a FIELD array: %s", s ? "2 samples, 6 coordinates" : lc_last_error());
    lc_samples_destroy(s);
    /* malformed: each fails with one message naming the file and line or byte */
    static const struct {
        const char *name, *text, *want;
    } bad[] = {
        {"nan.csv", "x,y,z,value\n0,0,0,1\n1,1,1,nan\n", "nan.csv:3: value 'nan' is not finite"},
        {"cols.csv", "x,y,z,value\n0,0,0\n", "cols.csv:2: 3 columns, the header has 4"},
        {"hdr.csv", "x,y,value\n0,0,0\n", "hdr.csv:1: the header names no column 'z'"},
        {"word.csv", "x,y,z,value\n0,0,0,1\n0,zero,0,1\n", "word.csv:3: y 'zero' is not a number"},
        {"short.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0\n", "short.vtk:"},
        {"sp.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET STRUCTURED_POINTS\n", "sp.vtk:4: DATASET STRUCTURED_POINTS"},
        {"nov.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 1 float\n0 0 0\n", "nov.vtk:"},
        {"nanv.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 1 float\n0 0 0\nPOINT_DATA 1\n"
                     "SCALARS s float\nLOOKUP_TABLE default\nnan\n", "nanv.vtk:10: SCALARS: value 0 is not finite"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        s = NULL;
        lc_status st = load(dev, bad[i].name, bad[i].text, 0, &s);
        const char *msg = lc_last_error();
        CHECK(st == LC_ERROR_FORMAT && !s && strstr(msg, bad[i].want) && !strchr(msg, '\n'), "%s fails: %s", bad[i].name,
              msg);
    }
    /* a lying binary header: a million points in a few bytes fails before allocating them */
    n = (size_t)sprintf((char *)b, "# vtk DataFile Version 3.0\nt\nBINARY\nDATASET POLYDATA\nPOINTS 1000000 float\n");
    memset(b + n, 0, 12), n += 12;
    s = NULL;
    lc_status st = load(dev, "lie.vtk", (const char *)b, n, &s);
    char want[64];
    snprintf(want, sizeof want, "lie.vtk: byte %zu:", n - 12); /* where the points would start */
    CHECK(st == LC_ERROR_FORMAT && strstr(lc_last_error(), want), "lying POINTS count: %s", lc_last_error());
}

static void bad_requests(lc_device *dev)
{
    float p[3 * 8], v[8];
    for (int i = 0; i < 8; i++) p[3 * i] = (float)i, p[3 * i + 1] = p[3 * i + 2] = 0, v[i] = (float)i;
    lc_samples *s = NULL;
    v[5] = NAN;
    CHECK(lc_samples_create(dev, &(lc_samples_desc){8, p, v, NULL}, &s) == LC_ERROR_INVALID_ARGUMENT &&
              strstr(lc_last_error(), "sample 5"),
          "a NaN value is refused: %s", lc_last_error());
    v[5] = 5;
    CHECK(lc_samples_create(dev, &(lc_samples_desc){8, p, v, NULL}, &s) == LC_OK, "8 samples");
    lc_rbf_encoded *set = NULL;
    lc_rbf_encode_desc d = {.fit_range_set = 1, .fit_range = {20, 30}};
    CHECK(lc_rbf_encode(dev, s, &d, &set, NULL) == LC_ERROR_INVALID_ARGUMENT && !set &&
              strstr(lc_last_error(), "fit range"),
          "an empty fit range: %s", lc_last_error());
    d = (lc_rbf_encode_desc){.max_rbfs = 8};
    CHECK(lc_rbf_encode(dev, s, &d, &set, NULL) == LC_ERROR_INVALID_ARGUMENT && !set &&
              strstr(lc_last_error(), "fewer than max_rbfs"),
          "fewer samples than RBFs: %s", lc_last_error());
    float bw = -1.0f, c[3] = {0, 0, 0}, w = 1;
    lc_rbf_desc rd = {.count = 1, .centres = c, .widths = &bw, .weights = &w};
    char path[512];
    snprintf(path, sizeof path, "%s/never.rbf", dir);
    unlink(path);
    CHECK(lc_rbf_write(dev, path, &rd, LC_RBF_FILE_BINARY) == LC_ERROR_INVALID_ARGUMENT && access(path, F_OK) != 0,
          "a negative width is not written: %s", lc_last_error());
    lc_samples_destroy(s);
}

int main(int argc, char **argv)
{
    if (argc > 1) dir = argv[1];
    lc_device *dev = NULL;
    if (lc_device_create(NULL, &dev) != LC_OK) return 1;
    readers(dev);
    if (!have_lapacke()) {
        float p[3] = {0, 0, 0}, v = 1;
        lc_samples *s = NULL;
        lc_rbf_encoded *set = NULL;
        lc_samples_create(dev, &(lc_samples_desc){1, p, &v, NULL}, &s);
        CHECK(lc_rbf_encode(dev, s, NULL, &set, NULL) == LC_ERROR_UNSUPPORTED && strstr(lc_last_error(), "liblapacke-dev"),
              "without LAPACKE: %s", lc_last_error());
        lc_samples_destroy(s);
    } else {
        bad_requests(dev);
        sum_of_gaussians(dev);
    }
    lc_device_destroy(dev);
    return check_summary("test_encode");
}
