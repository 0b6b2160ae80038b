/*
 * _result.c -- _core.Result: what one solve returned, copied out of the workspace into
 * one object (its numbers inline, one allocation), each field built as a Python object
 * on first access and kept.  A read-only mapping with the keys and values of the solve
 * dict of csrc/README.md (lazy solves: no node arrays), each key an attribute too;
 * as_dict() is that dict, which pickling returns.  A warm Problem.solve that reads its
 * tip and tensions pays for those few objects, not for the whole dict.
 */
#include "_glue.h"

/* The keys, in the order of the solve dict. */
enum {
    K_STATUS,
    K_MESSAGE,
    K_SUCCESS,
    K_NIT,
    K_NFEV,
    K_NJEV,
    K_WORK,
    K_RESNORM,
    K_COND,
    K_TRUNC,
    K_CARRIED,
    K_CONT,
    K_TENSION,
    K_SLACK,
    K_DISP,
    K_TIP_POS,
    K_TIP_FORCE,
    K_TIP_MOMENT,
    K_TIP_ROT,
    K_TIP_ANGLE,
    K_BASE,
    K_UNKNOWNS,
    K_VER_EST,
    K_VER_X,
    K_VER_VALUES,
    K_JACOBIAN,
    K_FORM,
    K_CARRY,
    K_VERDICT,
    K_N
};

static const char *const key_names[K_N] = {"status",
                                           "message",
                                           "success",
                                           "nit",
                                           "nfev",
                                           "njev",
                                           "work",
                                           "residual_norm",
                                           "jacobian_cond",
                                           "truncation_estimate",
                                           "truncation_carried",
                                           "continuation_steps",
                                           "tension",
                                           "slack",
                                           "displacement",
                                           "tip_position",
                                           "tip_force",
                                           "tip_moment",
                                           "tip_rotation",
                                           "tip_angle",
                                           "base_state",
                                           "unknowns",
                                           "verified_estimate",
                                           "verified_unknowns",
                                           "verified_values",
                                           "jacobian",
                                           "formulation",
                                           "stability_carry",
                                           "stability_verdict"};

typedef struct {
    PyObject_VAR_HEAD int status, nit, nfev, njev, cont_steps, carried, steps, nt, k, ncarry;
    int has_ver, has_ver_values, has_carry, has_verdict, v_stable, v_index;
    double work, resnorm, cond, trunc, tip_angle, ver_est, v_margin;
    PyObject *form;      /* the formulation template (all but the step count) */
    PyObject *slot[K_N]; /* the fields built so far */
    double *tension, *slack, *disp, *tip, *base, *x, *J, *ver_x, *ver_values, *carry;
    char *message, *v_reason, *carry_reason;
    double data[1]; /* the arrays, then the strings (ob_size doubles in all) */
} ResultObject;

PyTypeObject glue_result_type;

static char *copy_string(char **at, const char *s)
{
    char *out = *at;
    size_t n = strlen(s) + 1;
    memcpy(out, s, n);
    *at += n;
    return out;
}

/* n doubles at *p filled from src (when given); *p moves past them. */
static double *take(double **p, int n, const double *src)
{
    double *out = *p;
    if (src && n > 0) memcpy(out, src, (size_t)n * sizeof(double));
    *p += n;
    return out;
}

