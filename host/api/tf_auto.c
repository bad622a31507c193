/* Default transfer functions that show structure on the first try
 * (lc_tf_auto). Grids: from the voxel histogram, by the rule documented in
 * lanecast.h and docs/FIRST-IMAGE.md. Particles and RBF sets: the colour
 * map with lc_tf_preset's ramp and a peak extinction of one per largest
 * radius or width. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "host/api/tf.h"
#include "host/mpi/dp.h" /* lci_test_fault */

#define NBINS 1024
#define SMOOTH 4 /* box filter half-width in bins before looking for valleys */

/* The rule's numbers for one grid (lc_tf_auto fills them; the tests and the
 * docs restate them). */
typedef struct auto_range {
    double lo, hi;      /* the TF's value range: background edge .. 99th percentile of the rest */
    int inverted;       /* 1: the informative side lies below the background */
} auto_range;

static void informative_range(const uint64_t *h, double vmin, double vmax, auto_range *r)
{
    double sm[NBINS];
    uint64_t total = 0;
    for (int i = 0; i < NBINS; i++) {
        double s = 0.0;
        int n = 0;
        for (int k = i - SMOOTH; k <= i + SMOOTH; k++)
            if (k >= 0 && k < NBINS) s += (double)h[k], n++;
        sm[i] = s / n;
        total += h[i];
    }
    int m = 0; /* the dominant mode */
    for (int i = 1; i < NBINS; i++)
        if (h[i] > h[m]) m = i;
    /* its hill: down to the first valley of the smoothed histogram on each side */
    int a = m, b = m;
    while (a > 0 && sm[a - 1] <= sm[a]) a--;
    while (b < NBINS - 1 && sm[b + 1] <= sm[b]) b++;
    uint64_t below = 0, above = 0;
    for (int i = 0; i < a; i++) below += h[i];
    for (int i = b + 1; i < NBINS; i++) above += h[i];
    double w = (vmax - vmin) / NBINS;
    r->inverted = below > above;
    uint64_t rest = r->inverted ? below : above;
    if (rest < total / 1000 + 1) { /* nothing but the mode: ramp over the whole range */
        r->lo = vmin, r->hi = vmax, r->inverted = 0;
        return;
    }
    /* 99th percentile of the rest, counted away from the hill */
    uint64_t want = rest - rest / 100, acc = 0;
    if (!r->inverted) {
        int i = b + 1;
        for (; i < NBINS - 1 && (acc += h[i]) < want; i++) {}
        r->lo = vmin + (b + 1) * w;
        r->hi = vmin + (i + 1) * w;
    } else {
        int i = a - 1;
        for (; i > 0 && (acc += h[i]) < want; i--) {}
        r->lo = vmin + i * w;
        r->hi = vmin + a * w;
    }
    if (!(r->hi > r->lo)) r->lo = vmin, r->hi = vmax, r->inverted = 0;
}

lc_status lc_tf_auto(lc_device *dev, const lc_volume *vol, const char *colormap, float max_tau, lc_tf **out)
{
    if (!out) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_tf_auto: out is NULL");
    *out = NULL;
    if (!vol) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_tf_auto: volume is NULL");
    if (!(max_tau >= 0.0f) || !isfinite(max_tau))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_tf_auto: max_tau = %g, expected a finite value >= 0 (0 = default)",
                         (double)max_tau);
    const float *cpts;
    int nc;
    lc_status s = lci_colormap(dev, colormap ? colormap : LC_TF_AUTO_COLORMAP, &cpts, &nc);
    if (s != LC_OK) return s;
    lc_volume_info vi;
    if ((s = lc_volume_get_info(vol, &vi)) != LC_OK) return s;
    float dx = vi.bounds.hi.x - vi.bounds.lo.x, dy = vi.bounds.hi.y - vi.bounds.lo.y, dz = vi.bounds.hi.z - vi.bounds.lo.z;
    float diag = sqrtf(dx * dx + dy * dy + dz * dz);
    if (vi.kind == LC_KIND_PARTICLES || vi.kind == LC_KIND_RBF) {
        float scale = 1.0f;
        if (vi.kind == LC_KIND_PARTICLES) {
            lc_particles_info pi;
            if ((s = lc_particles_get_info(vol, &pi)) != LC_OK) return s;
            scale = pi.max_radius;
        } else {
            lc_rbf_info ri;
            if ((s = lc_rbf_get_info(vol, &ri)) != LC_OK) return s;
            scale = ri.max_width;
        }
        float t = max_tau > 0.0f ? max_tau : scale > 0.0f ? 1.0f / scale : 1.0f;
        return lc_tf_preset(dev, colormap ? colormap : "heat", vi.nfields, t, out);
    }
    if (vi.kind != LC_KIND_GRID)
        return lci_error(dev, LC_ERROR_UNSUPPORTED, "lc_tf_auto: no default for %s volumes", lc_kind_name(vi.kind));
    lc_grid_info gi;
    if ((s = lc_grid_get_info(vol, &gi)) != LC_OK) return s;
    /* on the stack: a data-parallel part's histogram is a collective (the
       ranks sum their counts), which no rank may skip for a failed malloc */
    uint64_t h[NBINS];
    s = lc_grid_histogram(vol, NBINS, h);
    auto_range r;
    if (s == LC_OK) informative_range(h, gi.value_min, gi.value_max, &r);
    if (s != LC_OK) return s;
    /* past the collective, a rank that fails is agreed on by its caller
       (tests/test_cli_mpi_faults.sh injects one here) */
    if (lci_test_fault("tf")) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_tf_auto: out of memory");
    if (!(gi.value_max > gi.value_min)) r.lo = gi.value_min, r.hi = gi.value_min + 1.0, r.inverted = 0;
    float t = max_tau > 0.0f ? max_tau : (diag > 0.0f ? LC_TF_AUTO_TAU / diag : 1.0f);
    /* opacity: 0 at the background edge, a faint shelf over the lower part of
     * the informative range, full at its 99th percentile */
    float op[6] = {0.0f, 0.0f, 0.5f, 0.15f * t, 1.0f, t};
    if (r.inverted) op[0] = 0.0f, op[1] = t, op[2] = 0.5f, op[3] = 0.15f * t, op[4] = 1.0f, op[5] = 0.0f;
    lc_tf_field f;
    memset(&f, 0, sizeof f);
    f.color = cpts, f.ncolor = nc, f.opacity = op, f.nopacity = 3;
    f.has_range = 1, f.range[0] = (float)r.lo, f.range[1] = (float)r.hi;
    return lc_tf_create(dev, &f, 1, out);
}
