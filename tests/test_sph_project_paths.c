/* The projection kernel's paths (kernels/sph_project.c) on every target this
 * machine runs, against the quadrature reference of tests/test_sph_project_ref.h
 * (written from the formulas, not from the library's tables):
 * - small particles (support 0.02 to 0.9 pixels) at random offsets: footprints
 *   of one pixel, across one column edge, one row edge, a pixel corner (the
 *   short path) and 2 x 3, 3 x 3 (the smallest matrix products), every pixel
 *   to 1e-6 of the particle's largest and the mass to 1e-6, each footprint
 *   class met for every kernel;
 * - the maps of every target bit for bit the scalar target's (plain, weighted),
 *   and 1 thread bit for bit 2, on 3000 particles of 0.01 to 19 pixels. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "lanecast/lanecast.h"
#include "test_sph_project_ref.h"

static lc_device *tdev[LC_TARGET_COUNT];
static int ntdev;

static lc_volume *make_on(lc_device *d, size_t n, const float *xyz, const float *r, const float *m, lc_kernel k)
{
    lc_particles_desc pd = {.count = n, .positions = xyz, .radii = r, .values = m, .params = {.kernel = k}};
    lc_volume *v = NULL;
    if (lc_particles_create(d, &pd, &v) != LC_OK) printf("create: %s\n", lc_last_error());
    return v;
}

/* classes: 0 one pixel, 1 across a column edge, 2 across a row edge, 3 across a corner, 4 larger */
static int footprint(double X, double Y, double S)
{
    int nx = (int)(floor(X + S) - floor(X - S)) + 1, ny = (int)(floor(Y + S) - floor(Y - S)) + 1;
    if (nx == 1 && ny == 1) return 0;
    if (nx == 2 && ny == 1) return 1;
    if (nx == 1 && ny == 2) return 2;
    if (nx == 2 && ny == 2) return 3;
    return 4;
}

static void test_small(void)
{
    enum { N = 6, NP = 20 };
    double pix = 1.0, half = 0.5 * N * pix;
    for (size_t kk = 0; kk < sizeof all_kernels / sizeof all_kernels[0]; kk++) {
        lc_kernel k = all_kernels[kk];
        unsigned seed = 99 + (unsigned)kk;
        int seen[5] = {0};
        double worst[LC_TARGET_COUNT] = {0}, wmass[LC_TARGET_COUNT] = {0};
        for (int p = 0; p < NP; p++) {
            double S = pix * pow(10, -1.7 + 1.65 * urand(&seed)); /* 0.02 .. 0.9 pixels */
            /* positions in image pixel units (x right from the left edge, y down from the top) inside the middle 2 x 2 pixels */
            double X = 2 + 2 * urand(&seed), Y = 2 + 2 * urand(&seed);
            if (p % 4 == 1) X = 3 + 0.5 * S * (2 * urand(&seed) - 1); /* near a column edge */
            if (p % 4 == 2) Y = 3 + 0.5 * S * (2 * urand(&seed) - 1); /* near a row edge */
            if (p % 4 == 3) X = 3 + 0.6 * S * (2 * urand(&seed) - 1), Y = 2 + 0.6 * S * (2 * urand(&seed) - 1);
            if (p == NP - 2) S = 0.7, X = 3.2, Y = 3.6; /* 2 x 3 pixels */
            if (p == NP - 1) S = 0.85, X = 3.5, Y = 3.45; /* 3 x 3 */
            float xyz[3] = {(float)(-half + X * pix), (float)(half - Y * pix), 0.0f};
            X = (xyz[0] + half) / pix, Y = (half - xyz[1]) / pix; /* as float positions */
            seen[footprint(X, Y, S)]++;
            double ref[N * N], peak = 0;
            for (int j = 0; j < N; j++)
                for (int i = 0; i < N; i++) {
                    double u0 = (i - X) / S, u1 = (i + 1 - X) / S, v0 = (j - Y) / S, v1 = (j + 1 - Y) / S;
                    ref[j * N + i] = pixel_ref(k, u0, u1, -v1, -v0) / (pix * pix);
                    peak = fmax(peak, ref[j * N + i]);
                }
            float r = (float)(k == LC_KERNEL_GAUSSIAN ? S / 5 : S), m = 1.0f;
            for (int t = 0; t < ntdev; t++) {
                lc_volume *v = make_on(tdev[t], 1, xyz, &r, &m, k);
                lc_project_desc d = view(N, half, LC_PROJECT_EXACT);
                float map[N * N];
                lc_status s = lc_particles_project(tdev[t], v, &d, map, NULL);
                double w = s == LC_OK ? 0 : INFINITY;
                for (int i = 0; i < N * N; i++) w = fmax(w, fabs(map[i] - ref[i]));
                worst[t] = fmax(worst[t], w / peak);
                wmass[t] = fmax(wmass[t], fabs(map_mass(map, N, pix) - 1));
                lc_volume_destroy(v);
            }
        }
        for (int t = 0; t < ntdev; t++)
            CHECK(worst[t] <= 1e-6 && wmass[t] <= 1e-6,
                  "%s %s: %d particles of 0.02..0.9 pixels against 2-D quadrature: largest difference %.2e of the peak "
                  "pixel, mass off by %.1e", dev_target_name(tdev[t]), lc_kernel_name(k), NP, worst[t], wmass[t]);
        CHECK(seen[0] && seen[1] && seen[2] && seen[3] && seen[4],
              "%s: footprints met: %d in one pixel, %d across a column edge, %d a row edge, %d a corner, %d larger",
              lc_kernel_name(k), seen[0], seen[1], seen[2], seen[3], seen[4]);
    }
}

