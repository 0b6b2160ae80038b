"""The paper's Cosserat-model studies (Section IV): the data behind Figs. 1, 10-18,
each a function returning plain arrays (a dict).  Load paths are warm-started sweeps
(:func:`tendonrod.sweep`), so that large loads are reached by continuation."""

from __future__ import annotations

import dataclasses
import math
import warnings
from typing import Any

import numpy as np

from .. import analytic
from ..model import PointLoad, Robot, Scene, Tendon
from ..results import ConvergenceWarning
from ..solver import compliance, solve
from ..sweeps import sweep, tip_measure
from .closed_forms import closed_form_tip_sigma_vs_alpha
from .robots import (
    ALPHA_PAPER,
    DIRECTIONS,
    actuate,
    paper_rod_ivb,
    paper_rod_slack,
    sigma_from_compliance,
    single_tendon_robot,
    tendon_EA,
    tip_angle,
)

__all__ = [
    "straight_load_sweep",
    "prescribed_comparison",
    "out_of_plane_comparison",
    "torsion_paradox",
    "compliance_map",
    "tip_compliance_vs_alpha",
    "slack_study",
    "critical_slack_load",
]


def _load_path(scene, forces, s=None, moments=None, options=None):
    """Solve ``scene`` under a point load stepping through ``forces`` (K, 3) [N] (and
    ``moments``), in one warm-started chunk (a continuation path), via tr.sweep."""
    L = scene.robot.rod.length
    s = L if s is None else s
    forces = np.asarray(forces, dtype=float).reshape(-1, 3)
    moments = (
        np.zeros_like(forces)
        if moments is None
        else np.asarray(moments, dtype=float).reshape(-1, 3)
    )
    base = dataclasses.replace(scene, loads=(PointLoad(s=s, force=(0.0, 0.0, 0.0)),))
    # points past the end of the load path fail: they are the study's data (the callers
    # read ``res.success``), not a failure to report
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        res = sweep(
            base,
            {"loads[0].force": list(forces), "loads[0].moment": list(moments)},
            grid=False,
            chunksize=len(forces),
            measure=_shape_measure,
            options=options,
            progress=False,
        )
    if not res.data:
        raise RuntimeError(
            f"load path: all {len(forces)} points failed; first: {res.message.flat[0]}"
        )
    return res


def _shape_measure(scene, sol):
    """Per-point record for load paths: tip pose, tensions, slack, and the backbone."""
    out = tip_measure(scene, sol)
    out["position"] = np.asarray(sol.position, dtype=float)
    out["tip_angle"] = np.array(tip_angle(sol))
    return out


def straight_load_sweep(rod=None, offset: float = 0.01, loads=None, options=None) -> dict:
    """Fig. 10: tip deflection of the initially straight robot (tendon locked at q = 0,
    inextensible) under a growing transverse tip load -F e_x, Cosserat against the
    closed forms, for no tendon, parallel and converging routing.

    Returns F_nd = F L^2 / EI, and per case 'cosserat' and 'closed' tip deflection
    delta / L along the load (+ 'success').
    """
    rod = paper_rod_ivb() if rod is None else rod
    EI, L = rod.bending_stiffness, rod.length
    F_nd = np.linspace(0.0, 3.0, 31) if loads is None else np.asarray(loads, dtype=float)
    F = F_nd * EI / L**2
    out: dict[Any, Any] = {"F_nd": F_nd}
    cases = {
        "no tendon": (Robot(rod, []), 0.0, 0.0),
        "parallel": (single_tendon_robot(rod, "parallel", offset), 0.0, math.inf),
        "converging": (single_tendon_robot(rod, "converging", offset), -offset / L, math.inf),
    }
    for name, (robot, a, k) in cases.items():
        scene = Scene(robot, displacement=[0.0] * robot.n_tendons)
        res = _load_path(scene, np.outer(F, [-1.0, 0.0, 0.0]), options=options)
        out[name] = {
            "cosserat": -res["tip_position"][:, 0] / L,
            "success": res.success,
            "tension": res["tension"],
            "closed": analytic.deflection(L, F, L, L, EI, a, offset, k) / L,
        }
    return out


