/* A small pthread pool for tile-parallel work: workers sleep on a condition
 * variable between jobs (no spinning that would slow an Embree build), take
 * tasks from an atomic counter, and run with denormals flushed. The calling
 * thread is worker 0 and takes tasks too. Runs from several threads (a
 * device's render jobs and its caller) take the pool one after another;
 * a waiting run gives up when its stop flag is set (lci_pool_wake). */
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <xmmintrin.h>
#include <pmmintrin.h>
#include "host/internal.h"

struct lci_pool {
    int nthreads; /* including the caller */
    pthread_t *tid;
    pthread_mutex_t mu;
    pthread_cond_t wake, done;
    uint64_t generation;
    int quit;
    int busy; /* workers still in the current job */
    lci_task_fn fn;
    void *ctx;
    int ntasks;
    atomic_int next;
    /* who runs now: one run at a time, the others wait on `free` */
    pthread_mutex_t owner_mu;
    pthread_cond_t freed;
    int owned;
};

typedef struct worker_arg {
    lci_pool *pool;
    int index;
} worker_arg;

void lci_flush_denormals(void)
{
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
}

static void drain(lci_pool *p, int worker)
{
    for (;;) {
        int t = atomic_fetch_add_explicit(&p->next, 1, memory_order_relaxed);
        if (t >= p->ntasks) break;
        p->fn(p->ctx, t, worker);
    }
}

static void *worker_main(void *arg)
{
    worker_arg *wa = arg;
    lci_pool *p = wa->pool;
    int index = wa->index;
    free(wa);
    lci_flush_denormals();
    uint64_t seen = 0;
    pthread_mutex_lock(&p->mu);
    for (;;) {
        while (!p->quit && p->generation == seen) pthread_cond_wait(&p->wake, &p->mu);
        if (p->quit) break;
        seen = p->generation;
        pthread_mutex_unlock(&p->mu);
        drain(p, index);
        pthread_mutex_lock(&p->mu);
        if (--p->busy == 0) pthread_cond_signal(&p->done);
    }
    pthread_mutex_unlock(&p->mu);
    return NULL;
}

lci_pool *lci_pool_create(int threads)
{
    lci_pool *p = calloc(1, sizeof *p);
    if (!p) return NULL;
    p->nthreads = threads < 1 ? 1 : threads;
    pthread_mutex_init(&p->mu, NULL);
    pthread_cond_init(&p->wake, NULL);
    pthread_cond_init(&p->done, NULL);
    pthread_mutex_init(&p->owner_mu, NULL);
    pthread_cond_init(&p->freed, NULL);
    if (p->nthreads > 1) {
        p->tid = calloc((size_t)p->nthreads - 1, sizeof *p->tid);
        if (!p->tid) goto fail;
        for (int i = 1; i < p->nthreads; i++) {
            worker_arg *wa = malloc(sizeof *wa);
            if (!wa) goto fail_threads;
            wa->pool = p;
            wa->index = i;
            if (pthread_create(&p->tid[i - 1], NULL, worker_main, wa) != 0) {
                free(wa);
                goto fail_threads;
            }
            continue;
        fail_threads:
            p->nthreads = i; /* threads 1..i-1 exist */
            lci_pool_destroy(p);
            return NULL;
        }
    }
    return p;
fail:
    free(p);
    return NULL;
}

void lci_pool_destroy(lci_pool *p)
{
    if (!p) return;
    pthread_mutex_lock(&p->mu);
    p->quit = 1;
    pthread_cond_broadcast(&p->wake);
    pthread_mutex_unlock(&p->mu);
    for (int i = 1; i < p->nthreads; i++) pthread_join(p->tid[i - 1], NULL);
    free(p->tid);
    pthread_mutex_destroy(&p->mu);
    pthread_cond_destroy(&p->wake);
    pthread_cond_destroy(&p->done);
    pthread_mutex_destroy(&p->owner_mu);
    pthread_cond_destroy(&p->freed);
    free(p);
}

int lci_pool_threads(const lci_pool *p) { return p->nthreads; }

static int acquire(lci_pool *p, const atomic_int *stop)
{
    pthread_mutex_lock(&p->owner_mu);
    while (p->owned && !(stop && atomic_load_explicit(stop, memory_order_acquire)))
        pthread_cond_wait(&p->freed, &p->owner_mu);
    int got = !p->owned;
    if (got) p->owned = 1;
    pthread_mutex_unlock(&p->owner_mu);
    return got;
}

static void release(lci_pool *p)
{
    pthread_mutex_lock(&p->owner_mu);
    p->owned = 0;
    pthread_cond_broadcast(&p->freed);
    pthread_mutex_unlock(&p->owner_mu);
}

void lci_pool_wake(lci_pool *p)
{
    pthread_mutex_lock(&p->owner_mu);
    pthread_cond_broadcast(&p->freed);
    pthread_mutex_unlock(&p->owner_mu);
}

static void run(lci_pool *p, int ntasks, lci_task_fn fn, void *ctx)
{
    unsigned int csr = _mm_getcsr();
    lci_flush_denormals();
    if (p->nthreads == 1 || ntasks == 1) {
        for (int t = 0; t < ntasks; t++) fn(ctx, t, 0);
        _mm_setcsr(csr);
        return;
    }
    pthread_mutex_lock(&p->mu);
    p->fn = fn;
    p->ctx = ctx;
    p->ntasks = ntasks;
    atomic_store(&p->next, 0);
    p->busy = p->nthreads - 1;
    p->generation++;
    pthread_cond_broadcast(&p->wake);
    pthread_mutex_unlock(&p->mu);
    drain(p, 0);
    pthread_mutex_lock(&p->mu);
    while (p->busy > 0) pthread_cond_wait(&p->done, &p->mu);
    pthread_mutex_unlock(&p->mu);
    _mm_setcsr(csr); /* the caller's FP mode is restored */
}

int lci_pool_run_until(lci_pool *p, int ntasks, lci_task_fn fn, void *ctx, const atomic_int *stop)
{
    if (ntasks <= 0) return 1;
    if (!acquire(p, stop)) return 0;
    run(p, ntasks, fn, ctx);
    release(p);
    return 1;
}

void lci_pool_run(lci_pool *p, int ntasks, lci_task_fn fn, void *ctx) { lci_pool_run_until(p, ntasks, fn, ctx, NULL); }
