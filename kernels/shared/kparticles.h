/* The particle scene as kernels read it (Knoll 2014): a flat binary BVH whose
 * node boxes bound the particle centres, a per-node maximum radius so the box
 * grows by sigma * rmax at traversal time (sigma and kappa change without a
 * rebuild, paper §5.3), a per-node value bound for the mode's culling test, and structure-of-arrays particle data in leaf order.
 *
 * RBF sets (Jang 2004) render through the same kernels (lc_method coherent,
 * host/kinds/rbf.c): a term w_i exp(-|x - mu_i|^2 / (2 s_i^2)) cut at its
 * support R_i is a particle with sigma = 1, r = R_i (the support test
 * d^2 < (sigma r)^2 and the box growth sigma * rmax), neg_inv_2r2 = -1 / (2 s_i^2)
 * (the Gaussian's own width, which for particles is r again), kappa = 1,
 * k = w_i and field 0; the set's constant w0 is `bias`, the lattice clip box
 * lo/hi is the set's domain. Particles leave bias = 0 and bias_clear = 0. */
#ifndef LC_KPARTICLES_H
#define LC_KPARTICLES_H

#include <math.h>
#include <stdint.h>
#include "kframe.h"

/* The particles' radial kernels (lc_kparticles.kernel; the values of the
 * public lc_kernel, asserted in host/kinds/particles.c); evaluated in
 * kernels/particles_sph.h. */
enum {
    LC_KSPH_GAUSSIAN = 0,
    LC_KSPH_M4 = 1,
    LC_KSPH_M5 = 2,
    LC_KSPH_M6 = 3,
    LC_KSPH_C2 = 4,
    LC_KSPH_C4 = 5,
    LC_KSPH_C6 = 6
};

/* Inner node: count == 0, children at first and first + 1.
 * Leaf: count >= 1 particles starting at first. */
typedef struct lc_kpnode {
    float lo[3];
    int32_t first;
    float hi[3];
    int32_t count;
} lc_kpnode;
_Static_assert(sizeof(lc_kpnode) == 32, "lc_kpnode layout");

typedef struct lc_kparticles {
    const lc_kpnode *nodes; /* nodes[0] is the root; NULL when empty */
    const float *node_rmax; /* per node: largest radius below it */
    const float *node_ksum; /* per node: sum of |k_i| below it (SPH kernels: of their peaks |k_i| knorm / H_i^3),
                               so |kappa| * node_ksum bounds the node's own contribution to any field
                               (others add to it) */
    const uint8_t *node_clear; /* dvr, this frame: 1 where no particle below the node can change a
                                  sample (host/kinds/particles.c clear_nodes); NULL = none */
    const float *px, *py, *pz;
    const float *r;
    const float *neg_inv_2r2; /* -1 / (2 r^2) */
    const float *k;           /* value k_i */
    const uint8_t *field;     /* field id */
    int64_t count;
    int32_t nnodes;
    int32_t depth;         /* longest root-to-leaf path; traversal stacks hold depth + 2 entries */
    int32_t nfields;
    int32_t buffer_k;      /* coherent: samples per ray per pass and field */
    float sigma, kappa;
    float sphere_scale;    /* > 0: opaque spheres of radius sphere_scale * r_i */
    float max_radius;
    float lo[4], hi[4];    /* centre bounds grown by max(sigma, sphere_scale) * max radius */
    /* A constant added to every field at every sample inside lo/hi, also where
       no particle reaches (RBF sets: w0; particles: 0). Samples a traversal
       found no particle for hold exactly bias; they are skipped as blending to
       nothing when bias == 0 and the frame's zero_transparent says tau(0) = 0,
       or when bias != 0 and bias_clear is 1 (dvr: the host found tau(bias) = 0
       in this frame's TF). */
    float bias;
    int32_t bias_clear;
    /* coherent: entries of a group's particle list (particles_coherent.c
       "one walk per group"); 0: the kernel's default, < 0: no lists (a BVH
       walk per pass). The host sets it only for tests and A/B runs
       (LANECAST_PARTICLE_GROUP_LIST); scratch sizing reads it. */
    int32_t group_list_cap;
    int32_t buffer_adapt; /* coherent: 1 = buffer_k is the buffer's capacity and the pass length adapts
                             per group (particles_coherent.c pass_adapt); 0 = passes of buffer_k */
    int32_t eye_generic; /* coherent: 1 = perspective rays take the per-lane origin arithmetic too
                            (tests: LANECAST_PARTICLE_EYE=0; the same image, bit for bit) */
    /* coherent, this frame: per particle (leaf order) the recurrence ratio
       c_i = lc_kparticles_ratio(neg_inv_2r2[i], cstep_dt), the same float the
       kernel would compute (host/kinds/particles_cstep.c); used where cstep_dt is the frame's
       dt. NULL: the kernel computes it. */
    float cstep_dt;
    const float *cstep;
    int32_t group_side; /* coherent: rays per group side when > 0 (the render desc left packet at its
                           default; particles_coherent.c group_dims), else the frame's packet */
    int32_t cone_off; /* coherent: 1 = no per-vector cone pre-test in list deposits (tests and A/B
                         runs: LANECAST_PARTICLE_CONE=0; the same image, bit for bit) */
    /* The radial kernel (kernels/particles_sph.h LC_KSPH_*, lc_kernel's values): 0 the Gaussian
       above; an SPH kernel has compact support r_i = H_i, so the host sets sigma = 1 (every
       support test, chord and grown box then holds as for the Gaussian), knorm its 3-D
       normalisation (a term is kappa k_i knorm / H^3 f(d / H)), node_ksum the node sums of
       |k_i| knorm / H_i^3 (the peaks) and no recurrence ratios (cstep NULL). */
    int32_t kernel;
    float knorm;
    /* The normalised SPH interpolant (lc_particle_params.normalise): each field is
       sum k_i W / sum kn_i W (kn_i = m_i / rho_i, leaf order), 0 where the
       denominator is 0; the direct method's gather and the probes divide
       (particles_common.h), the host renders dvr/mip/iso with the direct method
       and marks no node clear. kn NULL and normalise 0 otherwise. */
    const float *kn;
    int32_t normalise;
    int32_t pad_;
} lc_kparticles;
_Static_assert(sizeof(lc_kparticles) == 12 * 8 + 8 + 4 * 8 + 32 + 32 + 8 + 16, "lc_kparticles layout");

/* A perspective eye inside the particles' grown box (s->lo, s->hi): the
 * coherent kernel's first pass length (particles_coherent.c pass_first) and
 * the host's tile side (host/kinds/particles_frame.c) both follow it. */
static inline int lc_kparticles_eye_inside(const lc_kparticles *s, const lc_kframe *f)
{
    int in = !f->cam.ortho;
    for (int a = 0; a < 3; a++) in &= f->cam.eye[a] >= s->lo[a] && f->cam.eye[a] <= s->hi[a];
    return in;
}

/* The recurrence ratio of a Gaussian with neg_inv_2r2 nir stepped by dt
 * along a ray (g *= q, q *= c): c = exp(2 nir dt^2), rounded once from
 * double. One definition for the kernels (particles_common.h) and the host's
 * per-volume table (host/kinds/particles_cstep.c), so both give the same float. */
static inline float lc_kparticles_ratio(float nir, float dt)
{
    return (float)exp(2.0 * (double)nir * (double)dt * (double)dt);
}

#endif
