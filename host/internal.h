/* Host-side internals shared across host/ and bvh/ (never seen by kernels). */
#ifndef LC_HOST_INTERNAL_H
#define LC_HOST_INTERNAL_H

#include <stdarg.h>
#include <stddef.h>
#include "lanecast/lanecast.h"
#include "kernels/shared/ktable.h"
#include "lc_config.h" /* LC_HAVE_ZLIB, LC_HAVE_JSON, LC_HAVE_LAPACKE: 0 or 1 (meson features) */

_Static_assert(LC_KMAX_FIELDS == LC_MAX_FIELDS, "kernel and API field limits agree");
_Static_assert(LC_KMAX_PLANES == LC_MAX_PLANES, "kernel and API slice plane limits agree");

#define LCI_MSG_MAX 1024

typedef struct lci_pool lci_pool;

struct lc_device {
    lc_target target;
    const lc_ktable *kt;
    int threads;
    lc_log_fn log;
    void *log_user;
    lci_pool *pool;
    void *embree; /* RTCDevice, created on first use (bvh/embree.c) */
    char last_error[LCI_MSG_MAX];
    /* lc_volume_load's progress callback while a reader runs (else NULL) */
    void (*load_progress)(void *user, float fraction);
    void *load_progress_user;
    float load_last; /* the last fraction reported */
    /* lc_volume_load's memory limit (option max_memory) while a reader runs, 0 = the default (host/formats/checked.h) */
    unsigned long long load_max_memory;
    /* lci_read_volume_share's lci_share while a reader runs (host/formats/format.h), else NULL */
    void *load_share;
};

/* Reports the fraction (0..1) of the file read to lc_load_desc.progress, when
 * one is set and the fraction grew by at least 1% (dev may be NULL). */
void lci_load_progress(lc_device *dev, double fraction);
/* lc_render with a test hook (host/api/render.c): depth, when not NULL,
 * receives width * height floats, row 0 at the top: in iso and slice modes
 * the distance t along each pixel's ray of the point it shows (the iso hit,
 * the plane point), in mip minus the pixel's maximum normalised value, +inf
 * where it shows nothing; +inf everywhere in dvr. Tests read iso hit points
 * back through it; data-parallel compositing (host/mpi/) takes the nearest. */
lc_status lci_render(lc_device *device, const lc_render_desc *desc, float *rgba, float *depth, lc_render_stats *stats);

