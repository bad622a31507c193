/* lanecast: CPU volume ray casting of particle data, structured grids and
 * RBF-encoded volumes with SIMD kernels compiled per instruction set.
 *
 * Conventions (README.md "Library" shows a complete example):
 * - Opaque handles with create/destroy pairs; destroy accepts NULL.
 * - Descriptor structs in which zero means default: use designated
 *   initialisers and set only what you need.
 * - Every fallible call returns lc_status (LC_OK = 0, errors negative); the
 *   message of the last error is kept per device (lc_device_last_error) and
 *   per thread (lc_last_error), and goes to the device's log callback.
 * - The library never aborts or exits on bad input.
 * - Thread safety (docs/DEVELOPERS.md "Threads"): one device may be used
 *   from one thread at a time (render jobs run on threads of their own, see
 *   lc_render_begin); distinct devices are independent. Volumes and
 *   TFs are only read after creation (except by lc_particles_set_params and
 *   lc_grid_set_params), so one volume and one TF may be rendered, sampled
 *   and queried from several threads at once, each thread with its own
 *   device; lc_render keeps every per-frame state of its own. Creating,
 *   loading and destroying objects and writing images are safe on distinct
 *   devices. lc_last_error is per thread. Not allowed: set_params while the
 *   volume is rendered or sampled, destroying an object in use, one device
 *   on two threads at once.
 * - Determinism: a render's bytes depend on the target, the scene and the
 *   render descriptor, not on the thread count, the tile size or the run. */
#ifndef LANECAST_H
#define LANECAST_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define LC_VERSION_MAJOR 0
#define LC_VERSION_MINOR 1
#define LC_VERSION_PATCH 0
#define LC_VERSION_STRING "0.1.0"
#define LC_VERSION_NUMBER (LC_VERSION_MAJOR * 10000 + LC_VERSION_MINOR * 100 + LC_VERSION_PATCH)

#if defined(_WIN32)
#define LC_API
#else
#define LC_API __attribute__((visibility("default")))
#endif

/* ---------------------------------------------------------------- status */

typedef enum lc_status {
    LC_OK = 0,
    LC_ERROR_INVALID_ARGUMENT = -1, /* a NULL handle, an out-of-range value, a bad name */
    LC_ERROR_UNSUPPORTED = -2,      /* the CPU or this build lacks what was asked for */
    LC_ERROR_OUT_OF_MEMORY = -3,
    LC_ERROR_IO = -4,               /* a file could not be opened, read or written */
    LC_ERROR_FORMAT = -5,           /* a file's content is malformed */
    LC_ERROR_INTERNAL = -6,         /* a bug: please report it with the message */
    LC_CANCELLED = -7,              /* a render stopped by lc_job_cancel or lc_render_desc.cancel:
                                       its image is not complete */
    LC_TIMEOUT = -8                 /* lc_job_wait: the job still runs after the timeout (not an
                                       error: wait again, or cancel) */
} lc_status;

/* A static string naming the status ("invalid argument", ...). Never NULL. */
LC_API const char *lc_status_string(lc_status status);

/* The message of the last error raised on the calling thread by any lanecast
 * call, or "" if none. Valid until the next failing call on this thread. */
LC_API const char *lc_last_error(void);

/* ---------------------------------------------------------------- version */

/* The library's version, which may differ from LC_VERSION_* of the header
 * the caller compiled against. Any pointer may be NULL. */
LC_API void lc_version(int *major, int *minor, int *patch);
LC_API const char *lc_version_string(void);

/* ---------------------------------------------------------------- targets */

/* SIMD targets. Every kernel is compiled once per target; a device runs on
 * exactly one. AUTO picks the widest target this CPU (and OS) supports, in
 * the order avx512, avx512_8, avx2, sse4, scalar (not the enum order).
 * AVX512_8 runs AVX-512 instructions on 8 lanes, for comparing lane width
 * and instruction set separately. */
typedef enum lc_target {
    LC_TARGET_AUTO = 0,
    LC_TARGET_SCALAR = 1,   /* 1 lane, any x86-64 */
    LC_TARGET_SSE4 = 2,     /* 4 lanes, SSE4.2 */
    LC_TARGET_AVX2 = 3,     /* 8 lanes, AVX2 + FMA */
    LC_TARGET_AVX512 = 4,   /* 16 lanes, AVX-512 F/DQ/BW/VL */
    LC_TARGET_AVX512_8 = 5, /* 8 lanes, AVX-512 F/DQ/BW/VL on 256-bit vectors */
    LC_TARGET_COUNT = 6
} lc_target;

/* "auto", "scalar", "sse4", "avx2", "avx512", "avx512_8"; NULL for a value out of
 * range. */
LC_API const char *lc_target_name(lc_target target);
/* Parses a target name (case-sensitive, as above). Unknown names fail with
 * LC_ERROR_INVALID_ARGUMENT and a message listing the known ones. */
LC_API lc_status lc_target_from_name(const char *name, lc_target *out);
/* 1 if kernels for the target are compiled into this library, else 0. */
LC_API int lc_target_compiled(lc_target target);
/* 1 if this CPU and OS can run the target (instruction set and register state
 * enabled by the OS), else 0. AUTO is always supported. */
LC_API int lc_target_supported(lc_target target);
/* Lanes per vector of a target (1, 4, 8, 16); 0 for AUTO or an invalid value. */
LC_API int lc_target_lanes(lc_target target);

/* ---------------------------------------------------------------- device */

typedef struct lc_device lc_device;

typedef enum lc_log_level { LC_LOG_DEBUG = 0, LC_LOG_INFO = 1, LC_LOG_WARNING = 2, LC_LOG_ERROR = 3 } lc_log_level;
typedef void (*lc_log_fn)(void *user, lc_log_level level, const char *message);

typedef struct lc_device_desc {
    /* LC_TARGET_AUTO (0) reads the LANECAST_TARGET environment variable
     * ("scalar", "sse4", "avx2", "avx512", "avx512_8", "auto") and otherwise picks the
     * widest supported target. An explicit target overrides the variable. */
    lc_target target;
    /* Worker threads for rendering; 0 = LANECAST_THREADS or the number of
     * online CPUs. At most 1024. */
    int threads;
    /* Receives every error message and some information; NULL = silent. */
    lc_log_fn log;
    void *log_user;
} lc_device_desc;

/* Creates a device. desc may be NULL (all defaults). Fails with
 * LC_ERROR_UNSUPPORTED if the requested target is not compiled in or the CPU
 * cannot run it, LC_ERROR_INVALID_ARGUMENT for a bad thread count or an
 * unknown LANECAST_TARGET. *out is set to NULL on failure. */
LC_API lc_status lc_device_create(const lc_device_desc *desc, lc_device **out);
/* Destroys a device; NULL is ignored. Objects created on it must be destroyed
 * first. */
LC_API void lc_device_destroy(lc_device *device);
/* The target the device runs on (never AUTO). */
LC_API lc_status lc_device_target(const lc_device *device, lc_target *out);
LC_API lc_status lc_device_threads(const lc_device *device, int *out);
/* The message of the last error on this device, or "". Never NULL. */
LC_API const char *lc_device_last_error(const lc_device *device);

/* ---------------------------------------------------------------- math */

typedef struct lc_vec3 {
    float x, y, z;
} lc_vec3;

typedef struct lc_box3 {
    lc_vec3 lo, hi;
} lc_box3;

/* ---------------------------------------------------------------- camera */

typedef enum lc_projection { LC_PERSPECTIVE = 0, LC_ORTHOGRAPHIC = 1 } lc_projection;

/* SPEC.md "Camera and rays". A camera with eye == at (e.g. all zero) is
 * replaced by a default view framing the data's bounds: lc_camera_frame with
 * LC_CAMERA_AZIMUTH and LC_CAMERA_ELEVATION (an oblique three-quarter view,
 * +y up). */
typedef struct lc_camera {
    lc_projection projection;
    lc_vec3 eye, at;
    lc_vec3 up;   /* zero = +y */
    float fovy;   /* perspective: vertical field of view in degrees; 0 = 40 */
    float height; /* orthographic: image-plane height in world units; 0 = frames the data */
} lc_camera;

#define LC_CAMERA_AZIMUTH 35.0f   /* degrees around +y from +z towards +x */
#define LC_CAMERA_ELEVATION 25.0f /* degrees above the xz plane */

/* Points cam (eye, at, up = +y; projection, fovy and height kept) at the
 * centre of bounds from azimuth degrees around +y (0 = from +z, 90 = from
 * +x) and elevation degrees above the xz plane (in (-90, 90)), at the
 * distance where the bounding sphere fills the vertical field of view
 * (perspective; fovy 0 = 40). Orbits are a sequence of azimuths. */
