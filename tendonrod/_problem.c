/*
 * _problem.c -- _core.Problem: a scene's structure compiled once into a model and a
 * workspace that live as long as the object.  Per call only values change
 * (set_values); the last successful solution (unknowns, Jacobian, verified step count)
 * stays in the workspace between calls, so a warm solve ships nothing through Python.
 * One thread at a time: a call while another thread is inside a solve of the same
 * object raises RuntimeError.
 */
#include "_glue.h"

PyObject *glue_problem_form(ProblemObject *self)
{
    if (!self->form) self->form = glue_formulation(self->m, self->d);
    return self->form;
}

int glue_problem_check(ProblemObject *self)
{
    if (!self->m || !self->d) {
        PyErr_SetString(PyExc_RuntimeError, "Problem is not initialised");
        return -1;
    }
    if (self->busy) {
        PyErr_SetString(PyExc_RuntimeError,
                        "this Problem is being solved in another thread: a Problem belongs to "
                        "one thread at a time (make one per worker)");
        return -1;
    }
    return 0;
}

PyArrayObject *glue_problem_unknowns(const ProblemObject *self, PyObject *obj)
{
    PyArrayObject *x = glue_coerce(obj, "unknowns");
    if (x && PyArray_SIZE(x) != self->m->n_unknowns) {
        PyErr_Format(PyExc_ValueError, "unknowns must have %d values, got %ld", self->m->n_unknowns,
                     (long)PyArray_SIZE(x));
        Py_CLEAR(x);
    }
    return x;
}

static void problem_dealloc(ProblemObject *self)
{
    Py_XDECREF(self->form);
    tr_data_free(self->d);
    tr_model_free(self->m);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

static int problem_init(ProblemObject *self, PyObject *args, PyObject *kwds)
{
    glue_args a;
    PyObject *rod, *tendons, *loads, *dist, *kw = NULL;
    tr_model *m = NULL;
    tr_data *d = NULL;
    int r = -1;
    memset(&a, 0, sizeof a);
    if (self->m) {
        PyErr_SetString(PyExc_RuntimeError, "Problem is already initialised");
        return -1;
    }
    if (!PyArg_ParseTuple(args, "OOOO", &rod, &tendons, &loads, &dist)) return -1;
    if (kwds && !(kw = PyDict_Copy(kwds))) return -1;
    if (glue_scene(&a, rod, tendons, loads, dist) == 0 && glue_options(&a, kw, "Problem") == 0 &&
        glue_build(&a, NULL, &m, &d) == 0) {
        self->m = m;
        self->d = d;
        self->nnode_req = a.nnode;
        self->last_status = TR_CONTINUE;
        r = 0;
    }
    Py_XDECREF(kw);
    glue_args_clear(&a);
    return r;
}

/* An optional float64 array of exactly n values (a 1-D or any shape of that size). */
static int values_of(PyObject *obj, const char *name, npy_intp n, PyArrayObject **out)
{
    *out = NULL;
    if (obj == NULL || obj == Py_None) return 0;
    if (!(*out = glue_coerce(obj, name))) return -1;
    if (PyArray_SIZE(*out) != n) {
        PyErr_Format(PyExc_ValueError, "%s must have %ld values, got %ld", name, (long)n,
                     (long)PyArray_SIZE(*out));
        Py_CLEAR(*out);
        return -1;
    }
    return 0;
}

#define DATA_OR_NULL(a) ((a) ? (const double *)PyArray_DATA(a) : NULL)

static PyObject *problem_set_values(ProblemObject *self, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"values", "point_loads", "dist", "pretension", NULL};
    PyObject *ov = Py_None, *ol = Py_None, *od = Py_None, *op = Py_None, *result = NULL;
    PyArrayObject *v = NULL, *l = NULL, *dd = NULL, *p = NULL;
    char msg[TR_MSGLEN];
    if (glue_problem_check(self) < 0) return NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "|$OOOO", kwlist, &ov, &ol, &od, &op)) return NULL;
    if (values_of(ov, "values", self->m->nt, &v) < 0 ||
        values_of(ol, "point_loads", 6 * (npy_intp)self->m->nl, &l) < 0 ||
        values_of(od, "dist", 3, &dd) < 0 || values_of(op, "pretension", self->m->nt, &p) < 0)
        goto done;
    if (tr_data_set_values(self->m, self->d, DATA_OR_NULL(v), DATA_OR_NULL(l), DATA_OR_NULL(dd),
                           msg, sizeof msg) != TR_OK ||
        (p &&
         tr_data_set_pretension(self->m, self->d, DATA_OR_NULL(p), msg, sizeof msg) != TR_OK)) {
        PyErr_SetString(PyExc_ValueError, msg);
        goto done;
    }
    result = Py_NewRef(Py_None);
