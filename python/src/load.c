/* Files: lanecast.load (every format lanecast reads, with reading progress) and probe. */
#include "lcpy.h"

/* ---------------------------------------------------------------- files */

typedef struct {
    PyObject *callback;
    PyThreadState *tstate;
    int failed;
} progress_ctx;

/* Reading progress, on the loading thread (which released the GIL). */
static void load_progress(void *user, float fraction)
{
    progress_ctx *c = user;
    if (c->failed) return;
    PyGILState_STATE g = PyGILState_Ensure();
    PyObject *r = PyObject_CallFunction(c->callback, "f", fraction);
    if (!r) c->failed = 1; /* raised after the load */
    Py_XDECREF(r);
    PyGILState_Release(g);
}

static int load_desc(PyObject *format, PyObject *companion, long long frame, PyObject *options, lc_load_desc *ld,
                     lc_option *opts, PyObject *strings)
{
    if (format != Py_None && !(ld->format = PyUnicode_AsUTF8(format))) return -1;
    if (companion != Py_None) {
        PyObject *p = PyOS_FSPath(companion);
        if (!p || PyList_Append(strings, p)) return Py_XDECREF(p), -1;
        Py_DECREF(p);
        if (!(ld->companion = PyUnicode_Check(p) ? PyUnicode_AsUTF8(p) : NULL)) return -1;
    }
    if (frame < 0) return PyErr_Format(PyExc_ValueError, "frame: expected 0, 1, ... got %lld", frame), -1;
    ld->frame = frame;
    return lcpy_options(options, opts, 32, &ld->noptions, strings);
}

/* load(device, path, format, companion, frame, options, progress) */
PyObject *lcpy_load(PyObject *self, PyObject *args, PyObject *kw)
{
    (void)self;
    static char *kwlist[] = {"device", "path", "format", "companion", "frame", "options", "progress", NULL};
    PyObject *dev_o, *path_o, *format = Py_None, *companion = Py_None, *options = Py_None, *progress = Py_None;
    long long frame = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO&|OOLOO:load", kwlist, &dev_o, PyUnicode_FSConverter, &path_o,
                                     &format, &companion, &frame, &options, &progress))
        return NULL;
    DeviceObject *d = lcpy_device_or_default(dev_o);
    PyObject *strings = PyList_New(0), *result = NULL;
    lc_option opts[32];
    lc_load_desc ld = {.options = opts};
    progress_ctx pc = {progress, NULL, 0};
    if (!d || !strings || load_desc(format, companion, frame, options, &ld, opts, strings)) goto out;
    if (progress != Py_None) ld.progress = load_progress, ld.progress_user = &pc;
    const char *path = PyBytes_AS_STRING(path_o);
    lc_volume *vol = NULL;
    lc_status s;
    LCPY_UNLOCKED(d, s, lc_volume_load(d->dev, path, &ld, &vol));
    if (pc.failed || lcpy_flush_warnings(d)) {
        lc_volume_destroy(vol);
        goto out;
    }
    if (s != LC_OK) lcpy_raise(s, NULL); /* the message names the file */
    else result = lcpy_volume_wrap(vol, d, NULL);
out:
    Py_XDECREF(strings);
    Py_DECREF(path_o);
    return result;
}

/* probe(path, format=None, companion=None, options=None) -> dict */
PyObject *lcpy_probe(PyObject *self, PyObject *args, PyObject *kw)
{
    (void)self;
    static char *kwlist[] = {"path", "format", "companion", "options", NULL};
    PyObject *path_o, *format = Py_None, *companion = Py_None, *options = Py_None;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O&|OOO:probe", kwlist, PyUnicode_FSConverter, &path_o, &format,
                                     &companion, &options))
        return NULL;
    PyObject *strings = PyList_New(0), *result = NULL;
    lc_option opts[32];
    lc_load_desc ld = {.options = opts};
    if (strings && !load_desc(format, companion, 0, options, &ld, opts, strings)) {
        lc_file_info fi;
        lc_status s = lc_file_probe(NULL, PyBytes_AS_STRING(path_o), &ld, &fi);
        if (s != LC_OK) lcpy_raise(s, NULL);
        else result = Py_BuildValue("{s:s,s:s,s:L,s:O}", "format", fi.format, "kind", lc_kind_name(fi.kind), "frames",
                                    (long long)fi.frames, "gzip", fi.gzip ? Py_True : Py_False);
    }
    Py_XDECREF(strings);
    Py_DECREF(path_o);
    return result;
}
