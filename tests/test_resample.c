/* lc_particles_resample (issue 28) against the double-precision field of
 * SPEC.md "Fields" and "SPH kernels and projections" (tests/ref/ref_fields.c,
 * written from the formulas, no lanecast code), on every target this CPU
 * runs: the Gaussian and three SPH kernels, values and fields, a box that
 * clips particles (centres outside it still add what reaches inside), the
 * default box (the set's bounds), an empty grid, 1-node axes; the maximum
 * relative error must be at most 1e-5 where the field exceeds 1e-3 of its
 * maximum (nodes within a relative 1e-5 of a Gaussian's cut-off, where float
 * and double may disagree on the term's inclusion, are skipped and counted).
 * Then: bit-identical values for 1, 2 and 3 threads, sizes refused over the
 * memory limit before anything is written, bad descriptors, cancellation.
 * LANECAST_TEST_BREAK=1 perturbs the reference (sigma 1e-4 larger, a node's
 * position moved by 1e-3 of the spacing) to show the comparison bites. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "lanecast/lanecast.h"
#include "ref/ref_fields.h"

#define NP 400
#define NF 2

typedef struct scene {
    float pos[3 * NP], rad[NP], val[NP];
    uint8_t field[NP];
    double dpos[3 * NP], drad[NP], dval[NP];
    int dfield[NP];
} scene;

static scene sc;
static int broken;

static uint64_t rng = 0x243f6a8885a308d3ull;
static double urand(void)
{
    rng ^= rng >> 12, rng ^= rng << 25, rng ^= rng >> 27;
    return (double)((rng * 0x2545f4914f6cdd1dull) >> 11) / 9007199254740992.0;
}

static void make_scene(void)
{
    for (int i = 0; i < NP; i++) {
        for (int a = 0; a < 3; a++) sc.pos[3 * i + a] = (float)(-4.0 + 8.0 * urand());
        sc.rad[i] = (float)(0.25 + 0.6 * urand());
        sc.val[i] = (float)(0.2 + 1.8 * urand());
        sc.field[i] = (uint8_t)(i % NF);
    }
    for (int i = 0; i < 3 * NP; i++) sc.dpos[i] = sc.pos[i];
    for (int i = 0; i < NP; i++) sc.drad[i] = sc.rad[i], sc.dval[i] = sc.val[i], sc.dfield[i] = sc.field[i];
}

static lc_volume *make_set(lc_device *dev, lc_kernel kernel, float sigma, float kappa)
{
    lc_volume *v = NULL;
    lc_particles_desc d = {.count = NP, .positions = sc.pos, .radii = sc.rad, .values = sc.val, .fields = sc.field,
                           .nfields = NF, .params = {.sigma = sigma, .kappa = kappa, .kernel = kernel}};
    if (lc_particles_create(dev, &d, &v) != LC_OK) printf("lc_particles_create: %s\n", lc_last_error());
    return v;
}

typedef struct kcase {
    lc_kernel kernel;
    ref_kernel rk;
    float sigma, kappa;
    const char *name;
} kcase;

static const kcase kcases[] = {
    {LC_KERNEL_GAUSSIAN, REF_KERNEL_GAUSSIAN, 0.0f, 0.0f, "gaussian"},
    {LC_KERNEL_GAUSSIAN, REF_KERNEL_GAUSSIAN, 2.7f, 0.6f, "gaussian sigma 2.7 kappa 0.6"},
    {LC_KERNEL_M4, REF_KERNEL_M4, 0.0f, 0.0f, "m4"},
    {LC_KERNEL_WENDLAND_C2, REF_KERNEL_C2, 0.0f, 1.3f, "wendland-c2 kappa 1.3"},
    {LC_KERNEL_M6, REF_KERNEL_M6, 0.0f, 0.0f, "m6"},
};

typedef struct gcase {
    int size[3];
    lc_box3 box; /* all zero: the set's bounds */
    int field;
    const char *name;
} gcase;

