/* The panels' values by name, with the panels' bounds: the ImGui panels and
 * --script's `set NAME VALUE` both come through here, so a script reaches
 * every bound a slider can. Values outside a bound are clamped to it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "view.h"

static float diag(const view_state *v)
{
    lc_vec3 a = v->vinfo.bounds.lo, b = v->vinfo.bounds.hi;
    float d = sqrtf((b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y) + (b.z - a.z) * (b.z - a.z));
    return d > 0.0f && isfinite(d) ? d : 1.0f;
}

int view_param_bounds(const view_state *v, const char *name, float *lo, float *hi, int *integer)
{
    const float r0 = v->vinfo.range[0], r1 = v->vinfo.range[1], span = r1 > r0 ? r1 - r0 : 1.0f;
    static const struct {
        const char *name;
        float lo, hi;
        int integer;
    } fixed[] = {
        {"alpha_stop", 0.05f, 1.0f, 0},  {"sigma", 0.5f, 8.0f, 0},       {"kappa", 0.01f, 100.0f, 0},
        {"ka", 0.0f, 2.0f, 0},           {"kd", 0.0f, 2.0f, 0},          {"ks", 0.0f, 2.0f, 0},
        {"phong_exp", 1.0f, 256.0f, 1},  {"threads", 0.0f, 64.0f, 1},    {"nav_scale", 2.0f, 16.0f, 1},
        {"nav_step", 1.0f, 8.0f, 0},     {"target_ms", 5.0f, 1000.0f, 0}, {"adaptive", 0.0f, 1.0f, 1},
        {"refine_delay", 0.0f, 5.0f, 0}, {"opacity_scale", 0.0f, 100.0f, 0}, {"plane_axis", 0.0f, 2.0f, 1},
        {"plane_pos", 0.0f, 1.0f, 0},    {"box", 0.0f, 1.0f, 1},          {"panels", 0.0f, 1.0f, 1},
    };
    *integer = 0;
    for (size_t i = 0; i < sizeof fixed / sizeof fixed[0]; i++)
        if (!strcmp(name, fixed[i].name)) {
            *lo = fixed[i].lo, *hi = fixed[i].hi, *integer = fixed[i].integer;
            return 0;
        }
    if (!strcmp(name, "iso")) *lo = r0, *hi = r1 > r0 ? r1 : r0 + 1.0f;
    else if (!strcmp(name, "dt")) *lo = 0.0f, *hi = 0.25f * diag(v); /* 0 = the kind's default */
    else if (!strcmp(name, "range_lo") || !strcmp(name, "range_hi")) *lo = r0 - span, *hi = r1 + span;
    else if (!strcmp(name, "field")) *lo = 0.0f, *hi = (float)(v->vinfo.nfields - 1), *integer = 1;
    else return -1;
    return 0;
}

/* The slice plane from an axis and a position along the data's box. */
static void set_plane(view_state *v, int axis, float pos)
{
    lc_vec3 a = v->vinfo.bounds.lo, b = v->vinfo.bounds.hi;
    lc_plane *p = &v->want.rd.planes[0];
    p->point = (lc_vec3){0.5f * (a.x + b.x), 0.5f * (a.y + b.y), 0.5f * (a.z + b.z)};
    float *c = axis == 0 ? &p->point.x : axis == 1 ? &p->point.y : &p->point.z;
    float l = axis == 0 ? a.x : axis == 1 ? a.y : a.z, h = axis == 0 ? b.x : axis == 1 ? b.y : b.z;
    *c = l + pos * (h - l);
    p->normal = (lc_vec3){axis == 0, axis == 1, axis == 2};
    v->want.rd.nplanes = 1;
    v->plane_axis = axis, v->plane_pos = pos;
}