PyObject *glue_result_new(const tr_model *m, const tr_data *d, int status, PyObject *form)
{
    ResultObject *r;
    tr_result res;
    tr_outputs o;
    tr_verified v;
    tr_verdict vd;
    const char *carry;
    int nt = m->nt, k, have_ver, ncarry;
    size_t nd, chars;
    double *p;
    char *c;
    tr_data_result(d, &res);
    tr_data_outputs(d, &o);
    have_ver = tr_data_verified(d, &v);
    tr_data_verdict(d, &vd);
    carry = TR_SUCCEEDED(status) ? tr_data_carry_reason(d) : NULL;
    k = o.k;
    ncarry = carry ? tr_carry_len(m, d) : 0;
    nd = (size_t)(3 * nt + 18 + 6 + 2 * nt + k + k * k + k + nt + ncarry);
    chars = strlen(res.message) + 1 + (vd.reason ? strlen(vd.reason) : 0) + 1 +
            (carry ? strlen(carry) : 0) + 1;
    r = PyObject_NewVar(ResultObject, &glue_result_type,
                        (Py_ssize_t)(nd + (chars + sizeof(double) - 1) / sizeof(double)));
    if (!r) return NULL;
    memset(r->slot, 0, sizeof r->slot);
    r->status = status;
    r->nit = res.nit;
    r->nfev = res.nfev;
    r->njev = res.njev;
    r->cont_steps = res.cont_steps;
    r->carried = res.ver_carried;
    r->steps = tr_data_options(d)->integrator == TR_ADAPTIVE ? 0 : res.steps;
    r->work = res.work;
    r->resnorm = res.residual_norm;
    r->cond = res.jacobian_cond;
    r->trunc = res.truncation;
    r->tip_angle = o.tip_angle;
    r->nt = nt;
    r->k = k;
    r->ncarry = ncarry;
    r->has_ver = have_ver;
    r->has_ver_values = have_ver && v.values;
    r->ver_est = have_ver ? v.estimate : NAN;
    r->has_carry = carry != NULL;
    r->has_verdict = status >= 0 && status != TR_CONTINUE && !tr_data_options(d)->accept_unstable;
    r->v_stable = vd.stable;
    r->v_index = vd.index;
    r->v_margin = vd.margin;
    /* without a template (a one-shot solve) the model's, built now: m and d do not
     * outlive this call */
    r->form = form ? Py_NewRef(form) : glue_formulation(m, d);
    if (!r->form) {
        Py_DECREF(r);
        return NULL;
    }
    p = r->data;
    r->tension = take(&p, nt, o.tension);
    r->slack = take(&p, nt, o.slack);
    r->disp = take(&p, nt, o.displacement);
    r->tip = take(&p, 18, o.tip);
    r->base = take(&p, 6 + 2 * nt, NULL);
    r->x = take(&p, k, o.x);
    r->J = take(&p, k * k, o.J);
    r->ver_x = take(&p, k, have_ver ? v.x : NULL);
    r->ver_values = take(&p, nt, r->has_ver_values ? v.values : NULL);
    r->carry = take(&p, ncarry, NULL);
    tr_base_state(m, d, r->base);
    if (carry) tr_carry_get(m, d, r->carry);
    c = (char *)p;
    r->message = copy_string(&c, res.message);
    r->v_reason = copy_string(&c, vd.reason ? vd.reason : "");
    r->carry_reason = copy_string(&c, carry ? carry : "");
    return (PyObject *)r;
}

static void result_dealloc(ResultObject *r)
{
    int i;
    Py_XDECREF(r->form);
    for (i = 0; i < K_N; i++) Py_XDECREF(r->slot[i]);
    PyObject_Free(r);
}

/* A read-only copy of n values (as the solve dict's arrays). */
static PyObject *array_of(int nd, npy_intp d0, npy_intp d1, const double *src)
{
    npy_intp dims[2] = {d0, d1};
    return glue_array(nd, dims, src);
}

/* A writeable array of n values (the solve dict's base state and verdict record). */
static PyObject *writeable(npy_intp n, const double *src)
{
    PyObject *a = glue_array(1, &n, NULL);
    if (a && n > 0) memcpy(PyArray_DATA((PyArrayObject *)a), src, (size_t)n * sizeof(double));
    return a;
}

static PyObject *formulation(ResultObject *r)
{
    PyObject *f, *steps;
    if (!(f = PyDict_Copy(r->form))) return NULL;
    if (!(steps = PyLong_FromLong(r->steps)) || PyDict_SetItemString(f, "steps", steps) < 0) {
        Py_XDECREF(steps);
        Py_DECREF(f);
        return NULL;
    }
    Py_DECREF(steps);
    return f;
}

