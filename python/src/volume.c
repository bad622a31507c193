/* lanecast.Volume and its kinds Particles, Grid and RBFSet: creation from
 * arrays, loading from files, info, sampling and per-kind parameters. */
#include <math.h>
#include <string.h>
#include "lcpy.h"

/* ---------------------------------------------------------------- the base type */

PyObject *lcpy_volume_wrap(lc_volume *vol, DeviceObject *d, PyObject *keep)
{
    lc_kind k = lc_volume_kind(vol);
    PyTypeObject *t = k == LC_KIND_PARTICLES ? &lcpy_ParticlesType
                      : k == LC_KIND_GRID    ? &lcpy_GridType
                      : k == LC_KIND_RBF     ? &lcpy_RBFSetType
                                             : &lcpy_VolumeType;
    VolumeObject *v = (VolumeObject *)t->tp_alloc(t, 0);
    if (!v) return lc_volume_destroy(vol), NULL;
    v->vol = vol;
    v->device = d;
    Py_INCREF(d);
    v->keep = keep;
    Py_XINCREF(keep);
    return (PyObject *)v;
}

VolumeObject *lcpy_volume_arg(PyObject *obj, const char *name)
{
    if (!PyObject_TypeCheck(obj, &lcpy_VolumeType)) {
        PyErr_Format(PyExc_TypeError, "%s: expected a lanecast volume (Particles, Grid, RBFSet or load()), got %.100s",
                     name, Py_TYPE(obj)->tp_name);
        return NULL;
    }
    VolumeObject *v = (VolumeObject *)obj;
    if (!v->vol) {
        PyErr_Format(PyExc_ValueError, "%s: the volume was closed", name);
        return NULL;
    }
    return v;
}

static void volume_dealloc(VolumeObject *v)
{
    PyObject_GC_UnTrack(v);
    lc_volume_destroy(v->vol);
    Py_CLEAR(v->keep);
    Py_CLEAR(v->dict);
    Py_CLEAR(v->device);
    Py_TYPE(v)->tp_free((PyObject *)v);
}

int lcpy_volume_traverse(VolumeObject *v, visitproc visit, void *arg)
{
    Py_VISIT(v->keep);
    Py_VISIT(v->dict);
    Py_VISIT(v->device);
    return 0;
}

int lcpy_volume_clear(VolumeObject *v)
{
    Py_CLEAR(v->dict); /* the C volume and what it borrows go only with the object */
    return 0;
}

static PyObject *volume_close(VolumeObject *v, PyObject *unused)
{
    (void)unused;
    if (v->busy) return PyErr_Format(PyExc_RuntimeError, "close: the volume is being rendered");
    lc_volume_destroy(v->vol);
    v->vol = NULL;
    Py_CLEAR(v->keep);
    Py_RETURN_NONE;
}

static PyObject *box(const lc_box3 *b)
{
    return Py_BuildValue("((fff)(fff))", b->lo.x, b->lo.y, b->lo.z, b->hi.x, b->hi.y, b->hi.z);
}

/* Adds key = value (stealing value); -1 on error. */
static int put(PyObject *d, const char *key, PyObject *value)
{
    int r = value ? PyDict_SetItemString(d, key, value) : -1;
    Py_XDECREF(value);
    return r;
}

