/*
 * _batch.c -- _core.solve_batch: n scenes of one robot design in one call
 * (csrc/tr_batch.h), the GIL released around the whole batch.
 */
#include "_glue.h"
#include "tr_batch.h"

/* Optional per-point array of shape (n, *tail) (tail of length ntail); *n < 0 means
 * "not known yet" and is set from the first array given.  0 or -1 with ValueError. */
static int batch_points(PyObject *obj, const char *name, const npy_intp *tail, int ntail,
                        const char *what, PyArrayObject **out, npy_intp *n)
{
    int j, ok;
    *out = NULL;
    if (obj == NULL || obj == Py_None) return 0;
    if (!(*out = glue_coerce(obj, name))) return -1;
    ok = PyArray_NDIM(*out) == 1 + ntail;
    for (j = 0; ok && j < ntail; j++) ok = PyArray_DIM(*out, 1 + j) == tail[j];
    if (ok && *n >= 0 && PyArray_DIM(*out, 0) != *n) ok = 0;
    if (!ok) {
        char shp[96];
        int o = snprintf(shp, sizeof shp, "(%s", *n >= 0 ? "" : "n");
        if (*n >= 0) o += snprintf(shp + o, sizeof shp - o, "%ld", (long)*n);
        for (j = 0; j < ntail && o < (int)sizeof shp; j++)
            o += snprintf(shp + o, sizeof shp - o, ", %ld", (long)tail[j]);
        if (o < (int)sizeof shp) snprintf(shp + o, sizeof shp - o, ")");
        PyErr_Format(PyExc_ValueError, "%s must have shape %s: %s (got ndim %d)", name, shp, what,
                     PyArray_NDIM(*out));
        Py_CLEAR(*out);
        return -1;
    }
    *n = PyArray_DIM(*out, 0);
    return 0;
}

/* The flag `key` of kw (removed from it), or `dflt`.  0 or -1. */
static int take_flag(PyObject *kw, const char *key, int dflt, int *out)
{
    PyObject *v = glue_take(kw, key);
    *out = dflt;
    if (v) {
        *out = PyObject_IsTrue(v);
        Py_DECREF(v);
    }
    return *out < 0 ? -1 : 0;
}

/* Output arrays of a batch of n points. */
typedef struct {
    PyObject *pos, *rot, *ten, *sla, *dis, *res, *sta, *nit, *nfe, *cld, *unk, *stp, *stb;
    char *mbuf; /* (n x TR_MSGLEN) messages, zeroed */
} batch_arrays;

static void arrays_clear(batch_arrays *b)
{
    Py_XDECREF(b->pos);
    Py_XDECREF(b->rot);
    Py_XDECREF(b->ten);
    Py_XDECREF(b->sla);
    Py_XDECREF(b->dis);
    Py_XDECREF(b->res);
    Py_XDECREF(b->sta);
    Py_XDECREF(b->nit);
    Py_XDECREF(b->nfe);
    Py_XDECREF(b->cld);
    Py_XDECREF(b->unk);
    Py_XDECREF(b->stp);
    Py_XDECREF(b->stb);
    free(b->mbuf);
}

