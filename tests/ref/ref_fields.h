/* Brute-force field evaluators of SPEC.md "Fields" for the reference core
 * (ref_core.h), one per data kind, double precision, no lanecast code. Each
 * kind has a descriptor (caller-owned arrays, converted to double by the
 * caller), an evaluator with the ref_field_fn signature (user = the
 * descriptor) and a *_source function that fills a ref_source with the
 * evaluator, the field count and the lattice clip box. The descriptor must
 * outlive the source. */
#ifndef LC_TEST_REF_FIELDS_H
#define LC_TEST_REF_FIELDS_H

#include <stddef.h>
#include "ref_core.h"

/* Particles (Knoll 2014, eqs. 1-2): Phi_f(x) = sum over i with f_i = f and
 * |x - x_i| < sigma r_i of kappa k_i exp(-|x - x_i|^2 / (2 r_i^2)); with an SPH
 * kernel (SPEC.md "SPH kernels and projections"), the sum over |x - x_i| < H_i
 * = r_i of kappa k_i w(|x - x_i| / H_i) / H_i^3 (sigma unused). */
typedef enum ref_kernel {
    REF_KERNEL_GAUSSIAN = 0,
    REF_KERNEL_M4, /* cubic spline */
    REF_KERNEL_M5, /* quartic */
    REF_KERNEL_M6, /* quintic */
    REF_KERNEL_C2, /* Wendland C2, C4, C6 */
    REF_KERNEL_C4,
    REF_KERNEL_C6,
    REF_KERNEL_COUNT
} ref_kernel;

typedef struct ref_particle_set {
    size_t count;
    const double *pos;    /* 3 * count */
    const double *radius; /* count, > 0 */
    const double *value;  /* count, or NULL for k_i = 1 */
    const int *field;     /* count, or NULL for field 0 */
    int nfields;          /* 0: 1 */
    double sigma, kappa;  /* 0: 2 and 1 */
} ref_particle_set;

/* The same particles with another kernel (sigma unused for SPH kernels). */
typedef struct ref_sph_set {
    ref_particle_set ps;
    ref_kernel kernel;
    double norm_scale; /* 0: 1; tests scale SPEC.md's normalisation to show a wrong one is caught */
} ref_sph_set;

void ref_sph_eval(const void *user, const double p[3], double *phi, double (*grad)[3]);
/* Box: centre bounds grown by the support (sigma r for the Gaussian, r = H for
 * SPH kernels). Returns 0, or -1 on bad input. */
int ref_sph_source(const ref_sph_set *s, ref_source *src);

/* SPEC.md's w(u) of an SPH kernel, normalisation included (0 for u >= 1 and
 * for the Gaussian). */
double ref_sph_w(ref_kernel kernel, double u);

void ref_particles_eval(const void *user, const double p[3], double *phi, double (*grad)[3]);

/* Box: centre bounds grown by sigma * max r (empty for no particles).
 * Returns 0, or -1 on bad input (radius <= 0, field id out of range). */
int ref_particles_source(const ref_particle_set *ps, ref_source *src);

/* Error budget of Phi_f at x for a float implementation (per field f, arrays
 * of nfields): abs_sum = sum |phi_i| and gabs_sum = sum |grad phi_i| over the
 * terms inside their cut-off; pos_sens = sum |d phi_i / dx| (|x| + |x_i|) and
 * gpos_sens = sum |d grad phi_i / dx| (|x| + |x_i|), the sensitivity to an
 * absolute round-off of x - x_i proportional to the coordinates' magnitude
 * (|.| the 1-norm); *near_cut is set when a term lies within a relative 1e-5
 * of its truncation radius (float and double may disagree on inclusion). */
void ref_particles_budget(const ref_particle_set *ps, const double x[3], double *abs_sum, double *gabs_sum,
                          double *pos_sens, double *gpos_sens, int *near_cut);

/* lanecast's opaque particle spheres (Knoll 2014 sec. 5.2; not in SPEC.md,
 * which defines no surfaces; the rule is lanecast's, lc_particle_params
 * sphere_scale): a sphere of radius scale * r_i at every particle; the
 * nearest hit t > 0 (the far side when the eye is inside), coloured by its
 * particle's value kappa k_i through its field's transfer function and lit
 * by the headlight whatever the shading mode: rgb (ka + kd |n.d|), plus
 * ks |n.d|^p for phong (p's lighting, SPEC.md defaults). A ref_surface_fn:
 * set params.surface = ref_particles_spheres, surface_user = the set below. */
typedef struct ref_sphere_set {
    const ref_particle_set *ps;
    double scale; /* > 0 */
} ref_sphere_set;

int ref_particles_spheres(const void *user, const ref_params *p, const double o[3], const double d[3], double *t,
                          double rgb[3]);

/* Structured grid, one field: node (i, j, k) at origin + (i sx, j sy, k sz),
 * values x fastest; trilinear value and the analytic gradient of the same
 * trilinear form in world units. Points outside the domain are clamped to it. */
typedef struct ref_grid_field {
    int n[3]; /* each >= 2 */
    double origin[3], spacing[3]; /* spacing > 0 */
    const double *values;         /* n[0] * n[1] * n[2] */
} ref_grid_field;

void ref_grid_eval(const void *user, const double p[3], double *phi, double (*grad)[3]);

/* Box: the domain, first to last node. Returns 0, or -1 on bad input. */
int ref_grid_source(const ref_grid_field *g, ref_source *src);

/* RBF set (Jang 2004, eqs. 2-3): f(x) = w0 + sum over i with |x - mu_i| < R_i
 * of w_i exp(-|x - mu_i|^2 / (2 s_i^2)), R_i = s_i sqrt(2 ln(|w_i| / eps));
 * terms with |w_i| <= eps have no support. One field. */
typedef struct ref_rbf_set {
    size_t count;
    const double *centre; /* 3 * count */
    const double *width;  /* count, > 0 */
    const double *weight; /* count, any sign */
    double bias;          /* w0 */
    double eps;           /* > 0 */
} ref_rbf_set;

void ref_rbf_eval(const void *user, const double p[3], double *phi, double (*grad)[3]);

/* R_i of one term (0 when |w| <= eps). */
double ref_rbf_support(double width, double weight, double eps);

/* Box: union of the support spheres' boxes (empty when no term has support;
 * with a bias the field is defined everywhere, so a caller with a known domain
 * overwrites src->lo / src->hi). Returns 0, or -1 on bad input. */
int ref_rbf_source(const ref_rbf_set *s, ref_source *src);

#endif
