"""Independent pure-NumPy versions of the paper's closed forms (Sections II-III).

Written from the paper's equations as printed (piecewise in s < z / s >= z,
the paper's own grouping of terms), not from the C kernels, which use a
branch-free rearrangement.  Sign convention as tendonrod.analytic: the paper's
eqs. 3, 7, 22, 26 give -EI theta and -EI delta, and theta, delta are positive
in the direction of F.  Every function broadcasts; no domain checks (the
tests feed valid designs).  ``k = np.inf`` uses the limit formula written out
by hand (eq. 25 with k -> inf), never inf arithmetic.
"""

import numpy as np


def _f(*xs):
    return np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in xs))


# ---------------------------------------------------------------- general (Sec. III)


def tension(F, z, L, EI, a, b, k):
    """Eq. 25; k = inf: F (a z^3 + 3 b z^2) / (L (2 a^2 L^2 + 6 a b L + 6 b^2));
    a = b = 0: 0 (tendon on the centre line, the documented choice)."""
    F, z, L, EI, a, b, k = _f(F, z, L, EI, a, b, k)
    num = a * z**3 + 3 * b * z**2
    geo = 2 * a**2 * L**2 + 6 * a * b * L + 6 * b**2
    centre = (a == 0) & (b == 0)
    inf = np.isinf(k)
    kf = np.where(inf, 1.0, k)
    geo_safe = np.where(centre, 1.0, geo)
    finite = kf * F * num / (6 * EI + kf * L * geo)
    inext = F * num / (L * geo_safe)
    return np.where(centre, 0.0, np.where(inf, inext, finite))


def angle_given_tau(s, F, z, EI, a, b, tau):
    """Eq. 22: -EI theta(s), piecewise, with a given tension."""
    s, F, z, EI, a, b, tau = _f(s, F, z, EI, a, b, tau)
    before = 0.5 * (F + a * tau) * s**2 + (b * tau - F * z) * s
    after = 0.5 * a * tau * s**2 + b * tau * s - 0.5 * F * z**2
    return -np.where(s < z, before, after) / EI


def deflection_given_tau(s, F, z, EI, a, b, tau):
    """Eq. 26: -EI delta(s), piecewise, with a given tension."""
    s, F, z, EI, a, b, tau = _f(s, F, z, EI, a, b, tau)
    before = (F + a * tau) * s**3 / 6 + 0.5 * (b * tau - F * z) * s**2
    after = a * tau * s**3 / 6 + 0.5 * b * tau * s**2 - 0.5 * F * z**2 * s + F * z**3 / 6
    return -np.where(s < z, before, after) / EI


def angle(s, F, z, L, EI, a, b, k):
    return angle_given_tau(s, F, z, EI, a, b, tension(F, z, L, EI, a, b, k))


def deflection(s, F, z, L, EI, a, b, k):
    return deflection_given_tau(s, F, z, EI, a, b, tension(F, z, L, EI, a, b, k))


def stretch(F, z, L, EI, a, b, tau):
    """Eq. 24: tendon stretch Delta [m] for a given tension."""
    return (
        F * a * z**3 / 6 + F * b * z**2 / 2 - (a**2 * L**2 / 3 + a * b * L + b**2) * tau * L
    ) / EI


def equivalent_stiffness(k, kB):
    """Eq. 17 with its limits written out: k_B k / (k_B + k)."""
    k, kB = _f(k, kB)
    with np.errstate(all="ignore"):
        v = kB * k / (kB + k)
    v = np.where(np.isinf(kB), k, v)
    v = np.where(np.isinf(k), kB, v)
    return np.where((k == 0) | (kB == 0), 0.0, v)


def pattern_factor_sum(n):
    """sum_{i=1..n} cos^2(2 pi i / n), summed term by term."""
    i = np.arange(1, int(n) + 1)
    return float(np.sum(np.cos(2 * np.pi * i / n) ** 2))


def actuation_tension_for_angle(theta_L, L, EI, a, b):
    """Eq. 22 at s = L, F = 0, theta sign reversed, solved for tau: the
    tip angle per unit tension is (a L^2/2 + b L)/EI."""
    return theta_L * EI / (0.5 * a * L**2 + b * L)


def actuation_tension_for_deflection(delta_L, L, EI, a, b):
    """Eq. 26 at s = L, F = 0, sign reversed, solved for tau: tip deflection
    per unit tension is (a L^3/6 + b L^2/2)/EI."""
    return delta_L * EI / (a * L**3 / 6 + 0.5 * b * L**2)


# ---------------------------------------------------------------- special cases


