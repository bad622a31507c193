/* Scalar double-precision reference renderer (see ref_particles.h), from
 * SPEC.md "Fields", "Camera and rays", "Sampling and integration", "Shading"
 * and the opaque-sphere rule of Knoll 2014 §5.2 as lanecast defines it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "ref_particles.h"

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
    if (!(n > 0.0)) return -1;
    a[0] /= n, a[1] /= n, a[2] /= n;
    return 0;
}

/* Piecewise linear over control points [v, c0, c1, ...] (stride), clamped at both ends. */
static void pwl(const float *pts, int n, int stride, int nc, double v, double *out)
{
    if (v <= pts[0]) {
        for (int c = 0; c < nc; c++) out[c] = pts[1 + c];
        return;
    }
    for (int i = 1; i < n; i++) {
        const float *a = pts + (size_t)(i - 1) * stride, *b = pts + (size_t)i * stride;
        if (v < b[0]) {
            double w = (v - a[0]) / ((double)b[0] - a[0]);
            for (int c = 0; c < nc; c++) out[c] = a[1 + c] + w * ((double)b[1 + c] - a[1 + c]);
            return;
        }
    }
    const float *l = pts + (size_t)(n - 1) * stride;
    for (int c = 0; c < nc; c++) out[c] = l[1 + c];
}

typedef struct rtf {
    const lc_tf_field *f;
    double lo, hi;
} rtf;

static void classify(const rtf *t, double phi, double rgb[3], double *tau)
{
    double v = (phi - t->lo) / (t->hi - t->lo);
    v = v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v;
    pwl(t->f->color, t->f->ncolor, 4, 3, v, rgb);
    pwl(t->f->opacity, t->f->nopacity, 2, 1, v, tau);
}

void ref_field(const ref_particles *p, double sigma, double kappa, const double x[3], double *phi, double *grad,
               double *abs_sum, double *gabs_sum, double *pos_sens, double *gpos_sens, int *near_cut)
{
    int nf = p->nfields;
    for (int f = 0; f < nf; f++) {
        phi[f] = abs_sum[f] = gabs_sum[f] = pos_sens[f] = gpos_sens[f] = 0.0;
        grad[3 * f] = grad[3 * f + 1] = grad[3 * f + 2] = 0.0;
    }
    *near_cut = 0;
    double xmag = fabs(x[0]) + fabs(x[1]) + fabs(x[2]);
    for (size_t i = 0; i < p->count; i++) {
        const float *c = p->positions + 3 * i;
        double r = p->radii[i], R2 = sigma * r * sigma * r;
        double e[3] = {x[0] - c[0], x[1] - c[1], x[2] - c[2]};
        double d2 = dot3(e, e);
        if (fabs(d2 - R2) < 1e-5 * R2) *near_cut = 1;
        if (!(d2 < R2)) continue;
        double k = p->values ? p->values[i] : 1.0;
        int f = p->fields ? p->fields[i] : 0;
        double ph = kappa * k * exp(-d2 / (2.0 * r * r));
        double s = -ph / (r * r);
        phi[f] += ph;
        for (int a = 0; a < 3; a++) grad[3 * f + a] += s * e[a];
        double d = sqrt(d2), mag = xmag + fabs(c[0]) + fabs(c[1]) + fabs(c[2]);
        abs_sum[f] += fabs(ph);
        gabs_sum[f] += fabs(ph) * d / (r * r);
        /* d phi / d x = phi d / r^2; d grad / d x <= phi (1 + d^2 / r^2) / r^2 */
        pos_sens[f] += fabs(ph) * d / (r * r) * mag;
        gpos_sens[f] += fabs(ph) * (1.0 + d2 / (r * r)) / (r * r) * mag;
    }
}

typedef struct cand {
    size_t i;
    double t0, t1; /* chord of the sigma*r sphere along the ray */
} cand;

