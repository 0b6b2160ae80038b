/*
 * _core.c -- the module tendonrod._core: its definition (multi-phase init), the
 * method table, and the constants the Python layer reads instead of repeating them:
 * the solver's default options, the limits of options and values, the column
 * layouts of the flat scene arrays, and the status codes.
 */
#define TENDONROD_GLUE_MAIN
#include "_glue.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_version.h>

/* Steal `value` into module.name; -1 on error. */
static int add_object(PyObject *module, const char *name, PyObject *value)
{
    int r;
    if (!value) return -1;
    r = PyModule_AddObjectRef(module, name, value);
    Py_DECREF(value);
    return r;
}

/* DEFAULT_OPTIONS: tr_default_options() in the names and types of the keywords. */
static PyObject *default_options(void)
{
    const tr_options o = tr_default_options();
    return Py_BuildValue(
        "{s:s,s:i,s:d,s:d,s:i,s:i,s:s,s:s,s:O,s:i,s:i,s:O,s:O,s:i,s:O,s:d,s:d,s:O}", "integrator",
        glue_integrators[o.integrator], "steps", o.steps, "rtol", o.rtol, "tol", o.tol, "max_iter",
        o.max_iter, "max_nfev", o.max_nfev, "jacobian_method", glue_jacobians[o.jacobian_method],
        "slack_model", glue_slack_models[o.slack_model], "continuation",
        o.continuation ? Py_True : Py_False, "max_continuation", o.max_continuation, "nodes",
        TR_DEFAULT_NODES, "force_spatial", o.force_spatial ? Py_True : Py_False, "tip_only",
        o.tip_only ? Py_True : Py_False, "shooting_segments", o.shooting_segments, "auto_shooting",
        o.auto_shooting ? Py_True : Py_False, "max_work", o.max_work, "max_time", o.max_time,
        "accept_unstable", o.accept_unstable ? Py_True : Py_False);
}

/* LIMITS: the ranges tr_options_check and tr_model_alloc accept (tendonrod.h): per
 * option (lo, hi), inclusive for ints, max_work and max_time; rtol in [lo, hi), tol in
 * (lo, hi); rod L, EI,
 * GJ and the finite EA, GA of a rod or tendon in [lo, hi]. */
static PyObject *limits(void)
{
    return Py_BuildValue(
        "{s:(ii),s:(ii),s:(ii),s:(ii),s:(ii),s:(ii),s:(dd),s:(dd),s:(dd),s:(dd),s:(dd),s:(dd),s:d}",
        "steps", 0, TR_MAX_STEPS, "max_iter", 1, TR_MAX_ITER_CAP, "max_nfev", 1, TR_MAX_NFEV_CAP,
        "max_continuation", 0, TR_MAX_CONTINUATION_CAP, "shooting_segments", 1,
        TR_MAX_SHOOTING_SEGMENTS, "nodes", 2, TR_MAX_NODES, "rtol", TR_RTOL_MIN, 1.0, "tol", 0.0,
        1.0, "max_work", 1.0, TR_MAX_WORK_CAP, "max_time", 0.0, TR_MAX_TIME_CAP, "rod", TR_ROD_MIN,
        TR_ROD_MAX, "EA", TR_EA_MIN, TR_EA_MAX, "planar_sin", TR_PLANAR_SIN);
}

/* CHOICES: the accepted names of the choice options, in the order of their enums. */
static PyObject *choices(void)
{
    return Py_BuildValue("{s:(sss),s:(sss),s:(ss)}", "integrator", glue_integrators[0],
                         glue_integrators[1], glue_integrators[2], "jacobian_method",
                         glue_jacobians[0], glue_jacobians[1], glue_jacobians[2], "slack_model",
                         glue_slack_models[0], glue_slack_models[1]);
}

