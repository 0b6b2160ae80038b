"""Channel friction on the Section V prototype (the study the paper's Fig. 25 asks for).

The paper's parallel member (:data:`~tendonrod.paper.PROTOTYPE`: L = 0.201 m, r = 8 mm,
EI = 11.2e-3 N m^2, tendon k = 4.5e3 N/m, so EA = k L) with a Coulomb coefficient mu
between tendon and channel (``Tendon(friction=mu)``).  The core assumes the tendon slides
along its whole length in one direction (``Scene(sliding="in")``: toward the actuator,
the tension falls from the actuator to the anchor; ``"out"``: the reverse); static
friction allows every state between the two, so the two settings bound the band of
states a real (partly stuck) tendon can be in.

Geometry as everywhere in :mod:`tendonrod.paper`: the base clamped with the rod along +z
(up), the tendon at +x pulling the tip over toward +x.

:func:`axial_load_band` -- actuated to a tip angle and loaded along the base axis (Fig. 25).
:func:`actuation_hysteresis` -- tip angle and actuator tension against the displacement,
pulling (sliding in) and releasing (sliding out).
:func:`loading_slip` -- which way a locked tendon slips in its channel as the load grows.

Every function returns plain arrays in a dict; :mod:`tendonrod.paper.charts` draws them.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..model import PointLoad, Robot, Rod, Scene, Tendon
from ..solver import solve
from .prototype import PROTOTYPE, Prototype
from .robots import actuate

__all__ = [
    "FRICTIONS",
    "AXIAL_FORCES",
    "AXIAL_DIRECTION",
    "TIP_ANGLES",
    "friction_robot",
    "axial_load_band",
    "axial_load_study",
    "actuation_hysteresis",
    "loading_slip",
]

FRICTIONS = (0.05, 0.1, 0.2, 0.3)
"""Coulomb coefficients [-] of the study: lubricated to dry polymer on polymer."""
TIP_ANGLES = (math.radians(30.0), math.radians(60.0))
"""The paper's two actuated tip angles [rad] (Figs. 24-25)."""
AXIAL_FORCES = (0.0, 0.1, 0.2, 0.3, 0.4, 0.5)
"""Axial loads [N] (the paper hung 10-50 g; 0 is the actuated, unloaded state)."""
AXIAL_DIRECTION = np.array([0.0, 0.0, -1.0])
"""The axial load's direction (world): down the base axis.  The paper hung weights
("loaded in the axial (vertical) direction") with the base up, and says the direction
was "such that tendon slack could develop": a downward tip load on a robot bent toward
its tendon bends it further, shortening the tendon's path, so the locked tendon's tension
falls (it did: 7.3 N to 3.4 N at 60 deg, 0.5 N, frictionless)."""


def friction_robot(mu: float, proto: Prototype = PROTOTYPE) -> Robot:
    """The parallel member as a Kirchhoff rod with the calibrated EI and one parallel
    tendon at r with EA = k L and Coulomb coefficient ``mu`` (GJ = EI/1.3, irrelevant
    for these planar scenes, as :func:`~tendonrod.paper.actuation_tradeoff`)."""
    d = proto.design("parallel")
    rod = Rod(length=d["L"], EI=d["EI"], GJ=d["EI"] / 1.3, EA=1e9, GA=1e9, kirchhoff=True)
    return Robot(rod, [Tendon(offset=d["b"], EA=d["k"] * d["L"], friction=float(mu))])


def _axial(robot, q, sliding, F, guess, options):
    load = PointLoad(s=robot.rod.length, force=tuple(F * AXIAL_DIRECTION))
    scene = Scene(robot, displacement=[q], sliding=sliding, loads=[load])
    return solve(scene, guess=guess, options=options, strict=True)


def _branch(robot, q, sliding, forces, options):
    """Tip positions (nF, 3) [m], actuator and anchor tensions (nF,) [N] and tip
    angles (nF,) [rad] along the load ramp at locked displacement q."""
    tip, tau0, tau_tip, theta = [], [], [], []
    guess = None
    for F in forces:
        sol = guess = _axial(robot, q, sliding, F, guess, options)
        tip.append(np.asarray(sol.tip_position))
        tau0.append(float(sol.tension[0]))
        tau_tip.append(float(sol.tendon_tension[-1, 0]))
        theta.append(float(sol.tip_angle))
    return {
        "tip": np.array(tip),
        "tension": np.array(tau0),
        "tension_anchor": np.array(tau_tip),
        "theta": np.array(theta),
    }