LC_API lc_status lc_camera_frame(const lc_box3 *bounds, float azimuth, float elevation, lc_camera *cam);

/* ---------------------------------------------------------------- transfer function */

#define LC_MAX_FIELDS 8

/* One field's transfer function: piecewise linear colour and extinction over
 * the normalised value v in [0, 1], clamped at both ends (SPEC.md). */
typedef struct lc_tf_field {
    const float *color;   /* ncolor points of [v, r, g, b] */
    int ncolor;
    const float *opacity; /* nopacity points of [v, tau], tau = extinction per world unit */
    int nopacity;
    int has_range;        /* 1: range below is this field's [lo, hi] */
    float range[2];
} lc_tf_field;

typedef struct lc_tf lc_tf;

/* Creates a transfer function for nfields (1..LC_MAX_FIELDS) fields. Points
 * are copied. Fails if a list is empty, v is outside [0, 1] or decreasing, a
 * colour is not finite, tau is negative, or a range is empty. */
LC_API lc_status lc_tf_create(lc_device *device, const lc_tf_field *fields, int nfields, lc_tf **out);
/* Parses SPEC.md's JSON transfer function (a single TF or {"fields": [...]}),
 * or a ParaView colour-map preset (a JSON array of objects with "Name",
 * "RGBPoints" [x, r, g, b, ...] and optionally "Points" [x, alpha, midpoint,
 * sharpness, ...]; the first one with RGBPoints is read). A ParaView preset's
 * x range is rescaled to v in [0, 1] (as ParaView does on applying a preset:
 * the TF then spans the data's range or lc_render_desc.range); alpha becomes
 * tau = -ln(1 - alpha) per world unit (ParaView's unit distance 1, alpha at
 * most 0.999); without "Points" tau ramps from 0 to 1 and the field reports
 * lc_tf_default_opacity = 1. Midpoint and sharpness are ignored
 * and colours interpolate in RGB.
 * The message names the file and what is wrong. LC_ERROR_UNSUPPORTED when
 * this build lacks json-c (lc_feature_get: "json"). */
LC_API lc_status lc_tf_load(lc_device *device, const char *path, lc_tf **out);
LC_API lc_status lc_tf_parse(lc_device *device, const char *json, const char *name_for_messages, lc_tf **out);
/* A built-in colour map by name; nfields copies of it. Opacity ramps from 0
 * at v = 0.1 to max_tau at v = 1. Names: "heat", "cool", "gray", "demo"
 * (warm and cool by alternate field), and the published maps "viridis",
 * "inferno", "magma", "plasma" (matplotlib's, sampled at 65 points),
 * "cool-warm" (Moreland 2009) and "grayscale". lc_tf_preset_name lists them. */
LC_API lc_status lc_tf_preset(lc_device *device, const char *name, int nfields, float max_tau, lc_tf **out);
/* The name of preset index (0, 1, ...), or NULL past the last. */
LC_API const char *lc_tf_preset_name(int index);
LC_API void lc_tf_destroy(lc_tf *tf);
LC_API int lc_tf_field_count(const lc_tf *tf);
/* A field's points (pointers into the TF, valid until lc_tf_destroy) and
 * range: to build a TF from parts of others. */
LC_API lc_status lc_tf_get_field(const lc_tf *tf, int field, lc_tf_field *out);
/* 1 when the TF's source named no opacity for the field (a ParaView colour
 * preset without "Points"): its opacity is a stand-in ramp that a caller may
 * replace. 0 otherwise, and for a NULL TF or a field out of range. */
LC_API int lc_tf_default_opacity(const lc_tf *tf, int field);

/* ---------------------------------------------------------------- volumes */

/* Every kind of data renders as "a volume": one handle type that every kind's
 * create call and lc_volume_load return, one lc_volume_destroy, one render
 * descriptor field. Kind-specific calls (lc_particles_*, lc_grid_*) take the
 * same handle and fail with LC_ERROR_INVALID_ARGUMENT on another kind. */
typedef struct lc_volume lc_volume;

typedef enum lc_kind {
    LC_KIND_NONE = 0,
    LC_KIND_PARTICLES = 1, /* sums of truncated Gaussians (Knoll et al. 2014) */
    LC_KIND_GRID = 2,      /* structured volumes (Knoll et al. 2011) */
    LC_KIND_RBF = 3,       /* RBF-encoded volumes: sums of truncated Gaussians plus a bias (Jang et al. 2004) */
    LC_KIND_COUNT = 4
} lc_kind;

/* "particles", "grid", "rbf"; NULL for a value out of range. */
LC_API const char *lc_kind_name(lc_kind kind);

typedef struct lc_volume_info {
    lc_kind kind;
    lc_box3 bounds;   /* where the field may be non-zero with the current parameters */
    int nfields;      /* fields (1..LC_MAX_FIELDS) */
    float range[2];   /* the value range a TF maps by default (grids: the voxel range;
                         particles: from min(0, kappa k_i) to max(0, kappa k_i), [0, kappa]
                         for unit values (SPH kernels: the peaks kappa k_i norm / H_i^3); RBF sets: from the bias, their background,
                         to the largest value at the centres; lc_rbf_info.range is a bound) */
} lc_volume_info;

/* NULL is ignored. Objects are destroyed before their device. */
LC_API void lc_volume_destroy(lc_volume *volume);
/* LC_KIND_NONE for NULL. */
LC_API lc_kind lc_volume_kind(const lc_volume *volume);
LC_API lc_status lc_volume_get_info(const lc_volume *volume, lc_volume_info *out);

/* Evaluates every field (and optionally its gradient) at n points (xyz
 * interleaved) with the volume's current parameters, on the device's target:
 * values[i * nfields + f], gradients[3 * (i * nfields + f) + c]. gradients may
 * be NULL. Grids give 0 outside their domain; RBF sets give f(x) everywhere
 * (their domain only bounds where rays sample). */
LC_API lc_status lc_volume_sample(lc_device *device, const lc_volume *volume, size_t n, const float *points,
                                  float *values, float *gradients);

/* ---- particles (Knoll et al. 2014) */

/* The radial kernel of every particle. LC_KERNEL_GAUSSIAN (the default) is
 * Knoll et al. 2014's truncated Gaussian kappa k_i exp(-d^2 / (2 r_i^2)) for
 * d < sigma r_i (r_i a standard deviation, k_i the peak). The SPH kernels are
 * compact with support radius H_i = r_i (GADGET's and yt's HSML; no sigma):
 * W(d, H) = norm / H^3 f(d / H), normalised in 3-D, and a particle contributes
 * kappa k_i W(d, H_i) (k_i is then an amount, e.g. m_i / rho_i * A_i). Every
 * method and mode evaluates every kernel, with the analytic gradient for
 * shading; sigma applies to the Gaussian only, and the default step of an
 * SPH kernel is an eighth of the smallest H (the Gaussian's: a quarter of the
 * smallest r). Changing the kernel through lc_particles_set_params rebuilds
 * no BVH (node bounds scale with the support at render time; the per-node
 * value bounds are recomputed, O(particles)). */
typedef enum lc_kernel {
    LC_KERNEL_GAUSSIAN = 0,
    LC_KERNEL_M4 = 1,          /* cubic spline (Monaghan 1985): h = H / 2 */
    LC_KERNEL_M5 = 2,          /* quartic spline: h = H / 2.5 */
    LC_KERNEL_M6 = 3,          /* quintic spline: h = H / 3 */
    LC_KERNEL_WENDLAND_C2 = 4, /* Wendland (1995) C2, C4 and C6 in 3-D: h = H */
    LC_KERNEL_WENDLAND_C4 = 5,
    LC_KERNEL_WENDLAND_C6 = 6
} lc_kernel;

/* "gaussian", "m4", "m5", "m6", "wendland-c2", "wendland-c4", "wendland-c6";
 * NULL for a value out of range. */
LC_API const char *lc_kernel_name(lc_kernel kernel);
/* The kernel of that name (as lc_kernel_name spells it); LC_ERROR_INVALID_ARGUMENT otherwise. */
LC_API lc_status lc_kernel_from_name(const char *name, lc_kernel *out);

