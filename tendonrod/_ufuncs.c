/*
 * _ufuncs.c -- the closed forms (csrc/tr_closed.h) as NumPy ufuncs: one float64
 * loop each, so broadcasting, out= and where= come from NumPy.  Outside the domain
 * a kernel returns NaN and the loop raises the floating-point "invalid" flag, as
 * NumPy's own ufuncs do.
 */
#include "_glue.h"

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

/* ---- docstrings (NumPy prepends the call signature; NumPy-style sections for the
   API reference, whose Examples run as doctests: make docs) ---- */

static const char closed_tension_doc[] =
    "tension(F, z, L, EI, a, b, k)\n"
    "\n"
    "Tendon reaction tension tau [N] under a lateral point load (paper eq. 25).\n"
    "\n"
    "tau = k F (a z^3 + 3 b z^2) / (6 EI + k L (2 a^2 L^2 + 6 a b L + 6 b^2)),\n"
    "evaluated as F (a z^3 + 3 b z^2) / (6 EI/k + L (...)).  Eq. 6 is the\n"
    "parallel case a = 0, b = r; eq. 13 its inextensible limit F z^2/(2 r L).\n"
    "\n"
    "Parameters\n"
    "----------\n"
    "F : array_like\n"
    "    Lateral point force [N], applied at arc length z.\n"
    "z : array_like\n"
    "    Load position [m], 0 <= z <= L.\n"
    "L : array_like\n"
    "    Length [m], 0 < L < inf.\n"
    "EI : array_like\n"
    "    Flexural rigidity [N m^2], 0 < EI < inf.\n"
    "a : array_like\n"
    "    Tendon path slope dr/ds [-]; path r(s) = a s + b (parallel a = 0,\n"
    "    converging a = -b/L, semi-converging in between).\n"
    "b : array_like\n"
    "    Tendon offset at the base [m].\n"
    "k : array_like\n"
    "    Tendon spring constant [N/m], 0 <= k <= inf.  np.inf is the\n"
    "    inextensible limit (exact, no warning); 0 is no tendon.  Several\n"
    "    equally spaced tendons: k * pattern_factor(n); compressible\n"
    "    backbone: equivalent_stiffness(k, k_backbone).\n"
    "\n"
    "Returns\n"
    "-------\n"
    "ndarray or float\n"
    "    The tension [N], broadcast over the arguments.\n"
    "\n"
    "Notes\n"
    "-----\n"
    "Sign convention: with the tendon at +x (b > 0), F > 0 is the world force\n"
    "-F e_x, pointing away from the tendon side, so the tendon tightens;\n"
    "theta and delta are positive in the direction of F (theta = -(RHS of\n"
    "eq. 22)/EI, delta = -(RHS of eq. 26)/EI); tau > 0 is tension.  F < 0 or\n"
    "b < 0 returns the formula value (negative tau = compression).\n"
    "\n"
    "Outside the domain (or with a NaN input) the result is NaN and NumPy's\n"
    "floating-point 'invalid' flag is raised, as NumPy's own ufuncs do\n"
    "(see np.errstate).  A tendon on the centre line (a = b = 0) has no\n"
    "moment arm: tau = 0 for every k, including k = inf (the k -> inf limit\n"
    "at fixed geometry; the limit b -> 0 at k = inf is different, see\n"
    "tendonrod.analytic).\n"
    "\n"
    "Examples\n"
    "--------\n"
    ">>> from tendonrod import analytic as an\n"
    ">>> # inextensible parallel tendon, load at the tip: F z^2/(2 r L) = F L/(2 r)\n"
    ">>> round(float(an.tension(0.5, 0.2, 0.2, 0.0112, 0.0, 0.008, np.inf)), 9)\n"
    "6.25\n";

