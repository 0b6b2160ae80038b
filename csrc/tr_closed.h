/*
 * tr_closed.h -- closed-form small-deflection formulas of the paper's
 * Sections II-III (Bernoulli-Euler cantilever with a tendon on a linear path),
 * as pure C99 scalar kernels.  No Python, no NumPy, no GSL, no state.
 *
 * Problem (paper Figs. 2 and 5): an initially straight cantilever of length L
 * [m] and flexural rigidity EI [N m^2], clamped at s = 0, carries a lateral
 * point force of magnitude F [N] at arc length z [m].  One tendon runs in a
 * frictionless channel at the radial offset r(s) = a s + b [m] (slope a [-],
 * base offset b [m]; parallel: a = 0, b = r; converging: a = -b/L), is fixed at
 * the tip and, at the base, to a spring of stiffness k [N/m] (k = INFINITY:
 * inextensible tendon, k = 0: no tendon).
 *
 * Sign convention (docs/model.md): with the tendon at +x (b > 0), F > 0 is the
 * world force -F e_x, i.e. it points away from the tendon side, so the tendon
 * is stretched and tightens.  theta(s) [rad] and delta(s) [m] are positive in
 * the direction of F, so theta(s) = -(right-hand side of eq. 22)/EI and
 * delta(s) = -(right-hand side of eq. 26)/EI.  tau > 0 is tension; F < 0 (or
 * b < 0) simply returns the formula value (a negative tau is a compression,
 * which only a pretensioned set of tendons can carry).
 *
 * Domain: 0 < L < inf, 0 < EI < inf, 0 <= z <= L, 0 <= s <= L,
 * 0 <= k <= inf, F, a, b not NaN.  Outside it every kernel returns NaN (a
 * quiet NaN: the caller decides how to report it; the NumPy glue raises the
 * floating-point "invalid" flag for every NaN it returns).
 *
 * Limits, handled exactly (no inf/inf, 0*inf or x/0 is ever evaluated for
 * finite F, a, b):
 *  - k = INFINITY: eq. 25 is evaluated as F(a z^3 + 3 b z^2)/(6EI/k + L Q),
 *    and 6EI/INFINITY = 0 gives the inextensible limit (eqs. 13, 29-30, 33-34).
 *  - k = 0: tau = 0 and the plain cantilever (tendon without stiffness).
 *  - a = b = 0 (tendon on the centre line): the tendon has no moment arm, so
 *    its stretch is zero to first order and tau = 0 for every finite k; we
 *    take the same value, tau = 0, at k = INFINITY (the limit k -> inf at
 *    fixed geometry).  Note that this limit is not uniform: for k = INFINITY
 *    and b -> 0 (a = 0) the tension F z^2/(2 b L) grows without bound while
 *    the tendon moment b tau stays F z^2/(2L), so the deflection tends to
 *    eq. 11, not to the plain cantilever.  A tendon exactly on the centre
 *    line is the plain cantilever.
 *
 * Every kernel is a C99 inline function so the NumPy loops inline it;
 * tr_closed.c provides the external definitions for other C callers.
 */
#ifndef TR_CLOSED_H
#define TR_CLOSED_H

#include <math.h>

/* ---------------------------------------------------------------------- */
/* Domain helpers                                                          */
/* ---------------------------------------------------------------------- */

/* 1 when (L, EI) is a valid beam: finite and positive (NaN fails). */
inline int tr_closed_beam_ok(double L, double EI)
{
    return L > 0.0 && L < INFINITY && EI > 0.0 && EI < INFINITY;
}

/* ---------------------------------------------------------------------- */
/* Eq. 25: tendon tension                                                  */
/* ---------------------------------------------------------------------- */

/*
 * Tendon reaction tension tau [N] (eq. 25; eq. 6 is a = 0, b = r, eq. 13 its
 * k -> inf limit; eq. 16 is eq. 6 with k = k_eq of eq. 17):
 *
 *   tau = k F (a z^3 + 3 b z^2) / (6 EI + k L (2 a^2 L^2 + 6 a b L + 6 b^2))
 *       =   F (a z^3 + 3 b z^2) / (6 EI / k + L Q),
 *   Q   = 2 a^2 L^2 + 6 a b L + 6 b^2 = 2 (a L + 3b/2)^2 + 3/2 b^2  [m^2]
 *
 * (Q = 6/L * integral_0^L r(s)^2 ds >= 0, zero only for a = b = 0; the sum of
 * squares is used so that rounding can never make it negative.)
 * Inputs: F [N], z [m] in [0, L], L [m], EI [N m^2], a [-], b [m],
 * k [N/m] in [0, inf].  Returns NaN outside the domain.
 */
