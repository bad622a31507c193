/* Brute-force structured-grid ray casting: every lattice sample of every ray
 * inside the domain, no BVH (the baseline of Knoll et al. 2011, and the
 * method the BVH path must match). */
#include "grid_common.h"
#include "kernels.h"

/* One tile in mode `mode` (a constant), the sample loop inlined. */
static inline __attribute__((always_inline)) void brute_tile(const lc_kgrid *g, const lc_kframe *f, int mode,
                                                             const lc_ktile *t, lc_kstats *st)
{
    for (int y = t->y0; y < t->y1; y += DVR_PH) {
        if (lc_ktile_stopped(t)) return;
        for (int x = t->x0; x < t->x1; x += DVR_PW) {
            gpk p;
            grid_packlet_init(g, f, t, x, y, &p);
            st->rays += (uint64_t)vm_popcnt(vm_and(vi_lt(p.px, vi_set1(t->x1)), vi_lt(p.py, vi_set1(t->y1))));
            if (mode == LC_KMODE_SLICE) grid_slice(g, f, t, &p, st);
            else if (vm_any(p.live)) grid_integrate_as(g, f, mode, &p, p.knext, p.klast, st);
            grid_finish_store(g, f, t, &p, st);
        }
    }
}

/* One function per mode, each with its sample loop and packlet setup
 * inlined as the brute-force dvr tile had them before iso (called out of
 * line, or with iso's loop in the same function, avx2 dvr frames were 1-3%
 * slower; bench/ab_compare.sh). */
static __attribute__((noinline)) void brute_mip(const lc_kgrid *g, const lc_kframe *f, const lc_ktile *t, lc_kstats *st)
{
    brute_tile(g, f, LC_KMODE_MIP, t, st);
}

static __attribute__((noinline)) void brute_iso(const lc_kgrid *g, const lc_kframe *f, const lc_ktile *t, lc_kstats *st)
{
    brute_tile(g, f, LC_KMODE_ISO, t, st);
}

static __attribute__((noinline)) void brute_slice(const lc_kgrid *g, const lc_kframe *f, const lc_ktile *t,
                                                  lc_kstats *st)
{
    brute_tile(g, f, LC_KMODE_SLICE, t, st);
}

void LC_KFN(grid_brute)(const void *scene, const lc_kframe *f, const lc_ktile *t, lc_kscratch *scratch, lc_kstats *st)
{
    const lc_kgrid *g = scene;
    (void)scratch;
    if (f->mode == LC_KMODE_MIP) brute_mip(g, f, t, st);
    else if (f->mode == LC_KMODE_ISO) brute_iso(g, f, t, st);
    else if (f->mode == LC_KMODE_SLICE) brute_slice(g, f, t, st);
    else brute_tile(g, f, LC_KMODE_DVR, t, st);
}