static const char closed_angle_doc[] =
    "angle(s, F, z, L, EI, a, b, k)\n"
    "\n"
    "Tangent angle theta(s) [rad] of the loaded cantilever (paper eq. 22 with\n"
    "tau from eq. 25; eq. 3 is the parallel case, eq. 5 theta(L)).\n"
    "\n"
    "Parameters\n"
    "----------\n"
    "s : array_like\n"
    "    Arc length [m], 0 <= s <= L.\n"
    "F : array_like\n"
    "    Lateral point force [N], applied at arc length z.\n"
    "z : array_like\n"
    "    Load position [m], 0 <= z <= L.\n"
    "L : array_like\n"
    "    Length [m], 0 < L < inf.\n"
    "EI : array_like\n"
    "    Flexural rigidity [N m^2], 0 < EI < inf.\n"
    "a : array_like\n"
    "    Tendon path slope dr/ds [-]; path r(s) = a s + b (parallel a = 0,\n"
    "    converging a = -b/L, semi-converging in between).\n"
    "b : array_like\n"
    "    Tendon offset at the base [m].\n"
    "k : array_like\n"
    "    Tendon spring constant [N/m], 0 <= k <= inf.  np.inf is the\n"
    "    inextensible limit (exact, no warning); 0 is no tendon.  Several\n"
    "    equally spaced tendons: k * pattern_factor(n); compressible\n"
    "    backbone: equivalent_stiffness(k, k_backbone).\n"
    "\n"
    "Returns\n"
    "-------\n"
    "ndarray or float\n"
    "    The tangent angle [rad], broadcast over the arguments.\n"
    "\n"
    "Notes\n"
    "-----\n"
    "Sign convention: with the tendon at +x (b > 0), F > 0 is the world force\n"
    "-F e_x, pointing away from the tendon side, so the tendon tightens;\n"
    "theta and delta are positive in the direction of F (theta = -(RHS of\n"
    "eq. 22)/EI, delta = -(RHS of eq. 26)/EI); tau > 0 is tension.  F < 0 or\n"
    "b < 0 returns the formula value (negative tau = compression).\n"
    "\n"
    "Outside the domain (or with a NaN input) the result is NaN and NumPy's\n"
    "floating-point 'invalid' flag is raised, as NumPy's own ufuncs do\n"
    "(see np.errstate).  A tendon on the centre line (a = b = 0) has no\n"
    "moment arm: tau = 0 for every k, including k = inf (the k -> inf limit\n"
    "at fixed geometry; the limit b -> 0 at k = inf is different, see\n"
    "tendonrod.analytic).\n"
    "\n"
    "Examples\n"
    "--------\n"
    ">>> from tendonrod import analytic as an\n"
    ">>> # no tendon: F L^2/(2 EI) at the tip\n"
    ">>> round(float(an.angle(0.2, 0.5, 0.2, 0.2, 0.0112, 0.0, 0.008, 0.0)), 6)\n"
    "0.892857\n";

