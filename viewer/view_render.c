/* The render-control thread of lanecast view: it turns each new wanted
 * state (view_state.want) into a render job (lc_render_begin) and publishes
 * every finished pass (view_state.shown). A new state cancels the running
 * job first (lc_job_destroy cancels and waits a tile's time), so changes
 * that must not happen during a job (particle parameters, the TF, the
 * device, the volume) happen here, between jobs. The UI thread never waits
 * for this thread. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "view.h"

typedef struct view_render {
    view_state *v;
    pthread_t thread;
    lc_device *dev;          /* renders; replaced when the target or thread count changes */
    lc_device *tf_dev;       /* owns the TFs this thread builds */
    lc_tf *tf;               /* built from want.tf (NULL: v->initial_tf) */
    uint64_t started_gen, dev_gen, tf_gen, pp_gen;
    uint64_t job_gen;        /* want.gen of the running job (set before it starts) */
    lc_job *job;
    int job_nav, ended;
    float *buf;
    size_t cap;
} view_render;

static view_render the_render;

/* On the job's thread after each pass: the pass becomes the shown image. */
static void on_pass(void *user, const lc_job_pass *p)
{
    view_render *r = user;
    view_state *v = r->v;
    size_t n = (size_t)p->width * (size_t)p->height * 4;
    pthread_mutex_lock(&v->mu);
    view_shown *s = &v->shown;
    if (s->width != p->width || s->height != p->height || !s->rgba) {
        float *b = realloc(s->rgba, n * sizeof(float));
        float *f = realloc(v->refined, n * sizeof(float));
        if (f) v->refined = f;
        if (!b || !f) {
            if (b) s->rgba = b;
            snprintf(s->error, sizeof s->error, "out of memory for a %dx%d image", p->width, p->height);
            pthread_mutex_unlock(&v->mu);
            return;
        }
        s->rgba = b;
        s->width = p->width, s->height = p->height;
        v->refined_gen = 0;
    }
    memcpy(s->rgba, p->rgba, n * sizeof(float));
    s->gen = r->job_gen;
    s->seq++;
    s->pass = p->pass, s->npasses = p->npasses, s->scale = p->scale, s->final = p->final;
    s->nav = r->job_nav;
    s->pass_seconds = p->seconds;
    if (p->final && !r->job_nav) {
        memcpy(v->refined, p->rgba, n * sizeof(float));
        v->refined_gen = r->job_gen;
    }
    if (p->final) r->ended = 1;
    pthread_cond_broadcast(&v->cv);
    pthread_mutex_unlock(&v->mu);
    if (v->wake) v->wake(); /* set before this thread starts, cleared after it stops */
}

static void set_error(view_state *v, const char *what, const char *msg)
{
    pthread_mutex_lock(&v->mu);
    snprintf(v->shown.error, sizeof v->shown.error, "%s: %s", what, msg);
    pthread_mutex_unlock(&v->mu);
    fprintf(stderr, "%s: %s: %s\n", v->cmd, what, msg);
    if (v->wake) v->wake();
}

/* The device, TF and particle parameters the wanted state asks for; no job runs. */
static void apply(view_render *r, const view_want *w)
{
    view_state *v = r->v;
    if (!r->dev || w->dev_gen != r->dev_gen) {
        lc_device *d = NULL;
        lc_device_desc dd = {.target = w->target, .threads = w->threads};
        if (lc_device_create(&dd, &d) == LC_OK) {
            lc_device_destroy(r->dev);
            r->dev = d;
        } else {
            set_error(v, "target", lc_last_error());
        }
        r->dev_gen = w->dev_gen;
    }
    if (w->tf_gen != r->tf_gen) {
        lc_tf *t = NULL;
        if (view_tf_build(r->tf_dev, &w->tf, &t) == LC_OK) {
            lc_tf_destroy(r->tf);
            r->tf = t;
        } else {
            set_error(v, "transfer function", lc_last_error());
        }
        r->tf_gen = w->tf_gen;
    }
    if (w->pp_gen != r->pp_gen && lc_volume_kind(v->volume) == LC_KIND_PARTICLES) {
        pthread_mutex_lock(&v->vol_mu); /* the histogram may be sampling it */
        if (lc_particles_set_params(v->volume, &w->pp) != LC_OK) set_error(v, "particles", lc_last_error());
        pthread_mutex_unlock(&v->vol_mu);
    }
    r->pp_gen = w->pp_gen;
}

/* Starts the job of w (the old one is gone). */
static void begin(view_render *r, const view_want *w)
{
    view_state *v = r->v;
    lc_render_desc rd = w->rd;
    rd.volume = v->volume;
    rd.tf = r->tf ? r->tf : v->initial_tf;
    if (w->nav) {
        rd.pixel_scale = w->nav_scale;
        rd.step_scale = w->nav_step;
    }
    size_t n = (size_t)rd.width * (size_t)rd.height * 4;
    if (n > r->cap) {
        float *b = realloc(r->buf, n * sizeof(float));
        if (!b) {
            set_error(v, "render", "out of memory for the image");
            pthread_mutex_lock(&v->mu);
            v->shown.failed_gen = w->gen;
            pthread_mutex_unlock(&v->mu);
            return;
        }
        r->buf = b, r->cap = n;
    }
    r->job_nav = w->nav;
    r->job_gen = w->gen;
    r->ended = 0;
    lc_job_desc jd = {.on_pass = on_pass, .user = r};
    if (lc_render_begin(r->dev, &rd, &jd, r->buf, &r->job) != LC_OK) {
        r->job = NULL;
        set_error(v, "render", lc_last_error());
        pthread_mutex_lock(&v->mu);
        v->shown.failed_gen = w->gen;
        pthread_mutex_unlock(&v->mu);
    } else {
        pthread_mutex_lock(&v->mu);
        v->shown.error[0] = '\0';
        pthread_mutex_unlock(&v->mu);
    }
}