def prescribed_comparison(
    rod=None, offset: float = 0.01, theta: float = math.pi / 2, force=(-0.5, 0.0, 0.0), options=None
) -> dict:
    """Figs. 1 and 11(a, b): the same robot and load with the tendon's displacement held
    (actuator locked) or its tension held.

    theta = 0 is Fig. 1 (straight robot, q = 0: the tendon starts exactly taut and
    unstressed); theta = pi/2 with a transverse or axial force is Fig. 11(a)/(b).
    Returns 'unloaded', 'displacement held', 'tension held' backbones (N, 3) [m], their
    tensions, and the closed-form tip deflections for theta = 0 (eqs. 9 and 12).
    """
    rod = paper_rod_ivb() if rod is None else rod
    robot = single_tendon_robot(rod, "parallel", offset)
    L = rod.length
    if theta == 0.0:
        unloaded = solve(Scene(robot, displacement=[0.0]), options=options, strict=True)
        locked = Scene(robot, displacement=[0.0])
        held = Scene(robot, tension=[0.0])
    else:
        act = actuate(robot, theta, options=options)
        unloaded, locked, held = act.solution, act.locked_scene, act.tension_scene
    forces = np.outer(np.linspace(0.0, 1.0, 11)[1:], force)
    out = {
        "force": np.asarray(force, dtype=float),
        "theta": theta,
        "unloaded": np.asarray(unloaded.position),
    }
    for name, sc in (("displacement held", locked), ("tension held", held)):
        res = _load_path(sc, forces, options=options)
        out[name] = res["position"][-1]
        out[name + " tension"] = float(res["tension"][-1, 0])
        out[name + " success"] = bool(res.success[-1])
    if theta == 0.0:
        EI, F = rod.bending_stiffness, -float(force[0])
        out["closed displacement held"] = float(
            analytic.deflection(L, F, L, L, EI, 0.0, offset, math.inf)
        )
        out["closed tension held"] = float(analytic.deflection(L, F, L, L, EI, 0.0, offset, 0.0))
    return out


def out_of_plane_comparison(
    rod=None,
    offset: float = 0.01,
    theta: float = math.pi / 2,
    force=(0.0, 0.5, 0.0),
    alphas3=(50.0, 50e3),
    options=None,
) -> dict:
    """Fig. 11(c): three equally spaced stretchable tendons, actuated to ``theta`` by the
    tendon at +x, loaded out of plane at the tip; displacement held for each
    r^2 k L / (3 EI) in ``alphas3`` and tension held.  Returns backbones (N, 3) [m]."""
    rod = paper_rod_ivb() if rod is None else rod
    EI = rod.bending_stiffness
    out: dict[Any, Any] = {"force": np.asarray(force, dtype=float), "alphas3": tuple(alphas3)}
    forces = np.outer(np.linspace(0.0, 1.0, 11)[1:], force)
    for a3 in alphas3:
        EA = tendon_EA(3.0 * a3, EI, offset)
        robot = Robot(
            rod, [Tendon(offset=offset, angle=2 * math.pi * i / 3, EA=EA) for i in range(3)]
        )
        act = actuate(robot, theta, options=options)
        out["unloaded"] = np.asarray(act.solution.position)
        res = _load_path(act.locked_scene, forces, options=options)
        out[("displacement held", a3)] = res["position"][-1]
        out[("success", a3)] = bool(res.success[-1])
        out[("tension", a3)] = res["tension"][-1]
        if a3 == alphas3[0]:
            res_t = _load_path(act.tension_scene, forces, options=options)
            out["tension held"] = res_t["position"][-1]
    return out