static void test_identical(void)
{
    enum { NP = 3000, N = 160 };
    static float xyz[3 * NP], r[NP], m[NP], w[NP];
    unsigned seed = 5;
    double half = 10, pix = 2 * half / N;
    for (int i = 0; i < NP; i++) {
        double H = pix * pow(10, -2 + 4 * urand(&seed) * 0.82); /* 0.01 .. ~19 pixels */
        xyz[3 * i] = (float)((2 * urand(&seed) - 1) * half), xyz[3 * i + 1] = (float)((2 * urand(&seed) - 1) * half);
        xyz[3 * i + 2] = (float)(2 * urand(&seed) - 1);
        r[i] = (float)H, m[i] = (float)(0.5 + urand(&seed)), w[i] = (float)(0.1 + urand(&seed));
    }
    int scalar = -1;
    for (int t = 0; t < ntdev; t++) {
        lc_target tt;
        lc_device_target(tdev[t], &tt);
        if (tt == LC_TARGET_SCALAR) scalar = t;
    }
    CHECK(scalar >= 0, "the scalar target runs here");
    if (scalar < 0) return;
    const lc_kernel ks[] = {LC_KERNEL_M4, LC_KERNEL_WENDLAND_C2, LC_KERNEL_GAUSSIAN};
    for (size_t kk = 0; kk < 3; kk++) {
        float *ref = calloc(2 * N * N, sizeof *ref), *map = calloc(2 * N * N, sizeof *map);
        for (int weighted = 0; weighted < 2; weighted++) {
            float *want = ref + weighted * N * N;
            for (int t = -1; t < ntdev; t++) { /* the scalar one first */
                lc_device *d = tdev[t < 0 ? scalar : t];
                if (t == scalar) continue;
                lc_volume *v = make_on(d, NP, xyz, r, m, ks[kk]), *wv = weighted ? make_on(d, NP, xyz, r, w, ks[kk]) : NULL;
                lc_project_desc pd = view(N, half, LC_PROJECT_EXACT);
                pd.weight = wv;
                lc_status s = lc_particles_project(d, v, &pd, t < 0 ? want : map, NULL);
                CHECK_QUIET(s == LC_OK, "%s: %s", dev_target_name(d), lc_last_error());
                if (t >= 0) {
                    int same = !memcmp(map, want, sizeof(float) * N * N);
                    double diff = 0;
                    for (int i = 0; i < N * N; i++) diff = fmax(diff, fabs(map[i] - want[i]));
                    CHECK(same, "%s %s%s: the map is bit for bit the scalar target's (largest difference %.2e)",
                          dev_target_name(d), lc_kernel_name(ks[kk]), weighted ? " weighted" : "", diff);
                }
                lc_volume_destroy(v), lc_volume_destroy(wv);
            }
        }
        /* one thread against two on the default target */
        lc_device *d1 = NULL;
        lc_device_desc dd = {.threads = 1};
        lc_device_create(&dd, &d1);
        lc_volume *v = make_on(d1, NP, xyz, r, m, ks[kk]), *wv = make_on(d1, NP, xyz, r, w, ks[kk]);
        lc_project_desc pd = view(N, half, LC_PROJECT_EXACT);
        pd.weight = wv;
        lc_status s = lc_particles_project(d1, v, &pd, map, NULL);
        lc_volume *v2 = make_on(tdev[0], NP, xyz, r, m, ks[kk]), *wv2 = make_on(tdev[0], NP, xyz, r, w, ks[kk]);
        pd.weight = wv2;
        lc_status s2 = lc_particles_project(tdev[0], v2, &pd, map + N * N, NULL);
        CHECK(s == LC_OK && s2 == LC_OK && !memcmp(map, map + N * N, sizeof(float) * N * N),
              "%s weighted: 1 thread bit for bit 2 threads (%s)", lc_kernel_name(ks[kk]), dev_target_name(tdev[0]));
        lc_volume_destroy(v), lc_volume_destroy(wv), lc_volume_destroy(v2), lc_volume_destroy(wv2);
        lc_device_destroy(d1);
        free(ref), free(map);
    }
}

int main(void)
{
    gl_init();
    lc_device *def = NULL;
    lc_device_desc dd = {.threads = 2};
    if (lc_device_create(&dd, &def) != LC_OK) return printf("device: %s\n", lc_last_error()), 1;
    ntdev = open_targets(def, 2, tdev);
    test_small();
    test_identical();
    for (int t = 0; t < ntdev; t++) lc_device_destroy(tdev[t]);
    return check_summary("test_sph_project_paths");
}
