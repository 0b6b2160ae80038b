"""Independent reference solutions for the work-precision benchmark and the tests.

Nothing here calls the C core: every function is an exact solution, a closed
form, or a fine numerical solution of the rod/tendon equations written in a
*different* form from the core's (global balance of the distal part instead of
the local A, B, G, H matrices of MODEL.md), integrated with SciPy's DOP853 at
tight tolerance. Agreement between the core and these references therefore
tests the core's formulation, not only its arithmetic.

Conventions are those of MODEL.md: SI units, base at the origin, base frame =
world frame, undeformed rod along +z, loads in the world frame, tendon i at
body-frame offset ``r_i(s) = (a_i s + b_i)(cos phi_i, sin phi_i, 0)``, positive
displacement q retracts the tendon, tension tau >= 0.

Contents
--------
circle_end_moment        exact: a pure end moment bends any rod into a circle.
elastica_tip_force       exact (elliptic integrals): Kirchhoff cantilever under a
                         tip force perpendicular to the undeformed axis.
elastica_compressive     exact (elliptic integrals): first buckled mode of a
                         Kirchhoff cantilever under an axial compressive tip force.
twist_with_tendons       exact: paper Fig. 12 (three tendons, pure twisting moment).
small_load_deflection    the paper's eqs. 22-26 in plain NumPy (independent of the
                         ufuncs in tendonrod.analytic).
planar_rod_bvp           plain planar rod (Kirchhoff or Cosserat) under a tip force
                         and moment by collocation (scipy.integrate.solve_bvp);
                         stable for large tensile loads where shooting fails.
TendonRobotReference     spatial Kirchhoff/Cosserat rod with tip-anchored tendons
                         (displacement- or tension-controlled, stretch, pretension,
                         slack by an active set) under tip loads, by single shooting
                         on the distal-balance form with DOP853.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

__all__ = [
    "circle_end_moment",
    "elastica_tip_force",
    "elastica_compressive",
    "small_load_deflection",
    "planar_rod_bvp",
    "RefTendon",
    "RefResult",
    "TendonRobotReference",
    "from_scene",
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


def small_load_deflection(s, F, z, L, EI, a, b, k):
    """The paper's eqs. 25-26 in plain NumPy: transverse deflection [m] at ``s`` of
    a straight Bernoulli-Euler beam with one tendon on r(s) = a s + b (spring
    constant ``k`` [N/m], ``np.inf`` = inextensible) under a transverse force ``F``
    [N] at ``z``; positive in the direction of F (F pushes away from the tendon).
    Independent of the C ufuncs in :mod:`tendonrod.analytic`."""
    s, F, z, L, EI, a, b, k = np.broadcast_arrays(
        *[np.asarray(x, dtype=float) for x in (s, F, z, L, EI, a, b, k)]
    )
    with np.errstate(divide="ignore", invalid="ignore"):
        num = F * (a * z**3 + 3 * b * z**2)
        den_inf = L * (2 * a * a * L * L + 6 * a * b * L + 6 * b * b)
        tau = np.where(np.isinf(k), num / den_inf, k * num / (6 * EI + k * den_inf))
    below = (F + a * tau) * s**3 / 6 + (b * tau - F * z) * s**2 / 2
    above = a * tau * s**3 / 6 + b * tau * s**2 / 2 - F * z * z * s / 2 + F * z**3 / 6
    return -np.where(s < z, below, above) / EI


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


# --------------------------------------------------------------------------- shooting
@dataclass
class RefTendon:
    """One tendon for :class:`TendonRobotReference` (anchored at the tip).

    b [m] offset, phi [rad] angle, a [-] slope, EA [N] (inf: inextensible),
    exactly one of q [m] (displacement, > 0 retracts) or tau [N] (tension),
    pretension [N] (tension at q = 0 in the straight unloaded robot)."""

    b: float
    phi: float = 0.0
    a: float = 0.0
    EA: float = math.inf
    q: float | None = None
    tau: float | None = None
    pretension: float = 0.0

    def r(self, s):
        d = np.array([math.cos(self.phi), math.sin(self.phi), 0.0])
        return (self.a * s + self.b) * d

    def dr(self):
        return self.a * np.array([math.cos(self.phi), math.sin(self.phi), 0.0])


@dataclass
class RefResult:
    """Result of :meth:`TendonRobotReference.solve`.

    tip_position (3,) [m] world, tip_rotation (3, 3), tension (nt,) [N],
    slack (nt,) [m], residual (max abs scaled residual), s (N,), position (N, 3),
    base_force (3,) [N] and base_moment (3,) [N m]: the backbone's internal force and
    moment at s = 0 (world), for comparison with the core's n(0), m(0)."""

    tip_position: np.ndarray
    tip_rotation: np.ndarray
    tension: np.ndarray
    slack: np.ndarray
    residual: float
    s: np.ndarray
    position: np.ndarray
    base_force: np.ndarray
    base_moment: np.ndarray
    nfev: int = 0


