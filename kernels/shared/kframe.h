/* Plain structs every ray-casting kernel reads: camera, transfer functions,
 * shading, the render mode, sampling parameters, tiles, counters. Built by
 * lci_frame_build (host/api/render.c) from the public descriptors, one
 * implementation for every data kind. Fixed-width
 * types only; sizes are asserted so every target re-checks the layout. */
#ifndef LC_KFRAME_H
#define LC_KFRAME_H

#include <stdint.h>

#define LC_KMAX_FIELDS 8 /* = LC_MAX_FIELDS of the API (asserted in host/internal.h) */
#define LC_TF_TABLE_SIZE 1024

/* Ray for pixel (px, py), SPEC.md "Camera and rays":
 *   u = 2 (px + 0.5) / W - 1,  v = 1 - 2 (py + 0.5) / H
 *   perspective:  org = eye,                 dir = normalize(forward + u*right + v*up)
 *   orthographic: org = eye + u*right + v*up, dir = forward
 * where right/up are pre-scaled by tan(fovy/2)*W/H and tan(fovy/2)
 * (perspective) or by height/2*W/H and height/2 (orthographic). */
typedef struct lc_kcamera {
    float eye[4];
    float forward[4];
    float right[4];
    float up[4];
    int32_t width, height;
    int32_t ortho;
    int32_t pad;
} lc_kcamera;
_Static_assert(sizeof(lc_kcamera) == 80, "lc_kcamera layout");

/* A transfer function sampled into LC_TF_TABLE_SIZE entries of (r, g, b, tau)
 * over the normalised value v = (phi - lo) / (hi - lo) in [0, 1]; lookups
 * interpolate linearly between entries (SPEC.md allows >= 1024 entries).
 * The step table is the same TF classified for one step of the frame's dt
 * (built per frame by lci_tf_step_table, host/api/tf.c): cls[4 e ..] =
 * (a r, a g, a b, a) at entry e with a = 1 - exp(-tau dt), premultiplied,
 * LC_TF_TABLE_SIZE + 1 entries (the last repeats the one before, so a lookup
 * reads two entries from any index); the dvr sample loop of every kind
 * interpolates it instead of taking an exp per sample (mode.h). */
typedef struct lc_ktf {
    const float *rgbt; /* LC_TF_TABLE_SIZE * 4 floats */
    const float *cls;  /* (LC_TF_TABLE_SIZE + 1) * 4 floats, or NULL: classify with rgbt and exp */
    float lo;
    float inv_range; /* 1 / (hi - lo) */
    float cls_vzero; /* tau = 0 at every v <= cls_vzero (-1: nowhere, 2: everywhere) */
    float grad_eps;  /* no shading where |grad| < 1e-6 (hi - lo) / dt (SPEC.md) */
} lc_ktf;
_Static_assert(sizeof(lc_ktf) == 32, "lc_ktf layout");

enum { LC_KSHADE_NONE = 0, LC_KSHADE_DIFFUSE = 1, LC_KSHADE_PHONG = 2 };

/* Render modes (lc_mode): what the per-sample consumer (kernels/mode.h) does. */
enum { LC_KMODE_DVR = 0, LC_KMODE_MIP = 1, LC_KMODE_ISO = 2, LC_KMODE_SLICE = 3 };

#define LC_KMAX_PLANES 4 /* = LC_MAX_PLANES of the API (asserted in host/internal.h) */

/* A slice plane: a point on it and its unit normal. */
typedef struct lc_kplane {
    float point[4];
    float normal[4];
} lc_kplane;
_Static_assert(sizeof(lc_kplane) == 32, "lc_kplane layout");

/* A region of a data-parallel render (SPEC.md "Regions"): a kd-tree cell
 * whose faces on the data's outside are at -inf / +inf, so the regions of a
 * tree cover all of space. A ray takes the lattice samples t_k in [t_in,
 * t_out) of its slab interval against the cell (kernels/dvr.h dvr_region);
 * both cells beside a split plane compute its t from the same float, so
 * every sample goes to exactly one region. */
