/* The normalised SPH interpolant (issue 27; lc_particle_params.normalise):
 * A(x) = sum_j w_j A_j W(|x - x_j|, H_j) / sum_j w_j W(|x - x_j|, H_j), 0 where
 * no particle reaches, on every target this CPU runs, against references
 * written from the formula in double precision (no lanecast code):
 * (a) values and gradients at points (lc_volume_sample, the probes of both
 *     methods): the quotient of two direct float64 sums of the M4 and Wendland
 *     C2 closed forms written out here, and 0 outside every support; the
 *     unnormalised field and a denominator without the weights w_j must fail;
 * (b) slice images (coherent and direct: the slice's plane points with the
 *     full 3-D distance) and mip images (the host renders them with the
 *     direct method) against the reference renderer core fed with that
 *     quotient as its field (imgcmp at SPEC.md's tolerances); the
 *     unnormalised reference must fail;
 * (c) bad requests: normalise without norm_weights, with the Gaussian, or a
 *     value other than 0 or 1 fail with a message. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "host/internal.h" /* lci_render */
#include "imgcmp.h"
#include "modes_scene.h"
#include "ref/ref_core.h"

static const char *target_name;
static float hrad[NP], kval[NP], wval[NP];
static double dhrad[NP], dwval[NP], daval[NP];

/* the two kernels' f(u) and norm, from SPEC.md "SPH kernels and projections" */
static double w_shape(lc_kernel k, double u, double *norm)
{
    const double pi = 3.14159265358979323846;
    if (u >= 1.0) u = 1.0;
    if (k == LC_KERNEL_M4) {
        *norm = 8.0 / pi;
        return u < 0.5 ? 1.0 - 6.0 * u * u + 6.0 * u * u * u : 2.0 * pow(1.0 - u, 3);
    }
    *norm = 21.0 / (2.0 * pi);
    return pow(1.0 - u, 4) * (1.0 + 4.0 * u);
}

typedef struct nref {
    const scene *s;
    lc_kernel k;
    int mode; /* 0 normalised, 1 the numerator alone (unnormalised), 2 the denominator without w_j */
} nref;

/* The numerator and denominator per field at p (double), and whether any
 * particle reaches p. */
static void sums(const nref *r, const double p[3], double *num, double *den)
{
    for (int f = 0; f < 2; f++) num[f] = den[f] = 0.0;
    for (int j = 0; j < NP; j++) {
        double d2 = 0.0;
        for (int a = 0; a < 3; a++) d2 += (p[a] - r->s->dpos[3 * j + a]) * (p[a] - r->s->dpos[3 * j + a]);
        double hj = dhrad[j], u = sqrt(d2) / hj, norm;
        if (u >= 1.0) continue;
        double wj = w_shape(r->k, u, &norm) * norm / (hj * hj * hj);
        int f = r->s->field[j];
        num[f] += dwval[j] * daval[j] * wj;
        den[f] += (r->mode == 2 ? 1.0 : dwval[j]) * wj;
    }
}

static void nref_value(const nref *r, const double p[3], double *phi)
{
    double num[2], den[2];
    sums(r, p, num, den);
    for (int f = 0; f < 2; f++) phi[f] = r->mode == 1 ? num[f] : den[f] > 0.0 ? num[f] / den[f] : 0.0;
}

/* the field callback of the reference core: values and central-difference gradients */
static void nref_eval(const void *user, const double p[3], double *phi, double (*grad)[3])
{
    nref_value(user, p, phi);
    if (!grad) return;
    const double h = 1e-6;
    for (int a = 0; a < 3; a++) {
        double q[3] = {p[0], p[1], p[2]}, lo[2], hi[2];
        q[a] = p[a] + h;
        nref_value(user, q, hi);
        q[a] = p[a] - h;
        nref_value(user, q, lo);
        for (int f = 0; f < 2; f++) grad[f][a] = (hi[f] - lo[f]) / (2.0 * h);
    }
}

