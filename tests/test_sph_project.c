/* Projections (lc_particles_project, issue 27) against references written
 * from the formulas of SPEC.md "SPH kernels and projections", never from the
 * library's tables:
 * - the M4 column in closed form (antiderivatives of (b^2 + t^2)^{n/2}):
 *   F(0) = 3 / (2 pi h^2), F(b = h) = 0.1110360610 / h^2 (h = H / 2), and the
 *   Wendland C2 F(0) = 7 / (4 pi h^2) (h = H / 2), through centre sampling of
 *   single particles;
 * - exact pixel averages of single particles of every kernel for H / pixel
 *   from 0.01 to 100 against nested Gauss-Legendre quadrature of the 3-D
 *   kernel formulas, split at every radius where the integrand is not smooth,
 *   to 1e-6 of the particle's largest pixel (the Gaussian: its cube-cut
 *   separable form, products of erf differences);
 * - mass conservation (sum of pixels x pixel area = sum of m to 1e-6) for
 *   particles inside the image with H / pixel log-uniform in 0.01 .. 100;
 * - a 2 x 2 block average of the 2N map equals the N map;
 * - a Plummer sphere of 200,000 particles against
 *   Sigma(R) = M a^2 / (pi (a^2 + R^2)^2) in annuli, within 4 standard
 *   errors of the particle count in each;
 * - thread-count independence, slabs (mass fraction of a cut particle against
 *   the kernel's own radial integral), weighted maps (a constant A gives A)
 *   and bad descriptors.
 * LANECAST_TEST_BREAK=1 perturbs the reference (a pixel's edge moved by 1e-4)
 * to show the pixel-average comparison bites. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "check.h"
#include "lanecast/lanecast.h"

#include "test_sph_project_ref.h"

/* The M4 column in closed form, h units: F(b) h^2 = (2 / pi) int_0^inf w(sqrt(b^2 + t^2)) dt
 * with w = 1 - 1.5 q^2 + 0.75 q^3 (q < 1), 0.25 (2 - q)^3 (q < 2). */
/* b^n log(t + R), 0 at b = 0 (where the antiderivatives' log terms vanish) */
static double blog(double b, double t, int n) { return b > 0 ? pow(b, n) * log(t + sqrt(b * b + t * t)) : 0.0; }
static double I1(double b, double t) { double R = sqrt(b * b + t * t); return 0.5 * (t * R + blog(b, t, 2)); }
static double I3(double b, double t)
{
    double R = sqrt(b * b + t * t);
    return t * (2 * t * t + 5 * b * b) * R / 8 + 3.0 / 8 * blog(b, t, 4);
}
static double I2(double b, double t) { return b * b * t + t * t * t / 3; }
static double m4_closed(double b)
{
    if (b >= 2) return 0;
    double s = 0, t2 = sqrt(4 - b * b), t1 = b < 1 ? sqrt(1 - b * b) : 0;
    if (b < 1) s += t1 - 1.5 * I2(b, t1) + 0.75 * (I3(b, t1) - I3(b, 0));
    /* 0.25 (8 - 12 R + 6 R^2 - R^3) from t1 to t2 */
    s += 0.25 * (8 * (t2 - t1) - 12 * (I1(b, t2) - I1(b, t1)) + 6 * (I2(b, t2) - I2(b, t1)) - (I3(b, t2) - I3(b, t1)));
    return 2 / M_PI * s;
}

/* ---------------------------------------------------------------- helpers */

static lc_device *dev;
static int threads_env = 2;

static lc_volume *make_set(size_t n, const float *xyz, const float *r, const float *m, lc_kernel k)
{
    lc_particles_desc d = {.count = n, .positions = xyz, .radii = r, .values = m, .params = {.kernel = k}};
    lc_volume *v = NULL;
    if (lc_particles_create(dev, &d, &v) != LC_OK) printf("create: %s\n", lc_last_error());
    return v;
}