float view_getf(view_state *v, const char *name)
{
    const lc_render_desc *rd = &v->want.rd;
    const lc_lighting *l = &rd->lighting;
    if (!strcmp(name, "iso")) return rd->iso;
    if (!strcmp(name, "dt")) return rd->dt;
    if (!strcmp(name, "alpha_stop")) return rd->alpha_stop > 0.0f ? rd->alpha_stop : 0.97f;
    if (!strcmp(name, "sigma")) return v->want.pp.sigma > 0.0f ? v->want.pp.sigma : 2.0f;
    if (!strcmp(name, "kappa")) return v->want.pp.kappa > 0.0f ? v->want.pp.kappa : 1.0f;
    if (!strcmp(name, "ka")) return l->phong_exp ? l->ka : 0.2f;
    if (!strcmp(name, "kd")) return l->phong_exp ? l->kd : 0.8f;
    if (!strcmp(name, "ks")) return l->phong_exp ? l->ks : 0.4f;
    if (!strcmp(name, "phong_exp")) return (float)(l->phong_exp ? l->phong_exp : 16);
    if (!strcmp(name, "threads")) return (float)v->want.threads;
    if (!strcmp(name, "nav_scale")) return (float)v->want.nav_scale;
    if (!strcmp(name, "nav_step")) return v->want.nav_step;
    if (!strcmp(name, "target_ms")) return v->target_ms;
    if (!strcmp(name, "adaptive")) return (float)v->adaptive;
    if (!strcmp(name, "refine_delay")) return (float)v->refine_delay;
    if (!strcmp(name, "opacity_scale")) return v->want.tf.opacity_scale;
    if (!strcmp(name, "plane_axis")) return (float)v->plane_axis;
    if (!strcmp(name, "plane_pos")) return v->plane_pos;
    if (!strcmp(name, "box")) return (float)v->show_box;
    if (!strcmp(name, "panels")) return (float)(v->panels_open > 0);
    if (!strcmp(name, "field")) return (float)rd->field;
    if (!strcmp(name, "range_lo") || !strcmp(name, "range_hi")) {
        float lo = v->vinfo.range[0], hi = v->vinfo.range[1];
        if (rd->range[0] != 0.0f || rd->range[1] != 0.0f) lo = rd->range[0], hi = rd->range[1];
        else if (v->want.tf.nfields && v->want.tf.has_range[0]) lo = v->want.tf.range[0][0], hi = v->want.tf.range[0][1];
        return name[6] == 'l' ? lo : hi;
    }
    return 0.0f;
}

/* Sets a number (clamped to its bounds); mu held. */
static void setf_locked(view_state *v, const char *name, float x)
{
    lc_render_desc *rd = &v->want.rd;
    lc_lighting *l = &rd->lighting;
    if (!strcmp(name, "ka") || !strcmp(name, "kd") || !strcmp(name, "ks") || !strcmp(name, "phong_exp")) {
        if (!l->phong_exp) *l = (lc_lighting){0.2f, 0.8f, 0.4f, 16}; /* SPEC.md's defaults, made explicit */
        if (name[0] == 'p') l->phong_exp = (int)x;
        else *(name[1] == 'a' ? &l->ka : name[1] == 'd' ? &l->kd : &l->ks) = x;
    } else if (!strcmp(name, "iso")) rd->iso = x;
    else if (!strcmp(name, "dt")) rd->dt = x;
    else if (!strcmp(name, "alpha_stop")) rd->alpha_stop = x;
    else if (!strcmp(name, "sigma") || !strcmp(name, "kappa")) {
        *(name[0] == 's' ? &v->want.pp.sigma : &v->want.pp.kappa) = x;
        v->want.pp_gen++;
    } else if (!strcmp(name, "threads")) {
        v->want.threads = (int)x;
        v->want.dev_gen++;
    } else if (!strcmp(name, "nav_scale")) v->want.nav_scale = v->min_nav_scale = (int)x;
    else if (!strcmp(name, "nav_step")) v->want.nav_step = x;
    else if (!strcmp(name, "target_ms")) v->target_ms = x;
    else if (!strcmp(name, "adaptive")) v->adaptive = (int)x;
    else if (!strcmp(name, "refine_delay")) v->refine_delay = x;
    else if (!strcmp(name, "opacity_scale")) {
        v->want.tf.opacity_scale = x;
        v->want.tf_gen++;
    } else if (!strcmp(name, "plane_axis")) set_plane(v, (int)x, v->plane_pos);
    else if (!strcmp(name, "plane_pos")) set_plane(v, v->plane_axis, x);
    else if (!strcmp(name, "box")) v->show_box = (int)x;
    else if (!strcmp(name, "panels")) v->panels_open = (int)x, v->panels_asked = 1;
    else if (!strcmp(name, "field")) rd->field = (int)x;
    else if (!strcmp(name, "range_lo") || !strcmp(name, "range_hi")) {
        float lo = view_getf(v, "range_lo"), hi = view_getf(v, "range_hi");
        if (name[6] == 'l') lo = x;
        else hi = x;
        if (!(hi > lo)) { /* keep lo < hi: move the other end */
            float eps = fmaxf(1e-6f * fabsf(lo), 1e-6f);
            if (name[6] == 'l') hi = lo + eps;
            else lo = hi - eps;
        }
        rd->range[0] = lo, rd->range[1] = hi;
    }
}