static int kind_info(const lc_volume *vol, PyObject *d)
{
    lc_kind k = lc_volume_kind(vol);
    if (k == LC_KIND_PARTICLES) {
        lc_particles_info p;
        if (lc_particles_get_info(vol, &p) != LC_OK) return lcpy_raise(LC_ERROR_INTERNAL, "info"), -1;
        return put(d, "count", PyLong_FromSize_t(p.count)) || put(d, "dropped", PyLong_FromSize_t(p.dropped)) ||
               put(d, "centre_bounds", box(&p.bounds)) ||
               put(d, "radius", Py_BuildValue("(ff)", p.min_radius, p.max_radius)) ||
               put(d, "build_seconds", PyFloat_FromDouble(p.build_seconds)) ||
               put(d, "bvh_bytes", PyLong_FromSize_t(p.bvh_bytes)) ||
               put(d, "data_bytes", PyLong_FromSize_t(p.data_bytes)) ||
               put(d, "bvh_nodes", PyLong_FromLong(p.bvh_nodes)) || put(d, "bvh_depth", PyLong_FromLong(p.bvh_depth)) ||
               put(d, "leaf_size", PyLong_FromLong(p.leaf_size)) ||
               put(d, "params", Py_BuildValue("{s:f,s:f,s:i,s:f}", "sigma", p.params.sigma, "kappa", p.params.kappa,
                                              "buffer_samples", p.params.buffer_samples, "sphere_scale",
                                              p.params.sphere_scale));
    }
    if (k == LC_KIND_GRID) {
        static const char *types[] = {"default", "uint8", "uint16", "int16", "float32"};
        static const char *layouts[] = {"default", "linear", "bricked"};
        lc_grid_info g;
        if (lc_grid_get_info(vol, &g) != LC_OK) return lcpy_raise(LC_ERROR_INTERNAL, "info"), -1;
        return put(d, "size", Py_BuildValue("(iii)", g.size[0], g.size[1], g.size[2])) ||
               put(d, "type", PyUnicode_FromString(types[g.type <= 4 ? g.type : 0])) ||
               put(d, "spacing", Py_BuildValue("(fff)", g.spacing.x, g.spacing.y, g.spacing.z)) ||
               put(d, "origin", Py_BuildValue("(fff)", g.origin.x, g.origin.y, g.origin.z)) ||
               put(d, "values", Py_BuildValue("(ff)", g.value_min, g.value_max)) ||
               put(d, "layout", PyUnicode_FromString(layouts[g.layout <= 2 ? g.layout : 0])) ||
               put(d, "borrowed", PyBool_FromLong(g.borrowed)) ||
               put(d, "data_bytes", PyLong_FromUnsignedLongLong(g.data_bytes)) ||
               put(d, "layout_bytes", PyLong_FromUnsignedLongLong(g.layout_bytes)) ||
               put(d, "brick", PyLong_FromLong(g.brick)) ||
               put(d, "bvh_nodes", PyLong_FromUnsignedLongLong(g.bvh_nodes)) ||
               put(d, "bvh_depth", PyLong_FromLong(g.bvh_depth)) ||
               put(d, "build_seconds", PyFloat_FromDouble(g.bvh_build_seconds)) ||
               put(d, "params", Py_BuildValue("{s:O,s:f,s:f,s:f,s:f}", "preintegrated",
                                              g.params.preintegrated ? Py_True : Py_False, "rda", g.params.rda,
                                              "delta_c", g.params.delta_c, "delta_p", g.params.delta_p, "delta_sv",
                                              g.params.delta_sv));
    }
    if (k == LC_KIND_RBF) {
        static const char *accels[] = {"default", "bvh", "octree", "coherent"};
        lc_rbf_info r;
        if (lc_rbf_get_info(vol, &r) != LC_OK) return lcpy_raise(LC_ERROR_INTERNAL, "info"), -1;
        return put(d, "count", PyLong_FromSize_t(r.count)) || put(d, "dropped", PyLong_FromSize_t(r.dropped)) ||
               put(d, "bias", PyFloat_FromDouble(r.bias)) || put(d, "eps", PyFloat_FromDouble(r.eps)) ||
               put(d, "support_bounds", box(&r.support_bounds)) ||
               put(d, "width", Py_BuildValue("(ff)", r.min_width, r.max_width)) ||
               put(d, "max_support", PyFloat_FromDouble(r.max_support)) ||
               put(d, "build_seconds", PyFloat_FromDouble(r.build_seconds)) ||
               put(d, "bvh_nodes", PyLong_FromLong(r.bvh_nodes)) ||
               put(d, "accel", PyUnicode_FromString(accels[r.accel <= 3 ? r.accel : 0])) ||
               put(d, "octree_cells", PyLong_FromLong(r.octree_cells));
    }
    return 0;
}

static PyObject *volume_get_info(VolumeObject *v, void *c)
{
    (void)c;
    if (!lcpy_volume_arg((PyObject *)v, "info")) return NULL;
    lc_volume_info vi;
    lc_status s = lc_volume_get_info(v->vol, &vi);
    if (s != LC_OK) return lcpy_raise(s, "info");
    PyObject *d = Py_BuildValue("{s:s,s:N,s:i,s:(ff)}", "kind", lc_kind_name(vi.kind), "bounds", box(&vi.bounds),
                                "nfields", vi.nfields, "range", vi.range[0], vi.range[1]);
    if (d && kind_info(v->vol, d)) Py_CLEAR(d);
    return d;
}

