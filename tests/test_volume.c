/* The kind-neutral volume calls on both kinds, on every supported target:
 * lc_volume_get_info and lc_volume_kind; lc_volume_sample on a grid (a node
 * samples its voxel, 0 outside the domain, the gradient of a linear ramp is
 * its slope, per layout and value type) and on particles (the sum of
 * truncated Gaussians with the volume's sigma and kappa, as
 * lc_particles_sample computed it); lc_particles_set_params and
 * lc_grid_set_params change bounds, range, field and reported parameters
 * without a rebuild; kind-specific calls on the other kind fail. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "lanecast/lanecast.h"
#include "check.h"

static lc_target targets[LC_TARGET_COUNT];
static int ntargets;

static lc_device *device_for(lc_target t)
{
    lc_device *dev = NULL;
    if (lc_device_create(&(lc_device_desc){.target = t, .threads = 1}, &dev) != LC_OK)
        printf("lc_device_create(%s): %s\n", lc_target_name(t), lc_last_error());
    return dev;
}

static int box_eq(lc_box3 a, lc_box3 b, float tol)
{
    return fabsf(a.lo.x - b.lo.x) <= tol && fabsf(a.lo.y - b.lo.y) <= tol && fabsf(a.lo.z - b.lo.z) <= tol &&
           fabsf(a.hi.x - b.hi.x) <= tol && fabsf(a.hi.y - b.hi.y) <= tol && fabsf(a.hi.z - b.hi.z) <= tol;
}

/* ---------------------------------------------------------------- grids */

enum { NX = 7, NY = 6, NZ = 5, NV = NX * NY * NZ };

/* voxel (i, j, k) of the test grids: a linear ramp (exact in every type) or a
 * scrambled pattern */
static double voxel(int ramp, int i, int j, int k)
{
    if (ramp) return 3.0 * i - 2.0 * j + 5.0 * k + 40.0;
    return (double)((i * 37 + j * 101 + k * 53) % 200);
}

static void fill_grid(void *data, lc_value_type t, int ramp)
{
    for (int k = 0; k < NZ; k++)
        for (int j = 0; j < NY; j++)
            for (int i = 0; i < NX; i++) {
                int id = (k * NY + j) * NX + i;
                double v = voxel(ramp, i, j, k);
                switch (t) {
                case LC_VALUE_UINT8: ((uint8_t *)data)[id] = (uint8_t)v; break;
                case LC_VALUE_UINT16: ((uint16_t *)data)[id] = (uint16_t)v; break;
                case LC_VALUE_INT16: ((int16_t *)data)[id] = (int16_t)(v - 100); break;
                default: ((float *)data)[id] = (float)v; break;
                }
            }
}

static double stored(lc_value_type t, double v) { return t == LC_VALUE_INT16 ? v - 100 : v; }