/* Per-render parameters of particles; they change without a rebuild. */
typedef struct lc_particle_params {
    float sigma;        /* truncation radius in units of r_i; 0 = 2 */
    float kappa;        /* global density scale; 0 = 1 */
    int buffer_samples; /* samples per ray per pass in the coherent buffer; 0 = adapted per ray
                           group (up to 128, 128/M for M > 1 fields); images do not depend on it */
    float sphere_scale; /* > 0: also ray-trace opaque spheres of radius scale * r_i */
    lc_kernel kernel;   /* the radial kernel (LC_KERNEL_GAUSSIAN = 0 by default) */
    int normalise;      /* 1: the normalised SPH interpolant, each field sum k_i W / sum w_i W with w_i the
                           desc's norm_weights (m_i / rho_i), 0 where no particle reaches; needs an SPH
                           kernel and norm_weights; dvr/mip/iso then render with the direct method */
} lc_particle_params;

/* Particle data: a sum of truncated Gaussians per field,
 * Phi_f(x) = sum kappa k_i exp(-|x - x_i|^2 / (2 r_i^2)) over |x - x_i| < sigma r_i. */
typedef struct lc_particles_desc {
    size_t count;
    const float *positions; /* 3 * count floats, x y z interleaved */
    const float *radii;     /* count radii, or NULL to use `radius` for all */
    float radius;           /* radius of every particle when radii is NULL */
    const float *values;    /* count values k_i, or NULL for 1 */
    const uint8_t *fields;  /* count field ids, or NULL for field 0 */
    int nfields;            /* 0 = 1 + the largest field id; at most LC_MAX_FIELDS */
    int leaf_size;          /* particles per BVH leaf, 1..32; 0 = 4 */
    int drop_invalid;       /* 1: drop particles with non-finite or non-positive data (counted) instead of failing */
    lc_particle_params params; /* initial parameters (lc_particles_set_params changes them) */
    const char *radius_note;   /* optional: how the radii were made (a loader's smoothing-length convention);
                                  copied into lc_particles_info.radius_note */
    const float *norm_weights; /* optional: count weights w_i > 0 (m_i / rho_i) of the normalised SPH
                                  interpolant's denominator (params.normalise) */
    /* 1 or 0 (the default): the BVH's leaves in a canonical order (a Morton code of the centre over
       order_box, ties by each particle's data), so every sample adds its terms in one order in any set
       holding them: a data-parallel part renders the whole set's regions bit for bit (lanecast_mpi.h;
       docs/mpi.md). -1: Embree's binned SAH build (frames alike, the build twice the CPU; images
       differ from the canonical tree's by float rounding). */
    int canonical_order;
    lc_box3 order_box; /* the Morton code's box; all zero = the kept centres' bounds */
    int defer_bvh;             /* 1: build the BVH when a render or lc_volume_sample first needs it, not
                                  here (lc_particles_project never does); 0 = now */
} lc_particles_desc;

typedef struct lc_particles_info {
    size_t count;       /* particles kept */
    size_t dropped;     /* particles dropped by drop_invalid */
    int nfields;
    lc_box3 bounds;     /* of the centres */
    float min_radius, max_radius;
    double build_seconds; /* BVH build including flattening (0, and the bvh_ fields 0, until a
                             defer_bvh set's first render or sample builds it) */
    size_t bvh_bytes;   /* nodes, per-node radii and value bounds */
    size_t data_bytes;  /* the particle arrays lanecast keeps */
    int bvh_nodes, bvh_depth, leaf_size;
    lc_particle_params params; /* current, defaults filled in */
    char radius_note[256]; /* the desc's radius_note (truncated), or "" */
} lc_particles_info;

/* Copies the particles (the caller's arrays may be freed afterwards) and
 * builds the BVH with Embree (desc.defer_bvh: on the first render or sample,
 * on whichever thread comes first, the others waiting; a set rendered after
 * it was projected then keeps both orders of its arrays until destroyed,
 * about 33 bytes per particle more). Invalid particles (non-finite position or value,
 * radius <= 0 or non-finite, field id >= nfields) fail with
 * LC_ERROR_INVALID_ARGUMENT and a message naming the first bad index and the
 * number of bad ones, unless drop_invalid is set. count = 0 is a valid empty
 * scene. */
LC_API lc_status lc_particles_create(lc_device *device, const lc_particles_desc *desc, lc_volume **out);
LC_API lc_status lc_particles_get_info(const lc_volume *particles, lc_particles_info *out);
/* Sets sigma, kappa, buffer size, sphere scale (zero = default) and the
 * kernel without a rebuild. Not while the volume is being rendered. */
LC_API lc_status lc_particles_set_params(lc_volume *particles, const lc_particle_params *params);

/* ---- grids (structured volumes, Knoll et al. 2011) */

typedef enum lc_value_type {
    LC_VALUE_DEFAULT = 0, /* in load options: the file's type; required in lc_grid_desc */
    LC_VALUE_UINT8 = 1,
    LC_VALUE_UINT16 = 2,
    LC_VALUE_INT16 = 3,
    LC_VALUE_FLOAT32 = 4
} lc_value_type;

typedef enum lc_grid_layout {
    LC_LAYOUT_DEFAULT = 0, /* linear, except owned float32 grids: bricked (docs/bench/grid.md "Layouts") */
    LC_LAYOUT_LINEAR = 1,  /* x fastest, then y, then z (a borrowed buffer is used in place) */
    LC_LAYOUT_BRICKED = 2  /* 4^3-voxel bricks behind per-axis offset tables (paper §6.1) */
} lc_grid_layout;

/* Per-render parameters of grids; they change without a rebuild. */
typedef struct lc_grid_params {
    int preintegrated;  /* 1: classify with the pre-integrated table */
    float rda;          /* differential sampling: step grows by rda*dt per sample; 0 = off */
    float delta_c;      /* empty-space culling threshold (Knoll 2011 eq. 5); 0 = 1e-3, < 0 = off */
    float delta_p;      /* pruning threshold (eq. 6); 0 = 1.5, < 0 = off */
    float delta_sv;     /* constant-subvolume threshold (eq. 7); 0 = 1e-4, < 0 = off */
} lc_grid_params;

/* A grid of size[0] x size[1] x size[2] nodes (each >= 2); node (i, j, k) at
 * origin + (i sx, j sy, k sz); values x fastest. */
typedef struct lc_grid_desc {
    int size[3];
    lc_value_type type;   /* required */
    const void *data;     /* size[0] * size[1] * size[2] values, native endianness */
    lc_vec3 spacing;      /* all zero = (1, 1, 1); each > 0 otherwise */
    lc_vec3 origin;
    int borrow;           /* 1: keep `data` (caller keeps it alive and unchanged until destroy);
                             0: copy it. An owned uint8 grid of up to 1024^3 voxels keeps a
                             packed copy for sampling instead (4 bytes a voxel up to 2^25
                             voxels, 2 above plus row and plane padding: at most 12 %, 3 % at
                             1024^3; counted in lc_grid_info.layout_bytes; 1.1-1.4x
                             faster frames; `layout` then does not apply) */
    lc_grid_layout layout;
    int brick;            /* BVH leaf side L in voxels: 1, 2, 4, 8 or 16; 0 = by size */
    lc_grid_params params; /* initial parameters (lc_grid_set_params changes them) */
} lc_grid_desc;

typedef struct lc_grid_info {
    int size[3];
    lc_value_type type;
    lc_vec3 spacing, origin;
    lc_box3 bounds;          /* first to last node */
    float value_min, value_max;
    lc_grid_layout layout;
    int borrowed;
    uint64_t data_bytes;     /* voxel bytes as the caller's linear array */
    uint64_t layout_bytes;   /* bytes the grid holds for voxels (or its sampling copy) and offset tables */
    uint64_t layout_overhead_bytes; /* layout_bytes - data_bytes when owned (brick and row padding, tables, copy) */
    int brick;               /* BVH leaf side L */
    uint64_t bvh_nodes, bvh_leaves, bvh_bytes;
    int bvh_depth;
    double bvh_build_seconds;
    lc_grid_params params;   /* current */
    int copy_voxel_bytes;    /* 2 or 4: an owned uint8 grid keeps a packed sampling copy of this many
                                bytes a voxel instead of its voxels (`layout` does not apply); 0: none */
} lc_grid_info;

/* Creates a grid from caller memory, builds its implicit min-max BVH.
 * Fails with LC_ERROR_INVALID_ARGUMENT for sizes < 2, sizes whose product
 * overflows (or exceeds 2^31 values), a size above 2^24 nodes on one axis,
 * an unknown type, a bad spacing or brick,
 * borrow with LC_LAYOUT_BRICKED, or non-finite float values. *out = NULL on
 * failure. Thread safety: as the device. */