inline double tr_closed_tension(double F, double z, double L, double EI, double a, double b,
                                double k)
{
    if (!(tr_closed_beam_ok(L, EI) && z >= 0.0 && z <= L && k >= 0.0) || isnan(F) || isnan(a) ||
        isnan(b))
        return NAN;
    {
        const double aL = a * L;
        const double h = aL + 1.5 * b;
        const double Q = 2.0 * h * h + 1.5 * b * b; /* [m^2] */
        if (k == 0.0 || Q == 0.0) return 0.0;       /* no tendon stiffness, or no arm */
        {
            const double N = z * z * (a * z + 3.0 * b); /* [m^3] */
            const double D = 6.0 * EI / k + L * Q;      /* [m^3]; k = inf: L Q */
            return F * N / D;
        }
    }
}

/* ---------------------------------------------------------------------- */
/* Eqs. 22 and 26 for a given tension                                      */
/* ---------------------------------------------------------------------- */

/*
 * Tangent angle theta(s) [rad] for a given tendon tension tau [N]
 * (eq. 22; eq. 3 is a = 0, b = r).  Rearranged without a branch on s < z:
 *
 *   theta(s) = [F m (2z - m) - tau s (a s + 2b)] / (2 EI),  m = min(s, z)
 *
 * (s < z: m = s gives -(1/2 (F + a tau) s^2 + (b tau - F z) s)/EI;
 *  s >= z: m = z gives -(1/2 a tau s^2 + b tau s - 1/2 F z^2)/EI.)
 * Checks only s in [0, L]; the caller has checked the rest (a NaN tau, as
 * tr_closed_tension returns outside its domain, propagates).
 */
inline double tr_closed_angle_tau(double s, double F, double z, double L, double EI, double a,
                                  double b, double tau)
{
    if (!(s >= 0.0 && s <= L)) return NAN;
    {
        const double m = s < z ? s : z;
        return (F * m * (2.0 * z - m) - tau * s * (a * s + 2.0 * b)) / (2.0 * EI);
    }
}

/*
 * Lateral deflection delta(s) [m] for a given tendon tension tau [N]
 * (eq. 26; eq. 7 is a = 0, b = r).  Rearranged without a branch on s < z
 * (the load part is Maxwell-symmetric in s and z):
 *
 *   delta(s) = [F m^2 (3M - m) - tau s^2 (a s + 3b)] / (6 EI),
 *   m = min(s, z), M = max(s, z), 3M - m = 2m + 3|s - z|
 *
 * (s < z: -(1/6 (F + a tau) s^3 + 1/2 (b tau - F z) s^2)/EI;
 *  s >= z: -(1/6 a tau s^3 + 1/2 b tau s^2 - 1/2 F z^2 s + 1/6 F z^3)/EI.)
 * Checks only s in [0, L], as tr_closed_angle_tau.
 */
inline double tr_closed_deflection_tau(double s, double F, double z, double L, double EI, double a,
                                       double b, double tau)
{
    if (!(s >= 0.0 && s <= L)) return NAN;
    {
        /* 3M - m = 2m + 3|s - z|: one select (minsd) and a fabs instead of
         * a branch on s < z, which compilers emit for a min/max pair and
         * which is mispredicted half the time for unordered s.  Same
         * value to a rounding of |s - z|. */
        const double m = s < z ? s : z;
        return (F * m * m * (2.0 * m + 3.0 * fabs(s - z)) - tau * s * s * (a * s + 3.0 * b)) /
               (6.0 * EI);
    }
}

/* ---------------------------------------------------------------------- */
/* Eqs. 22 and 26 with eq. 25                                              */
/* ---------------------------------------------------------------------- */

/* theta(s) [rad], eq. 22 with tau from eq. 25.  NaN outside the domain. */
inline double tr_closed_angle(double s, double F, double z, double L, double EI, double a, double b,
                              double k)
{
    const double tau = tr_closed_tension(F, z, L, EI, a, b, k);
    return tr_closed_angle_tau(s, F, z, L, EI, a, b, tau);
}

/* delta(s) [m], eq. 26 with tau from eq. 25.  NaN outside the domain. */
inline double tr_closed_deflection(double s, double F, double z, double L, double EI, double a,
                                   double b, double k)
{
    const double tau = tr_closed_tension(F, z, L, EI, a, b, k);
    return tr_closed_deflection_tau(s, F, z, L, EI, a, b, tau);
}

/* ---------------------------------------------------------------------- */
/* Eq. 17: backbone compression                                            */
/* ---------------------------------------------------------------------- */