static void test_closed_forms(void)
{
    /* the reference quadrature itself against the M4 closed form (h units: F_h(b_h) = F_H(b_h / 2) / 4, H = 2 h) */
    double worst = 0;
    for (double bh = 0; bh < 2.0; bh += 0.0137) worst = fmax(worst, fabs(column_ref(LC_KERNEL_M4, bh / 2) / 4 - m4_closed(bh)));
    CHECK(worst < 1e-11, "M4 column: quadrature against the closed form, largest difference %.2e", worst);
    CHECK(fabs(m4_closed(0) - 3 / (2 * M_PI)) < 1e-14, "M4 closed form F(0) = %.12f = 3 / (2 pi)", m4_closed(0));
    CHECK(fabs(m4_closed(1) - 0.1110360610) < 1e-10, "M4 closed form F(h) = %.10f", m4_closed(1));
    /* the library, centre sampling of one particle of H = 2 (h = 1) at a pixel centre: pixels hold m F(b) / H^2 */
    int N = 41;
    float xyz[3] = {0, 0, 0}, r = 2.0f, m = 1.0f;
    for (int kk = 0; kk < 2; kk++) {
        lc_kernel k = kk ? LC_KERNEL_WENDLAND_C2 : LC_KERNEL_M4;
        lc_volume *v = make_set(1, xyz, &r, &m, k);
        lc_project_desc d = view(N, 2.05, LC_PROJECT_CENTRE); /* pixel 0.1, centre pixel 20 */
        float *map = calloc((size_t)N * N, sizeof *map);
        lc_status s = lc_particles_project(dev, v, &d, map, NULL);
        CHECK(s == LC_OK, "%s centre projection: %s", lc_kernel_name(k), s ? lc_last_error() : "ok");
        double h = 1.0, f0 = map[20 * N + 20];
        if (k == LC_KERNEL_M4) {
            CHECK(fabs(f0 - 3 / (2 * M_PI * h * h)) < 3e-6 * f0, "M4 F(0) = %.8f, 3/(2 pi h^2) = %.8f", f0, 3 / (2 * M_PI));
            double f1 = map[20 * N + 30]; /* b = 1.0 = h */
            CHECK(fabs(f1 - 0.1110360610) < 3e-6 * f0, "M4 F(h) = %.8f, expected 0.1110360610", f1);
            double worst2 = 0;
            for (int i = 0; i < N; i++) {
                double b = abs(i - 20) * 0.1; /* along the middle row, h units */
                worst2 = fmax(worst2, fabs(map[20 * N + i] - m4_closed(b) / (h * h)));
            }
            CHECK(worst2 < 3e-6 * f0, "M4 column along a row against the closed form: largest difference %.2e of F(0)",
                  worst2 / f0);
        } else {
            CHECK(fabs(f0 - 7 / (4 * M_PI * h * h)) < 3e-6 * f0, "Wendland C2 F(0) = %.8f, 7/(4 pi h^2) = %.8f", f0,
                  7 / (4 * M_PI));
        }
        free(map);
        lc_volume_destroy(v);
    }
}

/* Devices of every target this machine runs (targets[0] is the default device). */
static lc_device *tdev[LC_TARGET_COUNT];
static int ntdev;

