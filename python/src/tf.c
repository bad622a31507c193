/* lanecast.TransferFunction's C part (the Python class adds the
 * conveniences): presets, JSON and ParaView files, points, the default TF of
 * a volume. TFs are small: these calls keep the GIL and run on a private
 * device used only under it (a TF does not keep its device). */
#include <string.h>
#include "lcpy.h"

static lc_device *aux;

static lc_device *aux_device(void)
{
    if (!aux) {
        lc_device_desc dd = {.threads = 1};
        if (lc_device_create(&dd, &aux) != LC_OK) lcpy_raise(LC_ERROR_INTERNAL, "TransferFunction");
    }
    return aux;
}

static PyObject *wrap(PyTypeObject *cls, lc_tf *tf)
{
    TFObject *t = (TFObject *)cls->tp_alloc(cls, 0);
    if (!t) return lc_tf_destroy(tf), NULL;
    t->tf = tf;
    return (PyObject *)t;
}

static void tf_dealloc(TFObject *t)
{
    lc_tf_destroy(t->tf);
    Py_CLEAR(t->dict);
    Py_TYPE(t)->tp_free((PyObject *)t);
}

static PyObject *tf_preset(PyTypeObject *cls, PyObject *args)
{
    const char *name;
    int nfields = 1;
    float tau = 1.0f;
    if (!PyArg_ParseTuple(args, "s|if:preset", &name, &nfields, &tau)) return NULL;
    lc_device *dev = aux_device();
    lc_tf *tf = NULL;
    lc_status s = dev ? lc_tf_preset(dev, name, nfields, tau, &tf) : LC_ERROR_INTERNAL;
    if (s != LC_OK) return PyErr_Occurred() ? NULL : lcpy_raise(s, NULL);
    return wrap(cls, tf);
}

static PyObject *tf_load(PyTypeObject *cls, PyObject *arg)
{
    PyObject *path;
    if (!PyUnicode_FSConverter(arg, &path)) return NULL;
    lc_device *dev = aux_device();
    lc_tf *tf = NULL;
    lc_status s = dev ? lc_tf_load(dev, PyBytes_AS_STRING(path), &tf) : LC_ERROR_INTERNAL;
    Py_DECREF(path);
    if (s != LC_OK) return PyErr_Occurred() ? NULL : lcpy_raise(s, NULL);
    return wrap(cls, tf);
}

static PyObject *tf_parse(PyTypeObject *cls, PyObject *args)
{
    const char *text, *name = "<string>";
    if (!PyArg_ParseTuple(args, "s|s:parse", &text, &name)) return NULL;
    lc_device *dev = aux_device();
    lc_tf *tf = NULL;
    lc_status s = dev ? lc_tf_parse(dev, text, name, &tf) : LC_ERROR_INTERNAL;
    if (s != LC_OK) return PyErr_Occurred() ? NULL : lcpy_raise(s, NULL);
    return wrap(cls, tf);
}

/* _create([(color (n, 4), opacity (m, 2), range or None), ...]) */
static PyObject *tf_create(PyTypeObject *cls, PyObject *arg)
{
    PyObject *seq = PySequence_Fast(arg, "fields: expected a list of (color, opacity, range)");
    if (!seq) return NULL;
    Py_ssize_t n = PySequence_Fast_GET_SIZE(seq);
    if (n < 1 || n > LC_MAX_FIELDS) {
        Py_DECREF(seq);
        return PyErr_Format(PyExc_ValueError, "fields: expected 1 to %d fields, got %zd", LC_MAX_FIELDS, n);
    }
    lc_tf_field f[LC_MAX_FIELDS];
    PyArrayObject *keep[2 * LC_MAX_FIELDS] = {NULL};
    memset(f, 0, sizeof f);
    PyObject *result = NULL;
    int copied;
    for (Py_ssize_t i = 0; i < n; i++) {
        PyObject *c, *o, *r;
        if (!PyArg_ParseTuple(PySequence_Fast_GET_ITEM(seq, i), "OOO;fields: expected (color, opacity, range)", &c, &o,
                              &r))
            goto out;
        if (!(keep[2 * i] = lcpy_array(c, "color", NPY_FLOAT32, "fiu", 2, 4, LCPY_COPY_NEEDED, &copied)) ||
            !(keep[2 * i + 1] = lcpy_array(o, "opacity", NPY_FLOAT32, "fiu", 2, 2, LCPY_COPY_NEEDED, &copied)))
            goto out;
        f[i].color = PyArray_DATA(keep[2 * i]), f[i].ncolor = (int)PyArray_DIM(keep[2 * i], 0);
        f[i].opacity = PyArray_DATA(keep[2 * i + 1]), f[i].nopacity = (int)PyArray_DIM(keep[2 * i + 1], 0);
        if (r != Py_None) {
            if (!PyArg_ParseTuple(r, "ff;range: expected (lo, hi)", &f[i].range[0], &f[i].range[1])) goto out;
            f[i].has_range = 1;
        }
    }
    lc_device *dev = aux_device();
    lc_tf *tf = NULL;
    lc_status s = dev ? lc_tf_create(dev, f, (int)n, &tf) : LC_ERROR_INTERNAL;
    if (s != LC_OK) {
        if (!PyErr_Occurred()) lcpy_raise(s, NULL);
    } else {
        result = wrap(cls, tf);
    }
out:
    for (int i = 0; i < 2 * LC_MAX_FIELDS; i++) Py_XDECREF(keep[i]);
    Py_DECREF(seq);
    return result;
}