static gcase gcases[] = {
    {{31, 27, 23}, {{-2.0f, -1.5f, -2.0f}, {2.0f, 2.5f, 1.0f}}, -1, "box clipping particles, every field"},
    {{40, 41, 37}, {{0, 0, 0}, {0, 0, 0}}, 0, "the set's bounds, field 0"},
    {{33, 35, 34}, {{-6.0f, -6.0f, -6.0f}, {3.0f, 6.0f, 2.5f}}, 1, "box beyond the bounds on some sides, field 1"},
    {{1, 1, 1}, {{0, 0, 0}, {0, 0, 0}}, -1, "one node at the box's centre (near particle 0)"},
    {{1, 9, 1}, {{0, 0, 0}, {0, 0, 0}}, -1, "a line of nodes along y through particle 1 (flat box in x and z)"},
    {{70, 1, 1}, {{-4.0f, 0.5f, 0.0f}, {4.0f, 0.5f, 0.0f}}, 0, "a line of 70 nodes along x (several bricks)"},
};

/* The reference at every node: value, and whether a Gaussian term lies at
 * its cut-off there. */
static void reference(const kcase *kc, const gcase *gc, const lc_resample_info *info, double *want, uint8_t *near)
{
    ref_particle_set ps = {.count = NP, .pos = sc.dpos, .radius = sc.drad, .value = sc.dval, .field = sc.dfield,
                           .nfields = NF, .sigma = kc->sigma, .kappa = kc->kappa};
    if (broken && kc->rk == REF_KERNEL_GAUSSIAN) ps.sigma = (kc->sigma ? kc->sigma : 2.0) * 1.0001;
    ref_sph_set ss = {.ps = ps, .kernel = kc->rk};
    const double o[3] = {info->origin.x, info->origin.y, info->origin.z};
    const double s[3] = {info->spacing.x, info->spacing.y, info->spacing.z};
    size_t n = 0;
    for (int k = 0; k < gc->size[2]; k++)
        for (int j = 0; j < gc->size[1]; j++)
            for (int i = 0; i < gc->size[0]; i++, n++) {
                double x[3] = {o[0] + i * s[0], o[1] + j * s[1], o[2] + k * s[2]}, phi[NF];
                if (broken && n == 17) x[0] += 1e-3 * s[0];
                if (kc->rk == REF_KERNEL_GAUSSIAN) ref_particles_eval(&ps, x, phi, NULL);
                else ref_sph_eval(&ss, x, phi, NULL);
                want[n] = gc->field < 0 ? phi[0] + phi[1] : phi[gc->field];
                near[n] = 0;
                if (kc->rk == REF_KERNEL_GAUSSIAN) {
                    double a[NF], ga[NF], p1[NF], p2[NF];
                    int nc = 0;
                    ref_particles_budget(&ps, x, a, ga, p1, p2, &nc);
                    near[n] = (uint8_t)nc;
                }
            }
}

/* The box the desc asks for, as the nodes must lie (independent of the library). */
static void expected_geometry(const gcase *gc, const lc_box3 *bounds, double o[3], double s[3])
{
    const lc_box3 *b = gc->box.lo.x == 0 && gc->box.hi.x == 0 && gc->box.lo.y == 0 && gc->box.hi.y == 0 &&
                               gc->box.lo.z == 0 && gc->box.hi.z == 0
                           ? bounds
                           : &gc->box;
    const float *lo = &b->lo.x, *hi = &b->hi.x;
    for (int a = 0; a < 3; a++) {
        if (gc->size[a] > 1) o[a] = lo[a], s[a] = ((double)hi[a] - lo[a]) / (gc->size[a] - 1);
        else o[a] = 0.5 * ((double)lo[a] + hi[a]), s[a] = hi[a] > lo[a] ? (double)hi[a] - lo[a] : 1.0;
    }
}

