"""The stress suite's load ramps: cases that run a sequence of warm-started solves
and check the path, not one answer."""

from __future__ import annotations

import math
import time

import numpy as np

from ..model import PointLoad, Robot, Scene, Tendon
from ..options import Options
from . import references as refs
from .common import FIG17, EI_of, rod_of, solve_quiet
from .verify import verify


def ramp_fig17(slack_model="linear", warm=True, n=13):
    """Fig. 17 scene: load ramp 0 -> 2 P_c -> 0 (P_c the critical load), warm started
    along the ramp. Checks: every step converges and verifies; the tension is positive
    below P_c and zero above (within a step); the way back retraces the way up."""
    p = FIG17
    L, EI, r = p["L"], EI_of(p), p["r"]
    Pc = refs.critical_tip_angle_load(L, EI, math.pi / 2)
    up = list(np.linspace(0.0, 2.0 * Pc, n))
    path = up + up[-2::-1]
    robot = Robot(rod_of(p), [Tendon(offset=r)])
    prev = None
    recs = []
    opts = Options(slack_model=slack_model)
    t0 = time.perf_counter()
    for P in path:
        sc = Scene(
            robot, displacement=[r * math.pi / 2], loads=[PointLoad(s=L, force=(0.0, 0.0, -P))]
        )
        sol = solve_quiet(sc, opts, guess=prev if warm else None)
        v = (
            verify(sol)
            if sol.success
            else dict(verified=False, balance=math.nan, refine=math.nan, note="")
        )
        recs.append((P, sol, v))
        if sol.success:
            prev = sol
    secs = time.perf_counter() - t0
    ok = all(s.success for _, s, _ in recs)
    ver = all(v["verified"] for _, _, v in recs)
    notes = []
    # tension sign pattern against the critical load (independent, elliptic integrals)
    bad_t = [
        P
        for P, s, _ in recs
        if s.success
        and ((P < 0.98 * Pc and s.tension[0] <= 0.0) or (P > 1.02 * Pc and s.tension[0] > 1e-9))
    ]
    if bad_t:
        notes.append(f"tension wrong side of P_c={Pc:.4f} N at P={bad_t}")
    # up and down agree
    m = len(up)
    back = [
        float(np.linalg.norm(recs[i][1].tip_position - recs[len(path) - 1 - i][1].tip_position) / L)
        for i in range(m)
        if recs[i][1].success and recs[len(path) - 1 - i][1].success
    ]
    hyst = max(back) if back else math.nan
    if not (hyst < 1e-6):
        notes.append(f"ramp up and down differ by {hyst:.2e} L")
    # past P_c the tip must be the free elastica (exact)
    errs = []
    for P, s, _ in recs:
        if P > 1.02 * Pc and s.success:
            x, z, _ = refs.elastica_compressive(L, EI, P)
            errs.append(float(np.hypot(s.tip_position[0] - x, s.tip_position[2] - z) / L))
    e_ela = max(errs) if errs else math.nan
    if not (e_ela < 1e-6):
        notes.append(f"slack tip differs from the exact elastica by {e_ela:.2e} L")
    verified = ok and ver and not notes
    fails = [f"P={P:.3f}: {s.message}" for P, s, _ in recs if not s.success]
    msg = (
        "; ".join(fails[:3] + notes)
        or f"{len(path)} steps 0 -> {2 * Pc:.3f} N -> 0 (P_c={Pc:.4f} N)"
    )
    return dict(
        converged=ok,
        verified=verified,
        iterations=int(sum(s.nit for _, s, _ in recs)),
        nfev=int(sum(s.nfev for _, s, _ in recs)),
        residual=float(max((s.residual_norm for _, s, _ in recs), default=math.nan)),
        jacobian_cond=float(
            max(
                (s.jacobian_cond for _, s, _ in recs if np.isfinite(s.jacobian_cond)),
                default=math.nan,
            )
        ),
        seconds=secs,
        balance=float(
            max((v["balance"] for _, _, v in recs if np.isfinite(v["balance"])), default=math.nan)
        ),
        refine=float(
            max((v["refine"] for _, _, v in recs if np.isfinite(v["refine"])), default=math.nan)
        ),
        check_error=e_ela,
        message=msg,
        continuation_steps=int(sum(s.continuation_steps for _, s, _ in recs)),
    )


def ramp_large_load(n=13):
    """Plain Kirchhoff rod (Fig. 17 section), transverse tip load (-x) swept from
    F L^2/EI = 31.6 to 100 in 10 % steps, each solve warm started from the previous
    one (what a design sweep does). Every step must converge on the exact elastica
    (elliptic integrals): a warm start that jumps to another equilibrium is a wrong
    answer."""
    p = FIG17
    L, EI = p["L"], EI_of(p)
    robot = Robot(rod_of(p), [])
    prev = None
    errs, recs = [], []
    t0 = time.perf_counter()
    for fl in np.geomspace(10**1.5, 100.0, n):
        F = fl * EI / L**2
        sol = solve_quiet(
            Scene(robot, loads=[PointLoad(s=L, force=(-F, 0.0, 0.0))]),
            Options(),
            guess=prev,
        )
        recs.append(sol)
        if not sol.success:
            errs.append(math.nan)
            break
        x, z, _ = refs.elastica_tip_force(L, EI, F)
        errs.append(float(np.hypot(sol.tip_position[0] + x, sol.tip_position[2] - z) / L))
        prev = sol
    secs = time.perf_counter() - t0
    ok = all(s.success for s in recs) and len(recs) == n
    worst = max((e for e in errs if np.isfinite(e)), default=math.nan)
    bad = [f"{fl:.3g}" for fl, e in zip(np.geomspace(10**1.5, 100.0, n), errs) if not (e < 1e-6)]
    msg = (
        f"{len(recs)} warm-started steps; worst tip error vs the exact elastica {worst:.2e} L"
        + (f"; wrong or failed at F L^2/EI = {', '.join(bad)}" if bad else "")
        + ("" if ok else f"; last message: {recs[-1].message}")
    )
    return dict(
        converged=ok,
        verified=ok and not bad,
        iterations=int(sum(s.nit for s in recs)),
        nfev=int(sum(s.nfev for s in recs)),
        residual=float(max(s.residual_norm for s in recs)),
        jacobian_cond=float(recs[-1].jacobian_cond),
        seconds=secs,
        balance=math.nan,
        refine=math.nan,
        check_error=worst,
        message=msg,
        continuation_steps=int(sum(s.continuation_steps for s in recs)),
    )
