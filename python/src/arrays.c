/* Array arguments: the one conversion every array goes through (lcpy.h).
 * Zero-copy when the caller's array already has the layout a C call reads
 * (C-contiguous, aligned, native byte order, the right dtype); otherwise one
 * converted copy, or ValueError for copy=False. */
#include <math.h>
#include <string.h>
#include "lcpy.h"

int lcpy_copy_arg(PyObject *obj, lcpy_copy *out)
{
    if (!obj || obj == Py_None) return *out = LCPY_COPY_NEEDED, 0;
    if (obj == Py_True) return *out = LCPY_COPY_ALWAYS, 0;
    if (obj == Py_False) return *out = LCPY_COPY_NEVER, 0;
    PyErr_SetString(PyExc_TypeError, "copy: expected None (copy only when needed), False (never) or True (always)");
    return -1;
}

static void shape_text(PyArrayObject *a, char *buf, size_t n)
{
    size_t k = (size_t)snprintf(buf, n, "(");
    for (int i = 0; i < PyArray_NDIM(a) && k < n; i++)
        k += (size_t)snprintf(buf + k, n - k, "%s%lld", i ? ", " : "", (long long)PyArray_DIM(a, i));
    if (k < n) snprintf(buf + k, n - k, "%s)", PyArray_NDIM(a) == 1 ? "," : "");
}

/* Why a conversion is needed, or NULL when the array can be used as is. */
static const char *conversion_reason(PyArrayObject *a, int typenum, int from_sequence)
{
    if (from_sequence) return "it is not a NumPy array";
    if (PyArray_TYPE(a) != typenum) return "its dtype differs";
    if (!PyArray_ISNOTSWAPPED(a)) return "its byte order is not the machine's";
    if (!PyArray_IS_C_CONTIGUOUS(a)) return "it is not C-contiguous";
    if (!PyArray_ISALIGNED(a)) return "it is not aligned";
    return NULL;
}

PyArrayObject *lcpy_array(PyObject *obj, const char *name, int typenum, const char *kinds, int ndim, npy_intp cols,
                          lcpy_copy copy, int *copied)
{
    int from_sequence = !PyArray_Check(obj);
    PyArrayObject *a;
    if (from_sequence) {
        a = (PyArrayObject *)PyArray_FromAny(obj, NULL, 0, 0, 0, NULL);
        if (!a) {
            PyErr_Clear();
            return PyErr_Format(PyExc_TypeError, "%s: expected an array of numbers, got %.100s", name,
                                Py_TYPE(obj)->tp_name),
                   NULL;
        }
    } else {
        a = (PyArrayObject *)obj;
        Py_INCREF(a);
    }
    char kind = PyArray_DESCR(a)->kind;
    if (!strchr(kinds, kind) || PyArray_DESCR(a)->type_num == NPY_BOOL) {
        PyObject *d = PyObject_Str((PyObject *)PyArray_DESCR(a));
        PyErr_Format(PyExc_TypeError, "%s: expected %s, got dtype %s", name,
                     strchr(kinds, 'f') ? "numbers (a float or integer dtype)" : "integers (an integer dtype)",
                     d ? PyUnicode_AsUTF8(d) : "?");
        Py_XDECREF(d);
        Py_DECREF(a);
        return NULL;
    }
    int ok = PyArray_NDIM(a) == ndim && (cols < 0 || PyArray_DIM(a, ndim - 1) == cols);
    if (!ok) {
        char got[128];
        shape_text(a, got, sizeof got);
        if (ndim == 3 && cols > 0)
            PyErr_Format(PyExc_ValueError, "%s: expected an array of shape (H, W, %lld), got shape %s", name,
                         (long long)cols, got);
        else if (ndim == 2) PyErr_Format(PyExc_ValueError, "%s: expected an array of shape (N, %lld), got shape %s", name,
                                    (long long)cols, got);
        else if (ndim == 1) PyErr_Format(PyExc_ValueError, "%s: expected an array of shape (N,), got shape %s", name, got);
        else PyErr_Format(PyExc_ValueError, "%s: expected a %d-D array, got shape %s", name, ndim, got);
        Py_DECREF(a);
        return NULL;
    }
    const char *why = conversion_reason(a, typenum, from_sequence);
    if (!why && copy != LCPY_COPY_ALWAYS) return *copied = 0, a;
    if (why && copy == LCPY_COPY_NEVER) {
        PyObject *want = PyObject_Str((PyObject *)PyArray_DescrFromType(typenum));
        PyErr_Format(PyExc_ValueError,
                     "%s: copy=False, but the array would have to be copied (%s): pass a C-contiguous %s array "
                     "in the machine's byte order, or copy=None",
                     name, why, want ? PyUnicode_AsUTF8(want) : "?");
        Py_XDECREF(want);
        Py_DECREF(a);
        return NULL;
    }
    PyArrayObject *c = (PyArrayObject *)PyArray_FromArray(
        a, PyArray_DescrFromType(typenum),
        NPY_ARRAY_C_CONTIGUOUS | NPY_ARRAY_ALIGNED | NPY_ARRAY_FORCECAST | NPY_ARRAY_ENSURECOPY);
    Py_DECREF(a);
    if (!c) return NULL;
    *copied = 1;
    return c;
}