LC_API lc_status lc_grid_create(lc_device *device, const lc_grid_desc *desc, lc_volume **out);
LC_API lc_status lc_grid_get_info(const lc_volume *grid, lc_grid_info *out);
/* Not while the volume is being rendered. */
LC_API lc_status lc_grid_set_params(lc_volume *grid, const lc_grid_params *params);
/* Counts the grid's nodes into nbins (1..2^24) equal bins over [value_min,
 * value_max] of lc_grid_info (the top value in the last bin). */
LC_API lc_status lc_grid_histogram(const lc_volume *grid, int nbins, uint64_t *counts);

/* ---- RBF sets (RBF-encoded volumes, Jang et al. 2004) */

/* An RBF set: f(x) = w0 + sum over i with |x - mu_i| < R_i of
 * w_i exp(-|x - mu_i|^2 / (2 s_i^2)), with the support (eq. 3)
 * R_i = s_i sqrt(2 ln(|w_i| / eps)): each term is cut where its magnitude
 * falls to eps. Terms with |w_i| <= eps have no support and are dropped
 * (counted in lc_rbf_info.dropped). The gradient is analytic.
 * RBF sets have no per-render parameters (no lc_rbf_params or
 * lc_rbf_set_params): eps and the domain change the supports, hence the BVH,
 * so they are build parameters; create a new set to change them. */

/* Which structure finds the RBFs whose support holds a sample, i.e. what
 * LC_METHOD_DEFAULT renders (the BVH is always built: LC_METHOD_COHERENT,
 * LC_METHOD_BVH and LC_METHOD_BRUTE stay available on any set; the octree
 * only where it was built). */
typedef enum lc_rbf_accel {
    LC_RBF_ACCEL_DEFAULT = 0, /* the fastest on the measured sets (docs/bench/rbf.md): coherent */
    LC_RBF_ACCEL_BVH = 1,     /* per-sample gather through the BVH of the supports */
    LC_RBF_ACCEL_OCTREE = 2,  /* the adaptive octree of Jang 2004 §5: per-cell lists of the RBFs whose
                                 support reaches the cell, evaluated along each ray cell by cell */
    LC_RBF_ACCEL_COHERENT = 3 /* the BVH of the supports walked by coherent ray groups that deposit each
                                 term into per-group sample buffers without exp per sample (the
                                 particle kind's kernel, Knoll 2014; LC_METHOD_COHERENT) */
} lc_rbf_accel;

/* Largest lc_rbf_desc.cell_max. */
#define LC_RBF_MAX_CELL 4096

typedef struct lc_rbf_desc {
    size_t count;
    const float *centres; /* 3 * count floats, x y z interleaved (mu_i) */
    const float *widths;  /* count widths s_i > 0 */
    const float *weights; /* count weights w_i, any sign */
    float bias;           /* w0 */
    /* truncation tolerance > 0; 0 = 1e-4 * max |w_i|: each dropped tail is below
       1e-4 of the strongest term, under a fortieth of an 8-bit step of a TF
       spanning max |w|, while R_i stays 4.3 s_i at the strongest term */
    float eps;
    /* where rays sample (the lattice clip box); all zero = the union of the
       supports. With a bias the field is w0 outside every support, so a domain
       bounds the constant region that rays integrate. lo < hi on every axis. */
    lc_box3 domain;
    int leaf_size;        /* RBFs per BVH leaf, 1..32; 0 = 4 */
    lc_rbf_accel accel;   /* what LC_METHOD_DEFAULT renders through; 0 = LC_RBF_ACCEL_DEFAULT */
    /* octree: a cell splits while its list holds more than cell_max RBFs (and
       splitting still shortens the lists), 1..LC_RBF_MAX_CELL; 0 = 32 */
    int cell_max;
    /* octree only, 0 or 1: each cell keeps only its cell_max most significant
       RBFs (largest |w_i| exp(-d^2 / 2 s_i^2) over the cell) and adds the
       trilinear interpolation of the dropped terms' sum stored at its
       corners (Jang 2004 §5); lc_rbf_info.truncation_bound bounds the error.
       0 = every RBF whose support reaches the cell (the exact field). */
    int significant;
    /* 1 or 0 (the default): the BVH's leaves in a canonical order (a Morton code of the centre over
       the domain, ties by each term's data), as lc_particles_desc.canonical_order: a data-parallel
       part's sums are the whole set's bit for bit. -1: Embree's build. */
    int canonical_order;
} lc_rbf_desc;

typedef struct lc_rbf_info {
    size_t count;         /* RBFs kept */
    size_t dropped;       /* RBFs with |w_i| <= eps (no support) */
    float bias, eps;      /* eps: the one in use (default filled in) */
    lc_box3 bounds;       /* where rays sample: the domain, or the union of the supports */
    lc_box3 support_bounds; /* union of the supports (empty box at 0 when none) */
    float min_width, max_width, max_support; /* over kept RBFs (0 when none) */
    /* the default value range: w0 plus, over every BVH leaf, the sums of the
       positive (negative) weights of all RBFs whose supports reach the leaf's
       grown box; conservative: f(x) lies inside it everywhere */
    float range[2];
    double build_seconds; /* BVH build, flattening and range bound */
    size_t bvh_bytes, data_bytes;
    int bvh_nodes, bvh_depth, leaf_size;
    lc_rbf_accel accel;   /* the one in use (default resolved) */
    int cell_max, significant; /* as built (0 without an octree) */
    /* the octree (all 0 without one): cells (inner and leaves), leaves,
       depth, list entries, the longest leaf list, bytes (cells, lists and
       corner errors), build time (also counted in build_seconds) */
    int octree_cells, octree_leaves, octree_depth;
    size_t octree_refs, octree_max_list, octree_bytes;
    double octree_seconds;
    /* significant mode: list entries dropped, and the largest per-cell bound
       of |f - f_exact| (the sum over a cell's dropped terms of their largest
       magnitude in the cell; 0 when exact) */
    size_t truncated;
    double truncation_bound;
} lc_rbf_info;

/* Copies the RBFs (the caller's arrays may be freed afterwards) and builds
 * the BVH over their supports with Embree. Fails with
 * LC_ERROR_INVALID_ARGUMENT, naming the first bad index and the number of bad
 * ones, for a non-finite centre, width or weight or a width <= 0; and for a
 * non-finite bias, eps < 0 or non-finite, a domain with lo >= hi on an axis
 * (other than all zero), a bad leaf size, accel, cell_max or significant
 * (significant without accel = octree). count = 0 is valid (the field is
 * the bias inside the domain). LC_ERROR_OUT_OF_MEMORY when the octree's
 * lists would exceed 2^30 entries. */
LC_API lc_status lc_rbf_create(lc_device *device, const lc_rbf_desc *desc, lc_volume **out);
LC_API lc_status lc_rbf_get_info(const lc_volume *rbf, lc_rbf_info *out);

/* ---------------------------------------------------------------- default transfer functions */

/* A transfer function that shows a volume's structure on the first try
 * (docs/FIRST-IMAGE.md). colormap: an lc_tf_preset name, NULL = "viridis"
 * for grids, "heat" otherwise; max_tau: the peak extinction, 0 = a default.
 * Grids, from a 1024-bin histogram of the voxels over [value_min,
 * value_max]: the dominant bin and its hill (down to the first valley of the
 * histogram smoothed over 9 bins, on each side) are the background; the
 * informative values are those on the side of the hill holding more voxels;
 * the TF's range runs from the hill's edge to the 99th percentile of the
 * informative values (counted away from the hill), opacity rising from 0 at
 * the edge through 0.15 max_tau at the middle to max_tau at the far end
 * (reversed when the informative side lies below the background), and the
 * colour map spans the same range. Default max_tau = 16 / the volume's
 * diagonal. Particles and RBF sets: lc_tf_preset(colormap, nfields,
 * max_tau), default max_tau = 1 / the largest radius or width.
 * LC_ERROR_UNSUPPORTED for another kind. */
#define LC_TF_AUTO_COLORMAP "viridis"
#define LC_TF_AUTO_TAU 16.0f
LC_API lc_status lc_tf_auto(lc_device *device, const lc_volume *volume, const char *colormap, float max_tau, lc_tf **out);

/* ---------------------------------------------------------------- files */

/* One option of a file format or of the kind it makes, as text: "radius" =
 * "1.5", "size" = "64,64,32". lc_format_get lists each format's keys; an
 * unknown key or a bad value fails, naming the key. */
typedef struct lc_option {
    const char *key;
    const char *value;
} lc_option;

