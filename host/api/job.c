/* Render jobs: lc_render's passes on a thread of their own, a preview at a
 * pixel scale then the full image, cancellable between tiles. lc_render_begin
 * validates and prepares every pass on the caller's thread, so the job's
 * thread only renders tiles and never records an error (the device's error
 * text stays the caller's). The pool takes one run at a time; a job queued
 * behind another gives up its wait when cancelled (lci_pool_wake). */
#include <errno.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "host/api/render.h"

struct lc_job {
    lc_device *dev;
    lc_render_desc desc;
    lc_job_desc jd;
    float *rgba;
    lc_tf *own_tf;
    lci_pass pass[2];
    int npasses;
    long long pixels[2]; /* rendered per pass, for the job's fraction */
    atomic_int stop;
    atomic_int done[2];  /* tiles finished per pass */
    pthread_t thread;
    double t0;
    /* under mu: */
    pthread_mutex_t mu;
    pthread_cond_t ended;
    lc_job_state state;
    int passes_done, last_scale;
    double t_end;
    lc_render_stats stats;
};

static double fraction_of(lc_job *j, int passes_done)
{
    long long total = 0, got = 0;
    for (int k = 0; k < j->npasses; k++) {
        total += j->pixels[k];
        if (k < passes_done) got += j->pixels[k];
        else if (k == passes_done)
            got += (long long)((double)j->pixels[k] * atomic_load_explicit(&j->done[k], memory_order_relaxed) /
                               (j->pass[k].ntasks > 0 ? j->pass[k].ntasks : 1));
    }
    return total > 0 ? (double)got / (double)total : 1.0;
}

static void finish(lc_job *j, lc_job_state st)
{
    pthread_mutex_lock(&j->mu);
    j->state = st;
    j->t_end = lci_now();
    j->stats.seconds = j->t_end - j->t0;
    pthread_cond_broadcast(&j->ended);
    pthread_mutex_unlock(&j->mu);
}

static void *job_main(void *arg)
{
    lc_job *j = arg;
    pthread_mutex_lock(&j->mu);
    if (j->state == LC_JOB_QUEUED) j->state = LC_JOB_RUNNING;
    pthread_mutex_unlock(&j->mu);
    const lc_render_desc *d = &j->desc;
    for (int k = 0; k < j->npasses; k++) {
        lci_pass *p = &j->pass[k];
        float span = (float)j->pixels[k] / (float)(j->pixels[0] + (j->npasses > 1 ? j->pixels[1] : 0));
        lci_pass_ctl ctl = {.stop = &j->stop, .cancel = d->cancel, .cancel_user = d->cancel_user,
                            .done = &j->done[k], .progress = d->progress, .progress_user = d->progress_user,
                            .base = k ? 1.0f - span : 0.0f, .span = span};
        if (!lci_pass_run(j->dev, p, &ctl, j->rgba, NULL)) {
            finish(j, LC_JOB_CANCELLED);
            return NULL;
        }
        pthread_mutex_lock(&j->mu);
        lci_pass_stats_add(p, &j->stats);
        j->passes_done = k + 1;
        j->last_scale = p->scale;
        pthread_mutex_unlock(&j->mu);
        int last = k == j->npasses - 1;
        if (last && d->progress) d->progress(d->progress_user, 1.0f);
        if (j->jd.on_pass) {
            lc_job_pass info = {k + 1, j->npasses, p->scale, last, j->rgba, d->width, d->height, lci_now() - j->t0};
            j->jd.on_pass(j->jd.user, &info);
        }
    }
    /* a cancel that came while the last pass's callback ran finds the image complete */
    finish(j, LC_JOB_DONE);
    return NULL;
}

static void job_free(lc_job *j)
{
    for (int k = 0; k < 2; k++) lci_pass_release(&j->pass[k]);
    lc_tf_destroy(j->own_tf);
    pthread_mutex_destroy(&j->mu);
    pthread_cond_destroy(&j->ended);
    free(j);
}

