/*
 * _simulate.c -- _core.simulate: the dynamics in time of a compiled Problem from one of
 * its solutions (tr_dyn_run, csrc/tr_dyn.h).
 */
#include "_glue.h"
#include "tr_dyn.h"

const char glue_simulate_doc[] =
    "simulate(problem, unknowns, values, loads, dt, *, alpha=0.0, rho_a, rho_j, eta=0.0,\n"
    "         drag=0.0, max_iter=8, backbone=False, resume=None, dist0=None, cancel=None)\n"
    "         -> dict\n\n"
    "nsteps = len(values) - 1 implicit steps of dt [s] from the solution `unknowns` of a\n"
    "_core.Problem compiled spatial, Cosserat, fixed RK4 steps (any shooting segments):\n"
    "values (nsteps + 1, nt) actuation per time; loads (nsteps + 1, nl, 6) or None; rho_a\n"
    "[kg/m]; rho_j (3,) [kg m]; eta [s]; drag [N s^2/m^4]; dist0 (3,) the start's distributed\n"
    "load [N/m] (base frame) where it differs from the problem's (row 0 of values and loads\n"
    "is the start's likewise).  Returns status, message, done,\n"
    "nit, nfev, njev, tip (done + 1, 12), tension, slack (done + 1, nt), energy (done + 1, 6),\n"
    "residual (done + 1,), iters (done + 1,), backbone (done + 1, nb, 3) or None, s (nb,) the\n"
    "backbone nodes' arc lengths [m], state (the\n"
    "last good step's, to resume from: resume=state continues a run with the same problem\n"
    "and dt; row 0 is then the previous run's last, whose outputs the caller keeps).";

const char glue_dyn_segments_doc[] =
    "dyn_segments(problem, rho_a, dt, alpha, failed=0) -> (segments, growth)\n\n"
    "The shooting segments a time step of dt [s] (BDF-alpha alpha) of a rod of rho_a [kg/m]\n"
    "takes, and the growth exponent they are chosen from (tr_dyn_segments, csrc/tr_dyn.h);\n"
    "with failed, the status of a run on problem's segments: the segments to redo it with\n"
    "(0: none, tr_dyn_retry_segments).";

PyObject *glue_dyn_segments(PyObject *self, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"problem", "rho_a", "dt", "alpha", "failed", NULL};
    PyObject *op;
    double rhoA, dt, alpha;
    int failed = 0;
    ProblemObject *pr;
    (void)self;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "O!ddd|i", kwlist, &glue_problem_type, &op, &rhoA,
                                     &dt, &alpha, &failed))
        return NULL;
    pr = (ProblemObject *)op;
    if (glue_problem_check(pr) < 0) return NULL;
    return Py_BuildValue("id",
                         failed ? tr_dyn_retry_segments(pr->m, rhoA, dt, alpha, failed)
                                : tr_dyn_segments(pr->m, rhoA, dt, alpha),
                         tr_dyn_growth(pr->m, rhoA, dt, alpha));
}

static PyObject *rows(PyObject *a, int n)
{
    /* the first n rows of a (a new reference) */
    return PySequence_GetSlice(a, 0, n);
}