static void test_pixel_averages(void)
{
    /* 5, 12 and 28 lie below the largest supports of the lower ranks (host/sph/column.c levels: M4 20 terms
       to 12.2 pixels, 24 to 29.3) */
    const double ratios[] = {0.01, 0.1, 0.37, 1.0, 3.3, 5.0, 10.0, 12.0, 28.0, 100.0};
    int brk = getenv("LANECAST_TEST_BREAK") && atoi(getenv("LANECAST_TEST_BREAK")) == 1;
    for (size_t kk = 0; kk < sizeof all_kernels / sizeof all_kernels[0]; kk++) {
        lc_kernel k = all_kernels[kk];
        double worst_all[LC_TARGET_COUNT] = {0};
        for (size_t ri = 0; ri < sizeof ratios / sizeof ratios[0]; ri++) {
            double ratio = ratios[ri]; /* support S / pixel */
            double S = 1.0, pix = S / ratio;
            /* the image: enough pixels to hold the support, at least 4 */
            int N = (int)ceil(2 * ratio) + 4;
            double half = 0.5 * N * pix;
            /* an offset inside the centre pixel that is not symmetric */
            float xyz[3] = {(float)(0.2137 * pix), (float)(-0.3311 * pix), 0.0f};
            if (ratio < 0.05) xyz[0] = (float)(0.5 * pix - 0.003 * pix), xyz[1] = (float)(0.5 * pix - 0.004 * pix); /* across a corner */
            float r = (float)(k == LC_KERNEL_GAUSSIAN ? S / 5 : S), m = 1.0f;
            /* pixels to check: all for small footprints, a sample (every 15th row and column, and the centre row) for large */
            double *ref = malloc(sizeof(double) * N * N), peak = 0;
            int step = N > 60 ? 15 : 1;
            for (int j = 0; j < N; j++)
                for (int i = 0; i < N; i++) {
                    ref[j * N + i] = NAN;
                    if (step > 1 && (j % step) && j != N / 2) continue;
                    if (step > 1 && (i % step) && i != N / 2 + 1) continue;
                    double x0 = -half + i * pix, y1 = half - j * pix; /* row 0 at the top */
                    double u0 = (x0 - xyz[0]) / S, u1 = (x0 + pix - xyz[0]) / S;
                    double v0 = (y1 - pix - xyz[1]) / S, v1 = (y1 - xyz[1]) / S;
                    if (brk && i == N / 2 && j == N / 2) u0 += 1e-4 / S * pix;
                    ref[j * N + i] = m * pixel_ref(k, u0, u1, v0, v1) / (pix * pix);
                    peak = fmax(peak, ref[j * N + i]);
                }
            for (int t = 0; t < ntdev; t++) {
                dev = tdev[t];
                const char *tn = dev_target_name(dev);
                lc_volume *v = make_set(1, xyz, &r, &m, k);
                lc_project_desc d = view(N, half, LC_PROJECT_EXACT);
                float *map = calloc((size_t)N * N, sizeof *map);
                lc_status s = lc_particles_project(dev, v, &d, map, NULL);
                if (s != LC_OK) printf("project: %s\n", lc_last_error());
                double worst = 0;
                for (int i = 0; i < N * N; i++)
                    if (!isnan(ref[i])) worst = fmax(worst, fabs(map[i] - ref[i]));
                worst /= peak;
                worst_all[t] = fmax(worst_all[t], worst);
                CHECK_QUIET(worst <= 1e-6 && s == LC_OK, "%s %s H/pixel %g: largest difference %.2e of the peak pixel", tn,
                            lc_kernel_name(k), ratio, worst);
                /* mass of a particle inside the image */
                if (ratio >= 0.05) {
                    double mass = map_mass(map, N, pix);
                    CHECK_QUIET(fabs(mass - 1) < 1e-6, "%s %s H/pixel %g: mass %.9f", tn, lc_kernel_name(k), ratio, mass);
                }
                free(map);
                lc_volume_destroy(v);
            }
            free(ref);
        }
        for (int t = 0; t < ntdev; t++)
            CHECK(worst_all[t] <= 1e-6, "%s %s: pixel averages for H/pixel 0.01..100 against 2-D quadrature: largest "
                  "difference %.2e of the peak pixel", dev_target_name(tdev[t]), lc_kernel_name(k),
                  worst_all[t]);
    }
    dev = tdev[0];
}