/* _auto(volume, colormap=None, tau=0): lc_tf_auto on the volume's device */
static PyObject *tf_auto(PyTypeObject *cls, PyObject *args)
{
    PyObject *vol_o;
    const char *cmap = NULL;
    float tau = 0.0f;
    if (!PyArg_ParseTuple(args, "O|zf:auto", &vol_o, &cmap, &tau)) return NULL;
    VolumeObject *v = lcpy_volume_arg(vol_o, "volume");
    if (!v) return NULL;
    lc_tf *tf = NULL;
    lc_status s;
    DeviceObject *d = v->device;
    Py_BEGIN_ALLOW_THREADS /* a histogram of the whole grid */
    lcpy_lock(d);
    s = lc_tf_auto(d->dev, v->vol, cmap, tau, &tf);
    lcpy_unlock(d);
    Py_END_ALLOW_THREADS
    if (s != LC_OK) return lcpy_raise(s, NULL);
    return wrap(cls, tf);
}

static PyObject *points(const float *p, int n, int w)
{
    npy_intp dims[2] = {n, w};
    PyArrayObject *a = (PyArrayObject *)PyArray_SimpleNew(2, dims, NPY_FLOAT32);
    if (a) memcpy(PyArray_DATA(a), p, sizeof(float) * (size_t)n * (size_t)w);
    return (PyObject *)a;
}

/* fields() -> [{"color": (n, 4), "opacity": (m, 2), "range": (lo, hi) or None, "default_opacity": bool}] */
static PyObject *tf_fields(TFObject *t, PyObject *unused)
{
    (void)unused;
    int n = lc_tf_field_count(t->tf);
    PyObject *list = PyList_New(n);
    for (int i = 0; list && i < n; i++) {
        lc_tf_field f;
        if (lc_tf_get_field(t->tf, i, &f) != LC_OK) return Py_DECREF(list), lcpy_raise(LC_ERROR_INTERNAL, NULL);
        PyObject *range = f.has_range ? Py_BuildValue("(ff)", f.range[0], f.range[1]) : Py_NewRef(Py_None);
        PyObject *d = Py_BuildValue("{s:N,s:N,s:N,s:O}", "color", points(f.color, f.ncolor, 4), "opacity",
                                    points(f.opacity, f.nopacity, 2), "range", range, "default_opacity",
                                    lc_tf_default_opacity(t->tf, i) ? Py_True : Py_False);
        if (!d) Py_CLEAR(list);
        else PyList_SET_ITEM(list, i, d);
    }
    return list;
}

static PyObject *tf_get_nfields(TFObject *t, void *c)
{
    (void)c;
    return PyLong_FromLong(lc_tf_field_count(t->tf));
}

static PyMethodDef tf_methods[] = {
    {"_preset", (PyCFunction)tf_preset, METH_VARARGS | METH_CLASS, "_preset(name, nfields, tau)"},
    {"_load", (PyCFunction)tf_load, METH_O | METH_CLASS, "_load(path)"},
    {"_parse", (PyCFunction)tf_parse, METH_VARARGS | METH_CLASS, "_parse(json, name)"},
    {"_create", (PyCFunction)tf_create, METH_O | METH_CLASS, "_create([(color, opacity, range), ...])"},
    {"_auto", (PyCFunction)tf_auto, METH_VARARGS | METH_CLASS, "_auto(volume, colormap, tau)"},
    {"fields", (PyCFunction)tf_fields, METH_NOARGS, "fields() -> a list of dicts: color (n, 4) [v, r, g, b] points, "
                                                    "opacity (m, 2) [v, tau] points, range or None."},
    {NULL, NULL, 0, NULL},
};

static PyGetSetDef tf_getset[] = {
    {"__dict__", PyObject_GenericGetDict, PyObject_GenericSetDict, NULL, NULL},
    {"nfields", (getter)tf_get_nfields, NULL, "Fields the TF classifies (1 to 8).", NULL},
    {NULL, NULL, NULL, NULL, NULL},
};

PyTypeObject lcpy_TFType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "lanecast._lanecast.TF",
    .tp_basicsize = sizeof(TFObject),
    .tp_dealloc = (destructor)tf_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE,
    .tp_doc = "The C transfer function; use lanecast.TransferFunction.",
    .tp_methods = tf_methods,
    .tp_getset = tf_getset,
    .tp_dictoffset = offsetof(TFObject, dict),
};
