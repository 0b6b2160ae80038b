"""The closed-form engine (paper Sections II-III): ufuncs against independent
pure-NumPy versions (tests/closed_ref.py), every special-case equation, the
paper's statements, and the ufunc mechanics (broadcasting, out=, where=,
dtypes, NaN + 'invalid' flag, TypeError)."""

import re
import warnings

import closed_ref as ref
import numpy as np
import pytest
from scipy import integrate, optimize

import tendonrod
from tendonrod import analytic as an

EPS = np.finfo(float).eps
INF = np.inf
UFUNCS = [
    "tension",
    "angle",
    "deflection",
    "equivalent_stiffness",
    "pattern_factor",
    "actuation_tension_for_angle",
    "actuation_tension_for_deflection",
]


# ----------------------------------------------------------------------------- designs


def designs(n, kind, k_kind, seed):
    """n random, physically sensible designs as a dict of float arrays.

    kind: 'parallel' (a = 0), 'converging' (a = -b/L), 'semi' (a = -u b/L,
    0 < u < 1), 'general' (any slope, paths may cross the centre line, b of
    either sign).  k_kind: 'finite' (alpha = b^2 k L / EI log-uniform over
    1e-3..1e4, plus some k = 0), 'inf'.  Loads F of either sign; z and s
    uniform on [0, L] with the end points and s = z included exactly.
    """
    rng = np.random.default_rng(seed)
    L = rng.uniform(0.02, 1.0, n)
    EI = 10.0 ** rng.uniform(-4, 1, n)
    b = rng.uniform(1e-3, 0.05, n)
    if kind == "parallel":
        a = np.zeros(n)
    elif kind == "converging":
        a = -b / L
    elif kind == "semi":
        a = -rng.uniform(0.01, 0.99, n) * b / L
    else:
        b = b * rng.choice([-1.0, 1.0], n)
        a = rng.uniform(-3, 3, n) * 0.05 / L
    if k_kind == "inf":
        k = np.full(n, INF)
    else:
        alpha = 10.0 ** rng.uniform(-3, 4, n)
        k = alpha * EI / (b**2 * L)
        k[::17] = 0.0
    F = rng.uniform(-10, 10, n)
    z = rng.uniform(0, 1, n) * L
    s = rng.uniform(0, 1, n) * L
    z[:5], s[5:10], s[10:15], s[15:20] = L[:5], L[5:10], 0.0, z[15:20]
    z[20:25] = 0.0
    return dict(F=F, z=z, L=L, EI=EI, a=a, b=b, k=k, s=s)


KINDS = [
    (kind, kk) for kind in ("parallel", "converging", "semi", "general") for kk in ("finite", "inf")
]


def tau_scale(d):
    """Magnitude of eq. 25 without cancellation in its numerator: the scale of
    the round-off in tau.  (The denominator is a positive-definite sum,
    2 a^2 L^2 + 6 a b L + 6 b^2 >= 0.39 (a^2 L^2 + b^2), so it cannot cancel.)"""
    num = d["z"] ** 2 * (np.abs(d["a"]) * d["z"] + 3 * np.abs(d["b"])) * np.abs(d["F"])
    geo = 2 * d["a"] ** 2 * d["L"] ** 2 + 6 * d["a"] * d["b"] * d["L"] + 6 * d["b"] ** 2
    with np.errstate(divide="ignore"):
        den = 6 * d["EI"] / d["k"] + d["L"] * geo
    return np.where((d["k"] == 0) | (geo == 0), 0.0, num / den)


def term_scale(d, power):
    """Sum of the magnitudes of the terms of eq. 22 (power 2) or eq. 26
    (power 3) at s, both pieces: the scale of their round-off, which matters
    where the terms cancel (e.g. eq. 34's zero tip deflection)."""
    s, z, F, a, b, EI = d["s"], d["z"], d["F"], d["a"], d["b"], d["EI"]
    T = tau_scale(d)
    load = np.abs(F) * (s**power + s ** (power - 1) * z + s * z ** (power - 1) + z**power)
    ten = T * (np.abs(a) * s**power + 3 * np.abs(b) * s ** (power - 1))
    return (load + ten) / EI


# Tolerance of ufunc vs reference: both evaluate the same algebra with about
# 10-15 roundings each, in a different association; every rounding is at most
# eps/2 of the magnitude of the term it touches, and the denominator of eq. 25
# has condition number <= 20 (see tau_scale).  64 eps of the term scale covers
# that with margin and is still ~1e-14: far below any modelling difference.
ROUND = 64 * EPS


# ----------------------------------------------------------------------------- general formulas


@pytest.mark.parametrize("kind,k_kind", KINDS)
def test_tension_matches_reference(kind, k_kind):
    d = designs(2000, kind, k_kind, seed=1)
    args = [d[x] for x in ("F", "z", "L", "EI", "a", "b", "k")]
    got, want = an.tension(*args), ref.tension(*args)
    assert np.all(np.abs(got - want) <= ROUND * tau_scale(d))