static void run_target(lc_target t)
{
    lc_device *dev = NULL;
    if (lc_device_create(&(lc_device_desc){.target = t, .threads = 2}, &dev) != LC_OK) {
        CHECK(0, "%s: lc_device_create: %s", lc_target_name(t), lc_last_error());
        return;
    }
    for (size_t kci = 0; kci < sizeof kcases / sizeof kcases[0]; kci++) {
        const kcase *kc = &kcases[kci];
        lc_volume *v = make_set(dev, kc->kernel, kc->sigma, kc->kappa);
        lc_volume_info vi;
        if (!v || lc_volume_get_info(v, &vi) != LC_OK) {
            CHECK(0, "%s %s: no particle set", lc_target_name(t), kc->name);
            lc_volume_destroy(v);
            continue;
        }
        for (size_t gci = 0; gci < sizeof gcases / sizeof gcases[0]; gci++) {
            const gcase *gc = &gcases[gci];
            size_t n = (size_t)gc->size[0] * gc->size[1] * gc->size[2];
            float *got = malloc(sizeof(float) * n);
            double *want = malloc(sizeof(double) * n);
            uint8_t *near = malloc(n);
            lc_resample_desc d = {.size = {gc->size[0], gc->size[1], gc->size[2]}, .box = gc->box, .field = gc->field};
            lc_resample_info info;
            lc_status s = lc_particles_resample(dev, v, &d, got, &info);
            if (s != LC_OK) {
                CHECK(0, "%s %s, %s: %s", lc_target_name(t), kc->name, gc->name, lc_last_error());
                free(got), free(want), free(near);
                continue;
            }
            double eo[3], es[3], geo = 0.0;
            expected_geometry(gc, &vi.bounds, eo, es);
            const float *go = &info.origin.x, *gs = &info.spacing.x;
            for (int a = 0; a < 3; a++)
                geo = fmax(geo, fmax(fabs(go[a] - eo[a]), fabs(gs[a] - es[a])) / fmax(1.0, fabs(eo[a]) + es[a]));
            reference(kc, gc, &info, want, near);
            double mx = 0.0, worst = 0.0, tested = 0.0, skipped = 0.0;
            for (size_t e = 0; e < n; e++) mx = fmax(mx, fabs(want[e]));
            size_t at = 0;
            for (size_t e = 0; e < n; e++) {
                if (!(fabs(want[e]) > 1e-3 * mx)) continue;
                if (near[e]) {
                    skipped++;
                    continue;
                }
                double err = fabs((double)got[e] - want[e]) / fabs(want[e]);
                if (!(err <= worst)) worst = err, at = e;
                tested++;
            }
            /* where the reference is 0 the values are 0 too: exactly for the Gaussian (away from its
               cut-off); an SPH kernel falls to 0 at u = 1, where float and double may disagree on
               inclusion by a term of order (1 - u)^3 */
            double zero_err = 0.0, zero_ok = kc->rk == REF_KERNEL_GAUSSIAN ? 0.0 : 1e-6 * mx;
            for (size_t e = 0; e < n; e++)
                if (want[e] == 0.0 && !near[e]) zero_err = fmax(zero_err, fabs(got[e]));
            CHECK(geo < 1e-6 && worst <= 1e-5 && zero_err <= zero_ok && tested > 0,
                  "%s %s, %s (%dx%dx%d): max rel error %.3g at node %zu (%zu tested, %.0f at a cut-off skipped), "
                  "nonzero where 0: %g, geometry off by %.2g",
                  lc_target_name(t), kc->name, gc->name, gc->size[0], gc->size[1], gc->size[2], worst, at,
                  (size_t)tested, skipped, zero_err, geo);
            free(got), free(want), free(near);
        }
        lc_volume_destroy(v);
    }
    lc_device_destroy(dev);
}

/* A box away from every particle: exactly zero, no terms. */
static void check_empty(lc_device *dev)
{
    lc_volume *v = make_set(dev, LC_KERNEL_GAUSSIAN, 0.0f, 0.0f);
    float g[5 * 6 * 7];
    for (int i = 0; i < 5 * 6 * 7; i++) g[i] = 7.0f;
    lc_resample_desc d = {.size = {5, 6, 7}, .box = {{20, 20, 20}, {30, 31, 32}}, .field = -1};
    lc_resample_info info;
    lc_status s = lc_particles_resample(dev, v, &d, g, &info);
    int zero = 1;
    for (int i = 0; i < 5 * 6 * 7; i++) zero &= g[i] == 0.0f;
    CHECK(s == LC_OK && zero && info.evaluations == 0 && info.entries == 0 && info.value_max == 0.0f,
          "a box far from the particles: every node 0 (%d), %llu terms, %llu list entries", zero,
          (unsigned long long)info.evaluations, (unsigned long long)info.entries);
    lc_volume *none = NULL;
    lc_particles_create(dev, &(lc_particles_desc){.count = 0, .positions = sc.pos, .radius = 1.0f}, &none);
    for (int i = 0; i < 5 * 6 * 7; i++) g[i] = 7.0f;
    s = lc_particles_resample(dev, none, &d, g, &info);
    zero = 1;
    for (int i = 0; i < 5 * 6 * 7; i++) zero &= g[i] == 0.0f;
    CHECK(none && s == LC_OK && zero, "an empty particle set with a box: every node 0");
    lc_volume_destroy(none);
    lc_volume_destroy(v);
}

