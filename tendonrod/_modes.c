/*
 * _modes.c -- _core.modes: the natural frequencies and mode shapes of a compiled
 * Problem's solution (tr_modes, csrc/tr_modes.h).
 */
#include "_glue.h"
#include "tr_modes.h"

const char glue_modes_doc[] =
    "modes(problem, unknowns, steps, n, mass, point_masses, *, elements=0, levels=0,\n"
    "      rotary=True, cancel=None) -> dict\n\n"
    "The n lowest vibration modes about the solution (unknowns, steps) of a _core.Problem:\n"
    "mass (nmass, 5) [s_end, rho A, rho I1, rho I2, rho J] per section, base first;\n"
    "point_masses (npm, 2) [s, mass].  Returns omega2 (n,) [rad^2/s^2] (extrapolated),\n"
    "error (n,), levels (nlev, n), modal_mass (n,) [kg], s (ns,), position (ns, 3),\n"
    "dpos, drot (n, ns, 3), nit, nfac, status, message.";

/* float64 C-contiguous (rows, ncol) array of obj; NULL + exception naming it. */
static PyArrayObject *table_of(PyObject *obj, const char *name, int ncol)
{
    PyArrayObject *a = glue_coerce(obj, name);
    if (!a) return NULL;
    if (PyArray_NDIM(a) != 2 || PyArray_DIM(a, 1) != ncol) {
        PyErr_Format(PyExc_ValueError, "%s must have shape (k, %d), got ndim %d", name, ncol,
                     PyArray_NDIM(a));
        Py_DECREF(a);
        return NULL;
    }
    return a;
}

PyObject *glue_modes(PyObject *self, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"problem",  "unknowns", "steps",  "n",      "mass", "point_masses",
                             "elements", "levels",   "rotary", "cancel", NULL};
    PyObject *op, *ox, *omass, *opm, *cancel = Py_None, *res = NULL;
    PyArrayObject *x = NULL, *mass = NULL, *pm = NULL;
    ProblemObject *pr;
    tr_modes_spec sp;
    tr_modes_out o;
    glue_poll poll;
    int steps, status;
    (void)self;
    memset(&sp, 0, sizeof sp);
    memset(&o, 0, sizeof o);
    sp.rotary = 1;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "O!OiiOO|$iipO", kwlist, &glue_problem_type, &op,
                                     &ox, &steps, &sp.n, &omass, &opm, &sp.elements, &sp.levels,
                                     &sp.rotary, &cancel))
        return NULL;
    pr = (ProblemObject *)op;
    if (glue_problem_check(pr) < 0 || glue_poll_init(&poll, cancel) < 0) return NULL;
    if (!(x = glue_problem_unknowns(pr, ox))) goto done;
    if (steps < 1) {
        PyErr_Format(PyExc_ValueError, "steps must be >= 1, got %d", steps);
        goto done;
    }
    if (!(mass = table_of(omass, "mass", 5)) || !(pm = table_of(opm, "point_masses", 2))) goto done;
    sp.nmass = (int)PyArray_DIM(mass, 0), sp.mass = (const double *)PyArray_DATA(mass);
    sp.npm = (int)PyArray_DIM(pm, 0), sp.pm = (const double *)PyArray_DATA(pm);
    tr_set_poll(pr->d, glue_poll_hook, &poll);
    pr->busy = 1;
    Py_BEGIN_ALLOW_THREADS;
    status = tr_modes(pr->m, pr->d, (const double *)PyArray_DATA(x), steps, &sp, &o);
    Py_END_ALLOW_THREADS;
    pr->busy = 0;
    tr_set_poll(pr->d, NULL, NULL);
    if (glue_poll_finish(&poll, status) < 0) goto done;
    if (status == TR_EINVAL) {
        glue_err(PyExc_ValueError, "modes: %s", o.message);
        goto done;
    }
    if (!(res = PyDict_New())) goto done;
    if (glue_set(res, "status", PyLong_FromLong(status)) < 0 ||
        glue_set(res, "message", PyUnicode_FromString(o.message)) < 0 ||
        glue_set(res, "nit", PyLong_FromLong(o.nit)) < 0 ||
        glue_set(res, "nfac", PyLong_FromLong(o.nfac)) < 0)
        goto fail;
    if (status == TR_OK) {
        const npy_intp n = o.n, ns = o.ns;
        npy_intp d1[1] = {n}, d2[2] = {o.nlev, n}, ds[1] = {ns}, dp[2] = {ns, 3},
                 d3[3] = {n, ns, 3};
        if (glue_set(res, "omega2", glue_array(1, d1, o.omega2)) < 0 ||
            glue_set(res, "error", glue_array(1, d1, o.error)) < 0 ||
            glue_set(res, "levels", glue_array(2, d2, o.levels)) < 0 ||
            glue_set(res, "modal_mass", glue_array(1, d1, o.modal_mass)) < 0 ||
            glue_set(res, "s", glue_array(1, ds, o.s)) < 0 ||
            glue_set(res, "position", glue_array(2, dp, o.pos0)) < 0 ||
            glue_set(res, "dpos", glue_array(3, d3, o.dpos)) < 0 ||
            glue_set(res, "drot", glue_array(3, d3, o.drot)) < 0)
            goto fail;
    }
    goto done;
fail:
    Py_CLEAR(res);
done:
    tr_modes_out_free(&o);
    Py_XDECREF(x);
    Py_XDECREF(mass);
    Py_XDECREF(pm);
    return res;
}
