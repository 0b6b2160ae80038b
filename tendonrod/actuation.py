"""Inverse actuation: :func:`actuate`, the tendon controls that bring the tip to a target
under the scene's loads.

A square target whose controls are all displacements (a planar tip angle, a spatial tip
direction or position, one actuated tendon per component) is first solved inside the
shooting system: its residual takes the place of those tendons' length constraints and
one Newton solve finds the controls and the equilibrium together
(``_core.Problem.set_target``, ``csrc/tr_target.c``).  Everything else, and whatever that
solve leaves (it needs the actuated tendons taut and a well-conditioned target), goes by
steps on the linearisation: every iterate an equilibrium the solver converged to (a warm
:class:`~tendonrod.Problem` solve), every step from the linearisation of that equilibrium
(:meth:`Problem.jacobian <tendonrod.Problem.jacobian>`, forward differences): Newton's
method on the target, damped by a trust region (Levenberg-Marquardt) where the target has
at least as many components as there are controls, a sequential quadratic program where
it has fewer.  ``bench/results/jacobian_actuate.md`` measures both
(``bench/jacobian_actuate.py``).

Units: a target's residual is dimensionless, positions divided by the rod length L and
angles in radians; controls are measured in the solver's scales, a displacement q by the
largest tendon offset r and a tension tau by EI / (r L) (either turns the tip by about a
radian).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass

import numpy as np

from ._actuation_step import Iteration
from ._actuation_target import Target
from ._interrupt import current_token
from .compiled import is_planar, value_vector
from .model import Scene
from .options import _check_options, _replace
from .problem import Problem
from .results import ConvergenceError, ConvergenceWarning
from .solution import Solution

__all__ = ["actuate", "ActuationResult"]


@dataclass(frozen=True, eq=False)
class ActuationResult:
    """What :func:`actuate` did (``Solution.actuation``).

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
        except (TypeError, ValueError):
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
    values = np.array([scene.displacement[i] if disp[i] else scene.tension[i] for i in idx])
    is_tension = np.array([not disp[i] for i in idx])
    return idx, values, scale, is_tension, q_scale, tau_scale


def _with_controls(scene: Scene, idx, c) -> Scene:
    disp, ten = list(scene.displacement), list(scene.tension)
    for i, v in zip(idx, c):
        if disp[i] is not None:
            disp[i] = float(v)
        else:
            ten[i] = max(float(v), 0.0)  # the bounds hold it >= 0 up to round-off
    return dataclasses.replace(scene, displacement=disp, tension=ten)


