/* Rendering and image writing, with the GIL released.
 *
 * Ctrl-C: Python only notices SIGINT between bytecodes, which a C call of
 * seconds does not reach. So, for a render called from the main thread, a
 * C-level SIGINT handler is installed for the duration of the call (and the
 * previous one restored after); it sets an atomic flag that the render's
 * cancel callback (lc_render_desc.cancel, asked before every tile by the
 * worker threads) reads, so the render stops within a tile. The signal is
 * then handed to Python (PyErr_SetInterruptEx), whose handler raises
 * KeyboardInterrupt as usual. A SIGINT that Python ignores (SIG_IGN) or
 * leaves to the system (SIG_DFL) is not taken over. Renders from other
 * threads are not cancelled: Python delivers signals to the main thread. */
#include <signal.h>
#include <stdatomic.h>
#include <string.h>
#include "lcpy.h"

static atomic_int sigint_seen;
static unsigned long main_thread;

static void on_sigint(int sig)
{
    (void)sig;
    atomic_store(&sigint_seen, 1);
}

static int cancel_requested(void *user)
{
    (void)user;
    return atomic_load_explicit(&sigint_seen, memory_order_relaxed);
}

/* Takes SIGINT over for a call; 1 = taken (restore with `old`). */
static int take_sigint(struct sigaction *old)
{
    if (!main_thread) {
        PyObject *th = PyImport_ImportModule("threading");
        PyObject *mt = th ? PyObject_CallMethod(th, "main_thread", NULL) : NULL;
        PyObject *id = mt ? PyObject_GetAttrString(mt, "ident") : NULL;
        main_thread = id ? PyLong_AsUnsignedLong(id) : 0;
        Py_XDECREF(id);
        Py_XDECREF(mt);
        Py_XDECREF(th);
        PyErr_Clear();
    }
    if (!main_thread || PyThread_get_thread_ident() != main_thread) return 0;
    if (sigaction(SIGINT, NULL, old) != 0 || old->sa_handler == SIG_IGN || old->sa_handler == SIG_DFL) return 0;
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_sigint;
    sigemptyset(&sa.sa_mask);
    atomic_store(&sigint_seen, 0);
    return sigaction(SIGINT, &sa, NULL) == 0;
}

/* Gives SIGINT back; -1 with KeyboardInterrupt (or whatever Python's
 * handler raised) when it came during the call. */
static int give_sigint(const struct sigaction *old)
{
    sigaction(SIGINT, old, NULL);
    if (!atomic_exchange(&sigint_seen, 0)) return 0;
    PyErr_SetInterruptEx(SIGINT);
    return PyErr_CheckSignals();
}

static PyObject *stats_dict(const lc_render_stats *st)
{
    return Py_BuildValue("{s:d,s:K,s:K,s:K,s:K,s:K,s:K,s:s,s:i}", "seconds", st->seconds, "rays",
                         (unsigned long long)st->rays, "samples", (unsigned long long)st->samples, "kernel_evals",
                         (unsigned long long)st->kernel_evals, "nodes", (unsigned long long)st->nodes, "leaves",
                         (unsigned long long)st->leaves, "passes", (unsigned long long)st->passes, "target",
                         lc_target_name(st->target), "threads", st->threads);
}

static int parse_planes(PyObject *obj, lc_render_desc *rd)
{
    if (obj == Py_None) return 0;
    PyObject *seq = PySequence_Fast(obj, "planes: expected a list of (point, normal) pairs");
    if (!seq) return -1;
    Py_ssize_t n = PySequence_Fast_GET_SIZE(seq);
    if (n < 1 || n > LC_MAX_PLANES) {
        Py_DECREF(seq);
        PyErr_Format(PyExc_ValueError, "planes: expected 1 to %d (point, normal) pairs, got %zd", LC_MAX_PLANES, n);
        return -1;
    }
    for (Py_ssize_t i = 0; i < n; i++) {
        PyObject *p, *nrm;
        if (!PyArg_ParseTuple(PySequence_Fast_GET_ITEM(seq, i), "OO;planes: expected (point, normal) pairs", &p, &nrm) ||
            lcpy_vec3(p, "planes: point", &rd->planes[i].point) || lcpy_vec3(nrm, "planes: normal", &rd->planes[i].normal)) {
            Py_DECREF(seq);
            return -1;
        }
    }
    rd->nplanes = (int)n;
    Py_DECREF(seq);
    return 0;
}