@pytest.mark.parametrize("kind,k_kind", KINDS)
def test_angle_matches_reference(kind, k_kind):
    d = designs(2000, kind, k_kind, seed=2)
    args = [d[x] for x in ("s", "F", "z", "L", "EI", "a", "b", "k")]
    got, want = an.angle(*args), ref.angle(*args)
    assert np.all(np.abs(got - want) <= ROUND * term_scale(d, 2))


@pytest.mark.parametrize("kind,k_kind", KINDS)
def test_deflection_matches_reference(kind, k_kind):
    d = designs(2000, kind, k_kind, seed=3)
    args = [d[x] for x in ("s", "F", "z", "L", "EI", "a", "b", "k")]
    got, want = an.deflection(*args), ref.deflection(*args)
    assert np.all(np.abs(got - want) <= ROUND * term_scale(d, 3))


def test_tolerance_is_tight_enough_to_catch_a_wrong_formula():
    # The tolerance must not hide real errors: a 1e-9 relative change of the
    # tension (e.g. a wrong constant) is caught by the same comparison.
    d = designs(2000, "semi", "finite", seed=3)
    args = [d[x] for x in ("s", "F", "z", "L", "EI", "a", "b", "k")]
    tau = ref.tension(*args[1:]) * (1 + 1e-9)
    wrong = ref.deflection_given_tau(d["s"], d["F"], d["z"], d["EI"], d["a"], d["b"], tau)
    assert not np.all(np.abs(an.deflection(*args) - wrong) <= ROUND * term_scale(d, 3))


def test_actuation_and_stiffness_match_reference():
    rng = np.random.default_rng(4)
    n = 2000
    L, EI = rng.uniform(0.02, 1, n), 10.0 ** rng.uniform(-4, 1, n)
    b = rng.uniform(1e-3, 0.05, n)
    a = -rng.uniform(0, 1, n) * b / L
    x = rng.uniform(-1, 1, n)
    # one division and a handful of products each: a few eps relative; the
    # mean arm b + a L/2 >= b/2 here, so there is no cancellation.
    np.testing.assert_allclose(
        an.actuation_tension_for_angle(x, L, EI, a, b),
        ref.actuation_tension_for_angle(x, L, EI, a, b),
        rtol=8 * EPS,
    )
    np.testing.assert_allclose(
        an.actuation_tension_for_deflection(x, L, EI, a, b),
        ref.actuation_tension_for_deflection(x, L, EI, a, b),
        rtol=8 * EPS,
    )
    k, kB = 10.0 ** rng.uniform(-3, 9, n), 10.0 ** rng.uniform(-3, 9, n)
    k[:10], kB[10:20], k[20:25], kB[20:25] = INF, INF, INF, INF
    kB[25:30], k[30:35] = 0.0, 0.0
    # a product and a sum, or lo/(1 + lo/hi): a few eps relative.
    np.testing.assert_allclose(
        an.equivalent_stiffness(k, kB), ref.equivalent_stiffness(k, kB), rtol=4 * EPS
    )
    # beyond 1e150 N/m the product k kB would overflow: the C kernel switches
    # to lo / (1 + lo/hi); still a few eps, no overflow warning
    with np.errstate(all="raise"):
        big = an.equivalent_stiffness(
            [1e200, 1e300, 1e300, 3e-300, 0.0], [1e200, 1e-300, 1e300, 1e300, 1e300]
        )
    np.testing.assert_allclose(big, [5e199, 1e-300, 5e299, 3e-300, 0.0], rtol=4 * EPS)


def test_pattern_factor_is_the_direct_sum():
    n = np.arange(1, 13)
    direct = np.array([ref.pattern_factor_sum(i) for i in n])
    # the direct sum of n cos^2 terms carries ~n eps of rounding; the ufunc is exact.
    np.testing.assert_allclose(an.pattern_factor(n), direct, rtol=0, atol=16 * EPS * 12)
    assert an.pattern_factor(1) == 1 and an.pattern_factor(2) == 2
    np.testing.assert_array_equal(an.pattern_factor(n[2:]), n[2:] / 2)


# ----------------------------------------------------------------------------- Section II special cases


def param_grid(seed=5, n=500):
    rng = np.random.default_rng(seed)
    L = rng.uniform(0.05, 0.5, n)
    EI = 10.0 ** rng.uniform(-3, 0, n)
    r = rng.uniform(1e-3, 0.03, n)
    k = 10.0 ** rng.uniform(-2, 4, n) * EI / (r**2 * L)
    F = rng.uniform(-5, 5, n)
    z = rng.uniform(0, 1, n) * L
    s = rng.uniform(0, 1, n) * L
    return L, EI, r, k, F, z, s


# Special-case formulas are the general one with a = 0, a = -b/L, s = z, z = L
# and k = inf substituted by hand: the same quantity with different rounding.
# rtol is a few tens of eps relative to the largest term of the formula, which
# is F L^3/(3 EI) or F z^3/(3 EI) for a deflection (checked via atol below).
SPECIAL = 64 * EPS


def close(got, want, scale):
    """|got - want| <= SPECIAL * scale, elementwise."""
    return np.all(np.abs(got - want) <= SPECIAL * np.abs(scale))