static void check_threads(void)
{
    enum { N = 70 }; /* 3^3 bricks, particles on their seams */
    const lc_kernel kernels[2] = {LC_KERNEL_GAUSSIAN, LC_KERNEL_M4};
    for (int k = 0; k < 2; k++) {
        float *g[3];
        lc_status s[3];
        for (int t = 0; t < 3; t++) {
            lc_device *dev = NULL;
            lc_device_create(&(lc_device_desc){.threads = t + 1}, &dev);
            lc_volume *v = make_set(dev, kernels[k], 0.0f, 0.0f);
            g[t] = malloc(sizeof(float) * N * N * N);
            lc_resample_desc d = {.size = {N, N, N}, .field = -1};
            s[t] = lc_particles_resample(dev, v, &d, g[t], NULL);
            lc_volume_destroy(v);
            lc_device_destroy(dev);
        }
        CHECK(s[0] == LC_OK && s[1] == LC_OK && s[2] == LC_OK && !memcmp(g[0], g[1], sizeof(float) * N * N * N) &&
                  !memcmp(g[0], g[2], sizeof(float) * N * N * N),
              "%s: 1, 2 and 3 threads give the same bytes (%d^3 nodes)", lc_kernel_name(kernels[k]), N);
        for (int t = 0; t < 3; t++) free(g[t]);
    }
}

static void check_memory(lc_device *dev)
{
    lc_volume *v = make_set(dev, LC_KERNEL_GAUSSIAN, 0.0f, 0.0f);
    float sentinel[16];
    for (int i = 0; i < 16; i++) sentinel[i] = 3.0f;
    lc_resample_info info;
    /* 128^3 values are 8 MiB: over a limit of 4 MiB, refused before writing into values */
    lc_resample_desc d = {.size = {128, 128, 128}, .field = -1, .max_memory = 4u << 20};
    lc_status s = lc_particles_resample(dev, v, &d, sentinel, &info);
    int untouched = 1;
    for (int i = 0; i < 16; i++) untouched &= sentinel[i] == 3.0f;
    CHECK(s == LC_ERROR_OUT_OF_MEMORY && untouched && strstr(lc_last_error(), "memory limit"),
          "128^3 over max_memory 4 MiB: refused (%s), values untouched: %s", lc_status_string(s), lc_last_error());
    /* the values fit, the particle lists do not: a byte less than the dry run says it needs */
    d = (lc_resample_desc){.size = {64, 64, 64}, .field = -1};
    s = lc_particles_resample(dev, v, &d, NULL, &info);
    d.max_memory = info.bytes - 1;
    s = s == LC_OK ? lc_particles_resample(dev, v, &d, NULL, &info) : s;
    CHECK(s == LC_ERROR_OUT_OF_MEMORY && strstr(lc_last_error(), "particle lists"),
          "64^3 whose lists exceed the limit: refused: %s", lc_last_error());
    /* the default limit (3/4 of the physical memory) against 2^40 nodes */
    d = (lc_resample_desc){.size = {16384, 16384, 4096}, .field = -1};
    s = lc_particles_resample(dev, v, &d, sentinel, &info);
    CHECK(s == LC_ERROR_OUT_OF_MEMORY, "16384x16384x4096 under the default limit: refused: %s", lc_last_error());
    /* a dry run that fits: bytes reported, nothing written */
    d = (lc_resample_desc){.size = {64, 64, 64}, .field = -1};
    s = lc_particles_resample(dev, v, &d, NULL, &info);
    CHECK(s == LC_OK && info.bytes >= 64u * 64u * 64u * 4u && info.entries >= NP,
          "a dry run of 64^3: %llu bytes, %llu entries", (unsigned long long)info.bytes,
          (unsigned long long)info.entries);
    lc_volume_destroy(v);
}

