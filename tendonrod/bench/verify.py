"""Verification of a converged stress-suite solution: finite, global force and moment
balance, agreement under step refinement and with the adaptive integrator, physical
tension/slack, and a case-specific check where an independent answer is known."""

from __future__ import annotations

import math

import numpy as np

from ..options import Options
from .common import EI_scale, solve_quiet

__all__ = ["global_balance", "verify", "BALANCE_TOL", "REFINE_TOL"]


def _route(t, s):
    """Body-frame r(s) and r'(s) [m, -] of tendon ``t`` (linear, helical or a path)."""
    if t.path is not None:
        return t.path(s)[0], t.path(s, 1)[0]
    ang = t.angle + (t.twist or 0.0) * s
    d = np.array([math.cos(ang), math.sin(ang), 0.0])
    dperp = np.array([-math.sin(ang), math.cos(ang), 0.0])
    rho = t.slope * s + t.offset
    return rho * d, t.slope * d + rho * (t.twist or 0.0) * dperp


def _tendon_tangents(sol, s_index=0):
    """Unit tendon tangents (world) at node ``s_index`` from the solution's own strains
    (the base section's rigidities and precurvature: ``u = u* + m_b / K``)."""
    sc = sol.scene
    rod = sc.robot.rod
    R = sol.rotation[s_index]
    n_b = R.T @ sol.force[s_index]
    m_b = R.T @ sol.moment[s_index]
    EI, GJ = rod.bending_stiffness, rod.torsional_stiffness
    base = rod.segments[0] if rod.segments else rod
    u = np.asarray(base.precurvature, dtype=float) + m_b / np.array([EI, EI, GJ])
    if rod.kirchhoff:
        v = np.array([0.0, 0.0, 1.0])
    else:
        inv = np.array(
            [1.0 / rod.shear_stiffness, 1.0 / rod.shear_stiffness, 1.0 / rod.axial_stiffness]
        )
        v = np.array([0.0, 0.0, 1.0]) + inv * n_b
    s = sol.s[s_index]
    out = []
    for t in sc.robot.tendons:
        rr, rp = _route(t, s)
        w = np.cross(u, rr) + rp + v
        out.append((R @ rr, R @ (w / np.linalg.norm(w))))
    return out


def global_balance(sol):
    """Scaled residual of the whole robot's force and moment balance (world frame,
    about the base): base reaction, tendon pulls at the base, point loads at the
    solved positions, distributed loads (Simpson over the nodes; a load over part of the
    rod over its own interval); moments about the base (a mounted robot's too). Scaled by the
    largest force present (loads, tensions; EI/L^2 only if there is none) and that
    times L, so that a 1e-6 N load that the solver ignored shows as an O(1) error."""
    sc = sol.scene
    L = sc.robot.rod.length
    EI = sc.robot.rod.bending_stiffness
    if sol.s[0] != 0.0 or abs(sol.s[-1] - L) > 1e-12 * L:
        raise ValueError("global_balance needs nodes spanning [0, L]")
    Fsum = -sol.force[0].copy()
    Msum = -sol.moment[0].copy()
    p0 = sol.position[0]  # the base: moments about it
    fmax = 0.0
    for (rb, tb), tau in zip(_tendon_tangents(sol, 0), sol.tension):
        Fsum -= tau * tb
        Msum -= tau * np.cross(rb, tb)
        fmax = max(fmax, abs(tau))
    for pl in sc.point_loads:
        i = int(np.argmin(np.abs(sol.s - pl.s)))
        if abs(sol.s[i] - pl.s) > 1e-12 * L:
            pos = sol.at(pl.s).position
        else:
            pos = sol.position[i]
        Fsum += np.asarray(pl.force)
        Msum += np.cross(pos - p0, pl.force) + np.asarray(pl.moment)
        fmax = max(fmax, float(np.linalg.norm(pl.force)), float(np.linalg.norm(pl.moment)) / L)
    f = sc.distributed_force
    if np.any(f != 0.0):
        from scipy.integrate import simpson

        Fsum += f * L
        # piece by piece between the nodes a breakpoint doubles (Simpson needs h > 0)
        cuts = [0, *(np.flatnonzero(np.diff(sol.s) == 0.0) + 1), sol.s.size]
        first = sum(
            simpson(sol.position[a:b] - p0, x=sol.s[a:b], axis=0)
            for a, b in zip(cuts[:-1], cuts[1:])
            if b - a >= 2
        )
        Msum += np.cross(first, f)
        fmax = max(fmax, float(np.linalg.norm(f)) * L)
    for ld in sc.partial_loads:
        from scipy.integrate import simpson

        end = L if ld.end is None else min(ld.end, L)
        sp = np.linspace(ld.start, end, 401)
        f = np.asarray(ld.force, dtype=float)
        Fsum += f * (end - ld.start)
        Msum += np.cross(simpson(sol.at(sp).position - p0, x=sp, axis=0), f)
        fmax = max(fmax, float(np.linalg.norm(f)) * (end - ld.start))
    if fmax == 0.0:  # nothing loads the robot: compare with its natural force scale
        fmax = EI / L**2
    return float(max(np.linalg.norm(Fsum) / fmax, np.linalg.norm(Msum) / (fmax * L)))


