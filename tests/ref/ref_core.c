/* Reference renderer core (see ref_core.h), from SPEC.md "Camera and rays",
 * "Sampling and integration" (Knoll 2014, Listing 1) and "Shading". Plain C,
 * double precision, libm only. */
#include "ref_core.h"

#include <math.h>
#include <stddef.h>

static const double ref_pi = 3.14159265358979323846;

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross3(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static int normalize3(double a[3])
{
    double n = sqrt(dot3(a, a));
    if (!(n > 0.0) || !isfinite(n)) return -1;
    a[0] /= n, a[1] /= n, a[2] /= n;
    return 0;
}

/* forward, right = normalize(forward x up), up' = right x forward. */
static int camera_basis(const ref_camera *cam, double fwd[3], double right[3], double upv[3])
{
    double up[3] = {cam->up[0], cam->up[1], cam->up[2]};
    if (up[0] == 0.0 && up[1] == 0.0 && up[2] == 0.0) up[1] = 1.0;
    for (int a = 0; a < 3; a++) fwd[a] = cam->at[a] - cam->eye[a];
    if (normalize3(fwd)) return -1;
    cross3(fwd, up, right);
    if (normalize3(right)) return -1;
    cross3(right, fwd, upv);
    return 0;
}

int ref_camera_ray(const ref_camera *cam, int width, int height, int px, int py, double o[3], double d[3])
{
    double fwd[3], right[3], upv[3];
    if (width < 1 || height < 1 || camera_basis(cam, fwd, right, upv)) return -1;
    int ortho = cam->projection == REF_ORTHOGRAPHIC;
    double half;
    if (ortho) {
        if (!(cam->height > 0.0)) return -1;
        half = 0.5 * cam->height;
    } else {
        if (!(cam->fovy > 0.0 && cam->fovy < 180.0)) return -1;
        half = tan(cam->fovy * ref_pi / 360.0);
    }
    /* SPEC.md: u = (2 (px + 0.5) / W - 1) tan(fovy/2) W/H, v = (1 - 2 (py + 0.5) / H) tan(fovy/2);
     * orthographic: the same (u, v) with height/2 for tan(fovy/2), as an offset of the origin. */
    double u = (2.0 * (px + 0.5) / width - 1.0) * half * width / height;
    double v = (1.0 - 2.0 * (py + 0.5) / height) * half;
    for (int a = 0; a < 3; a++) {
        if (ortho) {
            o[a] = cam->eye[a] + u * right[a] + v * upv[a];
            d[a] = fwd[a];
        } else {
            o[a] = cam->eye[a];
            d[a] = fwd[a] + u * right[a] + v * upv[a];
        }
    }
    return normalize3(d);
}

int ref_ray_box(const double o[3], const double d[3], const double lo[3], const double hi[3], double *t0,
                double *t1)
{
    double a0 = 0.0, a1 = INFINITY;
    for (int a = 0; a < 3; a++) {
        if (!(lo[a] <= hi[a])) return 0;
        if (d[a] == 0.0) {
            if (o[a] < lo[a] || o[a] > hi[a]) return 0;
            continue;
        }
        double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
        if (ta > tb) {
            double s = ta;
            ta = tb, tb = s;
        }
        a0 = ta > a0 ? ta : a0;
        a1 = tb < a1 ? tb : a1;
    }
    *t0 = a0, *t1 = a1;
    return a0 <= a1;
}

double ref_lattice_t(long k, double dt, double rda)
{
    double kk = (double)k;
    return dt * (kk + rda * kk * (kk - 1.0) * 0.5);
}

/* Inverse of t_k for rda >= 0: the positive root of (rda/2) k^2 + (1 - rda/2) k = t/dt. */
static double lattice_k(double t, double dt, double rda)
{
    double s = t / dt;
    if (rda == 0.0) return s;
    double b = 1.0 - 0.5 * rda;
    return (-b + sqrt(b * b + 2.0 * rda * s)) / rda;
}

long ref_lattice_range(double t0, double t1, double dt, double rda, long *k0, long *k1)
{
    if (t0 < 0.0) t0 = 0.0;
    long a = (long)ceil(lattice_k(t0, dt, rda)), b = (long)floor(lattice_k(t1, dt, rda));
    if (a < 0) a = 0;
    /* settle on the computed t_k themselves, so the range agrees with ref_lattice_t exactly */
    while (ref_lattice_t(a, dt, rda) < t0) a++;
    while (a > 0 && ref_lattice_t(a - 1, dt, rda) >= t0) a--;
    while (b >= 0 && ref_lattice_t(b, dt, rda) > t1) b--;
    while (ref_lattice_t(b + 1, dt, rda) <= t1) b++;
    *k0 = a, *k1 = b;
    return b >= a ? b - a + 1 : 0;
}

/* Piecewise linear over points [v, c0 .. c(nc-1)] with the given stride, clamped at both ends. */
static void pwl(const double *pts, int n, int stride, int nc, double v, double *out)
{
    if (v <= pts[0]) {
        for (int c = 0; c < nc; c++) out[c] = pts[1 + c];
        return;
    }
    for (int i = 1; i < n; i++) {
        const double *a = pts + (size_t)(i - 1) * stride, *b = pts + (size_t)i * stride;
        if (v < b[0]) {
            double w = (v - a[0]) / (b[0] - a[0]);
            for (int c = 0; c < nc; c++) out[c] = a[1 + c] + w * (b[1 + c] - a[1 + c]);
            return;
        }
    }
    const double *l = pts + (size_t)(n - 1) * stride;
    for (int c = 0; c < nc; c++) out[c] = l[1 + c];
}

void ref_tf_eval(const ref_tf *tf, double phi, double rgb[3], double *tau)
{
    double v = (phi - tf->lo) / (tf->hi - tf->lo);
    if (isnan(v)) {
        rgb[0] = rgb[1] = rgb[2] = *tau = NAN;
        return;
    }
    v = v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v;
    pwl(tf->color, tf->ncolor, 4, 3, v, rgb);
    pwl(tf->opacity, tf->nopacity, 2, 1, v, tau);
}

static int tf_valid(const ref_tf *tf)
{
    if (!(tf->hi > tf->lo) || !isfinite(tf->hi - tf->lo)) return 0;
    if (!tf->color || tf->ncolor < 1 || !tf->opacity || tf->nopacity < 1) return 0;
    for (int i = 1; i < tf->ncolor; i++)
        if (!(tf->color[4 * i] >= tf->color[4 * (i - 1)])) return 0;
    for (int i = 1; i < tf->nopacity; i++)
        if (!(tf->opacity[2 * i] >= tf->opacity[2 * (i - 1)])) return 0;
    return 1;
}

/* Resolved parameters, shared by every ray of a frame. */
typedef struct ctx {
    const ref_source *src;
    const ref_params *p;
    double alpha_stop, ka, kd, ks, pe;
} ctx;

static int setup(ctx *c, const ref_source *src, const ref_params *p)
{
    if (!src || !p || !src->eval || src->nfields < 1 || src->nfields > REF_MAX_FIELDS || !p->tf) return -1;
    if (p->width < 1 || p->height < 1 || !(p->dt > 0.0) || !isfinite(p->dt) || !(p->rda >= 0.0)) return -1;
    if ((int)p->mode < (int)REF_MODE_DVR || (int)p->mode > (int)REF_MODE_SLICE) return -1;
    if (p->mode == REF_MODE_ISO || p->mode == REF_MODE_SLICE) {
        if (p->field < 0 || p->field >= src->nfields) return -1;
        if (p->mode == REF_MODE_ISO && !isfinite(p->iso)) return -1;
        if (p->mode == REF_MODE_SLICE) {
            if (p->nplanes < 1 || p->nplanes > REF_MAX_PLANES) return -1;
            for (int i = 0; i < p->nplanes; i++) {
                double n[3] = {p->planes[i][3], p->planes[i][4], p->planes[i][5]};
                for (int a = 0; a < 6; a++)
                    if (!isfinite(p->planes[i][a])) return -1;
                if (normalize3(n)) return -1;
            }
        }
    }
    if ((int)p->shading < 0 || (int)p->shading > (int)REF_SHADE_PHONG) return -1;
    for (int f = 0; f < src->nfields; f++)
        if (!tf_valid(&p->tf[f])) return -1;
    double o[3], d[3];
    if (ref_camera_ray(&p->camera, p->width, p->height, 0, 0, o, d)) return -1;
    c->src = src, c->p = p;
    c->alpha_stop = p->alpha_stop == 0.0 ? 0.97 : p->alpha_stop;
    if (!(c->alpha_stop > 0.0)) return -1;
    double k[4];
    ref_lighting(p, k);
    c->ka = k[0], c->kd = k[1], c->ks = k[2], c->pe = k[3];
    return 0;
}

void ref_lighting(const ref_params *p, double k[4])
{
    int dflt = p->ka == 0.0 && p->kd == 0.0 && p->ks == 0.0 && p->p == 0.0;
    k[0] = dflt ? 0.2 : p->ka, k[1] = dflt ? 0.8 : p->kd;
    k[2] = dflt ? 0.4 : p->ks, k[3] = dflt ? 16.0 : p->p;
}

/* SPEC.md "Shading": n = -grad/|grad|, l = -d, h = normalize(l - d); below
 * 1e-6 (hi - lo) / dt the gradient is too small and rgb stays as classified. */
static void shade(const ctx *c, const ref_tf *tf, const double g[3], const double d[3], double rgb[3])
{
    if (c->p->shading == REF_SHADE_NONE) return;
    double gl = sqrt(dot3(g, g));
    if (!(gl >= 1e-6 * (tf->hi - tf->lo) / c->p->dt)) return;
    double n[3], l[3], h[3];
    for (int a = 0; a < 3; a++) n[a] = -g[a] / gl, l[a] = -d[a], h[a] = l[a] - d[a];
    normalize3(h);
    double k = c->ka + c->kd * fabs(dot3(n, l));
    double s = c->p->shading == REF_SHADE_PHONG ? c->ks * pow(fabs(dot3(n, h)), c->pe) : 0.0;
    for (int a = 0; a < 3; a++) rgb[a] = rgb[a] * k + s;
}

/* Per-ray state of every mode; DVR uses C and A, MIP the running maximum of
 * the normalised value, the field that reached it and whether any sample was
 * taken; iso the previous sample and, once found, the hit; slice the hit. */
typedef struct ray_state {
    double o[3], d[3];
    double C[3], A;
    double vmax;
    int fmax, seen;
    double prev_phi, prev_t; /* iso: the previous lattice sample (seen: there is one) */
    int hit;                 /* iso, slice: found */
    double t_hit;
    double margin;           /* see ref_render_depth */
} ray_state;

/* Field p->field at x0 + t d (iso, slice). */
static double field_at(const ctx *c, const ray_state *r, double t, double (*grad)[3])
{
    double x[3], phi[REF_MAX_FIELDS];
    for (int a = 0; a < 3; a++) x[a] = r->o[a] + t * r->d[a];
    c->src->eval(c->src->user, x, phi, grad);
    return phi[c->p->field];
}

/* iso (SPEC.md "Other modes"): the first pair of consecutive lattice samples
 * on different sides of the iso value (inside: phi >= iso) is bisected in
 * double precision until the bracket is at most 1e-4 dt wide; the hit is its
 * end on the inside. Returns 1 (stop) on a hit. */
static int iso_sample(const ctx *c, ray_state *r, double t, const double *phi)
{
    const double iso = c->p->iso, v = phi[c->p->field];
    double m = fabs(v - iso);
    r->margin = m < r->margin ? m : r->margin;
    if (r->seen && (r->prev_phi >= iso) != (v >= iso)) {
        int in_a = r->prev_phi >= iso;
        double a = r->prev_t, b = t;
        while (b - a > 1e-4 * c->p->dt) {
            double mid = 0.5 * (a + b), pm = field_at(c, r, mid, NULL);
            if ((pm >= iso) == in_a) a = mid;
            else b = mid;
        }
        r->hit = 1;
        r->t_hit = in_a ? a : b;
        return 1;
    }
    r->seen = 1;
    r->prev_phi = v, r->prev_t = t;
    return 0;
}

/* slice: the nearest plane point with t in [t0, t1] and before t_surf. */
static void slice_ray(const ctx *c, ray_state *r, double t0, double t1, double t_surf)
{
    const ref_params *p = c->p;
    for (int i = 0; i < p->nplanes; i++) {
        double n[3] = {p->planes[i][3], p->planes[i][4], p->planes[i][5]}, e[3];
        normalize3(n);
        for (int a = 0; a < 3; a++) e[a] = p->planes[i][a] - r->o[a];
        double dn = dot3(r->d, n);
        if (dn == 0.0) continue;
        double tp = dot3(e, n) / dn;
        double m = fmin(fabs(tp - t0), fabs(tp - t1));
        if (isfinite(t_surf)) m = fmin(m, fabs(tp - t_surf));
        r->margin = m < r->margin ? m : r->margin;
        if (tp >= t0 && tp <= t1 && tp < t_surf && (!r->hit || tp < r->t_hit)) r->hit = 1, r->t_hit = tp;
    }
}

/* MIP (SPEC.md "Other modes"): the largest normalised value v = (phi - lo) /
 * (hi - lo) along the ray over every field (the first to reach it wins). */
static int mip_sample(const ctx *c, ray_state *r, const double *phi)
{
    for (int f = 0; f < c->src->nfields; f++) {
        const ref_tf *tf = &c->p->tf[f];
        double v = (phi[f] - tf->lo) / (tf->hi - tf->lo);
        if (!r->seen || v > r->vmax) r->vmax = v, r->fmax = f;
        r->seen = 1;
    }
    return 0;
}

/* DVR: classify, shade, blend front to back in field order. Returns 1 to stop the ray. */
static int dvr_sample(const ctx *c, ray_state *r, long k, double t, const double *phi, double (*grad)[3])
{
    const ref_params *p = c->p;
    double scale = p->tau_scale ? p->tau_scale(p->tau_scale_user, k, t) : 1.0 + p->rda * (double)k;
    for (int f = 0; f < c->src->nfields; f++) {
        double rgb[3], tau;
        ref_tf_eval(&p->tf[f], phi[f], rgb, &tau);
        shade(c, &p->tf[f], grad[f], r->d, rgb);
        double a = 1.0 - exp(-tau * p->dt * scale), w = (1.0 - r->A) * a;
        for (int ch = 0; ch < 3; ch++) r->C[ch] += w * rgb[ch];
        r->A += w;
    }
    return c->alpha_stop < 1.0 && r->A >= c->alpha_stop;
}

/* The one place where a mode consumes a sample. */
static int consume_sample(const ctx *c, ray_state *r, long k, double t, const double *phi, double (*grad)[3])
{
    switch (c->p->mode) {
    case REF_MODE_DVR: return dvr_sample(c, r, k, t, phi, grad);
    case REF_MODE_ISO: return iso_sample(c, r, t, phi);
    case REF_MODE_MIP: return mip_sample(c, r, phi);
    case REF_MODE_SLICE: /* not a lattice consumer: one sample on the plane */
    default: return 1;
    }
}

static void finish_ray(const ctx *c, const ray_state *r, double out[4])
{
    switch (c->p->mode) {
    case REF_MODE_ISO:   /* the TF's colour at the iso value, shaded with the gradient at the hit */
    case REF_MODE_SLICE: { /* the TF's colour at the plane point, unshaded */
        const ref_tf *tf = &c->p->tf[c->p->field];
        double rgb[3] = {0, 0, 0}, tau, grad[REF_MAX_FIELDS][3] = {{0}};
        if (r->hit && c->p->mode == REF_MODE_SLICE) {
            ref_tf_eval(tf, field_at(c, r, r->t_hit, NULL), rgb, &tau);
        } else if (r->hit) {
            ref_tf_eval(tf, c->p->iso, rgb, &tau);
            if (c->p->shading != REF_SHADE_NONE) {
                field_at(c, r, r->t_hit, grad);
                shade(c, tf, grad[c->p->field], r->d, rgb);
            }
        }
        out[0] = rgb[0], out[1] = rgb[1], out[2] = rgb[2], out[3] = r->hit ? 1.0 : 0.0;
        break;
    }
    case REF_MODE_MIP: { /* the maximum through its field's colour map, opaque where sampled */
        const ref_tf *tf = &c->p->tf[r->fmax];
        double rgb[3] = {0, 0, 0}, tau;
        if (r->seen) ref_tf_eval(tf, tf->lo + r->vmax * (tf->hi - tf->lo), rgb, &tau);
        out[0] = rgb[0], out[1] = rgb[1], out[2] = rgb[2], out[3] = r->seen ? 1.0 : 0.0;
        break;
    }
    case REF_MODE_DVR:
    default: out[0] = r->C[0], out[1] = r->C[1], out[2] = r->C[2], out[3] = r->A; break;
    }
}

/* One pixel: out = premultiplied (C, A); depth and margin as ref_render_depth. */
static void trace(const ctx *c, int px, int py, double out[4], double *depth, double *margin)
{
    const ref_params *p = c->p;
    const ref_source *s = c->src;
    ray_state r = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, 0.0, 0.0, 0, 0, 0.0, 0.0, 0, 0.0, INFINITY};
    double phi[REF_MAX_FIELDS], grad[REF_MAX_FIELDS][3] = {{0}};
    double t0, t1;
    long k0, k1;
    double t_surf = INFINITY, srgb[3] = {0, 0, 0};
    ref_camera_ray(&p->camera, p->width, p->height, px, py, r.o, r.d);
    int surf = p->surface && p->surface(p->surface_user, p, r.o, r.d, &t_surf, srgb);
    if (!surf) t_surf = INFINITY;
    if (p->mode == REF_MODE_SLICE) { /* no lattice: one sample on the nearest plane */
        if (ref_ray_box(r.o, r.d, s->lo, s->hi, &t0, &t1)) slice_ray(c, &r, t0, t1, t_surf);
    } else if (ref_ray_box(r.o, r.d, s->lo, s->hi, &t0, &t1) &&
               ref_lattice_range(t0, t1, p->dt, p->rda, &k0, &k1) > 0) {
        /* dvr shades every sample; iso takes its one gradient at the hit */
        int need_grad = p->shading != REF_SHADE_NONE && p->mode == REF_MODE_DVR;
        for (long k = k0; k <= k1; k++) {
            double t = ref_lattice_t(k, p->dt, p->rda), x[3];
            if (surf && !(t < t_surf)) break; /* only samples strictly in front of the surface */
            for (int a = 0; a < 3; a++) x[a] = r.o[a] + t * r.d[a];
            s->eval(s->user, x, phi, need_grad ? grad : NULL);
            if (consume_sample(c, &r, k, t, phi, grad)) break;
        }
    }
    finish_ray(c, &r, out);
    if (depth) *depth = r.hit && (p->mode == REF_MODE_ISO || p->mode == REF_MODE_SLICE) ? r.t_hit : INFINITY;
    if (margin) *margin = r.margin;
    if (surf) { /* the opaque surface behind whatever the ray gathered */
        double w = 1.0 - out[3];
        for (int ch = 0; ch < 3; ch++) out[ch] += w * srgb[ch];
        out[3] = 1.0;
    }
}