def torsion_paradox(
    rod=None,
    offset: float = 0.01,
    alphas=(10.0, 1e2, 1e3, 1e4),
    n: int = 21,
    twist_max: float = 0.5,
    options=None,
) -> dict:
    """Fig. 12: a straight robot with three parallel tendons locked at q = 0 under a pure
    twisting moment M_z at the tip, for growing tendon stiffness alpha = r^2 k L / EI.

    The moment is stepped up to twist_max * GJ / L (the rod alone would twist
    ``twist_max`` rad).  Returns M_nd = M L / GJ and the tip twist phi [rad] per alpha
    (and 'no tendon' = M_nd, the rod alone).  The slope d phi / d M_nd at 0 is 1 for
    every alpha: the tendons' length changes are second order in the twist.
    """
    rod = paper_rod_ivb() if rod is None else rod
    EI, GJ, L = rod.bending_stiffness, rod.torsional_stiffness, rod.length
    M_nd = np.linspace(0.0, twist_max, n)
    out: dict[Any, Any] = {"M_nd": M_nd, "no tendon": M_nd.copy(), "alphas": tuple(alphas)}
    for alpha in alphas:
        EA = tendon_EA(alpha, EI, offset)
        robot = Robot(
            rod, [Tendon(offset=offset, angle=2 * math.pi * i / 3, EA=EA) for i in range(3)]
        )
        scene = Scene(robot, displacement=[0.0] * 3)
        M = M_nd[1:] * GJ / L
        res = _load_path(
            scene, np.zeros((len(M), 3)), moments=np.outer(M, [0.0, 0.0, 1.0]), options=options
        )
        R = res["tip_rotation"]
        phi = np.arctan2(R[:, 1, 0], R[:, 0, 0])
        out[alpha] = np.concatenate([[0.0], np.where(res.success, phi, np.nan)])
        out[("tension", alpha)] = res["tension"]
    return out


def compliance_map(
    rod=None,
    offset: float = 0.01,
    routings=("parallel", "converging"),
    theta: float = math.pi / 2,
    alpha: float = ALPHA_PAPER,
    zeta=None,
    tension_held: bool = True,
    options=None,
) -> dict:
    """Figs. 13-15: sigma(zeta) at a loaded point z = zeta L of the robot actuated to
    ``theta``, for loads in the transverse, axial and out-of-plane directions.

    sigma = 12 EI/L^3 d^T C(z) d from compliance at s = z (small loads).  For each
    routing: the tendon locked ('displacement held') and, if ``tension_held``, its
    tension held.  Returns zeta and out[(routing, held, direction)] arrays.
    """
    rod = paper_rod_ivb() if rod is None else rod
    EI, L = rod.bending_stiffness, rod.length
    zeta = np.linspace(0.05, 1.0, 20) if zeta is None else np.asarray(zeta, dtype=float)
    out: dict[Any, Any] = {"zeta": zeta, "theta": theta, "alpha": alpha}
    for routing in routings:
        robot = single_tendon_robot(rod, routing, offset, alpha)
        act = actuate(robot, theta, options=options)
        scenes = {"displacement held": act.locked_scene}
        if tension_held:
            scenes["tension held"] = act.tension_scene
        for held, sc in scenes.items():
            sig = {d: np.empty(len(zeta)) for d in DIRECTIONS}
            for j, z in enumerate(zeta):
                C = compliance(sc, s=z * L, guess=act.solution, options=options)
                for dname, dvec in DIRECTIONS.items():
                    sig[dname][j] = sigma_from_compliance(C, dvec, EI, L)
            for dname in DIRECTIONS:
                out[(routing, held, dname)] = sig[dname]
    return out


class _LockedTipCompliance:
    """Sweep measure: lock the solved tension-controlled scene's actuators at
    sol.displacement and record the tip compliance (6, 6) of the locked scene."""

    def __call__(self, scene, sol):
        locked = dataclasses.replace(
            scene, displacement=list(sol.displacement), tension=[None] * scene.robot.n_tendons
        )
        return {
            "compliance": compliance(locked, guess=sol),
            "tension": np.asarray(sol.tension),
            "displacement": np.asarray(sol.displacement),
        }