def test_eq3_eq5_eq6_eq7_parallel():
    L, EI, r, k, F, z, s = param_grid()
    tau = an.tension(F, z, L, EI, 0.0, r, k)
    assert close(tau, ref.eq6(F, z, L, EI, r, k), F * k * r * z**2 / (2 * EI))  # eq. 6
    assert close(
        an.angle(L, F, z, L, EI, 0.0, r, k), ref.eq5(F, z, L, EI, r, k), F * z**2 / EI
    )  # eq. 5
    assert close(
        an.angle(s, F, z, L, EI, 0.0, r, k), ref.eq3(s, F, z, EI, r, tau), F * L**2 / EI
    )  # eq. 3
    assert close(
        an.deflection(s, F, z, L, EI, 0.0, r, k), ref.eq7(s, F, z, EI, r, tau), F * L**3 / EI
    )  # eq. 7
    # eq. 4: tau = k r theta_L (the tendon stretch is r theta_L)
    assert close(tau, k * r * an.angle(L, F, z, L, EI, 0.0, r, k), F * k * r * z**2 / EI)


def test_eq8_eq9_eq10_loaded_point_and_tip():
    L, EI, r, k, F, z, s = param_grid()
    assert close(
        an.deflection(z, F, z, L, EI, 0.0, r, k), ref.eq8(F, z, L, EI, r, k), F * z**3 / EI
    )  # eq. 8
    assert close(
        an.deflection(L, F, L, L, EI, 0.0, r, k), ref.eq9(F, L, EI, r, k), F * L**3 / EI
    )  # eq. 9
    sigma = 12 * EI / L**3 * an.deflection(z, F, z, L, EI, 0.0, r, k) / F
    assert close(sigma, ref.eq10(z / L, r**2 * k * L / EI), 4.0)  # eq. 10


def test_eq11_eq12_eq13_inextensible_parallel():
    L, EI, r, k, F, z, s = param_grid()
    assert close(
        an.deflection(z, F, z, L, EI, 0.0, r, INF), ref.eq11(F, z, L, EI), F * z**3 / EI
    )  # eq. 11
    assert close(
        an.deflection(L, F, L, L, EI, 0.0, r, INF), ref.eq12(F, L, EI), F * L**3 / EI
    )  # eq. 12
    tau = an.tension(F, z, L, EI, 0.0, r, INF)
    assert close(tau, ref.eq13(F, z, L, r), F * z**2 / (r * L))  # eq. 13
    # eq. 13 does not depend on EI: the same tension for a 1000x stiffer beam
    assert close(an.tension(F, z, L, 1e3 * EI, 0.0, r, INF), tau, F * z**2 / (r * L))
    # lim k->inf theta_L = 0 (the sentence after eq. 10): the tip keeps its angle
    assert close(an.angle(L, F, z, L, EI, 0.0, r, INF), 0.0, F * z**2 / EI)


def test_eq12_statement_tip_compliance_is_one_quarter():
    L, EI, r, k, F, z, s = param_grid()
    ratio = an.deflection(L, F, L, L, EI, 0.0, r, INF) / an.deflection(L, F, L, L, EI, 0.0, r, 0.0)
    # exactly 1/4 in exact arithmetic; a ratio of two results with a few
    # roundings each
    np.testing.assert_allclose(ratio, 0.25, rtol=16 * EPS)


def test_compliance_approaches_the_inextensible_limit():
    # k = inf is the limit of large k: at alpha = 1e12 the finite-k result is
    # within ~1/alpha (relative) of the k = inf value.
    L, EI, r, k, F, z, s = param_grid()
    k_big = 1e12 * EI / (r**2 * L)
    for a in (0.0 * r, -r / L, -0.5 * r / L):
        d_inf = an.deflection(s, F, z, L, EI, a, r, INF)
        d_big = an.deflection(s, F, z, L, EI, a, r, k_big)
        assert np.all(np.abs(d_big - d_inf) <= 1e-10 * np.abs(F) * L**3 / EI)


def test_eq14_to_17_backbone_compression_is_a_series_spring():
    # Solve eqs. 14, 15 and tau = k Delta directly as a linear system for
    # (tau, Delta_B, theta_L) with -EI theta_L = r tau L - F z^2/2 (eq. 3 at
    # s = L), and compare with eq. 16 through equivalent_stiffness.
    rng = np.random.default_rng(6)
    for _ in range(50):
        L, EI, r = rng.uniform(0.05, 0.5), 10 ** rng.uniform(-3, 0), rng.uniform(1e-3, 0.03)
        k, kB = 10 ** rng.uniform(0, 5), 10 ** rng.uniform(0, 5)
        F, z = rng.uniform(-5, 5), rng.uniform(0, L)
        # unknowns x = (tau, Delta_B, theta_L)
        A = np.array(
            [
                [1.0, -k, -k * r],  # tau = k (Delta_B + r theta_L)
                [1.0, kB, 0.0],  # c_B = -k_B Delta_B = tau
                [r * L, 0.0, EI],
            ]
        )  # EI theta_L + r tau L = F z^2/2
        tau, dB, thL = np.linalg.solve(A, [0.0, 0.0, F * z**2 / 2])
        keq = an.equivalent_stiffness(k, kB)
        # a 3x3 solve (condition <= ~1e5 here) against closed forms
        assert np.isclose(keq, ref.equivalent_stiffness(k, kB), rtol=4 * EPS)
        assert np.isclose(an.angle(L, F, z, L, EI, 0.0, r, keq), thL, rtol=1e-10, atol=0)
        assert np.isclose(ref.eq16(F, z, L, EI, r, keq), thL, rtol=1e-10, atol=0)
        assert np.isclose(an.tension(F, z, L, EI, 0.0, r, keq), tau, rtol=1e-10, atol=0)


