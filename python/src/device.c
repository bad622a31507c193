/* lanecast.Device: an lc_device, its lock and the warnings its log callback
 * collects (lcpy.h). */
#include <string.h>
#include "lcpy.h"

static DeviceObject *default_device;

void lcpy_lock(DeviceObject *d)
{
    PyThread_acquire_lock(d->lock, WAIT_LOCK);
}

void lcpy_unlock(DeviceObject *d)
{
    PyThread_release_lock(d->lock);
}

/* The log callback: any thread, GIL or not; keeps warnings for later. */
static void on_log(void *user, lc_log_level level, const char *message)
{
    DeviceObject *d = user;
    if (level != LC_LOG_WARNING) return;
    pthread_mutex_lock(&d->log_mutex);
    if (d->nwarnings < LCPY_MAX_WARNINGS) snprintf(d->warnings[d->nwarnings++], sizeof d->warnings[0], "%s", message);
    pthread_mutex_unlock(&d->log_mutex);
}

int lcpy_flush_warnings(DeviceObject *d)
{
    char w[LCPY_MAX_WARNINGS][512];
    pthread_mutex_lock(&d->log_mutex);
    int n = d->nwarnings;
    memcpy(w, d->warnings, sizeof w);
    d->nwarnings = 0;
    pthread_mutex_unlock(&d->log_mutex);
    for (int i = 0; i < n; i++)
        if (PyErr_WarnEx(lcpy_Warning, w[i], 1) < 0) return -1;
    return 0;
}

static PyObject *device_new(PyTypeObject *type, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"threads", "target", NULL};
    PyObject *threads = Py_None;
    const char *target = "auto";
    if (!PyArg_ParseTupleAndKeywords(args, kw, "|O$s:Device", kwlist, &threads, &target)) return NULL;
    lc_device_desc dd = {0};
    if (threads != Py_None) {
        long t = PyLong_AsLong(threads);
        if (t == -1 && PyErr_Occurred()) return NULL;
        if (t < 1 || t > 1024)
            return PyErr_Format(PyExc_ValueError, "threads: expected None (all CPUs) or 1 to 1024, got %ld", t);
        dd.threads = (int)t;
    }
    if (lc_target_from_name(target, &dd.target) != LC_OK) return lcpy_raise(LC_ERROR_INVALID_ARGUMENT, "target");
    DeviceObject *d = (DeviceObject *)type->tp_alloc(type, 0);
    if (!d) return NULL;
    pthread_mutex_init(&d->log_mutex, NULL);
    d->lock = PyThread_allocate_lock();
    if (!d->lock) {
        Py_DECREF(d);
        return PyErr_NoMemory();
    }
    dd.log = on_log, dd.log_user = d;
    lc_status s;
    Py_BEGIN_ALLOW_THREADS
    s = lc_device_create(&dd, &d->dev);
    Py_END_ALLOW_THREADS
    if (s != LC_OK) {
        Py_DECREF(d);
        return lcpy_raise(s, "Device");
    }
    return (PyObject *)d;
}

static void device_dealloc(DeviceObject *d)
{
    lc_device_destroy(d->dev); /* volumes and TFs hold references: they are gone */
    if (d->lock) PyThread_free_lock(d->lock);
    pthread_mutex_destroy(&d->log_mutex);
    Py_TYPE(d)->tp_free((PyObject *)d);
}

DeviceObject *lcpy_device_or_default(PyObject *obj)
{
    if (obj && obj != Py_None) {
        if (PyObject_TypeCheck(obj, &lcpy_DeviceType)) return (DeviceObject *)obj;
        PyErr_Format(PyExc_TypeError, "device: expected a lanecast.Device or None, got %.100s", Py_TYPE(obj)->tp_name);
        return NULL;
    }
    if (!default_device) {
        PyObject *args = PyTuple_New(0);
        default_device = args ? (DeviceObject *)device_new(&lcpy_DeviceType, args, NULL) : NULL;
        Py_XDECREF(args);
    }
    return default_device;
}

static PyObject *device_get_target(DeviceObject *d, void *c)
{
    (void)c;
    lc_target t;
    if (lc_device_target(d->dev, &t) != LC_OK) return lcpy_raise(LC_ERROR_INTERNAL, NULL);
    return PyUnicode_FromString(lc_target_name(t));
}

static PyObject *device_get_threads(DeviceObject *d, void *c)
{
    (void)c;
    int t;
    if (lc_device_threads(d->dev, &t) != LC_OK) return lcpy_raise(LC_ERROR_INTERNAL, NULL);
    return PyLong_FromLong(t);
}

static PyObject *device_get_lanes(DeviceObject *d, void *c)
{
    (void)c;
    lc_target t;
    if (lc_device_target(d->dev, &t) != LC_OK) return lcpy_raise(LC_ERROR_INTERNAL, NULL);
    return PyLong_FromLong(lc_target_lanes(t));
}

static PyObject *device_repr(DeviceObject *d)
{
    lc_target t = LC_TARGET_AUTO;
    int n = 0;
    lc_device_target(d->dev, &t);
    lc_device_threads(d->dev, &n);
    return PyUnicode_FromFormat("lanecast.Device(target=%s, threads=%d)", lc_target_name(t), n);
}

static PyGetSetDef device_getset[] = {
    {"target", (getter)device_get_target, NULL, "The SIMD target the device runs on (never 'auto').", NULL},
    {"threads", (getter)device_get_threads, NULL, "Worker threads of renders.", NULL},
    {"lanes", (getter)device_get_lanes, NULL, "Lanes per vector of the target.", NULL},
    {NULL, NULL, NULL, NULL, NULL},
};

PyTypeObject lcpy_DeviceType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "lanecast.Device",
    .tp_basicsize = sizeof(DeviceObject),
    .tp_dealloc = (destructor)device_dealloc,
    .tp_repr = (reprfunc)device_repr,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "Device(threads=None, *, target='auto')\n\n"
              "A lanecast device: the SIMD target and the worker threads renders use. threads=None uses\n"
              "LANECAST_THREADS or every CPU; target is 'auto' (LANECAST_TARGET or the widest the CPU\n"
              "runs), 'scalar', 'sse4', 'avx2', 'avx512' or 'avx512_8'. One device serves one call at a\n"
              "time: calls from several threads on one device wait for each other (the GIL is released\n"
              "meanwhile); give each thread its own device to render in parallel.",
    .tp_getset = device_getset,
    .tp_new = device_new,
};