def tip_compliance_vs_alpha(
    rod=None,
    offset: float = 0.01,
    theta: float = math.pi / 2,
    alphas=None,
    options=None,
    executor=None,
) -> dict:
    """Fig. 16: tip sigma against alpha = r^2 k L / EI (b^2 k L / EI converging) for the
    robot actuated to ``theta``, parallel and converging, three load directions.

    A tension-controlled tendon's stiffness does not change the unloaded shape, so each
    routing is actuated once (tension found by :func:`actuate`), then tr.sweep varies
    the tendon's EA and records the locked-actuator tip compliance.  Also returns the
    closed-form straight-robot curves of Fig. 7 for comparison (as the paper writes
    them; the exact straight-robot limit of the converging tendon is eq. 32 at
    alpha / c^3, c = sqrt(1 + a^2) -- see docs/model.md and tests/test_studies.py).
    ``out[(routing, "failures")]`` lists the sweep's failed points as
    :meth:`tendonrod.sweep.SweepResult.failures` gives them: ``(index, outcome,
    status, message)``; their sigma is NaN.
    """
    rod = paper_rod_ivb() if rod is None else rod
    EI, L = rod.bending_stiffness, rod.length
    alphas = np.logspace(-1, 4, 21) if alphas is None else np.asarray(alphas, dtype=float)
    out: dict[Any, Any] = {
        "alpha": alphas,
        "theta": theta,
        "closed": closed_form_tip_sigma_vs_alpha(alphas),
    }
    for routing in ("parallel", "converging"):
        act = actuate(single_tendon_robot(rod, routing, offset, math.inf), theta, options=options)
        EAs = [tendon_EA(a, EI, offset) for a in alphas]
        res = sweep(
            act.tension_scene,
            {"robot.tendons[0].EA": EAs},
            measure=_LockedTipCompliance(),
            options=options,
            executor=executor,
            chunksize=1,
            progress=False,
        )
        C = res["compliance"]
        for dname, dvec in DIRECTIONS.items():
            out[(routing, dname)] = np.array(
                [
                    sigma_from_compliance(c, dvec, EI, L) if ok else np.nan
                    for c, ok in zip(C, res.success)
                ]
            )
        out[(routing, "failures")] = res.failures()
    return out


