/* Every change a user (mouse, keys, panels) or a --script makes in lanecast
 * view: each takes the state's lock, changes view_state.want and wakes the
 * render thread. Runs on the UI thread. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "view.h"

double view_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

void view_changed(view_state *v)
{
    v->want.gen++;
    pthread_cond_broadcast(&v->cv);
}

/* Adaptive navigation quality: the pixel scale of the next navigation
 * frame from the measured time of the last one, ms at scale s. A frame's
 * cost goes nearly as its pixel count, (1/s)^2, with a per-frame part that
 * does not shrink (BVH set-up per packet, threads' start), so: slower than
 * the target, jump to the scale predicted to meet it,
 * ceil(s sqrt(ms / target)) (at least s + 1, the fixed part makes the
 * prediction optimistic); faster, go one finer only when scale s - 1 is
 * predicted to stay under 0.8 x target (no oscillation between two
 * scales). One step at a time had taken 7 frames to settle on 1tw7 at
 * 1024^2 (docs/bench/view.md). */
int view_next_scale(int s, double ms, double target_ms, int smin)
{
    if (ms > target_ms) {
        int t = (int)ceil(s * sqrt(ms / target_ms));
        t = t > s ? t : s + 1;
        return t < 16 ? t : 16;
    }
    if (s > smin && ms * (double)(s * s) / (double)((s - 1) * (s - 1)) < 0.8 * target_ms) return s - 1;
    return s;
}

/* Called with v->mu held before each navigation frame starts, so the
 * frame that just ended always sets the scale of the next one. */
static void adapt(view_state *v)
{
    static uint64_t seen;
    if (!v->adaptive || v->shown.stats_gen == seen || !v->shown.nav) return;
    seen = v->shown.stats_gen;
    v->want.nav_scale = view_next_scale(v->want.nav_scale, 1e3 * v->shown.job_seconds, v->target_ms, v->min_nav_scale);
}

/* While a drag moves the camera, frames render at navigation quality. */
void view_drag_begin(view_state *v, view_drag_kind k, double x, double y)
{
    v->drag = k;
    v->last_x = x, v->last_y = y;
}

void view_drag_move(view_state *v, double x, double y)
{
    if (v->drag == VIEW_DRAG_NONE) return;
    float dx = (float)(x - v->last_x), dy = (float)(y - v->last_y);
    v->last_x = x, v->last_y = y;
    if (dx == 0.0f && dy == 0.0f) return;
    pthread_mutex_lock(&v->mu);
    lc_camera *c = &v->want.rd.camera;
    if (v->drag == VIEW_DRAG_ORBIT) view_cam_orbit(c, dx, dy, v->want.rd.height);
    else view_cam_pan(c, dx, dy, v->want.rd.height);
    v->want.nav = 1;
    v->release_at = 0.0;
    adapt(v);
    view_changed(v);
    pthread_mutex_unlock(&v->mu);
}

/* The release: the full frame starts after refine_delay (default at once). */
void view_drag_end(view_state *v)
{
    if (v->drag == VIEW_DRAG_NONE) return;
    v->drag = VIEW_DRAG_NONE;
    v->release_at = view_now() + v->refine_delay;
    view_tick(v);
}

/* A wheel has no release: the full frame follows a pause of the wheel. */
void view_wheel(view_state *v, double steps)
{
    pthread_mutex_lock(&v->mu);
    view_cam_zoom(&v->want.rd.camera, (float)steps);
    v->want.nav = 1;
    adapt(v);
    view_changed(v);
    pthread_mutex_unlock(&v->mu);
    v->release_at = view_now() + (v->refine_delay > 0.1 ? v->refine_delay : 0.1);
}

void view_reset(view_state *v)
{
    pthread_mutex_lock(&v->mu);
    v->want.rd.camera = v->home;
    v->want.nav = 0;
    view_changed(v);
    pthread_mutex_unlock(&v->mu);
}