static int arrays_alloc(batch_arrays *b, npy_intp n, int nt, int k, tr_batch_out *out)
{
    npy_intp d2[2] = {n, 3}, d3[3] = {n, 3, 3}, dt[2] = {n, nt}, d1[1] = {n}, dk[2] = {n, k};
    b->pos = PyArray_SimpleNew(2, d2, NPY_DOUBLE);
    b->rot = PyArray_SimpleNew(3, d3, NPY_DOUBLE);
    b->ten = PyArray_SimpleNew(2, dt, NPY_DOUBLE);
    b->sla = PyArray_SimpleNew(2, dt, NPY_DOUBLE);
    b->dis = PyArray_SimpleNew(2, dt, NPY_DOUBLE);
    b->res = PyArray_SimpleNew(1, d1, NPY_DOUBLE);
    b->sta = PyArray_SimpleNew(1, d1, NPY_INT);
    b->nit = PyArray_SimpleNew(1, d1, NPY_INT);
    b->nfe = PyArray_SimpleNew(1, d1, NPY_INT);
    b->cld = PyArray_SimpleNew(1, d1, NPY_INT);
    b->unk = PyArray_SimpleNew(2, dk, NPY_DOUBLE);
    b->stp = PyArray_SimpleNew(1, d1, NPY_INT);
    b->stb = PyArray_SimpleNew(1, d1, NPY_INT);
    /* zeroed: pages of points that converged are never written, so never resident */
    b->mbuf = (char *)calloc((size_t)(n > 0 ? n : 1), TR_MSGLEN);
    if (!b->pos || !b->rot || !b->ten || !b->sla || !b->dis || !b->res || !b->sta || !b->nit ||
        !b->nfe || !b->cld || !b->unk || !b->stp || !b->stb)
        return -1;
    if (!b->mbuf) {
        PyErr_NoMemory();
        return -1;
    }
#define GLUE_DATA(o, type) ((type *)PyArray_DATA((PyArrayObject *)(o)))
    out->tip_pos = GLUE_DATA(b->pos, double);
    out->tip_rot = GLUE_DATA(b->rot, double);
    out->tension = GLUE_DATA(b->ten, double);
    out->slack = GLUE_DATA(b->sla, double);
    out->displacement = GLUE_DATA(b->dis, double);
    out->residual = GLUE_DATA(b->res, double);
    out->status = GLUE_DATA(b->sta, int);
    out->nit = GLUE_DATA(b->nit, int);
    out->nfev = GLUE_DATA(b->nfe, int);
    out->cold = GLUE_DATA(b->cld, int);
    out->unknowns = GLUE_DATA(b->unk, double);
    out->steps = GLUE_DATA(b->stp, int);
    out->stable = GLUE_DATA(b->stb, int);
#undef GLUE_DATA
    out->message = b->mbuf;
    out->msglen = TR_MSGLEN;
    return 0;
}

/* The result dict (references to the arrays are added, not stolen). */
static PyObject *batch_result(const batch_arrays *b, npy_intp n, const tr_model *m, double tol)
{
    PyObject *result = PyDict_New(), *msgs = PyList_New(n), *form = NULL, *succ = NULL;
    const int *status = (const int *)PyArray_DATA((PyArrayObject *)b->sta);
    const int *nit = (const int *)PyArray_DATA((PyArrayObject *)b->nit);
    const double *res = (const double *)PyArray_DATA((PyArrayObject *)b->res);
    npy_intp i;
    if (!result || !msgs) goto fail;
    for (i = 0; i < n; i++) {
        char *mi = b->mbuf + (size_t)i * TR_MSGLEN;
        /* the batch stores no message for a converged point: the core's wording */
        if (status[i] == TR_OK && mi[0] == '\0')
            tr_message_converged(mi, TR_MSGLEN, nit[i], res[i], tol);
        const char *end = (const char *)memchr(mi, '\0', TR_MSGLEN);
        PyObject *s = PyUnicode_DecodeUTF8(mi, end ? (Py_ssize_t)(end - mi) : TR_MSGLEN, "replace");
        if (!s) goto fail;
        PyList_SET_ITEM(msgs, i, s);
    }
    /* the verdict per point: the core's rule (TR_SUCCEEDED) */
    if (!(succ = PyArray_SimpleNew(1, &n, NPY_BOOL))) goto fail;
    for (i = 0; i < n; i++)
        ((npy_bool *)PyArray_DATA((PyArrayObject *)succ))[i] = TR_SUCCEEDED(status[i]);
    form = PyDict_New();
    if (!form || glue_set(form, "planar", PyBool_FromLong(m->planar)) < 0 ||
        glue_set(form, "kirchhoff", PyBool_FromLong(m->kirchhoff)) < 0 ||
        glue_set(form, "n_unknowns", PyLong_FromLong(m->n_unknowns)) < 0 ||
        glue_set(form, "n_states", PyLong_FromLong(m->n_states)) < 0)
        goto fail;
    if (PyDict_SetItemString(result, "tip_position", b->pos) < 0 ||
        PyDict_SetItemString(result, "tip_rotation", b->rot) < 0 ||
        PyDict_SetItemString(result, "tension", b->ten) < 0 ||
        PyDict_SetItemString(result, "slack", b->sla) < 0 ||
        PyDict_SetItemString(result, "displacement", b->dis) < 0 ||
        PyDict_SetItemString(result, "residual_norm", b->res) < 0 ||
        PyDict_SetItemString(result, "status", b->sta) < 0 ||
        PyDict_SetItemString(result, "nit", b->nit) < 0 ||
        PyDict_SetItemString(result, "nfev", b->nfe) < 0 ||
        PyDict_SetItemString(result, "cold", b->cld) < 0 ||
        PyDict_SetItemString(result, "unknowns", b->unk) < 0 ||
        PyDict_SetItemString(result, "steps", b->stp) < 0 ||
        PyDict_SetItemString(result, "stable", b->stb) < 0 ||
        PyDict_SetItemString(result, "message", msgs) < 0 ||
        PyDict_SetItemString(result, "success", succ) < 0 ||
        PyDict_SetItemString(result, "formulation", form) < 0)
        goto fail;
    Py_DECREF(msgs);
    Py_DECREF(form);
    Py_DECREF(succ);
    return result;
fail:
    Py_XDECREF(result);
    Py_XDECREF(msgs);
    Py_XDECREF(form);
    Py_XDECREF(succ);
    return NULL;
}