int view_setf(view_state *v, const char *name, float x)
{
    float lo, hi;
    int integer;
    if (view_param_bounds(v, name, &lo, &hi, &integer) || !isfinite(x)) return -1;
    x = x < lo ? lo : x > hi ? hi : x;
    if (integer) x = floorf(x + 0.5f);
    pthread_mutex_lock(&v->mu);
    setf_locked(v, name, x);
    view_changed(v);
    pthread_mutex_unlock(&v->mu);
    return 0;
}

static int pick(const char *value, const char *const *names, int n)
{
    for (int i = 0; i < n; i++)
        if (!strcmp(value, names[i])) return i;
    return -1;
}

const char *const view_modes[4] = {"dvr", "mip", "iso", "slice"};
const char *const view_shadings[3] = {"none", "diffuse", "phong"};
const char *const view_methods[5] = {"default", "coherent", "direct", "bvh", "brute"};

/* The words: mode, shading, method, target, colormap; 1 handled, 0 not a word, -1 bad value. */
static int set_word(view_state *v, const char *name, const char *value)
{
    int i;
    if (!strcmp(name, "colormap")) return view_tf_colormap(v, value) ? -1 : 1;
    pthread_mutex_lock(&v->mu);
    int r = 1;
    if (!strcmp(name, "mode")) {
        if ((i = pick(value, view_modes, 4)) < 0) r = -1;
        else {
            v->want.rd.mode = (lc_mode)i;
            if (i == LC_MODE_SLICE && v->want.rd.nplanes == 0) set_plane(v, v->plane_axis, v->plane_pos);
        }
    } else if (!strcmp(name, "shading")) {
        if ((i = pick(value, view_shadings, 3)) < 0) r = -1;
        else v->want.rd.shading = (lc_shading)i;
    } else if (!strcmp(name, "method")) {
        if ((i = pick(value, view_methods, 5)) < 0) r = -1;
        else v->want.rd.method = (lc_method)i;
    } else if (!strcmp(name, "target")) {
        lc_target t;
        if (lc_target_from_name(value, &t) != LC_OK) r = -1;
        else v->want.target = t, v->want.dev_gen++;
    } else {
        r = 0;
    }
    if (r > 0) view_changed(v);
    pthread_mutex_unlock(&v->mu);
    return r;
}

int view_set(view_state *v, const char *name, const char *value)
{
    int r = set_word(v, name, value);
    if (r > 0) return 0;
    if (r < 0) {
        fprintf(stderr, "%s: set %s: '%s' is not a value it takes\n", v->cmd, name, value);
        return -1;
    }
    char *end;
    float x = strtof(value, &end);
    if (end == value || *end || view_setf(v, name, x)) {
        fprintf(stderr, "%s: set %s %s: not a known name with a number (see lanecast view --help)\n", v->cmd, name,
                value);
        return -1;
    }
    return 0;
}