/* render(device, volume, tf, width, height, camera, range, mode, iso, field,
 *        planes, dt, alpha_stop, shading, lighting, method, packet, tile,
 *        pixel_scale, step_scale, out) -> (rgba, stats)
 * camera: (projection, eye, at, up, fovy, height); enums as ints (the
 * Python layer maps the names). */
PyObject *lcpy_render(PyObject *self, PyObject *args, PyObject *kw)
{
    (void)self;
    static char *kwlist[] = {"device", "volume", "tf", "width", "height", "camera", "range", "mode", "iso",
                             "field", "planes", "dt", "alpha_stop", "shading", "lighting", "method", "packet",
                             "tile", "pixel_scale", "step_scale", "out", NULL};
    PyObject *dev_o, *vol_o, *tf_o, *cam_o, *range_o = Py_None, *planes_o = Py_None, *light_o = Py_None, *out_o = Py_None;
    lc_render_desc rd;
    memset(&rd, 0, sizeof rd);
    int mode = 0, shading = 0, method = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OOOiiO|$OifiOffiOiiiifO:render", kwlist, &dev_o, &vol_o, &tf_o,
                                     &rd.width, &rd.height, &cam_o, &range_o, &mode, &rd.iso, &rd.field, &planes_o,
                                     &rd.dt, &rd.alpha_stop, &shading, &light_o, &method, &rd.packet, &rd.tile,
                                     &rd.pixel_scale, &rd.step_scale, &out_o))
        return NULL;
    DeviceObject *d = lcpy_device_or_default(dev_o);
    VolumeObject *v = lcpy_volume_arg(vol_o, "volume");
    if (!d || !v) return NULL;
    if (tf_o != Py_None) {
        if (!PyObject_TypeCheck(tf_o, &lcpy_TFType))
            return PyErr_Format(PyExc_TypeError, "tf: expected a lanecast.TransferFunction or None, got %.100s",
                                Py_TYPE(tf_o)->tp_name);
        rd.tf = ((TFObject *)tf_o)->tf;
    }
    int proj = 0;
    PyObject *eye, *at, *up;
    if (!PyArg_ParseTuple(cam_o, "iOOOff;camera: expected (projection, eye, at, up, fovy, height)", &proj, &eye, &at,
                          &up, &rd.camera.fovy, &rd.camera.height) ||
        lcpy_vec3(eye, "eye", &rd.camera.eye) || lcpy_vec3(at, "at", &rd.camera.at) || lcpy_vec3(up, "up", &rd.camera.up))
        return NULL;
    rd.camera.projection = (lc_projection)proj;
    if (range_o != Py_None && !PyArg_ParseTuple(range_o, "ff;range: expected (lo, hi)", &rd.range[0], &rd.range[1]))
        return NULL;
    if (light_o != Py_None && !PyArg_ParseTuple(light_o, "fffi;lighting: expected (ka, kd, ks, phong_exp)",
                                                &rd.lighting.ka, &rd.lighting.kd, &rd.lighting.ks,
                                                &rd.lighting.phong_exp))
        return NULL;
    if (parse_planes(planes_o, &rd)) return NULL;
    rd.mode = (lc_mode)mode, rd.shading = (lc_shading)shading, rd.method = (lc_method)method;
    rd.volume = v->vol;
    if (rd.width < 1 || rd.height < 1 || rd.width > LC_MAX_IMAGE_SIDE || rd.height > LC_MAX_IMAGE_SIDE)
        return PyErr_Format(PyExc_ValueError, "width, height: expected 1 to %d pixels each, got %dx%d",
                            LC_MAX_IMAGE_SIDE, rd.width, rd.height);
    PyArrayObject *img;
    if (out_o != Py_None) { /* a buffer of the caller's, reused */
        img = (PyArrayObject *)out_o;
        if (!PyArray_Check(out_o) || PyArray_TYPE(img) != NPY_FLOAT32 || !PyArray_ISCARRAY(img) ||
            PyArray_NDIM(img) != 3 || PyArray_DIM(img, 0) != rd.height || PyArray_DIM(img, 1) != rd.width ||
            PyArray_DIM(img, 2) != 4)
            return PyErr_Format(PyExc_ValueError, "out: expected a writeable C-contiguous float32 array of shape "
                                "(%d, %d, 4)", rd.height, rd.width);
        Py_INCREF(img);
    } else {
        npy_intp dims[3] = {rd.height, rd.width, 4};
        if (!(img = (PyArrayObject *)PyArray_SimpleNew(3, dims, NPY_FLOAT32))) return NULL;
    }
    struct sigaction old;
    int taken = take_sigint(&old);
    if (taken) rd.cancel = cancel_requested;
    lc_render_stats st;
    memset(&st, 0, sizeof st);
    lc_status s;
    v->busy++;
    Py_INCREF(v);
    Py_XINCREF(tf_o);
    Py_BEGIN_ALLOW_THREADS
    lcpy_lock(d);
    s = lc_render(d->dev, &rd, PyArray_DATA(img), &st);
    lcpy_unlock(d);
    Py_END_ALLOW_THREADS
    v->busy--;
    Py_DECREF(v);
    Py_XDECREF(tf_o);
    if ((taken && give_sigint(&old) < 0) || lcpy_flush_warnings(d)) return Py_DECREF(img), NULL;
    if (s != LC_OK) return Py_DECREF(img), lcpy_raise(s, "render");
    return Py_BuildValue("NN", img, stats_dict(&st));
}