done:
    Py_XDECREF(v);
    Py_XDECREF(l);
    Py_XDECREF(dd);
    Py_XDECREF(p);
    return result;
}

/* The values of one scene in one vector, [values (nt), point loads (nl x 6), dist (3)]:
 * the per-call path of Problem.solve (one argument to check, one array to read). */
static PyObject *problem_set_value_vector(ProblemObject *self, PyObject *arg)
{
    const tr_model *m = self->m;
    PyArrayObject *v = NULL;
    PyObject *result = NULL;
    char msg[TR_MSGLEN];
    const double *p;
    if (glue_problem_check(self) < 0) return NULL;
    if (values_of(arg, "value vector", m->nt + 6 * (npy_intp)m->nl + 3, &v) < 0) return NULL;
    p = (const double *)PyArray_DATA(v);
    if (tr_data_set_values(m, self->d, p, p + m->nt, p + m->nt + 6 * m->nl, msg, sizeof msg) !=
        TR_OK) {
        PyErr_SetString(PyExc_ValueError, msg);
        goto done;
    }
    result = Py_NewRef(Py_None);
done:
    Py_DECREF(v);
    return result;
}

/* Whether the point loads and the distributed force of a value vector (as for
 * set_value_vector) keep to the x-z plane: tr_is_planar on them alone (the tendons and
 * the partial distributed loads are the structure's). */
static PyObject *problem_values_planar(ProblemObject *self, PyObject *arg)
{
    const tr_model *m = self->m;
    PyArrayObject *v = NULL;
    double *rows;
    const double *p;
    int i, c, planar;
    if (glue_problem_check(self) < 0) return NULL;
    if (values_of(arg, "value vector", m->nt + 6 * (npy_intp)m->nl + 3, &v) < 0) return NULL;
    p = (const double *)PyArray_DATA(v) + m->nt;
    rows = PyMem_Malloc(sizeof(double) * TR_LD_NCOL * (size_t)(m->nl > 0 ? m->nl : 1));
    if (!rows) {
        Py_DECREF(v);
        return PyErr_NoMemory();
    }
    for (i = 0; i < m->nl; i++) {
        rows[TR_LD_NCOL * i + TR_LD_S] = 0.0;
        for (c = 0; c < 6; c++) rows[TR_LD_NCOL * i + TR_LD_F + c] = p[6 * i + c];
    }
    planar = tr_is_planar(NULL, 0, rows, m->nl, p + 6 * m->nl);
    PyMem_Free(rows);
    Py_DECREF(v);
    return PyBool_FromLong(planar);
}

static PyObject *problem_set_target(ProblemObject *self, PyObject *args)
{
    int kind, i, n, status, idx[3];
    PyObject *ov, *ot;
    PyArrayObject *v = NULL, *t = NULL;
    char msg[TR_MSGLEN];
    double val[3] = {0.0, 0.0, 0.0};
    if (glue_problem_check(self) < 0) return NULL;
    if (!PyArg_ParseTuple(args, "iOO", &kind, &ov, &ot)) return NULL;
    if (!(v = glue_coerce(ov, "values")) || !(t = glue_coerce(ot, "tendons"))) goto fail;
    n = (int)PyArray_SIZE(t);
    if (PyArray_NDIM(v) != 1 || PyArray_DIM(v, 0) > 3 || PyArray_NDIM(t) != 1 || n > 3) {
        PyErr_SetString(PyExc_ValueError, "values and tendons must be 1-D with at most 3 entries");
        goto fail;
    }
    for (i = 0; i < PyArray_DIM(v, 0); i++) val[i] = ((const double *)PyArray_DATA(v))[i];
    for (i = 0; i < n; i++) {
        const double x = ((const double *)PyArray_DATA(t))[i];
        if (!(x == floor(x) && fabs(x) < 1e9)) {
            glue_err(PyExc_ValueError, "tendons must hold tendon indices, got %g", x);
            goto fail;
        }
        idx[i] = (int)x;
    }
    status = tr_data_set_target(self->m, self->d, kind, val, idx, n, msg, sizeof msg);
    Py_DECREF(v);
    Py_DECREF(t);
    if (status != TR_OK) {
        PyErr_SetString(PyExc_ValueError, msg);
        return NULL;
    }
    self->last_status = TR_CONTINUE; /* the last solve solved another system */
    Py_RETURN_NONE;
fail:
    Py_XDECREF(v);
    Py_XDECREF(t);
    return NULL;
}