static int add_constants(PyObject *module)
{
    if (PyModule_AddStringConstant(module, "gsl_version", gsl_version) < 0) return -1;
    /* the one caveat status that is not a success (see TR_SUCCEEDED), and the statuses
     * the Python layer names */
    if (PyModule_AddIntConstant(module, "STATUS_OFFPATH", TR_OFFPATH) < 0 ||
        PyModule_AddIntConstant(module, "STATUS_CONFIRMED", TR_CONFIRMED) < 0 ||
        PyModule_AddIntConstant(module, "STATUS_TRUNCATION", TR_TRUNCATION) < 0 ||
        PyModule_AddIntConstant(module, "STATUS_FRICTION_HELD", TR_FRICTION_HELD) < 0 ||
        PyModule_AddIntConstant(module, "STATUS_ROUNDOFF", TR_ROUNDOFF) < 0 ||
        PyModule_AddIntConstant(module, "STATUS_UNSTABLE", TR_UNSTABLE) < 0 ||
        PyModule_AddIntConstant(module, "STATUS_EBUDGET", TR_EBUDGET) < 0 ||
        PyModule_AddIntConstant(module, "STATUS_EINTERRUPTED", TR_EINTERRUPTED) < 0)
        return -1;
    if (add_object(module, "DEFAULT_OPTIONS", default_options()) < 0 ||
        add_object(module, "LIMITS", limits()) < 0 ||
        add_object(module, "CHOICES", choices()) < 0 ||
        add_object(module, "ROD_COLUMNS",
                   Py_BuildValue("(ssssss)", "length", "EI", "GJ", "EA", "GA", "kirchhoff")) < 0 ||
        add_object(module, "TENDON_COLUMNS",
                   Py_BuildValue("(ssssssss)", "offset", "angle", "slope", "EA", "end", "control",
                                 "value", "pretension")) < 0 ||
        add_object(module, "LOAD_COLUMNS",
                   Py_BuildValue("(sssssss)", "s", "Fx", "Fy", "Fz", "Mx", "My", "Mz")) < 0)
        return -1;
    /* the parameter kinds of a linearisation, in the order of tr_param_kind (the typedef
     * fails to compile when the enum grows without this list) */
    typedef char param_kinds_listed[TR_PAR_NKIND == 10 ? 1 : -1];
    (void)sizeof(param_kinds_listed);
    if (add_object(module, "PARAM_KINDS",
                   Py_BuildValue("(ssssssssss)", "value", "load", "EI", "GJ", "EA", "GA",
                                 "tendon_EA", "offset", "slope", "friction")) < 0)
        return -1;
    return 0;
}

static PyMethodDef core_methods[] = {
    {"solve", (PyCFunction)(void (*)(void))glue_solve, METH_VARARGS | METH_KEYWORDS,
     glue_solve_doc},
    {"compliance", (PyCFunction)(void (*)(void))glue_compliance, METH_VARARGS | METH_KEYWORDS,
     glue_compliance_doc},
    {"solve_batch", (PyCFunction)(void (*)(void))glue_solve_batch, METH_VARARGS | METH_KEYWORDS,
     glue_solve_batch_doc},
    {"strerror", (PyCFunction)glue_strerror, METH_O, glue_strerror_doc},
    {"is_planar", (PyCFunction)glue_is_planar, METH_VARARGS, glue_is_planar_doc},
    {"path", (PyCFunction)(void (*)(void))glue_path, METH_VARARGS | METH_KEYWORDS, glue_path_doc},
    {"qp", (PyCFunction)(void (*)(void))glue_qp, METH_VARARGS | METH_KEYWORDS, glue_qp_doc},
    {"modes", (PyCFunction)(void (*)(void))glue_modes, METH_VARARGS | METH_KEYWORDS,
     glue_modes_doc},
    {"simulate", (PyCFunction)(void (*)(void))glue_simulate, METH_VARARGS | METH_KEYWORDS,
     glue_simulate_doc},
    {"dyn_segments", (PyCFunction)(void (*)(void))glue_dyn_segments, METH_VARARGS | METH_KEYWORDS,
     glue_dyn_segments_doc},
    {NULL, NULL, 0, NULL}};

static int add_type(PyObject *module, const char *name, PyTypeObject *type)
{
    if (PyType_Ready(type) < 0) return -1;
    return PyModule_AddObjectRef(module, name, (PyObject *)type);
}

static int core_exec(PyObject *module)
{
    if (add_constants(module) < 0) return -1;
    if (add_type(module, "Problem", &glue_problem_type) < 0 ||
        add_type(module, "Cancel", &glue_cancel_type) < 0 ||
        add_type(module, "Result", &glue_result_type) < 0)
        return -1;
    if (glue_add_ufuncs(module) < 0) return -1;
    return 0;
}

static int core_numpy_init(void)
{
    /* import_array/import_umath are macros that return on failure. */
    import_array1(-1);
    import_umath1(-1);
    return 0;
}

static PyModuleDef_Slot core_slots[] = {{Py_mod_exec, (void *)core_exec}, {0, NULL}};

static struct PyModuleDef core_module = {
    PyModuleDef_HEAD_INIT,
    .m_name = "tendonrod._core",
    .m_doc = "C core of tendonrod: closed-form ufuncs and the Cosserat-rod/tendon solver.",
    .m_size = 0,
    .m_methods = core_methods,
    .m_slots = core_slots,
};

PyMODINIT_FUNC PyInit__core(void)
{
    if (core_numpy_init() < 0) return NULL;
    /* GSL's default error handler aborts the process; switch it off once,
     * at module load.  Every core function returns a status instead. */
    gsl_set_error_handler_off();
    return PyModuleDef_Init(&core_module);
}
