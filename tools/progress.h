/* Progress on stderr for the render command: one line, updated in place,
 * shown only for work that has taken over a second (the caller decides
 * whether at all: a terminal and not --quiet). */
#ifndef LC_TOOLS_PROGRESS_H
#define LC_TOOLS_PROGRESS_H

#include <pthread.h>

double now_seconds(void);

/* A render's bar: render_progress is an lc_render_desc.progress callback
 * with a progress_state as its user pointer. */
typedef struct progress_state {
    const char *label; /* "rendering", "frame 3/36", ... */
    double t0;
    int shown;
} progress_state;
void progress_clear(progress_state *p);
void render_progress(void *user, float f);

/* Loading reports the fraction of the file read (lc_load_desc.progress);
 * building the volume (its BVH) none. A thread shows, after the first
 * second, a bar while reading and the elapsed time while building. */
typedef struct load_ticker {
    pthread_t thread;
    pthread_mutex_t mu;
    pthread_cond_t cv;
    int done, started;
    const char *what;
    double t0;
    float fraction; /* of the file read; -1 = none reported yet */
} load_ticker;
/* load_progress is an lc_load_desc.progress callback with the ticker as its
 * user pointer; ticker_start does nothing unless on (then t->started). */
void load_progress(void *user, float f);
void ticker_start(load_ticker *t, const char *what, int on);
void ticker_stop(load_ticker *t);

#endif