/* The keyword-only arguments of solve, in the order of SOLVE_KW. */
enum { KW_GUESS, KW_JACOBIAN, KW_VERIFIED, KW_WARM, KW_CANCEL, KW_RECORD, KW_CARRY, KW_N };
static const char *const SOLVE_KW[KW_N] = {"guess",  "jacobian", "verified", "warm",
                                           "cancel", "record",   "carry"};

/* The vectorcall arguments of solve into val[KW_N] (borrowed; unset ones keep their
 * value): keywords only, each at most once, by name; the flags through truth. */
static int solve_keywords(PyObject *const *args, Py_ssize_t nargs, PyObject *kwnames,
                          PyObject **val, int *warm, int *record)
{
    Py_ssize_t nkw = kwnames ? PyTuple_GET_SIZE(kwnames) : 0;
    int seen = 0;
    if (nargs) {
        PyErr_Format(PyExc_TypeError, "solve() takes no positional arguments (%zd given)", nargs);
        return -1;
    }
    for (Py_ssize_t i = 0; i < nkw; i++) {
        PyObject *name = PyTuple_GET_ITEM(kwnames, i);
        int k = 0;
        while (k < KW_N && PyUnicode_CompareWithASCIIString(name, SOLVE_KW[k]) != 0) k++;
        if (k == KW_N || (seen & (1 << k))) {
            PyErr_Format(PyExc_TypeError, "solve() got %s keyword argument '%U'",
                         k == KW_N ? "an unexpected" : "multiple values for", name);
            return -1;
        }
        seen |= 1 << k;
        val[k] = args[i];
    }
    if (seen & (1 << KW_WARM) && (*warm = PyObject_IsTrue(val[KW_WARM])) < 0) return -1;
    if (seen & (1 << KW_RECORD) && (*record = PyObject_IsTrue(val[KW_RECORD])) < 0) return -1;
    return 0;
}

