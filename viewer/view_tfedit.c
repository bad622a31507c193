/* The TF editor's edits of lanecast view (on view_state.want.tf) and its
 * JSON file: SPEC.md's format, which lanecast render --tf reads back. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "view.h"

/* Takes the TF into the editor's hands: from now on the render thread
 * builds it from want.tf. mu held. */
static void edited(view_state *v)
{
    v->want.tf_gen++;
    view_changed(v);
}

void view_tf_point(view_state *v, int f, int index, float x, float tau)
{
    pthread_mutex_lock(&v->mu);
    view_tf *t = &v->want.tf;
    if (f < 0 || f >= t->nfields || index < 0 || index > t->nopacity[f] ||
        (index == t->nopacity[f] && index == VIEW_MAX_POINTS) || !isfinite(x) || !isfinite(tau)) {
        pthread_mutex_unlock(&v->mu);
        return;
    }
    float *p = t->opacity[f];
    int n = t->nopacity[f];
    x = x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x;
    tau = tau < 0.0f ? 0.0f : tau;
    if (index == n) { /* a new point: where it falls in v */
        int k = 0;
        while (k < n && p[2 * k] <= x) k++;
        memmove(p + 2 * k + 2, p + 2 * k, sizeof(float) * 2 * (size_t)(n - k));
        index = k;
        t->nopacity[f] = ++n;
    } else { /* a moved point stays between its neighbours */
        if (index > 0 && x < p[2 * index - 2]) x = p[2 * index - 2];
        if (index < n - 1 && x > p[2 * index + 2]) x = p[2 * index + 2];
    }
    p[2 * index] = x, p[2 * index + 1] = tau;
    edited(v);
    pthread_mutex_unlock(&v->mu);
}

void view_tf_delete_point(view_state *v, int f, int index)
{
    pthread_mutex_lock(&v->mu);
    view_tf *t = &v->want.tf;
    if (f >= 0 && f < t->nfields && index >= 0 && index < t->nopacity[f] && t->nopacity[f] > 1) {
        float *p = t->opacity[f];
        memmove(p + 2 * index, p + 2 * index + 2, sizeof(float) * 2 * (size_t)(t->nopacity[f] - index - 1));
        t->nopacity[f]--;
        edited(v);
    }
    pthread_mutex_unlock(&v->mu);
}

/* The colours of a preset on every field (the opacity stays). */
int view_tf_colormap(view_state *v, const char *name)
{
    lc_tf *p = NULL;
    int n = v->want.tf.nfields > 0 ? v->want.tf.nfields : 1;
    if (lc_tf_preset(v->ui_dev, name, n, 1.0f, &p) != LC_OK) {
        fprintf(stderr, "%s: %s\n", v->cmd, lc_last_error());
        return -1;
    }
    pthread_mutex_lock(&v->mu);
    view_tf *t = &v->want.tf;
    for (int i = 0; i < t->nfields; i++) {
        lc_tf_field f;
        if (lc_tf_get_field(p, i, &f) != LC_OK) continue;
        t->ncolor[i] = f.ncolor < 256 ? f.ncolor : 256;
        memcpy(t->color[i], f.color, sizeof(float) * 4 * (size_t)t->ncolor[i]);
    }
    snprintf(t->colormap, sizeof t->colormap, "%s", name);
    edited(v);
    pthread_mutex_unlock(&v->mu);
    lc_tf_destroy(p);
    return 0;
}

static void write_points(FILE *f, const float *p, int n, int stride)
{
    for (int k = 0; k < n; k++) {
        fputs(k ? ", [" : "[", f);
        for (int c = 0; c < stride; c++) fprintf(f, "%s%.9g", c ? ", " : "", (double)p[stride * k + c]);
        fputc(']', f);
    }
}

/* The TF as the render thread builds it (opacity scale applied) and the
 * value range in use (lc_render_desc.range when set, which wins over a TF's
 * own), written under a temporary name and renamed. */
int view_tf_save(view_state *v, const char *path)
{
    char tmp[4200];
    snprintf(tmp, sizeof tmp, "%s.tmp", path);
    pthread_mutex_lock(&v->mu);
    view_tf t = v->want.tf;
    float range[2] = {v->want.rd.range[0], v->want.rd.range[1]};
    pthread_mutex_unlock(&v->mu);
    FILE *f = fopen(tmp, "w");
    if (!f) {
        snprintf(v->status, sizeof v->status, "cannot write %s", tmp);
        fprintf(stderr, "%s: %s\n", v->cmd, v->status);
        return -1;
    }
    fputs("{ \"fields\": [\n", f);
    for (int i = 0; i < t.nfields; i++) {
        float op[2 * VIEW_MAX_POINTS];
        for (int k = 0; k < t.nopacity[i]; k++) {
            op[2 * k] = t.opacity[i][2 * k];
            op[2 * k + 1] = t.opacity_scale == 1.0f ? t.opacity[i][2 * k + 1] : t.opacity[i][2 * k + 1] * t.opacity_scale;
        }
        fputs("  { \"color\": [", f);
        write_points(f, t.color[i], t.ncolor[i], 4);
        fputs("],\n    \"opacity\": [", f);
        write_points(f, op, t.nopacity[i], 2);
        fputc(']', f);
        if (range[0] != 0.0f || range[1] != 0.0f)
            fprintf(f, ",\n    \"range\": [%.9g, %.9g]", (double)range[0], (double)range[1]);
        else if (t.has_range[i])
            fprintf(f, ",\n    \"range\": [%.9g, %.9g]", (double)t.range[i][0], (double)t.range[i][1]);
        fprintf(f, " }%s\n", i + 1 < t.nfields ? "," : "");
    }
    fputs("] }\n", f);
    int bad = ferror(f);
    if (fclose(f) != 0 || bad || rename(tmp, path) != 0) {
        remove(tmp);
        snprintf(v->status, sizeof v->status, "cannot write %s", path);
        fprintf(stderr, "%s: %s\n", v->cmd, v->status);
        return -1;
    }
    snprintf(v->status, sizeof v->status, "wrote %s", path);
    printf("wrote %s\n", path);
    fflush(stdout);
    return 0;
}