const char glue_solve_batch_doc[] =
    "solve_batch(rod, tendons, loads, dist, *, values=None, point_loads=None, dists=None,\n"
    "            warm=True, retry_cold=False, predict=True, exact=False,\n"
    "            skip_tension_displacement=False, **options) -> dict\n\n"
    "n scenes of one robot design in one call (csrc/tr_batch.h), the GIL released around the\n"
    "whole batch.  rod, tendons, loads, dist as for solve() fix the design, the control modes,\n"
    "the load positions and the formulation; per point vary: values (n, nt) actuation values\n"
    "(q [m] or tau [N] per the control column), point_loads (n, nl, 6) [F (3), M (3)] world,\n"
    "dists (n, 3) N/m world (None: the base value at every point; at least one must be given).\n"
    "warm: warm-start each point from the previous converged one (its base state and\n"
    "Jacobian, as solve(guess=previous) does); retry_cold: retry a failed warm start without a\n"
    "guess; predict: start from the extrapolation of the last converged points when the point\n"
    "continues their line, else from the nearer of the last one and the first point of their\n"
    "line.  steps > 0: warm points run the lean solve first (no step\n"
    "verification, no polish), falling back to the full solve on failure.  exact: reproduce a\n"
    "loop of solve(guess=previous tip-only solution) bit for bit (no predictor, no lean\n"
    "solve).  skip_tension_displacement: a point the lean solve solved skips the recording\n"
    "pass; the displacement of tension-controlled tendons is then NaN there.  options as for\n"
    "solve (nodes and tip_only do not apply).\n"
    "Returns a dict of arrays over the n points: tip_position (n,3) [m], tip_rotation (n,3,3),\n"
    "tension, slack, displacement (n,nt), residual_norm (n,), status, nit, nfev, cold (n,)\n"
    "int32, message (list of n str), formulation (dict: planar,\n"
    "kirchhoff, n_unknowns, n_states), unknowns (n, n_unknowns) each point's final scaled\n"
    "unknowns and steps (n,) int32 their step count (Problem.record_from's arguments), stable\n"
    "(n,) int32 each point's stability verdict (1 stable, 0 unstable, -1 not judged).\n";

