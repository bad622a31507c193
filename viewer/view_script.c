/* --script FILE: one command per line, replayed on the UI thread through the
 * same actions as the mouse, the keys and the panels (view_action.c,
 * view_params.c). `wait` holds the script (not the UI) until the frame of
 * the current view is refined. Blank lines and '#' comments are skipped. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "view.h"

struct view_script {
    FILE *f;
    const char *path, *cmd;
    int line;
    int waiting;       /* 1: until the refined frame of the current want; 2: until its job ended */
    double sleep_until;
    int shot;          /* 1: write shot_path once refined */
    char shot_path[4096];
};

view_script *view_script_open(const char *path, const char *cmd)
{
    view_script *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    s->f = fopen(path, "r");
    if (!s->f) {
        fprintf(stderr, "%s: --script: cannot open %s\n", cmd, path);
        free(s);
        return NULL;
    }
    s->path = path, s->cmd = cmd;
    return s;
}

void view_script_close(view_script *s)
{
    if (!s) return;
    fclose(s->f);
    free(s);
}

/* The job of the current view has ended (its counters are in). */
static int job_ended(view_state *v)
{
    pthread_mutex_lock(&v->mu);
    int r = v->shown.stats_gen == v->want.gen || v->shown.error[0];
    pthread_mutex_unlock(&v->mu);
    return r;
}

/* One line about the last finished job, for measurements. */
static void print_stats(view_state *v)
{
    pthread_mutex_lock(&v->mu);
    const view_shown *sh = &v->shown;
    printf("stats nav %d scale %d passes %d size %dx%d job_ms %.3f samples %llu evals %llu target %s threads %d\n",
           sh->nav, sh->scale, sh->npasses, sh->width, sh->height, 1e3 * sh->job_seconds,
           (unsigned long long)sh->stats.samples, (unsigned long long)sh->stats.kernel_evals,
           lc_target_name(sh->target) ? lc_target_name(sh->target) : "?", sh->threads);
    pthread_mutex_unlock(&v->mu);
    fflush(stdout);
}

/* A drag from the image's centre by (dx, dy) pixels in 8 moves. */
static void drag(view_state *v, view_drag_kind k, float dx, float dy)
{
    double x0 = 0.5 * v->want.rd.width, y0 = 0.5 * v->want.rd.height;
    view_drag_begin(v, k, x0, y0);
    for (int i = 1; i <= 8; i++) view_drag_move(v, x0 + dx * i / 8.0, y0 + dy * i / 8.0);
    view_drag_end(v);
}

static int bad(view_script *s, const char *why)
{
    fprintf(stderr, "%s: --script %s:%d: %s\n", s->cmd, s->path, s->line, why);
    return -1;
}

