/* The TF editor's histogram, computed once on a thread of its own: grids
 * count their nodes (lc_grid_histogram); particles and RBF sets are sampled
 * (lc_volume_sample) on a 40^3 lattice over their bounds. Bins are log(1 +
 * count), scaled to a maximum of 1, over the data's value range. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "view.h"

#define LATTICE 40
#define CHUNK 4096

static pthread_t hist_thread;
static int hist_started;
static lc_volume *hist_volume; /* the first frame's: frames loaded later do not replace it while in use */

static void publish(view_state *v, double counts[LC_MAX_FIELDS][VIEW_HIST_BINS], int nfields, float lo, float hi)
{
    pthread_mutex_lock(&v->mu);
    v->hist.nfields = nfields;
    v->hist.range[0] = lo, v->hist.range[1] = hi;
    for (int f = 0; f < nfields; f++) {
        double m = 0.0;
        for (int b = 0; b < VIEW_HIST_BINS; b++) m = fmax(m, log1p(counts[f][b]));
        for (int b = 0; b < VIEW_HIST_BINS; b++)
            v->hist.log_counts[f][b] = m > 0.0 ? (float)(log1p(counts[f][b]) / m) : 0.0f;
    }
    v->hist.ready = 1;
    pthread_mutex_unlock(&v->mu);
    if (v->wake) v->wake();
}

static void grid_hist(view_state *v)
{
    uint64_t c[VIEW_HIST_BINS];
    lc_grid_info gi;
    if (lc_grid_get_info(hist_volume, &gi) != LC_OK || lc_grid_histogram(hist_volume, VIEW_HIST_BINS, c) != LC_OK) return;
    static double counts[LC_MAX_FIELDS][VIEW_HIST_BINS];
    for (int b = 0; b < VIEW_HIST_BINS; b++) counts[0][b] = (double)c[b];
    publish(v, counts, 1, gi.value_min, gi.value_max);
}

/* Samples in chunks, letting go of the volume between them (parameters may
 * change between chunks). */
static void sampled_hist(view_state *v, lc_device *dev)
{
    int nf = v->vinfo.nfields;
    size_t n = (size_t)LATTICE * LATTICE * LATTICE;
    float *val = malloc(sizeof(float) * n * (size_t)nf), *pts = malloc(sizeof(float) * 3 * CHUNK);
    static double counts[LC_MAX_FIELDS][VIEW_HIST_BINS];
    if (!val || !pts) goto out;
    lc_vec3 a = v->vinfo.bounds.lo, b = v->vinfo.bounds.hi;
    for (size_t i0 = 0; i0 < n; i0 += CHUNK) {
        size_t m = n - i0 < CHUNK ? n - i0 : CHUNK;
        for (size_t k = 0; k < m; k++) {
            size_t i = i0 + k, x = i % LATTICE, y = i / LATTICE % LATTICE, z = i / LATTICE / LATTICE;
            pts[3 * k] = a.x + (b.x - a.x) * ((float)x + 0.5f) / LATTICE;
            pts[3 * k + 1] = a.y + (b.y - a.y) * ((float)y + 0.5f) / LATTICE;
            pts[3 * k + 2] = a.z + (b.z - a.z) * ((float)z + 0.5f) / LATTICE;
        }
        pthread_mutex_lock(&v->mu);
        int quit = v->quit;
        pthread_mutex_unlock(&v->mu);
        pthread_mutex_lock(&v->vol_mu);
        lc_status s = quit ? LC_OK : lc_volume_sample(dev, hist_volume, m, pts, val + i0 * (size_t)nf, NULL);
        pthread_mutex_unlock(&v->vol_mu);
        if (quit || s != LC_OK) goto out;
    }
    float lo = v->vinfo.range[0], hi = v->vinfo.range[1];
    if (!(hi > lo)) hi = lo + 1.0f;
    for (size_t i = 0; i < n * (size_t)nf; i++) {
        float t = (val[i] - lo) / (hi - lo);
        if (!(t >= 0.0f && t <= 1.0f)) continue;
        int bin = (int)(t * VIEW_HIST_BINS);
        counts[i % (size_t)nf][bin < VIEW_HIST_BINS ? bin : VIEW_HIST_BINS - 1] += 1.0;
    }
    publish(v, counts, nf, lo, hi);
out:
    free(val);
    free(pts);
}

static void *hist_main(void *arg)
{
    view_state *v = arg;
    if (lc_volume_kind(hist_volume) == LC_KIND_GRID) {
        grid_hist(v);
    } else {
        lc_device *dev = NULL;
        lc_device_desc dd = {.threads = 1};
        if (lc_device_create(&dd, &dev) == LC_OK) sampled_hist(v, dev);
        lc_device_destroy(dev);
    }
    pthread_mutex_lock(&v->mu);
    v->hist_busy = 0;
    pthread_cond_broadcast(&v->cv);
    pthread_mutex_unlock(&v->mu);
    return NULL;
}

int view_hist_start(view_state *v)
{
    hist_volume = v->volume;
    v->hist_busy = 1;
    hist_started = pthread_create(&hist_thread, NULL, hist_main, v) == 0;
    if (!hist_started) v->hist_busy = 0;
    return hist_started ? 0 : -1;
}

void view_hist_stop(view_state *v)
{
    (void)v;
    if (hist_started) pthread_join(hist_thread, NULL);
    hist_started = 0;
}
