/* Field evaluators of SPEC.md "Fields" (see ref_fields.h): brute force over
 * every term, exp from libm, analytic gradients. */
#include "ref_fields.h"

#include <math.h>

static void box_empty(ref_source *src)
{
    for (int a = 0; a < 3; a++) src->lo[a] = INFINITY, src->hi[a] = -INFINITY;
}

static void box_grow(ref_source *src, const double c[3], double r)
{
    for (int a = 0; a < 3; a++) {
        src->lo[a] = fmin(src->lo[a], c[a] - r);
        src->hi[a] = fmax(src->hi[a], c[a] + r);
    }
}

/* ---------------------------------------------------------------- particles */

static double psigma(const ref_particle_set *ps) { return ps->sigma == 0.0 ? 2.0 : ps->sigma; }
static double pkappa(const ref_particle_set *ps) { return ps->kappa == 0.0 ? 1.0 : ps->kappa; }
static int pnfields(const ref_particle_set *ps) { return ps->nfields < 1 ? 1 : ps->nfields; }

/* Each bracketed power taken as 0 where its base is negative (SPEC.md). */
static double ppow(double x, int n) { return x > 0.0 ? pow(x, n) : 0.0; }

double ref_sph_w(ref_kernel kernel, double u)
{
    if (!(u >= 0.0 && u < 1.0)) return 0.0;
    const double pi = 3.14159265358979323846;
    double q;
    switch (kernel) {
    case REF_KERNEL_M4:
        return u <= 0.5 ? 8.0 / pi * (1.0 - 6.0 * u * u + 6.0 * u * u * u) : 8.0 / pi * 2.0 * pow(1.0 - u, 3);
    case REF_KERNEL_M5:
        q = 2.5 * u;
        return pow(2.5, 3) / (20.0 * pi) * (ppow(2.5 - q, 4) - 5.0 * ppow(1.5 - q, 4) + 10.0 * ppow(0.5 - q, 4));
    case REF_KERNEL_M6:
        q = 3.0 * u;
        return 27.0 / (120.0 * pi) * (ppow(3.0 - q, 5) - 6.0 * ppow(2.0 - q, 5) + 15.0 * ppow(1.0 - q, 5));
    case REF_KERNEL_C2: return 21.0 / (2.0 * pi) * pow(1.0 - u, 4) * (1.0 + 4.0 * u);
    case REF_KERNEL_C4: return 495.0 / (32.0 * pi) * pow(1.0 - u, 6) * (1.0 + 6.0 * u + 35.0 * u * u / 3.0);
    case REF_KERNEL_C6:
        return 1365.0 / (64.0 * pi) * pow(1.0 - u, 8) * (1.0 + 8.0 * u + 25.0 * u * u + 32.0 * u * u * u);
    default: return 0.0;
    }
}

/* w'(u) by a central difference of w(|u|) (step 1e-6: the kernels are at least
 * C^2, so its error is ~1e-12 of the kernel's scale), not from a second copy
 * of the derivatives. */
static double sph_dw(ref_kernel kernel, double u)
{
    const double h = 1e-6;
    return (ref_sph_w(kernel, fabs(u + h)) - ref_sph_w(kernel, fabs(u - h))) / (2.0 * h);
}

/* One particle's term (and gradient, when gr is not NULL) at offset e = x - x_i,
 * d2 = |e|^2; 0 outside its support. */
static double pterm(const ref_particle_set *ps, ref_kernel kernel, double norm_scale, size_t i, const double e[3],
                    double d2, double gr[3])
{
    const double r = ps->radius[i], kk = pkappa(ps) * (ps->value ? ps->value[i] : 1.0);
    if (kernel == REF_KERNEL_GAUSSIAN) {
        const double sigma = psigma(ps);
        if (!(d2 < sigma * r * sigma * r)) return 0.0;
        double ph = kk * exp(-d2 / (2.0 * r * r));
        /* grad phi_i = -(x - x_i) / r_i^2 phi_i */
        if (gr)
            for (int a = 0; a < 3; a++) gr[a] = -e[a] / (r * r) * ph;
        return ph;
    }
    if (!(d2 < r * r)) return 0.0;
    double d = sqrt(d2), u = d / r, sc = (norm_scale == 0.0 ? 1.0 : norm_scale) * kk / (r * r * r);
    if (gr) {
        double dw = d > 0.0 ? sc * sph_dw(kernel, u) / r / d : 0.0; /* dW/dd (x - x_i) / d */
        for (int a = 0; a < 3; a++) gr[a] = dw * e[a];
    }
    return sc * ref_sph_w(kernel, u);
}

