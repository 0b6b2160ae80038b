/*
 * _args.c -- the arguments the solver entry points share: the scene's flat arrays,
 * the solver options (one table, defaults from tr_default_options, ranges from
 * tendonrod.h), warm starts, and the compiled model and workspace.
 */
#include <stdarg.h>
#include <stddef.h>

#include "_glue.h"

const char *const glue_integrators[] = {"rk4", "rk8", "adaptive", NULL};
const char *const glue_jacobians[] = {"fd", "newton", "hybrid", NULL};
const char *const glue_slack_models[] = {"linear", "squared", NULL};

void glue_args_clear(glue_args *a)
{
    Py_CLEAR(a->rod);
    Py_CLEAR(a->tendons);
    Py_CLEAR(a->loads);
    Py_CLEAR(a->dist);
    Py_CLEAR(a->guess);
    Py_CLEAR(a->jac);
    Py_CLEAR(a->nodes);
    Py_CLEAR(a->dloads);
    Py_CLEAR(a->sections);
    Py_CLEAR(a->routes);
    Py_CLEAR(a->friction);
}

void glue_err(PyObject *type, const char *fmt, ...)
{
    char buf[TR_MSGLEN + 128];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    PyErr_SetString(type, buf);
}

PyArrayObject *glue_coerce(PyObject *obj, const char *name)
{
    PyArrayObject *arr =
        (PyArrayObject *)PyArray_FROMANY(obj, NPY_DOUBLE, 0, 0, NPY_ARRAY_IN_ARRAY);
    if (arr == NULL) {
        PyObject *et, *ev, *tb;
        PyErr_Fetch(&et, &ev, &tb);
        PyErr_Format(PyExc_TypeError, "%s must be a float64 array-like (could not convert %R)",
                     name, obj);
        Py_XDECREF(et);
        Py_XDECREF(ev);
        Py_XDECREF(tb);
    }
    return arr;
}

int glue_all_finite(PyArrayObject *a, const char *name, int posinf_col, int ncol)
{
    const double *v = (const double *)PyArray_DATA(a);
    npy_intp i, n = PyArray_SIZE(a);
    for (i = 0; i < n; i++) {
        const int inf_ok = posinf_col >= 0 && ncol > 0 && i % ncol == posinf_col && v[i] > 0;
        if (isnan(v[i]) || (isinf(v[i]) && !inf_ok)) {
            glue_err(PyExc_ValueError, "%s contains a non-finite value %g at flat index %ld", name,
                     v[i], (long)i);
            return -1;
        }
    }
    return 0;
}

PyObject *glue_take(PyObject *kw, const char *key)
{
    PyObject *v;
    if (kw == NULL) return NULL;
    v = PyDict_GetItemString(kw, key); /* borrowed */
    if (v == NULL) return NULL;
    Py_INCREF(v);
    PyDict_DelItemString(kw, key);
    return v;
}

/* A (rows, ncol) array, or an empty one (rows = 0).  0 or -1. */
static int table(PyObject *obj, const char *name, int ncol, const char *layout, PyArrayObject **out,
                 int *rows)
{
    if (!(*out = glue_coerce(obj, name))) return -1;
    if (PyArray_SIZE(*out) == 0 && PyArray_NDIM(*out) <= 2) {
        *rows = 0;
        return 0;
    }
    if (PyArray_NDIM(*out) != 2 || PyArray_DIM(*out, 1) != ncol || PyArray_DIM(*out, 0) > INT_MAX) {
        glue_err(PyExc_ValueError, "%s must have shape (n, %d): rows %s", name, ncol, layout);
        return -1;
    }
    *rows = (int)PyArray_DIM(*out, 0);
    return 0;
}

