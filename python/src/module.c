/* lanecast._lanecast: the module, its exceptions (one class per lc_status)
 * and the queries of the build (targets, formats, features, presets). */
#define LCPY_IMPORT_ARRAY
#include "lcpy.h"

static PyObject *error_base, *error_class[9];
PyObject *lcpy_Warning;

/* lc_status -1 .. -8 index error_class[1 .. 8]; unknown statuses get Error. */
PyObject *lcpy_error_class(lc_status status)
{
    int i = -(int)status;
    return i >= 1 && i <= 8 && error_class[i] ? error_class[i] : error_base;
}

PyObject *lcpy_raise(lc_status status, const char *prefix)
{
    const char *msg = lc_last_error();
    PyObject *text = prefix ? PyUnicode_FromFormat("%s: %s", prefix, msg && *msg ? msg : lc_status_string(status))
                            : PyUnicode_FromString(msg && *msg ? msg : lc_status_string(status));
    if (!text) return NULL;
    PyObject *cls = lcpy_error_class(status);
    PyObject *e = PyObject_CallOneArg(cls, text);
    Py_DECREF(text);
    if (!e) return NULL;
    PyObject *st = PyLong_FromLong((long)status);
    if (st && PyObject_SetAttrString(e, "status", st) == 0) PyErr_SetObject(cls, e);
    Py_XDECREF(st);
    Py_DECREF(e);
    return NULL;
}

int lcpy_choice(PyObject *obj, const char *what, const char *const *names, int n, int *out)
{
    const char *s = obj && PyUnicode_Check(obj) ? PyUnicode_AsUTF8(obj) : NULL;
    for (int i = 0; s && i < n; i++)
        if (names[i] && !strcmp(s, names[i])) return *out = i, 0;
    char list[256] = "";
    for (int i = 0; i < n; i++)
        if (names[i]) snprintf(list + strlen(list), sizeof list - strlen(list), "%s'%s'", *list ? ", " : "", names[i]);
    if (!s) PyErr_Format(PyExc_TypeError, "%s: expected one of %s", what, list);
    else PyErr_Format(PyExc_ValueError, "%s: '%s' is not one of %s", what, s, list);
    return -1;
}

int lcpy_options(PyObject *dict, lc_option *opts, int max, int *n, PyObject *strings)
{
    *n = 0;
    if (!dict || dict == Py_None) return 0;
    if (!PyDict_Check(dict)) return PyErr_SetString(PyExc_TypeError, "options: expected a dict"), -1;
    Py_ssize_t pos = 0;
    PyObject *k, *v;
    while (PyDict_Next(dict, &pos, &k, &v)) {
        if (*n == max) return PyErr_Format(PyExc_ValueError, "options: at most %d", max), -1;
        if (!PyUnicode_Check(k) || !PyUnicode_Check(v))
            return PyErr_SetString(PyExc_TypeError, "options: keys and values must be str"), -1;
        if (PyList_Append(strings, k) || PyList_Append(strings, v)) return -1;
        opts[*n].key = PyUnicode_AsUTF8(k);
        opts[*n].value = PyUnicode_AsUTF8(v);
        if (!opts[*n].key || !opts[*n].value) return -1;
        ++*n;
    }
    return 0;
}

/* Appends d (stolen) to *list; on failure clears *list (NULL = failed before). */
static void append(PyObject **list, PyObject *d)
{
    if (!d || !*list || PyList_Append(*list, d)) Py_CLEAR(*list);
    Py_XDECREF(d);
}

static PyObject *py_targets(PyObject *self, PyObject *unused)
{
    (void)self, (void)unused;
    PyObject *list = PyList_New(0);
    for (int t = LC_TARGET_SCALAR; list && t < LC_TARGET_COUNT; t++) {
        append(&list, Py_BuildValue("{s:s,s:i,s:O,s:O}", "name", lc_target_name((lc_target)t), "lanes",
                                    lc_target_lanes((lc_target)t), "compiled",
                                    lc_target_compiled((lc_target)t) ? Py_True : Py_False, "supported",
                                    lc_target_supported((lc_target)t) ? Py_True : Py_False));
    }
    return list;
}