static PyObject *volume_get_kind(VolumeObject *v, void *c)
{
    (void)c;
    return PyUnicode_FromString(v->vol ? lc_kind_name(lc_volume_kind(v->vol)) : "closed");
}

static PyObject *volume_get_device(VolumeObject *v, void *c)
{
    (void)c;
    return Py_NewRef((PyObject *)v->device);
}

static PyObject *volume_get_borrowed(VolumeObject *v, void *c)
{
    (void)c;
    return v->keep ? Py_NewRef(v->keep) : PyTuple_New(0);
}

/* sample(points, gradients=False) -> values (N, nfields) [, gradients (N, nfields, 3)] */
static PyObject *volume_sample(VolumeObject *v, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"points", "gradients", NULL};
    PyObject *pts;
    int want_grad = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "O|p:sample", kwlist, &pts, &want_grad)) return NULL;
    if (!lcpy_volume_arg((PyObject *)v, "sample")) return NULL;
    int copied;
    PyArrayObject *p = lcpy_array(pts, "points", NPY_FLOAT32, "fiu", 2, 3, LCPY_COPY_NEEDED, &copied);
    if (!p) return NULL;
    lc_volume_info vi;
    lc_volume_get_info(v->vol, &vi);
    npy_intp n = PyArray_DIM(p, 0);
    npy_intp vdims[2] = {n, vi.nfields}, gdims[3] = {n, vi.nfields, 3};
    PyArrayObject *val = (PyArrayObject *)PyArray_SimpleNew(2, vdims, NPY_FLOAT32);
    PyArrayObject *grad = want_grad ? (PyArrayObject *)PyArray_SimpleNew(3, gdims, NPY_FLOAT32) : NULL;
    lc_status s = LC_ERROR_OUT_OF_MEMORY;
    if (val && (grad || !want_grad)) {
        DeviceObject *d = v->device;
        Py_BEGIN_ALLOW_THREADS
        lcpy_lock(d);
        s = n ? lc_volume_sample(d->dev, v->vol, (size_t)n, PyArray_DATA(p), PyArray_DATA(val),
                                 grad ? PyArray_DATA(grad) : NULL)
              : LC_OK;
        lcpy_unlock(d);
        Py_END_ALLOW_THREADS
    }
    Py_DECREF(p);
    if (s != LC_OK) {
        Py_XDECREF(val);
        Py_XDECREF(grad);
        return PyErr_Occurred() ? NULL : lcpy_raise(s, "sample");
    }
    if (!want_grad) return (PyObject *)val;
    return Py_BuildValue("NN", val, grad);
}

static PyMethodDef volume_methods[] = {
    {"sample", (PyCFunction)(void (*)(void))volume_sample, METH_VARARGS | METH_KEYWORDS,
     "sample(points, gradients=False) -> values of shape (N, nfields) [and gradients (N, nfields, 3)]\n"
     "at points of shape (N, 3) (x, y, z), with the volume's current parameters."},
    {"close", (PyCFunction)volume_close, METH_NOARGS, "Frees the volume now (it also goes with the object)."},
    {NULL, NULL, 0, NULL},
};

static PyGetSetDef volume_getset[] = {
    {"info", (getter)volume_get_info, NULL, "A dict: kind, bounds, nfields, range and the kind's own figures "
                                            "(as `lanecast info`).", NULL},
    {"kind", (getter)volume_get_kind, NULL, "'particles', 'grid' or 'rbf'.", NULL},
    {"device", (getter)volume_get_device, NULL, "The device the volume was made on.", NULL},
    {"__dict__", PyObject_GenericGetDict, PyObject_GenericSetDict, NULL, NULL},
    {"borrowed", (getter)volume_get_borrowed, NULL, "The arrays the volume uses in place (kept alive by it).", NULL},
    {NULL, NULL, NULL, NULL, NULL},
};

PyTypeObject lcpy_VolumeType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "lanecast.Volume",
    .tp_basicsize = sizeof(VolumeObject),
    .tp_dealloc = (destructor)volume_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_BASETYPE | Py_TPFLAGS_HAVE_GC,
    .tp_doc = "Data lanecast renders: Particles, Grid, RBFSet, or what load() reads.",
    .tp_traverse = (traverseproc)lcpy_volume_traverse,
    .tp_clear = (inquiry)lcpy_volume_clear,
    .tp_methods = volume_methods,
    .tp_getset = volume_getset,
    .tp_dictoffset = offsetof(VolumeObject, dict),
};