/* image_write(device, path, rgba, background=(0, 0, 0), alpha=False) */
PyObject *lcpy_image_write(PyObject *self, PyObject *args, PyObject *kw)
{
    (void)self;
    static char *kwlist[] = {"device", "path", "rgba", "background", "alpha", NULL};
    PyObject *dev_o, *path_o, *rgba_o, *bg_o = Py_None;
    int alpha = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO&O|Op:image_write", kwlist, &dev_o, PyUnicode_FSConverter, &path_o,
                                     &rgba_o, &bg_o, &alpha))
        return NULL;
    DeviceObject *d = lcpy_device_or_default(dev_o);
    lc_image_desc id = {.alpha = alpha};
    int copied;
    PyArrayObject *a = NULL;
    PyObject *result = NULL;
    if (!d || (bg_o != Py_None && lcpy_vec3(bg_o, "background", &id.background))) goto out;
    if (!(a = lcpy_array(rgba_o, "image", NPY_FLOAT32, "fiu", 3, 4, LCPY_COPY_NEEDED, &copied))) goto out;
    id.width = (int)PyArray_DIM(a, 1), id.height = (int)PyArray_DIM(a, 0);
    id.rgba = PyArray_DATA(a);
    lc_status s;
    Py_BEGIN_ALLOW_THREADS
    lcpy_lock(d);
    s = lc_image_write(d->dev, PyBytes_AS_STRING(path_o), &id);
    lcpy_unlock(d);
    Py_END_ALLOW_THREADS
    if (s != LC_OK) lcpy_raise(s, NULL);
    else result = Py_NewRef(Py_None);
out:
    Py_XDECREF(a);
    Py_DECREF(path_o);
    return result;
}
