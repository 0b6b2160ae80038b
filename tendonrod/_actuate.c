/*
 * _actuate.c -- _core.Problem.actuate: the run of an inverse actuation (tr_actuate.h)
 * from the problem's last solve, with the GIL released.
 */
#include "_glue.h"
#include "tr_actuate.h"

const char glue_problem_actuate_doc[] =
    "actuate(*, kind, tendons, c0, scale, values, floor, tau_scale, k, tol, max_iter, tip_row,\n"
    "goal, theta=0.0, direction=None, basis=None, position=None, rotation=None, rows=None,\n"
    "length, augmented=False, judge=True, cancel=None) -> dict\n\n"
    "The inverse actuation (tr_actuate) from this problem's last solve, which must have\n"
    "succeeded at the controls c0: kind 0 square, 1 minimum change, 2 least squares;\n"
    "tendons (n,) the actuated tendons, c0 and scale (n,) their control values and scales,\n"
    "values (nt,) the scene's actuation values, floor (nt,) tension floors [N] (-inf: none);\n"
    "tau_scale [N], k = tau_scale / q_scale [N/m], tol, max_iter, tip_row (the tip's\n"
    "breakpoint index).  The target, base frame: goal 1 angle theta [rad], 2 direction\n"
    "(3,) with basis (m, 3), 3 position (3,) [m] with rotation (3, 3) or None and rows (m,)\n"
    "of [dx / L, phi]; length L [m].  augmented: try the target inside the shooting system\n"
    "first; judge: the final solve is judged for stability.  The dict of solve() for the\n"
    "final solve, with 'actuation': controls (n,), residual (m,), iterations, solves,\n"
    "jacobians, outcome ('done', 'stuck', 'unreachable', 'max_iter'), optimal, augmented,\n"
    "multipliers (m,) or None, tension_multipliers (nt,) or None, floors (nt,), why,\n"
    "success (the run's verdict, tr_act_result.success), optimality (least squares: the\n"
    "first-order test's cosine at the state returned, NaN where not measured).\n"
    "ValueError for a specification that does not fit, RuntimeError when a linearisation\n"
    "fails, KeyboardInterrupt on Ctrl-C.";

/* obj as a float64 array of n entries (n < 0: any), or NULL with ValueError. */
static PyArrayObject *vec(PyObject *obj, const char *name, npy_intp n)
{
    PyArrayObject *a;
    if (obj == Py_None) {
        glue_err(PyExc_ValueError, "actuate: %s is required", name);
        return NULL;
    }
    if (!(a = glue_coerce(obj, name))) return NULL;
    if (n >= 0 && PyArray_SIZE(a) != n) {
        glue_err(PyExc_ValueError, "actuate: %s must have %ld entries, got %ld", name, (long)n,
                 (long)PyArray_SIZE(a));
        Py_DECREF(a);
        return NULL;
    }
    return a;
}

static const double *D(PyArrayObject *a)
{
    return (const double *)PyArray_DATA(a);
}

static int ints(PyArrayObject *a, int *out, int lo, int hi, const char *name)
{
    npy_intp i;
    for (i = 0; i < PyArray_SIZE(a); i++) {
        const double v = D(a)[i];
        if (!(v == floor(v) && v >= lo && v <= hi)) {
            glue_err(PyExc_ValueError, "actuate: %s must hold integers in [%d, %d], got %g", name,
                     lo, hi, v);
            return -1;
        }
        out[i] = (int)v;
    }
    return 0;
}

static const char *const outcomes[] = {"done", "stuck", "unreachable", "max_iter"};

/* The 'actuation' dict of a run. */
static PyObject *report(const tr_act_spec *sp, const tr_act_result *res, int nt)
{
    npy_intp n = sp->n, m = sp->target.m, t = nt;
    return Py_BuildValue(
        "{s:N,s:N,s:i,s:i,s:i,s:s,s:O,s:O,s:N,s:N,s:N,s:s,s:O,s:d}", "controls",
        glue_array(1, &n, res->c), "residual", glue_array(1, &m, res->r), "iterations",
        res->iterations, "solves", res->solves, "jacobians", res->jacobians, "outcome",
        outcomes[res->outcome >= 0 && res->outcome < 4 ? res->outcome : 1], "optimal",
        res->optimal ? Py_True : Py_False, "augmented", res->augmented ? Py_True : Py_False,
        "multipliers", res->have_lam ? glue_array(1, &m, res->lam) : Py_NewRef(Py_None),
        "tension_multipliers", res->have_lam ? glue_array(1, &t, res->mus) : Py_NewRef(Py_None),
        "floors", glue_array(1, &t, res->floors), "why", res->why, "success",
        res->success ? Py_True : Py_False, "optimality", res->optimality);
}