lc_status lc_render_begin(lc_device *dev, const lc_render_desc *d, const lc_job_desc *jd, float *rgba, lc_job **out)
{
    if (out) *out = NULL;
    lc_status s = lci_render_check(dev, d, rgba, "lc_render_begin");
    if (s != LC_OK) return s;
    if (!out) return lci_error(dev, LC_ERROR_INVALID_ARGUMENT, "lc_render_begin: out is NULL");
    int preview = jd ? jd->preview_scale : 0;
    if (preview != 0 && preview != 1 && preview != 2 && preview != 4 && preview != 8)
        return lci_error(dev, LC_ERROR_INVALID_ARGUMENT,
                         "lc_render_begin: preview_scale = %d, expected 0 (by image size), 1 (none), 2, 4 or 8", preview);
    lc_job *j = calloc(1, sizeof *j);
    if (!j) return lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_render_begin: out of memory");
    pthread_mutex_init(&j->mu, NULL);
    pthread_condattr_t ca;
    pthread_condattr_init(&ca);
    pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
    pthread_cond_init(&j->ended, &ca);
    pthread_condattr_destroy(&ca);
    j->dev = dev;
    j->desc = *d;
    if (jd) j->jd = *jd;
    j->rgba = rgba;
    const lc_tf *tf = NULL;
    s = lci_render_tf(dev, d, &tf, &j->own_tf);
    if (s != LC_OK) goto fail;
    int scales[2], n = 0;
    if (d->pixel_scale > 1) {
        scales[n++] = d->pixel_scale; /* navigation quality: one pass */
    } else {
        if (preview == 0) preview = lci_preview_scale(d->width, d->height);
        if (preview > 1) scales[n++] = preview;
        scales[n++] = 1;
    }
    for (int k = 0; k < n; k++) {
        s = lci_pass_prepare(dev, d, tf, scales[k], 0, &j->pass[k]);
        if (s != LC_OK) goto fail;
        j->pixels[k] = (long long)j->pass[k].pw * j->pass[k].ph;
    }
    j->npasses = n;
    j->stats.target = dev->target;
    j->stats.threads = lci_pool_threads(dev->pool);
    j->state = LC_JOB_QUEUED;
    j->t0 = lci_now();
    int e = pthread_create(&j->thread, NULL, job_main, j);
    if (e != 0) {
        s = lci_error(dev, LC_ERROR_OUT_OF_MEMORY, "lc_render_begin: cannot start the job's thread (%s)", strerror(e));
        goto fail;
    }
    *out = j;
    return LC_OK;
fail:
    job_free(j);
    return s;
}

lc_status lc_job_wait(lc_job *j, double timeout, lc_render_stats *stats)
{
    if (!j) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_job_wait: job is NULL");
    if (timeout != timeout) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_job_wait: timeout is NaN");
    struct timespec until;
    clock_gettime(CLOCK_MONOTONIC, &until);
    if (timeout > 0.0) {
        double t = timeout > 1e9 ? 1e9 : timeout;
        long long ns = (long long)until.tv_nsec + (long long)((t - (double)(long long)t) * 1e9);
        until.tv_sec += (time_t)t + (time_t)(ns / 1000000000LL);
        until.tv_nsec = (long)(ns % 1000000000LL);
    }
    pthread_mutex_lock(&j->mu);
    while (j->state == LC_JOB_QUEUED || j->state == LC_JOB_RUNNING) {
        if (timeout < 0.0) pthread_cond_wait(&j->ended, &j->mu);
        else if (timeout == 0.0 || pthread_cond_timedwait(&j->ended, &j->mu, &until) == ETIMEDOUT) break;
    }
    lc_job_state st = j->state;
    if (st == LC_JOB_DONE && stats) *stats = j->stats;
    pthread_mutex_unlock(&j->mu);
    if (st == LC_JOB_DONE) return LC_OK;
    if (st == LC_JOB_CANCELLED) return lci_error(NULL, LC_CANCELLED, "lc_job_wait: the job was cancelled; its image is not complete");
    return LC_TIMEOUT;
}

void lc_job_cancel(lc_job *j)
{
    if (!j) return;
    atomic_store_explicit(&j->stop, 1, memory_order_release);
    lci_pool_wake(j->dev->pool); /* a job waiting for the pool stops waiting */
}

lc_status lc_job_get_progress(const lc_job *job, lc_job_progress *out)
{
    if (!job || !out) return lci_error(NULL, LC_ERROR_INVALID_ARGUMENT, "lc_job_get_progress: job and out must not be NULL");
    lc_job *j = (lc_job *)job; /* the mutex only */
    pthread_mutex_lock(&j->mu);
    out->state = j->state;
    out->pass = j->passes_done;
    out->npasses = j->npasses;
    out->scale = j->last_scale;
    out->fraction = j->state == LC_JOB_DONE ? 1.0f : (float)fraction_of(j, j->passes_done);
    out->seconds = (j->state == LC_JOB_DONE || j->state == LC_JOB_CANCELLED ? j->t_end : lci_now()) - j->t0;
    pthread_mutex_unlock(&j->mu);
    return LC_OK;
}

void lc_job_destroy(lc_job *j)
{
    if (!j) return;
    lc_job_cancel(j);
    pthread_join(j->thread, NULL);
    job_free(j);
}