static void test_grid(void)
{
    printf("-- grids\n");
    const lc_vec3 sp = {0.5f, 2.0f, 1.25f}, org = {-1.0f, 3.0f, 0.5f};
    static unsigned char data[NV * 4];
    for (int ti = 0; ti < ntargets; ti++) {
        lc_device *dev = device_for(targets[ti]);
        if (!dev) continue;
        const char *tn = lc_target_name(targets[ti]);
        for (int type = LC_VALUE_UINT8; type <= LC_VALUE_FLOAT32; type++)
            for (int layout = LC_LAYOUT_LINEAR; layout <= LC_LAYOUT_BRICKED; layout++)
                for (int ramp = 0; ramp <= 1; ramp++) {
                    lc_value_type t = (lc_value_type)type;
                    fill_grid(data, t, ramp);
                    lc_volume *g = NULL;
                    lc_grid_desc gd = {.size = {NX, NY, NZ}, .type = t, .data = data, .spacing = sp, .origin = org,
                                       .layout = (lc_grid_layout)layout};
                    if (lc_grid_create(dev, &gd, &g) != LC_OK) {
                        CHECK(0, "%s lc_grid_create: %s", tn, lc_last_error());
                        continue;
                    }
                    char tag[96];
                    snprintf(tag, sizeof tag, "%-8s type %d %-7s %s", tn, type, layout == LC_LAYOUT_LINEAR ? "linear" : "bricked",
                             ramp ? "ramp" : "pattern");
                    /* info: kind, bounds first to last node, one field, the voxel range */
                    lc_volume_info vi;
                    memset(&vi, 0, sizeof vi);
                    double mn = INFINITY, mx = -INFINITY;
                    for (int k = 0; k < NZ; k++)
                        for (int j = 0; j < NY; j++)
                            for (int i = 0; i < NX; i++) {
                                double v = stored(t, voxel(ramp, i, j, k));
                                mn = fmin(mn, v), mx = fmax(mx, v);
                            }
                    lc_box3 want = {org, {org.x + (NX - 1) * sp.x, org.y + (NY - 1) * sp.y, org.z + (NZ - 1) * sp.z}};
                    CHECK_QUIET(lc_volume_kind(g) == LC_KIND_GRID && lc_volume_get_info(g, &vi) == LC_OK &&
                                    vi.kind == LC_KIND_GRID && vi.nfields == 1 && box_eq(vi.bounds, want, 1e-6f) &&
                                    vi.range[0] == (float)mn && vi.range[1] == (float)mx,
                                "%s: lc_volume_get_info kind %d, %d fields, range [%g, %g] (want [%g, %g])", tag,
                                (int)vi.kind, vi.nfields, (double)vi.range[0], (double)vi.range[1], mn, mx);
                    /* every node samples its voxel */
                    float *pts = malloc(sizeof(float) * 3 * NV), *val = malloc(sizeof(float) * NV),
                          *grad = malloc(sizeof(float) * 3 * NV);
                    for (int k = 0; k < NZ; k++)
                        for (int j = 0; j < NY; j++)
                            for (int i = 0; i < NX; i++) {
                                int id = (k * NY + j) * NX + i;
                                pts[3 * id] = org.x + (float)i * sp.x;
                                pts[3 * id + 1] = org.y + (float)j * sp.y;
                                pts[3 * id + 2] = org.z + (float)k * sp.z;
                            }
                    lc_status s = lc_volume_sample(dev, g, NV, pts, val, grad);
                    int bad = 0;
                    double worst = 0;
                    for (int k = 0; k < NZ && s == LC_OK; k++)
                        for (int j = 0; j < NY; j++)
                            for (int i = 0; i < NX; i++) {
                                int id = (k * NY + j) * NX + i;
                                double e = fabs(val[id] - stored(t, voxel(ramp, i, j, k)));
                                worst = fmax(worst, e);
                                bad += e > 1e-4 * fmax(1.0, fabs(stored(t, voxel(ramp, i, j, k))));
                            }
                    CHECK_QUIET(s == LC_OK && bad == 0, "%s: %d of %d nodes do not sample their voxel (worst %g): %s", tag,
                                bad, NV, worst, s == LC_OK ? "" : lc_last_error());
                    /* 0 outside the domain: just past each face, far away, NaN */
                    float out_pts[] = {want.lo.x - 0.01f, 4, 1,   want.hi.x + 0.01f, 4, 1,   0, want.lo.y - 0.01f, 1,
                                       0, want.hi.y + 0.01f, 1,   0, 4, want.lo.z - 0.01f,   0, 4, want.hi.z + 0.01f,
                                       1e6f, -1e6f, 1e6f,         NAN, 4, 1};
                    enum { NOUT = sizeof out_pts / sizeof out_pts[0] / 3 };
                    float out_v[NOUT], out_g[3 * NOUT];
                    for (int i = 0; i < NOUT; i++) out_v[i] = 1;
                    s = lc_volume_sample(dev, g, NOUT, out_pts, out_v, out_g);
                    int nonzero = 0;
                    for (int i = 0; i < NOUT; i++)
                        nonzero += out_v[i] != 0 || out_g[3 * i] != 0 || out_g[3 * i + 1] != 0 || out_g[3 * i + 2] != 0;
                    CHECK_QUIET(s == LC_OK && nonzero == 0, "%s: %d of %d points outside the domain are not 0", tag, nonzero,
                                NOUT);
                    if (ramp) {
                        /* random points inside: the trilinear value is the ramp and its gradient the slope (world units) */
                        enum { NR = 64 };
                        float rp[3 * NR], rv[NR], rg[3 * NR];
                        uint32_t st = 12345u + (uint32_t)(type * 7 + layout);
                        for (int i = 0; i < 3 * NR; i++) {
                            st = st * 1664525u + 1013904223u;
                            double u = (double)(st >> 8) / 16777216.0;
                            int a = i % 3;
                            float lo = a == 0 ? want.lo.x : a == 1 ? want.lo.y : want.lo.z;
                            float hi = a == 0 ? want.hi.x : a == 1 ? want.hi.y : want.hi.z;
                            rp[i] = lo + (float)(u * (hi - lo));
                        }
                        s = lc_volume_sample(dev, g, NR, rp, rv, rg);
                        /* v = 3 i - 2 j + 5 k + 40 (- 100 for int16), i = (x - ox) / sx, ... */
                        double slope[3] = {3.0 / sp.x, -2.0 / sp.y, 5.0 / sp.z};
                        double ev = 0, eg = 0;
                        for (int i = 0; i < NR && s == LC_OK; i++) {
                            double ii = (rp[3 * i] - org.x) / sp.x, jj = (rp[3 * i + 1] - org.y) / sp.y,
                                   kk = (rp[3 * i + 2] - org.z) / sp.z;
                            ev = fmax(ev, fabs(rv[i] - stored(t, 3 * ii - 2 * jj + 5 * kk + 40)));
                            for (int a = 0; a < 3; a++) eg = fmax(eg, fabs(rg[3 * i + a] - slope[a]));
                        }
                        CHECK_QUIET(s == LC_OK && ev < 2e-4 && eg < 2e-4,
                                    "%s: ramp value error %g, gradient error %g (slope %g, %g, %g)", tag, ev, eg, slope[0],
                                    slope[1], slope[2]);
                        /* gradients may be NULL */
                        s = lc_volume_sample(dev, g, NR, rp, rv, NULL);
                        CHECK_QUIET(s == LC_OK, "%s: sample without gradients: %s", tag, lc_last_error());
                    }
                    free(pts), free(val), free(grad);
                    lc_volume_destroy(g);
                }
        printf("ok   grid samples, info, outside = 0, ramp gradients on %s\n", tn);
        lc_device_destroy(dev);
    }

    /* lc_grid_set_params: kept and reported, bounds and range unchanged, NULL = defaults */
    lc_device *dev = device_for(LC_TARGET_AUTO);
    if (!dev) return;
    fill_grid(data, LC_VALUE_FLOAT32, 0);
    lc_volume *g = NULL;
    lc_grid_params gp0 = {.preintegrated = 1, .delta_c = -1};
    CHECK(lc_grid_create(dev, &(lc_grid_desc){.size = {NX, NY, NZ}, .type = LC_VALUE_FLOAT32, .data = data, .params = gp0},
                         &g) == LC_OK,
          "grid with initial parameters in its desc");
    if (!g) {
        lc_device_destroy(dev);
        return;
    }
    lc_grid_info gi;
    lc_volume_info before, after;
    lc_grid_get_info(g, &gi);
    lc_volume_get_info(g, &before);
    CHECK(gi.params.preintegrated == 1 && gi.params.delta_c == -1.0f, "lc_grid_get_info reports the desc's parameters");
    uint64_t nodes = gi.bvh_nodes;
    double build = gi.bvh_build_seconds;
    lc_grid_params gp = {.rda = 0.01f, .delta_c = 2e-3f, .delta_p = -1, .delta_sv = 5e-4f};
    CHECK(lc_grid_set_params(g, &gp) == LC_OK && lc_grid_get_info(g, &gi) == LC_OK && gi.params.rda == 0.01f &&
              gi.params.delta_c == 2e-3f && gi.params.delta_p == -1.0f && gi.params.delta_sv == 5e-4f &&
              gi.params.preintegrated == 0 && gi.bvh_nodes == nodes && gi.bvh_build_seconds == build,
          "lc_grid_set_params: parameters reported, no rebuild (%llu nodes, build %.6f s)", (unsigned long long)gi.bvh_nodes,
          gi.bvh_build_seconds);
    lc_volume_get_info(g, &after);
    CHECK(box_eq(before.bounds, after.bounds, 0) && before.range[0] == after.range[0] && before.range[1] == after.range[1],
          "grid bounds and range do not depend on its parameters");
    CHECK(lc_grid_set_params(g, NULL) == LC_OK && lc_grid_get_info(g, &gi) == LC_OK && gi.params.rda == 0 &&
              gi.params.delta_c == 0 && gi.params.preintegrated == 0,
          "lc_grid_set_params(NULL) restores the defaults");
    lc_particles_info pi;
    CHECK(lc_particles_get_info(g, &pi) == LC_ERROR_INVALID_ARGUMENT &&
              lc_particles_set_params(g, &(lc_particle_params){0}) == LC_ERROR_INVALID_ARGUMENT,
          "particle calls on a grid fail: %s", lc_last_error());
    lc_volume_destroy(g);
    lc_device_destroy(dev);
}