static PyObject *py_formats(PyObject *self, PyObject *unused)
{
    (void)self, (void)unused;
    PyObject *list = PyList_New(0);
    for (int i = 0; list && i < lc_format_count(); i++) {
        lc_format_info f;
        if (lc_format_get(i, &f) != LC_OK) return Py_DECREF(list), lcpy_raise(LC_ERROR_INTERNAL, NULL);
        append(&list, Py_BuildValue("{s:s,s:s,s:s,s:s,s:s,s:O,s:s}", "name", f.name, "kind", lc_kind_name(f.kind),
                                    "extensions", f.extensions, "options", f.options, "description", f.description,
                                    "available", f.available ? Py_True : Py_False, "package", f.package));
    }
    return list;
}

static PyObject *py_features(PyObject *self, PyObject *unused)
{
    (void)self, (void)unused;
    PyObject *list = PyList_New(0);
    for (int i = 0; list && i < lc_feature_count(); i++) {
        lc_feature_info f;
        if (lc_feature_get(i, &f) != LC_OK) return Py_DECREF(list), lcpy_raise(LC_ERROR_INTERNAL, NULL);
        append(&list, Py_BuildValue("{s:s,s:s,s:O,s:s,s:s}", "name", f.name, "library", f.library, "available",
                                    f.available ? Py_True : Py_False, "package", f.package, "description",
                                    f.description));
    }
    return list;
}

static PyObject *py_presets(PyObject *self, PyObject *unused)
{
    (void)self, (void)unused;
    PyObject *list = PyList_New(0);
    for (int i = 0; list && lc_tf_preset_name(i); i++) append(&list, PyUnicode_FromString(lc_tf_preset_name(i)));
    return list;
}

static PyObject *py_select_check(PyObject *self, PyObject *arg)
{
    (void)self;
    const char *e = PyUnicode_AsUTF8(arg);
    if (!e) return NULL;
    lc_status s = lc_select_check(e);
    if (s != LC_OK) return lcpy_raise(s, "select");
    Py_RETURN_NONE;
}

/* camera_frame(bounds ((lo), (hi)), azimuth, elevation) -> (eye, at, up) */
static PyObject *py_camera_frame(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *lo, *hi;
    float az, el;
    if (!PyArg_ParseTuple(args, "(OO)ff:camera_frame", &lo, &hi, &az, &el)) return NULL;
    lc_box3 b;
    if (lcpy_vec3(lo, "bounds", &b.lo) || lcpy_vec3(hi, "bounds", &b.hi)) return NULL;
    lc_camera cam = {0};
    lc_status s = lc_camera_frame(&b, az, el, &cam);
    if (s != LC_OK) return lcpy_raise(s, "Camera.frame");
    return Py_BuildValue("(fff)(fff)(fff)", cam.eye.x, cam.eye.y, cam.eye.z, cam.at.x, cam.at.y, cam.at.z, cam.up.x,
                         cam.up.y, cam.up.z);
}

static PyMethodDef methods[] = {
    {"targets", py_targets, METH_NOARGS, "targets() -> list of dicts: every SIMD target (name, lanes, compiled, supported)."},
    {"formats", py_formats, METH_NOARGS, "formats() -> list of dicts: every file format of this build."},
    {"features", py_features, METH_NOARGS, "features() -> list of dicts: the optional libraries of this build."},
    {"presets", py_presets, METH_NOARGS, "presets() -> the names of the built-in colour maps."},
    {"select_check", py_select_check, METH_O, "select_check(expr): raises InvalidArgumentError for a bad selection."},
    {"camera_frame", py_camera_frame, METH_VARARGS, "camera_frame(bounds, azimuth, elevation) -> (eye, at, up)."},
    {"render", (PyCFunction)(void (*)(void))lcpy_render, METH_VARARGS | METH_KEYWORDS, "The C render call (lanecast.render wraps it)."},
    {"image_write", (PyCFunction)(void (*)(void))lcpy_image_write, METH_VARARGS | METH_KEYWORDS, "image_write(device, path, rgba, background, alpha)."},
    {"load", (PyCFunction)(void (*)(void))lcpy_load, METH_VARARGS | METH_KEYWORDS, "The C load call (lanecast.load wraps it)."},
    {"probe", (PyCFunction)(void (*)(void))lcpy_probe, METH_VARARGS | METH_KEYWORDS, "probe(path, format=None) -> dict."},
    {"encode", (PyCFunction)(void (*)(void))lcpy_encode, METH_VARARGS | METH_KEYWORDS, "The C encode call (lanecast.encode wraps it)."},
    {"rbf_write", (PyCFunction)(void (*)(void))lcpy_rbf_write, METH_VARARGS | METH_KEYWORDS, "rbf_write(device, path, centres, widths, weights, bias, text)."},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "lanecast._lanecast",
                                    "lanecast's C API for Python; use the package lanecast.", -1, methods,
                                    NULL, NULL, NULL, NULL};

