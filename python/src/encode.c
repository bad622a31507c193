/* RBF encoding (Jang et al. 2004 sec. 4) of scattered samples, a 3-D array
 * or a file, with progress; and writing .rbf files. */
#include <string.h>
#include "lcpy.h"

typedef struct {
    PyObject *callback;
    int failed;
} encode_ctx;

/* After each iteration, on the calling thread (which released the GIL). */
static void on_progress(void *user, const lc_rbf_encode_progress *p)
{
    encode_ctx *c = user;
    if (c->failed) return;
    PyGILState_STATE g = PyGILState_Ensure();
    PyObject *r = PyObject_CallFunction(c->callback, "({s:i,s:n,s:d,s:d,s:d,s:n,s:i})", "iteration", p->iteration,
                                        "rbfs", (Py_ssize_t)p->rbfs, "rms", p->rms, "seconds", p->seconds, "target",
                                        p->target, "max_rbfs", (Py_ssize_t)p->max_rbfs, "polish", p->polish);
    if (!r) c->failed = 1; /* kept, raised when the encoder returns (it cannot be stopped) */
    Py_XDECREF(r);
    PyGILState_Release(g);
}

static PyObject *array_of(const float *p, npy_intp n, int w)
{
    npy_intp dims[2] = {n, w};
    PyArrayObject *a = (PyArrayObject *)PyArray_SimpleNew(w > 1 ? 2 : 1, dims, NPY_FLOAT32);
    if (a && n) memcpy(PyArray_DATA(a), p, sizeof(float) * (size_t)n * (size_t)w);
    return (PyObject *)a;
}

/* The samples: points + values, a 3-D array (grid, order, spacing, origin) or a file. */
static lc_status make_samples(DeviceObject *d, PyObject *points, PyObject *values, PyObject *grid, const char *order,
                              PyObject *spacing, PyObject *origin, PyObject *path, lc_samples **out, PyObject **keep)
{
    int copied;
    lc_status s = LC_OK;
    if (path != Py_None) {
        PyObject *p;
        if (!PyUnicode_FSConverter(path, &p)) return LC_ERROR_INVALID_ARGUMENT;
        *keep = p;
        Py_BEGIN_ALLOW_THREADS
        lcpy_lock(d);
        s = lc_samples_load(d->dev, PyBytes_AS_STRING(p), NULL, out);
        lcpy_unlock(d);
        Py_END_ALLOW_THREADS
        return s;
    }
    lc_samples_desc sd = {0};
    lc_grid_desc gd = {0};
    PyArrayObject *a = NULL, *b = NULL;
    if (grid != Py_None) {
        if (lcpy_grid_array(grid, "grid", order, LCPY_COPY_NEEDED, &gd, &a, &copied) ||
            (spacing != Py_None && lcpy_vec3(spacing, "spacing", &gd.spacing)) ||
            (origin != Py_None && lcpy_vec3(origin, "origin", &gd.origin)))
            return Py_XDECREF(a), LC_ERROR_INVALID_ARGUMENT;
        sd.grid = &gd;
    } else if (points != Py_None && values != Py_None) {
        if (!(a = lcpy_array(points, "points", NPY_FLOAT32, "fiu", 2, 3, LCPY_COPY_NEEDED, &copied)) ||
            !(b = lcpy_array(values, "values", NPY_FLOAT32, "fiu", 1, -1, LCPY_COPY_NEEDED, &copied)))
            return Py_XDECREF(a), LC_ERROR_INVALID_ARGUMENT;
        if (PyArray_DIM(a, 0) != PyArray_DIM(b, 0)) {
            PyErr_Format(PyExc_ValueError, "values: expected %lld values (one per point), got %lld",
                         (long long)PyArray_DIM(a, 0), (long long)PyArray_DIM(b, 0));
            return Py_DECREF(a), Py_DECREF(b), LC_ERROR_INVALID_ARGUMENT;
        }
        sd.count = (size_t)PyArray_DIM(a, 0), sd.points = PyArray_DATA(a), sd.values = PyArray_DATA(b);
    } else {
        PyErr_SetString(PyExc_TypeError, "encode: give points and values, grid, or path");
        return LC_ERROR_INVALID_ARGUMENT;
    }
    Py_BEGIN_ALLOW_THREADS
    lcpy_lock(d);
    s = lc_samples_create(d->dev, &sd, out);
    lcpy_unlock(d);
    Py_END_ALLOW_THREADS
    Py_XDECREF(a);
    Py_XDECREF(b);
    return s;
}

/* encode(device, points, values, grid, order, spacing, origin, path, max_error, max_rbfs,
 *        centre, fit_range, fit_samples, lm_samples, local_rbfs, seed, progress)
 * -> (centres, widths, weights, bias, report) */