#: Verification thresholds (relative). A verified answer balances to 1e-6 of the
#: largest force (the default integrator's truncation error is ~1e-8; 1e-6 leaves
#: room for the extreme cases while still catching wrong answers, which are off by
#: O(1)), and its tip moves by less than 1e-6 L when the steps are doubled and when
#: the adaptive integrator at rtol 1e-10 is used instead.
BALANCE_TOL = 1e-6
REFINE_TOL = 1e-6


def verify(sol, check=None):
    """Verification of a converged solution (see the module docstring): a dict with
    ``verified``, ``balance``, ``refine``, ``check_error`` and a ``note``."""
    out = dict(verified=False, balance=math.nan, refine=math.nan, check_error=math.nan, note="")
    arrays = [sol.position, sol.rotation, sol.force, sol.moment, sol.tension, sol.slack]
    if not all(np.all(np.isfinite(a)) for a in arrays):
        out["note"] = "NaN/inf in a successful result"
        return out
    sc = sol.scene
    L = sc.robot.rod.length
    notes = []
    try:
        out["balance"] = global_balance(sol)
    except Exception as exc:  # noqa: BLE001
        notes.append(f"balance check failed: {exc}")
    # refinement: double the steps the solve used; and the adaptive integrator.
    diffs = []
    steps = max(int(sol.formulation.steps), 1)
    o = sol.options
    for kw in (
        dict(integrator=o.integrator if o.integrator != "adaptive" else "rk8", steps=2 * steps),
        dict(integrator="adaptive", rtol=1e-10),
    ):
        kk = o.raw()
        kk.update(kw)
        # the comparison is at 1e-6: 1e-8 is tight enough, and the adaptive integrator's
        # residual is noisy at its rtol level, so a tighter tol can stall on round-off
        kk["tol"] = max(o.tol, 1e-8)
        kk["tip_only"] = False
        s2 = solve_quiet(sc, Options(**kk), guess=sol)
        if not s2.success:
            notes.append(f"refined solve ({kw}) failed: {s2.message}")
            diffs.append(math.inf)
            continue
        d = float(np.linalg.norm(s2.tip_position - sol.tip_position) / L)
        if sol.tension.size:
            tscale = max(float(np.max(np.abs(s2.tension))), EI_scale(sc))
            d = max(d, float(np.max(np.abs(s2.tension - sol.tension))) / tscale)
        diffs.append(d)
    out["refine"] = max(diffs) if diffs else math.nan
    ok = out["balance"] < BALANCE_TOL and out["refine"] < REFINE_TOL
    if not out["balance"] < BALANCE_TOL:
        notes.append(f"global balance residual {out['balance']:.2e}")
    if not out["refine"] < REFINE_TOL:
        notes.append(f"refinement changes the answer by {out['refine']:.2e}")
    R = sol.rotation
    orth = float(np.max(np.abs(np.einsum("nij,nik->njk", R, R) - np.eye(3))))
    if orth > 1e-6:
        ok = False
        notes.append(f"rotation not orthonormal ({orth:.1e})")
    if (
        np.any(sol.tension < 0)
        or np.any(sol.slack < 0)
        or np.any((sol.tension > 0) & (sol.slack > 0))
    ):
        ok = False
        notes.append("tension/slack complementarity violated")
    if check is not None:
        try:
            e, cok, what = check(sol)
            out["check_error"] = e
            if not cok:
                ok = False
                notes.append(f"{what}: error {e:.2e}")
        except Exception as exc:  # noqa: BLE001
            ok = False
            notes.append(f"check raised {type(exc).__name__}: {exc}")
    out["verified"] = bool(ok)
    out["note"] = "; ".join(notes)
    return out