int glue_scene(glue_args *a, PyObject *rod, PyObject *tendons, PyObject *loads, PyObject *dist)
{
    const double *r;
    int i;
    if (!(a->rod = glue_coerce(rod, "rod"))) return -1;
    if (PyArray_NDIM(a->rod) != 1 || PyArray_DIM(a->rod, 0) != TR_ROD_NCOL) {
        PyErr_SetString(PyExc_ValueError,
                        "rod must have shape (6,): [L, EI, GJ, EA, GA, kirchhoff]");
        return -1;
    }
    if (table(tendons, "tendons", TR_TD_NCOL,
              "[offset, angle, slope, EA, end, control, value, pretension]", &a->tendons,
              &a->nt) < 0 ||
        table(loads, "loads", TR_LD_NCOL, "[s, Fx, Fy, Fz, Mx, My, Mz]", &a->loads, &a->nl) < 0)
        return -1;
    if (!(a->dist = glue_coerce(dist, "dist"))) return -1;
    if (PyArray_NDIM(a->dist) != 1 || PyArray_DIM(a->dist, 0) != 3) {
        PyErr_SetString(PyExc_ValueError,
                        "dist must have shape (3,): distributed force, world frame [N/m]");
        return -1;
    }
    /* EA, GA may be inf only for a Kirchhoff rod; the core checks the values */
    r = (const double *)PyArray_DATA(a->rod);
    for (i = 0; i < TR_ROD_NCOL; i++) {
        const int axial = i == TR_ROD_EA || i == TR_ROD_GA;
        if (isnan(r[i]) || (isinf(r[i]) && !(axial && r[TR_ROD_KIRCHHOFF] != 0.0 && r[i] > 0))) {
            glue_err(PyExc_ValueError,
                     "rod[%d] = %g must be finite (EA, GA may be inf only for a Kirchhoff rod)", i,
                     r[i]);
            return -1;
        }
    }
    if (a->nt > 0 && glue_all_finite(a->tendons, "tendons", TR_TD_EA, TR_TD_NCOL) < 0) return -1;
    if (a->nl > 0 && glue_all_finite(a->loads, "loads", -1, 0) < 0) return -1;
    return glue_all_finite(a->dist, "dist", -1, 0);
}

/* ------------------------------------------------------------------ options */
typedef enum { OPT_CHOICE, OPT_INT, OPT_DOUBLE, OPT_BOOL } opt_kind;

typedef struct {
    const char *name;
    opt_kind kind;
    size_t offset;              /* of the field in tr_options */
    const char *const *choices; /* OPT_CHOICE: names in enum order, NULL-terminated */
    int lo, hi;                 /* OPT_INT: range */
} opt_spec;

static const opt_spec options[] = {
    {"integrator", OPT_CHOICE, offsetof(tr_options, integrator), glue_integrators, 0, 0},
    {"steps", OPT_INT, offsetof(tr_options, steps), NULL, 0, TR_MAX_STEPS},
    {"rtol", OPT_DOUBLE, offsetof(tr_options, rtol), NULL, 0, 0},
    {"tol", OPT_DOUBLE, offsetof(tr_options, tol), NULL, 0, 0},
    {"max_iter", OPT_INT, offsetof(tr_options, max_iter), NULL, 1, TR_MAX_ITER_CAP},
    {"max_nfev", OPT_INT, offsetof(tr_options, max_nfev), NULL, 1, TR_MAX_NFEV_CAP},
    {"jacobian_method", OPT_CHOICE, offsetof(tr_options, jacobian_method), glue_jacobians, 0, 0},
    {"slack_model", OPT_CHOICE, offsetof(tr_options, slack_model), glue_slack_models, 0, 0},
    {"continuation", OPT_BOOL, offsetof(tr_options, continuation), NULL, 0, 1},
    {"max_continuation", OPT_INT, offsetof(tr_options, max_continuation), NULL, 0,
     TR_MAX_CONTINUATION_CAP},
    {"force_spatial", OPT_BOOL, offsetof(tr_options, force_spatial), NULL, 0, 1},
    {"tip_only", OPT_BOOL, offsetof(tr_options, tip_only), NULL, 0, 1},
    {"shooting_segments", OPT_INT, offsetof(tr_options, shooting_segments), NULL, 1,
     TR_MAX_SHOOTING_SEGMENTS},
    {"max_work", OPT_DOUBLE, offsetof(tr_options, max_work), NULL, 0, 0},
    {"max_time", OPT_DOUBLE, offsetof(tr_options, max_time), NULL, 0, 0},
    {"auto_shooting", OPT_BOOL, offsetof(tr_options, auto_shooting), NULL, 0, 1},
    {"accept_unstable", OPT_BOOL, offsetof(tr_options, accept_unstable), NULL, 0, 1},
};

