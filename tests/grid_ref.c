/* The reference: SPEC.md "Camera and rays", "Sampling and integration",
 * "Shading", evaluated in double with the exact piecewise-linear TF. */
#include "grid_ref.h"
#include <math.h>
#include "host/api/tf.h"

static double at(const ref_grid *g, int i, int j, int k) { return g->v[((size_t)k * g->n[1] + j) * g->n[0] + i]; }

double ref_sample(const ref_grid *g, const double x[3], double grad[3])
{
    int c[3];
    double w[3];
    for (int a = 0; a < 3; a++) {
        double u = (x[a] - g->origin[a]) / g->spacing[a];
        double f = floor(u);
        if (f < 0) f = 0;
        if (f > g->n[a] - 2) f = g->n[a] - 2;
        c[a] = (int)f;
        w[a] = u - f;
        if (w[a] < 0) w[a] = 0;
        if (w[a] > 1) w[a] = 1;
    }
    double v = 0, gr[3] = {0, 0, 0};
    for (int dk = 0; dk < 2; dk++)
        for (int dj = 0; dj < 2; dj++)
            for (int di = 0; di < 2; di++) {
                double val = at(g, c[0] + di, c[1] + dj, c[2] + dk);
                double wx = di ? w[0] : 1 - w[0], wy = dj ? w[1] : 1 - w[1], wz = dk ? w[2] : 1 - w[2];
                v += wx * wy * wz * val;
                gr[0] += (di ? 1 : -1) * wy * wz * val;
                gr[1] += wx * (dj ? 1 : -1) * wz * val;
                gr[2] += wx * wy * (dk ? 1 : -1) * val;
            }
    for (int a = 0; a < 3; a++) grad[a] = gr[a] / g->spacing[a];
    return v;
}

static void norm3(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int a = 0; a < 3; a++) v[a] /= l;
}
static void cross(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

void ref_render(const ref_grid *g, const ref_params *p, float *rgba)
{
    double fwd[3], right[3], up[3];
    for (int a = 0; a < 3; a++) fwd[a] = p->at[a] - p->eye[a];
    norm3(fwd);
    cross(fwd, p->up, right);
    norm3(right);
    cross(right, fwd, up);
    double th = tan(p->fovy * M_PI / 360.0), aspect = (double)p->width / p->height;
    double lo[3], hi[3];
    for (int a = 0; a < 3; a++) lo[a] = g->origin[a], hi[a] = g->origin[a] + (g->n[a] - 1) * g->spacing[a];
    double range = p->hi - p->lo;
    double grad_eps = 1e-6 * range / p->dt;
    for (int py = 0; py < p->height; py++)
        for (int px = 0; px < p->width; px++) {
            double u = (2.0 * (px + 0.5) / p->width - 1) * th * aspect, v = (1 - 2.0 * (py + 0.5) / p->height) * th;
            double d[3];
            for (int a = 0; a < 3; a++) d[a] = fwd[a] + u * right[a] + v * up[a];
            norm3(d);
            double t0 = 0, t1 = INFINITY;
            for (int a = 0; a < 3; a++) {
                if (d[a] == 0) {
                    if (p->eye[a] < lo[a] || p->eye[a] > hi[a]) t1 = -1;
                    continue;
                }
                double ta = (lo[a] - p->eye[a]) / d[a], tb = (hi[a] - p->eye[a]) / d[a];
                t0 = fmax(t0, fmin(ta, tb));
                t1 = fmin(t1, fmax(ta, tb));
            }
            double C[3] = {0, 0, 0}, A = 0;
            if (t0 <= t1) {
                /* SPEC.md: the step grows by rda*dt per sample, from the eye */
#define TK(k) (p->dt * ((double)(k) + p->rda * (double)(k) * ((double)(k) - 1) / 2))
                long k0 = 0;
                while (TK(k0) < t0) k0++;
                for (long k = k0; TK(k) <= t1 && A < p->alpha_stop; k++) {
                    double t = TK(k), x[3], gr[3];
                    for (int a = 0; a < 3; a++) x[a] = p->eye[a] + t * d[a];
                    double phi = ref_sample(g, x, gr);
                    double rgb[3], tau;
                    lci_tf_eval(p->tf, 0, fmin(fmax((phi - p->lo) / range, 0), 1), rgb, &tau);
                    double gl = sqrt(gr[0] * gr[0] + gr[1] * gr[1] + gr[2] * gr[2]);
                    if (p->shade && gl >= grad_eps) {
                        double ndl = fabs((gr[0] * d[0] + gr[1] * d[1] + gr[2] * d[2]) / gl);
                        double kk = 0.2 + 0.8 * ndl, s = p->shade == 2 ? 0.4 * pow(ndl, 16) : 0;
                        for (int c = 0; c < 3; c++) rgb[c] = rgb[c] * kk + s;
                    }
                    double al = 1 - exp(-tau * p->dt * (1 + p->rda * k));
                    for (int c = 0; c < 3; c++) C[c] += (1 - A) * al * rgb[c];
                    A += (1 - A) * al;
                }
            }
            float *o = rgba + ((size_t)py * p->width + px) * 4;
            o[0] = (float)C[0], o[1] = (float)C[1], o[2] = (float)C[2], o[3] = (float)A;
        }
}