static lc_volume *make_volume(lc_device *dev, const scene *s, lc_kernel k, int normalise)
{
    lc_volume *v = NULL;
    lc_particles_desc pd = {.count = NP, .positions = s->pos, .radii = hrad, .values = kval, .fields = s->field,
                            .nfields = 2, .norm_weights = wval, .params = {.kernel = k, .normalise = normalise}};
    if (lc_particles_create(dev, &pd, &v) != LC_OK) CHECK(0, "%s: particles: %s", target_name, lc_last_error());
    return v;
}

/* ---------------------------------------------------------------- (a) points */

enum { NPT = 500 };

static void run_points(lc_device *dev, const scene *s, lc_kernel k)
{
    static float pts[3 * NPT], v[2 * NPT], g[6 * NPT];
    uint32_t r = 5u;
    for (int i = 0; i < 3 * NPT; i++) {
        r = r * 1664525u + 1013904223u;
        pts[i] = (float)(4.4 * (double)(r >> 8) / 16777216.0 - 2.2); /* some points outside every support */
    }
    lc_volume *vol = make_volume(dev, s, k, 1);
    if (!vol) return;
    if (lc_volume_sample(dev, vol, NPT, pts, v, g) != LC_OK) {
        CHECK(0, "%s: sample: %s", target_name, lc_last_error());
        lc_volume_destroy(vol);
        return;
    }
    double ev = 0.0, eg = 0.0, e_un = 0.0, e_w = 0.0, gscale = 0.0;
    int inside = 0, outside = 0, zero_bad = 0;
    nref rn = {s, k, 0}, ru = {s, k, 1}, rw = {s, k, 2};
    for (int i = 0; i < NPT; i++) {
        double p[3] = {pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]}, want[2], grad[2][3], un[2], ww[2], num[2], den[2];
        nref_eval(&rn, p, want, grad);
        nref_value(&ru, p, un);
        nref_value(&rw, p, ww);
        sums(&rn, p, num, den);
        for (int f = 0; f < 2; f++) {
            double got = v[2 * i + f];
            if (den[f] == 0.0) { /* no particle of the field reaches: exactly 0 */
                outside++;
                zero_bad += got != 0.0;
                continue;
            }
            inside++;
            /* A is a weighted mean of the A_j in [1, 3]: float sums of positive terms, a few ulps */
            ev = fmax(ev, fabs(got - want[f]));
            e_un = fmax(e_un, fabs(got - un[f]));
            e_w = fmax(e_w, fabs(got - ww[f]));
            for (int a = 0; a < 3; a++) {
                eg = fmax(eg, fabs(g[3 * (2 * i + f) + a] - grad[f][a]));
                gscale = fmax(gscale, fabs(grad[f][a]));
            }
        }
    }
    CHECK(inside > NPT / 2 && outside > 20 && zero_bad == 0 && ev < 2e-5,
          "%s: %s normalised at %d field points (%d outside: %d not 0): value error %.2e (values 1..3)", target_name,
          lc_kernel_name(k), inside, outside, zero_bad, ev);
    /* the gradient: quotient rule in float against central differences in double */
    CHECK(eg < 2e-3 * gscale, "%s: %s normalised gradient error %.2e of gradients up to %.2f", target_name,
          lc_kernel_name(k), eg, gscale);
    CHECK(e_un > 0.1 && e_w > 0.1, "%s: %s: the unnormalised field (off by %.2f) and a denominator without w_j "
          "(off by %.2f) are caught", target_name, lc_kernel_name(k), e_un, e_w);
    lc_volume_destroy(vol);
}

/* ---------------------------------------------------------------- (b) images */

static const double planes[1][6] = {{0.1, -0.1, 0.2, 0.2, 0.1, 1.0}};
static const float opa_mip[] = {0.0f, 0.0f, 1.0f, 1.0f};

static ref_params ref_view(const ref_tf *tf, ref_mode mode)
{
    ref_params p = {0};
    p.width = W, p.height = H;
    p.camera = (ref_camera){REF_PERSPECTIVE, {0.7, 0.9, 9.0}, {0.05, 0.1, 0.0}, {0, 1, 0}, 38.0, 0.0};
    p.mode = mode;
    p.tf = tf;
    p.dt = 0.05;
    p.alpha_stop = 1.0;
    p.field = 1;
    memcpy(p.planes, planes, sizeof planes);
    p.nplanes = 1;
    return p;
}

