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

#include <fenv.h>
#include "tr_closed.h"

/* Raise the floating-point "invalid" flag that NumPy checks after a ufunc
 * loop.  This is what npy_set_floatstatus_invalid() does, but that function
 * lives in the static libnpymath, which this extension does not link;
 * C99's feraiseexcept is the portable equivalent.  The volatile 0/0
 * fallback is for a C library without FE_INVALID. */
static void closed_raise_invalid(void)
{
#ifdef FE_INVALID
    feraiseexcept(FE_INVALID);
#else
    volatile double zero = 0.0;
    volatile double nan = zero / zero;
    (void)nan;
#endif
}

/*
 * Section 1 loops.  Every loop is a NumPy "double" loop (inputs of other
 * numeric dtypes are cast by NumPy, non-numeric ones rejected by its type
 * resolution with a TypeError).  The kernels return a quiet NaN outside
 * their domain; like NumPy's own ufuncs, a loop that returns NaN raises the
 * floating-point "invalid" flag (once per call, after the loop), which
 * np.errstate turns into a warning, an exception or nothing.
 */

/* tension(F, z, L, EI, a, b, k) -> tau */
static void closed_tension_loop(char **args, npy_intp const *dimensions, npy_intp const *steps,
                                void *data)
{
    const npy_intp n = dimensions[0];
    char *F = args[0], *z = args[1], *L = args[2], *EI = args[3];
    char *a = args[4], *b = args[5], *k = args[6], *out = args[7];
    int nan_seen = 0;
    for (npy_intp i = 0; i < n; i++) {
        const double r = tr_closed_tension(*(double *)F, *(double *)z, *(double *)L, *(double *)EI,
                                           *(double *)a, *(double *)b, *(double *)k);
        nan_seen |= isnan(r);
        *(double *)out = r;
        F += steps[0];
        z += steps[1];
        L += steps[2];
        EI += steps[3];
        a += steps[4];
        b += steps[5];
        k += steps[6];
        out += steps[7];
    }
    if (nan_seen) closed_raise_invalid();
}

/* The 8-argument (s, F, z, L, EI, a, b, k) loops of angle and deflection.
 * When the seven design parameters are broadcast scalars (steps 0; the
 * common "shape along s" call) the tension is computed once per call.
 * The kernel is chosen by a loop-invariant selector, not a function pointer,
 * so that both kernels are inlined into the loop (the branch on `kind` is
 * perfectly predicted). */
enum closed_s_kind { CLOSED_ANGLE, CLOSED_DEFLECTION };

static inline double closed_s_kernel(enum closed_s_kind kind, double s, double F, double z,
                                     double L, double EI, double a, double b, double tau)
{
    return kind == CLOSED_DEFLECTION ? tr_closed_deflection_tau(s, F, z, L, EI, a, b, tau)
                                     : tr_closed_angle_tau(s, F, z, L, EI, a, b, tau);
}

static void closed_s_loop(char **args, npy_intp const *dimensions, npy_intp const *steps,
                          enum closed_s_kind kind)
{
    const npy_intp n = dimensions[0];
    char *s = args[0], *F = args[1], *z = args[2], *L = args[3], *EI = args[4];
    char *a = args[5], *b = args[6], *k = args[7], *out = args[8];
    const npy_intp s_s = steps[0], s_out = steps[8];
    int nan_seen = 0;
    if (steps[1] == 0 && steps[2] == 0 && steps[3] == 0 && steps[4] == 0 && steps[5] == 0 &&
        steps[6] == 0 && steps[7] == 0) {
        const double F0 = *(double *)F, z0 = *(double *)z, L0 = *(double *)L;
        const double EI0 = *(double *)EI, a0 = *(double *)a, b0 = *(double *)b;
        const double tau = tr_closed_tension(F0, z0, L0, EI0, a0, b0, *(double *)k);
        for (npy_intp i = 0; i < n; i++) {
            const double r = closed_s_kernel(kind, *(double *)s, F0, z0, L0, EI0, a0, b0, tau);
            nan_seen |= isnan(r);
            *(double *)out = r;
            s += s_s;
            out += s_out;
        }
    } else {
        for (npy_intp i = 0; i < n; i++) {
            const double Fi = *(double *)F, zi = *(double *)z, Li = *(double *)L;
            const double EIi = *(double *)EI, ai = *(double *)a, bi = *(double *)b;
            const double tau = tr_closed_tension(Fi, zi, Li, EIi, ai, bi, *(double *)k);
            const double r = closed_s_kernel(kind, *(double *)s, Fi, zi, Li, EIi, ai, bi, tau);
            nan_seen |= isnan(r);
            *(double *)out = r;
            s += s_s;
            F += steps[1];
            z += steps[2];
            L += steps[3];
            EI += steps[4];
            a += steps[5];
            b += steps[6];
            k += steps[7];
            out += s_out;
        }
    }
    if (nan_seen) closed_raise_invalid();
}

static void closed_angle_loop(char **args, npy_intp const *dimensions, npy_intp const *steps,
                              void *data)
{
    closed_s_loop(args, dimensions, steps, CLOSED_ANGLE);
}

static void closed_deflection_loop(char **args, npy_intp const *dimensions, npy_intp const *steps,
                                   void *data)
{
    closed_s_loop(args, dimensions, steps, CLOSED_DEFLECTION);
}

/* equivalent_stiffness(k, k_backbone) -> k_eq */
static void closed_equivalent_stiffness_loop(char **args, npy_intp const *dimensions,
                                             npy_intp const *steps, void *data)
{
    const npy_intp n = dimensions[0];
    char *k = args[0], *kB = args[1], *out = args[2];
    int nan_seen = 0;
    for (npy_intp i = 0; i < n; i++) {
        const double r = tr_closed_equivalent_stiffness(*(double *)k, *(double *)kB);
        nan_seen |= isnan(r);
        *(double *)out = r;
        k += steps[0];
        kB += steps[1];
        out += steps[2];
    }
    if (nan_seen) closed_raise_invalid();
}

/* pattern_factor(n) -> P */
static void closed_pattern_factor_loop(char **args, npy_intp const *dimensions,
                                       npy_intp const *steps, void *data)
{
    const npy_intp n = dimensions[0];
    char *nt = args[0], *out = args[1];
    int nan_seen = 0;
    for (npy_intp i = 0; i < n; i++) {
        const double r = tr_closed_pattern_factor(*(double *)nt);
        nan_seen |= isnan(r);
        *(double *)out = r;
        nt += steps[0];
        out += steps[1];
    }
    if (nan_seen) closed_raise_invalid();
}

/* actuation_tension_for_{angle,deflection}(x, L, EI, a, b) -> tau; the
 * kernel is selected as in closed_s_loop, so both are inlined. */
enum closed_actuation_kind { CLOSED_FOR_ANGLE, CLOSED_FOR_DEFLECTION };

static void closed_actuation_loop(char **args, npy_intp const *dimensions, npy_intp const *steps,
                                  enum closed_actuation_kind kind)
{
    const npy_intp n = dimensions[0];
    char *x = args[0], *L = args[1], *EI = args[2], *a = args[3], *b = args[4];
    char *out = args[5];
    int nan_seen = 0;
    for (npy_intp i = 0; i < n; i++) {
        const double xi = *(double *)x, Li = *(double *)L, EIi = *(double *)EI;
        const double ai = *(double *)a, bi = *(double *)b;
        const double r = kind == CLOSED_FOR_ANGLE
                             ? tr_closed_actuation_tension_for_angle(xi, Li, EIi, ai, bi)
                             : tr_closed_actuation_tension_for_deflection(xi, Li, EIi, ai, bi);
        nan_seen |= isnan(r);
        *(double *)out = r;
        x += steps[0];
        L += steps[1];
        EI += steps[2];
        a += steps[3];
        b += steps[4];
        out += steps[5];
    }
    if (nan_seen) closed_raise_invalid();
}