/* An int in [lo, hi] from a Python int; ValueError/TypeError naming it. */
static int parse_int(PyObject *obj, const char *name, long long lo, long long hi, int *out)
{
    long long v;
    int overflow = 0;
    if (!PyLong_Check(obj) || PyBool_Check(obj)) {
        PyErr_Format(PyExc_TypeError, "%s must be an int (got %R)", name, obj);
        return -1;
    }
    v = PyLong_AsLongLongAndOverflow(obj, &overflow);
    if (v == -1 && PyErr_Occurred()) return -1;
    if (overflow || v < lo || v > hi) {
        PyErr_Format(PyExc_ValueError, "%s = %R must lie in [%lld, %lld]", name, obj, lo, hi);
        return -1;
    }
    *out = (int)v;
    return 0;
}

static int parse_option(const opt_spec *o, PyObject *value, tr_options *opt)
{
    char *field = (char *)opt + o->offset;
    switch (o->kind) {
    case OPT_INT: return parse_int(value, o->name, o->lo, o->hi, (int *)field);
    case OPT_BOOL: {
        const int b = PyObject_IsTrue(value);
        if (b < 0) return -1;
        *(int *)field = b;
        return 0;
    }
    case OPT_DOUBLE: {
        const double v = PyFloat_AsDouble(value);
        if (v == -1.0 && PyErr_Occurred()) {
            PyErr_Clear();
            PyErr_Format(PyExc_TypeError, "%s must be a real number (got %R)", o->name, value);
            return -1;
        }
        *(double *)field = v;
        return 0;
    }
    case OPT_CHOICE: {
        const char *s;
        int i;
        if (!PyUnicode_Check(value)) {
            PyErr_Format(PyExc_TypeError, "%s must be a str (got %R)", o->name, value);
            return -1;
        }
        if (!(s = PyUnicode_AsUTF8(value))) return -1;
        for (i = 0; o->choices[i]; i++)
            if (strcmp(s, o->choices[i]) == 0) {
                *(int *)field = i;
                return 0;
            }
        PyErr_Format(PyExc_ValueError, "%s = %R is not one of the accepted values", o->name, value);
        return -1;
    }
    }
    return -1;
}

/* nodes: an int (uniform nodes plus breakpoints) or a sorted 1-D array of arc lengths. */
static int parse_nodes(glue_args *a, PyObject *nodes)
{
    const double *v;
    npy_intp i;
    if (nodes == Py_None) return 0;
    if (PyLong_Check(nodes) && !PyBool_Check(nodes))
        return parse_int(nodes, "nodes", 2, TR_MAX_NODES, &a->nnode);
    if (!(a->nodes = glue_coerce(nodes, "nodes"))) return -1;
    if (PyArray_NDIM(a->nodes) != 1 || PyArray_DIM(a->nodes, 0) < 1 ||
        PyArray_DIM(a->nodes, 0) > TR_MAX_NODES) {
        PyErr_SetString(PyExc_ValueError,
                        "nodes must be an int >= 2 or a non-empty 1-D array of arc lengths");
        return -1;
    }
    v = (const double *)PyArray_DATA(a->nodes);
    for (i = 0; i < PyArray_DIM(a->nodes, 0); i++)
        if (!isfinite(v[i]) || (i > 0 && v[i] < v[i - 1])) {
            glue_err(PyExc_ValueError, "nodes must be finite and sorted (nodes[%ld] = %g)", (long)i,
                     v[i]);
            return -1;
        }
    a->nnode = (int)PyArray_DIM(a->nodes, 0);
    return 0;
}

