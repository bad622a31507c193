/* Target dispatch: explicit targets, LANECAST_TARGET, their precedence, bad
 * values, and refusal of targets the CPU lacks (simulated with the
 * LANECAST_CPU_MASK test hook of host/cpu.c). */
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include "lanecast/lanecast.h"
#include "check.h"

static const int expected_lanes[LC_TARGET_COUNT] = {0, 1, 4, 8, 16, 8};

/* AUTO's preference, spelled out independently of host/cpu.c: widest first,
 * and at equal width avx512_8 before avx2. Not the enum order. */
static const lc_target auto_order[] = {LC_TARGET_AVX512, LC_TARGET_AVX512_8, LC_TARGET_AVX2, LC_TARGET_SSE4,
                                       LC_TARGET_SCALAR};

static int usable(lc_target t) { return lc_target_compiled(t) && lc_target_supported(t); }

static lc_target expected_auto(void)
{
    for (size_t i = 0; i < sizeof auto_order / sizeof auto_order[0]; i++)
        if (usable(auto_order[i])) return auto_order[i];
    return LC_TARGET_SCALAR;
}

/* Creates a device and returns its status; *got receives its target. */
static lc_status create(lc_target requested, lc_target *got)
{
    static char garbage;
    lc_device *dev = (lc_device *)&garbage; /* must be reset to NULL on failure */
    lc_status s = lc_device_create(&(lc_device_desc){.target = requested, .threads = 1}, &dev);
    *got = LC_TARGET_AUTO;
    if (s == LC_OK) lc_device_target(dev, got);
    else if (dev != NULL) {
        printf("FAIL lc_device_create failed but left *out non-NULL\n");
        check_failures++;
        dev = NULL;
    }
    lc_device_destroy(dev);
    return s;
}

static void names_and_lanes(void)
{
    for (int t = 0; t < LC_TARGET_COUNT; t++) {
        const char *name = lc_target_name((lc_target)t);
        lc_target back = LC_TARGET_COUNT;
        CHECK(name && lc_target_from_name(name, &back) == LC_OK && back == (lc_target)t,
              "lc_target_name(%d) = '%s' parses back to %d", t, name ? name : "(null)", (int)back);
        CHECK(lc_target_lanes((lc_target)t) == expected_lanes[t], "lc_target_lanes(%s) = %d", name,
              lc_target_lanes((lc_target)t));
    }
    CHECK(lc_target_name((lc_target)-1) == NULL && lc_target_name(LC_TARGET_COUNT) == NULL,
          "lc_target_name of -1 and LC_TARGET_COUNT is NULL");
    CHECK(lc_target_lanes((lc_target)-1) == 0 && lc_target_lanes(LC_TARGET_COUNT) == 0, "lanes of invalid targets = 0");
    lc_target t = LC_TARGET_SSE4;
    CHECK(lc_target_from_name("AVX2", &t) == LC_ERROR_INVALID_ARGUMENT && t == LC_TARGET_SSE4 &&
              strstr(lc_last_error(), "AVX2"),
          "lc_target_from_name is case-sensitive, leaves *out alone, names the bad value: %s", lc_last_error());
    CHECK(lc_target_compiled(LC_TARGET_SCALAR) && lc_target_supported(LC_TARGET_SCALAR),
          "scalar is always compiled and supported");
    CHECK(lc_target_supported(LC_TARGET_AUTO), "AUTO is always supported");
}

static void explicit_and_env(void)
{
    lc_target got;
    unsetenv("LANECAST_TARGET");
    int widest = expected_auto();
    CHECK(create(LC_TARGET_AUTO, &got) == LC_OK && got == (lc_target)widest, "AUTO picks the widest usable: %s",
          lc_target_name(got));
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++)
        CHECK(lc_target_lanes((lc_target)t) <= lc_target_lanes((lc_target)widest) || !usable((lc_target)t),
              "AUTO's %s is at least as wide as usable %s", lc_target_name((lc_target)widest),
              lc_target_name((lc_target)t));
    if (usable(LC_TARGET_AVX512))
        CHECK(widest == LC_TARGET_AVX512, "AUTO keeps the 16-lane avx512 over avx512_8 (got %s)",
              lc_target_name((lc_target)widest));
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        const char *name = lc_target_name((lc_target)t);
        if (!usable((lc_target)t)) {
            CHECK(create((lc_target)t, &got) == LC_ERROR_UNSUPPORTED, "explicit %s unusable here: refused", name);
            continue;
        }
        CHECK(create((lc_target)t, &got) == LC_OK && got == (lc_target)t, "explicit %s -> device target %s", name,
              lc_target_name(got));
        setenv("LANECAST_TARGET", name, 1);
        CHECK(create(LC_TARGET_AUTO, &got) == LC_OK && got == (lc_target)t, "LANECAST_TARGET=%s, AUTO -> %s", name,
              lc_target_name(got));
        /* an explicit target wins over the variable */
        lc_target other = t == LC_TARGET_SCALAR ? (lc_target)widest : LC_TARGET_SCALAR;
        CHECK(create(other, &got) == LC_OK && got == other, "LANECAST_TARGET=%s, explicit %s -> %s", name,
              lc_target_name(other), lc_target_name(got));
    }
    setenv("LANECAST_TARGET", "auto", 1);
    CHECK(create(LC_TARGET_AUTO, &got) == LC_OK && got == (lc_target)widest, "LANECAST_TARGET=auto -> %s",
          lc_target_name(got));
    setenv("LANECAST_TARGET", "bogus", 1);
    lc_status s = create(LC_TARGET_AUTO, &got);
    CHECK(s == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "bogus"),
          "LANECAST_TARGET=bogus -> %s: %s", lc_status_string(s), lc_last_error());
    CHECK(create(LC_TARGET_SCALAR, &got) == LC_OK && got == LC_TARGET_SCALAR,
          "LANECAST_TARGET=bogus is ignored when the target is explicit");
    unsetenv("LANECAST_TARGET");
    static const int bad_targets[] = {-1, LC_TARGET_COUNT, 99, INT_MAX};
    for (size_t i = 0; i < sizeof bad_targets / sizeof bad_targets[0]; i++) {
        int bad = bad_targets[i];
        char num[16];
        snprintf(num, sizeof num, "%d", bad);
        s = create((lc_target)bad, &got);
        CHECK(s == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), num), "desc.target = %d -> %s: %s", bad,
              lc_status_string(s), lc_last_error());
    }
}