/* After the last pass: the job's counters for the overlay (samples/s). */
static void collect(view_render *r)
{
    lc_render_stats st;
    memset(&st, 0, sizeof st);
    lc_status s = lc_job_wait(r->job, -1.0, &st);
    view_state *v = r->v;
    pthread_mutex_lock(&v->mu);
    if (s == LC_OK) {
        v->shown.stats = st;
        v->shown.job_seconds = st.seconds;
        v->shown.stats_gen = r->job_gen;
        v->shown.target = st.target;
        v->shown.threads = st.threads;
    }
    pthread_mutex_unlock(&v->mu);
    if (v->wake) v->wake();
}

static void *render_main(void *arg)
{
    view_render *r = arg;
    view_state *v = r->v;
    view_want *w = malloc(sizeof *w);
    if (!w) return NULL;
    for (;;) {
        pthread_mutex_lock(&v->mu);
        while (!v->quit && v->want.gen == r->started_gen && !(r->job && r->ended))
            pthread_cond_wait(&v->cv, &v->mu);
        if (v->quit) {
            pthread_mutex_unlock(&v->mu);
            break;
        }
        if (v->want.gen == r->started_gen) { /* the job finished */
            r->ended = 0;
            pthread_mutex_unlock(&v->mu);
            collect(r);
            continue;
        }
        *w = v->want;
        r->started_gen = w->gen;
        int64_t frame = 0;
        lc_volume *next = view_frames_take(v, &frame);
        pthread_mutex_unlock(&v->mu);
        lc_job_destroy(r->job); /* cancels: a tile's time */
        r->job = NULL;
        if (next) { /* a new frame: the old volume goes back to the loader */
            pthread_mutex_lock(&v->mu);
            v->retired = v->volume;
            v->volume = next;
            v->frame = frame;
            pthread_cond_broadcast(&v->cv);
            pthread_mutex_unlock(&v->mu);
            r->pp_gen = ~(uint64_t)0; /* the parameters the user set, on the new volume */
        }
        apply(r, w);
        if (r->dev) begin(r, w);
    }
    lc_job_destroy(r->job);
    r->job = NULL;
    free(w);
    return NULL;
}

int view_render_start(view_state *v)
{
    view_render *r = &the_render;
    memset(r, 0, sizeof *r);
    r->v = v;
    lc_device_desc dd = {.target = LC_TARGET_SCALAR, .threads = 1};
    if (lc_device_create(&dd, &r->tf_dev) != LC_OK) {
        fprintf(stderr, "%s: %s\n", v->cmd, lc_last_error());
        return -1;
    }
    if (pthread_create(&r->thread, NULL, render_main, r) != 0) {
        fprintf(stderr, "%s: cannot start the render thread\n", v->cmd);
        lc_device_destroy(r->tf_dev);
        return -1;
    }
    return 0;
}

void view_render_stop(view_state *v)
{
    view_render *r = &the_render;
    pthread_mutex_lock(&v->mu);
    v->quit = 1;
    pthread_cond_broadcast(&v->cv);
    pthread_mutex_unlock(&v->mu);
    pthread_join(r->thread, NULL);
    lc_tf_destroy(r->tf);
    lc_device_destroy(r->tf_dev);
    lc_device_destroy(r->dev);
    free(r->buf);
    memset(r, 0, sizeof *r);
}

lc_status view_tf_build(lc_device *dev, const view_tf *t, lc_tf **out)
{
    lc_tf_field f[LC_MAX_FIELDS];
    float op[LC_MAX_FIELDS][2 * VIEW_MAX_POINTS];
    for (int i = 0; i < t->nfields; i++) {
        for (int k = 0; k < t->nopacity[i]; k++) {
            op[i][2 * k] = t->opacity[i][2 * k];
            op[i][2 * k + 1] = t->opacity_scale == 1.0f ? t->opacity[i][2 * k + 1]
                                                        : t->opacity[i][2 * k + 1] * t->opacity_scale;
        }
        f[i] = (lc_tf_field){.color = t->color[i], .ncolor = t->ncolor[i], .opacity = op[i],
                             .nopacity = t->nopacity[i], .has_range = t->has_range[i],
                             .range = {t->range[i][0], t->range[i][1]}};
    }
    return lc_tf_create(dev, f, t->nfields, out);
}

void view_tf_from(view_tf *t, const lc_tf *tf)
{
    memset(t, 0, sizeof *t);
    t->opacity_scale = 1.0f;
    t->nfields = lc_tf_field_count(tf);
    for (int i = 0; i < t->nfields; i++) {
        lc_tf_field f;
        if (lc_tf_get_field(tf, i, &f) != LC_OK) continue;
        t->ncolor[i] = f.ncolor < 256 ? f.ncolor : 256;
        memcpy(t->color[i], f.color, sizeof(float) * 4 * (size_t)t->ncolor[i]);
        t->nopacity[i] = f.nopacity < VIEW_MAX_POINTS ? f.nopacity : VIEW_MAX_POINTS;
        memcpy(t->opacity[i], f.opacity, sizeof(float) * 2 * (size_t)t->nopacity[i]);
        t->has_range[i] = f.has_range;
        t->range[i][0] = f.range[0], t->range[i][1] = f.range[1];
    }
}