static int add_errors(PyObject *m)
{
    error_base = PyErr_NewExceptionWithDoc("lanecast.Error", "Every error of lanecast (its .status is the lc_status).",
                                           PyExc_Exception, NULL);
    if (!error_base || PyModule_AddObjectRef(m, "Error", error_base)) return -1;
    static const struct {
        lc_status status;
        const char *name;
        PyObject **also;
        const char *doc;
    } rows[] = {
        {LC_ERROR_INVALID_ARGUMENT, "InvalidArgumentError", &PyExc_ValueError, "A bad argument (LC_ERROR_INVALID_ARGUMENT)."},
        {LC_ERROR_UNSUPPORTED, "UnsupportedError", &PyExc_NotImplementedError,
         "The CPU or this build lacks what was asked for (LC_ERROR_UNSUPPORTED)."},
        {LC_ERROR_OUT_OF_MEMORY, "OutOfMemoryError", &PyExc_MemoryError, "LC_ERROR_OUT_OF_MEMORY."},
        {LC_ERROR_IO, "FileError", &PyExc_OSError, "A file could not be opened, read or written (LC_ERROR_IO)."},
        {LC_ERROR_FORMAT, "FormatError", &PyExc_ValueError, "A file's content is malformed (LC_ERROR_FORMAT)."},
        {LC_ERROR_INTERNAL, "InternalError", &PyExc_RuntimeError, "A bug in lanecast (LC_ERROR_INTERNAL)."},
        {LC_CANCELLED, "CancelledError", NULL, "A render was cancelled (LC_CANCELLED)."},
        {LC_TIMEOUT, "TimeoutError", &PyExc_TimeoutError, "A wait ended before the job (LC_TIMEOUT)."},
    };
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++) {
        PyObject *bases = rows[i].also ? PyTuple_Pack(2, error_base, *rows[i].also) : PyTuple_Pack(1, error_base);
        char full[64];
        snprintf(full, sizeof full, "lanecast.%s", rows[i].name);
        PyObject *cls = bases ? PyErr_NewExceptionWithDoc(full, rows[i].doc, bases, NULL) : NULL;
        Py_XDECREF(bases);
        if (!cls || PyModule_AddObjectRef(m, rows[i].name, cls)) return -1;
        error_class[-(int)rows[i].status] = cls;
    }
    lcpy_Warning = PyErr_NewExceptionWithDoc("lanecast.Warning", "Warnings of the library's log (e.g. a loader's).",
                                             PyExc_UserWarning, NULL);
    return lcpy_Warning ? PyModule_AddObjectRef(m, "Warning", lcpy_Warning) : -1;
}

PyMODINIT_FUNC PyInit__lanecast(void)
{
    import_array();
    PyObject *m = PyModule_Create(&module);
    if (!m) return NULL;
    PyTypeObject *types[] = {&lcpy_DeviceType, &lcpy_VolumeType, &lcpy_ParticlesType, &lcpy_GridType,
                             &lcpy_RBFSetType, &lcpy_TFType};
    const char *names[] = {"Device", "Volume", "Particles", "Grid", "RBFSet", "TF"};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (PyType_Ready(types[i]) < 0 || PyModule_AddObjectRef(m, names[i], (PyObject *)types[i])) goto fail;
    if (add_errors(m)) goto fail;
    if (PyModule_AddStringConstant(m, "version", lc_version_string()) ||
        PyModule_AddIntConstant(m, "MAX_FIELDS", LC_MAX_FIELDS) ||
        PyModule_AddIntConstant(m, "MAX_PLANES", LC_MAX_PLANES))
        goto fail;
    return m;
fail:
    Py_DECREF(m);
    return NULL;
}