static void closed_actuation_angle_loop(char **args, npy_intp const *dimensions,
                                        npy_intp const *steps, void *data)
{
    closed_actuation_loop(args, dimensions, steps, CLOSED_FOR_ANGLE);
}

static void closed_actuation_deflection_loop(char **args, npy_intp const *dimensions,
                                             npy_intp const *steps, void *data)
{
    closed_actuation_loop(args, dimensions, steps, CLOSED_FOR_DEFLECTION);
}

/* ---- docstrings (NumPy prepends the call signature) -------------------- */

#define CLOSED_SIGN_DOC                                                                            \
    "Sign convention: with the tendon at +x (b > 0), F > 0 is the world force\n"                   \
    "-F e_x, pointing away from the tendon side, so the tendon tightens;\n"                        \
    "theta and delta are positive in the direction of F (theta = -(RHS of\n"                       \
    "eq. 22)/EI, delta = -(RHS of eq. 26)/EI); tau > 0 is tension.  F < 0 or\n"                    \
    "b < 0 returns the formula value (negative tau = compression).\n"

#define CLOSED_PARAMS_DOC                                                                          \
    "F : lateral point force [N], applied at arc length z.\n"                                      \
    "z : load position [m], 0 <= z <= L.\n"                                                        \
    "L : length [m], 0 < L < inf.\n"                                                               \
    "EI : flexural rigidity [N m^2], 0 < EI < inf.\n"                                              \
    "a : tendon path slope dr/ds [-]; path r(s) = a s + b (parallel a = 0,\n"                      \
    "    converging a = -b/L, semi-converging in between).\n"                                      \
    "b : tendon offset at the base [m].\n"                                                         \
    "k : tendon spring constant [N/m], 0 <= k <= inf.  np.inf is the\n"                            \
    "    inextensible limit (exact, no warning); 0 is no tendon.  Several\n"                       \
    "    equally spaced tendons: k * pattern_factor(n); compressible\n"                            \
    "    backbone: equivalent_stiffness(k, k_backbone).\n"

#define CLOSED_DOMAIN_DOC                                                                          \
    "Outside the domain (or with a NaN input) the result is NaN and NumPy's\n"                     \
    "floating-point 'invalid' flag is raised, as NumPy's own ufuncs do\n"                          \
    "(see np.errstate).  A tendon on the centre line (a = b = 0) has no\n"                         \
    "moment arm: tau = 0 for every k, including k = inf (the k -> inf limit\n"                     \
    "at fixed geometry; the limit b -> 0 at k = inf is different, see\n"                           \
    "tendonrod.analytic).\n"

static const char closed_tension_doc[] =
    "tension(F, z, L, EI, a, b, k)\n\n"
    "Tendon reaction tension tau [N] under a lateral point load (paper eq. 25).\n\n"
    "tau = k F (a z^3 + 3 b z^2) / (6 EI + k L (2 a^2 L^2 + 6 a b L + 6 b^2)),\n"
    "evaluated as F (a z^3 + 3 b z^2) / (6 EI/k + L (...)).  Eq. 6 is the\n"
    "parallel case a = 0, b = r; eq. 13 its inextensible limit F z^2/(2 r L).\n\n" CLOSED_PARAMS_DOC
    "\n" CLOSED_SIGN_DOC "\n" CLOSED_DOMAIN_DOC;

static const char closed_angle_doc[] =
    "angle(s, F, z, L, EI, a, b, k)\n\n"
    "Tangent angle theta(s) [rad] of the loaded cantilever (paper eq. 22 with\n"
    "tau from eq. 25; eq. 3 is the parallel case, eq. 5 theta(L)).\n\n"
    "s : arc length [m], 0 <= s <= L.\n" CLOSED_PARAMS_DOC "\n" CLOSED_SIGN_DOC
    "\n" CLOSED_DOMAIN_DOC;

static const char closed_deflection_doc[] =
    "deflection(s, F, z, L, EI, a, b, k)\n\n"
    "Lateral deflection delta(s) [m] of the loaded cantilever (paper eq. 26\n"
    "with tau from eq. 25; eq. 7 is the parallel case; eqs. 8-12 and 27-34\n"
    "are s = z and z = L).\n\n"
    "s : arc length [m], 0 <= s <= L.\n" CLOSED_PARAMS_DOC "\n" CLOSED_SIGN_DOC
    "\n" CLOSED_DOMAIN_DOC;

static const char closed_equivalent_stiffness_doc[] =
    "equivalent_stiffness(k, k_backbone)\n\n"
    "Equivalent tendon stiffness [N/m] of a tendon on a compressible backbone\n"
    "(paper eq. 17): k_eq = k_backbone k / (k_backbone + k), the two springs in\n"
    "series.  Pass the result as k to tension/angle/deflection for a single\n"
    "tendon (or a one-sided set).  Do not combine with pattern_factor for a\n"
    "balanced pretensioned set: its tension changes sum to zero.\n\n"
    "k : tendon spring constant [N/m], 0 <= k <= inf.\n"
    "k_backbone : axial backbone stiffness [N/m] (E A / L), 0 <= k_backbone <= inf.\n\n"
    "Limits are exact: k_backbone = inf gives k, k = inf gives k_backbone.\n"
    "Negative or NaN input gives NaN and the 'invalid' flag.\n";

static const char closed_pattern_factor_doc[] =
    "pattern_factor(n)\n\n"
    "Pattern factor P = sum_{i=1..n} cos^2(2 pi i / n) [-] of n equally spaced\n"
    "tendons (paper eqs. 19-20, 35-36): n/2 for n >= 3, 2 for n = 2, 1 for n = 1.\n"
    "n equally spaced, equally pretensioned tendons of stiffness k act like one\n"
    "tendon of stiffness k P; the pretension cancels.  For n = 1, 2 the load\n"
    "is taken along tendon n (phi_n = 2 pi); for n >= 3 P does not depend on\n"
    "the load direction.\n\n"
    "n : number of tendons, a positive integer (any numeric dtype).\n"
    "Non-integer, < 1, inf or NaN gives NaN and the 'invalid' flag.\n";

static const char closed_actuation_angle_doc[] =
    "actuation_tension_for_angle(theta_L, L, EI, a, b)\n\n"
    "Tendon tension [N] that bends the unloaded beam to the tip angle theta_L\n"
    "(paper eqs. 37-38): tau = EI theta_L / (L (b + a L / 2)).\n"
    "Parallel (a = 0, b = r): EI theta_L/(r L); converging (a = -b/L):\n"
    "2 EI theta_L/(b L), twice the parallel tension.\n\n"
    "theta_L : tip angle [rad], positive toward the tendon side.\n"
    "L : length [m], 0 < L < inf.  EI : [N m^2], 0 < EI < inf.\n"
    "a : tendon path slope [-].  b : tendon base offset [m].\n\n"
    "Outside the domain, with a NaN input, or where the mean offset\n"
    "b + a L/2 is 0 (no tension can bend the tip), the result is NaN and\n"
    "the 'invalid' flag is raised.\n";