/* The value of key `key` (a new reference). */
static PyObject *build(ResultObject *r, int key)
{
    const npy_intp nt = r->nt, k = r->k;
    switch (key) {
    case K_STATUS: return PyLong_FromLong(r->status);
    case K_MESSAGE: return PyUnicode_FromString(r->message);
    case K_SUCCESS: return PyBool_FromLong(TR_SUCCEEDED(r->status));
    case K_NIT: return PyLong_FromLong(r->nit);
    case K_NFEV: return PyLong_FromLong(r->nfev);
    case K_NJEV: return PyLong_FromLong(r->njev);
    case K_WORK: return PyFloat_FromDouble(r->work);
    case K_RESNORM: return PyFloat_FromDouble(r->resnorm);
    case K_COND: return PyFloat_FromDouble(r->cond);
    case K_TRUNC: return PyFloat_FromDouble(r->trunc);
    case K_CARRIED: return PyBool_FromLong(r->carried);
    case K_CONT: return PyLong_FromLong(r->cont_steps);
    case K_TENSION: return array_of(1, nt, 0, r->tension);
    case K_SLACK: return array_of(1, nt, 0, r->slack);
    case K_DISP: return array_of(1, nt, 0, r->disp);
    case K_TIP_POS: return array_of(1, 3, 0, r->tip);
    case K_TIP_FORCE: return array_of(1, 3, 0, r->tip + 12);
    case K_TIP_MOMENT: return array_of(1, 3, 0, r->tip + 15);
    case K_TIP_ROT: return array_of(2, 3, 3, r->tip + 3);
    case K_TIP_ANGLE: return PyFloat_FromDouble(r->tip_angle);
    case K_BASE: return writeable(6 + 2 * nt, r->base);
    case K_UNKNOWNS: return array_of(1, k, 0, r->x);
    case K_VER_EST: return PyFloat_FromDouble(r->ver_est);
    case K_VER_X: return r->has_ver ? array_of(1, k, 0, r->ver_x) : Py_NewRef(Py_None);
    case K_VER_VALUES:
        return r->has_ver_values ? array_of(1, nt, 0, r->ver_values) : Py_NewRef(Py_None);
    case K_JACOBIAN: return array_of(2, k, k, r->J);
    case K_FORM: return formulation(r);
    case K_CARRY:
        return r->has_carry ? Py_BuildValue("(Ns)", writeable(r->ncarry, r->carry), r->carry_reason)
                            : Py_NewRef(Py_None);
    case K_VERDICT:
        if (!r->has_verdict) return Py_NewRef(Py_None);
        return Py_BuildValue("{s:N,s:d,s:i,s:s}", "stable",
                             r->v_stable < 0 ? Py_NewRef(Py_None) : PyBool_FromLong(r->v_stable),
                             "stability", r->v_margin, "index", r->v_index, "reason", r->v_reason);
    }
    PyErr_SetString(PyExc_SystemError, "Result: unknown key");
    return NULL;
}

/* The field `key`, built on first access (a new reference). */
static PyObject *field(ResultObject *r, int key)
{
    if (!r->slot[key] && !(r->slot[key] = build(r, key))) return NULL;
    return Py_NewRef(r->slot[key]);
}

static int present(const ResultObject *r, int key)
{
    return key != K_VERDICT || r->has_verdict;
}

/* The index of a key of the mapping, or -1 (no exception). */
static int key_index(const ResultObject *r, PyObject *name)
{
    const char *s;
    int i;
    if (!PyUnicode_Check(name) || !(s = PyUnicode_AsUTF8(name))) {
        PyErr_Clear();
        return -1;
    }
    for (i = 0; i < K_N; i++)
        if (strcmp(s, key_names[i]) == 0) return present(r, i) ? i : -1;
    return -1;
}

static PyObject *result_getattr(ResultObject *r, void *closure)
{
    return field(r, (int)(intptr_t)closure);
}

static PyObject *result_subscript(ResultObject *r, PyObject *name)
{
    int i = key_index(r, name);
    if (i < 0) {
        PyErr_SetObject(PyExc_KeyError, name);
        return NULL;
    }
    return field(r, i);
}

static Py_ssize_t result_length(ResultObject *r)
{
    return r->has_verdict ? K_N : K_N - 1;
}

static int result_contains(ResultObject *r, PyObject *name)
{
    return key_index(r, name) >= 0;
}

static PyObject *result_as_dict(ResultObject *r, PyObject *unused)
{
    PyObject *out = PyDict_New(), *v;
    int i;
    if (!out) return NULL;
    for (i = 0; i < K_N; i++) {
        if (!present(r, i)) continue;
        if (!(v = field(r, i)) || glue_set(out, key_names[i], v) < 0) {
            Py_DECREF(out);
            return NULL;
        }
    }
    return out;
}

PyObject *glue_result_dict(PyObject *r)
{
    return result_as_dict((ResultObject *)r, NULL);
}

static PyObject *view(ResultObject *r, const char *method)
{
    PyObject *d = result_as_dict(r, NULL), *out;
    if (!d) return NULL;
    out = PyObject_CallMethod(d, method, NULL);
    Py_DECREF(d);
    return out;
}

static PyObject *result_keys(ResultObject *r, PyObject *unused)
{
    return view(r, "keys");
}

static PyObject *result_items(ResultObject *r, PyObject *unused)
{
    return view(r, "items");
}

static PyObject *result_values(ResultObject *r, PyObject *unused)
{
    return view(r, "values");
}

static PyObject *result_iter(ResultObject *r)
{
    PyObject *keys = result_keys(r, NULL), *it;
    if (!keys) return NULL;
    it = PyObject_GetIter(keys);
    Py_DECREF(keys);
    return it;
}