static PyObject *problem_solve(ProblemObject *self, PyObject *const *args, Py_ssize_t nargs,
                               PyObject *kwnames)
{
    PyObject *val[KW_N] = {Py_None, Py_None, Py_None, Py_None, Py_None, Py_None, Py_None};
    PyObject *og, *oj, *ov, *cancel, *oc, *result = NULL;
    PyArrayObject *xv = NULL, *vv = NULL;
    glue_args a;
    glue_poll poll;
    tr_data *d = self->d;
    tr_verified ver = {0, 0.0, NULL, NULL};
    const double *g = NULL, *jac = NULL;
    int warm = 1, record = 1, status;
    memset(&a, 0, sizeof a);
    if (glue_problem_check(self) < 0) return NULL;
    if (solve_keywords(args, nargs, kwnames, val, &warm, &record) < 0) return NULL;
    og = val[KW_GUESS], oj = val[KW_JACOBIAN], ov = val[KW_VERIFIED];
    cancel = val[KW_CANCEL], oc = val[KW_CARRY];
    a.nt = self->m->nt;
    if (glue_poll_init(&poll, cancel) < 0 || glue_warm_start(&a, og, oj) < 0) goto done;
    if (ov != Py_None) {
        /* (steps, estimate, scaled unknowns) of the guess's step verification */
        PyObject *ox, *oval = Py_None;
        if (!PyArg_ParseTuple(ov, "idO|O;verified must be (steps, estimate, unknowns[, values])",
                              &ver.steps, &ver.estimate, &ox, &oval) ||
            values_of(ox, "verified unknowns", self->m->n_unknowns, &xv) < 0 ||
            (oval != Py_None && values_of(oval, "verified values", self->m->nt, &vv) < 0))
            goto done;
        if (ver.steps < 1 || ver.steps > TR_MAX_STEPS || !(ver.estimate >= 0.0) ||
            !isfinite(ver.estimate) || glue_all_finite(xv, "verified unknowns", -1, 0) < 0) {
            if (!PyErr_Occurred())
                glue_err(PyExc_ValueError,
                         "verified: steps must be in [1, %d] and the estimate finite and >= 0, "
                         "got steps = %d, estimate = %g",
                         TR_MAX_STEPS, ver.steps, ver.estimate);
            goto done;
        }
        ver.x = (const double *)PyArray_DATA(xv);
        if (vv && glue_all_finite(vv, "verified values", -1, 0) < 0) goto done;
        ver.values = vv ? (const double *)PyArray_DATA(vv) : NULL;
    }
    if (oc != Py_None) {
        /* (record, reason): the verdict record of the solution the guess came from; one of
         * another model (its breakpoints differ) is ignored: the solve judges afresh */
        PyObject *orec;
        PyArrayObject *rec;
        const char *reason;
        if (!PyArg_ParseTuple(oc, "Os;carry must be (record, reason)", &orec, &reason) ||
            !(rec = glue_coerce(orec, "carry record")))
            goto done;
        if (PyArray_SIZE(rec) == tr_carry_len(self->m, d))
            tr_carry_set(self->m, d, (const double *)PyArray_DATA(rec), tr_carry_len(self->m, d),
                         reason);
        Py_DECREF(rec);
    }
    g = a.guess ? (const double *)PyArray_DATA(a.guess) : NULL;
    if (a.jac && PyArray_DIM(a.jac, 0) == self->m->n_unknowns)
        jac = (const double *)PyArray_DATA(a.jac);
    tr_data_set_lazy(d, !record);
    tr_set_poll(d, glue_poll_hook, &poll);
    self->busy = 1;
    Py_BEGIN_ALLOW_THREADS;
    if (g)
        status = tr_solve_from(self->m, d, g, jac, ver.x ? &ver : NULL);
    else if (warm)
        status = tr_solve_warm(self->m, d);
    else
        status = tr_solve(self->m, d, NULL, NULL);
    Py_END_ALLOW_THREADS;
    self->busy = 0;
    tr_set_poll(d, NULL, NULL);
    self->last_status = status;
    if (glue_poll_finish(&poll, status) == 0 && glue_problem_form(self))
        result = record ? glue_solve_result(self->m, d, status, self->form)
                        : glue_result_new(self->m, d, status, self->form);
done:
    tr_data_set_lazy(d, 0);
    Py_XDECREF(xv);
    Py_XDECREF(vv);
    glue_args_clear(&a);
    return result;
}

static PyObject *problem_record_from(ProblemObject *self, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"unknowns", "steps", NULL};
    PyObject *ox, *result = NULL;
    PyArrayObject *x = NULL;
    int steps, status;
    if (glue_problem_check(self) < 0) return NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "Oi", kwlist, &ox, &steps)) return NULL;
    if (values_of(ox, "unknowns", self->m->n_unknowns, &x) < 0) return NULL;
    self->busy = 1;
    Py_BEGIN_ALLOW_THREADS;
    status = tr_record_from(self->m, self->d, (const double *)PyArray_DATA(x), steps);
    Py_END_ALLOW_THREADS;
    self->busy = 0;
    if (status == TR_EINVAL) {
        glue_err(PyExc_ValueError, "record_from: %s", tr_data_message(self->d));
        goto done;
    }
    /* a recording that fails (the last iterate of a failed solve) has NaN states */
    if (glue_problem_form(self)) result = glue_solve_result(self->m, self->d, status, self->form);
done:
    Py_XDECREF(x);
    return result;
}

