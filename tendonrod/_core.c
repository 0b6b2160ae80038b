/*
 * tendonrod._core -- the only file that speaks the CPython / NumPy C-API.
 *
 * Each wrapper has the same shape: parse, coerce (float64, C-contiguous),
 * check shapes with a message naming the argument, allocate outputs, release
 * the GIL around the core call, map status to data, clean up through one
 * label.  The numerics live in csrc/ (pure C99 + GSL).
 *
 * Sections (each owned by one part of the code base; edit only your own):
 *   1. closed-form ufuncs        (tr_closed.h)
 *   2. Cosserat solver entry points (tendonrod.h)
 *   3. module definition (multi-phase init)
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define PY_ARRAY_UNIQUE_SYMBOL tendonrod_ARRAY_API
#define PY_UFUNC_UNIQUE_SYMBOL tendonrod_UFUNC_API
#include <numpy/arrayobject.h>
#include <numpy/ufuncobject.h>
#include <numpy/npy_math.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_version.h>

/* ======================================================================== */
/* 1. closed-form ufuncs                                                     */
/* ======================================================================== */

static int
add_closed_forms(PyObject *module)
{
    /* BEGIN closed-form ufuncs (section 1) */
    return 0;
    /* END closed-form ufuncs (section 1) */
}

/* ======================================================================== */
/* 2. Cosserat solver entry points                                           */
/* ======================================================================== */

static int
add_solver(PyObject *module)
{
    /* BEGIN solver (section 2) */
    return 0;
    /* END solver (section 2) */
}

static PyMethodDef core_methods[] = {
    /* BEGIN method table (section 2 adds its entries here) */
    /* END method table */
    {NULL, NULL, 0, NULL}
};

/* ======================================================================== */
/* 3. module definition                                                      */
/* ======================================================================== */

static int
core_exec(PyObject *module)
{
    if (PyModule_AddStringConstant(module, "gsl_version", gsl_version) < 0)
        return -1;
    if (add_closed_forms(module) < 0)
        return -1;
    if (add_solver(module) < 0)
        return -1;
    return 0;
}

static int
core_numpy_init(void)
{
    /* import_array/import_umath are macros that return on failure. */
    import_array1(-1);
    import_umath1(-1);
    return 0;
}

static PyModuleDef_Slot core_slots[] = {
    {Py_mod_exec, (void *)core_exec},
    {0, NULL}
};

static struct PyModuleDef core_module = {
    PyModuleDef_HEAD_INIT,
    .m_name = "tendonrod._core",
    .m_doc = "C core of tendonrod: closed-form ufuncs and the Cosserat-rod/tendon solver.",
    .m_size = 0,
    .m_methods = core_methods,
    .m_slots = core_slots,
};

PyMODINIT_FUNC
PyInit__core(void)
{
    if (core_numpy_init() < 0)
        return NULL;
    /* GSL's default error handler aborts the process; switch it off once,
     * at module load.  Every core function returns a status instead. */
    gsl_set_error_handler_off();
    return PyModuleDef_Init(&core_module);
}
