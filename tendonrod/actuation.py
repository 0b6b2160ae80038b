"""Inverse actuation: :func:`actuate`, the tendon controls that bring the tip to a target
under the scene's loads.

Python checks the call, puts the target in the robot's base frame and solves the scene
once; the rest is one call into the core (``_core.Problem.actuate``,
``csrc/tr_actuate.c``), with the GIL released.  A square target whose controls are all
displacements (a planar tip angle, a spatial tip direction or position, one actuated
tendon per component) is first solved inside the shooting system: its residual takes the
place of those tendons' length constraints and one Newton solve finds the controls and
the equilibrium together (``csrc/tr_target.c``).  Everything else, and whatever that
solve leaves (it needs the actuated tendons taut and a well-conditioned target), goes by
steps on the linearisation: every iterate an equilibrium the solver converged to (a warm
solve), every step from the forward-difference linearisation of that equilibrium
(``tr_linearize``, as :meth:`Problem.jacobian <tendonrod.Problem.jacobian>`): Newton's
method on the target, damped by a trust region (Levenberg-Marquardt) where the target has
at least as many components as there are controls, a sequential quadratic program where
it has fewer.  The state reached is solved once more, judged for stability with the
caller's options.  ``bench/results/jacobian_actuate.md`` measures both routes
(``bench/jacobian_actuate.py``).

Units: a target's residual is dimensionless, positions divided by the rod length L and
angles in radians; controls are measured in the solver's scales, a displacement q by the
largest tendon offset r and a tension tau by EI / (r L) (either turns the tip by about a
radian).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ._actuation_target import Target
from ._interrupt import current_token
from .compiled import is_planar, value_vector
from .model import Scene
from .options import _check_options, _replace
from .problem import Problem
from .results import report_failure
from .solution import Solution, _in_rod_units

__all__ = ["actuate", "ActuationResult"]


@dataclass(frozen=True, eq=False)
class ActuationResult:
    """What :func:`actuate` did (``Solution.actuation``).

    A :class:`~tendonrod.Result`: ``success``, ``status``, ``message``, ``nit``, ``nfev``
    mean the same on every result type.

    Attributes
    ----------
    kind : str
        ``"square"`` (as many controls as target components: Newton), ``"minimum-change"``
        (more controls: the least change from the scene's values, tensions held), or
        ``"least-squares"`` (fewer controls: the least-squares target residual).
    route : str
        ``"augmented"``: a square target with displacement controls was first solved inside
        the shooting system (its residual in place of the actuated tendons' length
        constraints, one Newton solve); ``"linearisation"``: steps on the linearisation
        only.
    target : dict
        The target as given (``{"tip_angle": ...}`` etc.).
    tendons : tuple of int
        The actuated tendons.
    controls : ndarray (n,)
        Their control values found: q [m] (displacement-controlled) or tau [N].
    residual : ndarray (m,)
        The target residual at the returned state: position components / L, angles and
        direction components [rad].
    distance : float
        Its max-norm (dimensionless; times L for a position [m]).
    reached : bool
        ``distance <= tol``.
    iterations, solves, jacobians : int
        Outer iterations, equilibrium solves and linearisations spent.
    constrained : tuple of int
        Tendons taut in the scene, held at ``min_tension`` or more (minimum change).
    active : tuple of int
        Those of them that end at ``min_tension`` (their constraint is active).
    multipliers : ndarray (m,) or None
        The target's Lagrange multipliers (minimum change), in the scaled units.
    tension_multipliers : ndarray (len(constrained),) or None
        The tension constraints' multipliers (>= 0; nonzero only where active).
    message : str
        What happened.
    success : bool
        The verdict of the run (as the returned ``Solution.success``).
    status : int
        The final solve's status when ``success``; else negative (-1, or the final solve's
        status when that failed).
    nit : int
        Outer iterations (``iterations``).
    nfev : int
        Equilibrium solves (``solves``): the outer problem's function evaluations.

    Examples
    --------
    >>> rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    >>> robot = tr.Robot(rod, [tr.Tendon(offset=0.01, angle=0.0)])
    >>> act = tr.actuate(tr.Scene(robot, displacement=[0.0]), tip_angle=np.pi / 4)
    >>> res = act.actuation
    >>> res.kind, res.reached, res.tendons
    ('square', True, (0,))
    """

    kind: str
    route: str
    target: dict
    tendons: tuple
    controls: np.ndarray
    residual: np.ndarray
    distance: float
    reached: bool
    iterations: int
    solves: int
    jacobians: int
    constrained: tuple
    active: tuple
    multipliers: np.ndarray | None
    tension_multipliers: np.ndarray | None
    message: str
    success: bool = True
    status: int = 0
    nit: int = 0
    nfev: int = 0


# --------------------------------------------------------------------------- controls
def _control_set(scene: Scene, tendons):
    n_all = scene.robot.n_tendons
    if n_all == 0:
        raise ValueError("actuate: the robot has no tendons to actuate")
    if tendons is None:
        idx = list(range(n_all))
    else:
        try:
            idx = [int(i) for i in tendons]
        except (TypeError, ValueError, OverflowError):
            raise ValueError(f"tendons must be tendon indices, got {tendons!r}") from None
        if (
            not idx
            or len(set(idx)) != len(idx)
            or any(i < 0 or i >= n_all or i != j for i, j in zip(idx, tendons))
        ):
            raise ValueError(f"tendons must be distinct indices in 0..{n_all - 1}, got {tendons!r}")
    disp = scene.displacement_controlled()
    rod = scene.robot.rod
    r = max(
        [
            max(abs(t.offset), abs(t.offset + t.slope * scene.robot.tendon_end(i)))
            for i, t in enumerate(scene.robot.tendons)
        ]
    )
    r = r if r > 0.0 else rod.length
    q_scale, tau_scale = r, rod.bending_stiffness / (r * rod.length)
    scale = np.array([q_scale if disp[i] else tau_scale for i in idx])
    assert scene.displacement is not None and scene.tension is not None  # (Scene fills them)
    values = np.array([scene.displacement[i] if disp[i] else scene.tension[i] for i in idx])
    return idx, values, scale, q_scale, tau_scale


def _with_controls(scene: Scene, idx, c) -> Scene:
    assert scene.displacement is not None and scene.tension is not None  # (Scene fills them)
    disp, ten = list(scene.displacement), list(scene.tension)
    for i, v in zip(idx, c):
        if disp[i] is not None:
            disp[i] = float(v)
        else:
            ten[i] = max(float(v), 0.0)  # the bounds hold it >= 0 up to round-off
    return dataclasses.replace(scene, displacement=disp, tension=ten)


if TYPE_CHECKING:

    class ActuatedSolution(Solution):
        """What :func:`actuate` returns, to a type checker: a Solution whose ``actuation``
        is always set (at run time it is a plain :class:`Solution`)."""

        actuation: ActuationResult

else:
    ActuatedSolution = Solution


def actuate(
    scene: Scene,
    *,
    tip_angle=None,
    tip_direction=None,
    tip_position=None,
    tip_pose=None,
    tendons=None,
    min_tension: float = 0.0,
    tol: float = 1e-10,
    max_iter: int = 50,
    guess=None,
    options=None,
    strict: bool = False,
    method: str = "auto",
) -> ActuatedSolution:
    """The controls of the tendons ``tendons`` that bring the tip to a target under the
    scene's loads: displacements for displacement-controlled tendons, tensions for
    tension-controlled ones (each tendon keeps its control kind in ``scene``).

    Parameters
    ----------
    scene : Scene
        The robot, its loads, the control kind of each tendon and the starting values.
    tip_angle : float, optional
        [rad] planar scenes: the signed angle of the tip tangent from the base axis (+z)
        toward +x, unwrapped along s (:attr:`Solution.tip_angle`; beyond pi for a curl);
        base frame for a mounted robot, whose other targets are in the world frame (they
        are compared in the base frame, where the core solves).
    tip_direction : (3,), optional
        The tip tangent (body z axis) in the world frame; normalised.  Its residual is the
        tip tangent's log map on the unit sphere about the target (two components: the
        great-circle angle [rad] toward it), zero only at the target.
    tip_position : (3,), optional
        [m] the tip position, world frame.
    tip_pose : (position (3,), rotation (3, 3)), optional
        The tip position [m] and body-to-world rotation; the rotation's residual is the
        rotation vector of R R_target^T [rad].
    tendons : sequence of int, optional
        The actuated tendons (default: all); the others keep their values.
    min_tension : float
        [N] with more controls than target components, every tendon taut in the scene
        keeps at least this tension (default 0: taut tendons stay taut).
    tol : float
        Target tolerance on the residual's max-norm (positions / L, angles in rad);
        default 1e-10.
    max_iter : int
        Outer iterations (each a warm solve and a linearisation).
    guess, options
        As in :func:`tendonrod.solve` (``guess`` starts the first solve).
    strict : bool
        Raise :class:`ConvergenceError` instead of warning when ``success`` is False.
    method : {"auto", "linearisation"}
        ``"auto"``: a square target with displacement controls is first solved inside the
        shooting system (see the module notes), the rest by steps on the linearisation;
        ``"linearisation"``: steps on the linearisation only.

    Returns
    -------
    Solution
        The equilibrium at the controls found, its ``displacement`` and ``tension`` filled
        (a forward :func:`tendonrod.solve` of them reproduces it), and ``actuation``
        (:class:`ActuationResult`: residual, distance, iterations, multipliers).
        ``success`` is the core's verdict (``csrc/tr_actuate.c``), per kind of target, and
        in every kind the final solve of the state returned succeeded (judged for
        stability unless ``options.accept_unstable``):

        * square: the target reached (the residual's max-norm <= ``tol``);
        * minimum change: reached, and the least change verified (a KKT point);
        * least squares: reached, or a least-squares point: at the state returned every
          control's column a_j of the linearisation is orthogonal to the residual r to a
          cosine of 1e-4, ``|a_j^T r| <= 1e-4 |a_j| |r|`` (a control held at a bound that
          blocks its descent left out), and the run solved no state closer to the target
          by more than ``tol``.  The test is local: a reachable target may have
          least-squares points elsewhere.

        The state returned (square and least squares) is never farther from the target
        than a state the run solved, its start included; an unreachable target gives
        ``success=False`` with that state and its distance, never an exception.
        ``status`` stays the core's status of the final solve.

    Notes
    -----
    Square problems (as many controls as target components) take Newton steps on the
    linearisation, damped where they do not reduce the residual; more controls than
    components: the least change of the controls from the scene's values in the scaled
    units, subject to the target and to the tensions of the tendons taut in the scene
    (sequential quadratic programming); fewer: least squares (Levenberg-Marquardt).
    Tension controls stay >= 0.  Slack displacement-controlled tendons among the controls
    are first drawn to their taut/slack switch (their slack taken up), where pulling them
    has an effect the linearisation can see.

    Examples
    --------
    The displacement that bends the tip to 45 degrees under 0.1 N down:

    >>> rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    >>> robot = tr.Robot(rod, [tr.Tendon(offset=0.01, angle=0.0)])
    >>> scene = tr.Scene(robot, displacement=[0.0],
    ...                  loads=[tr.PointLoad(s=0.2, force=(0.0, 0.0, -0.1))])
    >>> act = tr.actuate(scene, tip_angle=np.pi / 4)
    >>> act.success, round(float(act.tip_angle), 9)
    (True, 0.785398163)
    """
    if not isinstance(scene, Scene):
        raise ValueError(f"scene must be a tendonrod.Scene, got {scene!r}")
    options = _check_options(options)
    for name, v, lo in (("min_tension", min_tension, 0.0), ("tol", tol, 0.0)):
        if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)):
            raise ValueError(f"{name} must be a number, got {v!r}")
        # (an int beyond a double, like 10**400, is not finite either)
        finite = not isinstance(v, int) or abs(v) < 2**1023
        if not (finite and math.isfinite(v) and v >= lo) or (name == "tol" and not 0.0 < v < 1.0):
            raise ValueError(f"{name} must be finite and >= 0 (tol in (0, 1)), got {v!r}")
    # (the upper bound: far beyond any search, within the core's C int)
    if (
        isinstance(max_iter, bool)
        or not isinstance(max_iter, (int, np.integer))
        or not 1 <= max_iter <= 10**6
    ):
        raise ValueError(f"max_iter must be an int in [1, 1000000], got {max_iter!r}")
    if method not in ("auto", "linearisation"):
        raise ValueError(f"method must be 'auto' or 'linearisation', got {method!r}")
    planar = is_planar(scene) and not options.force_spatial
    target = Target(scene, planar, tip_angle, tip_direction, tip_position, tip_pose)
    idx, c0, scale, q_scale, tau_scale = _control_set(scene, tendons)
    n, m = len(idx), target.m
    kind = "square" if n == m else ("minimum-change" if n > m else "least-squares")
    # the iterates are not judged for stability (a verdict per iterate would cost more than
    # the iterate); the state returned is, by a final solve with the caller's options
    prob = Problem(scene, options=_replace(options, accept_unstable=True))
    sol = prob._solve_quiet(scene, guess)
    report = {"kind": kind, "target": target.given, "tendons": tuple(idx), "tol": tol}
    if not sol.success:
        report.update(controls=c0, why="the scene did not solve at its own controls")
        return _finish(sol, report, strict)
    nt = scene.robot.n_tendons
    disp = scene.displacement_controlled()
    # lower bounds on the tensions: min_tension for the tendons taut in the scene (minimum
    # change), none for the others
    floor0 = np.full(nt, -np.inf)
    if kind == "minimum-change":
        for i in range(nt):
            if sol.tension[i] > 0.0 and (disp[i] or i in idx):
                floor0[i] = float(min_tension)
    rows = prob._jacobian_plan(None, (), False)[3]
    try:
        raw = prob._c.actuate(
            kind=_KIND[kind],
            tendons=np.array(idx, dtype=float),
            c0=c0,
            scale=scale,
            values=value_vector(scene)[:nt],
            floor=floor0,
            tau_scale=tau_scale,
            k=tau_scale / q_scale,
            tol=float(tol),
            max_iter=int(max_iter),
            tip_row=int(rows[0]),
            length=scene.robot.rod.length,
            augmented=method == "auto" and kind == "square",
            judge=not options.accept_unstable,
            cancel=current_token(),
            **target.spec(),
        )
    except RuntimeError as exc:  # a linearisation or a step failed (e.g. its budget)
        report.update(controls=c0, why=f"the iteration failed: {exc}")
        return _finish(sol, report, strict)
    act = raw["actuation"]
    c = act["controls"]
    final = Solution(
        raw, scene if np.array_equal(c, c0) else _with_controls(scene, idx, c), options
    )
    prob._plausible.check(final, "tendonrod.actuate", once=False)
    report.update(act)
    report["solves"] += 1  # the first solve
    return _finish(final, report, strict)


# The run's kinds (tr_act_kind).
_KIND = {"square": 0, "minimum-change": 1, "least-squares": 2}


def _finish(sol, report, strict):
    """The returned Solution: the final equilibrium with ``actuation`` and the verdict.
    ``report``: the run's (``Problem.actuate``'s 'actuation' dict, or the controls and
    ``why`` of a first solve that failed) with the kind, target, tendons and tol."""
    kind, tol = report["kind"], report["tol"]
    c, r = report["controls"], report.get("residual")
    why = report.get("why", "")
    iterations = report.get("iterations", 0)
    solves, jacobians = report.get("solves", 1), report.get("jacobians", 0)
    floors = report.get("floors")
    mus = report.get("tension_multipliers")
    constrained = (
        () if floors is None else tuple(int(i) for i in np.flatnonzero(np.isfinite(floors)))
    )
    active = tuple(i for i in constrained if mus is not None and mus[i] > 0.0)
    distance = float(np.abs(r).max()) if r is not None else math.inf
    reached = distance <= tol
    optimal = report.get("optimal", False)
    # the core's verdict (tr_actuate.h: the target kind's rule and the final solve's);
    # a run that never reached the core (the first solve failed) has none: no success
    ok = bool(report.get("success", False))
    if reached and not sol.success:
        # the controls reach the target, but the final solve does not accept the state
        # (unstable, or it failed): its reason first, and no "reached" before it
        msg = (
            f"{sol.message} -- at the controls that meet the target (residual "
            f"{distance:.3g} <= tol {tol:g})"
        )
    elif reached and not optimal:
        msg = (
            f"target reached (residual {distance:.3g} <= tol {tol:g}), but the least change "
            f"was not verified (no step within the tensions was accepted)"
        )
    elif reached:
        msg = f"target reached: residual {distance:.3g} <= tol {tol:g}"
    elif not sol.success:
        msg = f"target not reached: {why or 'a solve failed'}: {sol.message}"
    elif ok:  # (least squares: a least-squares point)
        msg = f"least-squares optimum: the closest reachable state is {distance:.3g} away"
    else:
        msg = (
            f"target not reached ({why or 'unreachable or no progress'}): the closest state "
            f"found is {distance:.3g} away (positions / L, angles in rad) after {iterations} "
            f"iterations"
        )
    hint = "" if ok or reached or not sol.success else _slack_hint(sol, report["tendons"])
    if hint:
        msg += f" -- {hint}"
    route = "augmented" if report.get("augmented") else "linearisation"
    msg += f"; {iterations} iterations, {solves} solves, {jacobians} linearisations"
    if route == "augmented":
        msg += " (the target solved inside the shooting system first)"
    result = ActuationResult(
        kind=kind,
        route=route,
        target=report["target"],
        tendons=report["tendons"],
        controls=np.array(c, dtype=float),
        residual=np.array(r if r is not None else [], dtype=float),
        distance=distance,
        reached=reached,
        iterations=iterations,
        solves=solves,
        jacobians=jacobians,
        constrained=constrained,
        active=active,
        multipliers=report.get("multipliers"),
        tension_multipliers=None if mus is None else np.array(mus),
        message=msg,
        success=bool(ok),
        status=int(sol.status) if ok else min(int(sol.status), -1),
        nit=int(iterations),
        nfev=int(solves),
    )
    # the run's verdict joins the final solve's before the Solution is handed out (a
    # Solution is read-only from then on)
    verdict: dict = {"actuation": result}
    if not ok:
        last = "" if reached and not sol.success else f" (last solve: {sol.message})"
        verdict.update(success=False, message=f"tr.actuate: {msg}{last}{_in_rod_units(sol)}")
    vars(sol).update(verdict)
    report_failure(sol, strict, sol.message)
    return sol


def _slack_hint(sol, tendons) -> str:
    """Of a target not reached: which actuated tendon ended slack (a tendon only pulls)
    and the tendon opposite it, not actuated, that the target would need."""
    robot = sol.scene.robot
    tension, slack = np.asarray(sol.tension), np.asarray(sol.slack)
    others = [j for j in range(robot.n_tendons) if j not in tendons]
    parts = []
    for i in tendons:
        if tension[i] > 0.0:
            continue
        part = f"tendon {i} went slack (tension 0, slack {slack[i]:.3g} m): a tendon only pulls"
        angle = robot.tendons[i].angle
        opposite = [j for j in others if math.cos(robot.tendons[j].angle - angle) < 0.0]
        if opposite:
            j = min(opposite, key=lambda j: math.cos(robot.tendons[j].angle - angle))
            part += f"; the target would need tendon {j}, opposite it (add it to tendons=)"
        else:
            part += "; the target would need a tendon on the opposite side"
        parts.append(part)
    return "; ".join(parts)