static const char closed_deflection_doc[] =
    "deflection(s, F, z, L, EI, a, b, k)\n"
    "\n"
    "Lateral deflection delta(s) [m] of the loaded cantilever (paper eq. 26\n"
    "with tau from eq. 25; eq. 7 is the parallel case; eqs. 8-12 and 27-34\n"
    "are s = z and z = L).\n"
    "\n"
    "Parameters\n"
    "----------\n"
    "s : array_like\n"
    "    Arc length [m], 0 <= s <= L.\n"
    "F : array_like\n"
    "    Lateral point force [N], applied at arc length z.\n"
    "z : array_like\n"
    "    Load position [m], 0 <= z <= L.\n"
    "L : array_like\n"
    "    Length [m], 0 < L < inf.\n"
    "EI : array_like\n"
    "    Flexural rigidity [N m^2], 0 < EI < inf.\n"
    "a : array_like\n"
    "    Tendon path slope dr/ds [-]; path r(s) = a s + b (parallel a = 0,\n"
    "    converging a = -b/L, semi-converging in between).\n"
    "b : array_like\n"
    "    Tendon offset at the base [m].\n"
    "k : array_like\n"
    "    Tendon spring constant [N/m], 0 <= k <= inf.  np.inf is the\n"
    "    inextensible limit (exact, no warning); 0 is no tendon.  Several\n"
    "    equally spaced tendons: k * pattern_factor(n); compressible\n"
    "    backbone: equivalent_stiffness(k, k_backbone).\n"
    "\n"
    "Returns\n"
    "-------\n"
    "ndarray or float\n"
    "    The deflection [m], broadcast over the arguments.\n"
    "\n"
    "Notes\n"
    "-----\n"
    "Sign convention: with the tendon at +x (b > 0), F > 0 is the world force\n"
    "-F e_x, pointing away from the tendon side, so the tendon tightens;\n"
    "theta and delta are positive in the direction of F (theta = -(RHS of\n"
    "eq. 22)/EI, delta = -(RHS of eq. 26)/EI); tau > 0 is tension.  F < 0 or\n"
    "b < 0 returns the formula value (negative tau = compression).\n"
    "\n"
    "Outside the domain (or with a NaN input) the result is NaN and NumPy's\n"
    "floating-point 'invalid' flag is raised, as NumPy's own ufuncs do\n"
    "(see np.errstate).  A tendon on the centre line (a = b = 0) has no\n"
    "moment arm: tau = 0 for every k, including k = inf (the k -> inf limit\n"
    "at fixed geometry; the limit b -> 0 at k = inf is different, see\n"
    "tendonrod.analytic).\n"
    "\n"
    "Examples\n"
    "--------\n"
    ">>> from tendonrod import analytic as an\n"
    ">>> k = np.array([0.0, 4.5e3, np.inf])  # no tendon, a spring, inextensible\n"
    ">>> an.deflection(0.2, 0.5, 0.2, 0.2, 0.0112, 0.0, 0.008, k)\n"
    "array([0.119048, 0.044297, 0.029762])\n";

static const char closed_equivalent_stiffness_doc[] =
    "equivalent_stiffness(k, k_backbone)\n"
    "\n"
    "Equivalent tendon stiffness [N/m] of a tendon on a compressible backbone\n"
    "(paper eq. 17): k_eq = k_backbone k / (k_backbone + k), the two springs in\n"
    "series.  Pass the result as k to tension/angle/deflection for a single\n"
    "tendon (or a one-sided set).  Do not combine with pattern_factor for a\n"
    "balanced pretensioned set: its tension changes sum to zero.\n"
    "\n"
    "Parameters\n"
    "----------\n"
    "k : array_like\n"
    "    Tendon spring constant [N/m], 0 <= k <= inf.\n"
    "k_backbone : array_like\n"
    "    Axial backbone stiffness [N/m] (E A / L), 0 <= k_backbone <= inf.\n"
    "\n"
    "Returns\n"
    "-------\n"
    "ndarray or float\n"
    "    The series stiffness [N/m].  Limits are exact: k_backbone = inf gives k,\n"
    "    k = inf gives k_backbone.  Negative or NaN input gives NaN and the\n"
    "    'invalid' flag.\n"
    "\n"
    "Examples\n"
    "--------\n"
    ">>> from tendonrod import analytic as an\n"
    ">>> an.equivalent_stiffness(np.array([1e3, np.inf]), 1e3)\n"
    "array([ 500., 1000.])\n";