/* The hook pretends the CPU has only scalar and SSE4. */
static void simulated_old_cpu(void)
{
    setenv("LANECAST_CPU_MASK", "scalar,sse4", 1);
    lc_target got;
    for (int t = LC_TARGET_AVX2; t < LC_TARGET_COUNT; t++) {
        const char *name = lc_target_name((lc_target)t);
        CHECK(!lc_target_supported((lc_target)t), "masked CPU: %s reported unsupported", name);
        lc_status s = create((lc_target)t, &got);
        CHECK(s == LC_ERROR_UNSUPPORTED && strstr(lc_last_error(), name), "masked CPU: explicit %s -> %s: %s", name,
              lc_status_string(s), lc_last_error());
        setenv("LANECAST_TARGET", name, 1);
        s = create(LC_TARGET_AUTO, &got);
        CHECK(s == LC_ERROR_UNSUPPORTED, "masked CPU: LANECAST_TARGET=%s -> %s", name, lc_status_string(s));
        unsetenv("LANECAST_TARGET");
    }
    lc_target want = usable(LC_TARGET_SSE4) ? LC_TARGET_SSE4 : LC_TARGET_SCALAR;
    CHECK(create(LC_TARGET_AUTO, &got) == LC_OK && got == want, "masked CPU: AUTO falls back to %s",
          lc_target_name(got));
    unsetenv("LANECAST_CPU_MASK");
}

/* AUTO's order among the wide targets, by masking some of them out: each
 * case is the expected_auto() of that pretended CPU. */
static void auto_order_masked(void)
{
    static const char *const masks[] = {"scalar,sse4,avx2,avx512,avx512_8", "scalar,sse4,avx2,avx512_8",
                                        "scalar,sse4,avx2", "scalar,sse4,avx512", "scalar,sse4,avx512_8"};
    for (size_t i = 0; i < sizeof masks / sizeof masks[0]; i++) {
        setenv("LANECAST_CPU_MASK", masks[i], 1);
        lc_target got, want = expected_auto();
        CHECK(create(LC_TARGET_AUTO, &got) == LC_OK && got == want, "LANECAST_CPU_MASK=%s: AUTO -> %s (want %s)",
              masks[i], lc_target_name(got), lc_target_name(want));
    }
    unsetenv("LANECAST_CPU_MASK");
    if (usable(LC_TARGET_AVX512) && usable(LC_TARGET_AVX512_8) && usable(LC_TARGET_AVX2)) {
        /* on this machine the expectations above are concrete: spell them out */
        lc_target got;
        setenv("LANECAST_CPU_MASK", "scalar,sse4,avx2,avx512_8", 1);
        CHECK(create(LC_TARGET_AUTO, &got) == LC_OK && got == LC_TARGET_AVX512_8,
              "without avx512, AUTO takes avx512_8 over avx2 (got %s)", lc_target_name(got));
        setenv("LANECAST_CPU_MASK", "scalar,sse4,avx2", 1);
        CHECK(create(LC_TARGET_AUTO, &got) == LC_OK && got == LC_TARGET_AVX2, "without AVX-512, AUTO takes avx2 (got %s)",
              lc_target_name(got));
        unsetenv("LANECAST_CPU_MASK");
    }
}

int main(void)
{
    unsetenv("LANECAST_CPU_MASK");
    names_and_lanes();
    explicit_and_env();
    simulated_old_cpu();
    auto_order_masked();
    return check_summary("test_dispatch");
}
