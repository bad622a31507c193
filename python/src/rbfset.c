/* lanecast.RBFSet: RBF sets from arrays (Jang et al. 2004) and their .rbf files. */
#include "lcpy.h"

/* ---------------------------------------------------------------- RBF sets */

static PyObject *rbf_new(PyTypeObject *type, PyObject *args, PyObject *kw)
{
    (void)type;
    static char *kwlist[] = {"device", "centres", "widths", "weights", "bias", "eps", "domain", "leaf_size",
                             "accel", "cell_max", "significant", NULL};
    PyObject *dev_o, *c_o, *w_o, *wt_o, *dom_o = Py_None, *acc_o = Py_None;
    float bias = 0.0f, eps = 0.0f;
    int leaf = 0, cell = 0, sig = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OOOO|f$fOiOip:RBFSet", kwlist, &dev_o, &c_o, &w_o, &wt_o, &bias, &eps,
                                     &dom_o, &leaf, &acc_o, &cell, &sig))
        return NULL;
    DeviceObject *d = lcpy_device_or_default(dev_o);
    if (!d) return NULL;
    lc_rbf_desc rd = {.bias = bias, .eps = eps, .leaf_size = leaf, .cell_max = cell, .significant = sig};
    static const char *const accels[] = {"default", "bvh", "octree", "coherent"};
    int acc = 0;
    if (acc_o != Py_None && lcpy_choice(acc_o, "accel", accels, 4, &acc)) return NULL;
    rd.accel = (lc_rbf_accel)acc;
    if (dom_o != Py_None) {
        PyObject *lo, *hi;
        if (!PyArg_ParseTuple(dom_o, "OO;domain: expected ((x0, y0, z0), (x1, y1, z1))", &lo, &hi) ||
            lcpy_vec3(lo, "domain", &rd.domain.lo) || lcpy_vec3(hi, "domain", &rd.domain.hi))
            return NULL;
    }
    PyArrayObject *a[3] = {NULL, NULL, NULL};
    static const char *const names[] = {"centres", "widths", "weights"};
    PyObject *result = NULL;
    int copied;
    if (!(a[0] = lcpy_array(c_o, "centres", NPY_FLOAT32, "fiu", 2, 3, LCPY_COPY_NEEDED, &copied)) ||
        !(a[1] = lcpy_array(w_o, "widths", NPY_FLOAT32, "fiu", 1, -1, LCPY_COPY_NEEDED, &copied)) ||
        !(a[2] = lcpy_array(wt_o, "weights", NPY_FLOAT32, "fiu", 1, -1, LCPY_COPY_NEEDED, &copied)))
        goto out;
    npy_intp n = PyArray_DIM(a[0], 0);
    for (int i = 1; i < 3; i++)
        if (PyArray_DIM(a[i], 0) != n) {
            PyErr_Format(PyExc_ValueError, "%s: expected %lld values (one per centre), got %lld", names[i],
                         (long long)n, (long long)PyArray_DIM(a[i], 0));
            goto out;
        }
    rd.count = (size_t)n;
    rd.centres = PyArray_DATA(a[0]);
    rd.widths = PyArray_DATA(a[1]);
    rd.weights = PyArray_DATA(a[2]);
    lc_volume *vol = NULL;
    lc_status s;
    LCPY_UNLOCKED(d, s, lc_rbf_create(d->dev, &rd, &vol));
    if (lcpy_flush_warnings(d)) lc_volume_destroy(vol);
    else if (s != LC_OK) lcpy_raise(s, lcpy_nonfinite_arg(a, names, 3));
    else if ((result = lcpy_volume_wrap(vol, d, NULL))) {
        /* the arrays as given (float32), for save() */
        PyObject *arrays = Py_BuildValue("(OOOf)", a[0], a[1], a[2], bias);
        if (!arrays || PyObject_SetAttrString(result, "_arrays", arrays)) Py_CLEAR(result);
        Py_XDECREF(arrays);
    }
out:
    for (int i = 0; i < 3; i++) Py_XDECREF(a[i]);
    return result;
}

/* save(path, text=False): the set as a .rbf file (docs/FORMATS-rbf.md) */
static PyObject *rbf_save(VolumeObject *v, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"path", "text", NULL};
    PyObject *path;
    int text = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O|p:save", kwlist, &path, &text)) return NULL;
    PyObject *arrays = v->dict ? PyDict_GetItemString(v->dict, "_arrays") : NULL;
    if (!arrays)
        return PyErr_Format(PyExc_ValueError, "save: only sets made from arrays (RBFSet, encode) can be saved; "
                            "this one was read from a file");
    PyObject *a = Py_BuildValue("(OO)", (PyObject *)v->device, path), *k = Py_BuildValue("{s:O}", "text", text ? Py_True : Py_False);
    PyObject *full = a ? PySequence_Concat(a, arrays) : NULL, *r = NULL;
    if (full && k) r = lcpy_rbf_write(NULL, full, k);
    Py_XDECREF(a);
    Py_XDECREF(k);
    Py_XDECREF(full);
    return r;
}

static PyMethodDef rbf_methods[] = {
    {"save", (PyCFunction)(void (*)(void))rbf_save, METH_VARARGS | METH_KEYWORDS,
     "save(path, text=False): writes the set as a .rbf file (binary, or text with text=True)."},
    {NULL, NULL, 0, NULL},
};

PyTypeObject lcpy_RBFSetType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "lanecast.RBFSet",
    .tp_basicsize = sizeof(VolumeObject),
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_HAVE_GC,
    .tp_doc = "RBFSet(device, centres, widths, weights, bias=0.0, *, eps=0.0, domain=None, leaf_size=0,\n"
              "       accel=None, cell_max=0, significant=False)\n\n"
              "An RBF-encoded volume (Jang et al. 2004): f(x) = bias + sum w_i exp(-|x - mu_i|^2 / (2 s_i^2)),\n"
              "centres (N, 3), widths (N,), weights (N,); copied by the library. accel: 'default',\n"
              "'coherent', 'bvh' or 'octree'; domain ((x0, y0, z0), (x1, y1, z1)) bounds where rays sample.",
    .tp_traverse = (traverseproc)lcpy_volume_traverse,
    .tp_clear = (inquiry)lcpy_volume_clear,
    .tp_methods = rbf_methods,
    .tp_base = &lcpy_VolumeType,
    .tp_new = rbf_new,
};