int ref_render(const ref_particles *p, const ref_params *q, double *rgba)
{
    const int W = q->width, H = q->height, nf = p->nfields > 0 ? p->nfields : 1;
    if (W < 1 || H < 1 || !(q->dt > 0.0f) || !q->tf || !(q->ntf == 1 || q->ntf >= nf)) return -1;
    memset(rgba, 0, sizeof(double) * 4 * (size_t)W * (size_t)H);
    if (p->count == 0) return 0;
    const double sigma = q->sigma, kappa = q->kappa, dt = q->dt, scale = q->sphere_scale;
    const lc_camera *cam = &q->camera;
    double eye[3] = {cam->eye.x, cam->eye.y, cam->eye.z}, at[3] = {cam->at.x, cam->at.y, cam->at.z};
    double up[3] = {cam->up.x, cam->up.y, cam->up.z};
    if (up[0] == 0 && up[1] == 0 && up[2] == 0) up[1] = 1.0;
    double fwd[3] = {at[0] - eye[0], at[1] - eye[1], at[2] - eye[2]}, right[3], upv[3];
    if (normalize3(fwd)) return -1;
    cross3(fwd, up, right);
    if (normalize3(right)) return -1;
    cross3(right, fwd, upv);
    int ortho = cam->projection == LC_ORTHOGRAPHIC;
    double fovy = cam->fovy == 0.0f ? 40.0 : cam->fovy;
    double sy = ortho ? 0.5 * cam->height : tan(fovy * M_PI / 360.0), sx = sy * W / H;
    if (ortho && !(cam->height > 0.0f)) return -1;

    /* lighting */
    const lc_lighting *l = &q->lighting;
    int custom = l->ka != 0 || l->kd != 0 || l->ks != 0 || l->phong_exp != 0;
    double ka = custom ? l->ka : 0.2, kd = custom ? l->kd : 0.8, ks = custom ? l->ks : 0.4;
    int pe = custom ? l->phong_exp : 16;

    /* transfer functions and value ranges per field */
    rtf tf[LC_MAX_FIELDS];
    int have_range = q->range[0] != 0.0f || q->range[1] != 0.0f;
    for (int f = 0; f < nf; f++) {
        tf[f].f = &q->tf[q->ntf == 1 ? 0 : f];
        if (have_range) tf[f].lo = q->range[0], tf[f].hi = q->range[1];
        else if (tf[f].f->has_range) tf[f].lo = tf[f].f->range[0], tf[f].hi = tf[f].f->range[1];
        else tf[f].lo = 0.0, tf[f].hi = fabs(kappa);
        if (!(tf[f].hi > tf[f].lo)) tf[f].hi = tf[f].lo + 1.0;
    }

    /* the lattice clip box: centre bounds grown by max(sigma, scale) * max r */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, rmax = 0.0;
    for (size_t i = 0; i < p->count; i++) {
        for (int a = 0; a < 3; a++) {
            double v = p->positions[3 * i + a];
            lo[a] = v < lo[a] ? v : lo[a];
            hi[a] = v > hi[a] ? v : hi[a];
        }
        rmax = p->radii[i] > rmax ? p->radii[i] : rmax;
    }
    double g = (scale > sigma ? scale : sigma) * rmax;
    for (int a = 0; a < 3; a++) lo[a] -= g, hi[a] += g;

    cand *cands = malloc(sizeof(cand) * p->count);
    if (!cands) return -1;
    size_t cap = 0;
    double *buf = NULL; /* per sample and field: phi, gx, gy, gz */
    int rc = 0;
    for (int py = 0; py < H && rc == 0; py++) {
        for (int px = 0; px < W; px++) {
            double u = (2.0 * (px + 0.5) / W - 1.0) * sx, v = (1.0 - 2.0 * (py + 0.5) / H) * sy;
            double o[3], d[3];
            for (int a = 0; a < 3; a++) {
                if (ortho) {
                    o[a] = eye[a] + u * right[a] + v * upv[a];
                    d[a] = fwd[a];
                } else {
                    o[a] = eye[a];
                    d[a] = fwd[a] + u * right[a] + v * upv[a];
                }
            }
            normalize3(d);
            /* ray / clip box, t >= 0 */
            double t0 = 0.0, t1 = INFINITY;
            for (int a = 0; a < 3; a++) {
                if (d[a] == 0.0) {
                    if (o[a] < lo[a] || o[a] > hi[a]) t0 = INFINITY;
                    continue;
                }
                double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
                if (ta > tb) { double s = ta; ta = tb; tb = s; }
                t0 = ta > t0 ? ta : t0;
                t1 = tb < t1 ? tb : t1;
            }
            double *out = rgba + 4 * ((size_t)py * W + px);
            if (!(t0 <= t1)) continue;
            long k0 = (long)ceil(t0 / dt), k1 = (long)floor(t1 / dt);

            /* opaque spheres: nearest hit t > 0 (either root) */
            double thit = INFINITY, srgb[3] = {0, 0, 0};
            if (scale > 0.0) {
                size_t best = 0;
                for (size_t i = 0; i < p->count; i++) {
                    const float *c = p->positions + 3 * i;
                    double oc[3] = {c[0] - o[0], c[1] - o[1], c[2] - o[2]};
                    double tc = dot3(oc, d), rr = scale * p->radii[i];
                    double h2 = rr * rr - (dot3(oc, oc) - tc * tc);
                    if (h2 < 0.0) continue;
                    double h = sqrt(h2), t = tc - h > 0.0 ? tc - h : tc + h;
                    if (t > 0.0 && t < thit) thit = t, best = i;
                }
                if (thit < INFINITY) {
                    const float *c = p->positions + 3 * best;
                    double rr = scale * p->radii[best], n[3];
                    for (int a = 0; a < 3; a++) n[a] = (o[a] + thit * d[a] - c[a]) / rr;
                    double ndl = fabs(dot3(n, d)), tau;
                    int f = p->fields ? p->fields[best] : 0;
                    classify(&tf[f], kappa * (p->values ? p->values[best] : 1.0), srgb, &tau);
                    double kk = ka + kd * ndl, spec = q->shading == LC_SHADE_PHONG ? ks * pow(ndl, pe) : 0.0;
                    for (int a = 0; a < 3; a++) srgb[a] = srgb[a] * kk + spec;
                    /* volume samples only strictly in front: k dt < t_hit */
                    long kh = (long)ceil(thit / dt) - 1;
                    k1 = kh < k1 ? kh : k1;
                }
            }
            double C[3] = {0, 0, 0}, A = 0.0;
            if (k1 >= k0) {
                size_t ns = (size_t)(k1 - k0 + 1);
                if (ns * nf * 4 > cap) {
                    free(buf);
                    cap = ns * nf * 4;
                    buf = malloc(sizeof(double) * cap);
                    if (!buf) { rc = -1; break; }
                }
                memset(buf, 0, sizeof(double) * ns * nf * 4);
                /* cull: particles whose sigma*r sphere the ray passes */
                size_t nc = 0;
                for (size_t i = 0; i < p->count; i++) {
                    const float *c = p->positions + 3 * i;
                    double oc[3] = {c[0] - o[0], c[1] - o[1], c[2] - o[2]};
                    double tc = dot3(oc, d), R = sigma * p->radii[i];
                    double h2 = R * R - (dot3(oc, oc) - tc * tc);
                    if (h2 < 0.0) continue;
                    double h = sqrt(h2);
                    cands[nc++] = (cand){i, tc - h, tc + h};
                }
                for (size_t j = 0; j < nc; j++) {
                    size_t i = cands[j].i;
                    long ka0 = (long)floor(cands[j].t0 / dt) - 1, kb = (long)ceil(cands[j].t1 / dt) + 1;
                    ka0 = ka0 < k0 ? k0 : ka0;
                    kb = kb > k1 ? k1 : kb;
                    const float *c = p->positions + 3 * i;
                    double r = p->radii[i], R2 = sigma * r * sigma * r;
                    double kv = kappa * (p->values ? p->values[i] : 1.0);
                    int f = p->fields ? p->fields[i] : 0;
                    for (long k = ka0; k <= kb; k++) {
                        double t = k * dt, e[3];
                        for (int a = 0; a < 3; a++) e[a] = o[a] + t * d[a] - c[a];
                        double d2 = dot3(e, e);
                        if (!(d2 < R2)) continue;
                        double ph = kv * exp(-d2 / (2.0 * r * r)), s = -ph / (r * r);
                        double *b = buf + ((size_t)(k - k0) * nf + f) * 4;
                        b[0] += ph;
                        b[1] += s * e[0], b[2] += s * e[1], b[3] += s * e[2];
                    }
                }
                for (long k = k0; k <= k1; k++) {
                    for (int f = 0; f < nf; f++) {
                        const double *b = buf + ((size_t)(k - k0) * nf + f) * 4;
                        double rgb[3], tau;
                        classify(&tf[f], b[0], rgb, &tau);
                        if (q->shading != LC_SHADE_NONE) {
                            double gl = sqrt(b[1] * b[1] + b[2] * b[2] + b[3] * b[3]);
                            if (gl >= 1e-6 * (tf[f].hi - tf[f].lo) / dt) {
                                /* n = -grad/|grad|, l = -dir: n.l = grad.dir/|grad|; h = l (headlight) */
                                double ndl = fabs((b[1] * d[0] + b[2] * d[1] + b[3] * d[2]) / gl);
                                double kk = ka + kd * ndl, spec = q->shading == LC_SHADE_PHONG ? ks * pow(ndl, pe) : 0.0;
                                for (int a = 0; a < 3; a++) rgb[a] = rgb[a] * kk + spec;
                            }
                        }
                        double al = 1.0 - exp(-tau * dt), w = (1.0 - A) * al;
                        for (int a = 0; a < 3; a++) C[a] += w * rgb[a];
                        A += w;
                    }
                    if (A >= q->alpha_stop) break;
                }
            }
            if (thit < INFINITY) {
                for (int a = 0; a < 3; a++) C[a] += (1.0 - A) * srgb[a];
                A += 1.0 - A;
            }
            out[0] = C[0], out[1] = C[1], out[2] = C[2], out[3] = A;
        }
    }
    free(buf);
    free(cands);
    return rc;
}