/* One command; 0 ok, -1 bad line. */
static int run(view_script *s, view_state *v, lc_device *dev, char *line)
{
    char *w[8];
    int n = 0;
    for (char *t = strtok(line, " \t\r\n"); t && n < 8; t = strtok(NULL, " \t\r\n")) w[n++] = t;
    if (n == 0 || w[0][0] == '#') return 0;
    const char *c = w[0];
    float a = n > 1 ? strtof(w[1], NULL) : 0.0f, b = n > 2 ? strtof(w[2], NULL) : 0.0f;
    if (!strcmp(c, "orbit") || !strcmp(c, "pan")) {
        if (n != 3) return bad(s, "expected orbit|pan DX DY (pixels)");
        drag(v, c[0] == 'o' ? VIEW_DRAG_ORBIT : VIEW_DRAG_PAN, a, b);
    } else if (!strcmp(c, "zoom")) {
        if (n != 2) return bad(s, "expected zoom STEPS (wheel steps, + = closer)");
        view_wheel(v, a);
    } else if (!strcmp(c, "key")) {
        if (n != 2 || !view_key(v, w[1])) return bad(s, "expected key r|s|c|h|b|q|escape");
    } else if (!strcmp(c, "set")) {
        if (n != 3) return bad(s, "expected set NAME VALUE");
        if (view_set(v, w[1], w[2])) return bad(s, "bad set");
    } else if (!strcmp(c, "mode")) {
        if (n == 3 && view_set(v, "iso", w[2])) return bad(s, "bad iso value");
        if (n < 2 || n > 3 || view_set(v, "mode", w[1])) return bad(s, "expected mode dvr|mip|iso V|slice");
    } else if (!strcmp(c, "target")) {
        if (n != 2 || view_set(v, "target", w[1])) return bad(s, "expected target NAME");
    } else if (!strcmp(c, "tf")) { /* tf FIELD INDEX V TAU: INDEX = the count adds a point */
        if (n != 5) return bad(s, "expected tf FIELD INDEX V TAU");
        view_tf_point(v, atoi(w[1]), atoi(w[2]), strtof(w[3], NULL), strtof(w[4], NULL));
    } else if (!strcmp(c, "tf-delete")) {
        if (n != 3) return bad(s, "expected tf-delete FIELD INDEX");
        view_tf_delete_point(v, atoi(w[1]), atoi(w[2]));
    } else if (!strcmp(c, "save-tf")) {
        if (n != 2) return bad(s, "expected save-tf PATH");
        if (view_tf_save(v, w[1])) return -1;
    } else if (!strcmp(c, "down")) { /* down X Y [shift|middle]: a button press at image pixel X, Y */
        if (n < 3 || n > 4) return bad(s, "expected down X Y [shift|middle]");
        view_drag_begin(v, n == 4 ? VIEW_DRAG_PAN : VIEW_DRAG_ORBIT, a, b);
    } else if (!strcmp(c, "move")) {
        if (n != 3) return bad(s, "expected move X Y");
        view_drag_move(v, a, b);
    } else if (!strcmp(c, "up")) {
        view_drag_end(v);
    } else if (!strcmp(c, "wait")) {
        s->waiting = 1;
    } else if (!strcmp(c, "wait-frame")) {
        s->waiting = 2;
    } else if (!strcmp(c, "stats")) {
        print_stats(v);
    } else if (!strcmp(c, "sleep")) {
        if (n != 2) return bad(s, "expected sleep SECONDS");
        s->sleep_until = view_now() + a;
    } else if (!strcmp(c, "screenshot")) {
        if (n != 2) return bad(s, "expected screenshot PATH");
        s->waiting = s->shot = 1; /* written once refined, by view_script_step */
        snprintf(s->shot_path, sizeof s->shot_path, "%s", w[1]);
    } else if (!strcmp(c, "camera")) {
        view_print_camera(v);
    } else if (!strcmp(c, "frame") || !strcmp(c, "step") || !strcmp(c, "play") || !strcmp(c, "pause")) {
        if (view_frames_command(v, c, n > 1 ? (long long)a : 1)) return bad(s, "bad frame command");
    } else if (!strcmp(c, "quit")) {
        v->quit_asked = 1;
    } else {
        (void)b;
        return bad(s, "unknown command (orbit, pan, zoom, key, set, mode, target, tf, tf-delete, save-tf, wait, "
                      "sleep, screenshot, camera, down, move, up, wait-frame, stats, frame, step, play, pause, quit)");
    }
    (void)dev;
    return 0;
}

int view_script_waiting(const view_script *s) { return s->waiting || s->sleep_until > 0.0; }

int view_script_step(view_script *s, view_state *v, lc_device *dev)
{
    if (s->sleep_until > 0.0) {
        if (view_now() < s->sleep_until) return 1;
        s->sleep_until = 0.0;
    }
    if (s->waiting && view_failed(v)) {
        pthread_mutex_lock(&v->mu);
        char why[600];
        snprintf(why, sizeof why, "waited for a render that failed (%s)", v->shown.error);
        pthread_mutex_unlock(&v->mu);
        return bad(s, why);
    }
    if (s->waiting == 2) {
        if (!job_ended(v)) return 1;
        s->waiting = 0;
    }
    if (s->waiting) {
        if (!view_refined(v) || !job_ended(v)) return 1;
        s->waiting = 0;
        if (s->shot) { /* a screenshot waited for its frame */
            s->shot = 0;
            if (view_save(v, dev, s->shot_path)) return bad(s, v->status);
        }
    }
    char buf[1024];
    if (!fgets(buf, sizeof buf, s->f)) return 0;
    s->line++;
    return run(s, v, dev, buf) ? -1 : 1;
}