typedef struct lc_load_desc {
    const char *format;    /* NULL or "" = detect (magic bytes, then extension); else a format name */
    const char *companion; /* a second file: topology for coordinates, data for a header;
                              NULL = none, or as the file names it */
    int64_t frame;         /* trajectory frame, 0 = the first */
    const lc_option *options;
    int noptions;
    /* Reading progress: called from the loading thread with the fraction of
     * the file read so far (0..1, non-decreasing, at most about 100 calls;
     * text files by bytes read, binary ones by the offset reached, volumes by
     * the voxel bytes read) and once with 1 when reading is done (building
     * the volume, e.g. its BVH, follows and reports nothing). NULL = none. */
    void (*progress)(void *user, float fraction);
    void *progress_user;
} lc_load_desc;

typedef struct lc_format_info {
    const char *name;        /* "pdb", "nrrd", "raw-particles", ... */
    lc_kind kind;            /* what the format makes */
    const char *extensions;  /* space-separated, with the dot: ".pdb .ent" */
    const char *options;     /* space-separated option keys it takes (besides the kind's) */
    const char *description;
    int available;           /* 0: compiled out of this build */
    const char *package;     /* the Debian package whose -dev files enable it when unavailable, or "" */
} lc_format_info;

/* Checks an atom selection, the `select` option of the molecular formats
 * (pdb, gro, xyz, dcd; lammps and gadget answer type (atom / particle type)
 * and index: `lanecast formats` lists who takes it), without a
 * file: LC_ERROR_INVALID_ARGUMENT with a message naming the 1-based position
 * of what is wrong. The language (after VMD and MDAnalysis): all, none,
 * protein, backbone, water, ion, solvent, element W..., name W..., resname
 * W..., chain W..., segid W..., type W..., index N|N:M..., resid N|N:M...
 * combined with and, or, not and parentheses; a word may end in '*'
 * (prefix); index counts a frame's atoms from 0 in file order, ranges are
 * inclusive. A keyword the file cannot answer (resname in an XYZ file)
 * fails the load, and so does a selection that matches no atom. */
LC_API lc_status lc_select_check(const char *expr);

/* Formats are numbered 0 .. lc_format_count() - 1. */
LC_API int lc_format_count(void);
LC_API lc_status lc_format_get(int index, lc_format_info *out);

/* Optional features of this build ("zlib": gzip-compressed inputs; "json":
 * JSON transfer functions; "lapacke": RBF encoding, lc_rbf_encode; "nifti": NIfTI volumes; "hdf5":
 * HDF5 files). What needs a missing one fails with
 * LC_ERROR_UNSUPPORTED and a message naming the library and its package. */
typedef struct lc_feature_info {
    const char *name;        /* "zlib", "json", "lapacke" */
    const char *library;     /* "zlib", "json-c", "LAPACKE" */
    int available;           /* 1: compiled in */
    const char *package;     /* the Debian package whose -dev files enable it */
    const char *description; /* what needs it */
} lc_feature_info;

/* Features are numbered 0 .. lc_feature_count() - 1. */
LC_API int lc_feature_count(void);
LC_API lc_status lc_feature_get(int index, lc_feature_info *out);

typedef struct lc_file_info {
    const char *format;  /* a format name (static string) */
    lc_kind kind;
    int64_t frames;      /* 1 unless the format holds trajectories (.gro), whose frames are
                            counted (reading the file's line structure); 0 = could not count
                            (unreadable or malformed: lc_volume_load says why) */
    int gzip;            /* 1: the file is gzip-compressed */
} lc_file_info;

/* Decides a file's format and kind without reading its data (beyond counting
 * a trajectory's frames): desc->format if given, else the magic bytes, else
 * the extension (".gz" looked through).
 * device may be NULL. */
LC_API lc_status lc_file_probe(lc_device *device, const char *path, const lc_load_desc *desc, lc_file_info *out);
/* What a file holds beyond lc_file_info, as lines of text for people
 * (DICOM: every series of a folder with its files, size, spacing, modality,
 * rescale and transfer syntax); "" when its format has nothing to add.
 * Writes at most size bytes (NUL included) into text. device may be NULL. */
LC_API lc_status lc_file_describe(lc_device *device, const char *path, const lc_load_desc *desc, char *text,
                                  size_t size);
/* Reads a file through its format's reader and creates the volume of its
 * kind. desc may be NULL (detect, frame 0, no options). Errors
 * (LC_ERROR_IO, LC_ERROR_FORMAT, LC_ERROR_INVALID_ARGUMENT, and
 * LC_ERROR_UNSUPPORTED for a format compiled out or gzip-compressed data
 * without zlib, naming the Debian package)
 * name the file and the line or byte offset. */
LC_API lc_status lc_volume_load(lc_device *device, const char *path, const lc_load_desc *desc, lc_volume **out);

/* ---------------------------------------------------------------- encoding (RBF sets from samples, Jang et al. 2004 sec. 4) */

/* Samples to fit: scattered points with values, or the nodes of a
 * structured volume (any value type; node positions from its spacing and
 * origin). An encoder input, not a render kind: lc_samples is not a volume. */
typedef struct lc_samples lc_samples;

typedef struct lc_samples_desc {
    size_t count;          /* scattered: samples */
    const float *points;   /* 3 * count floats, x y z interleaved */
    const float *values;   /* count values */
    const lc_grid_desc *grid; /* or (points NULL) a structured volume; only size, type, data,
                                 spacing and origin are read */
} lc_samples_desc;

typedef struct lc_samples_info {
    size_t count;
    lc_box3 bounds;        /* of the points */
    float value_min, value_max;
    int grid;              /* 1: from a structured volume */
    int size[3];           /* its node counts (grid only) */
    uint64_t input_bytes;  /* the data as given: voxel bytes of a grid, else 16 per sample
                              (x y z value as float32); the numerator of a compression ratio */
    const char *format;    /* the file format read ("csv", "vtk", "nrrd", ...), "" if none */
} lc_samples_info;

/* Copies the samples. Fails with LC_ERROR_INVALID_ARGUMENT for a
 * non-finite point or value (naming the first bad index, or node (i, j, k)
 * of a grid, and the number of bad ones), count 0, more than 2^31 - 1
 * samples, or a bad grid descriptor. */
LC_API lc_status lc_samples_create(lc_device *device, const lc_samples_desc *desc, lc_samples **out);
/* Reads samples from a file: CSV with a header naming the columns x, y, z
 * and value (any order, other columns ignored; '#' comments), a VTK legacy
 * file (POLYDATA or UNSTRUCTURED_GRID, ASCII or BINARY: its points and its
 * first scalar point data array), or any structured volume lanecast reads
 * (lanecast formats; desc as for lc_volume_load, NULL = detect). Errors name
 * the file and the line or byte offset. */
LC_API lc_status lc_samples_load(lc_device *device, const char *path, const lc_load_desc *desc, lc_samples **out);
LC_API lc_status lc_samples_get_info(const lc_samples *samples, lc_samples_info *out);
/* NULL is ignored. */
LC_API void lc_samples_destroy(lc_samples *samples);

typedef enum lc_rbf_centre {
    LC_RBF_CENTRE_MEAN = 0,   /* the cluster's mean weighted by the value still to fit (|residual|) */
    LC_RBF_CENTRE_MAXERR = 1  /* the cluster's sample of largest |residual| */
} lc_rbf_centre;

/* Where the encoder is, after each iteration (one RBF added). */
typedef struct lc_rbf_encode_progress {
    int iteration;
    size_t rbfs;
    double rms;       /* RMS error over the fitted samples, relative to their value range */
    double seconds;   /* since the start */
    double target;    /* the max_error asked for */
    size_t max_rbfs;
    int polish;       /* 0 while adding RBFs; k >= 1 after the k-th of the polish sweeps that
                         follow when max_rbfs is reached short of the target (lc_rbf_encode) */
} lc_rbf_encode_progress;

typedef struct lc_rbf_encode_desc {
    float max_error;      /* stop at an RMS error <= max_error * (value range); 0 = 0.02 */
    size_t max_rbfs;      /* stop at this many RBFs; 0 = min(4096, fitted samples - 1);
                             more than fitted samples - 1 is an error */
    lc_rbf_centre centre;
    int fit_range_set;    /* 1: fit only samples with values in fit_range (inclusive) */
    float fit_range[2];
    /* Bounded cost per iteration (docs/bench/rbf.md): the fit runs on at
       most fit_samples samples (a fixed-seed uniform subsample; 0 = 2^21,
       the report is over all), Levenberg-Marquardt sees at most lm_samples
       of the new RBF's neighbourhood (0 = 2048) and the local least squares
       at most 4 * lm_samples; local_rbfs RBFs (0 = 4, the new one and its
       nearest overlapping neighbours) are refitted per iteration. */
    size_t fit_samples, lm_samples;
    int local_rbfs;
    uint32_t seed;        /* subsampling seed; 0 = 1 */
    /* Called on the calling thread after each iteration; NULL = none. */
    void (*progress)(void *user, const lc_rbf_encode_progress *p);
    void *progress_user;
} lc_rbf_encode_desc;