/* ---------------------------------------------------------------- particles */

enum { NPART = 60, NF = 3 };

typedef struct pset {
    float xyz[3 * NPART], r[NPART], k[NPART];
    uint8_t f[NPART];
} pset;

static uint64_t rs = 0x9e3779b97f4a7c15ull;
static double rnd(void)
{
    rs ^= rs << 13, rs ^= rs >> 7, rs ^= rs << 17;
    return (double)(rs >> 11) / 9007199254740992.0;
}

/* phi_f(x) = sum kappa k_i exp(-d^2 / (2 r_i^2)) over d < sigma r_i, and its gradient, in double; the
 * tolerances of test_particles.c (1e-5 of the sum of |terms| for float exp and summation, plus 4 ulps of
 * |x| + |x_i| for the point minus the centre times the field's sensitivity to it) for the value (tol) and
 * gradient (gtol); and whether a particle lies within 1e-4 of its cut-off (the point is then skipped) */
static void brute(const pset *p, double sigma, double kappa, const float *x, double *phi, double *grad, double *tol,
                  double *gtol, int *near_cut)
{
    for (int f = 0; f < NF; f++)
        phi[f] = 0, tol[f] = gtol[f] = 1e-30, grad[3 * f] = grad[3 * f + 1] = grad[3 * f + 2] = 0;
    *near_cut = 0;
    for (int i = 0; i < NPART; i++) {
        double d[3] = {x[0] - (double)p->xyz[3 * i], x[1] - (double)p->xyz[3 * i + 1], x[2] - (double)p->xyz[3 * i + 2]};
        double d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], r = p->r[i], cut = sigma * r;
        if (fabs(sqrt(d2) - cut) < 1e-4 * cut) *near_cut = 1;
        if (d2 >= cut * cut) continue;
        double term = kappa * p->k[i] * exp(-d2 / (2 * r * r));
        int f = p->f[i];
        phi[f] += term;
        double at = fabs(term), dist = sqrt(d2), pos = 2.4e-7 * 3 * (fmax(fabs(x[0]), fmax(fabs(x[1]), fabs(x[2]))) +
                                                                      fmax(fabs(p->xyz[3 * i]), fmax(fabs(p->xyz[3 * i + 1]),
                                                                           fabs(p->xyz[3 * i + 2]))));
        tol[f] += 1e-5 * at + pos * at * dist / (r * r);
        gtol[f] += 1e-5 * at * dist / (r * r) + pos * at / (r * r) * (1 + d2 / (r * r));
        for (int a = 0; a < 3; a++) grad[3 * f + a] += -term * d[a] / (r * r);
    }
}