@pytest.mark.parametrize("n", range(2, 9))
def test_eq18_to_20_pretension_cancels_and_pattern_factor(n):
    # n tendons at phi_i = 2 pi i / n, equal k and pretension tau_p; eq. 19:
    # tau_i = k r cos(phi_i) theta_L + tau_p; moment balance at the tip (eq. 18
    # integrated): EI theta_L = F z^2/2 - r L T, T = sum cos(phi_i) tau_i.
    # Solve for theta_L summing the tendons one by one, for several tau_p.
    L, EI, r, k, F, z = 0.2, 0.05, 0.01, 3e3, 1.5, 0.15
    phi = 2 * np.pi * np.arange(1, n + 1) / n
    c = np.cos(phi)
    thetas = []
    for tau_p in (0.0, 1.0, 50.0):
        # EI th = F z^2/2 - r L sum c_i (k r c_i th + tau_p)
        th = (F * z**2 / 2 - r * L * tau_p * np.sum(c)) / (EI + r**2 * L * k * np.sum(c * c))
        thetas.append(th)
        tau_i = k * r * c * th + tau_p
        T = np.sum(c * tau_i)
        P = an.pattern_factor(n)
        # the recipe: k*P in the ufuncs gives theta_L and the resultant T ...
        assert np.isclose(an.angle(L, F, z, L, EI, 0.0, r, k * P), th, rtol=1e-12)
        assert np.isclose(an.tension(F, z, L, EI, 0.0, r, k * P), T, rtol=1e-12)
        # ... and tendon i carries tau_p + cos(phi_i) T / P
        np.testing.assert_allclose(tau_i, tau_p + c * T / P, rtol=1e-12)
    # pretension cancels: sum cos(phi_i) is zero up to ~n eps, times tau_p = 50
    np.testing.assert_allclose(thetas, thetas[0], rtol=1e-12)
    # eq. 20 at the loaded point
    d = an.deflection(z, F, z, L, EI, 0.0, r, k * an.pattern_factor(n))
    assert np.isclose(d, ref.eq20(F, z, L, EI, r, k, n), rtol=SPECIAL)
    # "the upper limit of eq. 12 still holds even with infinitely many tendons"
    d_many = an.deflection(L, F, L, L, EI, 0.0, r, k * an.pattern_factor(10**9))
    assert d_many > ref.eq12(F, L, EI)


# ----------------------------------------------------------------------------- Section III special cases


def sloped_grid(seed=7, n=500):
    L, EI, r, k, F, z, s = param_grid(seed, n)
    rng = np.random.default_rng(seed + 100)
    a = -rng.uniform(0, 1, n) * r / L
    return L, EI, a, r, k, F, z, s


def test_eq23_24_tension_is_k_times_the_stretch():
    # Delta = int_0^L r(s) theta'(s) ds = r(L) theta(L) - a int_0^L theta ds
    # (by parts), with theta from the angle ufunc and the integral by adaptive
    # quadrature: the tension ufunc must equal k * Delta (and Delta = 0 at
    # k = inf).  Also compares with eq. 24 as printed.
    L, EI, a, b, k, F, z, s = sloped_grid(n=40)
    for i in range(40):
        for kk in (k[i], INF):
            p = (F[i], z[i], L[i], EI[i], a[i], b[i], kk)
            tau = an.tension(*p)
            # theta is piecewise quadratic: Gauss-Kronrod on each piece is exact
            th_int, _ = integrate.quad(
                lambda u: an.angle(u, *p),
                0,
                L[i],
                points=[z[i]],
                epsabs=1e-14 * abs(F[i]) * L[i] ** 3 / EI[i],
                epsrel=1e-13,
            )
            Delta = (a[i] * L[i] + b[i]) * an.angle(L[i], *p) - a[i] * th_int
            scale = abs(F[i]) * L[i] ** 2 * b[i] / EI[i]  # size of each term of Delta
            # quad to ~1e-13 relative, the rest round-off
            assert (
                abs(Delta - ref.stretch(F[i], z[i], L[i], EI[i], a[i], b[i], tau)) <= 1e-12 * scale
            )
            if np.isinf(kk):
                assert abs(Delta) <= 1e-12 * scale
            else:
                assert abs(tau - kk * Delta) <= 1e-12 * kk * scale


def test_eq27_eq28_loaded_point_and_tip():
    L, EI, a, b, k, F, z, s = sloped_grid()
    tau = an.tension(F, z, L, EI, a, b, k)
    assert close(
        an.deflection(z, F, z, L, EI, a, b, k), ref.eq27(F, z, EI, a, b, tau), F * z**3 / EI
    )  # eq. 27
    tauL = an.tension(F, L, L, EI, a, b, k)
    assert close(
        an.deflection(L, F, L, L, EI, a, b, k), ref.eq28(F, L, EI, a, b, tauL), F * L**3 / EI
    )  # eq. 28