PyObject *glue_solve_batch(PyObject *self, PyObject *args, PyObject *kwds)
{
    glue_args a;
    PyObject *rod, *tendons, *loads, *dist, *kw = NULL, *result = NULL;
    PyObject *o_values = NULL, *o_pl = NULL, *o_dists = NULL, *cancel = NULL;
    glue_poll poll;
    PyArrayObject *values = NULL, *pl = NULL, *dists = NULL;
    batch_arrays b;
    tr_batch_in in;
    tr_batch_out out;
    tr_model *m = NULL;
    npy_intp n = -1;
    char emsg[TR_MSGLEN];
    int status;

    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    memset(&in, 0, sizeof in);
    if (!PyArg_ParseTuple(args, "OOOO", &rod, &tendons, &loads, &dist)) return NULL;
    if (kwds && !(kw = PyDict_Copy(kwds))) return NULL;
    o_values = glue_take(kw, "values");
    o_pl = glue_take(kw, "point_loads");
    o_dists = glue_take(kw, "dists");
    cancel = glue_take(kw, "cancel");
    if (glue_poll_init(&poll, cancel) < 0) goto done;
    if (take_flag(kw, "warm", 1, &in.warm) < 0 ||
        take_flag(kw, "retry_cold", 0, &in.retry_cold) < 0 ||
        take_flag(kw, "predict", 1, &in.predict) < 0 || take_flag(kw, "exact", 0, &in.exact) < 0 ||
        take_flag(kw, "skip_tension_displacement", 0, &in.skip_tension_displacement) < 0)
        goto done;
    if (glue_scene(&a, rod, tendons, loads, dist) < 0 || glue_options(&a, kw, "solve_batch") < 0)
        goto done;
    a.opt.tip_only = 1;
    {
        npy_intp tv[1] = {a.nt}, tl[2] = {a.nl, 6}, td[1] = {3};
        if (batch_points(o_values, "values", tv, 1, "an actuation value per point and tendon",
                         &values, &n) < 0 ||
            batch_points(o_pl, "point_loads", tl, 2, "[F (3), M (3)] per point and point load", &pl,
                         &n) < 0 ||
            batch_points(o_dists, "dists", td, 1, "a distributed force per point", &dists, &n) < 0)
            goto done;
    }
    if (n < 0) {
        PyErr_SetString(PyExc_ValueError, "solve_batch needs at least one of values, point_loads, "
                                          "dists (they set the number of points)");
        goto done;
    }
    if (n > INT_MAX / 2) {
        PyErr_Format(PyExc_ValueError, "solve_batch: n = %ld points is too many for one call",
                     (long)n);
        goto done;
    }
    if (glue_build(&a, NULL, &m, NULL) < 0 || arrays_alloc(&b, n, a.nt, m->n_unknowns, &out) < 0)
        goto done;
    in.n = (int)n;
    in.value = values ? (const double *)PyArray_DATA(values) : NULL;
    in.load = pl ? (const double *)PyArray_DATA(pl) : NULL;
    in.dist = dists ? (const double *)PyArray_DATA(dists) : NULL;
    in.poll = glue_poll_hook;
    in.poll_ctx = &poll;
    Py_BEGIN_ALLOW_THREADS;
    status = tr_batch_solve(m, &a.opt, &in, &out, emsg, sizeof emsg);
    Py_END_ALLOW_THREADS;
    if (glue_poll_finish(&poll, status) < 0) goto done;
    if (status != TR_OK) {
        if (status == TR_ENOMEM)
            PyErr_NoMemory();
        else
            PyErr_SetString(PyExc_ValueError, emsg);
        goto done;
    }
    result = batch_result(&b, n, m, a.opt.tol);
done:
    arrays_clear(&b);
    Py_XDECREF(values);
    Py_XDECREF(pl);
    Py_XDECREF(dists);
    Py_XDECREF(o_values);
    Py_XDECREF(o_pl);
    Py_XDECREF(o_dists);
    Py_XDECREF(cancel);
    Py_XDECREF(kw);
    tr_model_free(m);
    glue_args_clear(&a);
    return result;
}