npy_intp lcpy_first_nonfinite(PyArrayObject *a)
{
    if (PyArray_TYPE(a) != NPY_FLOAT32) return -1;
    const float *p = PyArray_DATA(a);
    npy_intp n = PyArray_SIZE(a);
    for (npy_intp i = 0; i < n; i++)
        if (!isfinite(p[i])) return i;
    return -1;
}

/* Names the array holding the first non-finite value, for the library's
 * message (which names the particle). */
const char *lcpy_nonfinite_arg(PyArrayObject **arrays, const char *const *names, int n)
{
    for (int i = 0; i < n; i++)
        if (arrays[i] && lcpy_first_nonfinite(arrays[i]) >= 0) return names[i];
    return NULL;
}

int lcpy_vec3(PyObject *obj, const char *name, lc_vec3 *out)
{
    PyObject *seq = PySequence_Fast(obj, "");
    if (!seq || PySequence_Fast_GET_SIZE(seq) != 3) {
        Py_XDECREF(seq);
        PyErr_Format(PyExc_ValueError, "%s: expected three numbers (x, y, z)", name);
        return -1;
    }
    float v[3];
    for (int i = 0; i < 3; i++) {
        double x = PyFloat_AsDouble(PySequence_Fast_GET_ITEM(seq, i));
        if (x == -1.0 && PyErr_Occurred()) {
            PyErr_Clear();
            Py_DECREF(seq);
            PyErr_Format(PyExc_TypeError, "%s: expected three numbers (x, y, z)", name);
            return -1;
        }
        if (!isfinite(x) || fabs(x) > 3.4e38) {
            Py_DECREF(seq);
            PyErr_Format(PyExc_ValueError, "%s: expected three finite numbers, got %g as %c", name, x, "xyz"[i]);
            return -1;
        }
        v[i] = (float)x;
    }
    Py_DECREF(seq);
    out->x = v[0], out->y = v[1], out->z = v[2];
    return 0;
}

/* perm[j] = the array axis holding lanecast axis "zyx"[j]; -1 for a bad order. */
static int order_perm(const char *order, int perm[3])
{
    if (!order || strlen(order) != 3) return -1;
    for (int j = 0; j < 3; j++) {
        const char *p = strchr(order, "zyx"[j]);
        if (!p) return -1;
        perm[j] = (int)(p - order);
    }
    return 0;
}

int lcpy_grid_array(PyObject *obj, const char *name, const char *order, lcpy_copy copy, lc_grid_desc *d,
                    PyArrayObject **buffer, int *copied)
{
    int perm[3];
    if (order_perm(order, perm)) {
        PyErr_Format(PyExc_ValueError, "order: expected the axes of the array as a permutation of 'xyz' "
                     "(\"zyx\": axis 0 is z, NumPy's C order of an x-fastest volume), got '%s'", order ? order : "");
        return -1;
    }
    PyArrayObject *a;
    int from_sequence = !PyArray_Check(obj);
    if (!from_sequence) a = (PyArrayObject *)obj, Py_INCREF(a);
    else if (copy == LCPY_COPY_NEVER) {
        PyErr_Format(PyExc_ValueError, "%s: copy=False, but a %.100s would have to be copied into an array", name,
                     Py_TYPE(obj)->tp_name);
        return -1;
    } else if (!(a = (PyArrayObject *)PyArray_FromAny(obj, NULL, 0, 0, 0, NULL))) {
        PyErr_Clear();
        PyErr_Format(PyExc_TypeError, "%s: expected a 3-D array of numbers, got %.100s", name, Py_TYPE(obj)->tp_name);
        return -1;
    }
    if (PyArray_NDIM(a) != 3) {
        char got[128];
        shape_text(a, got, sizeof got);
        PyErr_Format(PyExc_ValueError, "%s: expected a 3-D array, got shape %s", name, got);
        Py_DECREF(a);
        return -1;
    }
    PyArray_Dims pd = {(npy_intp[]){perm[0], perm[1], perm[2]}, 3};
    PyArrayObject *t = (PyArrayObject *)PyArray_Transpose(a, &pd); /* a view with axes (z, y, x) */
    if (!t) return Py_DECREF(a), -1;
    int typenum;
    switch (PyArray_TYPE(a)) {
    case NPY_UINT8: typenum = NPY_UINT8, d->type = LC_VALUE_UINT8; break;
    case NPY_UINT16: typenum = NPY_UINT16, d->type = LC_VALUE_UINT16; break;
    case NPY_INT16: typenum = NPY_INT16, d->type = LC_VALUE_INT16; break;
    default: typenum = NPY_FLOAT32, d->type = LC_VALUE_FLOAT32; break;
    }
    Py_DECREF(a);
    PyArrayObject *b = lcpy_array((PyObject *)t, name, typenum, "fiu", 3, -1, copy, copied);
    Py_DECREF(t);
    if (!b) return -1;
    *copied |= from_sequence;
    for (int k = 0; k < 3; k++) {
        npy_intp n = PyArray_DIM(b, 2 - k);
        if (n < 2 || n > (1 << 24)) {
            PyErr_Format(PyExc_ValueError, "%s: the %c axis has %lld nodes; a grid needs 2 to 2^24 on every axis", name,
                         "xyz"[k], (long long)n);
            Py_DECREF(b);
            return -1;
        }
        d->size[k] = (int)n;
    }
    d->data = PyArray_DATA(b);
    *buffer = b;
    return 0;
}
