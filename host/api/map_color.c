/* lc_map_colorize: a float map through a TF's colours (host/api/tf.c's
 * evaluation), on a log10 or linear scale, with an optional colour bar. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "host/api/tf.h"

int lc_map_colorbar_width(int width)
{
    int w = width / 16;
    return w < 12 ? 12 : w;
}

/* The 0.5th percentile of the positive values, from a histogram of log10
 * over [log min, log max] (4096 bins): robust against a few stray pixels. */
static float low_percentile(const float *v, size_t n, float mn, float mx)
{
    enum { NBIN = 4096 };
    if (!(mx > mn)) return mn;
    size_t *h = calloc(NBIN, sizeof *h), total = 0;
    if (!h) return mn;
    double l0 = log10(mn), l1 = log10(mx), sc = NBIN / (l1 - l0);
    for (size_t i = 0; i < n; i++)
        if (v[i] > 0.0f) {
            int b = (int)((log10(v[i]) - l0) * sc);
            h[b < 0 ? 0 : b >= NBIN ? NBIN - 1 : b]++, total++;
        }
    size_t want = total / 200, acc = 0;
    int b = 0;
    for (; b < NBIN && acc + h[b] <= want; b++) acc += h[b];
    free(h);
    return (float)pow(10.0, l0 + b / sc);
}

lc_status lc_map_colorize(lc_device *dev, const lc_map_color_desc *d, float *rgba, float used[2])
{
    if (!d || !d->values || !rgba)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_map_colorize: desc, values and rgba must not be NULL");
    if (d->width < 1 || d->height < 1 || d->width > LC_MAX_IMAGE_SIDE || d->height > LC_MAX_IMAGE_SIDE)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_map_colorize: size %dx%d, expected 1 to %d per side",
                         d->width, d->height, LC_MAX_IMAGE_SIDE);
    float lo = d->range[0], hi = d->range[1];
    int given = lo != 0.0f || hi != 0.0f;
    if (given && !(hi > lo && isfinite(lo) && isfinite(hi)))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_map_colorize: range [%g, %g]: expected finite lo < hi",
                         (double)lo, (double)hi);
    if (given && !d->linear && !(lo > 0.0f))
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "lc_map_colorize: range [%g, %g]: a log scale needs lo > 0 (or a linear scale)", (double)lo,
                         (double)hi);
    size_t n = (size_t)d->width * (size_t)d->height;
    if (!given) {
        float mn = INFINITY, mx = -INFINITY, mpos = INFINITY;
        for (size_t i = 0; i < n; i++) {
            float v = d->values[i];
            if (!isfinite(v)) continue;
            mn = fminf(mn, v), mx = fmaxf(mx, v);
            if (v > 0.0f) mpos = fminf(mpos, v);
        }
        if (d->linear) lo = isfinite(mn) ? mn : 0.0f, hi = isfinite(mx) ? mx : 1.0f;
        else if (isfinite(mpos)) lo = low_percentile(d->values, n, mpos, mx), hi = mx;
        else lo = 1.0f, hi = 10.0f; /* nothing positive: every pixel the lowest colour */
        if (!(hi > lo)) hi = d->linear ? lo + 1.0f : lo * 10.0f;
    }
    lc_tf *own = NULL;
    const lc_tf *tf = d->tf;
    if (!tf) {
        lc_status s = lc_tf_preset(dev, "viridis", 1, 1.0f, &own);
        if (s != LC_OK) return s;
        tf = own;
    }
    double a = d->linear ? lo : log10(lo), b = d->linear ? hi : log10(hi);
    int cb = d->colorbar ? lc_map_colorbar_width(d->width) : 0, stride = d->width + cb;
    for (int j = 0; j < d->height; j++)
        for (int i = 0; i < d->width; i++) {
            float v = d->values[(size_t)j * d->width + i];
            double x = d->linear ? v : (v > 0.0f ? log10(v) : -INFINITY);
            double t = (x - a) / (b - a);
            t = !(t > 0.0) ? 0.0 : t > 1.0 ? 1.0 : t; /* NaN and -inf: the lowest colour */
            double rgb[3], tau;
            lci_tf_eval(tf, 0, t, rgb, &tau);
            float *o = rgba + 4 * ((size_t)j * stride + i);
            o[0] = (float)rgb[0], o[1] = (float)rgb[1], o[2] = (float)rgb[2], o[3] = 1.0f;
        }
    for (int j = 0; j < d->height && cb; j++) { /* a black gap of a sixth, then the bar, top = hi */
        double t = d->height > 1 ? 1.0 - (double)j / (d->height - 1) : 1.0, rgb[3], tau;
        lci_tf_eval(tf, 0, t, rgb, &tau);
        for (int i = 0; i < cb; i++) {
            float *o = rgba + 4 * ((size_t)j * stride + d->width + i);
            int gap = i < cb / 6;
            o[0] = gap ? 0.0f : (float)rgb[0], o[1] = gap ? 0.0f : (float)rgb[1], o[2] = gap ? 0.0f : (float)rgb[2];
            o[3] = 1.0f;
        }
    }
    lc_tf_destroy(own);
    if (used) used[0] = lo, used[1] = hi;
    return LC_OK;
}