static lc_render_desc lib_view(const lc_volume *v, const lc_tf *tf, lc_mode mode)
{
    lc_render_desc d = {0};
    d.width = W, d.height = H;
    d.camera = (lc_camera){LC_PERSPECTIVE, {0.7f, 0.9f, 9.0f}, {0.05f, 0.1f, 0.0f}, {0, 1, 0}, 38.0f, 0.0f};
    d.mode = mode;
    d.tf = tf;
    d.volume = v;
    d.dt = 0.05f;
    d.alpha_stop = 1.0f;
    d.field = 1;
    d.planes[0] = (lc_plane){{(float)planes[0][0], (float)planes[0][1], (float)planes[0][2]},
                             {(float)planes[0][3], (float)planes[0][4], (float)planes[0][5]}};
    d.nplanes = 1;
    return d;
}

static void run_images(lc_device *dev, const scene *s, lc_kernel k, const char *diff_dir)
{
    static float want[4 * W * H], wrong[4 * W * H], img[4 * W * H];
    static double dopa_mip[4];
    to_double(col0, dcol0, 12), to_double(col1, dcol1, 8), to_double(opa_mip, dopa_mip, 4);
    /* the values 1..3 over the TF's [0, 1] */
    ref_tf rtf[2] = {{0.5, 3.5, dcol0, 3, dopa_mip, 2}, {0.5, 3.5, dcol1, 2, dopa_mip, 2}};
    lc_tf_field tfm[2] = {{col0, 3, opa_mip, 2, 1, {0.5f, 3.5f}}, {col1, 2, opa_mip, 2, 1, {0.5f, 3.5f}}};
    lc_tf *tf = NULL;
    if (lc_tf_create(dev, tfm, 2, &tf) != LC_OK) {
        CHECK(0, "%s: tf: %s", target_name, lc_last_error());
        return;
    }
    double grow = 0.0;
    for (int j = 0; j < NP; j++) grow = fmax(grow, dhrad[j]);
    nref rn = {s, k, 0}, ru = {s, k, 1};
    ref_source src = {nref_eval, &rn, 2, {0, 0, 0}, {0, 0, 0}};
    for (int a = 0; a < 3; a++) {
        src.lo[a] = INFINITY, src.hi[a] = -INFINITY;
        for (int j = 0; j < NP; j++) src.lo[a] = fmin(src.lo[a], s->dpos[3 * j + a]), src.hi[a] = fmax(src.hi[a], s->dpos[3 * j + a]);
        src.lo[a] -= grow, src.hi[a] += grow;
    }
    ref_source srcu = src;
    srcu.user = &ru;
    lc_volume *v = make_volume(dev, s, k, 1);
    static const struct {
        ref_mode rm;
        lc_mode lm;
        const char *name;
    } modes[] = {{REF_MODE_SLICE, LC_MODE_SLICE, "slice"}, {REF_MODE_MIP, LC_MODE_MIP, "mip"}};
    static const lc_method pm[] = {LC_METHOD_COHERENT, LC_METHOD_DIRECT};
    for (int m = 0; v && m < 2; m++) {
        ref_params p = ref_view(rtf, modes[m].rm);
        if (ref_render_f(&src, &p, want) != 0 || ref_render_f(&srcu, &p, wrong) != 0) {
            CHECK(0, "reference %s", modes[m].name);
            continue;
        }
        double amax = 0.0;
        for (int i = 0; i < W * H; i++) amax = fmax(amax, want[4 * i + 3]);
        CHECK(amax > 0.5, "reference %s %s: alpha up to %.2f", lc_kernel_name(k), modes[m].name, amax);
        char label[96];
        snprintf(label, sizeof label, "sph-norm-%s-%s-unnormalised", lc_kernel_name(k), modes[m].name);
        if (!strcmp(target_name, "scalar"))
            CHECK(imgcmp_check(label, wrong, want, W, H, 0, 0, NULL) != 0, "%s is caught", label);
        for (int me = 0; me < 2; me++) {
            lc_render_desc d = lib_view(v, tf, modes[m].lm);
            d.method = pm[me];
            snprintf(label, sizeof label, "sph-norm-%s-%s-%s-%s", lc_kernel_name(k), modes[m].name, target_name,
                     me ? "direct" : "coherent");
            lc_status st = lci_render(dev, &d, img, NULL, NULL);
            CHECK_QUIET(st == LC_OK, "%s: %s", label, lc_last_error());
            if (st != LC_OK) continue;
            imgcmp_result r;
            int bad = imgcmp_check_ex(label, img, want, W, H, 0, 0, diff_dir, 1, &r);
            CHECK(bad == 0, "%s: max %.3f/255, PSNR %.1f dB", label, r.max_diff_255, r.psnr_db);
        }
    }
    lc_volume_destroy(v);
    lc_tf_destroy(tf);
}