class TendonRobotReference:
    """Spatial Kirchhoff or Cosserat rod with tip-anchored tendons under a tip force
    ``F`` [N] and moment ``M`` [N m] (world), solved independently of the core.

    Form: the distal part [s, L] of backbone *and* tendons is cut free. Its balance
    gives the backbone's internal force and moment (world) as
        n(s) = F - sum_i tau_i t_i(s),
        m(s) = h(s) - sum_i tau_i (R r_i) x t_i(s),   h' = -p' x F,   h(L) = M,
    with t_i the tendon's unit tangent. The constitutive laws then give u, v
    implicitly (t_i depends on them); a small Newton solve recovers them at every
    right-hand-side evaluation. Unknowns: h(0) and the tensions of taut
    displacement-controlled tendons; residuals: h(L) - M and the length
    constraints  l_i(L) + q_i + beta_i - (1 + tau_i/EA_i) l_rest,i = 0. Slack is
    handled by an active set (a tendon whose tension would be negative is
    released with tau = 0 and must then be shorter than its free length).

    Accuracy: DOP853 at ``rtol`` (default 1e-13); the tip is typically good to
    ~1e-12 relative. Not fast (pure Python): seconds per solve.
    """

    def __init__(
        self,
        L,
        EI,
        GJ,
        tendons: Sequence[RefTendon] = (),
        *,
        EA=np.inf,
        GA=np.inf,
        kirchhoff=True,
        EI2=None,
        F=(0, 0, 0),
        M=(0, 0, 0),
        rtol=1e-13,
    ):
        self.L = float(L)
        self.Kbt = np.diag([EI, EI if EI2 is None else EI2, GJ]).astype(float)
        self.kirchhoff = bool(kirchhoff) or (np.isinf(EA) and np.isinf(GA))
        self.Cse = np.diag(
            [
                0.0 if np.isinf(GA) else 1.0 / GA,
                0.0 if np.isinf(GA) else 1.0 / GA,
                0.0 if np.isinf(EA) else 1.0 / EA,
            ]
        )
        self.tendons = list(tendons)
        for i, t in enumerate(self.tendons):
            if (t.q is None) == (t.tau is None):
                raise ValueError(f"RefTendon {i}: give exactly one of q, tau")
        self.F = np.asarray(F, dtype=float)
        self.M = np.asarray(M, dtype=float)
        self.rtol = rtol
        self.EI = float(EI)
        self.nfev = 0
        self._rest = None

    # -- local constitutive solve -------------------------------------------------
    def _uv(self, s, R, h, tau, guess):
        """Solve for body strains u, v at s given R, h and tensions (Newton)."""
        Kbt, Cse = self.Kbt, self.Cse
        hb = R.T @ h
        Fb = R.T @ self.F
        rs = [t.r(s) for t in self.tendons]
        drs = [t.dr() for t in self.tendons]
        u = guess[0].copy()
        v = guess[1].copy()
        active = [i for i in range(len(self.tendons)) if tau[i] != 0.0]
        scale_u = 1.0 / self.L
        last = math.inf
        step = math.inf
        for it in range(60):
            G2 = Kbt @ u - hb
            nb = Fb.copy()
            J = np.zeros((6, 6))
            J[3:, 3:] = Kbt
            for i in active:
                r = rs[i]
                w = np.cross(u, r) + drs[i] + v
                wn = np.linalg.norm(w)
                wh = w / wn
                P = (np.eye(3) - np.outer(wh, wh)) / wn
                rh = _hat(r)
                G2 = G2 + tau[i] * np.cross(r, wh)
                nb = nb - tau[i] * wh
                # d(wh)/du = P (-rh), d(wh)/dv = P
                J[3:, 3:] += tau[i] * (rh @ P @ (-rh))
                J[3:, :3] += tau[i] * (rh @ P)
                J[:3, 3:] += Cse @ (tau[i] * P @ (-rh))
                J[:3, :3] += Cse @ (tau[i] * P)
            if self.kirchhoff:
                du = np.linalg.solve(J[3:, 3:], -G2)
                u = u + du
                step = np.linalg.norm(du) / max(np.linalg.norm(u), scale_u)
            else:
                G1 = v - _E3 - Cse @ nb
                J[:3, :3] += np.eye(3)
                d = np.linalg.solve(J, -np.concatenate([G1, G2]))
                v = v + d[:3]
                u = u + d[3:]
                step = max(
                    np.linalg.norm(d[3:]) / max(np.linalg.norm(u), scale_u), np.linalg.norm(d[:3])
                )
            # converged: the update is at round-off, or it stopped shrinking there
            if step <= 1e-15 or (step <= 1e-11 and step >= 0.5 * last):
                break
            last = step
            if not active and it >= 1:
                break
        else:
            if step > 1e-11:
                raise RuntimeError("TendonRobotReference: constitutive Newton did not converge")
        return u, v, rs, drs

    def _rhs_factory(self, tau):
        nt = len(self.tendons)
        cache = [np.zeros(3), _E3.copy()]

        def rhs(s, y):
            self.nfev += 1
            R = y[3:12].reshape(3, 3)
            h = y[12:15]
            u, v, rs, drs = self._uv(s, R, h, tau, cache)
            cache[0], cache[1] = u, v
            dp = R @ v
            dR = R @ _hat(u)
            dh = -np.cross(dp, self.F)
            dl = np.empty(nt)
            for i in range(nt):
                dl[i] = np.linalg.norm(np.cross(u, rs[i]) + drs[i] + v)
            return np.concatenate([dp, dR.ravel(), dh, dl])

        return rhs

    def integrate(self, h0, tau, dense=False):
        """Integrate from the base with h(0) = h0 and tensions tau; returns the solve_ivp result."""
        from scipy.integrate import solve_ivp

        nt = len(self.tendons)
        y0 = np.concatenate([np.zeros(3), np.eye(3).ravel(), h0, np.zeros(nt)])
        atol = np.concatenate(
            [
                np.full(3, 1e-16 * self.L),
                np.full(9, 1e-16),
                np.full(3, 1e-16 * self.EI / self.L),
                np.full(nt, 1e-16 * self.L),
            ]
        )
        sol = solve_ivp(
            self._rhs_factory(np.asarray(tau, dtype=float)),
            (0.0, self.L),
            y0,
            method="DOP853",
            rtol=self.rtol,
            atol=atol,
            dense_output=dense,
        )
        if not sol.success:
            raise RuntimeError(f"TendonRobotReference: integration failed: {sol.message}")
        return sol

    def rest_lengths(self):
        """Free (unstretched) length of each tendon [m]: its path length in the straight
        robot at its pretension, shortened by the pretension's stretch."""
        if self._rest is None:
            nt = len(self.tendons)
            tp = np.array([t.pretension for t in self.tendons])
            F, M = self.F, self.M
            self.F = np.zeros(3)
            self.M = np.zeros(3)
            try:
                sol = self.integrate(np.zeros(3), tp)
            finally:
                self.F, self.M = F, M
            l0 = sol.y[15 : 15 + nt, -1]
            EA = np.array([t.EA for t in self.tendons])
            self._rest = l0 / (1.0 + tp / EA)
        return self._rest

    def solve(self, guess=None, *, steps=8, max_active_set=6):
        """Solve the scene by continuation (actuation and loads ramped in ``steps``
        steps from the straight unloaded robot, each step a MINPACK hybrid solve) and
        an active set for slack. ``guess``: a previous RefResult of a nearby scene to
        start from instead (then one step)."""
        from scipy.optimize import root

        nt = len(self.tendons)
        L, EI = self.L, self.EI
        rest = self.rest_lengths()
        disp = [i for i, t in enumerate(self.tendons) if t.q is not None]
        taut = set(disp)
        fscale = EI / L**2
        mscale = EI / L
        F_full, M_full = self.F.copy(), self.M.copy()
        q_full = np.array([t.q if t.q is not None else 0.0 for t in self.tendons])
        tau_ctrl = np.array([t.tau if t.tau is not None else 0.0 for t in self.tendons])
        tp = np.array([t.pretension for t in self.tendons])
        EA = np.array([t.EA for t in self.tendons])

        def unpack(x, act, lam):
            h0 = x[:3] * mscale
            tau = np.where([t.tau is not None for t in self.tendons], lam * tau_ctrl, 0.0)
            for j, i in enumerate(act):
                tau[i] = x[3 + j] * fscale
            for i in disp:
                if i not in act:
                    tau[i] = 0.0
            return h0, tau

        def residual(x, act, lam):
            h0, tau = unpack(x, act, lam)
            try:
                sol = self.integrate(h0, tau)
            except RuntimeError:
                # a trial point of the root finder far from any equilibrium: report a large
                # residual so that it backs off (continuation then halves its step)
                return np.full(3 + len(act), 1e6)
            yL = sol.y[:, -1]
            res = [(yL[12:15] - self.M) / mscale]
            for i in act:
                li = yL[15 + i]
                res.append([(li + lam * q_full[i] - (1.0 + tau[i] / EA[i]) * rest[i]) / L])
            return np.concatenate(res)

        if guess is not None:
            h0g = guess.base_moment + sum(
                guess.tension[i] * np.cross(self.tendons[i].r(0.0), _E3) for i in range(nt)
            )
            for i in disp:
                if guess.tension[i] <= 0.0 and guess.slack[i] > 0.0:
                    taut.discard(i)
            act = sorted(taut)
            x = np.concatenate([h0g / mscale] + [[guess.tension[i] / fscale] for i in act])
        else:
            act = sorted(taut)
            x = np.concatenate([np.zeros(3)] + [[tp[i] / fscale] for i in act])

        def step_to(lam, x, taut):
            """Active-set solve at ``lam`` from ``x``; returns (x, taut, ok, tip)."""
            taut = set(taut)
            self.F, self.M = lam * F_full, lam * M_full
            for _ in range(max_active_set):
                act = sorted(taut)
                r = root(
                    residual,
                    x,
                    args=(act, lam),
                    method="hybr",
                    options={"xtol": 1e-14, "maxfev": 400},
                )
                x = r.x
                h0, tau = unpack(x, act, lam)
                neg = [i for i in act if tau[i] < 0.0]
                if neg:
                    # release the most negative one, re-solve
                    worst = min(neg, key=lambda i: tau[i])
                    taut.discard(worst)
                    x = np.delete(x, 3 + act.index(worst))
                    continue
                # slack tendons must be shorter than their free length (beta >= 0)
                sol = self.integrate(h0, tau)
                yL = sol.y[:, -1]
                back = [
                    i
                    for i in disp
                    if i not in taut and rest[i] - yL[15 + i] - lam * q_full[i] < 0.0
                ]
                if back:
                    i = back[0]
                    taut.add(i)
                    act2 = sorted(taut)
                    x = np.insert(x, 3 + act2.index(i), 0.0)
                    continue
                ok = bool(np.max(np.abs(residual(x, act, lam)), initial=0.0) < 1e-8)
                return x, taut, ok, yL[:3].copy()
            return x, taut, False, None

        # adaptive continuation: a step is accepted when it converges and the tip moves
        # by less than 0.25 L (a larger jump means the solve left the branch it was on:
        # under large dead loads the rod has other, looped, unstable equilibria)
        lam_done = 0.0 if guess is None else 1.0 - 1e-300
        tip_prev = np.array([0.0, 0.0, L]) if guess is None else guess.tip_position
        dlam = 1.0 / steps if guess is None else 1.0
        if guess is not None:
            lam_done = 0.0
        while lam_done < 1.0:
            lam = min(1.0, lam_done + dlam)
            x_new, taut_new, ok, tip = step_to(lam, x.copy(), taut)
            if ok and (
                np.linalg.norm(tip - tip_prev) < 0.25 * L
                or (guess is not None and lam == 1.0 and dlam == 1.0)
            ):
                x, taut, lam_done, tip_prev = x_new, taut_new, lam, tip
                dlam = min(2.0 * dlam, 1.0 / steps) if guess is None else dlam
                continue
            dlam *= 0.5
            if dlam < 1e-5:
                raise RuntimeError(
                    f"TendonRobotReference: continuation stalled at {lam_done:.4g} of the load"
                )
        self.F, self.M = F_full, M_full
        act = sorted(taut)
        res = residual(x, act, 1.0)
        # polish: Newton steps with a central-difference Jacobian (MINPACK's hybrid
        # method stops on its step test, sometimes at 1e-10; this takes the residual
        # to the integration noise, ~1e-13)
        for _ in range(4):
            nrm = np.max(np.abs(res))
            if nrm < 1e-14:
                break
            h = 1e-6
            J = np.empty((len(res), len(x)))
            for j in range(len(x)):
                e = np.zeros(len(x))
                e[j] = h * max(1.0, abs(x[j]))
                J[:, j] = (residual(x + e, act, 1.0) - residual(x - e, act, 1.0)) / (2 * e[j])
            x2 = x - np.linalg.lstsq(J, res, rcond=None)[0]
            res2 = residual(x2, act, 1.0)
            if np.max(np.abs(res2)) < nrm:
                x, res = x2, res2
            else:
                break
        h0, tau = unpack(x, act, 1.0)
        sol = self.integrate(h0, tau, dense=True)
        yL = sol.y[:, -1]
        slack = np.zeros(nt)
        for i in disp:
            if i not in taut:
                slack[i] = rest[i] - yL[15 + i] - q_full[i]
        # base internal force/moment of the backbone alone (world)
        u0, v0, rs, drs = self._uv(0.0, np.eye(3), h0, tau, [np.zeros(3), _E3.copy()])
        n0 = self.F.copy()
        m0 = h0.copy()
        for i in range(nt):
            w = np.cross(u0, rs[i]) + drs[i] + v0
            t = w / np.linalg.norm(w)
            n0 = n0 - tau[i] * t
            m0 = m0 - tau[i] * np.cross(rs[i], t)
        return RefResult(
            tip_position=yL[:3].copy(),
            tip_rotation=yL[3:12].reshape(3, 3).copy(),
            tension=tau,
            slack=slack,
            residual=float(np.max(np.abs(res), initial=0.0)),
            s=sol.t,
            position=sol.y[:3].T.copy(),
            base_force=n0,
            base_moment=m0,
            nfev=self.nfev,
        )