typedef struct lc_rbf_encode_report {
    size_t rbfs;
    size_t samples, fitted;    /* all samples, and those in the fit range */
    float range[2];            /* value range of the fitted samples */
    /* errors of the result over every fitted sample, with the truncation a
       loaded set uses by default (lc_rbf_desc.eps = 0), relative to range */
    double rms, max_error;
    int iterations;
    int reached;               /* 1: rms <= max_error was reached */
    double seconds;
} lc_rbf_encode_report;

/* An encoded set: an lc_rbf_desc (eps, domain and leaf_size zero) whose
 * arrays the library owns; free with lc_rbf_encoded_free. */
typedef struct lc_rbf_encoded {
    lc_rbf_desc desc;
} lc_rbf_encoded;

/* Fits an RBF set to the samples (Jang 2004 sec. 4): clusters split by PCA
 * along the principal axis of the cluster of largest error, each new RBF
 * centred in it (desc->centre), widths by Levenberg-Marquardt on the mean
 * squared error, weights and the bias by linear least squares (LAPACKE),
 * until the RMS error relative to the value range is at most max_error or
 * there are max_rbfs RBFs. Each time the count has grown by a quarter (and
 * after max_rbfs short of the target), polish sweeps refit every RBF's
 * weight, width and centre in turn by LM against the residual. desc may be NULL (defaults). Fails with
 * LC_ERROR_UNSUPPORTED when this build lacks LAPACKE (lc_feature_get
 * "lapacke"), LC_ERROR_INVALID_ARGUMENT for an empty fit range or fewer
 * fitted samples than max_rbfs + 1. *out is NULL on failure; report may be
 * NULL. Uses the device's threads. */
LC_API lc_status lc_rbf_encode(lc_device *device, const lc_samples *samples, const lc_rbf_encode_desc *desc,
                               lc_rbf_encoded **out, lc_rbf_encode_report *report);
/* NULL is ignored. */
LC_API void lc_rbf_encoded_free(lc_rbf_encoded *set);

typedef enum lc_rbf_file { LC_RBF_FILE_BINARY = 0, LC_RBF_FILE_TEXT = 1 } lc_rbf_file;

/* Writes an RBF set as a .rbf file (docs/FORMATS-rbf.md; count, centres,
 * widths, weights and bias; eps, domain and leaf_size are not stored). The
 * file appears complete or not at all: it is written under a temporary name
 * in the same folder and renamed. Fails with LC_ERROR_INVALID_ARGUMENT for
 * data lc_rbf_create would refuse, LC_ERROR_IO naming the file otherwise. */
LC_API lc_status lc_rbf_write(lc_device *device, const char *path, const lc_rbf_desc *desc, lc_rbf_file variant);

/* ---------------------------------------------------------------- rendering */

typedef enum lc_shading { LC_SHADE_NONE = 0, LC_SHADE_DIFFUSE = 1, LC_SHADE_PHONG = 2 } lc_shading;

/* What a ray computes from the field samples (SPEC.md). */
typedef enum lc_mode {
    LC_MODE_DVR = 0,   /* emission-absorption volume rendering */
    LC_MODE_MIP = 1,   /* maximum intensity projection: the largest normalised value along the
                          ray through its field's colour map, opaque where the ray met the data
                          (with several fields, the field whose normalised value is largest) */
    LC_MODE_ISO = 2,   /* iso-surface of lc_render_desc.iso in field `field`: the first change of
                          side (phi >= iso or not) between consecutive lattice samples, refined
                          by bisection to 1e-4 dt; opaque, in the TF's colour at the iso value,
                          shaded as `shading` says with the normal -grad/|grad| at the hit
                          (LC_SHADE_NONE: flat); rays that cross nothing stay transparent */
    LC_MODE_SLICE = 3, /* the field `field` on up to LC_MAX_PLANES planes through the TF's
                          colours: one sample per ray where it meets the nearest plane in front
                          of the eye inside the data's box; opaque there, unshaded; elsewhere
                          transparent */
    LC_MODE_COUNT = 4
} lc_mode;

/* A plane of LC_MODE_SLICE: a point on it and its normal (any length > 0;
 * the side it faces does not matter). */
typedef struct lc_plane {
    lc_vec3 point;
    lc_vec3 normal;
} lc_plane;

#define LC_MAX_PLANES 4

/* How a kind walks its data; each kind takes its own (DEFAULT = the fast one). */
typedef enum lc_method {
    LC_METHOD_DEFAULT = 0,  /* coherent for particles, bvh for grids, the set's accel for RBF sets
                               (lc_rbf_desc.accel: coherent, the BVH gather or the octree) */
    LC_METHOD_COHERENT = 1, /* particles: coherent packet traversal with sample buffers (Knoll 2014);
                               RBF sets: the same kernel over the BVH of the supports */
    LC_METHOD_DIRECT = 2,   /* particles: per-sample gather through the BVH (the paper's baseline) */
    LC_METHOD_BVH = 3,      /* grids: implicit min-max BVH traversal (Knoll 2011); RBF sets:
                               per-sample gather of the RBFs through the BVH of their supports */
    LC_METHOD_BRUTE = 4     /* grids: every sample, no BVH; RBF sets: every RBF at every sample */
} lc_method;

/* Phong parameters; all zero means SPEC.md's defaults ka 0.2, kd 0.8, ks 0.4, p 16. */
typedef struct lc_lighting {
    float ka, kd, ks;
    int phong_exp; /* integer exponent, 1..256 */
} lc_lighting;

/* Largest image side lc_render and lc_image_write take. */
#define LC_MAX_IMAGE_SIDE 32768

typedef struct lc_render_desc {
    int width, height;         /* pixels, 1..LC_MAX_IMAGE_SIDE each */
    lc_camera camera;
    const lc_tf *tf;           /* NULL = a default ("heat") TF */
    float range[2];            /* value range [lo, hi]; both 0 = the TF's range or the data's */
    const lc_volume *volume;   /* required: what to render (any kind) */
    lc_mode mode;              /* LC_MODE_DVR (0), MIP, ISO or SLICE; shading applies to dvr and iso */
    float iso;                 /* LC_MODE_ISO: the iso value (the field's own units), finite */
    int field;                 /* LC_MODE_ISO and LC_MODE_SLICE: the field they show (0 = the first;
                                  0 .. nfields - 1); the other modes show every field */
    lc_plane planes[LC_MAX_PLANES]; /* LC_MODE_SLICE: planes[0 .. nplanes - 1] */
    int nplanes;               /* LC_MODE_SLICE: 1 .. LC_MAX_PLANES */
    float dt;                  /* sampling step in world units; 0 = a default from the data */
    float alpha_stop;          /* early termination; 0 = 0.97, 1 = never */
    lc_shading shading;
    lc_lighting lighting;
    lc_method method;
    int packet;                /* packet side in rays (8 = 8x8 groups); 0 = 8, 1 = lane-width packets */
    int tile;                  /* tile side in pixels for threads; 0 = the kind's choice (32; particles:
                                  64 with 32x32 groups and the eye inside the data) */
    /* Called on the calling thread (a job's own thread under lc_render_begin)
     * as tiles complete, with the fraction done in [0, 1]; NULL = none. */
    void (*progress)(void *user, float fraction);
    void *progress_user;
    /* Navigation quality, for frames rendered while a camera moves:
     * pixel_scale s in 2..16 renders every s-th pixel in x and y (pixels
     * (s i, s j), with the rays of the full image) and fills each s x s block
     * with it; 0 or 1 = every pixel. step_scale >= 1 multiplies dt (0 = 1). */
    int pixel_scale;
    float step_scale;
    /* Asked before every tile, from the render's worker threads: non-zero
     * stops the render, which returns LC_CANCELLED with no complete image
     * (lc_render's rgba then holds some tiles). Must be thread-safe and cheap,
     * e.g. a load of an atomic flag set by a signal handler. NULL = never. */
    int (*cancel)(void *user);
    void *cancel_user;
} lc_render_desc;

typedef struct lc_render_stats {
    double seconds;       /* wall time of the render */
    uint64_t rays;
    uint64_t samples;      /* samples integrated (empty samples skipped exactly when tau(0) = 0 are not counted) */
    uint64_t kernel_evals; /* Gaussian evaluations (particles, RBF sets) or voxel reconstructions (grids) */
    uint64_t nodes;        /* BVH nodes visited */
    uint64_t leaves;
    uint64_t passes;       /* coherent buffer passes */
    lc_target target;
    int threads;
} lc_render_stats;