static const char closed_actuation_deflection_doc[] =
    "actuation_tension_for_deflection(delta_L, L, EI, a, b)\n\n"
    "Tendon tension [N] that moves the unloaded beam's tip by delta_L (paper\n"
    "eqs. 39-40): tau = EI delta_L / (L^2 (b/2 + a L/6)).\n"
    "Parallel (a = 0, b = r): 2 EI delta_L/(r L^2); converging (a = -b/L):\n"
    "3 EI delta_L/(b L^2), 1.5 times the parallel tension.\n\n"
    "delta_L : tip deflection [m], positive toward the tendon side.\n"
    "L : length [m], 0 < L < inf.  EI : [N m^2], 0 < EI < inf.\n"
    "a : tendon path slope [-].  b : tendon base offset [m].\n\n"
    "Outside the domain, with a NaN input, or where b/2 + a L/6 is 0\n"
    "(a = -3b/L), the result is NaN and the 'invalid' flag is raised.\n";

/* ---- registration ------------------------------------------------------ */

static PyUFuncGenericFunction closed_tension_funcs[] = {closed_tension_loop};
static PyUFuncGenericFunction closed_angle_funcs[] = {closed_angle_loop};
static PyUFuncGenericFunction closed_deflection_funcs[] = {closed_deflection_loop};
static PyUFuncGenericFunction closed_equivalent_stiffness_funcs[] = {
    closed_equivalent_stiffness_loop};
static PyUFuncGenericFunction closed_pattern_factor_funcs[] = {closed_pattern_factor_loop};
static PyUFuncGenericFunction closed_actuation_angle_funcs[] = {closed_actuation_angle_loop};
static PyUFuncGenericFunction closed_actuation_deflection_funcs[] = {
    closed_actuation_deflection_loop};

/* One loop each, all float64 (9 = the most operands, 8 in + 1 out). */
static const char closed_types[9] = {NPY_DOUBLE, NPY_DOUBLE, NPY_DOUBLE, NPY_DOUBLE, NPY_DOUBLE,
                                     NPY_DOUBLE, NPY_DOUBLE, NPY_DOUBLE, NPY_DOUBLE};
static void *closed_data[] = {NULL};

typedef struct {
    const char *name;
    PyUFuncGenericFunction *funcs;
    int nin;
    const char *doc;
} closed_ufunc_spec;

static const closed_ufunc_spec closed_ufuncs[] = {
    {"tension", closed_tension_funcs, 7, closed_tension_doc},
    {"angle", closed_angle_funcs, 8, closed_angle_doc},
    {"deflection", closed_deflection_funcs, 8, closed_deflection_doc},
    {"equivalent_stiffness", closed_equivalent_stiffness_funcs, 2, closed_equivalent_stiffness_doc},
    {"pattern_factor", closed_pattern_factor_funcs, 1, closed_pattern_factor_doc},
    {"actuation_tension_for_angle", closed_actuation_angle_funcs, 5, closed_actuation_angle_doc},
    {"actuation_tension_for_deflection", closed_actuation_deflection_funcs, 5,
     closed_actuation_deflection_doc},
};

static int add_closed_forms(PyObject *module)
{
    /* BEGIN closed-form ufuncs (section 1) */
    const size_t n = sizeof closed_ufuncs / sizeof closed_ufuncs[0];
    for (size_t i = 0; i < n; i++) {
        const closed_ufunc_spec *u = &closed_ufuncs[i];
        PyObject *f = PyUFunc_FromFuncAndData(u->funcs, closed_data, closed_types, 1, u->nin, 1,
                                              PyUFunc_None, u->name, u->doc, 0);
        if (f == NULL) return -1;
        if (PyModule_AddObjectRef(module, u->name, f) < 0) {
            Py_DECREF(f);
            return -1;
        }
        Py_DECREF(f);
    }
    return 0;
    /* END closed-form ufuncs (section 1) */
}

/* ======================================================================== */
/* 2. Cosserat solver entry points                                           */
/* ======================================================================== */

/* BEGIN solver functions (section 2) */
#include <stdarg.h>
#include "tendonrod.h"

/* Options and arrays shared by _core.solve and _core.compliance. */
typedef struct {
    PyArrayObject *rod, *tendons, *loads, *dist, *guess, *jac, *nodes;
    int nt, nl, nnode;
    tr_options opt;
} solver_args;

static void solver_args_clear(solver_args *a)
{
    Py_XDECREF(a->rod);
    Py_XDECREF(a->tendons);
    Py_XDECREF(a->loads);
    Py_XDECREF(a->dist);
    Py_XDECREF(a->guess);
    Py_XDECREF(a->jac);
    Py_XDECREF(a->nodes);
}

/* Exception with a printf-style message (doubles formatted with %g). */
static void solver_err(PyObject *type, const char *fmt, ...)
{
    char buf[TR_MSGLEN + 128];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    PyErr_SetString(type, buf);
}

/* float64, C-contiguous copy-or-view of obj; NULL + exception naming `name`. */
static PyArrayObject *solver_coerce(PyObject *obj, const char *name)
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

static int solver_all_finite(PyArrayObject *a, const char *name, int allow_posinf_col, int ncol)
{
    const double *v = (const double *)PyArray_DATA(a);
    npy_intp i, n = PyArray_SIZE(a);
    for (i = 0; i < n; i++) {
        if (isnan(v[i]) || (isinf(v[i]) && !(allow_posinf_col >= 0 && ncol > 0 &&
                                             i % ncol == allow_posinf_col && v[i] > 0))) {
            solver_err(PyExc_ValueError, "%s contains a non-finite value %g at flat index %ld",
                       name, v[i], (long)i);
            return -1;
        }
    }
    return 0;
}

static int solver_choice(const char *value, const char *name, const char *const *choices, int n,
                         int *out)
{
    int i;
    for (i = 0; i < n; i++)
        if (strcmp(value, choices[i]) == 0) {
            *out = i;
            return 0;
        }
    PyErr_Format(PyExc_ValueError, "%s = '%s' is not one of the accepted values", name, value);
    return -1;
}

