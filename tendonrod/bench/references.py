"""Exact and collocation references for the benchmarks and the tests.

Nothing here calls the C core: every function is an exact solution or a fine
numerical solution by collocation (SciPy).  Conventions are those of
``docs/model.md``: SI units, base at the origin, base frame = world frame,
undeformed rod along +z, loads in the world frame.  The spatial robot solver with
tendons is :mod:`tendonrod.bench.reference_robot`; the paper's closed forms are the
library's own :mod:`tendonrod.analytic`.

Contents
--------
circle_end_moment        exact: a pure end moment bends any rod into a circle.
elastica_tip_force       exact (elliptic integrals): Kirchhoff cantilever under a
                         tip force perpendicular to the undeformed axis.
elastica_compressive     exact (elliptic integrals): first buckled mode of a
                         Kirchhoff cantilever under an axial compressive tip force.
critical_tip_angle_load  exact: the compressive load at which the free elastica's
                         tip reaches a given angle (paper Fig. 17's slack load).
elastica_limit_force     shooting (DOP853): the extreme lateral tip force on the buckled
                         cantilever's branch (a limit point).
twist_with_tendons       exact: paper Fig. 12 (three tendons, pure twisting moment).
planar_rod_bvp           plain planar rod (Kirchhoff or Cosserat) under a tip force
                         and moment by collocation (scipy.integrate.solve_bvp);
                         stable for large tensile loads where shooting fails.
precurved_helix_end_moment  exact: a precurved rod under an end moment along its
                         curvature stays a helix.
cantilever_dead_loads    a horizontal cantilever under its weight and point weights
                         (disks) by shooting (scipy.integrate.solve_ivp).
helical_tendon_tip       a rod with one helical tendon under tension and a tip force
helical_tendon_state     the same, tension- or displacement-controlled: (tip, tension)
                         by shooting (solve_ivp, fsolve).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "circle_end_moment",
    "elastica_tip_force",
    "elastica_compressive",
    "critical_tip_angle_load",
    "twist_with_tendons",
    "planar_rod_bvp",
    "precurved_helix_end_moment",
    "cantilever_dead_loads",
    "helical_tendon_tip",
    "helical_tendon_state",
]

_E3 = np.array([0.0, 0.0, 1.0])


def _hat(x):
    return np.array([[0.0, -x[2], x[1]], [x[2], 0.0, -x[0]], [-x[1], x[0], 0.0]])


# --------------------------------------------------------------------------- exact
def circle_end_moment(L, EI, moment, s=None):
    """Exact shape of a straight rod (any shear/extension stiffness) under a pure
    end moment ``moment`` (world frame [N m], perpendicular to z).

    The internal force vanishes, so the rod neither shears nor stretches and bends
    into a circle of curvature ``|M|/EI`` about the moment's axis. Returns
    ``(position (N, 3), rotation (N, 3, 3))`` at arc lengths ``s`` (default: the tip
    only, N = 1)."""
    M = np.asarray(moment, dtype=float)
    if abs(M[2]) > 1e-14 * max(1.0, np.linalg.norm(M)):
        raise ValueError(f"circle_end_moment: moment must be perpendicular to z, got {moment!r}")
    s = np.atleast_1d(np.asarray(L if s is None else s, dtype=float))
    Mn = np.linalg.norm(M)
    if Mn == 0.0:
        pos = np.outer(s, _E3)
        rot = np.repeat(np.eye(3)[None], len(s), axis=0)
        return pos, rot
    ax = M / Mn
    kappa = Mn / EI
    side = np.cross(ax, _E3)  # direction the rod bends toward
    th = kappa * s
    pos = (np.sin(th)[:, None] * _E3 + (1.0 - np.cos(th))[:, None] * side) / kappa
    K = _hat(ax)
    rot = (
        np.eye(3)[None]
        + np.sin(th)[:, None, None] * K
        + (1.0 - np.cos(th))[:, None, None] * (K @ K)
    )
    return pos, rot


def elastica_tip_force(L, EI, F):
    """Exact tip of a Kirchhoff cantilever (clamped along +z) under a tip force of
    magnitude ``F`` > 0 [N] along +x (perpendicular to the undeformed axis, fixed
    direction), from elliptic integrals.

    With theta the tangent angle from z toward x, EI theta'' = -F cos(theta),
    theta(0) = 0, theta'(L) = 0. Substituting 1 + sin(theta) = 2 k^2 sin^2(phi):
    L sqrt(F/EI) = K(k) - F(phi0, k) with sin(phi0) = 1/(sqrt(2) k), and
    z_L = 2 k cos(phi0) / lam, x_L = L - 2 (E(k) - E(phi0, k)) / lam, lam = sqrt(F/EI).
    Returns ``(x_L, z_L, theta_L)``."""
    from scipy.optimize import brentq
    from scipy.special import ellipe, ellipeinc, ellipk, ellipkinc

    if not F > 0:
        raise ValueError(f"elastica_tip_force: F must be > 0, got {F!r}")
    lam = math.sqrt(F / EI)
    target = L * lam

    def g(k):
        m = k * k
        phi0 = math.asin(1.0 / (math.sqrt(2.0) * k))
        return ellipk(m) - ellipkinc(phi0, m) - target

    lo = 1.0 / math.sqrt(2.0) * (1.0 + 1e-15)
    hi = 1.0 - 1e-16
    k = brentq(g, lo, hi, xtol=1e-16, rtol=4 * np.finfo(float).eps, maxiter=500)
    m = k * k
    phi0 = math.asin(1.0 / (math.sqrt(2.0) * k))
    zL = 2.0 * k * math.cos(phi0) / lam
    xL = L - 2.0 * (ellipe(m) - ellipeinc(phi0, m)) / lam
    thetaL = math.asin(2.0 * m - 1.0)
    return xL, zL, thetaL


def elastica_compressive(L, EI, P):
    """Exact tip of the first buckled mode of a Kirchhoff cantilever (clamped along
    +z) under an axial compressive tip force of magnitude ``P`` [N] (force -P e_z),
    bent toward +x. EI theta'' = -P sin(theta), theta(0) = 0, theta'(L) = 0:
    L sqrt(P/EI) = K(k), k = sin(theta_L/2); x_L = 2k/lam, z_L = (2E(k) - K(k))/lam.
    Needs P > pi^2 EI / (4 L^2) (Euler's load). Returns ``(x_L, z_L, theta_L)``."""
    from scipy.optimize import brentq
    from scipy.special import ellipe, ellipk

    lam = math.sqrt(P / EI)
    target = L * lam
    if not target > math.pi / 2:
        raise ValueError(
            f"elastica_compressive: P={P!r} is below Euler's load "
            f"{math.pi**2 * EI / (4 * L * L)!r}; the straight rod is the only solution"
        )
    k = brentq(
        lambda k: ellipk(k * k) - target,
        1e-300,
        1.0 - 1e-16,
        xtol=1e-16,
        rtol=4 * np.finfo(float).eps,
        maxiter=500,
    )
    m = k * k
    return 2.0 * k / lam, (2.0 * ellipe(m) - ellipk(m)) / lam, 2.0 * math.asin(k)


def elastica_limit_force(P, EI, L):
    """The extreme lateral tip force H [N] along the branch of the planar Kirchhoff
    cantilever under the tip force (H, -P) (x, z), bent toward +x: EI theta'' = -(H cos
    theta + P sin theta), theta(0) = 0, theta'(L) = 0, shot from theta'(0) = kappa0 with
    DOP853 at rtol 1e-13; H(kappa0) by brentq, its extremum (the limit point where the
    buckled column pushed back by H snaps through) by a bounded scalar minimisation over
    kappa0 L in [1.5, 2.3] (the range for P = 1.5 pi^2 EI / 4 L^2)."""
    from scipy.integrate import solve_ivp
    from scipy.optimize import brentq, minimize_scalar

    def end_moment(k0, H):
        def f(s, y):
            return [y[1], -(H * math.cos(y[0]) + P * math.sin(y[0])) / EI]

        r = solve_ivp(f, (0.0, L), [0.0, k0], rtol=1e-13, atol=1e-14, method="DOP853")
        return r.y[1, -1]

    def H_of(kL):
        return brentq(lambda H: end_moment(kL / L, H), -P, 0.2 * P, xtol=1e-16, rtol=1e-15)

    res = minimize_scalar(H_of, bounds=(1.5, 2.3), method="bounded", options=dict(xatol=1e-9))
    return H_of(res.x)


def critical_tip_angle_load(L, EI, theta_L):
    """The compressive tip load P [N] at which the free (tendon-less) elastica's tip
    angle equals ``theta_L`` (0 < theta_L < pi): L sqrt(P/EI) = K(sin(theta_L/2)).
    For a robot locked at tip angle theta_L by one inextensible tendon and loaded
    axially (paper Fig. 17), this is the load at which the tendon's tension reaches
    zero: beyond it the tendon is slack."""
    from scipy.special import ellipk

    k = math.sin(theta_L / 2.0)
    return EI * (ellipk(k * k) / L) ** 2


def twist_with_tendons(L, GJ, EA, r, n, M):
    """Paper Fig. 12, exactly: a straight Kirchhoff rod with ``n`` equally spaced
    parallel tendons at offset ``r`` (axial rigidity ``EA`` [N] each, displacement 0,
    no pretension) under a pure twisting tip moment ``M`` [N m].

    By symmetry the rod stays straight and twists uniformly by psi; each tendon
    becomes a helix of length L sqrt(1 + s^2), s = r psi / L, so its tension is
    T = EA (sqrt(1 + s^2) - 1) and it adds the moment r T s / sqrt(1 + s^2) about the
    axis: M = GJ psi / L + n r T s / sqrt(1 + s^2). Returns ``(psi [rad], T [N])``.
    The tendon term is cubic in psi, so the slope at zero is GJ/L whatever EA (the
    paper's observation), and psi -> 0 as EA -> inf (no equilibrium in the limit)."""
    from scipy.optimize import brentq

    def tension(psi):
        s = r * psi / L
        return (
            EA * (math.sqrt(1.0 + s * s) - 1.0)
            if s * s > 1e-8
            else EA * (0.5 * s * s - 0.125 * s**4)
        )

    def g(psi):
        s = r * psi / L
        return GJ * psi / L + n * r * tension(psi) * s / math.sqrt(1.0 + s * s) - M

    hi = M * L / GJ  # the tendons only reduce the twist
    psi = (
        brentq(g, 0.0, hi, xtol=1e-300, rtol=4 * np.finfo(float).eps, maxiter=500) if M > 0 else 0.0
    )
    return psi, tension(psi)


# --------------------------------------------------------------------------- collocation
def planar_rod_bvp(L, EI, F, M=0.0, *, EA=np.inf, GA=np.inf, tol=1e-10, nodes=400, s_out=None):
    """Plain planar rod (no tendons) clamped along +z under a tip force
    ``F = (Fx, Fz)`` [N] and tip moment ``M`` [N m] about +y, by collocation
    (scipy.integrate.solve_bvp, 4th-order Lobatto IIIA): stable where single
    shooting is not (tensile loads with L sqrt(T/EI) >> 1).

    States x, z, theta (tangent angle from z toward x), m (moment about y). The
    internal force is the constant F; body components n1 = Fx cos - Fz sin,
    n3 = Fx sin + Fz cos; v = (n1/GA, 0, 1 + n3/EA) (Kirchhoff: EA = GA = inf).
    Returns ``(x_L, z_L, theta_L, sol)``."""
    from scipy.integrate import solve_bvp

    Fx, Fz = float(F[0]), float(F[1])

    def f(s, y):
        x, zz, th, m = y
        c, sn = np.cos(th), np.sin(th)
        n1 = Fx * c - Fz * sn
        n3 = Fx * sn + Fz * c
        v1 = n1 / GA
        v3 = 1.0 + n3 / EA
        xp = c * v1 + sn * v3
        zp = -sn * v1 + c * v3
        # m' = -(p' x F)_y = -(zp Fx - xp Fz)
        return np.vstack([xp, zp, m / EI, -(zp * Fx - xp * Fz)])

    def bc(ya, yb):
        return np.array([ya[0], ya[1], ya[2], yb[3] - M])

    s = np.linspace(0.0, L, nodes)
    y0 = np.zeros((4, nodes))
    y0[1] = s
    sol = solve_bvp(f, bc, s, y0, tol=tol, max_nodes=200000)
    # continuation in the load if the cold collocation did not converge
    if sol.status != 0:
        ylast = y0
        for lam in np.linspace(0.1, 1.0, 10):
            Fx, Fz = lam * float(F[0]), lam * float(F[1])
            Ms = lam * M

            def bc2(ya, yb, Ms=Ms):
                return np.array([ya[0], ya[1], ya[2], yb[3] - Ms])

            sol = solve_bvp(f, bc2, s, ylast, tol=tol, max_nodes=200000)
            ylast = sol.sol(s)
    if sol.status != 0:
        raise RuntimeError(f"planar_rod_bvp did not converge: {sol.message}")
    return float(sol.y[0, -1]), float(sol.y[1, -1]), float(sol.y[2, -1]), sol


# --------------------------------------------------------------------------- as built
def precurved_helix_end_moment(L, EI, GJ, precurvature, c):
    """Exact: a rod with constant precurvature ``u*`` [1/m] (body frame) under the world
    tip moment ``M = c u`` [N m] along its deformed curvature keeps a constant curvature
    ``u_i = u*_i / (1 - c / K_i)``, ``K = (EI, EI, GJ)`` (no force anywhere, so a Cosserat
    rod neither shears nor stretches): the helix ``p' = R e3, R' = R u^``.  Returns
    ``(u (3,), tip position (3,), tip rotation (3, 3))``; ``c < min(K)``."""
    us = np.asarray(precurvature, dtype=float)
    K = np.array([EI, EI, GJ], dtype=float)
    u = us / (1.0 - c / K)
    w = float(np.linalg.norm(u))
    if w == 0.0:
        return u, L * _E3, np.eye(3)
    k = u / w
    Kx = _hat(k)
    R = np.eye(3) + math.sin(w * L) * Kx + (1.0 - math.cos(w * L)) * (Kx @ Kx)
    p = (
        _E3 * math.sin(w * L) / w
        + np.cross(k, _E3) * (1.0 - math.cos(w * L)) / w
        + k * k[2] * (L - math.sin(w * L) / w)
    )
    return u, p, R


def cantilever_dead_loads(L, EI, w, s_point=(), P_point=()):
    """Planar inextensible cantilever clamped horizontal under a uniform downward load
    ``w`` [N/m] and downward point forces ``P_point`` [N] at arc lengths ``s_point`` [m]
    (a robot's own weight and its disks' weights), by shooting on the base moment with
    ``solve_ivp`` (DOP853, rtol 1e-12) piece by piece between the point loads, and
    ``brentq``.  The internal force is statically determinate, ``n_v(s) = w (L - s) +
    sum_{s_k >= s} P_k`` (downward), so with theta the tangent angle below the
    horizontal: ``h' = cos(theta)``, ``v' = sin(theta)``, ``theta' = m / EI``,
    ``m' = -cos(theta) n_v(s)``, ``h = v = theta = 0`` at the clamp, ``m(L) = 0``.
    Returns ``(h_L, v_L)`` [m]: the tip's distance along the clamp's axis and its sag."""
    from scipy.integrate import solve_ivp
    from scipy.optimize import brentq

    sk = np.asarray(s_point, dtype=float)
    Pk = np.asarray(P_point, dtype=float)
    cuts = sorted({0.0, L, *[float(x) for x in sk if 0.0 < x < L]})

    def shoot(m0):
        y = np.array([0.0, 0.0, 0.0, m0])
        for a, b in zip(cuts[:-1], cuts[1:]):
            Pin = float(Pk[sk > a].sum()) if sk.size else 0.0  # loads distal to the piece

            def f(s, y, Pin=Pin):
                h, v, th, m = y
                return [math.cos(th), math.sin(th), m / EI, -math.cos(th) * (w * (L - s) + Pin)]

            y = solve_ivp(f, (a, b), y, method="DOP853", rtol=1e-12, atol=1e-15 * L).y[:, -1]
        return y

    m_lin = w * L * L / 2.0 + float((Pk * sk).sum())
    if m_lin == 0.0:
        return L, 0.0
    # m(L) >= 0 at m0 = m_lin (cos <= 1); scan down for the first sign change (at large
    # sag, m0 = 0 can overshoot the hanging branch)
    hi, lo = m_lin, None
    for x in np.linspace(0.95, 0.0, 20):
        if shoot(x * m_lin)[3] < 0.0:
            lo = x * m_lin
            break
        hi = x * m_lin
    if lo is None:
        raise RuntimeError("cantilever_dead_loads: no base moment brackets m(L) = 0")
    m0 = brentq(lambda m: shoot(m)[3], lo, hi, xtol=1e-15 * m_lin, rtol=1e-15)
    y = shoot(m0)
    return float(y[0]), float(y[1])


def helical_tendon_tip(L, EI, GJ, b, phi, twist, tip_force, tension):
    """Tip position [m] of a Kirchhoff rod (EI, GJ [N m^2], length L) with one helical
    tendon (offset ``b`` [m], base angle ``phi`` [rad], ``dphi/ds = twist`` [rad/m])
    anchored at the tip and pulled with ``tension`` [N], and a dead world tip force
    ``tip_force`` [N] (:func:`helical_tendon_state`)."""
    return helical_tendon_state(L, EI, GJ, b, phi, twist, tip_force, tension=tension)[0]


def helical_tendon_state(L, EI, GJ, b, phi, twist, tip_force, *, tension=None, q=None):
    """(tip position [m], tension [N]) of a Kirchhoff rod (EI, GJ [N m^2], length L) with
    one helical tendon (offset ``b`` [m], base angle ``phi`` [rad], ``dphi/ds = twist``
    [rad/m]) anchored at the tip, tension-controlled (``tension`` [N]) or
    displacement-controlled and inextensible (``q`` [m] retracted from the straight
    robot's channel length), under a dead world tip force ``tip_force`` [N]: shooting on
    n_b(0), u(0) (and the tension) with ``solve_ivp`` (DOP853, rtol 1e-12) and ``fsolve``,
    written from ``docs/model.md`` with the curvature u as a state (not the core's moment),
    r, r', r'' of the helix by hand, and the channel length integrated as |w|."""
    from scipy.integrate import solve_ivp
    from scipy.optimize import fsolve

    if (tension is None) == (q is None):
        raise ValueError("helical_tendon_state: give exactly one of tension, q")
    K = np.diag([EI, EI, GJ])
    F = np.asarray(tip_force, dtype=float)

    def helix(s):
        a = phi + twist * s
        c, sn = math.cos(a), math.sin(a)
        return (
            b * np.array([c, sn, 0.0]),
            b * twist * np.array([-sn, c, 0.0]),
            -b * twist**2 * np.array([c, sn, 0.0]),
        )

    def rhs(s, y, tau):
        R = y[3:12].reshape(3, 3)
        nb, u = y[12:15], y[15:18]
        r, rp, rpp = helix(s)
        wv = np.cross(u, r) + rp + _E3
        nw = np.linalg.norm(wv)
        A = -tau * _hat(wv) @ _hat(wv) / nw**3
        G = -A @ _hat(r)
        H = -_hat(r) @ A @ _hat(r)
        a = A @ (np.cross(u, wv) + np.cross(u, rp) + rpp)
        up = np.linalg.solve(K + H, -np.cross(u, K @ u) - np.cross(_E3, nb) - np.cross(r, a))
        nbp = -np.cross(u, nb) - a - G @ up
        return np.concatenate([R @ _E3, (R @ _hat(u)).ravel(), nbp, up, [nw]])

    def shoot(x):
        tau = float(tension) if tension is not None else x[6]
        y0 = np.concatenate([np.zeros(3), np.eye(3).ravel(), x[:3], x[3:6], [0.0]])
        y = solve_ivp(rhs, (0.0, L), y0, args=(tau,), method="DOP853", rtol=1e-12, atol=1e-14).y[
            :, -1
        ]
        R = y[3:12].reshape(3, 3)
        nb, u = y[12:15], y[15:18]
        r, rp, _ = helix(L)
        wv = np.cross(u, r) + rp + _E3
        t = wv / np.linalg.norm(wv)
        res = np.concatenate(
            [(nb + tau * t - R.T @ F) / (EI / L**2), (K @ u + tau * np.cross(r, t)) / (EI / L)]
        )
        if q is not None:
            ref = L * math.sqrt(1.0 + (b * twist) ** 2)  # the straight robot's channel
            res = np.append(res, (y[18] + q - ref) / b)
        return res, y[:3], tau

    x0 = np.zeros(6) if q is None else np.r_[np.zeros(6), 1.0]
    x = fsolve(lambda x: shoot(x)[0], x0, xtol=1e-13)
    res, p, tau = shoot(x)
    if not np.abs(res).max() < 1e-10:
        raise RuntimeError(f"helical_tendon_state did not converge: residual {np.abs(res).max()!r}")
    return p, tau
