/* Concurrency (issue 13): one shared scene of each kind (particles, grid,
 * RBF set) and one shared TF, rendered at once from several threads, each
 * with its own device (the API allows one thread per device at a time;
 * volumes and TFs are read-only while rendering), must give exactly the
 * bytes of the serial renders. Errors are per thread: lc_last_error on one
 * thread keeps its own message while others fail differently. Run under
 * ThreadSanitizer by scripts/tsan.sh. usage: test_concurrency [THREADS] */
#define _POSIX_C_SOURCE 200809L
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "scenes3.h"

#define W 80
#define H 60
#define ROUNDS 3
#define MAX_WORKERS 8

static scenes3 sc;
static float *serial[3];
static pthread_barrier_t barrier;

typedef struct worker {
    int id, threads;
    int mismatches, failures, error_mixups, renders;
    char first_problem[200];
} worker;

static void *work(void *arg)
{
    worker *w = arg;
    lc_device *dev = NULL;
    /* odd workers render with two pool threads each: two pools at once */
    if (lc_device_create(&(lc_device_desc){.target = LC_TARGET_AUTO, .threads = w->threads}, &dev) != LC_OK) {
        snprintf(w->first_problem, sizeof w->first_problem, "device: %s", lc_last_error());
        w->failures++;
        pthread_barrier_wait(&barrier);
        return NULL;
    }
    float *img = malloc(sizeof(float) * 4 * W * H);
    pthread_barrier_wait(&barrier); /* start together */
    for (int r = 0; r < ROUNDS && img; r++)
        for (int j = 0; j < 3; j++) {
            int k = (j + w->id + r) % 3; /* different scenes at the same moment */
            lc_render_desc d = scenes3_desc(&sc, k, W, H, 16);
            if (lc_render(dev, &d, img, NULL) != LC_OK) {
                if (!w->failures++)
                    snprintf(w->first_problem, sizeof w->first_problem, "%s: %s", sc.name[k], lc_last_error());
                continue;
            }
            w->renders++;
            if (memcmp(img, serial[k], sizeof(float) * 4 * W * H) != 0 && !w->mismatches++)
                snprintf(w->first_problem, sizeof w->first_problem, "%s: round %d differs from the serial render",
                         sc.name[k], r);
            /* an error of our own; its message must still be ours after the
             * other threads raised theirs */
            char want[64];
            snprintf(want, sizeof want, "tile = %d", -100 - w->id);
            lc_render_desc bad = d;
            bad.tile = -100 - w->id;
            lc_render(dev, &bad, img, NULL);
            if (!strstr(lc_last_error(), want) || !strstr(lc_device_last_error(dev), want)) w->error_mixups++;
        }
    free(img);
    lc_device_destroy(dev);
    return NULL;
}

int main(int argc, char **argv)
{
    int nworkers = argc > 1 ? atoi(argv[1]) : 4;
    if (nworkers < 2 || nworkers > MAX_WORKERS) nworkers = 4;
    lc_device *owner = NULL;
    if (lc_device_create(&(lc_device_desc){.target = LC_TARGET_AUTO, .threads = 1}, &owner) != LC_OK ||
        scenes3_create(owner, &sc) != 0) {
        printf("FAIL setup: %s\n", lc_last_error());
        return 1;
    }
    lc_target t;
    lc_device_target(owner, &t);
    printf("target %s, %d workers x %d rounds x 3 scenes\n", lc_target_name(t), nworkers, ROUNDS);
    for (int k = 0; k < 3; k++) {
        serial[k] = malloc(sizeof(float) * 4 * W * H);
        lc_render_desc d = scenes3_desc(&sc, k, W, H, 16);
        CHECK(serial[k] && lc_render(owner, &d, serial[k], NULL) == LC_OK, "serial render of %s", sc.name[k]);
        CHECK(serial[k] && scenes3_nontrivial(serial[k], W, H), "%s: the serial image shows the scene", sc.name[k]);
    }
    worker ws[MAX_WORKERS];
    pthread_t th[MAX_WORKERS];
    pthread_barrier_init(&barrier, NULL, (unsigned)nworkers);
    for (int i = 0; i < nworkers; i++) {
        ws[i] = (worker){.id = i, .threads = 1 + i % 2};
        pthread_create(&th[i], NULL, work, &ws[i]);
    }
    for (int i = 0; i < nworkers; i++) pthread_join(th[i], NULL);
    pthread_barrier_destroy(&barrier);
    for (int i = 0; i < nworkers; i++) {
        CHECK(ws[i].failures == 0 && ws[i].mismatches == 0 && ws[i].renders == 3 * ROUNDS,
              "worker %d (%d pool threads): %d renders identical to the serial ones (%d failed, %d differ)%s%s", i,
              ws[i].threads, ws[i].renders - ws[i].mismatches, ws[i].failures, ws[i].mismatches,
              ws[i].first_problem[0] ? ": " : "", ws[i].first_problem);
        CHECK(ws[i].error_mixups == 0, "worker %d: lc_last_error and its device's message stay its own (%d mix-ups)",
              i, ws[i].error_mixups);
    }
    /* the comparison can fail: a changed scene parameter changes the bytes */
    float *other = malloc(sizeof(float) * 4 * W * H);
    lc_render_desc d = scenes3_desc(&sc, 1, W, H, 16);
    d.dt = 0.9f * 0.125f;
    CHECK(other && lc_render(owner, &d, other, NULL) == LC_OK &&
              memcmp(other, serial[1], sizeof(float) * 4 * W * H) != 0,
          "control: another step size gives other bytes (the identity check can fail)");
    free(other);
    for (int k = 0; k < 3; k++) free(serial[k]);
    scenes3_destroy(&sc);
    lc_device_destroy(owner);
    return check_summary("concurrency");
}
