/* A render as passes (host/api/render.c): lc_render runs one, a render job
 * (host/api/job.c) a preview and the full image. A pass is the frame built
 * and the volume prepared at one pixel scale, with its scratch and counters;
 * preparing does all the validation and allocation, so running one only
 * renders tiles (never an error, never a message). */
#ifndef LC_HOST_RENDER_H
#define LC_HOST_RENDER_H

#include <stdatomic.h>
#include "host/kinds/kind.h"

typedef struct lci_pass_stats lci_pass_stats; /* per-worker counters */

typedef struct lci_pass {
    int scale;           /* every scale-th pixel; 1 = all */
    int width, height;   /* the full image */
    int pw, ph;          /* pixels rendered: ceil(width / scale) x ceil(height / scale) */
    int tile, ntx, ntasks;
    int nthreads;
    float *tables;       /* the frame's TF tables */
    lc_kframe *frame;
    lci_prepared prep;
    unsigned char *scratch;
    uint64_t scratch_bytes; /* per worker */
    lci_pass_stats *ws;
    float *small, *small_depth; /* scale > 1: the pw x ph pixels before filling blocks */
    int carry;           /* dvr at scale 1: rays go on from the (C, A) in the image (lc_ktile carry) */
} lci_pass;

/* Checks what lc_render checks before the frame (handles, sizes, tile,
 * pixel_scale); fn names the caller in messages. */
lc_status lci_render_check(lc_device *dev, const lc_render_desc *d, const float *rgba, const char *fn);
/* Builds the frame at pixel scale `scale` (1 .. 16) and prepares the volume
 * for it; tf is the TF to use (the desc's or a default). Released with
 * lci_pass_release also on failure. */
lc_status lci_pass_prepare(lc_device *dev, const lc_render_desc *d, const lc_tf *tf, int scale, int depth,
                           lci_pass *out);
void lci_pass_release(lci_pass *p);
/* lci_pass_prepare for the part of each ray inside region (NULL: all of
 * it; kernels/dvr.h dvr_region), for data-parallel rendering (host/mpi/). */
lc_status lci_pass_prepare_region(lc_device *dev, const lc_render_desc *d, const lc_tf *tf, int scale, int depth,
                                  const lc_kregion *region, lci_pass *out);
/* The TF a desc renders with: its own, or the default ("heat"), which *own
 * then holds (lc_tf_destroy; NULL otherwise). */
lc_status lci_render_tf(lc_device *dev, const lc_render_desc *d, const lc_tf **tf, lc_tf **own);
/* lci_render (host/internal.h) of the samples inside region (NULL: all). */
lc_status lci_render_region(lc_device *dev, const lc_render_desc *d, const lc_kregion *region, float *rgba,
                            float *depth, lc_render_stats *stats);

/* Where a pass's tiles stop and report. stop, when not NULL, is a job's
 * flag; cancel is the desc's callback; done counts finished tiles (for
 * progress from other threads); the desc's progress callback, when set,
 * gets base + span * (tiles done / tiles). */
typedef struct lci_pass_ctl {
    const atomic_int *stop;
    int (*cancel)(void *user);
    void *cancel_user;
    atomic_int *done;
    void (*progress)(void *user, float fraction);
    void *progress_user;
    float base, span;
    int row0, row1;      /* row1 > row0: only the pixel rows [row0, row1), the rest untouched */
} lci_pass_ctl;

/* Renders the pass into rgba (and depth, when not NULL): width x height,
 * every pixel written. 1 when every tile ran, 0 when stopped or cancelled
 * (the image then holds some tiles). */
int lci_pass_run(lc_device *dev, lci_pass *p, const lci_pass_ctl *ctl, float *rgba, float *depth);
/* Adds the pass's counters to *acc (rays, samples, ... ; not seconds). */
void lci_pass_stats_add(const lci_pass *p, lc_render_stats *acc);

/* The default pixel scale of a job's preview pass for an image (2, 4 or 8). */
int lci_preview_scale(int width, int height);

#endif