def test_eq29_eq30_inextensible_sloped():
    L, EI, a, b, k, F, z, s = sloped_grid()
    assert close(
        an.deflection(z, F, z, L, EI, a, b, INF), ref.eq29(F, z, L, EI, a, b), F * z**3 / EI
    )  # eq. 29
    assert close(
        an.deflection(L, F, L, L, EI, a, b, INF), ref.eq30(F, L, EI, a, b), F * L**3 / EI
    )  # eq. 30


def test_eq31_to_34_converging():
    L, EI, a, b, k, F, z, s = sloped_grid()
    a = -b / L
    assert close(
        an.deflection(z, F, z, L, EI, a, b, k), ref.eq31(F, z, L, EI, b, k), F * z**3 / EI
    )  # eq. 31
    assert close(
        an.deflection(L, F, L, L, EI, a, b, k), ref.eq32(F, L, EI, b, k), F * L**3 / EI
    )  # eq. 32
    assert close(
        an.deflection(z, F, z, L, EI, a, b, INF), ref.eq33(F, z, L, EI), F * z**3 / EI
    )  # eq. 33
    tip = an.deflection(L, F, L, L, EI, a, b, INF)
    assert close(tip, ref.eq34(F, L, EI), F * L**3 / EI)  # eq. 34
    # eq. 34's statement: zero tip deflection, to round-off of F L^3 / (3 EI)
    assert np.all(np.abs(tip) <= 16 * EPS * np.abs(F) * L**3 / EI)


@pytest.mark.parametrize("n", [2, 3, 4, 6])
def test_eq35_36_multiple_converging(n):
    L, EI, a, b, k, F, z, s = sloped_grid()
    P = an.pattern_factor(n)
    assert close(
        an.deflection(z, F, z, L, EI, -b / L, b, k * P),
        ref.eq36(F, z, L, EI, b, k, n),
        F * z**3 / EI,
    )  # eq. 36


def test_eq37_to_40_actuation():
    L, EI, a, b, k, F, z, s = sloped_grid()
    th = np.linspace(-1, 1, L.size)
    conv = -b / L
    np.testing.assert_allclose(
        an.actuation_tension_for_angle(th, L, EI, 0.0, b), ref.eq37(th, L, EI, b), rtol=8 * EPS
    )  # eq. 37
    np.testing.assert_allclose(
        an.actuation_tension_for_angle(th, L, EI, conv, b), ref.eq38(th, L, EI, b), rtol=8 * EPS
    )  # eq. 38
    np.testing.assert_allclose(
        an.actuation_tension_for_deflection(th, L, EI, 0.0, b), ref.eq39(th, L, EI, b), rtol=8 * EPS
    )  # eq. 39
    np.testing.assert_allclose(
        an.actuation_tension_for_deflection(th, L, EI, conv, b),
        ref.eq40(th, L, EI, b),
        rtol=8 * EPS,
    )  # eq. 40


def test_actuation_statements_twice_and_one_and_a_half():
    L, EI, a, b, k, F, z, s = sloped_grid()
    th = 0.3
    r_ang = an.actuation_tension_for_angle(th, L, EI, -b / L, b) / an.actuation_tension_for_angle(
        th, L, EI, 0.0, b
    )
    r_def = an.actuation_tension_for_deflection(
        th, L, EI, -b / L, b
    ) / an.actuation_tension_for_deflection(th, L, EI, 0.0, b)
    np.testing.assert_allclose(r_ang, 2.0, rtol=8 * EPS)  # a ratio of two ~exact values
    np.testing.assert_allclose(r_def, 1.5, rtol=8 * EPS)


def test_actuation_tension_reproduces_the_target_in_the_forward_model():
    # Superposition: a tendon tension tau and no load bends the beam by
    # -tau * (d/dtau of eq. 22/26).  The forward angle/deflection with a given
    # tau is the kernel of the ufuncs; build it from the reference with F = 0
    # and check that the actuation tension reaches -theta_L / -delta_L (the
    # paper reverses its sign for eqs. 37-40: toward the tendon side).
    L, EI, a, b, k, F, z, s = sloped_grid()
    tau = an.actuation_tension_for_angle(0.2, L, EI, a, b)
    np.testing.assert_allclose(ref.angle_given_tau(L, 0.0, L, EI, a, b, tau), -0.2, rtol=16 * EPS)
    tau = an.actuation_tension_for_deflection(0.01, L, EI, a, b)
    np.testing.assert_allclose(
        ref.deflection_given_tau(L, 0.0, L, EI, a, b, tau), -0.01, rtol=16 * EPS
    )