/*
 * Equivalent stiffness [N/m] of the tendon spring k and the backbone's axial
 * spring k_B in series (eq. 17): k_eq = k_B k / (k_B + k).
 * Evaluated as printed (one division) while the product cannot overflow
 * (hi < 1e150 N/m), else as lo / (1 + lo/hi) with lo = min, hi = max, which
 * cannot overflow and gives the limits exactly: k_B = inf -> k,
 * k = inf -> k_B, either 0 -> 0, both inf -> inf.
 * Domain: k, k_B in [0, inf]; else NaN.
 */
inline double tr_closed_equivalent_stiffness(double k, double k_B)
{
    if (!(k >= 0.0 && k_B >= 0.0)) return NAN;
    if (k < 1e150 && k_B < 1e150) {
        const double sum = k_B + k;
        return sum > 0.0 ? k_B * k / sum : 0.0; /* both 0: 0 */
    }
    {
        /* lo / (1 + lo/hi); where lo/hi < 2^-53 that rounds to lo, and
         * returning lo directly also avoids an underflow of lo/hi and covers
         * hi = inf (and lo = hi = inf) exactly. */
        const double lo = k < k_B ? k : k_B;
        const double hi = k < k_B ? k_B : k;
        if (lo <= hi * 0x1p-53) return lo;
        return lo / (1.0 + lo / hi);
    }
}

/* ---------------------------------------------------------------------- */
/* Eqs. 19-20, 35-36: pattern factor of n equally spaced tendons           */
/* ---------------------------------------------------------------------- */

/*
 * P(n) = sum_{i=1..n} cos^2(2 pi i / n) [-] for n equally spaced tendons with
 * the load direction along tendon n (phi_n = 2 pi).  Exactly n/2 for n >= 3
 * (the double-angle terms sum to zero), 2 for n = 2 (both tendons in the
 * bending plane), 1 for n = 1.  For n >= 3 the value does not depend on the
 * load direction.  Domain: n a positive integer (as a double); else NaN.
 */
inline double tr_closed_pattern_factor(double n)
{
    /* Every double >= 2^52 is an integer; below it the round trip through a
     * 64-bit integer tests integrality without a libm call (floor). */
    const double two52 = 4503599627370496.0;
    if (!(n >= 1.0 && n < INFINITY)) return NAN;
    if (n < two52 && n != (double)(long long)n) return NAN;
    return n >= 3.0 ? 0.5 * n : n;
}

/* ---------------------------------------------------------------------- */
/* Eqs. 37-40: actuation tension in free space                             */
/* ---------------------------------------------------------------------- */

/*
 * Tension [N] that bends the unloaded beam (F = 0) to the tip angle theta_L
 * [rad] (eqs. 37-38, from eq. 22 at s = L with the theta sign reversed, so
 * theta_L > 0 is toward the tendon side):
 *
 *   tau = EI theta_L / (L (b + a L / 2))
 *
 * (parallel: EI theta_L/(r L), eq. 37; converging a = -b/L: 2 EI theta_L/(b L),
 * eq. 38).  b + a L/2 is the mean offset (1/L) int_0^L r ds; where it is 0
 * no tension bends the tip and the result is NaN (as outside the domain).
 * Domain: L, EI finite positive, theta_L, a, b not NaN.
 */
inline double tr_closed_actuation_tension_for_angle(double theta_L, double L, double EI, double a,
                                                    double b)
{
    if (!tr_closed_beam_ok(L, EI) || isnan(theta_L)) return NAN;
    {
        const double arm = b + 0.5 * a * L; /* [m] */
        if (!(arm != 0.0)) return NAN;
        return EI * theta_L / (L * arm);
    }
}

/*
 * Tension [N] that moves the unloaded beam's tip by delta_L [m] toward the
 * tendon side (eqs. 39-40, from eq. 26 at s = L, F = 0):
 *
 *   tau = EI delta_L / (L^2 (b/2 + a L/6))
 *
 * (parallel: 2 EI delta_L/(r L^2), eq. 39; converging: 3 EI delta_L/(b L^2),
 * eq. 40).  Where b/2 + a L/6 = 0 (a = -3b/L: the path crosses the centre
 * line at s = L/3) the result is NaN.  Domain as above.
 */
inline double tr_closed_actuation_tension_for_deflection(double delta_L, double L, double EI,
                                                         double a, double b)
{
    if (!tr_closed_beam_ok(L, EI) || isnan(delta_L)) return NAN;
    {
        const double arm = 0.5 * b + (1.0 / 6.0) * a * L; /* [m] */
        if (!(arm != 0.0)) return NAN;
        return EI * delta_L / (L * L * arm);
    }
}

#endif /* TR_CLOSED_H */