static void test_mass_blocks(void)
{
    enum { NP = 3000, N = 128 };
    static float xyz[3 * NP], r[NP], m[NP];
    unsigned seed = 7;
    double half = 10, pix = 2 * half / N, total = 0;
    for (int i = 0; i < NP; i++) {
        double H = pix * pow(10, -2 + 4 * urand(&seed) * 0.82); /* 0.01 .. ~19 pixels: inside a 128-pixel image */
        double lim = half - H - 1e-3;
        xyz[3 * i] = (float)((2 * urand(&seed) - 1) * lim), xyz[3 * i + 1] = (float)((2 * urand(&seed) - 1) * lim);
        xyz[3 * i + 2] = (float)(2 * urand(&seed) - 1);
        r[i] = (float)H, m[i] = (float)(0.5 + urand(&seed));
        total += m[i];
    }
    /* one particle of H / pixel = 100 in the middle of a larger image as well */
    for (size_t kk = 0; kk < sizeof all_kernels / sizeof all_kernels[0]; kk++) {
        lc_kernel k = all_kernels[kk];
        if (k == LC_KERNEL_GAUSSIAN)
            for (int i = 0; i < NP; i++) r[i] /= 5; /* support 5 r */
        lc_volume *v = make_set(NP, xyz, r, m, k);
        float *a = calloc(N * N, sizeof *a), *b = calloc(4 * N * N, sizeof *b);
        lc_project_desc d = view(N, half, LC_PROJECT_EXACT), d2 = view(2 * N, half, LC_PROJECT_EXACT);
        lc_project_info info;
        lc_status s1 = lc_particles_project(dev, v, &d, a, &info), s2 = lc_particles_project(dev, v, &d2, b, NULL);
        double mass = map_mass(a, N, pix);
        CHECK(s1 == LC_OK && s2 == LC_OK && fabs(mass - total) < 1e-6 * total && fabs(info.mass - total) < 1e-6 * total,
              "%s: mass of %d particles (H/pixel 0.01..19) %.9g, expected %.9g (info %.9g)", lc_kernel_name(k), NP, mass,
              total, info.mass);
        double worst = 0, peak = 0;
        for (int j = 0; j < N; j++)
            for (int i = 0; i < N; i++) {
                double avg = 0.25 * ((double)b[(2 * j) * 2 * N + 2 * i] + b[(2 * j) * 2 * N + 2 * i + 1] +
                                     b[(2 * j + 1) * 2 * N + 2 * i] + b[(2 * j + 1) * 2 * N + 2 * i + 1]);
                worst = fmax(worst, fabs(avg - a[j * N + i]));
                peak = fmax(peak, a[j * N + i]);
            }
        CHECK(worst < 1e-6 * peak, "%s: 2x2 block average of the %d^2 map = the %d^2 map: largest difference %.2e of the peak",
              lc_kernel_name(k), 2 * N, N, worst / peak);
        if (k == LC_KERNEL_M4) { /* thread-count independence */
            lc_device *d1 = NULL;
            lc_device_desc dd = {.threads = 1};
            lc_device_create(&dd, &d1);
            float *c = calloc(N * N, sizeof *c);
            lc_particles_project(d1, v, &d, c, NULL);
            CHECK(!memcmp(a, c, sizeof(float) * N * N), "M4: the map of 1 thread is bit for bit the map of %d", threads_env);
            free(c);
            lc_device_destroy(d1);
        }
        if (k == LC_KERNEL_GAUSSIAN)
            for (int i = 0; i < NP; i++) r[i] *= 5;
        free(a), free(b);
        lc_volume_destroy(v);
    }
}

/* Plummer sphere: positions from the inverse of M(r) = M r^3 / (r^2 + a^2)^{3/2}, H = the radius of a sphere
 * holding 64 particles at the analytic density. */