int glue_options(glue_args *a, PyObject *kw, const char *fn)
{
    PyObject *key, *value;
    Py_ssize_t pos = 0;
    char msg[TR_MSGLEN];
    a->opt = tr_default_options();
    a->nnode = TR_DEFAULT_NODES;
    while (kw && PyDict_Next(kw, &pos, &key, &value)) {
        const char *k = PyUnicode_Check(key) ? PyUnicode_AsUTF8(key) : NULL;
        size_t i;
        if (!k) {
            if (!PyErr_Occurred()) PyErr_SetString(PyExc_TypeError, "keywords must be strings");
            return -1;
        }
        if (strcmp(k, "nodes") == 0) {
            if (parse_nodes(a, value) < 0) return -1;
            continue;
        }
        if (strcmp(k, "dloads") == 0) {
            Py_CLEAR(a->dloads);
            if (table(value, "dloads", TR_DL_NCOL, "[s0, s1, fx, fy, fz]", &a->dloads, &a->nd) <
                    0 ||
                (a->nd > 0 && glue_all_finite(a->dloads, "dloads", -1, 0) < 0))
                return -1;
            continue;
        }
        if (strcmp(k, "sections") == 0) {
            Py_CLEAR(a->sections);
            if (table(value, "sections", TR_SC_NCOL, "[end, EI, GJ, EA, GA, ux, uy, uz]",
                      &a->sections, &a->nsec) < 0)
                return -1;
            continue;
        }
        if (strcmp(k, "routes") == 0) {
            Py_CLEAR(a->routes);
            if (table(value, "routes", TR_RT_NCOL, "[tendon, kind, s0, s1, p (8)]", &a->routes,
                      &a->nroute) < 0)
                return -1;
            continue;
        }
        if (strcmp(k, "friction") == 0) {
            Py_CLEAR(a->friction);
            if (table(value, "friction", 2, "[mu, sliding (+1 in, -1 out)] per tendon",
                      &a->friction, &a->nfric) < 0)
                return -1;
            continue;
        }
        for (i = 0; i < sizeof options / sizeof options[0]; i++)
            if (strcmp(k, options[i].name) == 0) break;
        if (i == sizeof options / sizeof options[0]) {
            PyErr_Format(PyExc_TypeError, "%s() got an unexpected keyword argument '%s'", fn, k);
            return -1;
        }
        if (parse_option(&options[i], value, &a->opt) < 0) return -1;
    }
    if (tr_options_check(&a->opt, msg, sizeof msg) != TR_OK) {
        PyErr_SetString(PyExc_ValueError, msg);
        return -1;
    }
    return 0;
}

int glue_warm_start(glue_args *a, PyObject *guess, PyObject *jacobian)
{
    if (guess != NULL && guess != Py_None) {
        if (!(a->guess = glue_coerce(guess, "guess"))) return -1;
        if (PyArray_NDIM(a->guess) != 1 || PyArray_DIM(a->guess, 0) != 6 + 2 * a->nt) {
            PyErr_Format(PyExc_ValueError,
                         "guess must have shape (%d,): [n(0) (3), m(0) (3), "
                         "tension (nt), slack (nt)]",
                         6 + 2 * a->nt);
            return -1;
        }
        if (glue_all_finite(a->guess, "guess", -1, 0) < 0) return -1;
    }
    if (jacobian != NULL && jacobian != Py_None) {
        if (!(a->jac = glue_coerce(jacobian, "jacobian"))) return -1;
        if (PyArray_NDIM(a->jac) != 2 || PyArray_DIM(a->jac, 0) != PyArray_DIM(a->jac, 1)) {
            PyErr_SetString(PyExc_ValueError, "jacobian must be a square 2-D array (the 'jacobian' "
                                              "a previous solve returned)");
            return -1;
        }
    }
    return 0;
}