/* Records an error (device may be NULL), logs it and returns status. */
lc_status lci_error(lc_device *device, lc_status status, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
void lci_log(lc_device *device, lc_log_level level, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* CPU features (host/cpu.c) */
int lci_cpu_supports(lc_target target);
const char *lci_cpu_missing(lc_target target); /* what the CPU/OS lacks, or "" */
const lc_ktable *lci_ktable(lc_target target); /* NULL if not compiled */
/* AUTO's choice: the first compiled and supported target of an explicit
 * preference order (widest first; ISA breaks ties), never the enum order. */
lc_target lci_target_auto(void);
/* The known target names, for error messages. */
#define LCI_TARGET_NAMES "auto, scalar, sse4, avx2, avx512, avx512_8"

/* Threads (host/pool.c): runs fn(ctx, task, worker) for task in [0, ntasks)
 * on the pool's threads plus the caller; FTZ/DAZ are set in every worker.
 * Runs from several threads take the pool one after another. */
typedef void (*lci_task_fn)(void *ctx, int task, int worker);
lci_pool *lci_pool_create(int threads);
void lci_pool_destroy(lci_pool *pool);
void lci_pool_run(lci_pool *pool, int ntasks, lci_task_fn fn, void *ctx);
/* lci_pool_run that stops waiting for the pool once *stop is non-zero (a
 * cancelled render job): 1 when it ran, 0 when it gave up. lci_pool_wake
 * makes waiting runs look at their flags again. */
int lci_pool_run_until(lci_pool *pool, int ntasks, lci_task_fn fn, void *ctx, const _Atomic int *stop);
void lci_pool_wake(lci_pool *pool);
int lci_pool_threads(const lci_pool *pool);
void lci_flush_denormals(void);

/* The device's Embree device, created on first use (bvh/embree.c); NULL +
 * error recorded on failure. */
void *lci_embree_device(lc_device *device);
void lci_embree_release(lc_device *device);

/* Strict parsing of lc_option values (host/api/options.c): each error names
 * the file, the key and the value. */
lc_status lci_option_int(lc_device *dev, const char *file, const lc_option *o, int lo, int hi, int *out);
lc_status lci_option_size(lc_device *dev, const char *file, const lc_option *o, size_t hi, size_t *out);
lc_status lci_option_float(lc_device *dev, const char *file, const lc_option *o, float lo, float hi, float *out);
/* n comma-separated floats or ints */
lc_status lci_option_floats(lc_device *dev, const char *file, const lc_option *o, int n, float *out);
lc_status lci_option_ints(lc_device *dev, const char *file, const lc_option *o, int n, int lo, int hi, int *out);
/* The load option canonical_order, 0 or 1, as the descs' canonical_order: 1, or -1 for 0 */
lc_status lci_option_order(lc_device *dev, const char *file, const lc_option *o, int *out);
/* An integer knob from the environment (tests and A/B runs, e.g.
 * LANECAST_PARTICLE_SKIP): its value when set to a whole number in [lo, hi],
 * else unset. */
long lci_env_long(const char *name, long lo, long hi, long unset);

/* Optional features (host/api/features.c), indexed like lc_feature_get. */
enum { LCI_FEATURE_ZLIB = 0, LCI_FEATURE_JSON = 1, LCI_FEATURE_LAPACKE = 2, LCI_FEATURE_NIFTI = 3, LCI_FEATURE_HDF5 = 4,
       LCI_FEATURE_MPI = 5, LCI_FEATURE_NETCDF = 6, LCI_FEATURE_FITS = 7,
       LCI_FEATURE_GDCM = 8 };
/* The error for something this build lacks: "WHERE: WHAT needs LIB, which this
 * build of lanecast lacks (install PKG and rebuild)", LC_ERROR_UNSUPPORTED. */
lc_status lci_missing(lc_device *dev, const char *where, const char *what, int feature);

double lci_now(void);
void *lci_aligned_alloc(size_t align, size_t bytes); /* zeroed; free with lci_aligned_free */
void lci_aligned_free(void *p);

/* A private temporary file next to path with the same extension, registered
 * so that SIGINT/SIGTERM handlers remove it (host/api/image.c): its name in
 * out (n bytes), its fd returned, or -1 with errno set; *slot is released
 * with lci_temp_release once the file is renamed or unlinked. */
#define LCI_TEMP_NAME 4096 /* the longest temporary name lci_temp_file registers */
int lci_temp_file(const char *path, char *out, size_t n, int *slot);
void lci_test_write_delay(void); /* LANECAST_TEST_WRITE_DELAY_MS (tests only) */
/* The extension of path's last component ("" if none), e.g. ".png". */
const char *lci_path_extension(const char *path);
void lci_temp_release(int slot);
/* host/api/image.c: files that appear complete or not at all (a temporary
 * name next to path, checked writes, fsync, rename). Pixels (ch channels,
 * float or 8-bit) encoded as path's format by OpenImageIO; plain bytes; or a
 * writer that fills the (created, empty) temporary file tmp itself, returning
 * 0 or -1 with a message in err. */
lc_status lci_image_encode_write(lc_device *device, const char *path, int width, int height, int channels,
                                 int is_float, const void *pixels);
lc_status lci_write_bytes(lc_device *device, const char *path, const void *bytes, size_t n);
lc_status lci_write_with(lc_device *device, const char *path,
                         int (*write)(void *user, const char *tmp, char *err, size_t errlen), void *user);

#endif