def test_fig7_converging_beats_parallel_exactly_above_alpha_5():
    # sigma_tip(alpha) for parallel (a = 0) and converging (a = -b/L) at the
    # same b = r: find where they cross with a root finder on the ufunc output.
    L, EI, r, F = 0.2, 0.05, 0.01, 1.0

    def sigma(alpha, a):
        k = alpha * EI / (r**2 * L)
        return 12 * EI / L**3 * an.deflection(L, F, L, L, EI, a, r, k) / F

    def diff(alpha):
        return sigma(alpha, -r / L) - sigma(alpha, 0.0)

    cross = optimize.brentq(diff, 0.5, 50, xtol=1e-14, rtol=1e-15)
    # the crossing of 4 - 3 alpha/(1+alpha) and 4 - 4 alpha/(3+alpha) is at 5;
    # diff has slope ~0.03 there, so round-off of ~1e-15 in sigma moves the
    # root by ~1e-13.
    assert abs(cross - 5.0) < 1e-11
    assert diff(4.9) > 0 and diff(5.1) < 0  # parallel stiffer below, converging above
    alphas = np.geomspace(1e-3, 1e6, 200)
    assert np.all((diff(alphas) < 0) == (alphas > 5))
    # asymptotes of Fig. 7: 1 for parallel, 0 for converging
    assert abs(sigma(INF, 0.0) - 1.0) < 1e-14 and abs(sigma(INF, -r / L)) < 1e-14


def test_fig6_converging_is_stiffer_at_every_load_position():
    # Figs. 3 and 6: inextensible tendons; deflection at the loaded point
    # decreases as the slope goes from 0 (parallel) to -b/L (converging), at
    # every load position; the no-tendon member is the most compliant.
    L, EI, b, F = 0.2, 0.05, 0.01, 1.0
    zeta = np.linspace(0.01, 1, 100)[:, None]
    slopes = -np.linspace(0, 1, 11)[None, :] * b / L
    d = an.deflection(zeta * L, F, zeta * L, L, EI, slopes, b, INF)
    assert np.all(np.diff(d, axis=1) <= 16 * EPS * F * L**3 / EI)
    assert np.all(d <= an.deflection(zeta * L, F, zeta * L, L, EI, 0.0, b, 0.0))


# ----------------------------------------------------------------------------- limits and domain


def test_k_inf_never_warns_and_k_zero_is_the_plain_cantilever():
    L, EI, a, b, k, F, z, s = sloped_grid()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with np.errstate(all="raise"):
            for f in (
                an.tension(F, z, L, EI, a, b, INF),
                an.angle(s, F, z, L, EI, a, b, INF),
                an.deflection(s, F, z, L, EI, a, b, INF),
                an.deflection(s, F, z, L, EI, a, b, 0.0),
                an.deflection(s, F, z, L, EI, 0.0, 0.0, INF),  # centre line
                an.deflection(s, F, z, L, EI, 0.0, 0.0, 0.0),
                an.equivalent_stiffness([0.0, 1.0, INF, INF], [INF, INF, INF, 0.0]),
                an.planar_shape(s, F, z, L, EI, a, b, INF),
            ):
                assert not np.any(np.isnan(f))
    plain = F * np.minimum(s, z) ** 2 * (3 * np.maximum(s, z) - np.minimum(s, z)) / (6 * EI)
    assert close(an.deflection(s, F, z, L, EI, a, b, 0.0), plain, F * L**3 / EI)
    assert np.all(an.tension(F, z, L, EI, a, b, 0.0) == 0.0)


def test_centre_line_tendon_is_the_plain_cantilever_for_every_k():
    # a = b = 0: documented choice tau = 0 for every k including inf; and the
    # non-uniform limit: for b -> 0 at k = inf the deflection tends to eq. 11.
    L, EI, F, z = 0.2, 0.05, 1.0, 0.15
    for k in (0.0, 1.0, 1e6, INF):
        assert an.tension(F, z, L, EI, 0.0, 0.0, k) == 0.0
        np.testing.assert_allclose(
            an.deflection(z, F, z, L, EI, 0.0, 0.0, k), F * z**3 / (3 * EI), rtol=4 * EPS
        )
    np.testing.assert_allclose(
        an.deflection(z, F, z, L, EI, 0.0, 1e-12, INF), ref.eq11(F, z, L, EI), rtol=1e-12
    )


BAD = [  # (argument index in deflection(s, F, z, L, EI, a, b, k), value)
    (3, 0.0),
    (3, -1.0),
    (3, np.inf),
    (4, 0.0),
    (4, -1.0),
    (4, np.inf),
    (2, -0.01),
    (2, 0.3),
    (0, -0.01),
    (0, 0.3),
    (7, -1.0),
    (0, np.nan),
    (1, np.nan),
    (2, np.nan),
    (3, np.nan),
    (4, np.nan),
    (5, np.nan),
    (6, np.nan),
    (7, np.nan),
]


@pytest.mark.parametrize("idx,value", BAD)
def test_out_of_domain_gives_nan_and_invalid_flag(idx, value):
    good = [0.1, 1.0, 0.15, 0.2, 0.05, -0.02, 0.01, 100.0]
    args = [np.array(good) for _ in range(3)]
    args = list(good)
    args[idx] = np.array([good[idx], value, good[idx]])  # element by element
    for f in (an.deflection, an.angle):
        with np.errstate(invalid="ignore"):
            out = f(*args)
        assert np.isnan(out[1]) and np.all(np.isfinite(out[[0, 2]]))
        with np.errstate(invalid="raise"), pytest.raises(FloatingPointError):
            f(*args)
        with pytest.warns(RuntimeWarning, match="invalid value"):
            f(*args)
    if idx >= 1:  # tension has no s
        with np.errstate(invalid="raise"), pytest.raises(FloatingPointError):
            an.tension(*args[1:])