static void test_plummer(void)
{
    enum { NP = 200000, N = 200, NBIN = 10 };
    float *xyz = malloc(sizeof(float) * 3 * NP), *r = malloc(sizeof(float) * NP), *m = malloc(sizeof(float) * NP);
    unsigned seed = 12345;
    double a = 1, M = 1;
    for (int i = 0; i < NP; i++) {
        double X = urand(&seed) * 0.999999 + 1e-7, rad = a / sqrt(pow(X, -2.0 / 3) - 1);
        double cz = 2 * urand(&seed) - 1, ph = 2 * M_PI * urand(&seed), sz = sqrt(1 - cz * cz);
        xyz[3 * i] = (float)(rad * sz * cos(ph)), xyz[3 * i + 1] = (float)(rad * sz * sin(ph)), xyz[3 * i + 2] = (float)(rad * cz);
        double rho = 3 * M / (4 * M_PI * a * a * a) * pow(1 + rad * rad / (a * a), -2.5);
        r[i] = (float)cbrt(64.0 * (M / NP) / (4.0 / 3 * M_PI * rho));
        m[i] = (float)(M / NP);
    }
    lc_volume *v = make_set(NP, xyz, r, m, LC_KERNEL_M4);
    double half = 3;
    lc_project_desc d = view(N, half, LC_PROJECT_EXACT);
    float *map = calloc(N * N, sizeof *map);
    lc_project_info pinfo;
    lc_status s = lc_particles_project(dev, v, &d, map, &pinfo);
    printf("     projection %.3f s, %llu kernel-pixel evaluations\n", pinfo.seconds, (unsigned long long)pinfo.evaluations);
    double pix = 2 * half / N, sum[NBIN] = {0}, ref[NBIN] = {0};
    int cnt[NBIN] = {0};
    double edges[NBIN + 1];
    for (int b = 0; b <= NBIN; b++) edges[b] = 0.25 + 2.5 * b / NBIN; /* annuli 0.25a .. 2.75a */
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            double x = -half + (i + 0.5) * pix, y = half - (j + 0.5) * pix, R = sqrt(x * x + y * y);
            for (int b = 0; b < NBIN; b++)
                if (R >= edges[b] && R < edges[b + 1]) {
                    sum[b] += map[j * N + i], cnt[b]++;
                    /* the analytic pixel average: the centre value is enough at this smooth scale (2e-5 relative) */
                    ref[b] += M * a * a / (M_PI * pow(a * a + R * R, 2));
                }
        }
    int bad = 0;
    for (int b = 0; b < NBIN; b++) {
        double got = sum[b] / cnt[b], want = ref[b] / cnt[b];
        /* particles in the annulus's cylinder: N M_cyl / M; the relative standard error 1 / sqrt of it */
        double R0 = edges[b], R1 = edges[b + 1];
        double mcyl = a * a / (a * a + R0 * R0) - a * a / (a * a + R1 * R1); /* projected mass fraction of the annulus */
        double se = 1 / sqrt(mcyl * NP);
        double tol = 4 * se + 0.003; /* + the kernel's smoothing of the profile's curvature (H ~ 0.1a at the centre) */
        printf("     annulus %.2f..%.2f a: %.6f against %.6f (%.2f%%, tolerance %.2f%%)\n", R0, R1, got, want,
               100 * (got / want - 1), 100 * tol);
        bad += !(fabs(got / want - 1) < tol);
    }
    CHECK(s == LC_OK && bad == 0, "Plummer sphere, %d particles: Sigma(R) in %d annuli within 4 standard errors", NP, NBIN);
    free(map), free(xyz), free(r), free(m);
    lc_volume_destroy(v);
}