PyObject *glue_problem_actuate(ProblemObject *self, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {
        "kind",     "tendons",  "c0",      "scale",     "values", "floor",  "tau_scale", "k",
        "tol",      "max_iter", "tip_row", "goal",      "length", "theta",  "direction", "basis",
        "position", "rotation", "rows",    "augmented", "judge",  "cancel", NULL};
    PyObject *ot, *oc, *os, *ov, *of, *odir = Py_None, *obas = Py_None, *opos = Py_None;
    PyObject *orot = Py_None, *orows = Py_None, *cancel = Py_None, *result = NULL, *rep = NULL;
    PyArrayObject *at = NULL, *ac = NULL, *as = NULL, *av = NULL, *af = NULL, *ad = NULL;
    PyArrayObject *ab = NULL, *ap = NULL, *ar = NULL, *aw = NULL;
    tr_act_spec sp;
    tr_act_result res;
    tr_act_target *tg = &sp.target;
    glue_poll poll;
    int idx[64], status, augmented = 0, judge = 1, nt;
    double *buf = NULL;
    memset(&sp, 0, sizeof sp);
    memset(&res, 0, sizeof res);
    if (glue_problem_check(self) < 0) return NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kwds,
                                     "|$iOOOOOdddiiidd"
                                     "OOOOOppO",
                                     kwlist, &sp.kind, &ot, &oc, &os, &ov, &of, &sp.tau_scale,
                                     &sp.k, &sp.tol, &sp.max_iter, &sp.tip_row, &tg->goal, &tg->L,
                                     &tg->theta, &odir, &obas, &opos, &orot, &orows, &augmented,
                                     &judge, &cancel))
        return NULL;
    nt = self->m->nt;
    if (!TR_SUCCEEDED(self->last_status)) {
        PyErr_SetString(PyExc_RuntimeError, "actuate needs a successful solve of this Problem "
                                            "first (its state starts the run)");
        return NULL;
    }
    if (glue_poll_init(&poll, cancel) < 0 || !(at = vec(ot, "tendons", -1)) ||
        !(ac = vec(oc, "c0", PyArray_SIZE(at))) || !(as = vec(os, "scale", PyArray_SIZE(at))) ||
        !(av = vec(ov, "values", nt)) || !(af = vec(of, "floor", nt)))
        goto done;
    sp.n = (int)PyArray_SIZE(at);
    if (sp.n < 1 || sp.n > 64) {
        glue_err(PyExc_ValueError, "actuate: 1 to 64 tendons, got %d", sp.n);
        goto done;
    }
    if (ints(at, idx, 0, nt - 1, "tendons") < 0) goto done;
    sp.idx = idx, sp.c0 = D(ac), sp.scale = D(as), sp.values = D(av), sp.floor0 = D(af);
    sp.augmented = augmented, sp.judge = judge;
    if (tg->goal == TR_TARGET_ANGLE) {
        tg->m = 1;
    } else if (tg->goal == TR_TARGET_DIRECTION) {
        if (!(ad = vec(odir, "direction", 3)) || !(ab = vec(obas, "basis", -1))) goto done;
        if (PyArray_SIZE(ab) != 3 && PyArray_SIZE(ab) != 6) {
            glue_err(PyExc_ValueError, "actuate: basis must be (m, 3) with m = 1 or 2");
            goto done;
        }
        tg->m = (int)PyArray_SIZE(ab) / 3;
        memcpy(tg->t, D(ad), 3 * sizeof(double));
        memcpy(tg->BT, D(ab), (size_t)PyArray_SIZE(ab) * sizeof(double));
    } else if (tg->goal == TR_TARGET_POSITION) {
        int rows[6];
        tg->has_R = orot != Py_None;
        if (!(ap = vec(opos, "position", 3)) || !(ar = vec(orows, "rows", -1)) ||
            (tg->has_R && !(aw = vec(orot, "rotation", 9))))
            goto done;
        if (PyArray_SIZE(ar) < 1 || PyArray_SIZE(ar) > 6 ||
            ints(ar, rows, 0, tg->has_R ? 5 : 2, "rows") < 0) {
            if (!PyErr_Occurred())
                glue_err(PyExc_ValueError, "actuate: rows must have 1..6 entries");
            goto done;
        }
        tg->m = (int)PyArray_SIZE(ar);
        memcpy(tg->rows, rows, sizeof rows);
        memcpy(tg->p, D(ap), 3 * sizeof(double));
        if (aw) memcpy(tg->R, D(aw), 9 * sizeof(double));
    } else {
        glue_err(PyExc_ValueError,
                 "actuate: goal must be 1 (angle), 2 (direction) or 3 "
                 "(position), got %d",
                 tg->goal);
        goto done;
    }
    if (!(buf = (double *)PyMem_Calloc((size_t)(sp.n + 2 * nt) + 1, sizeof(double)))) {
        PyErr_NoMemory();
        goto done;
    }
    res.c = buf, res.mus = buf + sp.n, res.floors = buf + sp.n + nt;
    tr_set_poll(self->d, glue_poll_hook, &poll);
    self->busy = 1;
    Py_BEGIN_ALLOW_THREADS;
    status = tr_actuate(self->m, self->d, &sp, &res);
    Py_END_ALLOW_THREADS;
    self->busy = 0;
    tr_set_poll(self->d, NULL, NULL);
    /* the workspace holds the final solve (or, after a failure, no vouched state) */
    self->last_status = status == TR_OK ? res.status : TR_CONTINUE;
    if (glue_poll_finish(&poll, status) < 0) goto done;
    if (status != TR_OK) {
        glue_err(status == TR_EINVAL ? PyExc_ValueError : PyExc_RuntimeError, "%s (status %d: %s)",
                 tr_data_message(self->d), status, tr_strerror(status));
        goto done;
    }
    /* the final solve was lazy: no node arrays (record_from computes them) */
    tr_data_set_lazy(self->d, 1);
    if (!glue_problem_form(self) ||
        !(result = glue_solve_result(self->m, self->d, res.status, self->form)) ||
        !(rep = report(&sp, &res, nt)) || glue_set(result, "actuation", rep) < 0)
        Py_CLEAR(result);
    tr_data_set_lazy(self->d, 0);
done:
    PyMem_Free(buf);
    Py_XDECREF(at);
    Py_XDECREF(ac);
    Py_XDECREF(as);
    Py_XDECREF(av);
    Py_XDECREF(af);
    Py_XDECREF(ad);
    Py_XDECREF(ab);
    Py_XDECREF(ap);
    Py_XDECREF(ar);
    Py_XDECREF(aw);
    return result;
}