/* An int option in [lo, hi] from any Python int; ValueError/TypeError naming it. */
static int solver_int(PyObject *obj, const char *name, long long lo, long long hi, int *out)
{
    long long v;
    int overflow = 0;
    if (obj == NULL) return 0;
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

static const char *const solver_integrators[] = {"rk4", "rk8", "adaptive"};
static const char *const solver_jacobians[] = {"fd", "newton", "hybrid"};
static const char *const solver_slack[] = {"linear", "squared"};

/* Parse the shared part; returns 0 or -1 with an exception set. */
static int solver_prepare(solver_args *a, PyObject *rod, PyObject *tendons, PyObject *loads,
                          PyObject *dist, PyObject *guess, PyObject *jacobian,
                          const char *integrator, int steps, double rtol, double tol, int max_iter,
                          int max_nfev, const char *jac_method, const char *slack_model,
                          int continuation, int max_continuation, PyObject *nodes,
                          int force_spatial, int tip_only, int shooting_segments)
{
    int ig, jm, sm;
    memset(a, 0, sizeof *a);
    a->opt = tr_default_options();
    if (solver_choice(integrator, "integrator", solver_integrators, 3, &ig) < 0 ||
        solver_choice(jac_method, "jacobian_method", solver_jacobians, 3, &jm) < 0 ||
        solver_choice(slack_model, "slack_model", solver_slack, 2, &sm) < 0)
        return -1;
    if (steps < 0) {
        PyErr_Format(PyExc_ValueError, "steps = %d must be >= 0 (0: automatic)", steps);
        return -1;
    }
    /* below ~1e-14 no double-precision step can meet the tolerance: the adaptive
     * integrator would shrink its step to underflow (seconds per evaluation) */
    if (!(rtol >= TR_RTOL_MIN) || !(rtol < 1.0)) {
        solver_err(PyExc_ValueError,
                   "rtol = %g must lie in [%g, 1) (double precision cannot "
                   "deliver less)",
                   rtol, TR_RTOL_MIN);
        return -1;
    }
    if (!(tol > 0.0) || !isfinite(tol)) {
        solver_err(PyExc_ValueError, "tol = %g must be finite and > 0", tol);
        return -1;
    }
    if (max_iter < 0 || max_nfev < 1 || max_continuation < 0) {
        PyErr_Format(PyExc_ValueError,
                     "max_iter = %d, max_nfev = %d, max_continuation = %d: "
                     "need max_iter >= 0, max_nfev >= 1, max_continuation >= 0",
                     max_iter, max_nfev, max_continuation);
        return -1;
    }
    a->opt.integrator = ig;
    a->opt.steps = steps;
    a->opt.rtol = rtol;
    a->opt.tol = tol;
    a->opt.max_iter = max_iter;
    a->opt.max_nfev = max_nfev;
    a->opt.jacobian_method = jm;
    a->opt.slack_model = sm;
    a->opt.continuation = continuation;
    a->opt.max_continuation = max_continuation;
    a->opt.force_spatial = force_spatial;
    a->opt.tip_only = tip_only;
    a->opt.shooting_segments = shooting_segments;

    if (!(a->rod = solver_coerce(rod, "rod"))) return -1;
    if (PyArray_NDIM(a->rod) != 1 || PyArray_DIM(a->rod, 0) != 6) {
        PyErr_SetString(PyExc_ValueError,
                        "rod must have shape (6,): [L, EI, GJ, EA, GA, kirchhoff]");
        return -1;
    }
    if (!(a->tendons = solver_coerce(tendons, "tendons"))) return -1;
    if (PyArray_SIZE(a->tendons) == 0 && PyArray_NDIM(a->tendons) <= 2) {
        a->nt = 0;
    } else if (PyArray_NDIM(a->tendons) != 2 || PyArray_DIM(a->tendons, 1) != 8) {
        PyErr_SetString(PyExc_ValueError, "tendons must have shape (nt, 8): rows [offset, angle, "
                                          "slope, EA, end, control, value, pretension]");
        return -1;
    } else {
        a->nt = (int)PyArray_DIM(a->tendons, 0);
    }
    if (!(a->loads = solver_coerce(loads, "loads"))) return -1;
    if (PyArray_SIZE(a->loads) == 0 && PyArray_NDIM(a->loads) <= 2) {
        a->nl = 0;
    } else if (PyArray_NDIM(a->loads) != 2 || PyArray_DIM(a->loads, 1) != 7) {
        PyErr_SetString(PyExc_ValueError,
                        "loads must have shape (nl, 7): rows [s, Fx, Fy, Fz, Mx, My, Mz]");
        return -1;
    } else {
        a->nl = (int)PyArray_DIM(a->loads, 0);
    }
    if (!(a->dist = solver_coerce(dist, "dist"))) return -1;
    if (PyArray_NDIM(a->dist) != 1 || PyArray_DIM(a->dist, 0) != 3) {
        PyErr_SetString(PyExc_ValueError,
                        "dist must have shape (3,): distributed force, world frame [N/m]");
        return -1;
    }
    {
        /* rod: EA, GA may be inf only for a Kirchhoff rod; the C core checks values */
        const double *r = (const double *)PyArray_DATA(a->rod);
        int i;
        for (i = 0; i < 6; i++)
            if (isnan(r[i]) || (isinf(r[i]) && !(i >= 3 && i <= 4 && r[5] != 0.0 && r[i] > 0))) {
                solver_err(PyExc_ValueError,
                           "rod[%d] = %g must be finite (EA, GA may be inf only "
                           "for a Kirchhoff rod)",
                           i, r[i]);
                return -1;
            }
    }
    if (a->nt > 0 && solver_all_finite(a->tendons, "tendons", 3, 8) < 0) return -1;
    if (a->nl > 0 && solver_all_finite(a->loads, "loads", -1, 0) < 0) return -1;
    if (solver_all_finite(a->dist, "dist", -1, 0) < 0) return -1;

    if (guess != NULL && guess != Py_None) {
        if (!(a->guess = solver_coerce(guess, "guess"))) return -1;
        if (PyArray_NDIM(a->guess) != 1 || PyArray_DIM(a->guess, 0) != 6 + 2 * a->nt) {
            PyErr_Format(PyExc_ValueError,
                         "guess must have shape (%d,): [n(0) (3), m(0) (3), "
                         "tension (nt), slack (nt)]",
                         6 + 2 * a->nt);
            return -1;
        }
        if (solver_all_finite(a->guess, "guess", -1, 0) < 0) return -1;
    }
    if (jacobian != NULL && jacobian != Py_None) {
        if (!(a->jac = solver_coerce(jacobian, "jacobian"))) return -1;
        if (PyArray_NDIM(a->jac) != 2 || PyArray_DIM(a->jac, 0) != PyArray_DIM(a->jac, 1)) {
            PyErr_SetString(PyExc_ValueError, "jacobian must be a square 2-D array (the 'jacobian' "
                                              "a previous solve returned)");
            return -1;
        }
    }
    if (nodes == NULL || nodes == Py_None) {
        a->nnode = 101;
    } else if (PyLong_Check(nodes) && !PyBool_Check(nodes)) {
        if (solver_int(nodes, "nodes", 2, 10000000, &a->nnode) < 0) return -1;
    } else {
        const double *v;
        npy_intp i;
        if (!(a->nodes = solver_coerce(nodes, "nodes"))) return -1;
        if (PyArray_NDIM(a->nodes) != 1 || PyArray_DIM(a->nodes, 0) < 1) {
            PyErr_SetString(PyExc_ValueError,
                            "nodes must be an int >= 2 or a non-empty 1-D array of arc lengths");
            return -1;
        }
        v = (const double *)PyArray_DATA(a->nodes);
        for (i = 0; i < PyArray_DIM(a->nodes, 0); i++)
            if (!isfinite(v[i]) || (i > 0 && v[i] < v[i - 1])) {
                solver_err(PyExc_ValueError, "nodes must be finite and sorted (nodes[%ld] = %g)",
                           (long)i, v[i]);
                return -1;
            }
        a->nnode = (int)PyArray_DIM(a->nodes, 0);
    }
    return 0;
}

/* Compile the model and workspace; ValueError with the core's message on a bad
 * model (it names the value), MemoryError on allocation failure. */
static int solver_build(solver_args *a, const double *extra_load, tr_model **mp, tr_data **dp)
{
    char msg[TR_MSGLEN];
    int status;
    const double *loads = a->nl > 0 ? (const double *)PyArray_DATA(a->loads) : NULL;
    double *tmp = NULL;
    int nl = a->nl;
    *mp = NULL;
    *dp = NULL;
    if (extra_load) {
        tmp = (double *)PyMem_Malloc((size_t)(7 * (nl + 1)) * sizeof(double));
        if (!tmp) {
            PyErr_NoMemory();
            return -1;
        }
        if (nl > 0) memcpy(tmp, loads, (size_t)(7 * nl) * sizeof(double));
        memcpy(tmp + 7 * nl, extra_load, 7 * sizeof(double));
        loads = tmp;
        nl++;
    }
    status =
        tr_model_alloc(mp, (const double *)PyArray_DATA(a->rod),
                       a->nt > 0 ? (const double *)PyArray_DATA(a->tendons) : NULL, a->nt, loads,
                       nl, (const double *)PyArray_DATA(a->dist), &a->opt, msg, sizeof msg);
    PyMem_Free(tmp);
    if (status != TR_OK) {
        if (status == TR_ENOMEM)
            PyErr_NoMemory();
        else
            PyErr_SetString(PyExc_ValueError, msg);
        return -1;
    }
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

static PyObject *solver_array(int nd, const npy_intp *dims, const double *src)
{
    PyObject *arr = PyArray_SimpleNew(nd, (npy_intp *)dims, NPY_DOUBLE);
    if (arr && src) {
        npy_intp n = PyArray_SIZE((PyArrayObject *)arr);
        if (n > 0) memcpy(PyArray_DATA((PyArrayObject *)arr), src, (size_t)n * sizeof(double));
    }
    return arr;
}

/* Steal `value` into dict[key]; returns -1 on error (value released). */
static int solver_set(PyObject *dict, const char *key, PyObject *value)
{
    int r;
    if (value == NULL) return -1;
    r = PyDict_SetItemString(dict, key, value);
    Py_DECREF(value);
    return r;
}

static PyObject *solver_result(const tr_model *m, const tr_data *d, int status)
{
    PyObject *res = PyDict_New(), *form = NULL;
    const int N = d->nnode, nt = m->nt, k = d->k;
    npy_intp dims[3];
    if (!res) return NULL;
    if (solver_set(res, "status", PyLong_FromLong(status)) < 0 ||
        solver_set(res, "message", PyUnicode_FromString(d->message)) < 0 ||
        solver_set(res, "success", PyBool_FromLong(TR_SUCCEEDED(status))) < 0 ||
        solver_set(res, "nit", PyLong_FromLong(d->nit)) < 0 ||
        solver_set(res, "nfev", PyLong_FromLong(d->nfev)) < 0 ||
        solver_set(res, "njev", PyLong_FromLong(d->njev)) < 0 ||
        solver_set(res, "residual_norm", PyFloat_FromDouble(d->residual_norm)) < 0 ||
        solver_set(res, "jacobian_cond", PyFloat_FromDouble(d->jacobian_cond)) < 0 ||
        solver_set(res, "truncation_estimate", PyFloat_FromDouble(d->truncation)) < 0 ||
        solver_set(res, "continuation_steps", PyLong_FromLong(d->cont_steps)) < 0)
        goto fail;
    dims[0] = N;
    if (solver_set(res, "s", solver_array(1, dims, d->s)) < 0) goto fail;
    dims[1] = 3;
    if (solver_set(res, "position", solver_array(2, dims, d->pos)) < 0 ||
        solver_set(res, "force", solver_array(2, dims, d->force)) < 0 ||
        solver_set(res, "moment", solver_array(2, dims, d->moment)) < 0)
        goto fail;
    dims[2] = 3;
    if (solver_set(res, "rotation", solver_array(3, dims, d->rot)) < 0) goto fail;
    dims[0] = nt;
    if (solver_set(res, "tension", solver_array(1, dims, d->tension)) < 0 ||
        solver_set(res, "slack", solver_array(1, dims, d->slack)) < 0 ||
        solver_set(res, "displacement", solver_array(1, dims, d->displacement)) < 0)
        goto fail;
    dims[0] = k;
    if (solver_set(res, "unknowns", solver_array(1, dims, d->x)) < 0) goto fail;
    dims[1] = k;
    if (solver_set(res, "jacobian", solver_array(2, dims, d->J)) < 0) goto fail;
    form = PyDict_New();
    if (!form) goto fail;
    if (solver_set(form, "planar", PyBool_FromLong(m->planar)) < 0 ||
        solver_set(form, "kirchhoff", PyBool_FromLong(m->kirchhoff)) < 0 ||
        solver_set(form, "n_unknowns", PyLong_FromLong(m->n_unknowns)) < 0 ||
        solver_set(form, "n_states", PyLong_FromLong(m->n_states)) < 0 ||
        solver_set(form, "n_segments", PyLong_FromLong(m->nseg)) < 0 ||
        solver_set(form, "n_length_states", PyLong_FromLong(m->ndisp)) < 0 ||
        solver_set(form, "n_stretch_terms", PyLong_FromLong(m->n_stretch)) < 0 ||
        solver_set(form, "distributed_load", PyBool_FromLong(m->has_dist)) < 0 ||
        solver_set(form, "tip_only", PyBool_FromLong(d->opt.tip_only)) < 0 ||
        solver_set(form, "integrator",
                   PyUnicode_FromString(solver_integrators[d->opt.integrator])) < 0 ||
        solver_set(form, "steps",
                   PyLong_FromLong(d->opt.integrator == TR_ADAPTIVE ? 0 : d->steps)) < 0 ||
        solver_set(form, "slack_model", PyUnicode_FromString(solver_slack[d->opt.slack_model])) <
            0 ||
        solver_set(form, "jacobian_method",
                   PyUnicode_FromString(solver_jacobians[d->opt.jacobian_method])) < 0 ||
        solver_set(form, "shooting_segments", PyLong_FromLong(m->nshoot)) < 0)
        goto fail;
    if (solver_set(res, "formulation", form) < 0) {
        form = NULL;
        goto fail;
    }
    return res;
fail:
    Py_XDECREF(form);
    Py_DECREF(res);
    return NULL;
}

#define SOLVER_KW_TAIL                                                                             \
    "guess", "jacobian", "integrator", "steps", "rtol", "tol", "max_iter", "max_nfev",             \
        "jacobian_method", "slack_model", "continuation", "max_continuation", "nodes",             \
        "force_spatial", "tip_only", "shooting_segments"

PyDoc_STRVAR(
    core_solve_doc,
    "solve(rod, tendons, loads, dist, *, guess=None, jacobian=None, integrator='rk8', steps=0,\n"
    "      rtol=1e-10, tol=1e-10, max_iter=50, max_nfev=20000, jacobian_method='fd',\n"
    "      slack_model='linear', continuation=True, max_continuation=64, nodes=101,\n"
    "      force_spatial=False, tip_only=False, shooting_segments=1) -> dict\n\n"
    "Raw entry point of the Cosserat-rod/tendon shooting solver (see csrc/README.md).\n\n"
    "rod (6,) [L, EI, GJ, EA, GA, kirchhoff]; tendons (nt, 8) [offset, angle, slope, EA (inf:\n"
    "inextensible), end, control (0 displacement / 1 tension), value (q [m], > 0 retracts, or\n"
    "tau [N]), pretension [N]]; loads (nl, 7) [s, F (3), M (3)] world frame; dist (3,) N/m world.\n"
    "guess: None or (6 + 2 nt,) [n(0) world, m(0) world, tension, slack]; jacobian: None or the\n"
    "'jacobian' of a previous solve (reused when its shape matches: Broyden steps from it).\n"
    "integrator 'rk4' | 'rk8' (fixed steps; steps = total over [0, L], 0 = automatic with\n"
    "step-doubling verification) | 'adaptive' (GSL rk8pd with error control rtol).\n"
    "jacobian_method 'fd' (forward differences, then Broyden updates, refreshed on poor\n"
    "progress) | 'newton' (fresh forward differences every iteration) | 'hybrid' (GSL hybridsj:\n"
    "Powell dogleg trust region with the same finite-difference Jacobian).\n"
    "slack_model 'linear' (tau = tau_s max(g,0), slack = L max(-g,0)) | 'squared' (the paper's "
    "g^2).\n"
    "continuation: on failure ramp the actuation (loads off), then the loads, from the straight\n"
    "robot; at most max_continuation steps.  nodes: int (uniform nodes incl. 0 and L plus every\n"
    "interior breakpoint twice: the state before and after its jump) or a sorted 1-D array of\n"
    "arc lengths (a node at an interior breakpoint gives the state after the jump, unless the\n"
    "next node has the same s).  tip_only: only the tip (N = 1).  shooting_segments: M > 1\n"
    "adds full-state unknowns and continuity residuals at j L / M (multiple shooting, for\n"
    "tensile axial loads with L sqrt(T/EI) >~ 7).\n\n"
    "Returns a dict: status (0 ok, > 0 caveat, < 0 failure; _core.strerror(status)), message,\n"
    "success (converged: status >= 0 except 3, off the load path), nit, nfev (integrations, incl. "
    "the recording pass), njev,\n"
    "residual_norm (scaled max-norm), s (N,), position (N,3) world [m], rotation (N,3,3)\n"
    "body-to-world, force (N,3) and moment (N,3) internal backbone force/moment, world [N, N m],\n"
    "tension (nt,) [N], slack (nt,) [m], displacement (nt,) [m] (input q for displacement-\n"
    "controlled tendons; from the path length for tension-controlled ones), unknowns (k,)\n"
    "scaled [(n(0) + sum tau t0)/(EI/L^2), (m(0) + sum tau r x t0)/(EI/L), gammas],\n"
    "jacobian (k,k) scaled, jacobian_cond (1-norm), truncation_estimate (scaled residual at\n"
    "doubled steps; NaN when steps were given or the integrator is adaptive),\n"
    "continuation_steps, formulation (dict: planar, kirchhoff, n_unknowns, n_states,\n"
    "n_segments, n_length_states, n_stretch_terms, distributed_load, tip_only, integrator,\n"
    "steps, slack_model, jacobian_method, shooting_segments).\n");

static PyObject *core_solve(PyObject *self, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"rod", "tendons", "loads", "dist", SOLVER_KW_TAIL, NULL};
    PyObject *rod, *tendons, *loads, *dist, *guess = Py_None, *jacobian = Py_None, *nodes = NULL;
    const char *integrator = "rk8", *jac_method = "fd", *slack_model = "linear";
    int steps = 0, max_iter = 50, max_nfev = 20000, continuation = 1, max_continuation = 64;
    int force_spatial = 0, tip_only = 0, status;
    PyObject *o_steps = NULL, *o_max_iter = NULL, *o_max_nfev = NULL, *o_max_cont = NULL;
    PyObject *o_shoot = NULL;
    int shooting_segments = 1;
    double rtol = 1e-10, tol = 1e-10;
    solver_args a;
    tr_model *m = NULL;
    tr_data *d = NULL;
    PyObject *result = NULL;
    const double *g = NULL, *jac = NULL;

    memset(&a, 0, sizeof a);
    if (!PyArg_ParseTupleAndKeywords(
            args, kwds, "OOOO|$OOsOddOOsspOOppO", kwlist, &rod, &tendons, &loads, &dist, &guess,
            &jacobian, &integrator, &o_steps, &rtol, &tol, &o_max_iter, &o_max_nfev, &jac_method,
            &slack_model, &continuation, &o_max_cont, &nodes, &force_spatial, &tip_only, &o_shoot))
        return NULL;
    if (solver_int(o_steps, "steps", 0, TR_MAX_STEPS, &steps) < 0 ||
        solver_int(o_max_iter, "max_iter", 0, 1000000, &max_iter) < 0 ||
        solver_int(o_max_nfev, "max_nfev", 1, 1000000000, &max_nfev) < 0 ||
        solver_int(o_max_cont, "max_continuation", 0, 1000000, &max_continuation) < 0 ||
        solver_int(o_shoot, "shooting_segments", 1, TR_MAX_SHOOTING_SEGMENTS, &shooting_segments) <
            0)
        return NULL;
    if (solver_prepare(&a, rod, tendons, loads, dist, guess, jacobian, integrator, steps, rtol, tol,
                       max_iter, max_nfev, jac_method, slack_model, continuation, max_continuation,
                       nodes, force_spatial, tip_only, shooting_segments) < 0)
        goto done;
    if (solver_build(&a, NULL, &m, &d) < 0) goto done;
    g = a.guess ? (const double *)PyArray_DATA(a.guess) : NULL;
    if (a.jac && PyArray_DIM(a.jac, 0) == m->n_unknowns) jac = (const double *)PyArray_DATA(a.jac);
    Py_BEGIN_ALLOW_THREADS status = tr_solve(m, d, g, jac);
    Py_END_ALLOW_THREADS result = solver_result(m, d, status);
done:
    tr_data_free(d);
    tr_model_free(m);
    solver_args_clear(&a);
    return result;
}

PyDoc_STRVAR(
    core_compliance_doc,
    "compliance(rod, tendons, loads, dist, s, *, guess=None, **options) -> (6, 6) array\n\n"
    "[dx (3), dtheta (3)] of the backbone point at arc length s per [force (3), moment (3)]\n"
    "applied there, world frame (dtheta: world rotation-vector increment), linearised at the\n"
    "solved state (solved first from `guess`, normally the solution's base state) with the\n"
    "prescribed displacements and tensions held fixed: implicit function theorem\n"
    "J du = -dF/dp with central differences on the shooting map (spatial formulation).\n"
    "Same options as solve (nodes, tip_only and force_spatial are ignored).  Raises\n"
    "RuntimeError with the solver's message if the state cannot be solved.\n");

static PyObject *core_compliance(PyObject *self, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"rod", "tendons", "loads", "dist", "s", SOLVER_KW_TAIL, NULL};
    PyObject *rod, *tendons, *loads, *dist, *guess = Py_None, *jacobian = Py_None, *nodes = NULL;
    const char *integrator = "rk8", *jac_method = "fd", *slack_model = "linear";
    int steps = 0, max_iter = 50, max_nfev = 20000, continuation = 1, max_continuation = 64;
    int force_spatial = 0, tip_only = 0, status;
    PyObject *o_steps = NULL, *o_max_iter = NULL, *o_max_nfev = NULL, *o_max_cont = NULL;
    PyObject *o_shoot = NULL;
    int shooting_segments = 1;
    double rtol = 1e-10, tol = 1e-10, s = 0.0, extra[7] = {0, 0, 0, 0, 0, 0, 0};
    solver_args a;
    tr_model *m = NULL;
    tr_data *d = NULL;
    PyObject *result = NULL;
    const double *g = NULL;
    double C[36];

    memset(&a, 0, sizeof a);
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OOOOd|$OOsOddOOsspOOppO", kwlist, &rod, &tendons,
                                     &loads, &dist, &s, &guess, &jacobian, &integrator, &o_steps,
                                     &rtol, &tol, &o_max_iter, &o_max_nfev, &jac_method,
                                     &slack_model, &continuation, &o_max_cont, &nodes,
                                     &force_spatial, &tip_only, &o_shoot))
        return NULL;
    if (solver_int(o_steps, "steps", 0, TR_MAX_STEPS, &steps) < 0 ||
        solver_int(o_max_iter, "max_iter", 0, 1000000, &max_iter) < 0 ||
        solver_int(o_max_nfev, "max_nfev", 1, 1000000000, &max_nfev) < 0 ||
        solver_int(o_max_cont, "max_continuation", 0, 1000000, &max_continuation) < 0 ||
        solver_int(o_shoot, "shooting_segments", 1, TR_MAX_SHOOTING_SEGMENTS, &shooting_segments) <
            0)
        return NULL;
    if (solver_prepare(&a, rod, tendons, loads, dist, guess, Py_None, integrator, steps, rtol, tol,
                       max_iter, max_nfev, jac_method, slack_model, continuation, max_continuation,
                       NULL, 1, 1, shooting_segments) < 0)
        goto done;
    {
        const double L = ((const double *)PyArray_DATA(a.rod))[0];
        if (!(s > 0.0 && s <= L)) {
            solver_err(PyExc_ValueError, "s = %g must lie in (0, L = %g]", s, L);
            goto done;
        }
    }
    extra[0] = s;
    if (solver_build(&a, extra, &m, &d) < 0) goto done;
    g = a.guess ? (const double *)PyArray_DATA(a.guess) : NULL;
    Py_BEGIN_ALLOW_THREADS status = tr_solve(m, d, g, NULL);
    if (TR_SUCCEEDED(status))
        status = tr_compliance(m, d, s, C);
    else if (status >= 0)
        status = TR_ECONTINUATION; /* linearising about an unvouched equilibrium: refuse */
    Py_END_ALLOW_THREADS if (status < 0)
    {
        solver_err(PyExc_RuntimeError, "compliance: %s (status %d: %s)", d->message, status,
                   tr_strerror(status));
        goto done;
    }
    {
        npy_intp dims[2] = {6, 6};
        result = solver_array(2, dims, C);
    }
