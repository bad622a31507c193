/* The coherent particle kernel's paired integration (issue 8,
 * kernels/particles_integrate.h integrate_two: one field without gradient in
 * dvr and mip, two ray vectors' samples interleaved) against the general
 * loop (integrate_buffer, one vector at a time) on the same pass, through
 * each kernel library's probe (lc_pintegrate_probe): every colour channel of
 * every lane, the samples integrated and the pass's waste (which sets the
 * next group's pass length) bit for bit, for groups of 1 to 64 vectors (odd
 * counts leave one vector alone), alpha_stop 0.5, 0.9 and 1, many seeds, on
 * every compiled and supported target. The inputs must not be vacuous (lanes
 * become opaque within the pass, samples are integrated), and the probe's
 * broken mode (the paired loop one sample short) must be caught in at least
 * 75% of the passes (a pass whose last sample no lane takes integrates the
 * same either way). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "lanecast/lanecast.h"
#include "check.h"

typedef int (*probe_fn)(int, int, uint64_t, float, int, void *, uint64_t *);
#define WEAK __attribute__((weak))
int lc_pintegrate_probe_scalar(int, int, uint64_t, float, int, void *, uint64_t *) WEAK;
int lc_pintegrate_probe_sse4(int, int, uint64_t, float, int, void *, uint64_t *) WEAK;
int lc_pintegrate_probe_avx2(int, int, uint64_t, float, int, void *, uint64_t *) WEAK;
int lc_pintegrate_probe_avx512(int, int, uint64_t, float, int, void *, uint64_t *) WEAK;
int lc_pintegrate_probe_avx512_8(int, int, uint64_t, float, int, void *, uint64_t *) WEAK;

static probe_fn probe_of(lc_target t)
{
    switch (t) {
    case LC_TARGET_SCALAR: return lc_pintegrate_probe_scalar;
    case LC_TARGET_SSE4: return lc_pintegrate_probe_sse4;
    case LC_TARGET_AVX2: return lc_pintegrate_probe_avx2;
    case LC_TARGET_AVX512: return lc_pintegrate_probe_avx512;
    case LC_TARGET_AVX512_8: return lc_pintegrate_probe_avx512_8;
    default: return NULL;
    }
}

#define MEM_BYTES (4u << 20)

int main(void)
{
    void *mem = aligned_alloc(64, MEM_BYTES);
    CHECK(mem != NULL, "probe memory");
    if (!mem) return check_summary("test_particles_integrate");
    static const int nvs[] = {1, 2, 3, 5, 8, 16, 17, 63, 64};
    static const float stops[] = {0.5f, 0.9f, 1.0f};
    int tested = 0;
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        probe_fn fn = probe_of((lc_target)t);
        const char *name = lc_target_name((lc_target)t);
        if (!fn || !lc_target_compiled((lc_target)t) || !lc_target_supported((lc_target)t)) {
            printf("skip %s: not compiled or not supported here\n", name);
            continue;
        }
        for (int mode = 0; mode < 2; mode++) { /* LC_KMODE_DVR, LC_KMODE_MIP */
            uint64_t diff = 0, samples = 0, died = 0, broken = 0, runs = 0;
            for (size_t i = 0; i < sizeof nvs / sizeof nvs[0]; i++)
                for (size_t a = 0; a < sizeof stops / sizeof stops[0]; a++)
                    for (uint64_t seed = 1; seed <= 12; seed++) {
                        uint64_t out[3] = {0, 0, 0};
                        memset(mem, 0, MEM_BYTES);
                        int rc = fn(mode, nvs[i], seed * 0x9e3779b97f4a7c15ull + (uint64_t)i, stops[a], 0, mem, out);
                        CHECK_QUIET(rc == 0, "%s probe rc %d", name, rc);
                        CHECK_QUIET(out[0] == 0, "%s mode %d nv %d stop %.1f seed %llu: %llu words differ", name, mode,
                                    nvs[i], (double)stops[a], (unsigned long long)seed, (unsigned long long)out[0]);
                        diff += out[0], samples += out[1], died += out[2], runs++;
                        memset(mem, 0, MEM_BYTES);
                        if (fn(mode, nvs[i], seed * 0x9e3779b97f4a7c15ull + (uint64_t)i, stops[a], 1, mem, out) == 0)
                            broken += out[0] > 0;
                    }
            printf("%s mode %d: %llu passes, %llu samples, %llu lanes became opaque, %llu words differ\n", name, mode,
                   (unsigned long long)runs, (unsigned long long)samples, (unsigned long long)died,
                   (unsigned long long)diff);
            CHECK(diff == 0, "%s mode %d: paired = general integration, bit for bit (%llu words differ)", name, mode,
                  (unsigned long long)diff);
            CHECK(samples > runs * 4 * (uint64_t)lc_target_lanes((lc_target)t), "%s mode %d: samples integrated (%llu)", name, mode,
                  (unsigned long long)samples);
            if (mode == 0)
                CHECK(died > runs, "%s dvr: lanes become opaque within the pass (%llu)", name,
                      (unsigned long long)died);
            /* (a pass whose last sample no lane takes, or whose lanes are all opaque
               before it, integrates the same either way) */
            CHECK(broken * 4 >= runs * 3, "%s mode %d: a pass one sample short is caught (%llu of %llu)", name, mode,
                  (unsigned long long)broken, (unsigned long long)runs);
        }
        CHECK(fn(0, 0, 1, 0.9f, 0, mem, (uint64_t[3]){0}) == -1, "%s: nv 0 refused", name);
        tested++;
    }
    CHECK(tested > 0, "%d targets tested", tested);
    free(mem);
    return check_summary("test_particles_integrate");
}