static PyObject *problem_stability(ProblemObject *self, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"unknowns", "steps", "quick", NULL};
    PyObject *ox, *result = NULL;
    PyArrayObject *x = NULL;
    int steps, status, quick = 0;
    tr_data *d = self->d;
    if (glue_problem_check(self) < 0) return NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "Oi|p", kwlist, &ox, &steps, &quick)) return NULL;
    if (values_of(ox, "unknowns", self->m->n_unknowns, &x) < 0) return NULL;
    self->busy = 1;
    Py_BEGIN_ALLOW_THREADS;
    status = tr_stability_of(self->m, d, (const double *)PyArray_DATA(x), steps, quick);
    Py_END_ALLOW_THREADS;
    self->busy = 0;
    if (status == TR_EINVAL) {
        glue_err(PyExc_ValueError, "stability: %s", tr_data_message(d));
        goto done;
    }
    {
        tr_verdict v;
        tr_data_verdict(d, &v);
        result = Py_BuildValue("{s:N,s:d,s:i,s:s}", "stable",
                               v.stable < 0 ? Py_NewRef(Py_None) : PyBool_FromLong(v.stable),
                               "stability", v.margin, "index", v.index, "reason", v.reason);
    }
done:
    Py_XDECREF(x);
    return result;
}

static PyObject *problem_compliance(ProblemObject *self, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"s", "cancel", NULL};
    PyObject *cancel = Py_None;
    glue_poll poll;
    double s, C[36];
    npy_intp dims[2] = {6, 6};
    int status;
    if (glue_problem_check(self) < 0) return NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "d|$O", kwlist, &s, &cancel)) return NULL;
    if (glue_poll_init(&poll, cancel) < 0) return NULL;
    if (!TR_SUCCEEDED(self->last_status)) {
        PyErr_SetString(PyExc_RuntimeError,
                        "compliance needs a successful solve of this Problem first");
        return NULL;
    }
    tr_set_poll(self->d, glue_poll_hook, &poll);
    self->busy = 1;
    Py_BEGIN_ALLOW_THREADS;
    status = tr_compliance(self->m, self->d, s, C);
    Py_END_ALLOW_THREADS;
    self->busy = 0;
    tr_set_poll(self->d, NULL, NULL);
    if (glue_poll_finish(&poll, status) < 0) return NULL;
    if (status != TR_OK) {
        glue_err(status == TR_EINVAL ? PyExc_ValueError : PyExc_RuntimeError, "%s",
                 tr_data_message(self->d));
        return NULL;
    }
    return glue_array(2, dims, C);
}

/* The (np, 2) [kind, index] rows of the parameters of a linearisation into par. */
static int params_of(PyArrayObject *a, tr_param *par, npy_intp np)
{
    const double *v = (const double *)PyArray_DATA(a);
    npy_intp j;
    for (j = 0; j < 2 * np; j++)
        if (!(v[j] == floor(v[j]) && fabs(v[j]) < 1e9)) {
            glue_err(PyExc_ValueError, "params must hold integers [kind, index], got %g", v[j]);
            return -1;
        }
    for (j = 0; j < np; j++) {
        par[j].kind = (int)v[2 * j];
        par[j].index = (int)v[2 * j + 1];
    }
    return 0;
}

