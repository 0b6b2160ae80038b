/*
 * _path.c -- _core.path: the load path of a scene (tr_path) as a dict of arrays.
 */
#include "_glue.h"
#include "tr_path.h"

const char glue_path_doc[] =
    "path(rod, tendons, loads, dist, *, kind, index, p0, p1, ds0=0.05, ds_max=0.2,\n"
    "max_points=400, side=0, cancel=None, **options) -> dict: the branch through the\n"
    "scene's equilibrium at p0 (the scene's value of the parameter) toward p1 (tr_path).\n"
    "kind -1: entry `index` of the value vector [actuation (nt), point loads (nl x 6), dist\n"
    "(3)]; else a design parameter kind (PARAM_KINDS) of tendon `index`.  Keys: status,\n"
    "message, n, par (n,), tip (n, 18), tension (n, nt), margin (n,), stable (n,) int,\n"
    "kind (n,) int (0 regular, 1 limit, 2 bifurcation), branch (n,) int, tlam (n,),\n"
    "unknowns (n, k), steps (n,) int, residual (n,), truncation (n,).  Ctrl-C raises\n"
    "KeyboardInterrupt.";

static PyObject *int_array(npy_intp n, const int *src)
{
    PyObject *a = PyArray_SimpleNew(1, &n, NPY_INT);
    if (a && n > 0) memcpy(PyArray_DATA((PyArrayObject *)a), src, (size_t)n * sizeof(int));
    return a;
}

static PyObject *result_of(const tr_model *m, const tr_data *d, const tr_path_out *o, int status)
{
    PyObject *res = PyDict_New();
    npy_intp n = o->n, d2[2];
    if (!res) return NULL;
    if (glue_set(res, "status", PyLong_FromLong(status)) < 0 ||
        glue_set(res, "message", PyUnicode_FromString(tr_data_message(d))) < 0 ||
        glue_set(res, "n", PyLong_FromLong(o->n)) < 0 ||
        glue_set(res, "par", glue_array(1, &n, o->par)) < 0 ||
        glue_set(res, "margin", glue_array(1, &n, o->margin)) < 0 ||
        glue_set(res, "tlam", glue_array(1, &n, o->tlam)) < 0 ||
        glue_set(res, "residual", glue_array(1, &n, o->residual)) < 0 ||
        glue_set(res, "truncation", glue_array(1, &n, o->truncation)) < 0 ||
        glue_set(res, "stable", int_array(n, o->stable)) < 0 ||
        glue_set(res, "kind", int_array(n, o->kind)) < 0 ||
        glue_set(res, "branch", int_array(n, o->branch)) < 0 ||
        glue_set(res, "steps", int_array(n, o->steps)) < 0)
        goto fail;
    d2[0] = n;
    d2[1] = 18;
    if (glue_set(res, "tip", glue_array(2, d2, o->tip)) < 0) goto fail;
    d2[1] = m->nt;
    if (glue_set(res, "tension", glue_array(2, d2, o->tension)) < 0) goto fail;
    d2[1] = m->n_unknowns;
    if (glue_set(res, "unknowns", glue_array(2, d2, o->x)) < 0) goto fail;
    return res;
fail:
    Py_DECREF(res);
    return NULL;
}

PyObject *glue_path(PyObject *self, PyObject *args, PyObject *kwds)
{
    PyObject *rod, *tendons, *loads, *dist, *kw = NULL, *o, *cancel = Py_None, *result = NULL;
    glue_args a;
    glue_poll poll;
    tr_model *m = NULL;
    tr_data *d = NULL;
    tr_path_spec sp = {0, 0, 0.0, 1.0, 0.05, 0.2, 0};
    tr_path_out out;
    long cap = 400;
    int status;
    const char *names[] = {"kind", "index", "side"};
    int *ivals[] = {&sp.kind, &sp.index, &sp.side};
    const char *dnames[] = {"p0", "p1", "ds0", "ds_max"};
    double *dvals[] = {&sp.p0, &sp.p1, &sp.ds0, &sp.ds_max};
    int i;
    (void)self;
    memset(&a, 0, sizeof a);
    memset(&out, 0, sizeof out);
    if (!PyArg_ParseTuple(args, "OOOO", &rod, &tendons, &loads, &dist)) return NULL;
    if (!(kw = kwds ? PyDict_Copy(kwds) : PyDict_New())) return NULL;
    for (i = 0; i < 3; i++)
        if ((o = glue_take(kw, names[i]))) {
            *ivals[i] = (int)PyLong_AsLong(o);
            Py_DECREF(o);
            if (PyErr_Occurred()) goto done;
        }
    for (i = 0; i < 4; i++)
        if ((o = glue_take(kw, dnames[i]))) {
            *dvals[i] = PyFloat_AsDouble(o);
            Py_DECREF(o);
            if (PyErr_Occurred()) goto done;
        }
    if ((o = glue_take(kw, "max_points"))) {
        cap = PyLong_AsLong(o);
        Py_DECREF(o);
        if (PyErr_Occurred()) goto done;
    }
    if ((o = glue_take(kw, "cancel"))) {
        cancel = o;
        Py_DECREF(o); /* the caller's kwds keep it alive */
    }
    if (cap < 2 || cap > 1000000) {
        glue_err(PyExc_ValueError, "max_points = %ld must be in [2, 1000000]", cap);
        goto done;
    }
    if (glue_poll_init(&poll, cancel) < 0 || glue_scene(&a, rod, tendons, loads, dist) < 0 ||
        glue_options(&a, kw, "path") < 0 || glue_build(&a, NULL, &m, &d) < 0)
        goto done;
    if (sp.kind == TR_PATH_SLOT ? !(sp.index >= 0 && sp.index < m->nt + 6 * m->nl + 3)
                                : !(sp.kind >= TR_PAR_ROD_EI && sp.kind < TR_PAR_NKIND &&
                                    sp.index >= 0 && sp.index < (m->nt > 0 ? m->nt : 1))) {
        glue_err(PyExc_ValueError, "path: parameter kind %d, index %d out of range", sp.kind,
                 sp.index);
        goto done;
    }
    out.cap = (int)cap;
    out.par = (double *)malloc((size_t)cap * (6 + 18 + m->nt + m->n_unknowns) * sizeof(double));
    out.stable = (int *)malloc((size_t)cap * 4 * sizeof(int));
    if (!out.par || !out.stable) {
        PyErr_NoMemory();
        goto done;
    }
    out.margin = out.par + cap;
    out.tlam = out.margin + cap;
    out.residual = out.tlam + cap;
    out.truncation = out.residual + cap;
    out.tip = out.truncation + cap;
    out.tension = out.tip + 18 * cap;
    out.x = out.tension + (size_t)cap * m->nt;
    out.kind = out.stable + cap;
    out.branch = out.kind + cap;
    out.steps = out.branch + cap;
    tr_data_set_lazy(d, 1);
    tr_set_poll(d, glue_poll_hook, &poll);
    Py_BEGIN_ALLOW_THREADS;
    status = tr_path(m, d, &sp, &out);
    Py_END_ALLOW_THREADS;
    tr_set_poll(d, NULL, NULL);
    if (status == TR_EINVAL && out.n == 0) {
        glue_err(PyExc_ValueError, "path: %s", tr_data_message(d));
        goto done;
    }
    if (glue_poll_finish(&poll, status) == 0) result = result_of(m, d, &out, status);
done:
    free(out.par);
    free(out.stable);
    tr_data_free(d);
    tr_model_free(m);
    Py_XDECREF(kw);
    glue_args_clear(&a);
    return result;
}