def slack_study(
    rod=None,
    offset: float = 0.01,
    theta: float = math.pi / 2,
    F_max: float = 1.0,
    n: int = 41,
    opposing: bool = False,
    pretension: float = 5.0,
    alpha: float = ALPHA_PAPER,
    options=None,
) -> dict:
    """Figs. 17 (single tendon) and 18 (``opposing``: a second tendon at -x held at
    ``pretension`` [N] before locking; finite stiffness ``alpha`` so that the opposing pair
    has a defined tension level): the robot of Figs. 17-18 actuated to ``theta``, actuators
    locked, under a vertical tip force -F e_z stepped from 0 to F_max (one continuation
    path).  Also the tension-held response.

    On ``alpha``: an opposing pair of inextensible tendons on a Kirchhoff rod has no
    defined tension level, so the pair needs a finite stiffness; the default is the
    paper's r^2 k L / EI = 8.29e6 (1e5 gives the same tensions to 3 digits).  Past about
    0.3 N the locked planar equilibrium buckles laterally (one unstable mode) at either
    stiffness: those points fail with status 5 and are NaN here.

    Points that did not converge are NaN in the returned arrays ("success" says which).

    Returns F [N], tension (n, nt) [N], slack (n, nt) [m], tip displacement from the
    unloaded tip (n, 3) [m], tip angle [rad], success, and the tension-held tip
    displacement and angle.
    """
    rod = paper_rod_slack() if rod is None else rod
    EI = rod.bending_stiffness
    if opposing:
        EA = tendon_EA(alpha, EI, offset)
        robot = Robot(
            rod,
            [
                Tendon(offset=offset, angle=0.0, EA=EA),
                Tendon(offset=offset, angle=math.pi, EA=EA),
            ],
        )
        act = actuate(robot, theta, tensions=[pretension, pretension], options=options)
    else:
        robot = single_tendon_robot(rod, "parallel", offset, math.inf)
        act = actuate(robot, theta, options=options)
    F = np.linspace(0.0, F_max, n)
    tip0 = np.asarray(act.solution.tip_position)
    out: dict[Any, Any] = {
        "F": F,
        "theta": theta,
        "opposing": opposing,
        "unloaded": np.asarray(act.solution.position),
        "tension0": act.tensions,
    }
    for key, sc in (("locked", act.locked_scene), ("held", act.tension_scene)):
        res = _load_path(sc, np.outer(F[1:], [0.0, 0.0, -1.0]), options=options)
        ok = np.concatenate([[True], res.success])

        def masked(first, rest):
            arr = np.concatenate(
                [np.asarray(first, dtype=float)[None], np.asarray(rest, dtype=float)]
            )
            arr[~ok] = np.nan
            return arr

        out[key] = {
            "tension": masked(act.tensions, res["tension"]),
            "slack": masked(np.zeros_like(act.tensions), res["slack"]),
            "tip_displacement": masked(np.zeros(3), res["tip_position"] - tip0),
            "tip_angle": masked(act.theta, res["tip_angle"]),
            "position": masked(act.solution.position, res["position"]),
            "success": ok,
        }
    # critical load: bracketed by the first converged grid point where the (first)
    # tendon's tension reaches 0, then refined to solver accuracy (not a grid value)
    tau = out["locked"]["tension"][:, 0]
    crit = np.nonzero(out["locked"]["success"] & (tau <= 0.0))[0]
    out["F_slack"] = math.nan
    if crit.size and crit[0] > 0 and out["locked"]["success"][crit[0] - 1]:
        out["F_slack"] = critical_slack_load(
            act.locked_scene,
            F[crit[0] - 1],
            F[crit[0]],
            direction=(0.0, 0.0, -1.0),
            options=options,
        )
    return out


def critical_slack_load(
    scene,
    F_lo: float,
    F_hi: float,
    direction=(0.0, 0.0, -1.0),
    tendon: int = 0,
    xtol: float = 1e-12,
    options=None,
) -> float:
    """Load magnitude [N] at which ``tendon`` of ``scene`` goes slack under a tip force
    ``F * direction`` (world frame), bracketed by ``F_lo`` (taut) and ``F_hi`` (slack).

    Bisection on the signed taut/slack indicator g(F) = tension [N] when taut and
    -slack [m] when slack: both vanish at the switch, so g changes sign exactly there
    (the solver's semismooth tension/slack variable makes g continuous).  Each solve is
    warm-started from the nearer bracket end.  Stops when the bracket is below
    ``xtol`` relative.  Raises RuntimeError when a solve fails or the bracket does not
    straddle the switch."""
    L = scene.robot.rod.length
    d = np.asarray(direction, dtype=float)

    def g(F, guess):
        sc = dataclasses.replace(scene, loads=(PointLoad(s=L, force=tuple(F * d)),))
        sol = solve(sc, guess=guess, options=options)
        if not sol.success:
            raise RuntimeError(f"critical_slack_load: solve at F = {F!r} N failed: {sol.message}")
        tau, beta = float(sol.tension[tendon]), float(sol.slack[tendon])
        return (tau if tau > 0.0 else -beta), sol

    lo, hi = float(F_lo), float(F_hi)
    g_lo, sol_lo = g(lo, None)
    g_hi, sol_hi = g(hi, sol_lo)
    if not (g_lo > 0.0 and g_hi <= 0.0):
        raise RuntimeError(
            f"critical_slack_load: [{lo}, {hi}] N does not bracket the switch "
            f"(tension/-slack {g_lo!r} and {g_hi!r})"
        )
    while hi - lo > xtol * hi:
        mid = 0.5 * (lo + hi)
        g_mid, sol_mid = g(mid, sol_lo)
        if g_mid > 0.0:
            lo, sol_lo = mid, sol_mid
        else:
            hi = mid
    return 0.5 * (lo + hi)
