"""The stress suite's load paths and stability limits: cases that follow a branch with
:func:`tendonrod.path` or judge equilibria on either side of a critical load, each
against an independent answer.

- the Euler load of the cantilever as a bifurcation (pi^2 EI / 4 L^2);
- the post-buckled branch against the exact elastica (elliptic integrals);
- a limit point (the buckled column pushed back by a lateral force) against SciPy's own
  shooting of the planar elastica;
- a stepped column judged on either side of its characteristic buckling load;
- four tendons locked at their taut/slack switch holding a column past its Euler load,
  judged on either side of the clamped column with a rotational tip spring EA r^2 / L.
"""

from __future__ import annotations

import math
import time

import numpy as np

from ..continuation import path
from ..model import PointLoad, Robot, Rod, Scene, Tendon
from ..options import Options
from ..solver import solve
from . import references as refs

__all__ = ["path_cases"]

_COLUMN = dict(length=0.25, diameter=1.2e-3, E=60e9, G=23e9, kirchhoff=True)


def _column():
    rod = Rod(**_COLUMN)
    EI, L = rod.bending_stiffness, rod.length
    scene = Scene(Robot(rod, []), loads=[PointLoad(s=L, force=(0.0, 0.0, 0.0))])
    return scene, EI, L, math.pi**2 * EI / (4 * L**2)


def _record(ok, verified, err, msg, t0, points=0):
    return dict(
        converged=bool(ok),
        verified=bool(verified),
        iterations=int(points),
        nfev=0,
        residual=math.nan,
        jacobian_cond=math.nan,
        seconds=time.perf_counter() - t0,
        balance=math.nan,
        refine=math.nan,
        check_error=float(err),
        message=msg,
        continuation_steps=0,
    )


def _euler():
    """Bifurcation of the straight cantilever at pi^2 EI / 4 L^2, to 1e-8 relative."""
    t0 = time.perf_counter()
    scene, EI, L, Pe = _column()
    p = path(scene, "loads[0].force[2]", (0.0, -3.0 * Pe))
    bif = [sp for sp in p.special_points if sp.kind == "bifurcation"]
    err = abs(-bif[0].value / Pe - 1.0) if bif else math.nan
    ok = p.success and len(bif) == 1
    return _record(
        ok, ok and err <= 1e-8, err, f"{p.message}; bifurcation / P_E - 1 = {err:.2e}", t0, len(p)
    )


def _elastica():
    """The post-buckled branch (switch=+1) against the exact elastica: L sqrt(P/EI) =
    K(k), tip x = 2k / sqrt(P/EI), z = (2E(k) - K(k)) / sqrt(P/EI), k = sin(alpha/2);
    1e-8 relative on P and 1e-8 L on the tip."""
    from scipy.special import ellipe, ellipk

    t0 = time.perf_counter()
    scene, EI, L, Pe = _column()
    p = path(scene, "loads[0].force[2]", (0.0, -3.0 * Pe), switch=1)
    post = p.branch == 1
    if not (p.success and post.sum() >= 10):
        return _record(False, False, math.nan, p.message, t0, len(p))
    P = -p.value[post]
    d3 = p.tip_rotation[post][:, :, 2]
    k = np.sin(np.arctan2(np.abs(d3[:, 0]), d3[:, 2]) / 2)
    lam = np.sqrt(P / EI)
    eP = float(np.max(np.abs(P / (EI * ellipk(k**2) ** 2 / L**2) - 1.0)))
    ex = float(np.max(np.abs(np.abs(p.tip_position[post][:, 0]) - 2 * k / lam))) / L
    ez = float(np.max(np.abs(p.tip_position[post][:, 2] - (2 * ellipe(k**2) - ellipk(k**2)) / lam)))
    err = max(eP, ex, ez / L)
    msg = (
        f"{p.message}; {int(post.sum())} post-buckled points, worst {err:.2e} against the elastica"
    )
    return _record(True, err <= 1e-8, err, msg, t0, len(p))