PyObject *lcpy_encode(PyObject *self, PyObject *args, PyObject *kw)
{
    (void)self;
    static char *kwlist[] = {"device", "points", "values", "grid", "order", "spacing", "origin", "path",
                             "max_error", "max_rbfs", "centre", "fit_range", "fit_samples", "lm_samples",
                             "local_rbfs", "seed", "progress", NULL};
    PyObject *dev_o, *points = Py_None, *values = Py_None, *grid = Py_None, *spacing = Py_None, *origin = Py_None;
    PyObject *path = Py_None, *centre_o = Py_None, *fit_o = Py_None, *progress = Py_None;
    const char *order = "zyx";
    lc_rbf_encode_desc ed = {0};
    Py_ssize_t max_rbfs = 0, fit_samples = 0, lm_samples = 0;
    unsigned int seed = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O|$OOOsOOOfnOOnniIO:encode", kwlist, &dev_o, &points, &values, &grid,
                                     &order, &spacing, &origin, &path, &ed.max_error, &max_rbfs, &centre_o, &fit_o,
                                     &fit_samples, &lm_samples, &ed.local_rbfs, &seed, &progress))
        return NULL;
    DeviceObject *d = lcpy_device_or_default(dev_o);
    if (!d) return NULL;
    if (max_rbfs < 0 || fit_samples < 0 || lm_samples < 0)
        return PyErr_Format(PyExc_ValueError, "max_rbfs, fit_samples, lm_samples: expected counts >= 0");
    ed.max_rbfs = (size_t)max_rbfs, ed.fit_samples = (size_t)fit_samples, ed.lm_samples = (size_t)lm_samples;
    ed.seed = seed;
    static const char *const centres[] = {"mean", "maxerr"};
    int centre = 0;
    if (centre_o != Py_None && lcpy_choice(centre_o, "centre", centres, 2, &centre)) return NULL;
    ed.centre = (lc_rbf_centre)centre;
    if (fit_o != Py_None) {
        if (!PyArg_ParseTuple(fit_o, "ff;fit_range: expected (lo, hi)", &ed.fit_range[0], &ed.fit_range[1])) return NULL;
        ed.fit_range_set = 1;
    }
    encode_ctx ctx = {progress, 0};
    if (progress != Py_None) ed.progress = on_progress, ed.progress_user = &ctx;
    lc_samples *sm = NULL;
    PyObject *keep = NULL;
    lc_status s = make_samples(d, points, values, grid, order, spacing, origin, path, &sm, &keep);
    Py_XDECREF(keep);
    if (PyErr_Occurred()) return lc_samples_destroy(sm), NULL;
    if (s != LC_OK) return lcpy_raise(s, "encode");
    lc_rbf_encoded *enc = NULL;
    lc_rbf_encode_report rep;
    memset(&rep, 0, sizeof rep);
    Py_BEGIN_ALLOW_THREADS
    lcpy_lock(d);
    s = lc_rbf_encode(d->dev, sm, &ed, &enc, &rep);
    lcpy_unlock(d);
    Py_END_ALLOW_THREADS
    lc_samples_destroy(sm);
    if (ctx.failed) return lc_rbf_encoded_free(enc), NULL;
    if (s != LC_OK) return lcpy_raise(s, "encode");
    const lc_rbf_desc *e = &enc->desc;
    PyObject *r = Py_BuildValue("NNNf{s:n,s:n,s:n,s:(ff),s:d,s:d,s:i,s:O,s:d}", array_of(e->centres, (npy_intp)e->count, 3),
                                array_of(e->widths, (npy_intp)e->count, 1), array_of(e->weights, (npy_intp)e->count, 1),
                                e->bias, "rbfs", (Py_ssize_t)rep.rbfs, "samples", (Py_ssize_t)rep.samples, "fitted",
                                (Py_ssize_t)rep.fitted, "range", rep.range[0], rep.range[1], "rms", rep.rms,
                                "max_error", rep.max_error, "iterations", rep.iterations, "reached",
                                rep.reached ? Py_True : Py_False, "seconds", rep.seconds);
    lc_rbf_encoded_free(enc);
    return r;
}

/* rbf_write(device, path, centres, widths, weights, bias, text=False) */
PyObject *lcpy_rbf_write(PyObject *self, PyObject *args, PyObject *kw)
{
    (void)self;
    static char *kwlist[] = {"device", "path", "centres", "widths", "weights", "bias", "text", NULL};
    PyObject *dev_o, *path_o, *c_o, *w_o, *wt_o;
    float bias;
    int text = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO&OOOf|p:rbf_write", kwlist, &dev_o, PyUnicode_FSConverter, &path_o,
                                     &c_o, &w_o, &wt_o, &bias, &text))
        return NULL;
    DeviceObject *d = lcpy_device_or_default(dev_o);
    PyArrayObject *a[3] = {NULL, NULL, NULL};
    PyObject *result = NULL;
    int copied;
    if (!d || !(a[0] = lcpy_array(c_o, "centres", NPY_FLOAT32, "fiu", 2, 3, LCPY_COPY_NEEDED, &copied)) ||
        !(a[1] = lcpy_array(w_o, "widths", NPY_FLOAT32, "fiu", 1, -1, LCPY_COPY_NEEDED, &copied)) ||
        !(a[2] = lcpy_array(wt_o, "weights", NPY_FLOAT32, "fiu", 1, -1, LCPY_COPY_NEEDED, &copied)))
        goto out;
    lc_rbf_desc rd = {.count = (size_t)PyArray_DIM(a[0], 0), .centres = PyArray_DATA(a[0]),
                      .widths = PyArray_DATA(a[1]), .weights = PyArray_DATA(a[2]), .bias = bias};
    if (PyArray_DIM(a[1], 0) != PyArray_DIM(a[0], 0) || PyArray_DIM(a[2], 0) != PyArray_DIM(a[0], 0)) {
        PyErr_SetString(PyExc_ValueError, "widths, weights: expected one per centre");
        goto out;
    }
    lc_status s;
    Py_BEGIN_ALLOW_THREADS
    lcpy_lock(d);
    s = lc_rbf_write(d->dev, PyBytes_AS_STRING(path_o), &rd, text ? LC_RBF_FILE_TEXT : LC_RBF_FILE_BINARY);
    lcpy_unlock(d);
    Py_END_ALLOW_THREADS
    if (s != LC_OK) lcpy_raise(s, NULL);
    else result = Py_NewRef(Py_None);
out:
    for (int i = 0; i < 3; i++) Py_XDECREF(a[i]);
    Py_DECREF(path_o);
    return result;
}
