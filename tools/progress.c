/* Progress on stderr for the render command (progress.h). */
#include <stdio.h>
#include <string.h>
#include <time.h>
#include "progress.h"

double now_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}


void progress_clear(progress_state *p)
{
    if (p->shown) fputs("\r\033[K", stderr), fflush(stderr);
    p->shown = 0;
}

void render_progress(void *user, float f)
{
    progress_state *p = user;
    if (now_seconds() - p->t0 < 1.0 && !p->shown) return;
    if (f >= 1.0f) {
        progress_clear(p);
        return;
    }
    char bar[31];
    int n = (int)(30.0f * f);
    for (int i = 0; i < 30; i++) bar[i] = i < n ? '#' : '.';
    bar[30] = '\0';
    fprintf(stderr, "\r%s [%s] %3d%%", p->label, bar, (int)(100.0f * f));
    fflush(stderr);
    p->shown = 1;
}


void load_progress(void *user, float f)
{
    load_ticker *t = user;
    if (!t->started) return;
    pthread_mutex_lock(&t->mu);
    t->fraction = f;
    pthread_mutex_unlock(&t->mu);
}

static void *ticker_main(void *arg)
{
    load_ticker *t = arg;
    static const char spin[] = "|/-\\";
    int shown = 0, k = 0;
    pthread_mutex_lock(&t->mu);
    while (!t->done) {
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        until.tv_nsec += 200000000L;
        if (until.tv_nsec >= 1000000000L) until.tv_sec++, until.tv_nsec -= 1000000000L;
        pthread_cond_timedwait(&t->cv, &t->mu, &until);
        double el = now_seconds() - t->t0;
        if (!t->done && el >= 1.0 && t->fraction >= 0.0f && t->fraction < 1.0f) {
            char bar[31];
            int n = (int)(30.0f * t->fraction);
            for (int i = 0; i < 30; i++) bar[i] = i < n ? '#' : '.';
            bar[30] = '\0';
            fprintf(stderr, "\r\033[Kreading %s [%s] %3d%%", t->what, bar, (int)(100.0f * t->fraction));
            fflush(stderr);
            shown = 1;
        } else if (!t->done && el >= 1.0) {
            fprintf(stderr, "\r\033[K%c %s %s  %.1f s", spin[k++ & 3], t->fraction >= 1.0f ? "building" : "loading and building",
                    t->what, el);
            fflush(stderr);
            shown = 1;
        }
    }
    if (shown) fputs("\r\033[K", stderr), fflush(stderr);
    pthread_mutex_unlock(&t->mu);
    return NULL;
}

void ticker_start(load_ticker *t, const char *what, int on)
{
    memset(t, 0, sizeof *t);
    if (!on) return;
    t->what = what;
    t->t0 = now_seconds();
    t->fraction = -1.0f;
    pthread_mutex_init(&t->mu, NULL);
    pthread_cond_init(&t->cv, NULL);
    t->started = pthread_create(&t->thread, NULL, ticker_main, t) == 0;
}

void ticker_stop(load_ticker *t)
{
    if (!t->started) return;
    pthread_mutex_lock(&t->mu);
    t->done = 1;
    pthread_cond_signal(&t->cv);
    pthread_mutex_unlock(&t->mu);
    pthread_join(t->thread, NULL);
    pthread_mutex_destroy(&t->mu);
    pthread_cond_destroy(&t->cv);
}