# --------------------------------------------------------------------------- iteration
class _Run:
    """The solves and linearisations of one actuation, counted."""

    def __init__(self, scene, options, target, idx, c0, scale, q_scale, tau_scale):
        self.scene, self.options, self.target = scene, options, target
        self.idx, self.c0, self.scale = idx, c0, scale
        self.k = tau_scale / q_scale
        # the iterates are not judged for stability (a verdict per iterate would cost more
        # than the iterate); the state returned is, by a solve with the caller's options
        self.prob = Problem(scene, _replace(options, accept_unstable=True))
        self.solves = self.jacobians = 0
        # the scene's per-call values, whose control entries the iterates change
        self.values = np.array(value_vector(scene))
        self.tension_controls = np.array([q is None for q in scene.displacement])[idx]
        self.jac = None  # the last linearisation's shooting Jacobian, for the next solves
        self.polish = False  # iterate solves take a Newton step past convergence
        self.solved = {}  # the last few successful solutions by their value vectors

    def solve(self, c, guess=None, state=None):
        """(Solution, r, D) at controls c: a warm solve from the last success (the first
        one from ``guess``) with the last linearisation's shooting Jacobian where there is
        one, or from the solution at c when c was solved before; from ``state`` (the
        base-frame guess vector [n(0), m(0), tension, slack], e.g. the last success with a
        released tendon's slack) with the last linearisation's Jacobian when given.

        Iterates set their controls in C only: their Solutions carry the run's scene
        (the same robot, loads and structure), and :meth:`scene_at` makes the scene of the
        controls of the state returned."""
        self.solves += 1
        # iterates are neither reported nor checked for plausibility: the state returned
        # is, by the final solve with the caller's options
        if guess is not None or self.prob.last_solution is None:
            sol = self.prob._solve_quiet(self.scene_at(c), guess)
        else:
            # only the controls differ from the scene set: their values, as _with_controls
            # sets them, straight into the problem
            values = self.values.copy()
            values[self.idx] = np.where(self.tension_controls, np.maximum(c, 0.0), c)
            # back at controls solved before (an iterate the iteration returns to): from
            # that solution, one evaluation
            start = None if state is not None else self.solved.get(values.tobytes())
            sol = self._solve_values(self.scene, values, start, state)
            if sol.success:
                if len(self.solved) >= 8:
                    self.solved.pop(next(iter(self.solved)))
                self.solved[values.tobytes()] = sol
        if not sol.success:
            return sol, None, None
        r, D = self.target.residual(sol)
        return sol, r, D

    def verified(self, sol):
        """The step verification record (steps, estimate, unknowns, values) of a solution
        of this run, which a solve from it starts with (None: there is none)."""
        raw = sol.raw
        xv = raw.get("verified_unknowns")
        if xv is None or self.prob.options.steps != 0:
            return None
        steps, est = int(raw["formulation"]["steps"]), float(raw["verified_estimate"])
        return steps, est, xv, raw.get("verified_values")

    def scene_at(self, c) -> Scene:
        """The scene with the actuated tendons' controls c (the scene itself at its own)."""
        if np.array_equal(c, self.c0):
            return self.scene
        return _with_controls(self.scene, self.idx, c)

    def _solve_values(self, scene, values, start, state=None):
        """The Solution of ``scene``, whose per-call values ``values`` (the layout of
        ``compiled.value_vector``) differ from the scene set in C only in the controls, so
        that neither is compared: from ``start`` (a solution of this problem) with its
        Jacobian, or from the last success with the last linearisation's Jacobian (from
        the guess vector ``state`` instead of that success's state, when given), else
        warm; neither reported nor checked, as :meth:`Problem._solve_quiet`.  Near the
        target (``self.polish``, set by the iteration) each takes one Newton step past
        convergence: a control change that moves the shooting residual by less than its
        tol would otherwise leave the state, and the target residual, where they were
        (steps there stall at tol)."""
        prob = self.prob
        prob._c.set_value_vector(values)
        prob._current = scene
        jac = self.jac if start is None else start.jacobian
        start = prob._last if start is None else start
        if jac is None or start is None:
            raw = prob._c.solve(warm=True, cancel=current_token(), record=False, polish=self.polish)
        else:
            raw = prob._c.solve(
                guess=start.raw["base_state"] if state is None else state,
                jacobian=jac,
                verified=self.verified(start),
                cancel=current_token(),
                record=False,
                polish=self.polish,
            )
        sol = Solution(raw, scene, prob.options)
        if sol.success:
            prob._last = sol
        return sol

    def linearize(self, sol, D, side=None):
        """(A (m, n), T (nt, n), side (nt,)): at the solution ``sol``, the target
        residual's and the tensions' derivatives by the controls, in the scaled units
        (columns times the control scales), and the side of its switch each tendon's
        derivatives are from (``side``: the sides asked for, as in
        :meth:`Problem.jacobian`).  Forward differences; D and the core's tip rows are
        both in the base frame."""
        self.jacobians += 1
        raw, here = self.prob._tip_rates(sol, side)
        nt = len(raw["at_switch"])
        switch = np.asarray(raw["at_switch"], dtype=int)
        # its shooting Jacobian starts the next solves (fresher than the solver's own),
        # unless a tendon sits at its switch: the map is kinked there, and the side taken
        # may not be the one those solves land on
        self.jac = raw["jacobian"] if here and not np.any(switch) else None
        A = D @ raw["pose"][:nt, 0, :].T[:, self.idx]
        # the signed tension psi = tension - k slack (see _Run.psi): continuous and
        # increasing through the switch, so a slack tendon's rates are not lost
        T = (raw["tension"][:nt].T - self.k * raw["slack"][:nt].T)[:, self.idx]
        return A * self.scale, T * self.scale, switch

    def psi(self, sol):
        """The signed tension psi = tension - k slack (nt,) [N] of a solution, with k =
        EI / (r^2 L) [N/m] (the solver's tension scale per its length scale): the tension
        of a taut tendon, minus its slack turned into a tension of a slack one.  A floor on
        psi keeps a tendon taut; the linearisation sees a slack tendon come back."""
        return sol.tension - self.k * sol.slack


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
) -> Solution:
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
        ``success`` is the outer verdict: the target reached (to ``tol``), or, with fewer
        controls than components, the least-squares optimum found; an unreachable target
        gives ``success=False`` with the closest reachable state found and its distance,
        never an exception.  ``status`` stays the core's status of the final solve.

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
        if not (math.isfinite(v) and v >= lo) or (name == "tol" and not 0.0 < v < 1.0):
            raise ValueError(f"{name} must be finite and >= 0 (tol in (0, 1)), got {v!r}")
    if isinstance(max_iter, bool) or not isinstance(max_iter, (int, np.integer)) or max_iter < 1:
        raise ValueError(f"max_iter must be an int >= 1, got {max_iter!r}")
    if method not in ("auto", "linearisation"):
        raise ValueError(f"method must be 'auto' or 'linearisation', got {method!r}")
    planar = is_planar(scene) and not options.force_spatial
    target = Target(scene, planar, tip_angle, tip_direction, tip_position, tip_pose)
    idx, c0, scale, is_tension, q_scale, tau_scale = _control_set(scene, tendons)
    n, m = len(idx), target.m
    kind = "square" if n == m else ("minimum-change" if n > m else "least-squares")
    run = _Run(scene, options, target, idx, c0, scale, q_scale, tau_scale)
    sol, r, D = run.solve(c0, guess)
    report = dict(kind=kind, target=target.given, tendons=tuple(idx), run=run)
    if r is None:
        return _finish(
            sol,
            c0,
            None,
            report,
            (),
            (),
            None,
            None,
            0,
            False,
            tol,
            strict,
            "the scene did not solve at its own controls",
        )
    nt = scene.robot.n_tendons
    disp = scene.displacement_controlled()
    # lower bounds on the tensions: min_tension for the tendons taut in the scene (minimum
    # change), none for the others
    floor0 = np.full(nt, -np.inf)
    if kind == "minimum-change":
        for i in range(nt):
            if sol.tension[i] > 0.0 and (disp[i] or i in idx):
                floor0[i] = float(min_tension)
    c = c0.copy()
    report["route"] = "linearisation"
    if method == "auto" and kind == "square" and np.abs(r).max() > tol:
        # the target inside the shooting system first; the iteration polishes or takes over
        aug = _augmented(run, target, idx, disp, planar)
        if aug is not None:
            sol, r, D, c = aug
            report["route"] = "augmented"
    # slack displacement controls drawn to their switch, where pulling them acts (the
    # least change pays those it does not need out again at the end)
    sol, r, D, c = _take_up_slack(run, sol, r, D, c)
    it = Iteration(run, sol, r, D, c, c0, scale, is_tension, tau_scale, floor0, tol)
    out = it.iterate(max_iter, report)
    return _finish(*out[:-1], strict, out[-1])