@pytest.mark.parametrize(
    "call",
    [
        lambda: an.pattern_factor(np.array([0.0, 2.5, -3.0, np.inf, np.nan])),
        lambda: an.equivalent_stiffness([-1.0, np.nan], [1.0, 1.0]),
        lambda: an.actuation_tension_for_angle(0.1, [0.0, np.nan], 1.0, 0.0, 0.01),
        # exactly zero mean arms (representable values): b + aL/2 = 0, b/2 + aL/6 = 0
        lambda: an.actuation_tension_for_angle(0.1, 1.0, 1.0, -1.0, 0.5),
        lambda: an.actuation_tension_for_deflection(0.1, 1.0, 1.0, -1.5, 0.5),
        lambda: an.actuation_tension_for_deflection(0.1, 0.3, -1.0, 0.0, 0.01),
    ],
)
def test_other_ufuncs_domain(call):
    with np.errstate(invalid="ignore"):
        assert np.all(np.isnan(call()))
    with np.errstate(invalid="raise"), pytest.raises(FloatingPointError):
        call()


# ----------------------------------------------------------------------------- ufunc mechanics


def test_they_are_real_ufuncs_with_documented_arity():
    arity = dict(
        tension=7,
        angle=8,
        deflection=8,
        equivalent_stiffness=2,
        pattern_factor=1,
        actuation_tension_for_angle=5,
        actuation_tension_for_deflection=5,
    )
    for name in UFUNCS:
        f = getattr(an, name)
        assert isinstance(f, np.ufunc) and f.nin == arity[name] and f.nout == 1
        assert f.types == ["d" * f.nin + "->d"]
        assert re.search(r"eq", f.__doc__) and "[" in f.__doc__  # equations and units
        assert name in an.__all__


def test_broadcasting_out_and_where():
    s = np.linspace(0, 0.2, 7)[:, None]  # (7, 1)
    F = np.array([-1.0, 0.5, 2.0])  # (3,)
    z = 0.15
    args = (s, F, z, 0.2, 0.05, -0.02, 0.01, 300.0)
    d = an.deflection(*args)
    assert d.shape == (7, 3)
    want = ref.deflection(*np.broadcast_arrays(*(np.asarray(x, float) for x in args)))
    np.testing.assert_allclose(d, want, rtol=1e-13, atol=1e-18)  # round-off (see ROUND)
    out = np.full((7, 3), -7.0)
    r = an.deflection(*args, out=out)
    assert r is out and np.array_equal(out, d)
    mask = np.zeros((7, 3), bool)
    mask[::2, 1] = True
    out = np.full((7, 3), -7.0)
    an.deflection(*args, out=out, where=mask)
    assert np.array_equal(out[mask], d[mask]) and np.all(out[~mask] == -7.0)
    # where= skips masked-out elements entirely: an out-of-domain s there is
    # neither evaluated nor flagged
    bad_s = np.where(mask, s, 99.0)
    out = np.zeros((7, 3))
    with np.errstate(invalid="raise"):
        an.deflection(bad_s, *args[1:], out=out, where=mask)
    # the s-only fast path (all parameters scalar) and the general path agree
    s1 = np.linspace(0, 0.2, 101)
    fast = an.deflection(s1, 1.0, z, 0.2, 0.05, -0.02, 0.01, 300.0)
    slow = an.deflection(s1, np.full(101, 1.0), z, 0.2, 0.05, -0.02, 0.01, 300.0)
    assert np.array_equal(fast, slow)
    assert np.array_equal(
        an.angle(s1, 1.0, z, 0.2, 0.05, -0.02, 0.01, 300.0),
        an.angle(s1, np.full(101, 1.0), z, 0.2, 0.05, -0.02, 0.01, 300.0),
    )
    # non-contiguous strided input
    s2 = np.linspace(0, 0.2, 202)[::2]
    assert np.array_equal(
        an.deflection(s2, 1.0, z, 0.2, 0.05, 0, 0.01, 1.0),
        an.deflection(s2.copy(), 1.0, z, 0.2, 0.05, 0, 0.01, 1.0),
    )


def test_non_float_inputs_are_cast():
    # ints (L = 1 m, EI = 2 N m^2, ...), bools, float32: computed in float64
    d_int = an.deflection(1, 3, 1, 1, 2, 0, 1, 5)
    d_flt = an.deflection(1.0, 3.0, 1.0, 1.0, 2.0, 0.0, 1.0, 5.0)
    assert d_int == d_flt and isinstance(d_int, np.float64)
    f32 = np.linspace(0, 0.2, 5, dtype=np.float32)  # float32(0.2) > 0.2: use L = 0.25
    got = an.deflection(f32, 1.0, 0.1, 0.25, 0.05, 0.0, 0.01, 10.0)
    assert got.dtype == np.float64
    np.testing.assert_array_equal(
        got, an.deflection(f32.astype(float), 1.0, 0.1, 0.25, 0.05, 0.0, 0.01, 10.0)
    )
    assert an.pattern_factor(np.int8(4)) == 2.0
    assert an.pattern_factor(np.array([1, 2, 3], dtype=np.uint16)).tolist() == [1.0, 2.0, 1.5]
    out32 = np.zeros(5, np.float32)  # same_kind output casting
    an.deflection(f32, 1.0, 0.1, 0.25, 0.05, 0.0, 0.01, 10.0, out=out32)
    np.testing.assert_allclose(out32, got, rtol=1e-6)  # float32 resolution