/* A float keyword: 1 = given (into *out), 0 = absent/None, -1 error. */
static int opt_float(PyObject *obj, const char *name, float *out)
{
    if (!obj || obj == Py_None) return 0;
    double x = PyFloat_AsDouble(obj);
    if (x == -1.0 && PyErr_Occurred()) {
        PyErr_Clear();
        PyErr_Format(PyExc_TypeError, "%s: expected a number, got %.100s", name, Py_TYPE(obj)->tp_name);
        return -1;
    }
    *out = (float)x;
    return 1;
}

/* ---------------------------------------------------------------- particles */


/* fields: integer ids 0 .. LC_MAX_FIELDS - 1 as uint8 (checked before the narrowing). */
static PyArrayObject *field_ids(PyObject *obj, npy_intp n, lcpy_copy copy)
{
    int copied;
    PyArrayObject *w = lcpy_array(obj, "fields", NPY_INT64, "iu", 1, -1, LCPY_COPY_NEEDED, &copied);
    if (!w) return NULL;
    if (PyArray_DIM(w, 0) != n) {
        PyErr_Format(PyExc_ValueError, "fields: expected %lld field ids (one per position), got %lld", (long long)n,
                     (long long)PyArray_DIM(w, 0));
        return Py_DECREF(w), NULL;
    }
    const int64_t *id = PyArray_DATA(w);
    for (npy_intp i = 0; i < n; i++)
        if (id[i] < 0 || id[i] >= LC_MAX_FIELDS) {
            PyErr_Format(PyExc_ValueError, "fields: id %lld at index %lld is outside 0..%d", (long long)id[i],
                         (long long)i, LC_MAX_FIELDS - 1);
            return Py_DECREF(w), NULL;
        }
    Py_DECREF(w);
    return lcpy_array(obj, "fields", NPY_UINT8, "iu", 1, -1, copy, &copied);
}

static int particle_params(PyObject *kw_sigma, PyObject *kw_kappa, PyObject *kw_buffer, PyObject *kw_spheres,
                           lc_particle_params *p)
{
    float b = 0.0f;
    if (opt_float(kw_sigma, "sigma", &p->sigma) < 0 || opt_float(kw_kappa, "kappa", &p->kappa) < 0 ||
        opt_float(kw_buffer, "buffer_samples", &b) < 0 || opt_float(kw_spheres, "sphere_scale", &p->sphere_scale) < 0)
        return -1;
    if (b != 0.0f) p->buffer_samples = (int)b;
    return 0;
}