static const char closed_pattern_factor_doc[] =
    "pattern_factor(n)\n"
    "\n"
    "Pattern factor P = sum_{i=1..n} cos^2(2 pi i / n) [-] of n equally spaced\n"
    "tendons (paper eqs. 19-20, 35-36): n/2 for n >= 3, 2 for n = 2, 1 for n = 1.\n"
    "n equally spaced, equally pretensioned tendons of stiffness k act like one\n"
    "tendon of stiffness k P; the pretension cancels.  For n = 1, 2 the load\n"
    "is taken along tendon n (phi_n = 2 pi); for n >= 3 P does not depend on\n"
    "the load direction.\n"
    "\n"
    "Parameters\n"
    "----------\n"
    "n : array_like\n"
    "    Number of tendons, a positive integer (any numeric dtype).\n"
    "\n"
    "Returns\n"
    "-------\n"
    "ndarray or float\n"
    "    P [-].  Non-integer, < 1, inf or NaN gives NaN and the 'invalid' flag.\n"
    "\n"
    "Examples\n"
    "--------\n"
    ">>> from tendonrod import analytic as an\n"
    ">>> an.pattern_factor(np.arange(1, 6))\n"
    "array([1. , 2. , 1.5, 2. , 2.5])\n";

static const char closed_actuation_angle_doc[] =
    "actuation_tension_for_angle(theta_L, L, EI, a, b)\n"
    "\n"
    "Tendon tension [N] that bends the unloaded beam to the tip angle theta_L\n"
    "(paper eqs. 37-38): tau = EI theta_L / (L (b + a L / 2)).\n"
    "Parallel (a = 0, b = r): EI theta_L/(r L); converging (a = -b/L):\n"
    "2 EI theta_L/(b L), twice the parallel tension.\n"
    "\n"
    "Parameters\n"
    "----------\n"
    "theta_L : array_like\n"
    "    Tip angle [rad], positive toward the tendon side.\n"
    "L : array_like\n"
    "    Length [m], 0 < L < inf.\n"
    "EI : array_like\n"
    "    Flexural rigidity [N m^2], 0 < EI < inf.\n"
    "a : array_like\n"
    "    Tendon path slope [-].\n"
    "b : array_like\n"
    "    Tendon base offset [m].\n"
    "\n"
    "Returns\n"
    "-------\n"
    "ndarray or float\n"
    "    The tension [N].  Outside the domain, with a NaN input, or where the mean\n"
    "    offset b + a L/2 is 0 (no tension can bend the tip), NaN and the\n"
    "    'invalid' flag.\n"
    "\n"
    "Examples\n"
    "--------\n"
    ">>> from tendonrod import analytic as an\n"
    ">>> round(float(an.actuation_tension_for_angle(np.pi / 2, 0.2, 0.0112, 0.0, 0.008)), 4)\n"
    "10.9956\n";

static const char closed_actuation_deflection_doc[] =
    "actuation_tension_for_deflection(delta_L, L, EI, a, b)\n"
    "\n"
    "Tendon tension [N] that moves the unloaded beam's tip by delta_L (paper\n"
    "eqs. 39-40): tau = EI delta_L / (L^2 (b/2 + a L/6)).\n"
    "Parallel (a = 0, b = r): 2 EI delta_L/(r L^2); converging (a = -b/L):\n"
    "3 EI delta_L/(b L^2), 1.5 times the parallel tension.\n"
    "\n"
    "Parameters\n"
    "----------\n"
    "delta_L : array_like\n"
    "    Tip deflection [m], positive toward the tendon side.\n"
    "L : array_like\n"
    "    Length [m], 0 < L < inf.\n"
    "EI : array_like\n"
    "    Flexural rigidity [N m^2], 0 < EI < inf.\n"
    "a : array_like\n"
    "    Tendon path slope [-].\n"
    "b : array_like\n"
    "    Tendon base offset [m].\n"
    "\n"
    "Returns\n"
    "-------\n"
    "ndarray or float\n"
    "    The tension [N].  Outside the domain, with a NaN input, or where\n"
    "    b/2 + a L/6 is 0 (a = -3b/L), NaN and the 'invalid' flag.\n"
    "\n"
    "Examples\n"
    "--------\n"
    ">>> from tendonrod import analytic as an\n"
    ">>> round(float(an.actuation_tension_for_deflection(0.01, 0.2, 0.0112, 0.0, 0.008)), 4)\n"
    "0.7\n";

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

int glue_add_ufuncs(PyObject *module)
{
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
}
