"""Independent reference results for the Cosserat solver tests.

Nothing here imports tendonrod: these are written from classical elastica theory and
as a from-scratch planar shooting solver built on SciPy, so that agreement with the C
core means something.  The paper's closed forms (Sections II-III) are in closed_ref.py.

Sign conventions (tendonrod's, see docs/model.md): base at the origin, rod along +z; the
tangent angle theta(s) is measured from +z toward +x (rotation about +y); a tendon at
angle 0 sits at +x. Closed forms (paper): with the tendon at +x, F > 0 is the world force
-F e_x and theta, delta are positive in the direction of F (toward -x).
"""

from __future__ import annotations

import math

import numpy as np
from scipy import integrate, optimize, special

# --------------------------------------------------------------------------- closed forms
# The paper's closed forms themselves are in closed_ref.py (the one independent NumPy
# version); here only the map from a sloped tendon to their parameters.


def sloped_closed_params(slope, offset, EA_tendon, L):
    """Exact small-load parameters (a, b, k) for a sloped tendon (docs/model.md, "Links to the
    closed forms"): the moment arm and the stretch both see r/c, c = sqrt(1 + a^2), and the
    spring constant is EA/(c L) (tendon reference length c L)."""
    c = math.sqrt(1.0 + slope**2)
    k = math.inf if math.isinf(EA_tendon) else EA_tendon / (c * L)
    return slope / c, offset / c, k


# --------------------------------------------------------------------------- elastica
def elastica_transverse_tip_force(P, L, EI):
    """Cantilever (clamped at the origin along +z) under a dead tip force -P e_x, P > 0.

    Exact solution by elliptic integrals (pendulum analogy). With psi = pi/2 - theta
    and k = sin(psi_L/2), the substitution sin(psi/2) = k sin(t) gives
    lambda L = K(k) - F(t0, k), sin t0 = sin(pi/4)/k, lambda = sqrt(P/EI), and
    x_tip = [2 (E(k) - E(t0,k)) - (K(k) - F(t0,k))]/lambda, z_tip = 2 k cos(t0)/lambda,
    theta_L = pi/2 - 2 arcsin(k).

    Returns (x_tip, z_tip, theta_tip) [m, m, rad].
    """
    lam = math.sqrt(P / EI)

    def parts(k):
        m = k * k
        t0 = math.asin(min(1.0, math.sin(math.pi / 4) / k))
        return m, t0

    def g(k):
        m, t0 = parts(k)
        return special.ellipk(m) - special.ellipkinc(t0, m) - lam * L

    k_lo = math.sin(math.pi / 4) * (1.0 + 1e-15)
    k_hi = 1.0 - 1e-16
    k = optimize.brentq(g, k_lo, k_hi, xtol=1e-17, rtol=1e-15, maxiter=500)
    m, t0 = parts(k)
    KK, EE = special.ellipk(m), special.ellipe(m)
    Fi, Ei = special.ellipkinc(t0, m), special.ellipeinc(t0, m)
    x = (2.0 * (EE - Ei) - (KK - Fi)) / lam
    z = 2.0 * k * math.cos(t0) / lam
    theta = math.pi / 2 - 2.0 * math.asin(k)
    return x, z, theta


def elastica_compressive_tip_angle(theta_L, L, EI):
    """Cantilever along +z under a dead axial tip force -P e_z, on the first buckled branch
    bent toward +x with tip angle theta_L (0 < theta_L < pi).

    Pendulum analogy: k = sin(theta_L/2), lambda L = K(k), so P = K(k)^2 EI / L^2;
    x_tip = 2k/lambda, z_tip = (2 E(k) - K(k))/lambda.

    Returns (P, x_tip, z_tip) [N, m, m].
    """
    k = math.sin(theta_L / 2.0)
    m = k * k
    KK, EE = special.ellipk(m), special.ellipe(m)
    lam = KK / L
    return lam * lam * EI, 2.0 * k / lam, (2.0 * EE - KK) / lam