static PyObject *particles_new(PyTypeObject *type, PyObject *args, PyObject *kw)
{
    (void)type;
    static char *kwlist[] = {"device", "positions", "radii", "values", "fields", "nfields", "leaf_size",
                             "drop_invalid", "sigma", "kappa", "buffer_samples", "sphere_scale", "copy", NULL};
    PyObject *dev_o, *pos_o, *rad_o = NULL, *val_o = Py_None, *fld_o = Py_None, *copy_o = Py_None;
    PyObject *sig = NULL, *kap = NULL, *buf = NULL, *sph = NULL;
    int nfields = 0, leaf = 0, drop = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO|OOO$iipOOOOO:Particles", kwlist, &dev_o, &pos_o, &rad_o, &val_o,
                                     &fld_o, &nfields, &leaf, &drop, &sig, &kap, &buf, &sph, &copy_o))
        return NULL;
    DeviceObject *d = lcpy_device_or_default(dev_o);
    lcpy_copy copy;
    if (!d || lcpy_copy_arg(copy_o, &copy)) return NULL;
    lc_particles_desc pd = {.nfields = nfields, .leaf_size = leaf, .drop_invalid = drop, .radius = 1.0f};
    if (particle_params(sig, kap, buf, sph, &pd.params)) return NULL;
    PyArrayObject *a[4] = {NULL, NULL, NULL, NULL}; /* positions, radii, values, fields */
    static const char *const names[] = {"positions", "radii", "values", "fields"};
    PyObject *result = NULL;
    int copied;
    if (!(a[0] = lcpy_array(pos_o, "positions", NPY_FLOAT32, "fiu", 2, 3, copy, &copied))) goto out;
    npy_intp n = PyArray_DIM(a[0], 0);
    if (n == 0) {
        PyErr_SetString(PyExc_ValueError, "positions: no particles (shape (0, 3)); lanecast needs at least one");
        goto out;
    }
    if (rad_o && rad_o != Py_None &&
        (PyFloat_Check(rad_o) || PyLong_Check(rad_o) || PyArray_IsScalar(rad_o, Number) ||
         (PyArray_Check(rad_o) && PyArray_NDIM((PyArrayObject *)rad_o) == 0))) {
        if (opt_float(rad_o, "radii", &pd.radius) < 0) goto out;
        if (!(pd.radius > 0.0f) || !isfinite(pd.radius)) {
            PyErr_Format(PyExc_ValueError, "radii: expected a radius > 0 (or one per particle), got %g", (double)pd.radius);
            goto out;
        }
    } else if (rad_o && rad_o != Py_None) {
        if (!(a[1] = lcpy_array(rad_o, "radii", NPY_FLOAT32, "fiu", 1, -1, copy, &copied))) goto out;
    }
    if (val_o != Py_None && !(a[2] = lcpy_array(val_o, "values", NPY_FLOAT32, "fiu", 1, -1, copy, &copied))) goto out;
    if (fld_o != Py_None && !(a[3] = field_ids(fld_o, n, copy))) goto out;
    for (int i = 1; i < 3; i++)
        if (a[i] && PyArray_DIM(a[i], 0) != n) {
            PyErr_Format(PyExc_ValueError, "%s: expected %lld values (one per position), got %lld", names[i],
                         (long long)n, (long long)PyArray_DIM(a[i], 0));
            goto out;
        }
    pd.count = (size_t)n;
    pd.positions = PyArray_DATA(a[0]);
    pd.radii = a[1] ? PyArray_DATA(a[1]) : NULL;
    pd.values = a[2] ? PyArray_DATA(a[2]) : NULL;
    pd.fields = a[3] ? PyArray_DATA(a[3]) : NULL;
    lc_volume *vol = NULL;
    lc_status s;
    LCPY_UNLOCKED(d, s, lc_particles_create(d->dev, &pd, &vol));
    if (lcpy_flush_warnings(d)) {
        lc_volume_destroy(vol);
        goto out;
    }
    if (s != LC_OK) {
        lcpy_raise(s, lcpy_nonfinite_arg(a, names, 3));
        goto out;
    }
    result = lcpy_volume_wrap(vol, d, NULL); /* the library copied the particles */
out:
    for (int i = 0; i < 4; i++) Py_XDECREF(a[i]);
    return result;
}

static PyObject *particles_set_params(VolumeObject *v, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"sigma", "kappa", "buffer_samples", "sphere_scale", NULL};
    PyObject *sig = NULL, *kap = NULL, *buf = NULL, *sph = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "|$OOOO:set_params", kwlist, &sig, &kap, &buf, &sph)) return NULL;
    if (!lcpy_volume_arg((PyObject *)v, "set_params")) return NULL;
    if (v->busy) return PyErr_Format(PyExc_RuntimeError, "set_params: the volume is being rendered");
    lc_particles_info pi;
    lc_particles_get_info(v->vol, &pi);
    lc_particle_params p = pi.params; /* only what is given changes */
    if (particle_params(sig, kap, buf, sph, &p)) return NULL;
    lc_status s = lc_particles_set_params(v->vol, &p);
    if (s != LC_OK) return lcpy_raise(s, "set_params");
    Py_RETURN_NONE;
}

static PyMethodDef particles_methods[] = {
    {"set_params", (PyCFunction)(void (*)(void))particles_set_params, METH_VARARGS | METH_KEYWORDS,
     "set_params(*, sigma=None, kappa=None, buffer_samples=None, sphere_scale=None): changes the given\n"
     "parameters (0 = the default) without a rebuild."},
    {NULL, NULL, 0, NULL},
};

PyTypeObject lcpy_ParticlesType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "lanecast.Particles",
    .tp_basicsize = sizeof(VolumeObject),
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_HAVE_GC,
    .tp_doc = "Particles(device, positions, radii=1.0, values=None, fields=None, *, nfields=0, leaf_size=0,\n"
              "          drop_invalid=False, sigma=None, kappa=None, buffer_samples=None, sphere_scale=None,\n"
              "          copy=None)\n\n"
              "Particle data: a sum of truncated Gaussians per field (Knoll et al. 2014). positions (N, 3) x y z;\n"
              "radii one number or (N,); values (N,) weights k_i; fields (N,) ids 0..7. The library copies\n"
              "the arrays into its own layout while it builds the BVH (the GIL is released meanwhile);\n"
              "C-contiguous float32 arrays are read in place, others converted first (copy=False refuses).",
    .tp_traverse = (traverseproc)lcpy_volume_traverse,
    .tp_clear = (inquiry)lcpy_volume_clear,
    .tp_methods = particles_methods,
    .tp_base = &lcpy_VolumeType,
    .tp_new = particles_new,
};