static PyObject *problem_linearize(ProblemObject *self, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"params", "rows", "forward", "unknowns",
                             "steps",  "side", "cancel",  NULL};
    PyObject *op, *orows, *cancel = Py_None, *result = NULL, *pose = NULL, *ten = NULL, *sl = NULL;
    PyObject *sw = NULL, *ox = Py_None, *oside = Py_None, *jac = NULL;
    PyArrayObject *pa = NULL, *ra = NULL, *xa = NULL, *sa = NULL;
    tr_param *par = NULL;
    int *rows = NULL, *at_switch = NULL, status, forward = 0, steps = 0;
    npy_intp np_, nrow, i, nt = self->m ? self->m->nt : 0, dims[3];
    glue_poll poll;
    if (glue_problem_check(self) < 0) return NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OO|$pOiOO", kwlist, &op, &orows, &forward, &ox,
                                     &steps, &oside, &cancel))
        return NULL;
    if (ox != Py_None) {
        /* the state of a converged solution of this structure, set without solving */
        if (values_of(ox, "unknowns", self->m->n_unknowns, &xa) < 0) return NULL;
        status = tr_state_from(self->m, self->d, (const double *)PyArray_DATA(xa), steps);
        Py_DECREF(xa);
        self->last_status = TR_CONTINUE; /* the workspace no longer holds its last solve */
        if (status != TR_OK) {
            glue_err(PyExc_ValueError, "linearize: %s", tr_data_message(self->d));
            return NULL;
        }
    } else if (!TR_SUCCEEDED(self->last_status)) {
        PyErr_SetString(PyExc_RuntimeError,
                        "linearize needs a successful solve of this Problem first");
        return NULL;
    }
    if (glue_poll_init(&poll, cancel) < 0 || !(pa = glue_coerce(op, "params")) ||
        !(ra = glue_coerce(orows, "rows")))
        goto done;
    if (!(PyArray_NDIM(pa) == 2 && PyArray_DIM(pa, 1) == 2) || PyArray_NDIM(ra) != 1) {
        PyErr_SetString(PyExc_ValueError, "params must be (np, 2) [kind, index], rows (nrow,)");
        goto done;
    }
    np_ = PyArray_DIM(pa, 0);
    nrow = PyArray_DIM(ra, 0);
    par = (tr_param *)PyMem_Calloc((size_t)np_ + 1, sizeof(tr_param));
    rows = (int *)PyMem_Calloc((size_t)(nrow + nt) + 1, sizeof(int));
    if (!par || !rows) {
        PyErr_NoMemory();
        goto done;
    }
    at_switch = rows + nrow;
    if (params_of(pa, par, np_) < 0) goto done;
    if (oside != Py_None) {
        /* the side wanted for each tendon at its switch (+1, -1, 0) */
        if (!(sa = glue_coerce(oside, "side"))) goto done;
        if (PyArray_NDIM(sa) != 1 || PyArray_DIM(sa, 0) != nt) {
            glue_err(PyExc_ValueError, "side must have shape (%ld,) (one per tendon)", (long)nt);
            goto done;
        }
        for (i = 0; i < nt; i++) {
            const double v = ((const double *)PyArray_DATA(sa))[i];
            if (!(v == 1.0 || v == -1.0 || v == 0.0)) {
                glue_err(PyExc_ValueError, "side must hold +1, -1 or 0, got %g", v);
                goto done;
            }
            at_switch[i] = (int)v;
        }
    }
    for (i = 0; i < nrow; i++) {
        const double r = ((const double *)PyArray_DATA(ra))[i];
        if (!(r == floor(r) && fabs(r) < 1e9)) {
            glue_err(PyExc_ValueError, "rows must hold breakpoint indices, got %g", r);
            goto done;
        }
        rows[i] = (int)r;
    }
    dims[0] = np_;
    dims[1] = nrow;
    dims[2] = 6;
    if (!(pose = glue_array(3, dims, NULL))) goto done;
    dims[1] = nt;
    if (!(ten = glue_array(2, dims, NULL)) || !(sl = glue_array(2, dims, NULL))) goto done;
    tr_set_poll(self->d, glue_poll_hook, &poll);
    self->busy = 1;
    Py_BEGIN_ALLOW_THREADS;
    status = tr_linearize(self->m, self->d, par, (int)np_, rows, (int)nrow,
                          (double *)PyArray_DATA((PyArrayObject *)pose),
                          (double *)PyArray_DATA((PyArrayObject *)ten),
                          (double *)PyArray_DATA((PyArrayObject *)sl), at_switch,
                          forward ? TR_DIFF_FORWARD : TR_DIFF_CENTRAL);
    Py_END_ALLOW_THREADS;
    self->busy = 0;
    tr_set_poll(self->d, NULL, NULL);
    if (glue_poll_finish(&poll, status) < 0) goto done;
    if (status != TR_OK) {
        glue_err(status == TR_EINVAL ? PyExc_ValueError : PyExc_RuntimeError, "%s",
                 tr_data_message(self->d));
        goto done;
    }
    if (!(sw = PyTuple_New(nt))) goto done;
    for (i = 0; i < nt; i++) PyTuple_SET_ITEM(sw, i, PyLong_FromLong(at_switch[i]));
    /* the shooting Jacobian at the state (scaled), for a solve from a nearby state */
    dims[0] = dims[1] = self->m->n_unknowns;
    {
        tr_outputs o;
        tr_data_outputs(self->d, &o);
        if (!(jac = glue_array(2, dims, o.J))) goto done;
    }
    result = Py_BuildValue("{s:O,s:O,s:O,s:O,s:i,s:O}", "pose", pose, "tension", ten, "slack", sl,
                           "at_switch", sw, "k", self->m->n_unknowns, "jacobian", jac);