void view_set_size(view_state *v, int w, int h)
{
    if (w < 1 || h < 1 || w > LC_MAX_IMAGE_SIDE || h > LC_MAX_IMAGE_SIDE) return;
    pthread_mutex_lock(&v->mu);
    if (v->want.rd.width != w || v->want.rd.height != h) {
        v->want.rd.width = w, v->want.rd.height = h;
        view_changed(v);
    }
    pthread_mutex_unlock(&v->mu);
}

void view_tick(view_state *v)
{
    pthread_mutex_lock(&v->mu);
    view_frames_tick(v);
    if (v->release_at > 0.0 && view_now() >= v->release_at && v->drag == VIEW_DRAG_NONE) {
        v->release_at = 0.0;
        if (v->want.nav) {
            v->want.nav = 0;
            view_changed(v);
        }
    }
    pthread_mutex_unlock(&v->mu);
}

/* The next free lanecast-view-NNN.png in the current folder. */
static void next_name(view_state *v, char *out, size_t n)
{
    for (;;) {
        snprintf(out, n, "lanecast-view-%03d.png", v->saved_count++);
        if (access(out, F_OK) != 0) return;
    }
}

int view_save(view_state *v, lc_device *dev, const char *path)
{
    char name[4096];
    if (path) snprintf(name, sizeof name, "%s", path);
    else next_name(v, name, sizeof name);
    pthread_mutex_lock(&v->mu);
    if (!v->refined || v->refined_gen != v->want.gen) {
        pthread_mutex_unlock(&v->mu);
        snprintf(v->status, sizeof v->status, "no refined frame to save yet");
        return -1;
    }
    size_t n = (size_t)v->shown.width * (size_t)v->shown.height * 4;
    float *copy = malloc(n * sizeof(float));
    int w = v->shown.width, h = v->shown.height;
    if (copy) memcpy(copy, v->refined, n * sizeof(float));
    pthread_mutex_unlock(&v->mu);
    if (!copy) {
        snprintf(v->status, sizeof v->status, "out of memory saving %s", name);
        fprintf(stderr, "%s: %s\n", v->cmd, v->status);
        return -1;
    }
    lc_image_desc id = {w, h, copy, v->background, v->alpha};
    lc_status s = lc_image_write(dev, name, &id);
    free(copy);
    if (s != LC_OK) {
        snprintf(v->status, sizeof v->status, "%s", lc_last_error());
        fprintf(stderr, "%s: %s\n", v->cmd, v->status);
        return -1;
    }
    snprintf(v->status, sizeof v->status, "wrote %s (%dx%d)", name, w, h);
    printf("wrote %s (%dx%d)\n", name, w, h);
    fflush(stdout);
    return 0;
}

void view_print_camera(view_state *v)
{
    char line[512];
    pthread_mutex_lock(&v->mu);
    view_cam_format(&v->want.rd.camera, line, sizeof line);
    pthread_mutex_unlock(&v->mu);
    printf("%s\n", line);
    fflush(stdout);
    snprintf(v->status, sizeof v->status, "%s", line);
}

int view_failed(view_state *v)
{
    pthread_mutex_lock(&v->mu);
    int r = v->shown.failed_gen == v->want.gen;
    pthread_mutex_unlock(&v->mu);
    return r;
}

int view_refined(view_state *v)
{
    pthread_mutex_lock(&v->mu);
    int r = v->refined_gen == v->want.gen && !v->want.nav && v->release_at == 0.0 && v->frame_want < 0 &&
            v->frame_loading < 0 && !v->next_volume;
    pthread_mutex_unlock(&v->mu);
    return r;
}

int view_key(view_state *v, const char *key)
{
    if (!strcmp(key, "r")) view_reset(v);
    else if (!strcmp(key, "s")) v->save_pending++;
    else if (!strcmp(key, "c")) view_print_camera(v);
    else if (!strcmp(key, "h")) v->show_ui = !v->show_ui;
    else if (!strcmp(key, "b")) v->show_box = !v->show_box;
    else if (!strcmp(key, "q") || !strcmp(key, "escape")) v->quit_asked = 1;
    else return 0;
    return 1;
}