/* ---------------------------------------------------------------- grids */

static int grid_params(PyObject *pre, PyObject *rda, PyObject *dc, PyObject *dp, PyObject *dsv, lc_grid_params *p)
{
    if (pre && pre != Py_None) {
        int t = PyObject_IsTrue(pre);
        if (t < 0) return -1;
        p->preintegrated = t;
    }
    return opt_float(rda, "rda", &p->rda) < 0 || opt_float(dc, "delta_c", &p->delta_c) < 0 ||
                   opt_float(dp, "delta_p", &p->delta_p) < 0 || opt_float(dsv, "delta_sv", &p->delta_sv) < 0
               ? -1
               : 0;
}

static PyObject *grid_new(PyTypeObject *type, PyObject *args, PyObject *kw)
{
    (void)type;
    static char *kwlist[] = {"device", "data", "spacing", "origin", "order", "copy", "layout", "brick",
                             "preintegrated", "rda", "delta_c", "delta_p", "delta_sv", NULL};
    PyObject *dev_o, *data_o, *sp_o = Py_None, *or_o = Py_None, *copy_o = Py_None, *lay_o = Py_None;
    PyObject *pre = NULL, *rda = NULL, *dc = NULL, *dp = NULL, *dsv = NULL;
    const char *order = "zyx";
    int brick = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "OO|OO$sOOiOOOOO:Grid", kwlist, &dev_o, &data_o, &sp_o, &or_o, &order,
                                     &copy_o, &lay_o, &brick, &pre, &rda, &dc, &dp, &dsv))
        return NULL;
    DeviceObject *d = lcpy_device_or_default(dev_o);
    lcpy_copy copy;
    if (!d || lcpy_copy_arg(copy_o, &copy)) return NULL;
    lc_grid_desc gd = {.brick = brick};
    static const char *const layouts[] = {"default", "linear", "bricked"};
    int lay = 0;
    if (lay_o != Py_None && lcpy_choice(lay_o, "layout", layouts, 3, &lay)) return NULL;
    gd.layout = (lc_grid_layout)lay;
    if (grid_params(pre, rda, dc, dp, dsv, &gd.params)) return NULL;
    if (sp_o != Py_None && lcpy_vec3(sp_o, "spacing", &gd.spacing)) return NULL;
    if (or_o != Py_None && lcpy_vec3(or_o, "origin", &gd.origin)) return NULL;
    if (sp_o != Py_None && !(gd.spacing.x > 0 && gd.spacing.y > 0 && gd.spacing.z > 0))
        return PyErr_Format(PyExc_ValueError, "spacing: expected three spacings > 0 (x, y, z)");
    PyArrayObject *buf = NULL;
    int copied = 0;
    /* A bricked layout is always the library's own copy. */
    if (lcpy_grid_array(data_o, "data", order, gd.layout == LC_LAYOUT_BRICKED && copy == LCPY_COPY_NEEDED
                                                   ? LCPY_COPY_NEEDED : copy, &gd, &buf, &copied))
        return NULL;
    if (gd.layout == LC_LAYOUT_BRICKED && copy == LCPY_COPY_NEVER) {
        Py_DECREF(buf);
        return PyErr_Format(PyExc_ValueError, "copy: copy=False borrows the array, which a bricked layout cannot");
    }
    /* Borrow the caller's array when it can be read in place and no copy
       was asked for; a converted copy is handed over to the library (which
       then lays it out for speed: bricks or a packed sampling copy). */
    gd.borrow = !copied && copy != LCPY_COPY_ALWAYS && gd.layout != LC_LAYOUT_BRICKED;
    lc_volume *vol = NULL;
    lc_status s;
    LCPY_UNLOCKED(d, s, lc_grid_create(d->dev, &gd, &vol));
    PyObject *result = NULL;
    if (lcpy_flush_warnings(d)) lc_volume_destroy(vol);
    else if (s != LC_OK) lcpy_raise(s, "data");
    else {
        PyObject *keep = gd.borrow ? PyTuple_Pack(1, (PyObject *)buf) : NULL;
        if (!gd.borrow || keep) result = lcpy_volume_wrap(vol, d, keep);
        else lc_volume_destroy(vol);
        Py_XDECREF(keep);
    }
    Py_DECREF(buf);
    return result;
}