/* The friction table (nt rows [mu, sliding]) into the compiled model m. */
static int set_friction(const glue_args *a, tr_model *m, char *msg, size_t msglen)
{
    const double *f = (const double *)PyArray_DATA(a->friction);
    double *mu;
    int *sl, i, status;
    if (a->nfric != a->nt) {
        snprintf(msg, msglen, "friction must have one row per tendon (%d), got %d", a->nt,
                 a->nfric);
        return TR_EINVAL;
    }
    mu = (double *)PyMem_Malloc((size_t)(a->nt + 1) * sizeof(double));
    sl = (int *)PyMem_Malloc((size_t)(a->nt + 1) * sizeof(int));
    if (!mu || !sl) {
        PyMem_Free(mu);
        PyMem_Free(sl);
        return TR_ENOMEM;
    }
    for (i = 0; i < a->nt; i++) {
        mu[i] = f[2 * i];
        sl[i] = f[2 * i + 1] == 1.0 ? 1 : f[2 * i + 1] == -1.0 ? -1 : 0;
    }
    status = tr_model_set_friction(m, mu, sl, msg, msglen);
    PyMem_Free(mu);
    PyMem_Free(sl);
    return status;
}

int glue_build(glue_args *a, const double *extra_load, tr_model **mp, tr_data **dp)
{
    char msg[TR_MSGLEN];
    int status, nl = a->nl;
    const double *loads = a->nl > 0 ? (const double *)PyArray_DATA(a->loads) : NULL;
    double *tmp = NULL;
    *mp = NULL;
    if (dp) *dp = NULL;
    if (extra_load) {
        tmp = (double *)PyMem_Malloc((size_t)(TR_LD_NCOL * (nl + 1)) * sizeof(double));
        if (!tmp) {
            PyErr_NoMemory();
            return -1;
        }
        if (nl > 0) memcpy(tmp, loads, (size_t)(TR_LD_NCOL * nl) * sizeof(double));
        memcpy(tmp + TR_LD_NCOL * nl, extra_load, TR_LD_NCOL * sizeof(double));
        loads = tmp;
        nl++;
    }
    status =
        tr_model_alloc_ext(mp, (const double *)PyArray_DATA(a->rod),
                           a->nt > 0 ? (const double *)PyArray_DATA(a->tendons) : NULL, a->nt,
                           loads, nl, (const double *)PyArray_DATA(a->dist),
                           a->nd > 0 ? (const double *)PyArray_DATA(a->dloads) : NULL, a->nd,
                           a->nsec > 0 ? (const double *)PyArray_DATA(a->sections) : NULL, a->nsec,
                           a->nroute > 0 ? (const double *)PyArray_DATA(a->routes) : NULL,
                           a->nroute, &a->opt, msg, sizeof msg);
    PyMem_Free(tmp);
    if (status == TR_OK && a->nfric > 0) status = set_friction(a, *mp, msg, sizeof msg);
    if (status != TR_OK) {
        if (status == TR_ENOMEM)
            PyErr_NoMemory();
        else
            PyErr_SetString(PyExc_ValueError, msg);
        tr_model_free(*mp);
        *mp = NULL;
        return -1;
    }
    if (!dp) return 0;
    *dp = tr_data_alloc(*mp, &a->opt, a->nnode,
                        a->nodes ? (const double *)PyArray_DATA(a->nodes) : NULL, msg, sizeof msg);
    if (*dp == NULL) {
        tr_model_free(*mp);
        *mp = NULL;
        PyErr_SetString(PyExc_ValueError, msg);
        return -1;
    }
    return 0;
}

PyObject *glue_array(int nd, const npy_intp *dims, const double *src)
{
    PyObject *arr = PyArray_SimpleNew(nd, (npy_intp *)dims, NPY_DOUBLE);
    if (arr && src) {
        npy_intp n = PyArray_SIZE((PyArrayObject *)arr);
        if (n > 0) memcpy(PyArray_DATA((PyArrayObject *)arr), src, (size_t)n * sizeof(double));
    }
    /* a result is what the core computed: read-only, so a Solution cannot be edited in
     * place (np.array(x) or x.copy() gives a writeable copy) */
    if (arr && src) PyArray_CLEARFLAGS((PyArrayObject *)arr, NPY_ARRAY_WRITEABLE);
    return arr;
}

int glue_set(PyObject *dict, const char *key, PyObject *value)
{
    int r;
    if (value == NULL) return -1;
    r = PyDict_SetItemString(dict, key, value);
    Py_DECREF(value);
    return r;
}