/* Renders into rgba: width * height * 4 floats, row 0 at the top, holding
 * premultiplied colour C and opacity A (the background is not applied; see
 * lc_image_write). stats may be NULL. The volume and TF are only read.
 * LC_ERROR_INVALID_ARGUMENT names the bad member: besides sizes, camera, dt,
 * alpha_stop, shading, lighting, packet, range and the TF's field count, a
 * mode out of range, iso a non-finite iso, iso or slice a field outside
 * 0 .. nfields - 1, slice nplanes outside 1 .. LC_MAX_PLANES or a plane with a
 * non-finite point or a zero or non-finite normal, pixel_scale outside
 * 0 .. 16, step_scale below 1 or not finite. LC_CANCELLED when desc->cancel
 * stopped it. */
LC_API lc_status lc_render(lc_device *device, const lc_render_desc *desc, float *rgba, lc_render_stats *stats);

/* ---------------------------------------------------------------- render jobs (progressive, cancellable) */

/* A render that runs on a thread of its own while the caller goes on: a
 * preview pass at reduced resolution, then the full image, which is bit for
 * bit what lc_render gives for the same descriptor (on every target and
 * thread count). Passes report through a callback; the job can be waited
 * for with a timeout, polled and cancelled (within a tile: milliseconds).
 *
 * Threads: lc_render_begin validates the descriptor and prepares the frame
 * on the calling thread (errors are reported there, as by lc_render), then
 * returns. Jobs on one device run one after another in the order begun; a
 * new job waits for the one before it, so a caller whose camera moved
 * cancels the old job first. lc_job_cancel and lc_job_get_progress may be
 * called from any thread (the callbacks included); lc_job_wait and
 * lc_job_destroy from one thread at a time. While a job exists, its volume,
 * TF and rgba buffer must stay alive and unchanged (no set_params); between
 * jobs they may change as between lc_render calls. Destroy every job before
 * its device. */
typedef struct lc_job lc_job;

typedef enum lc_job_state {
    LC_JOB_QUEUED = 0,    /* waiting for the device's earlier jobs */
    LC_JOB_RUNNING = 1,
    LC_JOB_DONE = 2,      /* rgba holds the finished image */
    LC_JOB_CANCELLED = 3  /* stopped before the end: rgba holds no complete image */
} lc_job_state;

typedef struct lc_job_progress {
    lc_job_state state;
    int pass;         /* passes finished, 0 .. npasses */
    int npasses;      /* 1 (navigation quality, or no preview) or 2 (preview, full) */
    int scale;        /* pixel scale of the last finished pass (0: none yet; 1: full resolution) */
    float fraction;   /* of the whole job's pixels, 0 .. 1 */
    double seconds;   /* since lc_render_begin returned, to now or to the job's end */
} lc_job_progress;

/* What the pass callback sees, on the job's thread, after each pass. */
typedef struct lc_job_pass {
    int pass;           /* 1 .. npasses */
    int npasses;
    int scale;          /* every scale-th pixel, filled to scale x scale blocks; 1 = every pixel */
    int final;          /* 1: the last pass; rgba is the finished image */
    const float *rgba;  /* the job's image (the caller's buffer): read it during the callback */
    int width, height;
    double seconds;     /* since lc_render_begin returned */
} lc_job_pass;

typedef struct lc_job_desc {
    /* Pixel scale of the preview pass: 2, 4 or 8; 0 = by image size (2 below
     * 256 pixels on the longer side, 4 below 2048, 8 from there); 1 = no
     * preview pass. Ignored when the render descriptor asks for navigation
     * quality (pixel_scale > 1): that is the job's one pass. */
    int preview_scale;
    /* Called on the job's thread after each pass (not after a cancelled one);
     * it may copy pass->rgba and call lc_job_cancel and lc_job_get_progress,
     * but not wait for or destroy the job. NULL = none. */
    void (*on_pass)(void *user, const lc_job_pass *pass);
    void *user;
} lc_job_desc;

/* Starts a render of desc into rgba (width * height * 4 floats, as
 * lc_render) and returns at once with *out set; job_desc may be NULL
 * (defaults). The descriptor is copied; its TF, volume and rgba are not.
 * Errors (the descriptor's, as lc_render's) leave *out NULL and start
 * nothing. */
LC_API lc_status lc_render_begin(lc_device *device, const lc_render_desc *desc, const lc_job_desc *job_desc,
                                 float *rgba, lc_job **out);
/* Waits up to timeout_seconds (< 0: without limit; 0: only looks) for the
 * job to end: LC_OK when its image is finished (stats of all its passes,
 * seconds from begin to end, when stats is not NULL), LC_CANCELLED when it
 * was cancelled first, LC_TIMEOUT when it still runs. */
LC_API lc_status lc_job_wait(lc_job *job, double timeout_seconds, lc_render_stats *stats);
/* Asks the job to stop: it ends within the tiles being rendered (or at
 * once, while queued) as LC_JOB_CANCELLED; a job already done stays done.
 * Returns at once; NULL is ignored. */
LC_API void lc_job_cancel(lc_job *job);
LC_API lc_status lc_job_get_progress(const lc_job *job, lc_job_progress *out);
/* Cancels the job if it still runs, waits until its thread has let go of
 * rgba (a tile's time), and frees it. NULL is ignored. */
LC_API void lc_job_destroy(lc_job *job);

/* ---------------------------------------------------------------- projections (column maps, issue 27) */

/* How a projection samples each pixel (SPEC.md "SPH kernels and projections"). */
typedef enum lc_project_sample {
    LC_PROJECT_EXACT = 0, /* the average of the column over the pixel's area: exact for any
                             particle size (cumulative tables of the column kernel), so a
                             particle inside the image puts exactly its amount into the map */
    LC_PROJECT_CENTRE = 1 /* the column at the pixel's centre (SPLASH's and yt's convention,
                             without their smoothing-length floor: particles between pixel
                             centres are missed) */
} lc_project_sample;

typedef struct lc_project_desc {
    int width, height;        /* pixels, 1..LC_MAX_IMAGE_SIDE each */
    /* Orthographic: eye, at, up and height as for lc_render (square pixels of
     * height / height_px world units), the line of sight along at - eye.
     * eye == at (e.g. all zero): looking down -z at the centre of the
     * particles' centres, framing their x, y extent. A perspective camera is
     * refused (LC_ERROR_UNSUPPORTED): a column along diverging rays has no
     * pixel area to average over. */
    lc_camera camera;
    lc_project_sample sample;
    /* NULL: the column map sum_i kappa k_i W_i (amount per unit area). Else
     * a weighted projection, sum_i w_i A_i W_i / sum_i w_i W_i per pixel, with
     * A_i = kappa k_i of `particles` and w_i = kappa' k'_i of this particle set,
     * which must hold the same particles (created from descriptors of the
     * same count and the same positions and radii, e.g. the same file loaded
     * with another value); 0 where no particle reaches. */
    const lc_volume *weight;
    /* > 0: only the slab of this thickness (world units) centred on
     * camera.at across the line of sight; particles cut by a face contribute
     * their kernel's exact mass inside the slab, spread as their partial
     * column (at pixel centres, normalised to that mass; LC_PROJECT_CENTRE:
     * the partial column itself). 0 = the whole line of sight. */
    float depth;
    /* As lc_render_desc: progress on the calling thread, cancel asked by the
     * worker threads before each band of rows (LC_CANCELLED, map incomplete). */
    void (*progress)(void *user, float fraction);
    void *progress_user;
    int (*cancel)(void *user);
    void *cancel_user;
} lc_project_desc;

typedef struct lc_project_info {
    double seconds;          /* wall time */
    uint64_t particles;      /* particles that reach the image */
    uint64_t evaluations;    /* kernel-pixel evaluations (pixel contributions computed) */
    double mass;             /* sum of map x pixel area (of the numerator for weighted maps), in double */
    double pixel;            /* pixel side in world units */
    lc_vec3 centre;          /* the image centre on the image plane (world) */
    lc_vec3 right, up, view; /* unit axes: image x (left to right), image y (bottom to top), line of sight */
    double extent[4];        /* the image's [left, right, bottom, top] edges as world coordinates along
                                `right` and `up` (dot products with those axes); for a view down -z
                                with +y up these are x_min, x_max, y_min, y_max */
    int rank;                /* terms of the separable cumulative table of the kernel */
    int threads;
} lc_project_info;