@pytest.mark.parametrize("bad", ["0.1", b"x", None, {"a": 1}, np.array(["a"]), np.array([1 + 2j])])
def test_non_numeric_input_is_a_type_error(bad):
    with pytest.raises(TypeError, match="deflection"):
        an.deflection(bad, 1.0, 0.1, 0.2, 0.05, 0.0, 0.01, 10.0)


# ----------------------------------------------------------------------------- planar shape


@pytest.mark.parametrize(
    "case",
    [
        (1.0, 0.15, 0.2, 0.05, 0.0, 0.01, 300.0),  # parallel, alpha = 0.12, |theta| <= 0.2
        (3.0, 0.15, 0.2, 0.02, -0.05, 0.01, np.inf),  # converging, inextensible
        (-2.0, 0.07, 0.2, 0.01, -0.02, 0.01, 1e4),  # semi-converging, |theta| <= 0.3
        (-20.0, 0.07, 0.2, 0.01, -0.02, 0.01, 1e4),  # far outside small angles: |theta| <= 2.9
    ],
)
def test_planar_shape_against_adaptive_quadrature(case):
    F, z, L, EI, a, b, k = case
    s = np.linspace(0, L, 9)
    xy = an.planar_shape(s, *case)
    assert xy.shape == (9, 2)

    def th(u):
        return float(an.angle(u, *case))

    def quad(f, si):
        # adaptive Gauss-Kronrod on each smooth piece, asked for ~round-off;
        # QUADPACK's round-off detector fires at such tolerances (harmless:
        # the integrands are smooth and the 21-point rule already converged).
        m, v = min(si, z), 0.0
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", integrate.IntegrationWarning)
            for lo, hi in ((0.0, m), (m, si)):
                if hi > lo:
                    v += integrate.quad(f, lo, hi, epsabs=1e-18, epsrel=1e-14, limit=200)[0]
        return v

    ref_xy = np.array(
        [[quad(lambda u: np.cos(th(u)), si), quad(lambda u: np.sin(th(u)), si)] for si in s]
    )
    # the docstring's accuracy claim: round-off, below 1e-15 L (measured
    # <= 3e-16 L for these cases, up to |theta| ~ 3 rad)
    assert np.all(np.abs(xy - ref_xy) <= 1e-15 * L)
    # ... and the comparison is sensitive: 4 nodes per piece is visibly worse
    assert np.max(np.abs(an.planar_shape(s, *case, nodes=4) - ref_xy)) > 1e-15 * L
    # small angles: lateral ~ deflection to second order in theta
    thmax = np.max(np.abs(an.angle(s, *case)))
    if thmax < 0.5:
        assert np.all(np.abs(xy[:, 1] - an.deflection(s, *case)) <= thmax**2 * L)


def test_planar_shape_broadcasts_and_flags_bad_input():
    xy = an.planar_shape(
        np.linspace(0, 0.2, 4)[:, None], [1.0, 2.0], 0.1, 0.2, 0.05, 0.0, 0.01, 100.0
    )
    assert xy.shape == (4, 2, 2)
    for j, F in enumerate((1.0, 2.0)):
        one = an.planar_shape(np.linspace(0, 0.2, 4), F, 0.1, 0.2, 0.05, 0.0, 0.01, 100.0)
        np.testing.assert_allclose(xy[:, j], one, rtol=4 * EPS, atol=0)  # summation order
    with np.errstate(invalid="raise"), pytest.raises(FloatingPointError):
        an.planar_shape([0.1, 0.3], 1.0, 0.1, 0.2, 0.05, 0.0, 0.01, 100.0)
    args = (0.1, 1.0, 0.1, 0.2, 0.05, 0.0, 0.01, 100.0)
    for bad in (0, -3, 101, 10**12):
        with pytest.raises(ValueError, match="nodes"):
            an.planar_shape(*args, nodes=bad)
    for bad in (2.7, np.inf, np.nan, "abc", None, [3]):
        with pytest.raises(TypeError, match="nodes"):
            an.planar_shape(*args, nodes=bad)
    assert an.planar_shape(*args, nodes=np.int64(8)).shape == (2,)
    for i, name in enumerate(("s", "F", "z", "L", "EI", "a", "b", "k")):
        for bad in (None, "abc", 1j):
            with pytest.raises(TypeError, match=f"\\b{name} must"):
                an.planar_shape(*args[:i], bad, *args[i + 1 :])


def test_gsl_version_is_a_version_string():
    assert re.fullmatch(r"\d+\.\d+(\.\d+)?", tendonrod.gsl_version)