static void eval_kernel(const ref_particle_set *ps, ref_kernel kernel, double norm_scale, const double p[3],
                        double *phi, double (*grad)[3])
{
    const int nf = pnfields(ps);
    for (int f = 0; f < nf; f++) {
        phi[f] = 0.0;
        if (grad) grad[f][0] = grad[f][1] = grad[f][2] = 0.0;
    }
    for (size_t i = 0; i < ps->count; i++) {
        const double *c = ps->pos + 3 * i;
        double e[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
        double d2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2], gr[3] = {0.0, 0.0, 0.0};
        double ph = pterm(ps, kernel, norm_scale, i, e, d2, grad ? gr : NULL);
        if (ph == 0.0 && gr[0] == 0.0 && gr[1] == 0.0 && gr[2] == 0.0) continue; /* outside its support */
        int f = ps->field ? ps->field[i] : 0;
        phi[f] += ph;
        if (grad)
            for (int a = 0; a < 3; a++) grad[f][a] += gr[a];
    }
}

void ref_particles_eval(const void *user, const double p[3], double *phi, double (*grad)[3])
{
    eval_kernel(user, REF_KERNEL_GAUSSIAN, 0.0, p, phi, grad);
}

void ref_sph_eval(const void *user, const double p[3], double *phi, double (*grad)[3])
{
    const ref_sph_set *s = user;
    eval_kernel(&s->ps, s->kernel, s->norm_scale, p, phi, grad);
}

static int source_kernel(const ref_particle_set *ps, ref_kernel kernel, ref_source *src)
{
    const int nf = pnfields(ps);
    if (nf > REF_MAX_FIELDS || (ps->count && (!ps->pos || !ps->radius)) || kernel < 0 || kernel >= REF_KERNEL_COUNT)
        return -1;
    double rmax = 0.0;
    for (size_t i = 0; i < ps->count; i++) {
        if (!(ps->radius[i] > 0.0) || (ps->field && (ps->field[i] < 0 || ps->field[i] >= nf))) return -1;
        rmax = fmax(rmax, ps->radius[i]);
    }
    src->eval = ref_particles_eval, src->user = ps, src->nfields = nf;
    box_empty(src);
    for (size_t i = 0; i < ps->count; i++) box_grow(src, ps->pos + 3 * i, 0.0);
    double g = (kernel == REF_KERNEL_GAUSSIAN ? psigma(ps) : 1.0) * rmax; /* an SPH kernel's support is r */
    if (ps->count)
        for (int a = 0; a < 3; a++) src->lo[a] -= g, src->hi[a] += g;
    return 0;
}

int ref_particles_source(const ref_particle_set *ps, ref_source *src)
{
    return source_kernel(ps, REF_KERNEL_GAUSSIAN, src);
}

int ref_sph_source(const ref_sph_set *s, ref_source *src)
{
    int rc = source_kernel(&s->ps, s->kernel, src);
    src->eval = ref_sph_eval, src->user = s;
    return rc;
}

void ref_particles_budget(const ref_particle_set *ps, const double x[3], double *abs_sum, double *gabs_sum,
                          double *pos_sens, double *gpos_sens, int *near_cut)
{
    const double sigma = psigma(ps), kappa = pkappa(ps);
    const int nf = pnfields(ps);
    for (int f = 0; f < nf; f++) abs_sum[f] = gabs_sum[f] = pos_sens[f] = gpos_sens[f] = 0.0;
    *near_cut = 0;
    const double xmag = fabs(x[0]) + fabs(x[1]) + fabs(x[2]);
    for (size_t i = 0; i < ps->count; i++) {
        const double *c = ps->pos + 3 * i, r = ps->radius[i], R2 = sigma * r * sigma * r;
        double e[3] = {x[0] - c[0], x[1] - c[1], x[2] - c[2]};
        double d2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
        if (fabs(d2 - R2) < 1e-5 * R2) *near_cut = 1;
        if (!(d2 < R2)) continue;
        int f = ps->field ? ps->field[i] : 0;
        double ph = fabs(kappa * (ps->value ? ps->value[i] : 1.0) * exp(-d2 / (2.0 * r * r)));
        double d = sqrt(d2), mag = xmag + fabs(c[0]) + fabs(c[1]) + fabs(c[2]);
        abs_sum[f] += ph;
        gabs_sum[f] += ph * d / (r * r); /* |grad phi_i| = |phi_i| d / r^2 */
        /* |d phi_i / dx| = |phi_i| d / r^2; |d grad phi_i / dx| <= |phi_i| (1 + d^2 / r^2) / r^2 */
        pos_sens[f] += ph * d / (r * r) * mag;
        gpos_sens[f] += ph * (1.0 + d2 / (r * r)) / (r * r) * mag;
    }
}