/* Projects a particle set along the camera's line of sight into map
 * (width * height floats, row 0 at the top), with the set's kernel
 * (lc_particle_params.kernel; the Gaussian as the 3-D Gaussian of standard
 * deviation r_i cut at 5 r_i per axis, unit mass; the SPH kernels with
 * support H_i = r_i) and amounts kappa k_i: a column-density map when k_i are
 * masses. Every field's particles count. info may be NULL. Threads: the
 * device's pool. Errors (LC_ERROR_INVALID_ARGUMENT naming the member: sizes,
 * camera, sample, depth, a weight set that is not a particle set or holds
 * other particles; LC_ERROR_UNSUPPORTED: a perspective camera;
 * LC_CANCELLED) leave map incomplete. */
LC_API lc_status lc_particles_project(lc_device *device, const lc_volume *particles, const lc_project_desc *desc,
                                      float *map, lc_project_info *info);

/* ---------------------------------------------------------------- float maps (projections as data) */

/* A float map and what it means, for lc_map_write. */
typedef struct lc_map_desc {
    int width, height;
    const float *values;           /* width * height, row 0 at the top */
    const char *quantity;          /* what a pixel holds, e.g. "column density"; NULL = "value" */
    const char *units;             /* its units as text, e.g. "mass length^-2"; NULL = "" */
    const char *kernel;            /* the kernel's name (lc_kernel_name); NULL = not recorded */
    const char *sample;            /* "exact" or "centre"; NULL = not recorded */
    double depth;                  /* the slab's thickness, 0 = the whole line of sight */
    const lc_project_info *view;   /* the view (extent, axes, pixel size); NULL = not recorded */
} lc_map_desc;

/* 1 if path names a float-map format of lc_map_write (.npy, .fits/.fit/.fts,
 * .exr), else 0. */
LC_API int lc_map_format(const char *path);
/* Writes the map itself (not colours), the format by extension: .npy (NumPy
 * 1.0, little-endian float32, shape (height, width), rows top to bottom)
 * with a JSON sidecar PATH.json (quantity, units, kernel, sample, depth,
 * extent, axes, pixel size); .fits (cfitsio: one float32 image, first row at
 * the bottom as FITS has it, with BUNIT, BTYPE, KERNEL, SAMPLE, a linear WCS
 * (CRPIX, CRVAL, CDELT: the world coordinates along the image axes) and
 * XMIN/XMAX/YMIN/YMAX); .exr (one float channel "Y" through OpenImageIO,
 * rows top to bottom). Files appear complete or not at all.
 * LC_ERROR_UNSUPPORTED for .fits without cfitsio (lc_feature_get "fits") or
 * another extension. */
LC_API lc_status lc_map_write(lc_device *device, const char *path, const lc_map_desc *desc);

/* Colours a float map through a TF's colours (field 0; opacity unused) into
 * rgba (premultiplied, opaque: A = 1), as lc_image_write takes it. */
typedef struct lc_map_color_desc {
    int width, height;
    const float *values;
    const lc_tf *tf;     /* NULL = the "viridis" colour map */
    float range[2];      /* [lo, hi] in data units; both 0 = from the data (log: the 0.5th
                            percentile of the positive values to the largest; linear: min to max) */
    int linear;          /* 0 = log10 scale (values <= lo, zero and negative ones too, take the lowest colour) */
    int colorbar;        /* 1: rgba is (width + lc_map_colorbar_width(width)) x height, a colour
                            bar from lo (bottom) to hi (top) at its right */
} lc_map_color_desc;

LC_API int lc_map_colorbar_width(int width);
/* used (may be NULL) receives the range applied. */
LC_API lc_status lc_map_colorize(lc_device *device, const lc_map_color_desc *desc, float *rgba, float used[2]);

/* ---------------------------------------------------------------- images */

typedef struct lc_image_desc {
    int width, height;
    const float *rgba;    /* premultiplied C, A as lc_render writes them */
    lc_vec3 background;   /* composited where alpha is off: C + (1 - A) * background */
    int alpha;            /* 1: write RGBA (premultiplied in EXR, straight in PNG/TIFF) */
} lc_image_desc;

/* Writes an image through OpenImageIO, the format chosen by the file's
 * extension (.png, .exr, .tif, .jpg, .ppm, ...). The file appears complete or
 * not at all: it is written to a temporary name and renamed. */
LC_API lc_status lc_image_write(lc_device *device, const char *path, const lc_image_desc *desc);
/* Checks, before any long work, that path has an extension OpenImageIO can
 * write and that its folder is writable. device may be NULL. */
LC_API lc_status lc_image_check(lc_device *device, const char *path);

/* ---------------------------------------------------------------- resampling (particles to grids, issue 28) */

/* A particle set's field deposited at the nodes of a grid: at node
 * origin + (i, j, k) * spacing the value the particle renderer evaluates at
 * that point with the set's current parameters (lc_particle_params: the
 * Gaussian kappa k_i exp(-d^2 / (2 r_i^2)) for d < sigma r_i, or the SPH
 * kernel kappa k_i W(d, H_i) with H_i = r_i), so lc_grid_create over the
 * values renders an approximation of the particle image. */
typedef struct lc_resample_desc {
    int size[3];          /* nodes per axis, 1 .. 2^24 each */
    /* Nodes from box.lo to box.hi: spacing (hi - lo) / (size - 1); an axis
     * of one node holds it at the box's centre (spacing: the box's extent,
     * or 1 when flat). All zero = the set's bounds (lc_volume_info.bounds:
     * the centres grown by the support, where rays sample the particles). */
    lc_box3 box;
    int field;            /* the field deposited, 0 .. nfields - 1 (0 = the first); -1 = the sum of every field */
    uint64_t max_memory;  /* bytes the call may need, the values included (lc_resample_info.bytes);
                             0 = 3/4 of the physical memory */
    /* As lc_render_desc: progress on the calling thread, cancel asked before
     * each brick of nodes by the worker threads (LC_CANCELLED, values incomplete). */
    void (*progress)(void *user, float fraction);
    void *progress_user;
    int (*cancel)(void *user);
    void *cancel_user;
} lc_resample_desc;

typedef struct lc_resample_info {
    lc_vec3 origin, spacing; /* node (i, j, k) at origin + (i, j, k) * spacing (as lc_grid_desc takes them) */
    uint64_t bytes;          /* memory the deposition needs: the values, its brick tables, particle lists, scratch */
    uint64_t entries;        /* particle-brick pairs listed (a particle is listed with every brick it reaches) */
    uint64_t evaluations;    /* node-particle terms added */
    float value_min, value_max;
    double seconds;          /* wall time */
    int bricks, threads;
} lc_resample_info;

/* Evaluates the field of `particles` at size[0] * size[1] * size[2] nodes
 * into values (x fastest, then y, then z), on the device's target and pool:
 * particle-major over each particle's support in bricks of 32^3 nodes, each
 * brick summing its particles in the set's order, so the values do not depend
 * on the thread count. values NULL: a dry run that checks the sizes against
 * the memory limit and fills info (origin, spacing, bytes) without
 * depositing. info may be NULL. Errors: LC_ERROR_INVALID_ARGUMENT naming the
 * member (size, box, field; particles not a particle set),
 * LC_ERROR_OUT_OF_MEMORY when bytes would exceed max_memory (refused before
 * anything large is allocated), LC_CANCELLED. Thread safety: as lc_render
 * (the volume is only read). */
LC_API lc_status lc_particles_resample(lc_device *device, const lc_volume *particles, const lc_resample_desc *desc,
                                       float *values, lc_resample_info *info);

/* The values of a deposition (or any float grid) as a volume file, by the
 * extension: .nrrd (NRRD0004, raw, little-endian, with the spacings and the
 * space origin) or .nhdr (a detached NRRD header and its data file PATH.raw).
 * type: LC_VALUE_FLOAT32 (0 = it), or LC_VALUE_UINT8 / LC_VALUE_UINT16 storing
 * round((v - lo) / (hi - lo) * max), clamped, with range[2] = {lo, hi} (both 0:
 * the values' own minimum and maximum); the range is recorded in the header
 * (oldmin/oldmax). Files appear complete or not at all. */
typedef struct lc_volume_write_desc {
    int size[3];
    const float *values;
    lc_vec3 origin, spacing;
    lc_value_type type;
    float range[2];
} lc_volume_write_desc;
LC_API lc_status lc_volume_write(lc_device *device, const char *path, const lc_volume_write_desc *desc);

#ifdef __cplusplus
}
#endif

#endif