def eq3(s, F, z, EI, r, tau):
    """-EI theta(s) for a parallel tendon, piecewise; returns theta."""
    return (
        -np.where(s < z, 0.5 * F * s**2 + (r * tau - F * z) * s, r * tau * s - 0.5 * F * z**2) / EI
    )


def eq5(F, z, L, EI, r, k):
    return F * z**2 / (2 * (EI + r**2 * k * L))


def eq6(F, z, L, EI, r, k):
    return F * k * r * z**2 / (2 * (EI + r**2 * k * L))


def eq7(s, F, z, EI, r, tau):
    return (
        -np.where(
            s < z,
            F * s**3 / 6 + 0.5 * (r * tau - F * z) * s**2,
            0.5 * r * tau * s**2 - 0.5 * F * z**2 * s + F * z**3 / 6,
        )
        / EI
    )


def eq8(F, z, L, EI, r, k):
    return F * z**3 / (3 * EI) - (r**2 * k * z / (EI + r**2 * k * L)) * F * z**3 / (4 * EI)


def eq9(F, L, EI, r, k):
    return F * L**3 / (3 * EI) - (r**2 * k * L / (EI + r**2 * k * L)) * F * L**3 / (4 * EI)


def eq10(zeta, alpha):
    """sigma = (12 EI / L^3) delta / F at the loaded point."""
    return 4 * zeta**3 - 3 * (alpha / (1 + alpha)) * zeta**4


def eq11(F, z, L, EI):
    return F * z**3 / (3 * EI) - (z / L) * F * z**3 / (4 * EI)


def eq12(F, L, EI):
    return F * L**3 / (12 * EI)


def eq13(F, z, L, r):
    return F * z**2 / (2 * r * L)


def eq16(F, z, L, EI, r, k_eq):
    return F * z**2 / (2 * (EI + r**2 * L * k_eq))


def eq20(F, z, L, EI, r, k, n):
    P = pattern_factor_sum(n)
    return F * z**3 / (3 * EI) - (r**2 * k * z * P / (EI + r**2 * k * L * P)) * F * z**3 / (4 * EI)


def eq27(F, z, EI, a, b, tau):
    return F * z**3 / (3 * EI) - tau / (6 * EI) * (a * z**3 + 3 * b * z**2)


def eq28(F, L, EI, a, b, tau):
    return F * L**3 / (3 * EI) - tau / (6 * EI) * (a * L**3 + 3 * b * L**2)


def eq29(F, z, L, EI, a, b):
    return F * z**3 / (3 * EI) - (
        (a * z + 3 * b) ** 2 * z / (3 * L * (a**2 * L**2 + 3 * a * b * L + 3 * b**2))
    ) * F * z**3 / (4 * EI)


def eq30(F, L, EI, a, b):
    return F * L**3 / (3 * EI) - (
        (a * L + 3 * b) ** 2 / (3 * (a**2 * L**2 + 3 * a * b * L + 3 * b**2))
    ) * F * L**3 / (4 * EI)


def eq31(F, z, L, EI, b, k):
    return F * z**3 / (3 * EI) - (
        (3 * b * L * z**2 - b * z**3) ** 2 / (3 * EI + b**2 * k * L)
    ) * k * F / (12 * L**2 * EI)


def eq32(F, L, EI, b, k):
    return F * L**3 / (3 * EI) - (b**2 * k * L / (3 * EI + b**2 * k * L)) * F * L**3 / (3 * EI)


def eq33(F, z, L, EI):
    return F * z**3 / (3 * EI) - (z / L) * ((3 * L - z) / (np.sqrt(3) * L)) ** 2 * F * z**3 / (
        4 * EI
    )


def eq34(F, L, EI):
    return F * L**3 / (3 * EI) - (2 * L / (np.sqrt(3) * L)) ** 2 * F * L**3 / (4 * EI)


def eq36(F, z, L, EI, b, k, n):
    P = pattern_factor_sum(n)
    return F * z**3 / (3 * EI) - (
        (3 * b * L * z**2 - b * z**3) ** 2 * P / (3 * EI + b**2 * k * L * P)
    ) * k * F / (12 * L**2 * EI)


def eq37(theta_L, L, EI, r):
    return EI / (r * L) * theta_L


def eq38(theta_L, L, EI, b):
    return 2 * EI / (b * L) * theta_L


def eq39(delta_L, L, EI, r):
    return 2 * EI / (r * L**2) * delta_L


def eq40(delta_L, L, EI, b):
    return 3 * EI / (b * L**2) * delta_L