# The core's kinds of tip target (tr_target_kind).
_TARGET_KIND = {"tip_angle": 1, "tip_direction": 2, "tip_position": 3}


def _augmented(run, target, idx, disp, planar):
    """The target solved inside the shooting system (``_core.Problem.set_target``): its
    residual takes the place of the length constraints of the actuated tendons, one per
    component, and one Newton solve, warm from the scene's equilibrium, finds the
    controls and the equilibrium together.  For as many displacement controls as target
    components, a planar tip angle or a spatial direction or position.  (sol, r, D, c) at
    the controls found (a forward warm solve of them), or None where it does not apply or
    does not converge to taut actuated tendons (a slack one would leave the system
    singular), for the iteration to take over."""
    kind = _TARGET_KIND.get(target.name)
    if (
        kind is None
        or (kind == 1) != planar
        or len(idx) != target.m
        or not all(disp[i] for i in idx)
    ):
        return None
    values = [target.theta] if kind == 1 else (target.t if kind == 2 else target.p)
    core = run.prob._c
    try:
        core.set_target(kind, np.asarray(values, dtype=float), np.asarray(idx, dtype=float))
    except ValueError:
        return None
    run.solves += 1
    try:
        raw = core.solve(warm=True, record=False, cancel=current_token())
    finally:
        core.set_target(0, np.zeros(1), np.zeros(0))
    q = np.asarray(raw["displacement"], dtype=float)[idx]
    taut = np.asarray(raw["tension"], dtype=float)[idx] > 0.0
    if not (raw["success"] and np.all(np.isfinite(q)) and np.all(taut)):
        return None
    sol, r, D = run.solve(q)
    return None if r is None else (sol, r, D, q)