static PyObject *result_get(ResultObject *r, PyObject *args)
{
    PyObject *name, *dflt = Py_None;
    int i;
    if (!PyArg_ParseTuple(args, "O|O", &name, &dflt)) return NULL;
    i = key_index(r, name);
    return i < 0 ? Py_NewRef(dflt) : field(r, i);
}

static PyObject *result_reduce(ResultObject *r, PyObject *unused)
{
    return Py_BuildValue("(O(N))", (PyObject *)&PyDict_Type, result_as_dict(r, NULL));
}

static PyObject *result_repr(ResultObject *r)
{
    PyObject *d = result_as_dict(r, NULL), *s;
    if (!d) return NULL;
    s = PyObject_Repr(d);
    Py_DECREF(d);
    return s;
}

static PyMethodDef result_methods[] = {
    {"as_dict", (PyCFunction)result_as_dict, METH_NOARGS,
     "as_dict() -> dict: every field (the solve dict of _core.solve, no node arrays)."},
    {"keys", (PyCFunction)result_keys, METH_NOARGS, "The keys of as_dict()."},
    {"items", (PyCFunction)result_items, METH_NOARGS, "The items of as_dict()."},
    {"values", (PyCFunction)result_values, METH_NOARGS, "The values of as_dict()."},
    {"get", (PyCFunction)result_get, METH_VARARGS, "get(key, default=None)."},
    {"__reduce__", (PyCFunction)result_reduce, METH_NOARGS, "Pickled as its dict."},
    {NULL, NULL, 0, NULL}};

#define ATTR(name, key)                                                                            \
    {                                                                                              \
        name, (getter)result_getattr, NULL, NULL, (void *)(intptr_t)(key)                          \
    }
/* stability_verdict as an attribute is None when the solve judged none */
static PyGetSetDef result_getset[] = {ATTR("status", K_STATUS),
                                      ATTR("message", K_MESSAGE),
                                      ATTR("success", K_SUCCESS),
                                      ATTR("nit", K_NIT),
                                      ATTR("nfev", K_NFEV),
                                      ATTR("njev", K_NJEV),
                                      ATTR("work", K_WORK),
                                      ATTR("residual_norm", K_RESNORM),
                                      ATTR("jacobian_cond", K_COND),
                                      ATTR("truncation_estimate", K_TRUNC),
                                      ATTR("truncation_carried", K_CARRIED),
                                      ATTR("continuation_steps", K_CONT),
                                      ATTR("tension", K_TENSION),
                                      ATTR("slack", K_SLACK),
                                      ATTR("displacement", K_DISP),
                                      ATTR("tip_position", K_TIP_POS),
                                      ATTR("tip_force", K_TIP_FORCE),
                                      ATTR("tip_moment", K_TIP_MOMENT),
                                      ATTR("tip_rotation", K_TIP_ROT),
                                      ATTR("tip_angle", K_TIP_ANGLE),
                                      ATTR("base_state", K_BASE),
                                      ATTR("unknowns", K_UNKNOWNS),
                                      ATTR("verified_estimate", K_VER_EST),
                                      ATTR("verified_unknowns", K_VER_X),
                                      ATTR("verified_values", K_VER_VALUES),
                                      ATTR("jacobian", K_JACOBIAN),
                                      ATTR("formulation", K_FORM),
                                      ATTR("stability_carry", K_CARRY),
                                      ATTR("stability_verdict", K_VERDICT),
                                      {NULL, NULL, NULL, NULL, NULL}};
#undef ATTR

static PyMappingMethods result_mapping = {
    .mp_length = (lenfunc)result_length,
    .mp_subscript = (binaryfunc)result_subscript,
};

static PySequenceMethods result_sequence = {
    .sq_contains = (objobjproc)result_contains,
};

PyTypeObject glue_result_type = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "tendonrod._core.Result",
    .tp_basicsize = offsetof(ResultObject, data),
    .tp_itemsize = sizeof(double),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "What one lazy solve of a _core.Problem returned: a read-only mapping (and\n"
              "attributes) with the keys of the solve dict, each built on first access.",
    .tp_dealloc = (destructor)result_dealloc,
    .tp_repr = (reprfunc)result_repr,
    .tp_as_mapping = &result_mapping,
    .tp_as_sequence = &result_sequence,
    .tp_iter = (getiterfunc)result_iter,
    .tp_methods = result_methods,
    .tp_getset = result_getset,
};