static PyObject *grid_set_params(VolumeObject *v, PyObject *args, PyObject *kw)
{
    static char *kwlist[] = {"preintegrated", "rda", "delta_c", "delta_p", "delta_sv", NULL};
    PyObject *pre = NULL, *rda = NULL, *dc = NULL, *dp = NULL, *dsv = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "|$OOOOO:set_params", kwlist, &pre, &rda, &dc, &dp, &dsv)) return NULL;
    if (!lcpy_volume_arg((PyObject *)v, "set_params")) return NULL;
    if (v->busy) return PyErr_Format(PyExc_RuntimeError, "set_params: the volume is being rendered");
    lc_grid_info gi;
    lc_grid_get_info(v->vol, &gi);
    lc_grid_params p = gi.params;
    if (grid_params(pre, rda, dc, dp, dsv, &p)) return NULL;
    lc_status s = lc_grid_set_params(v->vol, &p);
    if (s != LC_OK) return lcpy_raise(s, "set_params");
    Py_RETURN_NONE;
}

static PyObject *grid_histogram(VolumeObject *v, PyObject *arg)
{
    long n = PyLong_AsLong(arg);
    if (n == -1 && PyErr_Occurred()) return NULL;
    if (!lcpy_volume_arg((PyObject *)v, "histogram")) return NULL;
    if (n < 1 || n > (1 << 24)) return PyErr_Format(PyExc_ValueError, "bins: expected 1 to 2^24, got %ld", n);
    npy_intp dims[1] = {n};
    PyArrayObject *h = (PyArrayObject *)PyArray_SimpleNew(1, dims, NPY_UINT64);
    if (!h) return NULL;
    lc_status s;
    Py_BEGIN_ALLOW_THREADS
    s = lc_grid_histogram(v->vol, (int)n, PyArray_DATA(h));
    Py_END_ALLOW_THREADS
    if (s != LC_OK) return Py_DECREF(h), lcpy_raise(s, "histogram");
    return (PyObject *)h;
}

static PyMethodDef grid_methods[] = {
    {"set_params", (PyCFunction)(void (*)(void))grid_set_params, METH_VARARGS | METH_KEYWORDS,
     "set_params(*, preintegrated=None, rda=None, delta_c=None, delta_p=None, delta_sv=None)"},
    {"histogram", (PyCFunction)grid_histogram, METH_O, "histogram(bins) -> uint64 counts over the value range."},
    {NULL, NULL, 0, NULL},
};

PyTypeObject lcpy_GridType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "lanecast.Grid",
    .tp_basicsize = sizeof(VolumeObject),
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_HAVE_GC,
    .tp_doc = "Grid(device, data, spacing=(1, 1, 1), origin=(0, 0, 0), *, order='zyx', copy=None,\n"
              "     layout=None, brick=0, preintegrated=None, rda=None, delta_c=None, delta_p=None, delta_sv=None)\n\n"
              "A structured volume (Knoll et al. 2011) from a 3-D array. order names the array's axes:\n"
              "'zyx' (default) is NumPy's C order of an x-fastest volume, data[k, j, i] the node at\n"
              "origin + (i sx, j sy, k sz); 'xyz' for data[i, j, k]. spacing and origin are (x, y, z).\n"
              "uint8, uint16, int16 and float32 keep their type, other numbers become float32.\n"
              "copy=None: an array already in lanecast's layout (x fastest, native, C-contiguous after\n"
              "the axis order) is borrowed in place (kept referenced; do not change it while the grid\n"
              "lives), anything else is converted once and owned by the library; copy=True: the library\n"
              "keeps its own copy (bricked or packed: faster frames); copy=False: borrow or raise.",
    .tp_traverse = (traverseproc)lcpy_volume_traverse,
    .tp_clear = (inquiry)lcpy_volume_clear,
    .tp_methods = grid_methods,
    .tp_base = &lcpy_VolumeType,
    .tp_new = grid_new,
};