PyObject *glue_simulate(PyObject *self, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"problem", "unknowns", "values", "loads", "dt",       "alpha",
                             "rho_a",   "rho_j",    "eta",    "drag",  "max_iter", "backbone",
                             "resume",  "dist0",    "cancel", NULL};
    PyObject *op, *ox, *ov, *ol, *orj = Py_None, *ors = Py_None, *cancel = Py_None, *res = NULL;
    PyObject *od0 = Py_None;
    PyArrayObject *x = NULL, *val = NULL, *ld = NULL, *rj = NULL, *rsm = NULL, *d0 = NULL;
    PyObject *tip = NULL, *ten = NULL, *sl = NULL, *en = NULL, *rs = NULL, *it = NULL, *bb = NULL;
    PyObject *stt = NULL, *sn = NULL;
    ProblemObject *pr;
    tr_dyn_spec sp;
    tr_dyn_out o;
    glue_poll poll;
    int status, backbone = 0, n, nstate;
    (void)self;
    memset(&sp, 0, sizeof sp);
    memset(&o, 0, sizeof o);
    sp.alpha = 0.0; /* BDF2, as simulate's default */
    sp.max_iter = 8;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "O!OOOd|$ddOddipOOO", kwlist, &glue_problem_type,
                                     &op, &ox, &ov, &ol, &sp.dt, &sp.alpha, &sp.rhoA, &orj, &sp.eta,
                                     &sp.drag, &sp.max_iter, &backbone, &ors, &od0, &cancel))
        return NULL;
    pr = (ProblemObject *)op;
    if (glue_problem_check(pr) < 0 || glue_poll_init(&poll, cancel) < 0) return NULL;
    if (!(x = glue_problem_unknowns(pr, ox))) goto done;
    if (!(val = glue_coerce(ov, "values"))) goto done;
    if (PyArray_NDIM(val) != 2 || PyArray_DIM(val, 0) < 2 || PyArray_DIM(val, 1) != pr->m->nt) {
        PyErr_Format(PyExc_ValueError, "values must have shape (nsteps + 1 >= 2, %d)", pr->m->nt);
        goto done;
    }
    n = (int)PyArray_DIM(val, 0) - 1;
    if (ol != Py_None) {
        if (!(ld = glue_coerce(ol, "loads"))) goto done;
        if (PyArray_SIZE(ld) != (npy_intp)(n + 1) * 6 * pr->m->nl) {
            PyErr_Format(PyExc_ValueError, "loads must have shape (%d, %d, 6)", n + 1, pr->m->nl);
            goto done;
        }
    }
    if (!(rj = glue_coerce(orj, "rho_j"))) goto done;
    if (PyArray_SIZE(rj) != 3) {
        PyErr_SetString(PyExc_ValueError, "rho_j must have 3 values");
        goto done;
    }
    memcpy(sp.rhoJ, PyArray_DATA(rj), 3 * sizeof(double));
    if (od0 != Py_None) {
        if (!(d0 = glue_coerce(od0, "dist0"))) goto done;
        if (PyArray_SIZE(d0) != 3) {
            PyErr_SetString(PyExc_ValueError, "dist0 must have 3 values");
            goto done;
        }
        sp.dist0 = (const double *)PyArray_DATA(d0);
    }
    nstate = tr_dyn_state_len(pr->m, pr->d);
    if (ors != Py_None) {
        if (!(rsm = glue_coerce(ors, "resume"))) goto done;
        if (PyArray_SIZE(rsm) != nstate) {
            PyErr_Format(PyExc_ValueError,
                         "resume must be a state of this problem and grid (%d values), got %ld",
                         nstate, (long)PyArray_SIZE(rsm));
            goto done;
        }
        sp.resume = (const double *)PyArray_DATA(rsm);
    }
    sp.nsteps = n;
    sp.values = (const double *)PyArray_DATA(val);
    sp.loads = ld ? (const double *)PyArray_DATA(ld) : NULL;
    {
        npy_intp d12[2] = {n + 1, 12}, dnt[2] = {n + 1, pr->m->nt}, d4[2] = {n + 1, TR_DYN_NE},
                 d1[1] = {n + 1}, db[3] = {n + 1, tr_dyn_nodes(pr->m, pr->d), 3};
        tip = PyArray_ZEROS(2, d12, NPY_DOUBLE, 0);
        ten = PyArray_ZEROS(2, dnt, NPY_DOUBLE, 0);
        sl = PyArray_ZEROS(2, dnt, NPY_DOUBLE, 0);
        en = PyArray_ZEROS(2, d4, NPY_DOUBLE, 0);
        rs = PyArray_ZEROS(1, d1, NPY_DOUBLE, 0);
        it = PyArray_ZEROS(1, d1, NPY_INT, 0);
        npy_intp dst[1] = {nstate};
        bb = backbone ? PyArray_ZEROS(3, db, NPY_DOUBLE, 0) : (Py_INCREF(Py_None), Py_None);
        stt = PyArray_ZEROS(1, dst, NPY_DOUBLE, 0);
        sn = PyArray_ZEROS(1, db + 1, NPY_DOUBLE, 0);
        if (!tip || !ten || !sl || !en || !rs || !it || !bb || !stt || !sn) goto done;
        o.s = (double *)PyArray_DATA((PyArrayObject *)sn);
        o.state = (double *)PyArray_DATA((PyArrayObject *)stt);
        o.tip = (double *)PyArray_DATA((PyArrayObject *)tip);
        o.tension = (double *)PyArray_DATA((PyArrayObject *)ten);
        o.slack = (double *)PyArray_DATA((PyArrayObject *)sl);
        o.energy = (double *)PyArray_DATA((PyArrayObject *)en);
        o.residual = (double *)PyArray_DATA((PyArrayObject *)rs);
        o.iters = (int *)PyArray_DATA((PyArrayObject *)it);
        o.backbone = backbone ? (double *)PyArray_DATA((PyArrayObject *)bb) : NULL;
    }
    tr_set_poll(pr->d, glue_poll_hook, &poll);
    pr->busy = 1;
    Py_BEGIN_ALLOW_THREADS;
    status = tr_dyn_run(pr->m, pr->d, (const double *)PyArray_DATA(x), &sp, &o);
    Py_END_ALLOW_THREADS;
    pr->busy = 0;
    tr_set_poll(pr->d, NULL, NULL);
    if (glue_poll_finish(&poll, status) < 0) goto done;
    if (status == TR_EINVAL && o.done == 0) {
        glue_err(PyExc_ValueError, "simulate: %s", o.message);
        goto done;
    }
    if (!(res = PyDict_New())) goto done;
    if (glue_set(res, "status", PyLong_FromLong(status)) < 0 ||
        glue_set(res, "message", PyUnicode_FromString(o.message)) < 0 ||
        glue_set(res, "done", PyLong_FromLong(o.done)) < 0 ||
        glue_set(res, "nit", PyLong_FromLong(o.nit)) < 0 ||
        glue_set(res, "nfev", PyLong_FromLong(o.nfev)) < 0 ||
        glue_set(res, "njev", PyLong_FromLong(o.njev)) < 0 ||
        glue_set(res, "tip", rows(tip, o.done + 1)) < 0 ||
        glue_set(res, "tension", rows(ten, o.done + 1)) < 0 ||
        glue_set(res, "slack", rows(sl, o.done + 1)) < 0 ||
        glue_set(res, "energy", rows(en, o.done + 1)) < 0 ||
        glue_set(res, "residual", rows(rs, o.done + 1)) < 0 ||
        glue_set(res, "iters", rows(it, o.done + 1)) < 0 ||
        glue_set(res, "backbone", backbone ? rows(bb, o.done + 1) : (Py_INCREF(Py_None), Py_None)) <
            0 ||
        glue_set(res, "state", (Py_INCREF(stt), stt)) < 0 ||
        glue_set(res, "s", (Py_INCREF(sn), sn)) < 0)
        Py_CLEAR(res);
done:
    Py_XDECREF(x);
    Py_XDECREF(val);
    Py_XDECREF(ld);
    Py_XDECREF(rj);
    Py_XDECREF(tip);
    Py_XDECREF(ten);
    Py_XDECREF(sl);
    Py_XDECREF(en);
    Py_XDECREF(rs);
    Py_XDECREF(it);
    Py_XDECREF(bb);
    Py_XDECREF(stt);
    Py_XDECREF(sn);
    Py_XDECREF(rsm);
    Py_XDECREF(d0);
    return res;
}