int ref_render_pixel(const ref_source *src, const ref_params *p, int px, int py, double out[4])
{
    ctx c;
    if (setup(&c, src, p) || px < 0 || py < 0 || px >= p->width || py >= p->height) return -1;
    trace(&c, px, py, out, NULL, NULL);
    return 0;
}

int ref_render_depth(const ref_source *src, const ref_params *p, double *depth, double *margin)
{
    ctx c;
    if (!depth || setup(&c, src, p)) return -1;
    for (int py = 0; py < p->height; py++)
        for (int px = 0; px < p->width; px++) {
            double o[4];
            size_t i = (size_t)py * (size_t)p->width + (size_t)px;
            trace(&c, px, py, o, depth + i, margin ? margin + i : NULL);
        }
    return 0;
}

static int render(const ref_source *src, const ref_params *p, double *outd, float *outf)
{
    ctx c;
    if (setup(&c, src, p)) return -1;
    for (int py = 0; py < p->height; py++)
        for (int px = 0; px < p->width; px++) {
            double o[4];
            size_t i = 4 * ((size_t)py * (size_t)p->width + (size_t)px);
            trace(&c, px, py, o, NULL, NULL);
            for (int ch = 0; ch < 4; ch++) {
                if (outd) outd[i + ch] = o[ch];
                if (outf) outf[i + ch] = (float)o[ch];
            }
        }
    return 0;
}

int ref_render(const ref_source *src, const ref_params *p, double *rgba)
{
    return rgba ? render(src, p, rgba, NULL) : -1;
}

int ref_render_f(const ref_source *src, const ref_params *p, float *rgba)
{
    return rgba ? render(src, p, NULL, rgba) : -1;
}