static int cancel_now(void *user)
{
    (void)user;
    return 1;
}

static void check_errors(lc_device *dev)
{
    lc_volume *v = make_set(dev, LC_KERNEL_GAUSSIAN, 0.0f, 0.0f);
    float g[64];
    struct {
        lc_resample_desc d;
        const char *what, *says;
    } bad[] = {
        {{.size = {0, 4, 4}}, "size 0", "size[0]"},
        {{.size = {4, 4, 1 << 25}}, "size 2^25", "size[2]"},
        {{.size = {2, 2, 2}, .field = NF}, "field = nfields", "field"},
        {{.size = {2, 2, 2}, .field = -2}, "field -2", "field"},
        {{.size = {2, 2, 2}, .box = {{1, 0, 0}, {0, 1, 1}}}, "box lo > hi", "box x"},
        {{.size = {2, 2, 2}, .box = {{0, 0, 0}, {1, 0, 1}}}, "flat box with 2 nodes", "box y"},
        {{.size = {2, 2, 2}, .box = {{0, 0, 0}, {1, INFINITY, 1}}}, "infinite box", "box y"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        lc_status s = lc_particles_resample(dev, v, &bad[i].d, g, NULL);
        CHECK(s == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), bad[i].says), "%s: %s", bad[i].what,
              lc_last_error());
    }
    lc_resample_desc ok = {.size = {2, 2, 2}};
    CHECK(lc_particles_resample(dev, v, NULL, g, NULL) == LC_ERROR_INVALID_ARGUMENT, "NULL desc: %s", lc_last_error());
    CHECK(lc_particles_resample(NULL, v, &ok, g, NULL) == LC_ERROR_INVALID_ARGUMENT, "NULL device: %s", lc_last_error());
    float vox[8] = {0};
    lc_volume *grid = NULL;
    lc_grid_create(dev, &(lc_grid_desc){.size = {2, 2, 2}, .type = LC_VALUE_FLOAT32, .data = vox}, &grid);
    CHECK(lc_particles_resample(dev, grid, &ok, g, NULL) == LC_ERROR_INVALID_ARGUMENT &&
              strstr(lc_last_error(), "not a particle set"), "a grid volume: %s",
          lc_last_error());
    lc_volume_destroy(grid);
    lc_resample_desc c = {.size = {40, 40, 40}, .cancel = cancel_now};
    float *big = malloc(sizeof(float) * 40 * 40 * 40);
    CHECK(lc_particles_resample(dev, v, &c, big, NULL) == LC_CANCELLED, "a cancel callback: %s", lc_last_error());
    free(big);
    lc_volume_destroy(v);
}

int main(void)
{
    broken = getenv("LANECAST_TEST_BREAK") && atoi(getenv("LANECAST_TEST_BREAK"));
    make_scene();
    /* the boxes of the 1-node cases follow the particles: about particle 0, through particle 1 */
    const float *p = sc.pos, *q = sc.pos + 3;
    gcases[3].box = (lc_box3){{p[0] - 0.13f, p[1] - 0.2f, p[2] + 0.05f}, {p[0] + 0.17f, p[1] + 0.1f, p[2] + 0.15f}};
    gcases[4].box = (lc_box3){{q[0] + 0.05f, q[1] - 3.0f, q[2] - 0.1f}, {q[0] + 0.05f, q[1] + 3.0f, q[2] - 0.1f}};
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        if (!lc_target_compiled((lc_target)t) || !lc_target_supported((lc_target)t)) {
            printf("skip %s: %s on this machine\n", lc_target_name((lc_target)t),
                   lc_target_compiled((lc_target)t) ? "not supported" : "not compiled");
            continue;
        }
        run_target((lc_target)t);
    }
    lc_device *dev = NULL;
    if (lc_device_create(NULL, &dev) != LC_OK) return printf("lc_device_create: %s\n", lc_last_error()), 1;
    check_empty(dev);
    check_memory(dev);
    check_errors(dev);
    lc_device_destroy(dev);
    check_threads();
    return check_summary("test_resample");
}