done:
    Py_XDECREF(pose);
    Py_XDECREF(ten);
    Py_XDECREF(sl);
    Py_XDECREF(sw);
    Py_XDECREF(jac);
    Py_XDECREF(pa);
    Py_XDECREF(ra);
    Py_XDECREF(sa);
    PyMem_Free(par);
    PyMem_Free(rows);
    return result;
}

static PyObject *problem_forget(ProblemObject *self, PyObject *unused)
{
    if (glue_problem_check(self) < 0) return NULL;
    tr_forget(self->d);
    self->last_status = TR_CONTINUE;
    Py_RETURN_NONE;
}

static PyObject *problem_formulation(ProblemObject *self, void *closure)
{
    if (glue_problem_check(self) < 0) return NULL;
    return glue_formulation(self->m, self->d);
}

static PyObject *problem_last_success(ProblemObject *self, void *closure)
{
    return PyBool_FromLong(TR_SUCCEEDED(self->last_status));
}

static PyObject *problem_has_solution(ProblemObject *self, void *closure)
{
    return PyBool_FromLong(self->d && tr_data_has_last(self->d));
}

static PyObject *problem_breakpoints(ProblemObject *self, void *closure)
{
    npy_intp n;
    if (glue_problem_check(self) < 0) return NULL;
    n = self->m->nseg + 1;
    return glue_array(1, &n, self->m->bp);
}

