/* CPU feature detection and the table of compiled targets. A target counts as
 * supported only if the CPU has the instructions and the OS saves the register
 * state (XCR0 via xgetbv), so forcing a target never ends in SIGILL. */
#include <cpuid.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "host/internal.h"

typedef struct cpu_caps {
    int sse42, avx, avx2, fma, f16c, avx512f, avx512dq, avx512bw, avx512vl, os_avx, os_avx512;
} cpu_caps;

static uint64_t xgetbv0(void)
{
    uint32_t eax, edx;
    __asm__ volatile("xgetbv" : "=a"(eax), "=d"(edx) : "c"(0));
    return ((uint64_t)edx << 32) | eax;
}

static cpu_caps detect(void)
{
    cpu_caps c;
    memset(&c, 0, sizeof c);
    unsigned a, b, cx, d;
    if (!__get_cpuid(1, &a, &b, &cx, &d)) return c;
    c.sse42 = (cx >> 20) & 1;
    c.fma = (cx >> 12) & 1;
    c.avx = (cx >> 28) & 1;
    int osxsave = (cx >> 27) & 1;
    if (osxsave) {
        uint64_t xcr0 = xgetbv0();
        c.os_avx = (xcr0 & 0x6) == 0x6;            /* XMM and YMM state */
        c.os_avx512 = (xcr0 & 0xe6) == 0xe6;       /* plus opmask, ZMM_Hi256, Hi16_ZMM */
    }
    if (__get_cpuid_max(0, NULL) >= 7) {
        __cpuid_count(7, 0, a, b, cx, d);
        c.avx2 = (b >> 5) & 1;
        c.avx512f = (b >> 16) & 1;
        c.avx512dq = (b >> 17) & 1;
        c.avx512bw = (b >> 30) & 1;
        c.avx512vl = (b >> 31) & 1;
    }
    return c;
}

/* Test hook: LANECAST_CPU_MASK=scalar,sse4 pretends the CPU has only these
 * (for testing refusal of unsupported targets on a machine that has them). */
static int masked_out(lc_target t)
{
    const char *m = getenv("LANECAST_CPU_MASK");
    if (!m || !*m) return 0;
    const char *name = lc_target_name(t);
    size_t n = strlen(name);
    for (const char *p = m; *p;) {
        const char *e = strchr(p, ',');
        size_t len = e ? (size_t)(e - p) : strlen(p);
        if (len == n && strncmp(p, name, n) == 0) return 0;
        if (!e) break;
        p = e + 1;
    }
    return 1;
}

const char *lci_cpu_missing(lc_target target)
{
    cpu_caps c = detect();
    if (target != LC_TARGET_AUTO && target != LC_TARGET_SCALAR && masked_out(target))
        return "the instructions (masked by LANECAST_CPU_MASK)";
    switch (target) {
    case LC_TARGET_AUTO:
    case LC_TARGET_SCALAR: return "";
    case LC_TARGET_SSE4: return c.sse42 ? "" : "SSE4.2";
    case LC_TARGET_AVX2:
        if (!c.avx2 || !c.fma) return "AVX2/FMA instructions";
        return c.os_avx ? "" : "OS support for AVX state";
    case LC_TARGET_AVX512:
    case LC_TARGET_AVX512_8: /* same instructions, 256-bit vectors (VL) */
        if (!(c.avx512f && c.avx512dq && c.avx512bw && c.avx512vl)) return "AVX-512 F/DQ/BW/VL instructions";
        return c.os_avx512 ? "" : "OS support for AVX-512 state";
    default: return "a valid target";
    }
}

int lci_cpu_supports(lc_target target) { return lci_cpu_missing(target)[0] == '\0'; }

const lc_ktable *lci_ktable(lc_target target)
{
    switch (target) {
    case LC_TARGET_SCALAR: return &lc_ktable_scalar;
#ifdef LC_HAVE_SSE4
    case LC_TARGET_SSE4: return &lc_ktable_sse4;
#endif
#ifdef LC_HAVE_AVX2
    case LC_TARGET_AVX2: return &lc_ktable_avx2;
#endif
#ifdef LC_HAVE_AVX512
    case LC_TARGET_AVX512: return &lc_ktable_avx512;
#endif
#ifdef LC_HAVE_AVX512_8
    case LC_TARGET_AVX512_8: return &lc_ktable_avx512_8;
#endif
    default: return NULL;
    }
}

/* Widest first. avx512_8 comes after avx512 (it is a width study: the same
 * CPU always runs the 16-lane one) and before avx2 (same width, a superset of
 * its instructions), so AUTO lands on it only if avx512 is not compiled in or
 * masked out. Appending to the enum must not change this order. */
static const lc_target auto_order[] = {LC_TARGET_AVX512, LC_TARGET_AVX512_8, LC_TARGET_AVX2, LC_TARGET_SSE4,
                                       LC_TARGET_SCALAR};
_Static_assert(sizeof auto_order / sizeof auto_order[0] == LC_TARGET_COUNT - 1,
               "every target except AUTO has a place in auto_order");

lc_target lci_target_auto(void)
{
    for (size_t i = 0; i < sizeof auto_order / sizeof auto_order[0]; i++)
        if (lc_target_compiled(auto_order[i]) && lci_cpu_supports(auto_order[i])) return auto_order[i];
    return LC_TARGET_SCALAR; /* always compiled, always supported */
}

static const char *const target_names[LC_TARGET_COUNT] = {"auto", "scalar", "sse4", "avx2", "avx512", "avx512_8"};

const char *lc_target_name(lc_target target)
{
    if ((int)target < 0 || target >= LC_TARGET_COUNT) return NULL;
    return target_names[target];
}

lc_status lc_target_from_name(const char *name, lc_target *out)
{
    if (!name) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_target_from_name: name is NULL");
    if (!out) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_target_from_name: out is NULL");
    for (int t = 0; t < LC_TARGET_COUNT; t++) {
        if (strcmp(name, target_names[t]) == 0) {
            *out = (lc_target)t;
            return LC_OK;
        }
    }
    return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT,
                     "unknown target '%s' (known: " LCI_TARGET_NAMES ")", name);
}

int lc_target_compiled(lc_target target)
{
    if (target == LC_TARGET_AUTO) return 1;
    return lci_ktable(target) != NULL;
}

int lc_target_supported(lc_target target)
{
    if ((int)target < 0 || target >= LC_TARGET_COUNT) return 0;
    return lci_cpu_supports(target);
}

int lc_target_lanes(lc_target target)
{
    static const int lanes[LC_TARGET_COUNT] = {0, 1, 4, 8, 16, 8};
    if ((int)target < 0 || target >= LC_TARGET_COUNT) return 0;
    return lanes[target];
}