static void test_particles(void)
{
    printf("-- particles\n");
    pset p;
    for (int i = 0; i < NPART; i++) {
        for (int a = 0; a < 3; a++) p.xyz[3 * i + a] = (float)(rnd() * 6 - 3);
        p.r[i] = (float)(0.3 + 0.7 * rnd());
        p.k[i] = (float)(0.2 + 1.5 * rnd());
        p.f[i] = (uint8_t)(i % NF);
    }
    float rmin = p.r[0], rmax = p.r[0];
    lc_box3 c = {{p.xyz[0], p.xyz[1], p.xyz[2]}, {p.xyz[0], p.xyz[1], p.xyz[2]}};
    for (int i = 0; i < NPART; i++) {
        rmin = fminf(rmin, p.r[i]), rmax = fmaxf(rmax, p.r[i]);
        c.lo.x = fminf(c.lo.x, p.xyz[3 * i]), c.hi.x = fmaxf(c.hi.x, p.xyz[3 * i]);
        c.lo.y = fminf(c.lo.y, p.xyz[3 * i + 1]), c.hi.y = fmaxf(c.hi.y, p.xyz[3 * i + 1]);
        c.lo.z = fminf(c.lo.z, p.xyz[3 * i + 2]), c.hi.z = fmaxf(c.hi.z, p.xyz[3 * i + 2]);
    }
    enum { NPTS = 400 };
    float pts[3 * NPTS];
    for (int i = 0; i < NPTS; i++) {
        if (i % 2 == 0) { /* near a particle, inside and around the edge of its support */
            int j = (int)(rnd() * NPART);
            for (int a = 0; a < 3; a++) pts[3 * i + a] = p.xyz[3 * j + a] + (float)((rnd() - 0.5) * 3.0 * p.r[j]);
        } else {
            for (int a = 0; a < 3; a++) pts[3 * i + a] = (float)(rnd() * 12 - 6);
        }
    }
    /* (sigma, kappa): defaults, then changed with lc_particles_set_params on the same volume */
    static const float params[][2] = {{0, 0}, {3.0f, 0.5f}, {1.5f, -2.0f}, {2.5f, 4.0f}};
    for (int ti = 0; ti < ntargets; ti++) {
        lc_device *dev = device_for(targets[ti]);
        if (!dev) continue;
        const char *tn = lc_target_name(targets[ti]);
        lc_volume *v = NULL;
        lc_particles_desc d = {.count = NPART, .positions = p.xyz, .radii = p.r, .values = p.k, .fields = p.f};
        if (lc_particles_create(dev, &d, &v) != LC_OK) {
            CHECK(0, "%s lc_particles_create: %s", tn, lc_last_error());
            lc_device_destroy(dev);
            continue;
        }
        lc_particles_info pi0;
        lc_particles_get_info(v, &pi0);
        for (size_t q = 0; q < sizeof params / sizeof params[0]; q++) {
            lc_particle_params pp = {.sigma = params[q][0], .kappa = params[q][1]};
            CHECK_QUIET(lc_particles_set_params(v, &pp) == LC_OK, "%s set_params: %s", tn, lc_last_error());
            double sigma = pp.sigma ? pp.sigma : 2.0, kappa = pp.kappa ? pp.kappa : 1.0;
            /* info: the current parameters (defaults filled in), no rebuild, bounds grown by sigma r_max */
            lc_particles_info pi;
            lc_volume_info vi;
            lc_particles_get_info(v, &pi);
            lc_volume_get_info(v, &vi);
            float g = (float)sigma * rmax;
            lc_box3 want = {{c.lo.x - g, c.lo.y - g, c.lo.z - g}, {c.hi.x + g, c.hi.y + g, c.hi.z + g}};
            /* the default range: the peaks kappa k_i and 0 */
            float rlo = 0.0f, rhi = 0.0f;
            for (int i = 0; i < NPART; i++)
                rlo = fminf(rlo, (float)kappa * p.k[i]), rhi = fmaxf(rhi, (float)kappa * p.k[i]);
            CHECK_QUIET(pi.params.sigma == (float)sigma && pi.params.kappa == (float)kappa && pi.bvh_nodes == pi0.bvh_nodes &&
                            pi.build_seconds == pi0.build_seconds && pi.nfields == NF && box_eq(pi.bounds, c, 0),
                        "%s sigma %g kappa %g: particle info params %g %g, %d nodes (was %d), build %g s (was %g)", tn,
                        sigma, kappa, (double)pi.params.sigma, (double)pi.params.kappa, pi.bvh_nodes, pi0.bvh_nodes,
                        pi.build_seconds, pi0.build_seconds);
            CHECK_QUIET(lc_volume_kind(v) == LC_KIND_PARTICLES && vi.kind == LC_KIND_PARTICLES && vi.nfields == NF &&
                            box_eq(vi.bounds, want, 1e-5f) && vi.range[0] == rlo && vi.range[1] == rhi,
                        "%s sigma %g kappa %g: volume info bounds [%g %g %g]-[%g %g %g] (want [%g %g %g]-[%g %g %g]), "
                        "range [%g, %g] (want [%g, %g])", tn, sigma, kappa, (double)vi.bounds.lo.x, (double)vi.bounds.lo.y,
                        (double)vi.bounds.lo.z, (double)vi.bounds.hi.x, (double)vi.bounds.hi.y, (double)vi.bounds.hi.z,
                        (double)want.lo.x, (double)want.lo.y, (double)want.lo.z, (double)want.hi.x, (double)want.hi.y,
                        (double)want.hi.z, (double)vi.range[0], (double)vi.range[1], (double)rlo, (double)rhi);
            /* the field and its gradient, values[i * nf + f], gradients[3 (i * nf + f) + c] */
            float val[NPTS * NF], grad[3 * NPTS * NF];
            lc_status s = lc_volume_sample(dev, v, NPTS, pts, val, grad);
            int bad = 0, skipped = 0, nonzero = 0;
            double worst = 0;
            for (int i = 0; i < NPTS && s == LC_OK; i++) {
                double phi[NF], gr[3 * NF], tol[NF], gtol[NF];
                int near;
                brute(&p, sigma, kappa, pts + 3 * i, phi, gr, tol, gtol, &near);
                if (near) {
                    skipped++;
                    continue;
                }
                for (int f = 0; f < NF; f++) {
                    double e = fabs(val[i * NF + f] - phi[f]) / tol[f];
                    for (int a = 0; a < 3; a++) e = fmax(e, fabs(grad[3 * (i * NF + f) + a] - gr[3 * f + a]) / gtol[f]);
                    worst = fmax(worst, e);
                    bad += e > 1.0;
                    nonzero += phi[f] != 0;
                }
            }
            CHECK_QUIET(s == LC_OK && bad == 0 && nonzero > NPTS / 4,
                        "%s sigma %g kappa %g: %d of %d values off the brute-force sum (worst err/tol %.3f), %d non-zero, "
                        "%d near a cut-off skipped: %s", tn, sigma, kappa, bad, NPTS * NF, worst, nonzero, skipped,
                        s == LC_OK ? "" : lc_last_error());
            if (q == 0) printf("ok   particle samples on %s: worst err/tol %.3f, %d non-zero\n", tn, worst, nonzero);
        }
        /* sigma alone decides the support, without a rebuild: a point 2.5 r from an isolated particle */
        lc_volume *one = NULL;
        float x0[3] = {0, 0, 0}, at[3] = {2.5f, 0, 0}, phi = -1;
        lc_particles_create(dev, &(lc_particles_desc){.count = 1, .positions = x0, .radius = 1.0f}, &one);
        if (one) {
            lc_status s1 = lc_volume_sample(dev, one, 1, at, &phi, NULL);
            float phi2 = phi;
            lc_particles_set_params(one, &(lc_particle_params){.sigma = 3.0f});
            lc_status s2 = lc_volume_sample(dev, one, 1, at, &phi, NULL);
            CHECK_QUIET(s1 == LC_OK && s2 == LC_OK && phi2 == 0.0f && fabs(phi - exp(-2.5 * 2.5 / 2)) < 1e-6,
                        "%s: 2.5 r from a particle: %g with sigma 2, %g with sigma 3 (want %g)", tn, (double)phi2,
                        (double)phi, exp(-2.5 * 2.5 / 2));
        }
        lc_volume_destroy(one);
        lc_grid_info gi;
        CHECK_QUIET(lc_grid_get_info(v, &gi) == LC_ERROR_INVALID_ARGUMENT &&
                        lc_grid_set_params(v, &(lc_grid_params){0}) == LC_ERROR_INVALID_ARGUMENT,
                    "%s: grid calls on particles fail", tn);
        lc_volume_destroy(v);
        lc_device_destroy(dev);
    }
    /* parameters given at creation */
    lc_device *dev = device_for(LC_TARGET_AUTO);
    lc_volume *v = NULL;
    lc_particles_desc d = {.count = NPART, .positions = p.xyz, .radii = p.r, .values = p.k, .fields = p.f,
                           .params = {.sigma = 1.0f, .kappa = 3.0f, .buffer_samples = 16, .sphere_scale = 0.5f}};
    lc_particles_info pi;
    memset(&pi, 0, sizeof pi);
    if (dev && lc_particles_create(dev, &d, &v) == LC_OK) lc_particles_get_info(v, &pi);
    CHECK(v && pi.params.sigma == 1.0f && pi.params.kappa == 3.0f && pi.params.buffer_samples == 16 &&
              pi.params.sphere_scale == 0.5f,
          "lc_particles_desc.params are the initial parameters (sigma %g kappa %g buffer %d spheres %g)",
          (double)pi.params.sigma, (double)pi.params.kappa, pi.params.buffer_samples, (double)pi.params.sphere_scale);
    d.params.sigma = -1.0f;
    lc_volume *bad = NULL;
    CHECK(dev && lc_particles_create(dev, &d, &bad) == LC_ERROR_INVALID_ARGUMENT && bad == NULL,
          "a bad sigma in lc_particles_desc.params is refused: %s", lc_last_error());
    lc_volume_destroy(v);
    lc_device_destroy(dev);
}