static PyMethodDef problem_methods[] = {
    {"set_values", (PyCFunction)(void (*)(void))problem_set_values, METH_VARARGS | METH_KEYWORDS,
     "set_values(*, values=None, point_loads=None, dist=None, pretension=None): the per-call\n"
     "values (nt actuation values, nl x 6 point-load forces and moments, the distributed\n"
     "force, nt pretensions); None keeps what is set.  ValueError naming a bad value."},
    {"set_value_vector", (PyCFunction)problem_set_value_vector, METH_O,
     "set_value_vector(v): v = [values (nt), point loads (nl x 6), dist (3)] in one float64\n"
     "vector (the per-call values of set_values without the pretensions)."},
    {"values_planar", (PyCFunction)problem_values_planar, METH_O,
     "values_planar(v) -> bool: whether the point loads and the distributed force of the value\n"
     "vector v (as for set_value_vector) keep to the x-z plane (tr_is_planar on them alone)."},
    {"set_target", (PyCFunction)problem_set_target, METH_VARARGS,
     "set_target(kind, values, tendons): the residual of a tip target (kind 1 angle [rad]\n"
     "(planar), 2 direction (3), 3 position (3) [m] world; 0 none) replaces the length\n"
     "constraints of the displacement-controlled tendons `tendons`, one per component\n"
     "(tr_data_set_target); a solve then reports the displacements that reach it.\n"
     "ValueError naming what is wrong."},
    {"solve", (PyCFunction)(void (*)(void))problem_solve, METH_FASTCALL | METH_KEYWORDS,
     "solve(*, guess=None, jacobian=None, verified=None, warm=True, cancel=None, record=True,\n"
     "carry=None)\n"
     "-> dict: from the guess (a base_state) if given, else warm from the last successful solve\n"
     "(warm=True; cold if there is none), else cold.  verified: (steps, estimate, unknowns[,\n"
     "values]), the 'formulation' steps, 'verified_estimate', 'verified_unknowns' and\n"
     "'verified_values' of the solve the guess came from (same structure): its verified step\n"
     "count is the start and vouches for a solution close to it (values None: a model with a\n"
     "tension-controlled tendon then verifies afresh).  carry: the 'stability_carry' of that "
     "solve, its verdict record,\n"
     "which a solution close to it keeps instead of being judged again (one of another model\n"
     "is ignored).  The dict of\n"
     "_core.solve; record=False leaves out the node arrays (record_from computes them) and\n"
     "returns a _core.Result instead (the same keys, each built on first access).\n"
     "Ctrl-C raises KeyboardInterrupt."},
    {"record_from", (PyCFunction)(void (*)(void))problem_record_from, METH_VARARGS | METH_KEYWORDS,
     "record_from(unknowns, steps) -> dict: the states at this problem's nodes of the solution\n"
     "with these scaled unknowns at this step count (no solve; NaN where the recording fails)."},
    {"stability", (PyCFunction)(void (*)(void))problem_stability, METH_VARARGS | METH_KEYWORDS,
     "stability(unknowns, steps, quick=False) -> dict(stable, stability, index, reason): whether\n"
     "the solution\n"
     "with these scaled unknowns at this step count is a strict local minimum of the total\n"
     "potential energy (True / False / None with the reason), the margin (the smallest\n"
     "eigenvalue of the constrained second variation, scaled by EI/L) and the number of\n"
     "negative modes (no solve)."},
    {"compliance", (PyCFunction)(void (*)(void))problem_compliance, METH_VARARGS | METH_KEYWORDS,
     "compliance(s, *, cancel=None) -> (6, 6): at breakpoint s [m] of the last successful\n"
     "solve (spatial formulation only)."},
    {"linearize", (PyCFunction)(void (*)(void))problem_linearize, METH_VARARGS | METH_KEYWORDS,
     "linearize(params, rows, *, forward=False, unknowns=None, steps=0, side=None, cancel=None)\n"
     "-> dict:\n"
     "the linearisation (tr_linearize; forward: first-order differences) of the last successful\n"
     "solve, or of the converged solution with these scaled unknowns at this step count (then\n"
     "the workspace no longer holds its last solve), with respect to params, (np, 2) rows\n"
     "[kind, index] (kinds: PARAM_KINDS),\n"
     "reporting the poses at breakpoint indices rows (nrow,): pose (np, nrow, 6) [dx (3) m,\n"
     "dtheta (3) rad] world frame per unit parameter, tension (np, nt) [N per unit], slack\n"
     "(np, nt) [m per unit], at_switch\n"
     "(nt ints: the side of its taut/slack switch a tendon there was given, +1 taut, -1 slack,\n"
     "0 not at the switch; side (nt,) asks +1 / -1 for a displacement-controlled tendon at its\n"
     "switch, 0 the side it is on), k (unknowns).  ValueError\n"
     "for a parameter the model lacks."},
    {"actuate", (PyCFunction)(void (*)(void))glue_problem_actuate, METH_VARARGS | METH_KEYWORDS,
     glue_problem_actuate_doc},
    {"forget", (PyCFunction)problem_forget, METH_NOARGS,
     "Forget the last solution (the next warm solve starts cold)."},
    {NULL, NULL, 0, NULL}};

static PyGetSetDef problem_getset[] = {
    {"formulation", (getter)problem_formulation, NULL, "What the scene compiled to (dict).", NULL},
    {"last_success", (getter)problem_last_success, NULL,
     "True when the last solve succeeded (its state is the workspace's).", NULL},
    {"has_solution", (getter)problem_has_solution, NULL,
     "True once a solve succeeded (a warm start is kept).", NULL},
    {"breakpoints", (getter)problem_breakpoints, NULL,
     "Breakpoint arc lengths [m] (nseg + 1,): anchors, point loads, shooting nodes.", NULL},
    {NULL, NULL, NULL, NULL, NULL}};

PyTypeObject glue_problem_type = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "tendonrod._core.Problem",
    .tp_basicsize = sizeof(ProblemObject),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "Problem(rod, tendons, loads, dist, **options): a compiled scene structure with\n"
              "its workspace (the raw contract of _core.solve).  See tendonrod.Problem.",
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)problem_init,
    .tp_dealloc = (destructor)problem_dealloc,
    .tp_methods = problem_methods,
    .tp_getset = problem_getset,
};