done:
    tr_data_free(d);
    tr_model_free(m);
    solver_args_clear(&a);
    return result;
}

PyDoc_STRVAR(core_strerror_doc, "strerror(status) -> str: the name of a solver status code.");

static PyObject *core_strerror(PyObject *self, PyObject *arg)
{
    long code = PyLong_AsLong(arg);
    if (code == -1 && PyErr_Occurred()) return NULL;
    return PyUnicode_FromString(tr_strerror((int)code));
}

#define SOLVER_METHODS                                                                             \
    {"solve", (PyCFunction)(void (*)(void))core_solve, METH_VARARGS | METH_KEYWORDS,               \
     core_solve_doc},                                                                              \
        {"compliance", (PyCFunction)(void (*)(void))core_compliance, METH_VARARGS | METH_KEYWORDS, \
         core_compliance_doc},                                                                     \
        {"strerror", (PyCFunction)core_strerror, METH_O, core_strerror_doc},
/* END solver functions (section 2) */

/* BEGIN batch (section 2b: batch; owner: issue 7, tendonrod/batch.py) */
#include "tr_batch.h"

/* Optional per-point array of shape (n, *tail) (tail of length ntail); *n < 0 means
 * "not known yet" and is set from the first array given.  0 or -1 with ValueError. */
static int batch_points(PyObject *obj, const char *name, const npy_intp *tail, int ntail,
                        const char *what, PyArrayObject **out, npy_intp *n)
{
    int j, ok;
    *out = NULL;
    if (obj == NULL || obj == Py_None) return 0;
    if (!(*out = solver_coerce(obj, name))) return -1;
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

PyDoc_STRVAR(
    core_solve_batch_doc,
    "solve_batch(rod, tendons, loads, dist, *, values=None, point_loads=None, dists=None,\n"
    "            warm=True, retry_cold=False, predict=True, exact=False,\n"
    "            skip_tension_displacement=False, integrator='rk8', steps=0, rtol=1e-10, "
    "tol=1e-10,\n"
    "            max_iter=50, max_nfev=20000, jacobian_method='fd', slack_model='linear',\n"
    "            continuation=True, max_continuation=64, force_spatial=False,\n"
    "            shooting_segments=1) -> dict\n\n"
    "n scenes of one robot design in one call (csrc/tr_batch.h), the GIL released around the\n"
    "whole batch.  rod, tendons, loads, dist as for solve() fix the design, the control modes,\n"
    "the load positions and the formulation; per point vary: values (n, nt) actuation values\n"
    "(q [m] or tau [N] per the control column), point_loads (n, nl, 6) [F (3), M (3)] world,\n"
    "dists (n, 3) N/m world (None: the base value at every point; at least one must be given).\n"
    "warm: warm-start each point from the previous converged one (guess + Jacobian, as\n"
    "solve(guess=previous) does); retry_cold: retry a failed warm start without a guess;\n"
    "predict: start from the secant extrapolation of the last two converged points when the\n"
    "point continues their line.  steps > 0: warm points run a lean Newton/Broyden loop first\n"
    "(no step verification, no polish), falling back to the full solve on failure.\n"
    "exact: reproduce a loop of solve(guess=previous tip-only solution) bit for bit (the\n"
    "Python layer's guess map; no predictor, no lean loop).  skip_tension_displacement: the\n"
    "lean loop reads the tip from its last residual evaluation and skips the recording pass;\n"
    "the displacement of tension-controlled tendons is then NaN at those points.\n"
    "Returns a dict of arrays over the n points: tip_position (n,3) [m], tip_rotation (n,3,3),\n"
    "tension, slack, displacement (n,nt), residual_norm (n,), status, nit, nfev, cold (n,)\n"
    "int32, message (list of n str; '' where status == 0), formulation (dict: planar,\n"
    "n_unknowns).\n");

static PyObject *core_solve_batch(PyObject *self, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"rod",
                             "tendons",
                             "loads",
                             "dist",
                             "values",
                             "point_loads",
                             "dists",
                             "warm",
                             "retry_cold",
                             "predict",
                             "exact",
                             "skip_tension_displacement",
                             "integrator",
                             "steps",
                             "rtol",
                             "tol",
                             "max_iter",
                             "max_nfev",
                             "jacobian_method",
                             "slack_model",
                             "continuation",
                             "max_continuation",
                             "force_spatial",
                             "shooting_segments",
                             NULL};
    PyObject *rod, *tendons, *loads, *dist, *o_values = Py_None, *o_pl = Py_None,
                                            *o_dists = Py_None;
    const char *integrator = "rk8", *jac_method = "fd", *slack_model = "linear";
    int steps = 0, max_iter = 50, max_nfev = 20000, continuation = 1, max_continuation = 64;
    int force_spatial = 0, warm = 1, retry_cold = 0, predict = 1, exact = 0, shooting_segments = 1;
    int skip_td = 0;
    int status = TR_OK;
    PyObject *o_steps = NULL, *o_max_iter = NULL, *o_max_nfev = NULL, *o_max_cont = NULL;
    PyObject *o_shoot = NULL;
    double rtol = 1e-10, tol = 1e-10;
    solver_args a;
    tr_model *m = NULL;
    PyArrayObject *values = NULL, *pl = NULL, *dists = NULL;
    PyObject *pos = NULL, *rot = NULL, *ten = NULL, *sla = NULL, *dis = NULL, *res = NULL;
    PyObject *sta = NULL, *nit = NULL, *nfe = NULL, *cld = NULL, *msgs = NULL, *result = NULL;
    PyObject *form = NULL;
    char *mbuf = NULL;
    npy_intp n = -1, i;
    char emsg[TR_MSGLEN];

    memset(&a, 0, sizeof a);
    if (!PyArg_ParseTupleAndKeywords(
            args, kwds, "OOOO|$OOOpppppsOddOOsspOpO", kwlist, &rod, &tendons, &loads, &dist,
            &o_values, &o_pl, &o_dists, &warm, &retry_cold, &predict, &exact, &skip_td, &integrator,
            &o_steps, &rtol, &tol, &o_max_iter, &o_max_nfev, &jac_method, &slack_model,
            &continuation, &o_max_cont, &force_spatial, &o_shoot))
        return NULL;
    if (solver_int(o_steps, "steps", 0, TR_MAX_STEPS, &steps) < 0 ||
        solver_int(o_max_iter, "max_iter", 0, 1000000, &max_iter) < 0 ||
        solver_int(o_max_nfev, "max_nfev", 1, 1000000000, &max_nfev) < 0 ||
        solver_int(o_max_cont, "max_continuation", 0, 1000000, &max_continuation) < 0 ||
        solver_int(o_shoot, "shooting_segments", 1, TR_MAX_SHOOTING_SEGMENTS, &shooting_segments) <
            0)
        return NULL;
    if (solver_prepare(&a, rod, tendons, loads, dist, Py_None, Py_None, integrator, steps, rtol,
                       tol, max_iter, max_nfev, jac_method, slack_model, continuation,
                       max_continuation, NULL, force_spatial, 1, shooting_segments) < 0)
        goto done;
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
    status = tr_model_alloc(&m, (const double *)PyArray_DATA(a.rod),
                            a.nt > 0 ? (const double *)PyArray_DATA(a.tendons) : NULL, a.nt,
                            a.nl > 0 ? (const double *)PyArray_DATA(a.loads) : NULL, a.nl,
                            (const double *)PyArray_DATA(a.dist), &a.opt, emsg, sizeof emsg);
    if (status != TR_OK) {
        if (status == TR_ENOMEM)
            PyErr_NoMemory();
        else
            PyErr_SetString(PyExc_ValueError, emsg);
        goto done;
    }
    {
        npy_intp d2[2] = {n, 3}, d3[3] = {n, 3, 3}, dt[2] = {n, a.nt}, d1[1] = {n};
        pos = PyArray_SimpleNew(2, d2, NPY_DOUBLE);
        rot = PyArray_SimpleNew(3, d3, NPY_DOUBLE);
        ten = PyArray_SimpleNew(2, dt, NPY_DOUBLE);
        sla = PyArray_SimpleNew(2, dt, NPY_DOUBLE);
        dis = PyArray_SimpleNew(2, dt, NPY_DOUBLE);
        res = PyArray_SimpleNew(1, d1, NPY_DOUBLE);
        sta = PyArray_SimpleNew(1, d1, NPY_INT);
        nit = PyArray_SimpleNew(1, d1, NPY_INT);
        nfe = PyArray_SimpleNew(1, d1, NPY_INT);
        cld = PyArray_SimpleNew(1, d1, NPY_INT);
        /* zeroed: pages of points that converged are never written, so never resident */
        mbuf = (char *)calloc((size_t)(n > 0 ? n : 1), TR_MSGLEN);
        if (!pos || !rot || !ten || !sla || !dis || !res || !sta || !nit || !nfe || !cld) goto done;
        if (!mbuf) {
            PyErr_NoMemory();
            goto done;
        }
    }
    {
        tr_batch_in in;
        tr_batch_out out;
        in.n = (int)n;
        in.value = values ? (const double *)PyArray_DATA(values) : NULL;
        in.load = pl ? (const double *)PyArray_DATA(pl) : NULL;
        in.dist = dists ? (const double *)PyArray_DATA(dists) : NULL;
        in.warm = warm;
        in.retry_cold = retry_cold;
        in.predict = predict;
        in.exact = exact;
        in.skip_tension_displacement = skip_td;
        out.tip_pos = (double *)PyArray_DATA((PyArrayObject *)pos);
        out.tip_rot = (double *)PyArray_DATA((PyArrayObject *)rot);
        out.tension = (double *)PyArray_DATA((PyArrayObject *)ten);
        out.slack = (double *)PyArray_DATA((PyArrayObject *)sla);
        out.displacement = (double *)PyArray_DATA((PyArrayObject *)dis);
        out.residual = (double *)PyArray_DATA((PyArrayObject *)res);
        out.status = (int *)PyArray_DATA((PyArrayObject *)sta);
        out.nit = (int *)PyArray_DATA((PyArrayObject *)nit);
        out.nfev = (int *)PyArray_DATA((PyArrayObject *)nfe);
        out.cold = (int *)PyArray_DATA((PyArrayObject *)cld);
        out.message = mbuf;
        out.msglen = TR_MSGLEN;
        Py_BEGIN_ALLOW_THREADS status = tr_batch_solve(m, &a.opt, &in, &out, emsg, sizeof emsg);
        Py_END_ALLOW_THREADS
    }
    if (status != TR_OK) {
        if (status == TR_ENOMEM)
            PyErr_NoMemory();
        else
            PyErr_SetString(PyExc_ValueError, emsg);
        goto done;
    }
    if (!(msgs = PyList_New(n))) goto done;
    for (i = 0; i < n; i++) {
        const char *mi = mbuf + (size_t)i * TR_MSGLEN;
        const char *end = (const char *)memchr(mi, '\0', TR_MSGLEN);
        PyObject *s = PyUnicode_DecodeUTF8(mi, end ? (Py_ssize_t)(end - mi) : TR_MSGLEN, "replace");
        if (!s) goto done;
        PyList_SET_ITEM(msgs, i, s);
    }
    if (!(result = PyDict_New())) goto done;
    form = PyDict_New();
    if (!form || solver_set(form, "planar", PyBool_FromLong(m->planar)) < 0 ||
        solver_set(form, "kirchhoff", PyBool_FromLong(m->kirchhoff)) < 0 ||
        solver_set(form, "n_unknowns", PyLong_FromLong(m->n_unknowns)) < 0 ||
        solver_set(form, "n_states", PyLong_FromLong(m->n_states)) < 0)
        goto fail;
    if (PyDict_SetItemString(result, "tip_position", pos) < 0 ||
        PyDict_SetItemString(result, "tip_rotation", rot) < 0 ||
        PyDict_SetItemString(result, "tension", ten) < 0 ||
        PyDict_SetItemString(result, "slack", sla) < 0 ||
        PyDict_SetItemString(result, "displacement", dis) < 0 ||
        PyDict_SetItemString(result, "residual_norm", res) < 0 ||
        PyDict_SetItemString(result, "status", sta) < 0 ||
        PyDict_SetItemString(result, "nit", nit) < 0 ||
        PyDict_SetItemString(result, "nfev", nfe) < 0 ||
        PyDict_SetItemString(result, "cold", cld) < 0 ||
        PyDict_SetItemString(result, "message", msgs) < 0 ||
        PyDict_SetItemString(result, "formulation", form) < 0)
        goto fail;
    goto done;
fail:
    Py_CLEAR(result);
done:
    free(mbuf);
    Py_XDECREF(form);
    Py_XDECREF(pos);
    Py_XDECREF(rot);
    Py_XDECREF(ten);
    Py_XDECREF(sla);
    Py_XDECREF(dis);
    Py_XDECREF(res);
    Py_XDECREF(sta);
    Py_XDECREF(nit);
    Py_XDECREF(nfe);
    Py_XDECREF(cld);
    Py_XDECREF(msgs);
    Py_XDECREF(values);
    Py_XDECREF(pl);
    Py_XDECREF(dists);
    tr_model_free(m);
    solver_args_clear(&a);
    return result;
}

#define BATCH_METHODS                                                                              \
    {"solve_batch", (PyCFunction)(void (*)(void))core_solve_batch, METH_VARARGS | METH_KEYWORDS,   \
     core_solve_batch_doc},
/* END batch (section 2b) */

static int add_solver(PyObject *module)
{
    /* BEGIN solver (section 2) */
    /* the one caveat status that is not a success (see TR_SUCCEEDED) */
    if (PyModule_AddIntConstant(module, "STATUS_OFFPATH", TR_OFFPATH) < 0) return -1;
    return 0;
    /* END solver (section 2) */
}

static PyMethodDef core_methods[] = {
    /* BEGIN method table (section 2 adds its entries here) */
    SOLVER_METHODS BATCH_METHODS /* section 2b: batch */
    /* END method table */
    {NULL, NULL, 0, NULL}};

/* ======================================================================== */
/* 3. module definition                                                      */
/* ======================================================================== */

static int core_exec(PyObject *module)
{
    if (PyModule_AddStringConstant(module, "gsl_version", gsl_version) < 0) return -1;
    if (add_closed_forms(module) < 0) return -1;
    if (add_solver(module) < 0) return -1;
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