def from_scene(scene, rtol=1e-13):
    """Build a :class:`TendonRobotReference` from a :class:`tendonrod.Scene` with tip
    loads only and tip-anchored tendons (raises ValueError otherwise)."""
    robot = scene.robot
    rod = robot.rod
    L = rod.length
    F = np.zeros(3)
    M = np.zeros(3)
    for ld in scene.loads:
        if type(ld).__name__ == "DistributedLoad":
            if np.any(np.asarray(ld.force) != 0.0):
                raise ValueError("from_scene: distributed loads are not supported by the reference")
            continue
        if abs(ld.s - L) > 1e-12 * L:
            raise ValueError(f"from_scene: only tip loads are supported, got a load at s={ld.s!r}")
        F += ld.force
        M += ld.moment
    tendons = []
    for i, t in enumerate(robot.tendons):
        if t.end is not None and abs(t.end - L) > 1e-12 * L:
            raise ValueError("from_scene: only tip-anchored tendons are supported")
        tendons.append(
            RefTendon(
                b=t.offset,
                phi=t.angle,
                a=t.slope,
                EA=t.EA,
                q=scene.displacement[i],
                tau=scene.tension[i],
                pretension=t.pretension,
            )
        )
    return TendonRobotReference(
        L,
        rod.bending_stiffness,
        rod.torsional_stiffness,
        tendons,
        EA=rod.axial_stiffness,
        GA=rod.shear_stiffness,
        kirchhoff=rod.kirchhoff,
        F=F,
        M=M,
        rtol=rtol,
    )