static void test_slab_weight_errors(void)
{
    /* one M4 particle of H = 1 at z = 0.3, slab of depth 1 around z = 0: heights -0.8 .. 0.2 of the kernel */
    float xyz[6] = {0, 0, 0.3f, 0.5f, 0, -0.2f}, r[2] = {1, 1}, m[2] = {1, 1};
    lc_volume *v = make_set(1, xyz, r, m, LC_KERNEL_M4);
    enum { N = 64 };
    float *map = calloc(N * N, sizeof *map);
    lc_project_desc d = view(N, 1.5, LC_PROJECT_EXACT);
    d.depth = 1.0f;
    lc_project_info info;
    lc_status s = lc_particles_project(dev, v, &d, map, &info);
    /* the mass fraction with height in [-0.8, 0.2]: int dz int 2 pi rho w(sqrt(rho^2 + z^2)) drho, by quadrature here */
    double frac = 0;
    for (int iz = 0; iz < 2000; iz++) {
        double z = -0.8 + (iz + 0.5) * 1.0 / 2000, plane = 0;
        for (int ir = 0; ir < 2000; ir++) {
            double rr = (ir + 0.5) / 2000.0;
            plane += 2 * M_PI * rr * shape(LC_KERNEL_M4, sqrt(rr * rr + z * z)) / 2000.0;
        }
        frac += plane / 2000.0;
    }
    CHECK(s == LC_OK && fabs(info.mass - frac) < 2e-5, "slab: a cut M4 particle keeps %.6f of its mass, expected %.6f",
          info.mass, frac);
    lc_volume_destroy(v);
    /* weighted: A = 3 everywhere gives 3 wherever a particle reaches */
    float k3[2] = {3, 3}, w[2] = {1, 5};
    lc_volume *a = make_set(2, xyz, r, k3, LC_KERNEL_WENDLAND_C2), *wv = make_set(2, xyz, r, w, LC_KERNEL_WENDLAND_C2);
    d.depth = 0;
    d.weight = wv;
    s = lc_particles_project(dev, a, &d, map, NULL);
    double worst = 0;
    int reached = 0;
    for (int i = 0; i < N * N; i++)
        if (map[i] != 0) worst = fmax(worst, fabs(map[i] - 3)), reached++;
    CHECK(s == LC_OK && reached > 100 && worst < 1e-5, "weighted: constant A = 3 gives 3 at %d pixels (largest difference %.1e)",
          reached, worst);
    /* a weight set of other particles is refused */
    float xyz2[6] = {0, 0, 0.3f, 0.5f, 0, -0.25f};
    lc_volume *other = make_set(2, xyz2, r, w, LC_KERNEL_WENDLAND_C2);
    d.weight = other;
    s = lc_particles_project(dev, a, &d, map, NULL);
    CHECK(s == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "not the same particles"),
          "weight of other particles refused: %s", lc_last_error());
    d.weight = NULL;
    d.camera.projection = LC_PERSPECTIVE;
    s = lc_particles_project(dev, a, &d, map, NULL);
    CHECK(s == LC_ERROR_UNSUPPORTED && strstr(lc_last_error(), "perspective"), "perspective refused: %s", lc_last_error());
    d = view(N, 1.5, LC_PROJECT_EXACT);
    d.width = 0;
    CHECK(lc_particles_project(dev, a, &d, map, NULL) == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "size"),
          "size 0 refused: %s", lc_last_error());
    d = view(N, 1.5, (lc_project_sample)7);
    CHECK(lc_particles_project(dev, a, &d, map, NULL) == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "sample"),
          "sample 7 refused: %s", lc_last_error());
    d = view(N, 1.5, LC_PROJECT_EXACT);
    d.depth = -1;
    CHECK(lc_particles_project(dev, a, &d, map, NULL) == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "depth"),
          "depth -1 refused: %s", lc_last_error());
    /* a particle 2e6 pixels across, cut by a slab: no endless loop over its footprint, a uniform map */
    float big = 1e5f, one = 1.0f, at0[3] = {0, 0, 0.5f};
    lc_volume *huge = make_set(1, at0, &big, &one, LC_KERNEL_M4);
    d = view(N, 1.5, LC_PROJECT_EXACT);
    d.depth = 1.0f;
    s = lc_particles_project(dev, huge, &d, map, NULL);
    CHECK(s == LC_OK && map[0] > 0 && fabs(map[0] / map[N * N / 2 + N / 2] - 1) < 1e-3,
          "a particle of H / pixel = 2e6 cut by a slab: %g at the corner, %g at the centre", map[0], map[N * N / 2 + N / 2]);
    lc_volume_destroy(huge);
    free(map);
    lc_volume_destroy(a), lc_volume_destroy(wv), lc_volume_destroy(other);
}

static int cancel_now(void *u) { return (void)u, 1; }

int main(void)
{
    gl_init();
    lc_device_desc dd = {.threads = threads_env};
    if (lc_device_create(&dd, &dev) != LC_OK) return printf("device: %s\n", lc_last_error()), 1;
    ntdev = open_targets(dev, threads_env, tdev);
    void (*tests[])(void) = {test_closed_forms, test_pixel_averages, test_mass_blocks, test_plummer,
                             test_slab_weight_errors};
    for (size_t t = 0; t < sizeof tests / sizeof tests[0]; t++) {
        struct timespec a, b;
        clock_gettime(CLOCK_MONOTONIC, &a);
        tests[t]();
        clock_gettime(CLOCK_MONOTONIC, &b);
        printf("     (part %zu: %.2f s)\n", t + 1, (double)(b.tv_sec - a.tv_sec) + 1e-9 * (double)(b.tv_nsec - a.tv_nsec));
    }
    {
        float xyz[3] = {0, 0, 0}, r = 1, m = 1, map[16];
        lc_volume *v = make_set(1, xyz, &r, &m, LC_KERNEL_M4);
        lc_project_desc d = view(4, 2, LC_PROJECT_EXACT);
        d.cancel = cancel_now;
        CHECK(lc_particles_project(dev, v, &d, map, NULL) == LC_CANCELLED, "cancel: %s", lc_last_error());
        lc_volume_destroy(v);
    }
    for (int t = 1; t < ntdev; t++) lc_device_destroy(tdev[t]);
    lc_device_destroy(dev);
    return check_summary("test_sph_project");
}