def axial_load_band(
    theta: float,
    frictions=FRICTIONS,
    forces=AXIAL_FORCES,
    proto: Prototype = PROTOTYPE,
    options=None,
) -> dict:
    """The prototype actuated to ``theta`` [rad] and loaded along the base axis.

    Protocol, per mu: pull the tendon until the unloaded tip angle is ``theta`` with the
    tendon sliding in (it is being pulled: :func:`tendonrod.paper.actuate`, tension
    control, default ``sliding="in"``), lock that displacement q, and apply each axial
    load with the tendon slid fully in and fully out.  The frictionless robot is actuated
    to ``theta`` the same way (its own q).

    Deflection: the tip's displacement along the load [m], from the actuated state (the
    ``"in"`` state at F = 0, where the robot is after pulling; for mu = 0 its own).  The
    ``"out"`` edge therefore starts below 0 at F = 0: at the locked q the unloaded robot
    may rest anywhere in that band.  Tip angles are :attr:`Solution.tip_angle`
    (unwrapped along s).

    Returns ``theta``, ``forces`` (nF,) [N], ``direction`` (3,), ``frictions``, and per
    mu (0.0 for the frictionless robot) a dict with ``q`` [m], ``tension_actuated`` [N],
    ``tip0`` (3,) [m] (the actuated tip), and per sliding ``"in"`` / ``"out"`` (mu = 0:
    ``"none"``) a dict with ``tip`` (nF, 3), ``deflection`` (nF,), ``tension`` and
    ``tension_anchor`` (nF,) [N], ``theta`` (nF,) [rad].
    """
    forces = np.asarray(forces, dtype=float)
    out = {
        "theta": float(theta),
        "forces": forces,
        "direction": AXIAL_DIRECTION.copy(),
        "frictions": tuple(float(m) for m in frictions),
    }
    for mu in (0.0, *out["frictions"]):
        robot = friction_robot(mu, proto)
        act = actuate(robot, theta, options=options)
        q = float(act.displacements[0])
        # the reference is the locked, unloaded state solved as the loads are (not the
        # actuation's own solution): every curve then measures from one solve setting
        tip0 = np.asarray(_axial(robot, q, "in", 0.0, act.solution, options).tip_position)
        rec = {"q": q, "tension_actuated": float(act.tensions[0]), "tip0": tip0}
        for sliding in ("in", "out") if mu > 0 else ("none",):
            br = _branch(robot, q, "in" if sliding == "none" else sliding, forces, options)
            br["deflection"] = (br["tip"] - tip0) @ AXIAL_DIRECTION
            rec[sliding] = br
        out[mu] = rec
    return out


def axial_load_study(thetas=TIP_ANGLES, **kw) -> dict:
    """:func:`axial_load_band` for each tip angle [rad]: ``{theta: band}``."""
    return {float(t): axial_load_band(t, **kw) for t in thetas}


def actuation_hysteresis(
    frictions=FRICTIONS,
    theta_max: float = math.radians(90.0),
    n: int = 31,
    proto: Prototype = PROTOTYPE,
    options=None,
) -> dict:
    """Tip angle and actuator tension against the tendon displacement, unloaded: pulling
    (q rising from 0, the tendon sliding in) and releasing (q falling back, sliding out).

    The displacement grid runs from 0 to the q that brings the frictionless robot to
    ``theta_max`` [rad], ``n`` points.  At the turning point the real tendon sticks while
    the actuator tension drops from the pulling to the releasing value (not modelled:
    the two branches are joined there by a vertical segment in a chart); at q = 0 the
    tendon carries no tension, so there is no friction and the loop closes.

    Returns ``q`` (n,) [m], ``frictions``, and per mu (0.0: frictionless, key
    ``"none"``) per branch ``"in"`` / ``"out"`` a dict with ``theta`` (n,) [rad],
    ``tension`` (n,) [N] at the actuator, ``tension_anchor`` (n,) [N] and ``tip`` (n, 3)
    [m], all on the same q grid (ascending).
    """
    q_max = float(actuate(friction_robot(0.0, proto), theta_max, options=options).displacements[0])
    q = np.linspace(0.0, q_max, n)
    out: dict[Any, Any] = {
        "q": q,
        "frictions": tuple(float(m) for m in frictions),
        "theta_max": theta_max,
    }
    for mu in (0.0, *out["frictions"]):
        robot = friction_robot(mu, proto)
        rec = {}
        for branch in ("in", "out") if mu > 0 else ("none",):
            sliding = "in" if branch == "none" else branch
            # pulling walks q up, releasing walks it down: continuation in the real order
            order = range(n) if branch != "out" else range(n - 1, -1, -1)
            th, tau0, tau1 = np.empty(n), np.empty(n), np.empty(n)
            tip = np.empty((n, 3))
            guess = None
            for i in order:
                scene = Scene(robot, displacement=[q[i]], sliding=sliding)
                sol = guess = solve(scene, guess=guess, options=options, strict=True)
                th[i] = sol.tip_angle
                tau0[i] = sol.tension[0]
                tau1[i] = sol.tendon_tension[-1, 0]
                tip[i] = sol.tip_position
            rec[branch] = {"theta": th, "tension": tau0, "tension_anchor": tau1, "tip": tip}
        out[mu] = rec
    return out


def loading_slip(
    theta: float,
    force: float = 0.5,
    mu: float = 0.1,
    proto: Prototype = PROTOTYPE,
    options=None,
) -> dict:
    """Which way the locked tendon slips in its channel when the axial ``force`` [N] is
    applied to the prototype with friction ``mu`` actuated to ``theta`` [rad].

    The robot is pulled to ``theta`` (sliding in), its displacement locked, and solved
    unloaded and loaded with the tendon on the *in* edge, where pulling left it;
    :func:`tendonrod.slip` then gives the slip of the tendon material between the two
    states and says where it contradicts "in": there the tendon slid out, and the loaded
    state moves toward the *out* edge of the band.

    Returns ``s`` (N,) [m], ``slip`` (N,) [m] (positive toward the actuator, "in"), the
    locked displacement ``q`` [m] and ``check``, the :class:`tendonrod.Slip`.
    """
    from ..friction import slip

    robot = friction_robot(mu, proto)
    q = float(actuate(robot, theta, options=options).displacements[0])
    unloaded = _axial(robot, q, "in", 0.0, None, options)
    loaded = _axial(robot, q, "in", force, unloaded, options)
    check = slip(loaded, reference=unloaded)
    return {"s": loaded.s, "slip": check.slip[:, 0], "q": q, "check": check}