/* lc_format_count / lc_format_get: every format named in the header is listed with its kind. */
static void test_formats(void)
{
    static const struct { const char *name; lc_kind kind; } want[] = {
        {"xyz", LC_KIND_PARTICLES}, {"pdb", LC_KIND_PARTICLES}, {"raw-particles", LC_KIND_PARTICLES},
        {"nrrd", LC_KIND_GRID},     {"metaimage", LC_KIND_GRID}, {"raw-volume", LC_KIND_GRID}};
    int n = lc_format_count(), found = 0;
    for (size_t w = 0; w < sizeof want / sizeof want[0]; w++)
        for (int i = 0; i < n; i++) {
            lc_format_info fi;
            if (lc_format_get(i, &fi) == LC_OK && fi.name && !strcmp(fi.name, want[w].name)) {
                found += fi.kind == want[w].kind && fi.available && fi.extensions && fi.options && fi.description &&
                         fi.package;
                break;
            }
        }
    CHECK(found == (int)(sizeof want / sizeof want[0]), "lc_format_get lists %d formats, %d of the %d expected with their kind",
          n, found, (int)(sizeof want / sizeof want[0]));
}

int main(void)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    for (lc_target t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        if (lc_target_compiled(t) && lc_target_supported(t)) targets[ntargets++] = t;
        else printf("skip target %s: not compiled or not supported here\n", lc_target_name(t));
    }
    test_grid();
    test_particles();
    test_formats();
    return check_summary("test_volume");
}
