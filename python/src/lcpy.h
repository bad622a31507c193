/* The CPython extension lanecast._lanecast: shared declarations of its C
 * files. Written against the public C API only (include/lanecast/lanecast.h);
 * the pure-Python package lanecast/ wraps it (docs/PYTHON.md).
 *
 * Rules every file follows (STYLE.md "A binding is thin and checked"):
 * - one conversion per argument kind (arrays.c), one function turning an
 *   lc_status into an exception (lcpy_raise);
 * - the GIL is released around every call that may take long (loads, BVH
 *   builds, renders, encoding, image writes), with the device's lock held so
 *   that one device is used by one thread at a time (lanecast.h);
 * - a volume holds a reference to its device and to every array it borrows. */
#ifndef LCPY_H
#define LCPY_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <pthread.h>

#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#define PY_ARRAY_UNIQUE_SYMBOL lanecast_ARRAY_API
#ifndef LCPY_IMPORT_ARRAY
#define NO_IMPORT_ARRAY
#endif
#include <numpy/arrayobject.h>

#include <lanecast/lanecast.h>

/* ---- devices (device.c) */

#define LCPY_MAX_WARNINGS 8

typedef struct {
    PyObject_HEAD
    lc_device *dev;
    PyThread_type_lock lock; /* held (without the GIL) by the thread using dev */
    /* warnings the log callback collects during a call; issued as Python
       warnings (lanecast.Warning) once the call is over and the GIL is back */
    pthread_mutex_t log_mutex;
    char warnings[LCPY_MAX_WARNINGS][512];
    int nwarnings;
} DeviceObject;

extern PyTypeObject lcpy_DeviceType;

/* The device to use: obj if it is a Device, else (None) the module's default
 * device, created on first use. A borrowed reference, or NULL with an
 * exception set. */
DeviceObject *lcpy_device_or_default(PyObject *obj);
/* Release the GIL before lcpy_lock, reacquire after lcpy_unlock. */
void lcpy_lock(DeviceObject *d);
void lcpy_unlock(DeviceObject *d);
/* Issues the collected warnings (GIL held); -1 when a warning filter raised. */
int lcpy_flush_warnings(DeviceObject *d);

/* Runs `status = call` with the GIL released and the device d locked. */
#define LCPY_UNLOCKED(d, status, call)                                                                               \
    do {                                                                                                               \
        Py_BEGIN_ALLOW_THREADS lcpy_lock(d);                                                                           \
        status = (call);                                                                                               \
        lcpy_unlock(d);                                                                                                \
        Py_END_ALLOW_THREADS                                                                                           \
    } while (0)

/* ---- volumes (volume.c, rbfset.c, load.c) */

typedef struct {
    PyObject_HEAD
    lc_volume *vol;
    DeviceObject *device; /* strong: destroyed after the volume */
    PyObject *keep;       /* arrays the volume borrows (a tuple), or NULL */
    PyObject *dict;       /* instance attributes (the Python layer's) */
    int busy;             /* renders in flight; changed with the GIL held */
} VolumeObject;

extern PyTypeObject lcpy_VolumeType, lcpy_ParticlesType, lcpy_GridType, lcpy_RBFSetType;

/* The GC slots every volume type shares. */
int lcpy_volume_traverse(VolumeObject *v, visitproc visit, void *arg);
int lcpy_volume_clear(VolumeObject *v);
/* A new Python object of the type matching the volume's kind, owning vol. */
PyObject *lcpy_volume_wrap(lc_volume *vol, DeviceObject *d, PyObject *keep);
/* The lc_volume of obj (a Volume), or NULL with TypeError naming `name`. */
VolumeObject *lcpy_volume_arg(PyObject *obj, const char *name);

/* ---- transfer functions (tf.c) */

typedef struct {
    PyObject_HEAD
    lc_tf *tf;
    PyObject *dict;
} TFObject;

extern PyTypeObject lcpy_TFType;

/* ---- arrays (arrays.c) */

typedef enum { LCPY_COPY_NEEDED = -1, LCPY_COPY_NEVER = 0, LCPY_COPY_ALWAYS = 1 } lcpy_copy;

/* Parses the copy= argument (None, False, True). */
int lcpy_copy_arg(PyObject *obj, lcpy_copy *out);

/* obj as a C-contiguous, aligned, native-endian array of typenum with ndim
 * axes (the last of size cols unless cols < 0): the caller's array itself
 * when it already is one (unless copy = ALWAYS), else a converted copy
 * (copy = NEVER: ValueError instead). kinds: the accepted dtype kinds ("fiu";
 * "iu" for ids). Messages name `name` and what was expected. Returns a new
 * reference or NULL with TypeError/ValueError set; *copied tells which. */
PyArrayObject *lcpy_array(PyObject *obj, const char *name, int typenum, const char *kinds, int ndim, npy_intp cols,
                          lcpy_copy copy, int *copied);
/* The name (of names[i]) of the first of n float32 arrays holding a non-finite
 * value, or NULL: for the library's message, which names the element. */
const char *lcpy_nonfinite_arg(PyArrayObject **arrays, const char *const *names, int n);
/* The first non-finite value of a float32 array, or -1. */
npy_intp lcpy_first_nonfinite(PyArrayObject *a);
/* A sequence of 3 finite numbers (x, y, z); -1 with an exception naming name. */
int lcpy_vec3(PyObject *obj, const char *name, lc_vec3 *out);

/* The grid descriptor of a 3-D array: axis order (e.g. "zyx": axis 0 is z),
 * dtype kept when lanecast has it (uint8, uint16, int16, float32), other
 * numbers as float32; *buffer receives the array whose memory d->data points
 * into (a new reference). Sets size, type, data only. */
int lcpy_grid_array(PyObject *obj, const char *name, const char *order, lcpy_copy copy, lc_grid_desc *d,
                    PyArrayObject **buffer, int *copied);

/* ---- errors (module.c) */

/* Raises the exception class of status with lc_last_error() (prefixed with
 * "prefix: " when prefix is not NULL). Always returns NULL. */
PyObject *lcpy_raise(lc_status status, const char *prefix);
/* The exception classes: lanecast.Error and one per status. */
PyObject *lcpy_error_class(lc_status status);
extern PyObject *lcpy_Warning;

/* ---- functions of the other files, in the module's method table */

PyObject *lcpy_render(PyObject *self, PyObject *args, PyObject *kw);       /* render.c */
PyObject *lcpy_image_write(PyObject *self, PyObject *args, PyObject *kw);  /* render.c */
PyObject *lcpy_load(PyObject *self, PyObject *args, PyObject *kw);         /* load.c */
PyObject *lcpy_probe(PyObject *self, PyObject *args, PyObject *kw);        /* load.c */
PyObject *lcpy_encode(PyObject *self, PyObject *args, PyObject *kw);       /* encode.c */
PyObject *lcpy_rbf_write(PyObject *self, PyObject *args, PyObject *kw);    /* encode.c */
/* load options: a dict of key -> str; fills opts (keys and values borrowed
 * from `strings`, a list the caller keeps until the call is over) */
int lcpy_options(PyObject *dict, lc_option *opts, int max, int *n, PyObject *strings);

/* Parses one of several names into its index (ValueError naming what). */
int lcpy_choice(PyObject *obj, const char *what, const char *const *names, int n, int *out);

#endif