def circle_tip(kappa, length):
    """Tip (x, z, theta) of a circular arc of curvature kappa [1/m] bending toward +x."""
    if kappa == 0.0:
        return 0.0, length, 0.0
    th = kappa * length
    return (1.0 - math.cos(th)) / kappa, math.sin(th) / kappa, th


# --------------------------------------------------------------------------- planar shooting
class PlanarKirchhoffRobot:
    """From-scratch planar (x-z) reference for a Kirchhoff rod with tendons in frictionless
    channels, written for these tests with SciPy only.

    Formulation (independent of the C core's): the *total* section force N(s) of
    backbone plus tendons on the distal part is known in closed form from the external
    loads, N(s) = sum_{z_k > s} F_k + f (L - s), and the total moment about p(s) obeys
    M' = x' N_z - z' N_x (y component), jumping by -M_k at point moments. The backbone
    moment follows by removing the tendons' cut forces: with signed radius
    rho(s) = +-(a s + b) (+ for a channel at angle 0, - at angle pi) and the tendon tangent
    (rho', 1 - rho kappa) in the body (d1, d3) frame,

        EI kappa = M_y + sum_i tau_i rho_i (1 - rho_i kappa) / sqrt((1 - rho_i kappa)^2 + rho_i'^2),

    solved for kappa = theta' by scalar Newton. Tendon path lengths obey
    s_i' = sqrt((1 - rho kappa)^2 + rho'^2). Shooting unknowns: M_y(0) and the tension of
    each displacement-controlled tendon; residuals: M_y(L) = tip moment and the length
    constraint s_i(t_i) + q_i = (1 + tau_i/EA_i) * rest_i (rest_i = t_i sqrt(1 + a^2)
    unless given). Integration: DOP853, rtol 1e-13.

    tendons: list of dicts with keys offset, slope, sign (+1 angle 0, -1 angle pi), end,
    EA, and either q (displacement) or tau (tension); optional rest (rest length).
    loads: list of (s, Fx, Fz, My). dist: (fx, fz) [N/m].
    """

    def __init__(self, L, EI, tendons=(), loads=(), dist=(0.0, 0.0)):
        self.L, self.EI = float(L), float(EI)
        self.tendons = [dict(t) for t in tendons]
        for t in self.tendons:
            t.setdefault("slope", 0.0)
            t.setdefault("sign", 1.0)
            t.setdefault("EA", math.inf)
            t["end"] = self.L if t.get("end") is None else float(t["end"])
            t.setdefault("rest", t["end"] * math.sqrt(1.0 + t["slope"] ** 2))
        self.loads = [tuple(map(float, ld)) for ld in loads]
        self.fx, self.fz = map(float, dist)
        self.unknown_tendons = [i for i, t in enumerate(self.tendons) if "q" in t]
        brk = {ld[0] for ld in self.loads if 0.0 < ld[0] < self.L}
        brk |= {t["end"] for t in self.tendons if t["end"] < self.L}
        self.breaks = [0.0] + sorted(brk) + [self.L]

    # ---- pieces
    def _N(self, s, s_next):
        """Total section force on (s, L] for s within a segment ending at s_next."""
        Nx = self.fx * (self.L - s)
        Nz = self.fz * (self.L - s)
        for zk, Fx, Fz, _My in self.loads:
            if zk >= s_next and zk > 0.0:
                Nx += Fx
                Nz += Fz
        return Nx, Nz

    def _kappa(self, s, M, taus):
        EI = self.EI
        act = [(t, taus[i]) for i, t in enumerate(self.tendons) if s < t["end"]]
        kap = M / EI
        for t, tau in act:
            kap += (
                tau
                * t["sign"]
                * (t["slope"] * s + t["offset"])
                / math.sqrt(1 + t["slope"] ** 2)
                / EI
            )
        for _ in range(50):
            f, df = EI * kap - M, EI
            for t, tau in act:
                rho = t["sign"] * (t["slope"] * s + t["offset"])
                a = t["sign"] * t["slope"]
                u = 1.0 - rho * kap
                h = math.sqrt(u * u + a * a)
                f -= tau * rho * u / h
                df += tau * rho * rho * a * a / h**3
            step = f / df
            kap -= step
            if abs(step) <= 1e-16 * (abs(kap) + 1.0 / self.L):
                break
        return kap, act

    def _rhs(self, s, y, taus, s_next):
        x, z, th, M = y[:4]
        kap, _ = self._kappa(s, M, taus)
        Nx, Nz = self._N(s, s_next)
        dx, dz = math.sin(th), math.cos(th)
        dy = np.zeros_like(y)
        dy[0], dy[1], dy[2] = dx, dz, kap
        dy[3] = dx * Nz - dz * Nx
        for j, t in enumerate(self.tendons):
            if s < t["end"]:
                rho = t["sign"] * (t["slope"] * s + t["offset"])
                a = t["sign"] * t["slope"]
                dy[4 + j] = math.sqrt((1.0 - rho * kap) ** 2 + a * a)
        return dy

    def taus_from(self, x):
        taus = np.zeros(len(self.tendons))
        scale = self.EI / self.L**2
        for i, t in enumerate(self.tendons):
            if "tau" in t:
                taus[i] = t["tau"]
        for j, i in enumerate(self.unknown_tendons):
            taus[i] = x[1 + j] * scale
        return taus

    def integrate(self, M0, taus, nodes=None, rtol=1e-13):
        """Integrate from the base; returns (tip state y, node states or None)."""
        y = np.zeros(4 + len(self.tendons))
        y[3] = M0
        out = [] if nodes is not None else None
        for sa, sb in zip(self.breaks[:-1], self.breaks[1:]):
            if sb <= sa:
                continue
            tev = None
            if nodes is not None:
                tev = [sn for sn in nodes if sa <= sn <= sb and (sn < sb or sb == self.L)]
            sol = integrate.solve_ivp(
                self._rhs,
                (sa, sb),
                y,
                method="DOP853",
                rtol=rtol,
                atol=1e-15 * max(1.0, abs(M0)),
                args=(taus, sb),
                t_eval=tev if tev else None,
                dense_output=False,
            )
            if not sol.success:
                raise RuntimeError(sol.message)
            if tev:
                out.extend(sol.y.T)
            y = sol.y[:, -1].copy()
            for zk, _Fx, _Fz, My in self.loads:
                if zk == sb and sb < self.L:
                    y[3] -= My
        return y, (np.array(out) if out is not None else None)

    def residual(self, x):
        EI, L = self.EI, self.L
        M0 = x[0] * EI / L
        taus = self.taus_from(x)
        y, _ = self.integrate(M0, taus)
        My_tip = sum(ld[3] for ld in self.loads if ld[0] == L)
        res = [(y[3] - My_tip) * L / EI]
        for i in self.unknown_tendons:
            t = self.tendons[i]
            stretch = 0.0 if math.isinf(t["EA"]) else taus[i] / t["EA"]
            res.append((y[4 + i] + t["q"] - (1.0 + stretch) * t["rest"]) / L)
        return np.array(res)

    def solve(self, M0_guess=0.0, tau_guess=None, nodes=None):
        """Solve; returns dict with tip (x, z, theta), M0, tensions and node states
        (columns x, z, theta, M, s_i) if nodes were given."""
        EI, L = self.EI, self.L
        x0 = [M0_guess * L / EI]
        for j in range(len(self.unknown_tendons)):
            tg = 0.0 if tau_guess is None else tau_guess[j]
            x0.append(tg / (EI / L**2))
        r = optimize.root(
            self.residual, np.array(x0), method="hybr", options={"xtol": 1e-14, "maxfev": 2000}
        )
        if np.max(np.abs(r.fun)) > 1e-11:  # hybr may stall *at* the root; judge by residual
            raise RuntimeError(f"reference shooting failed: {r.message}, residual {r.fun}")
        M0 = r.x[0] * EI / L
        taus = self.taus_from(r.x)
        y, ys = self.integrate(M0, taus, nodes=nodes)
        return {
            "x": y[0],
            "z": y[1],
            "theta": y[2],
            "M0": M0,
            "tension": taus,
            "path_length": y[4:],
            "nodes": ys,
        }