typedef struct lc_kregion {
    float lo[4];
    float hi[4];
} lc_kregion;
_Static_assert(sizeof(lc_kregion) == 32, "lc_kregion layout");

/* Lattice indices are clamped below this so k * dt stays exact in float and
 * k fits an int32 (2^24 = 16777216 > LC_KLATTICE_MAX). */
#define LC_KLATTICE_MAX 1.6e7f

typedef struct lc_kframe {
    lc_kcamera cam;
    lc_ktf tf[LC_KMAX_FIELDS];
    int32_t nfields;
    int32_t shade;       /* LC_KSHADE_* */
    float ka, kd, ks;
    int32_t phong_exp;   /* integer Phong exponent p */
    float dt;
    float alpha_stop;    /* stop a ray once A >= alpha_stop; 1 = never */
    int32_t mode;        /* LC_KMODE_* */
    int32_t packet;      /* rays per packet group side (e.g. 8 for 8x8); 0 = lane width */
    int32_t zero_transparent; /* 1: every field's TF has tau = 0 at value 0, so samples where no
                                 particle (or nothing) contributes may be skipped exactly */
    int32_t field;       /* iso, slice: the field they show */
    float iso;           /* iso: the iso value */
    int32_t nplanes;     /* slice: planes[0 .. nplanes - 1] */
    int32_t has_region;  /* 1: integrate only the part of each ray inside `region` (dvr_region) */
    int32_t pad2;
    lc_kplane planes[LC_KMAX_PLANES];
    lc_kregion region;
} lc_kframe;
_Static_assert(sizeof(lc_kframe) == 80 + 32 * LC_KMAX_FIELDS + 64 + 32 * LC_KMAX_PLANES + 32, "lc_kframe layout");

/* A rectangle of pixels [x0, x1) x [y0, y1) and where its result goes: the
 * kernel writes premultiplied (C, A) into rgba[(y * stride + x) * 4 ...] and,
 * when depth is not NULL, in iso and slice modes the ray distance t of the
 * point a pixel shows (the iso hit, the plane point; +inf where none) into
 * depth[y * stride + x] (a test hook, lci_render). */
typedef struct lc_ktile {
    int32_t x0, y0, x1, y1;
    int32_t stride;
    /* non-zero (dvr only): each ray starts from the premultiplied (C, A)
       already in rgba instead of zero and goes on blending, so a
       data-parallel render that hands the image from region to region in
       visibility order makes the same operations, in the same order, as one
       process (host/mpi/pipeline.c); pixels no ray of the tile meets keep
       what they hold */
    int32_t carry;
    float *rgba;
    float *depth;
    /* a render job's cancel flag (non-zero: stop), or NULL: kernels read it
       between row strips and ray groups and return early, leaving the rest of
       the tile cleared, so a cancel does not wait for a whole expensive tile */
    const int32_t *stop;
} lc_ktile;
_Static_assert(sizeof(lc_ktile) == 48, "lc_ktile layout");

/* The tile's job was cancelled (relaxed atomic load: the host stores the flag atomically). */
static inline int lc_ktile_stopped(const lc_ktile *t) { return t->stop && __atomic_load_n(t->stop, __ATOMIC_RELAXED); }

/* Per-tile counters, summed by the host for --stats. */
typedef struct lc_kstats {
    uint64_t rays;
    uint64_t samples;       /* samples integrated */
    uint64_t kernel_evals;  /* Gaussian (or voxel) evaluations */
    uint64_t nodes;         /* BVH nodes visited */
    uint64_t leaves;        /* BVH leaves visited */
    uint64_t passes;        /* buffer passes (coherent particle path) */
} lc_kstats;

/* Per-thread scratch memory the host allocates once per worker, so kernels
 * never allocate. */
typedef struct lc_kscratch {
    void *mem;
    uint64_t bytes;
} lc_kscratch;

#endif
