/* The independent reference renderer core for the tests: slow, scalar, double
 * precision, written straight from SPEC.md ("Camera and rays", "Sampling and
 * integration", "Shading"). It includes and calls nothing of lanecast; the
 * data comes from a field callback (see ref_fields.h for the SPEC.md kinds),
 * so every kind shares one camera, one lattice, one transfer function and one
 * blending rule. Zero in a parameter struct means the SPEC.md default. */
#ifndef LC_TEST_REF_CORE_H
#define LC_TEST_REF_CORE_H

#define REF_MAX_FIELDS 64

typedef enum ref_projection { REF_PERSPECTIVE = 0, REF_ORTHOGRAPHIC = 1 } ref_projection;

typedef struct ref_camera {
    ref_projection projection;
    double eye[3], at[3];
    double up[3];  /* all zero: +y */
    double fovy;   /* perspective: vertical field of view in degrees, (0, 180) */
    double height; /* orthographic: image-plane height in world units, > 0 */
} ref_camera;

/* A mode consumes the field samples of a ray (SPEC.md "Sampling and
 * integration", "Other modes"); the one switch is in ref_core.c
 * (consume_sample / finish_ray; slice takes no lattice sample, trace()). */
typedef enum ref_mode { REF_MODE_DVR = 0, REF_MODE_ISO, REF_MODE_MIP, REF_MODE_SLICE } ref_mode;

#define REF_MAX_PLANES 4

typedef enum ref_shading { REF_SHADE_NONE = 0, REF_SHADE_DIFFUSE, REF_SHADE_PHONG } ref_shading;

/* One field's transfer function: colour points [v, r, g, b] and opacity points
 * [v, tau] (tau = extinction per world unit), v non-decreasing, evaluated
 * exactly piecewise linear, clamped at both ends, over v = (phi - lo) / (hi - lo)
 * clamped to [0, 1]. hi > lo. */
typedef struct ref_tf {
    double lo, hi;
    const double *color; /* 4 * ncolor */
    int ncolor;
    const double *opacity; /* 2 * nopacity */
    int nopacity;
} ref_tf;

/* Field values phi[f] (and, when grad is not NULL, gradients grad[f]) of all
 * nfields fields at world point p. */
typedef void (*ref_field_fn)(const void *user, const double p[3], double *phi /*[nfields]*/,
                             double (*grad)[3] /*[nfields], may be NULL*/);

/* A data source: the field callback and the box the lattice is clipped to
 * (particle bounds grown by sigma * max r, a grid's first-to-last-node box...).
 * An empty box (lo > hi on an axis) renders nothing. */
typedef struct ref_source {
    ref_field_fn eval;
    const void *user;
    int nfields; /* 1 .. REF_MAX_FIELDS */
    double lo[3], hi[3];
} ref_source;

/* Optional extinction scale of lattice sample k at t (tau is multiplied by it
 * before a = 1 - exp(-tau * dt * scale)). NULL: 1 + rda * k, the length of
 * the step that follows sample k in differential sampling. */
typedef double (*ref_tau_scale_fn)(const void *user, long k, double t);

typedef struct ref_params ref_params;

/* Optional opaque surface behind the volume (not a SPEC.md mode: a kind's
 * own extra geometry, e.g. lanecast's opaque particle spheres; see
 * ref_fields.h). Returns 1 and the surface's distance *t > 0 along the ray
 * (o, d) and its final colour rgb (classified and lit by the callback), or 0
 * on a miss. With a hit, only lattice samples with t_k < *t are taken, and
 * after the ray's samples (also after early termination) the surface is
 * blended behind them: C += (1 - A) rgb, A = 1. */
typedef int (*ref_surface_fn)(const void *user, const ref_params *p, const double o[3], const double d[3], double *t,
                              double rgb[3]);

struct ref_params {
    int width, height;
    ref_camera camera;
    ref_mode mode;
    const ref_tf *tf;  /* one per source field, blended in field order */
    double dt;         /* > 0 */
    double alpha_stop; /* 0: 0.97; >= 1: never stop */
    ref_shading shading;
    double ka, kd, ks, p; /* all zero: 0.2, 0.8, 0.4, 16 */
    double rda;           /* >= 0; t_k = dt (k + rda k (k - 1) / 2); 0 = uniform */
    ref_tau_scale_fn tau_scale;
    const void *tau_scale_user;
    ref_surface_fn surface; /* NULL: none */
    const void *surface_user;
    /* iso: the iso value and the field (0 .. nfields - 1). Along the ray, the
     * first pair of consecutive lattice samples on different sides (phi >= iso
     * or not) is bisected to at most 1e-4 dt; the hit is the end of that
     * bracket on the phi >= iso side; it shows the field's colour at the iso
     * value, shaded with the gradient there, opaque. No crossing: transparent. */
    double iso;
    int field; /* iso and slice */
    /* slice: planes[i] = point (x, y, z), normal (x, y, z) (non-zero); each ray
     * shows the nearest plane point with t in its box overlap (t >= 0), in the
     * field's colour at that point, opaque and unshaded; none: transparent. */
    double planes[REF_MAX_PLANES][6];
    int nplanes;
};

/* The lighting coefficients of p with the SPEC.md defaults applied (all zero:
 * ka 0.2, kd 0.8, ks 0.4, p 16): k = {ka, kd, ks, p}. */
void ref_lighting(const ref_params *p, double k[4]);

/* Ray of pixel (px, py), py = 0 the top row, through the pixel centre:
 * origin o and unit direction d. Returns 0, or -1 on a degenerate camera. */
int ref_camera_ray(const ref_camera *cam, int width, int height, int px, int py, double o[3], double d[3]);

/* The ray's overlap [*t0, *t1] with the box, clipped to t >= 0. Returns 1 on
 * a non-empty overlap, else 0. */
int ref_ray_box(const double o[3], const double d[3], const double lo[3], const double hi[3], double *t0,
                double *t1);

/* t_k = dt (k + rda k (k - 1) / 2). */
double ref_lattice_t(long k, double dt, double rda);

/* The lattice indices with t0 <= t_k <= t1: [*k0, *k1]. Returns the count
 * (0 when none; then *k0 > *k1). */
long ref_lattice_range(double t0, double t1, double dt, double rda, long *k0, long *k1);

/* Classification of one value: rgb and tau (see ref_tf). NaN phi gives NaN. */
void ref_tf_eval(const ref_tf *tf, double phi, double rgb[3], double *tau);

/* One pixel: out = premultiplied (C, A), background not applied. */
int ref_render_pixel(const ref_source *src, const ref_params *p, int px, int py, double out[4]);

/* iso and slice, per pixel (width * height, row 0 at the top): depth = t of
 * the point shown (the iso hit, the plane point), INFINITY where nothing is;
 * margin (may be NULL) = how near the pixel came to another outcome: iso, the
 * smallest |phi - iso| over the lattice samples it took (field units: a
 * float renderer may put a sample this close on the other side, and find
 * another first crossing; bisection points near the crossing only move the
 * hit within the bracket); slice, the smallest distance in t of a plane
 * point from either end of the ray's box overlap (or from the surface).
 * Other modes: INFINITY in both. Returns 0 or -1 on bad parameters. */
int ref_render_depth(const ref_source *src, const ref_params *p, double *depth, double *margin);

/* width * height * 4 values, premultiplied C and A, background not applied,
 * row 0 at the top. Returns 0, or -1 on bad parameters (rgba then
 * untouched). */
int ref_render(const ref_source *src, const ref_params *p, double *rgba);
int ref_render_f(const ref_source *src, const ref_params *p, float *rgba);

#endif