/* ---------------------------------------------------------------- (c) bad requests */

static void run_errors(lc_device *dev, const scene *s)
{
    lc_volume *v = NULL;
    lc_particles_desc pd = {.count = NP, .positions = s->pos, .radii = hrad, .values = kval,
                            .params = {.kernel = LC_KERNEL_M4, .normalise = 1}};
    CHECK(lc_particles_create(dev, &pd, &v) == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "norm_weights"),
          "normalise without norm_weights: %s", lc_last_error());
    pd.params.normalise = 0;
    if (lc_particles_create(dev, &pd, &v) != LC_OK) return;
    lc_particle_params q = {.kernel = LC_KERNEL_M4, .normalise = 1};
    CHECK(lc_particles_set_params(v, &q) == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "norm_weights"),
          "set_params normalise without norm_weights: %s", lc_last_error());
    lc_volume_destroy(v);
    v = make_volume(dev, s, LC_KERNEL_M4, 0);
    if (!v) return;
    q = (lc_particle_params){.kernel = LC_KERNEL_GAUSSIAN, .normalise = 1};
    CHECK(lc_particles_set_params(v, &q) == LC_ERROR_INVALID_ARGUMENT && strstr(lc_last_error(), "SPH kernel"),
          "normalise with the Gaussian: %s", lc_last_error());
    q = (lc_particle_params){.kernel = LC_KERNEL_M4, .normalise = 2};
    CHECK(lc_particles_set_params(v, &q) == LC_ERROR_INVALID_ARGUMENT, "normalise = 2: %s", lc_last_error());
    lc_volume_destroy(v);
}

int main(int argc, char **argv)
{
    const char *diff_dir = argc > 1 ? argv[1] : NULL;
    (void)rbf_domain, (void)dopa; /* modes_scene.h's RBF set and opacity are not used here */
    static scene s;
    make_scene(&s);
    uint32_t r = 11u;
    for (int i = 0; i < NP; i++) {
        dhrad[i] = hrad[i] = (float)(2.5 * s.drad[i]);
        r = r * 1664525u + 1013904223u;
        wval[i] = (float)(0.5 + (double)(r >> 8) / 16777216.0); /* m / rho in [0.5, 1.5) */
        r = r * 1664525u + 1013904223u;
        float a = (float)(1.0 + 2.0 * (double)(r >> 8) / 16777216.0); /* A in [1, 3) */
        kval[i] = wval[i] * a;
        dwval[i] = wval[i];
        daval[i] = (double)kval[i] / (double)wval[i]; /* the A_j the library divides out, in double */
    }
    for (int t = LC_TARGET_SCALAR; t < LC_TARGET_COUNT; t++) {
        target_name = lc_target_name((lc_target)t);
        if (!lc_target_compiled((lc_target)t) || !lc_target_supported((lc_target)t)) {
            printf("skip %s: not compiled or not supported by this CPU\n", target_name);
            continue;
        }
        lc_device *dev;
        if (lc_device_create(&(lc_device_desc){.target = (lc_target)t, .threads = 2}, &dev) != LC_OK) {
            CHECK(0, "%s: device: %s", target_name, lc_last_error());
            continue;
        }
        for (int k = 0; k < 2; k++) {
            lc_kernel kern = k ? LC_KERNEL_WENDLAND_C2 : LC_KERNEL_M4;
            run_points(dev, &s, kern);
            run_images(dev, &s, kern, diff_dir);
        }
        if (t == LC_TARGET_SCALAR) run_errors(dev, &s);
        lc_device_destroy(dev);
    }
    return check_summary("sph_normalise");
}
