/* Frames of multi-frame inputs (trajectories, PDB models, NIfTI 4-D): a
 * loader thread with a device of its own loads the asked-for frame through
 * the render command's loader (render_load) and hands the volume to the
 * render thread (view_state.next_volume), which swaps it in between jobs
 * and retires the old one; the loader destroys retired volumes. A failed
 * load leaves the current frame on screen with the error in the overlay. */
#include <stdio.h>
#include <string.h>
#include "render_opts.h"
#include "view.h"

static pthread_t frames_thread;
static int frames_started;

/* Takes the loaded volume if one waits (the render thread, between jobs, mu held). */
lc_volume *view_frames_take(view_state *v, int64_t *frame)
{
    if (!v->next_volume || v->retired) return NULL; /* the loader has not destroyed the last one yet */
    lc_volume *n = v->next_volume;
    v->next_volume = NULL;
    *frame = v->next_frame;
    pthread_cond_broadcast(&v->cv);
    return n;
}

static void *frames_main(void *arg)
{
    view_state *v = arg;
    lc_device *dev = v->frames_dev;
    pthread_mutex_lock(&v->mu);
    for (;;) {
        while (!v->quit && (v->frame_want < 0 || v->next_volume) && !(v->retired && !v->hist_busy))
            pthread_cond_wait(&v->cv, &v->mu);
        if (v->quit) break;
        if (v->retired && !v->hist_busy) {
            lc_volume *old = v->retired;
            v->retired = NULL;
            pthread_cond_broadcast(&v->cv);
            pthread_mutex_unlock(&v->mu);
            lc_volume_destroy(old);
            pthread_mutex_lock(&v->mu);
            if (v->next_volume) view_changed(v); /* the render thread may take it now */
            continue;
        }
        int64_t f = v->frame_want;
        v->frame_want = -1;
        v->frame_loading = f;
        pthread_mutex_unlock(&v->mu);
        lc_volume *vol = NULL;
        lc_tf *keep = v->initial_tf; /* set: render_load builds no TF */
        lc_status s = render_load(v->ro, dev, 0, v->kind, f, &vol, &keep);
        pthread_mutex_lock(&v->mu);
        v->frame_loading = -1;
        if (s == LC_OK) {
            v->next_volume = vol;
            v->next_frame = f;
            v->frame_error[0] = '\0';
            view_changed(v);
        } else {
            snprintf(v->frame_error, sizeof v->frame_error, "frame %lld: %s", (long long)f, lc_last_error());
            fprintf(stderr, "%s: %s\n", v->cmd, v->frame_error);
            v->playing = 0;
        }
        if (v->wake) v->wake();
    }
    pthread_mutex_unlock(&v->mu);
    return NULL;
}

int view_frames_start(view_state *v)
{
    v->frame_want = -1;
    lc_device_desc dd = {0};
    if (lc_device_create(&dd, &v->frames_dev) != LC_OK) {
        fprintf(stderr, "%s: %s\n", v->cmd, lc_last_error());
        return -1;
    }
    frames_started = pthread_create(&frames_thread, NULL, frames_main, v) == 0;
    return frames_started ? 0 : -1;
}

void view_frames_stop(view_state *v)
{
    pthread_mutex_lock(&v->mu);
    v->quit = 1;
    pthread_cond_broadcast(&v->cv);
    pthread_mutex_unlock(&v->mu);
    if (frames_started) pthread_join(frames_thread, NULL);
    frames_started = 0;
}

int view_frames_command(view_state *v, const char *cmd, long long n)
{
    pthread_mutex_lock(&v->mu);
    int64_t frames = v->frames > 0 ? v->frames : 1, to = -1;
    int r = 0;
    if (!strcmp(cmd, "play")) v->playing = frames > 1;
    else if (!strcmp(cmd, "pause")) v->playing = 0;
    else if (!strcmp(cmd, "step")) to = ((v->frame + n) % frames + frames) % frames;
    else if (n >= 0 && n < frames) to = n; /* frame N */
    else {
        fprintf(stderr, "%s: frame %lld: %s holds %lld frame%s\n", v->cmd, n, v->input, (long long)frames,
                frames == 1 ? "" : "s");
        r = -1;
    }
    if (to >= 0) {
        v->frame_want = to;
        pthread_cond_broadcast(&v->cv);
    }
    pthread_mutex_unlock(&v->mu);
    return r;
}

/* Playing: the next frame once the current one is refined (UI thread, mu held). */
void view_frames_tick(view_state *v)
{
    if (!v->playing || v->frame_want >= 0 || v->frame_loading >= 0 || v->next_volume ||
        v->refined_gen != v->want.gen)
        return;
    int64_t frames = v->frames > 0 ? v->frames : 1;
    v->frame_want = (v->frame + 1) % frames;
    pthread_cond_broadcast(&v->cv);
}