def _take_up_slack(run, sol, r, D, c):
    """The slack displacement controls moved to their taut/slack switch (q + slack), a
    hair past it (1e-12 of the offset scale) so that they sit on its taut side, whose
    linearisation sees them act."""
    disp = run.scene.displacement_controlled()
    cn = c.copy()
    for j, i in enumerate(run.idx):
        if disp[i] and sol.slack[i] > 0.0:
            cn[j] += sol.slack[i] + 1e-12 * run.scale[j]
    if np.all(cn == c):
        return sol, r, D, c
    s2, r2, D2 = run.solve(cn)
    if r2 is None:
        s2, r2, D2 = run.solve(c)  # keep c (and the Problem's warm state at it)
        return s2, r2, D2, c
    return s2, r2, D2, cn


def _judged(run, sol, r):
    """The final state solved again, warm from itself, judged for stability (the
    iterates are not: ``Problem.solve(judge=True)`` in the run's workspace) and checked
    for plausibility as any solve with the caller's options: (that solution, its target
    residual), or (the failed solve, r) when the equilibrium reaching the target is
    unstable (its message says so)."""
    run.solves += 1
    prob = run.prob
    prob._set(sol.scene)  # its controls (a trial since may have set others)
    raw = prob._c.solve(
        guess=sol.raw["base_state"],
        jacobian=sol.jacobian,
        verified=run.verified(sol),
        cancel=current_token(),
        record=False,
        judge=True,
    )
    final = Solution(raw, sol.scene, run.options)
    prob._plausible.check(final, "tendonrod.actuate", once=False)
    if not final.success:
        return final, r
    return final, run.target.residual(final)[0]


def _finish(
    sol, c, r, report, constrained, active, lam, mus, iterations, converged, tol, strict, why
):
    """The returned Solution: the final equilibrium with ``actuation`` and the verdict."""
    run, kind = report["run"], report["kind"]
    if sol.scene is run.scene:  # an iterate's: the scene of its controls
        sol.scene = run.scene_at(c)
    if sol.success and r is not None and not run.options.accept_unstable:
        sol, r = _judged(run, sol, r)
    distance = float(np.abs(r).max()) if r is not None else math.inf
    reached = distance <= tol
    optimal = report.get("optimal", False)
    ok = sol.success and (
        (reached and optimal) or (kind == "least-squares" and converged and not why)
    )
    if reached and not optimal:
        msg = (
            f"target reached (residual {distance:.3g} <= tol {tol:g}), but the least change "
            f"was not verified (no step within the tensions was accepted)"
        )
    elif reached:
        msg = f"target reached: residual {distance:.3g} <= tol {tol:g}"
    elif not sol.success:
        msg = f"target not reached: {why or 'a solve failed'}: {sol.message}"
    elif kind == "least-squares" and converged and not why:
        msg = f"least-squares optimum: the closest reachable state is {distance:.3g} away"
    else:
        msg = (
            f"target not reached ({why or 'unreachable or no progress'}): the closest state "
            f"found is {distance:.3g} away (positions / L, angles in rad) after {iterations} "
            f"iterations"
        )
    route = report.get("route", "linearisation")
    msg += f"; {iterations} iterations, {run.solves} solves, {run.jacobians} linearisations"
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
        solves=run.solves,
        jacobians=run.jacobians,
        constrained=tuple(constrained),
        active=tuple(active),
        multipliers=None if lam is None else np.array(lam),
        tension_multipliers=None if mus is None else np.array(mus),
        message=msg,
    )
    sol.actuation = result
    if not ok:
        sol.success = False
        sol.message = f"tr.actuate: {msg} (last solve: {sol.message})"
        if strict:
            raise ConvergenceError(sol.message, sol)
        warnings.warn(sol.message, ConvergenceWarning, stacklevel=3)
    return sol
