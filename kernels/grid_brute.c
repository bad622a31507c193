/* Brute-force structured-grid ray casting: every lattice sample of every ray
 * inside the domain, no BVH (the baseline of Knoll et al. 2011, and the
 * method the BVH path must match). */
#include "grid_common.h"
#include "kernels.h"

void LC_KFN(grid_brute)(const void *scene, const lc_kframe *f, const lc_ktile *t, lc_kscratch *scratch, lc_kstats *st)
{
    const lc_kgrid *g = scene;
    (void)scratch;
    for (int y = t->y0; y < t->y1; y += DVR_PH) {
        for (int x = t->x0; x < t->x1; x += DVR_PW) {
            gpk p;
            grid_packlet_init(g, f, t, x, y, &p);
            st->rays += (uint64_t)vm_popcnt(vm_and(vi_lt(p.px, vi_set1(t->x1)), vi_lt(p.py, vi_set1(t->y1))));
            if (vm_any(p.live)) grid_integrate(g, f, &p, p.knext, p.klast, st);
            mode_finish(f, &p.c);
            dvr_store(t, p.px, p.py, &p.c);
        }
    }
}