def _limit():
    """The column buckled at 1.5 P_E pushed back by a lateral tip force: the limit point
    against SciPy's elastica (1e-8 relative); the path returns to the straight column."""
    t0 = time.perf_counter()
    scene, EI, L, Pe = _column()
    P = 1.5 * Pe
    scene = Scene(scene.robot, loads=[PointLoad(s=L, force=(0.0, 0.0, -P))])
    x0 = solve(scene).tip_position[0]
    p = path(scene, "loads[0].force[0]", (0.0, -math.copysign(0.5 * Pe, x0)))
    lim = [sp for sp in p.special_points if sp.kind == "limit"]
    if len(lim) != 1:
        return _record(False, False, math.nan, p.message, t0, len(p))
    ref = refs.elastica_limit_force(P, EI, L) * math.copysign(1.0, x0)
    err = abs(lim[0].value / ref - 1.0)
    back = "returned to the start" in p.message and abs(p.tip_position[-1, 0]) < 1e-9 * L
    msg = (
        f"limit point H L^2/EI = {lim[0].value * L**2 / EI:.10f}, {err:.2e} from SciPy; {p.message}"
    )
    return _record(True, err <= 1e-8 and back, err, msg, t0, len(p))


def _stepped():
    """A stepped cantilever column (EI1 on the base half, EI2 on the tip half): stable at
    0.97 and unstable at 1.03 of the root of cos(k1 a) cos(k2 b) = (k1/k2) sin(k1 a)
    sin(k2 b), k = sqrt(P/EI)."""
    from scipy.optimize import brentq

    t0 = time.perf_counter()
    base = Rod(length=0.1, diameter=1.0e-3, E=207e9, G=79.6e9, kirchhoff=True)
    tip = Rod(length=0.1, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    rod = Rod.segmented([base, tip])
    EI1, EI2 = base.bending_stiffness, tip.bending_stiffness

    def f(P):
        k1, k2 = math.sqrt(P / EI1), math.sqrt(P / EI2)
        return math.cos(k1 * 0.1) * math.cos(k2 * 0.1) - (k1 / k2) * math.sin(k1 * 0.1) * math.sin(
            k2 * 0.1
        )

    lo = math.pi**2 * EI2 / (4 * 0.2**2)
    Pcr = brentq(f, 0.9 * lo, 4 * lo)
    return _either_side(
        lambda P: Scene(Robot(rod, []), loads=[PointLoad(s=0.2, force=(0, 0, -P))]), Pcr, t0
    )


def _locked():
    """Four tendons locked at zero tension around a straight column (EA = 3e3 N, r = 1 cm):
    judged on either side of the clamped column with a rotational tip spring K = EA r^2 /
    L, EI a cos(aL) + K sin(aL) = 0, a^2 = P / EI."""
    from scipy.optimize import brentq

    t0 = time.perf_counter()
    rod = Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    EI, L, r, EA = rod.bending_stiffness, 0.2, 0.01, 3e3
    K = EA * r * r / L
    aL = brentq(lambda x: EI * (x / L) * math.cos(x) + K * math.sin(x), math.pi / 2, math.pi)
    robot = Robot(rod, [Tendon(offset=r, angle=k * math.pi / 2, EA=EA) for k in range(4)])
    return _either_side(
        lambda P: Scene(robot, displacement=[0.0] * 4, loads=[PointLoad(s=L, force=(0, 0, -P))]),
        EI * (aL / L) ** 2,
        t0,
    )


def _either_side(build, Pcr, t0):
    """Stable at 0.97 Pcr, unstable at 1.03 Pcr (the straight state, accept_unstable)."""
    got = []
    for f in (0.97, 1.03):
        sol = solve(build(f * Pcr), options=Options(accept_unstable=True))
        got.append((sol.success, sol.stable, sol.stability, sol.stability_reason))
    ok = all(g[0] for g in got)
    right = got[0][1] is True and got[1][1] is False
    msg = "; ".join(f"{f:g} Pcr: {g[3]}" for f, g in zip((0.97, 1.03), got))
    return _record(ok, ok and right, math.nan, msg, t0, 2)


def path_cases(StressCase) -> list:
    """The group's cases (``StressCase`` passed in: the suite's record type)."""
    g = "load paths and limits"
    runs = [  # (name, runner, in the test suite's quick subset)
        ("paths/euler/bifurcation", _euler, True),
        ("paths/euler/post-buckled-elastica", _elastica, False),
        ("paths/pushed-back/limit-point", _limit, False),
        ("limits/stepped-column/verdict", _stepped, True),
        ("limits/locked-tendons/verdict", _locked, True),
    ]
    return [StressCase(name, g, build=None, ramp=fn, quick=q) for name, fn, q in runs]