int ref_particles_spheres(const void *user, const ref_params *p, const double o[3], const double d[3], double *t,
                          double rgb[3])
{
    const ref_sphere_set *ss = user;
    const ref_particle_set *ps = ss->ps;
    double best = INFINITY;
    size_t hit = 0;
    for (size_t i = 0; i < ps->count; i++) {
        const double *c = ps->pos + 3 * i, rr = ss->scale * ps->radius[i];
        double oc[3] = {c[0] - o[0], c[1] - o[1], c[2] - o[2]};
        double tc = oc[0] * d[0] + oc[1] * d[1] + oc[2] * d[2];
        double h2 = rr * rr - (oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2] - tc * tc);
        if (h2 < 0.0) continue;
        double h = sqrt(h2), th = tc - h > 0.0 ? tc - h : tc + h;
        if (th > 0.0 && th < best) best = th, hit = i;
    }
    if (!(best < INFINITY)) return 0;
    const double *c = ps->pos + 3 * hit, rr = ss->scale * ps->radius[hit];
    double ndl = 0.0, k[4], tau;
    for (int a = 0; a < 3; a++) ndl += (o[a] + best * d[a] - c[a]) / rr * d[a];
    ndl = fabs(ndl);
    int f = ps->field ? ps->field[hit] : 0;
    ref_tf_eval(&p->tf[f], pkappa(ps) * (ps->value ? ps->value[hit] : 1.0), rgb, &tau);
    ref_lighting(p, k);
    double kk = k[0] + k[1] * ndl, spec = p->shading == REF_SHADE_PHONG ? k[2] * pow(ndl, k[3]) : 0.0;
    for (int a = 0; a < 3; a++) rgb[a] = rgb[a] * kk + spec;
    *t = best;
    return 1;
}

/* ---------------------------------------------------------------- structured grid */

static double node(const ref_grid_field *g, int i, int j, int k)
{
    return g->values[((size_t)k * (size_t)g->n[1] + (size_t)j) * (size_t)g->n[0] + (size_t)i];
}

void ref_grid_eval(const void *user, const double p[3], double *phi, double (*grad)[3])
{
    const ref_grid_field *g = user;
    int c[3];
    double w[3];
    for (int a = 0; a < 3; a++) {
        /* cell by floor, clamped to the domain (the lattice never leaves it but for round-off) */
        double u = (p[a] - g->origin[a]) / g->spacing[a], f = floor(u);
        f = f < 0.0 ? 0.0 : f > g->n[a] - 2 ? g->n[a] - 2 : f;
        c[a] = (int)f;
        w[a] = u - f;
        w[a] = w[a] < 0.0 ? 0.0 : w[a] > 1.0 ? 1.0 : w[a];
    }
    double v = 0.0, gr[3] = {0.0, 0.0, 0.0};
    for (int dk = 0; dk < 2; dk++)
        for (int dj = 0; dj < 2; dj++)
            for (int di = 0; di < 2; di++) {
                double val = node(g, c[0] + di, c[1] + dj, c[2] + dk);
                double wx = di ? w[0] : 1.0 - w[0], wy = dj ? w[1] : 1.0 - w[1], wz = dk ? w[2] : 1.0 - w[2];
                v += wx * wy * wz * val;
                gr[0] += (di ? 1.0 : -1.0) * wy * wz * val;
                gr[1] += wx * (dj ? 1.0 : -1.0) * wz * val;
                gr[2] += wx * wy * (dk ? 1.0 : -1.0) * val;
            }
    phi[0] = v;
    if (grad)
        for (int a = 0; a < 3; a++) grad[0][a] = gr[a] / g->spacing[a];
}

int ref_grid_source(const ref_grid_field *g, ref_source *src)
{
    if (!g->values) return -1;
    for (int a = 0; a < 3; a++)
        if (g->n[a] < 2 || !(g->spacing[a] > 0.0) || !isfinite(g->origin[a])) return -1;
    src->eval = ref_grid_eval, src->user = g, src->nfields = 1;
    for (int a = 0; a < 3; a++) {
        src->lo[a] = g->origin[a];
        src->hi[a] = g->origin[a] + (g->n[a] - 1) * g->spacing[a];
    }
    return 0;
}

/* ---------------------------------------------------------------- RBF set */

double ref_rbf_support(double width, double weight, double eps)
{
    double q = fabs(weight) / eps;
    return q > 1.0 ? width * sqrt(2.0 * log(q)) : 0.0;
}

void ref_rbf_eval(const void *user, const double p[3], double *phi, double (*grad)[3])
{
    const ref_rbf_set *s = user;
    double v = s->bias, gr[3] = {0.0, 0.0, 0.0};
    for (size_t i = 0; i < s->count; i++) {
        const double *c = s->centre + 3 * i, sw = s->width[i];
        double R = ref_rbf_support(sw, s->weight[i], s->eps);
        double e[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
        double d2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
        if (!(d2 < R * R)) continue;
        double ph = s->weight[i] * exp(-d2 / (2.0 * sw * sw));
        v += ph;
        for (int a = 0; a < 3; a++) gr[a] -= e[a] / (sw * sw) * ph;
    }
    phi[0] = v;
    if (grad) grad[0][0] = gr[0], grad[0][1] = gr[1], grad[0][2] = gr[2];
}

int ref_rbf_source(const ref_rbf_set *s, ref_source *src)
{
    if (!(s->eps > 0.0) || (s->count && (!s->centre || !s->width || !s->weight))) return -1;
    src->eval = ref_rbf_eval, src->user = s, src->nfields = 1;
    box_empty(src);
    for (size_t i = 0; i < s->count; i++) {
        if (!(s->width[i] > 0.0)) return -1;
        double R = ref_rbf_support(s->width[i], s->weight[i], s->eps);
        if (R > 0.0) box_grow(src, s->centre + 3 * i, R);
    }
    return 0;
}
