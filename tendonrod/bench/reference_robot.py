"""An independent solver of the tendon robot for the benchmarks and the tests.

A spatial Kirchhoff or Cosserat rod with tip-anchored tendons (displacement- or
tension-controlled, stretch, pretension, slack by an active set) under tip loads,
written in a *different* form from the core's (global balance of the distal part
instead of the local A, B, G, H matrices of ``docs/model.md``), by single shooting
with SciPy's DOP853 at tight tolerance.  It never calls the C core, so agreement
with the core tests the core's formulation, not only its arithmetic.

Conventions are those of ``docs/model.md``: SI units, base at the origin, base
frame = world frame, undeformed rod along +z, loads in the world frame, tendon i at
body-frame offset ``r_i(s) = (a_i s + b_i)(cos phi_i, sin phi_i, 0)``, positive
displacement q retracts the tendon, tension tau >= 0.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .references import _E3, _hat

__all__ = ["RefTendon", "RefResult", "TendonRobotReference", "from_scene"]


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
        # One long method (~170 lines): the continuation, the active set and the final
        # polish are closures over the same unknowns and active set; it is kept whole
        # because it is the independent reference the committed results and the tests
        # were computed with.
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
