/* The coherent particle deposit's exp-free Gaussian (issue 8; SPEC.md
 * "Fields": the ratio recurrence g(k+1) = g(k) q(k), q(k+1) = q(k) c,
 * re-anchored so each term stays within 1e-5 relative of a direct
 * evaluation) on every compiled and supported target, through each kernel
 * library's probe (lc_pgauss_probe, kernels/particles_common.h): long chords
 * (sigma up to 8, dt down to r/16, so up to ~260 samples per chord) against
 * the Gaussian in double at the same anchor offsets, inside the support. A
 * run without re-anchoring must exceed the bound (the check can fail). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include "lanecast/lanecast.h"
#include "check.h"

typedef int (*probe_fn)(const float *, const float *, float, float, float, int, int, int, float *);
#define WEAK __attribute__((weak))
int lc_pgauss_probe_scalar(const float *, const float *, float, float, float, int, int, int, float *) WEAK;
int lc_pgauss_probe_sse4(const float *, const float *, float, float, float, int, int, int, float *) WEAK;
int lc_pgauss_probe_avx2(const float *, const float *, float, float, float, int, int, int, float *) WEAK;
int lc_pgauss_probe_avx512(const float *, const float *, float, float, float, int, int, int, float *) WEAK;
int lc_pgauss_probe_avx512_8(const float *, const float *, float, float, float, int, int, int, float *) WEAK;

static probe_fn probe_of(lc_target t)
{
    switch (t) {
    case LC_TARGET_SCALAR: return lc_pgauss_probe_scalar;
    case LC_TARGET_SSE4: return lc_pgauss_probe_sse4;
    case LC_TARGET_AVX2: return lc_pgauss_probe_avx2;
    case LC_TARGET_AVX512: return lc_pgauss_probe_avx512;
    case LC_TARGET_AVX512_8: return lc_pgauss_probe_avx512_8;
    default: return NULL;
    }
}

static uint64_t rs = 0x243f6a8885a308d3ull;
static double rnd(void)
{
    rs ^= rs << 13, rs ^= rs >> 7, rs ^= rs << 17;
    return (double)(rs >> 11) / 9007199254740992.0;
}

#define MAXK 600

/* Worst relative error over `chords` random chords (each LC_W lanes) with
 * anchor period `period` (0 = the kernels'). */
static double worst_error(probe_fn fn, int lanes, int period, int chords, int *used_period, long *terms)
{
    static float out[MAXK * 16];
    double worst = 0.0;
    for (int c = 0; c < chords; c++) {
        float r = (float)(0.3 + 2.7 * rnd()), sigma = (float)(2.0 + 6.0 * rnd());
        float dt = r / (float)(2.0 + 14.0 * rnd()), kk = (float)(0.1 + 10.0 * rnd()) * (rnd() < 0.3 ? -1.0f : 1.0f);
        float nir = -1.0f / (2.0f * r * r), R = sigma * r;
        float base = (float)(-50.0 + 100.0 * rnd()) * r; /* centre foot along the ray */
        float d2[16], tc[16];
        for (int l = 0; l < 16; l++) {
            d2[l] = (float)(rnd() * 0.9) * R * R;
            tc[l] = base + (float)(rnd() - 0.5) * r;
        }
        int ka = (int)floorf((base - R - r) / dt), kb = (int)ceilf((base + R + r) / dt);
        if (kb - ka + 1 > MAXK) kb = ka + MAXK - 1;
        int per = fn(d2, tc, nir, kk, dt, ka, kb, period, out);
        *used_period = per;
        for (int l = 0; l < lanes; l++) {
            for (int k = ka; k <= kb; k++) {
                int k0 = ka + (k - ka) / per * per;
                /* the anchor's offset as the kernel forms it, then exact steps */
                volatile float t0 = (float)k0 * dt; /* no contraction: the kernels build with -ffp-contract=off */
                float ua = t0 - tc[l];
                double u = (double)ua + (double)(k - k0) * (double)dt;
                double a = (double)d2[l] + u * u;
                if (a >= (double)R * (double)R) continue; /* outside the support: never deposited */
                double ref = (double)kk * exp((double)nir * a);
                double got = out[(size_t)(k - ka) * (size_t)lanes + (size_t)l];
                double e = fabs(got - ref) / fabs(ref);
                if (!(e <= worst)) worst = e; /* NaN counts as worst */
                (*terms)++;
            }
        }
    }
    return worst;
}

int main(void)
{
    int tested = 0;
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        probe_fn fn = probe_of((lc_target)t);
        if (!fn || !lc_target_compiled((lc_target)t) || !lc_target_supported((lc_target)t)) {
            printf("skip %s: not compiled or not supported here\n", lc_target_name((lc_target)t));
            continue;
        }
        int lanes = lc_target_lanes((lc_target)t), per = 0;
        long terms = 0, terms_free = 0;
        double e = worst_error(fn, lanes, 0, 400, &per, &terms);
        printf("%s: %ld terms, re-anchor every %d samples: worst relative error %.3g (bound 1e-5)\n",
               lc_target_name((lc_target)t), terms, per, e);
        CHECK(e <= 1e-5, "%s: recurrence within 1e-5 of direct evaluation (worst %.3g)", lc_target_name((lc_target)t), e);
        CHECK(terms > 20000, "%s: %ld terms compared", lc_target_name((lc_target)t), terms);
        /* without re-anchoring the drift over ~100+ steps exceeds the bound: the check can fail */
        double ef = worst_error(fn, lanes, MAXK, 100, &per, &terms_free);
        printf("%s: never re-anchored: worst relative error %.3g\n", lc_target_name((lc_target)t), ef);
        CHECK(ef > 1e-5, "%s: the check detects drift without re-anchoring (%.3g)", lc_target_name((lc_target)t), ef);
        tested++;
    }
    CHECK(tested > 0, "%d targets tested", tested);
    return check_summary("test_particles_recurrence");
}
