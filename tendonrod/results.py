"""What a solve reports besides its :class:`~tendonrod.solver.Solution`: the problem the
core actually solved (:class:`Formulation`), the rod state at given arc lengths
(:class:`RodState`, from ``Solution.at``), and how a failed solve is reported
(:class:`ConvergenceWarning`, :class:`ConvergenceError`).

``Solution`` itself lives in :mod:`tendonrod.solver`, next to :func:`~tendonrod.solve`:
``Solution.at`` is a warm solve, so the two cannot be apart without an import cycle.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, fields
from typing import Any, Protocol, runtime_checkable

import numpy as np

from . import _core
from .plausibility import _user_stacklevel, tendon_radius

__all__ = [
    "Result",
    "Formulation",
    "RodState",
    "ConvergenceWarning",
    "ConvergenceError",
    "report_failure",
]


@runtime_checkable
class Result(Protocol):
    """The fields every result type carries, documented once: :class:`~tendonrod.Solution`
    (``solve``, ``Problem.solve``, ``actuate``), :class:`~tendonrod.BatchResult`,
    :class:`~tendonrod.SweepResult`, :class:`~tendonrod.Branch` (``path``),
    :class:`~tendonrod.Jacobian`, :class:`~tendonrod.FitResult` and
    :class:`~tendonrod.actuation.ActuationResult` (``Solution.actuation``) each have them,
    plus their own fields.  For a result over points (``solve_batch``, ``sweep``) each is
    an array with one entry per point.

    Attributes
    ----------
    success : bool
        The verdict, decided where the computation ran (the C core for a solve); a False
        one is reported by the failure rule (:class:`ConvergenceWarning`, or
        :class:`ConvergenceError` with ``strict=True``).
    status : int
        0 ok, > 0 finished with a caveat (``message`` says which), < 0 failed; a solve's
        is the core's (``tendonrod._core.strerror`` names it).
    message : str
        What happened, in words.
    nit : int
        Iterations (-1 where none ran).
    nfev : int
        Residual (function) evaluations (-1 where not counted).

    Examples
    --------
    >>> robot = tr.Robot(tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True), [tr.Tendon(0.01)])
    >>> sol = tr.solve(tr.Scene(robot, displacement=[0.01]))
    >>> isinstance(sol, tr.Result), sol.success, sol.status
    (True, True, 0)
    """

    success: Any
    status: Any
    message: Any
    nit: Any
    nfev: Any


class ConvergenceWarning(RuntimeWarning):
    """Issued when a computation did not succeed: the one failure rule of every entry point
    that can fail (:func:`~tendonrod.solve`, :meth:`~tendonrod.Problem.solve`,
    :func:`~tendonrod.solve_batch`, :func:`~tendonrod.sweep`, :func:`~tendonrod.path`,
    :func:`~tendonrod.jacobian`, :func:`~tendonrod.actuate`, :func:`~tendonrod.fit`): by
    default the result is returned with ``success`` False and this warning is issued;
    with ``strict=True`` :class:`ConvergenceError` is raised instead.  (Only
    :func:`~tendonrod.compliance` always raises: it returns a bare matrix, which has no
    ``success`` to carry the verdict.)

    Examples
    --------
    >>> import warnings
    >>> rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    >>> scene = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=0.2, force=(1.0, 0, 0))])
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     sol = tr.solve(scene, options=tr.Options(max_iter=1, continuation=False))
    >>> sol.success, w[0].category.__name__
    (False, 'ConvergenceWarning')
    """


class ConvergenceError(RuntimeError):
    """Raised by an entry point called with ``strict=True`` when it did not succeed (and
    always by :func:`~tendonrod.compliance`); see :class:`ConvergenceWarning`.

    Attribute ``solution`` holds the unsuccessful result (a
    :class:`~tendonrod.solver.Solution`, or the entry point's own result type).

    Examples
    --------
    >>> rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    >>> scene = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=0.2, force=(1.0, 0, 0))])
    >>> try:
    ...     tr.solve(scene, options=tr.Options(max_iter=1, continuation=False), strict=True)
    ... except tr.ConvergenceError as e:
    ...     print(type(e).__name__)
    ConvergenceError
    """

    def __init__(self, message: str, solution: Any = None):
        super().__init__(message)
        self.solution = solution


def report_failure(result: Any, strict: bool, message: str) -> None:
    """The one failure rule: nothing when ``result.success`` is true (all of it, for an
    array over points); else :class:`ConvergenceError` carrying ``result`` (``strict``) or
    a :class:`ConvergenceWarning` with ``message``, attributed to the user's line."""
    if bool(np.all(result.success)):
        return
    if strict:
        raise ConvergenceError(message, result)
    warnings.warn(message, ConvergenceWarning, stacklevel=_user_stacklevel())


def failed_points(who: str, success: np.ndarray, failures: list) -> str:
    """The message of a run over points some of which failed: how many, and the first."""
    n_bad, n = int(np.size(success) - np.count_nonzero(success)), int(np.size(success))
    first = failures[0] if failures else ()
    return f"{who}: {n_bad} of {n} points did not succeed (the first: {first})"


@dataclass(frozen=True)
class Formulation:
    """What the core actually solved (the scene compiled into the smallest problem).

    Attributes
    ----------
    planar : bool
        Solved as a planar (x-z) problem.
    kirchhoff : bool
        Unshearable, inextensible backbone.
    n_unknowns : int
        Shooting unknowns (planar: 3, spatial: 6, plus one per displacement-controlled tendon).
    n_states : int
        ODE states integrated.
    n_segments : int
        Integration segments (split at point loads, tendon anchors and the ends of
        partial distributed loads).
    n_length_states : int
        Tendon path-length states (one per displacement-controlled tendon).
    n_stretch_terms : int
        Extensible (finite EA) displacement-controlled tendons.
    distributed_load : bool
        A distributed force is integrated.
    tip_only : bool
        Only the tip state was filled.
    integrator : str
        Integrator used.
    steps : int
        Integrator steps over the rod actually used.
    slack_model : str
        Tension/slack parametrisation.
    jacobian_method : str
        How the shooting Jacobian was formed.
    shooting_segments : int
        Shooting segments (1: single shooting).
    shooting_auto : bool
        The segments were chosen by the model (``Options.auto_shooting``) because tensile
        loads make the single-shooting sensitivities grow like exp(``shooting_growth``).
    shooting_growth : float
        int_0^L sqrt(T/EI) ds of the tensile axial loads (L sqrt(T/EI) for a tip load).
    n_partial_loads : int
        Distributed loads over part of the rod (each adds its ends as breakpoints).
    mounted : bool
        The robot's base is not the world's origin and frame: solved in the base frame,
        results carried into the world frame.
    n_sections : int
        Backbone sections compiled (0: a straight uniform rod; a precurved rod has 1, a
        segmented one one per segment, each joint a breakpoint).
    precurved : bool
        Some section has a precurvature (the constitutive law ``m_b = K_bt (u - u*)``).
    n_routed_tendons : int
        Tendons with a helical or piecewise (spline, disk-by-disk) path: their r, r', r''
        enter the right-hand side, their knots are breakpoints, the scene is spatial.
    """

    planar: bool
    kirchhoff: bool
    n_unknowns: int
    n_states: int
    n_segments: int
    n_length_states: int
    n_stretch_terms: int
    distributed_load: bool
    tip_only: bool
    integrator: str
    steps: int
    slack_model: str
    jacobian_method: str = ""
    shooting_segments: int = 1
    shooting_auto: bool = False
    shooting_growth: float = 0.0
    n_partial_loads: int = 0
    mounted: bool = False
    n_sections: int = 0
    precurved: bool = False
    n_routed_tendons: int = 0

    @classmethod
    def from_dict(cls, d: dict) -> Formulation:
        kw: dict[str, Any] = {}
        for f in fields(cls):
            v = d.get(f.name)
            if f.type in ("bool",):
                v = bool(v)
            elif f.type in ("int",):
                v = int(v) if v is not None else (f.default if isinstance(f.default, int) else -1)
            elif f.type in ("float",):
                v = float(v) if v is not None else f.default
            else:
                v = "" if v is None else (v.decode() if isinstance(v, bytes) else str(v))
            kw[f.name] = v
        return cls(**kw)

    def __repr__(self):
        geom = "planar" if self.planar else "spatial"
        rod = "Kirchhoff" if self.kirchhoff else "Cosserat"
        extra = []
        if self.n_length_states:
            extra.append(f"{self.n_length_states} tendon length state(s)")
        if self.n_stretch_terms:
            extra.append(f"{self.n_stretch_terms} stretch term(s)")
        if self.distributed_load:
            extra.append("distributed load")
        if self.n_partial_loads:
            extra.append(f"{self.n_partial_loads} over part of the rod")
        if self.mounted:
            extra.append("mounted base")
        if self.precurved:
            extra.append("precurved")
        if self.n_sections > 1:
            extra.append(f"{self.n_sections} backbone sections")
        if self.n_routed_tendons:
            extra.append(f"{self.n_routed_tendons} routed tendon(s)")
        if self.tip_only:
            extra.append("tip only")
        more = (", " + ", ".join(extra)) if extra else ""
        return (
            f"Formulation({geom} {rod}, {self.n_unknowns} unknowns, {self.n_states} states, "
            f"{self.n_segments} segment(s){more}; {self.integrator} x {self.steps} steps, "
            f"slack model {self.slack_model}, jacobian {self.jacobian_method}"
            + (
                f", {self.shooting_segments} shooting segments"
                + (
                    f" (chosen: tensile loads, growth exp({self.shooting_growth:.3g}))"
                    if self.shooting_auto
                    else ""
                )
                if self.shooting_segments > 1
                else ""
            )
            + ")"
        )


@dataclass(frozen=True)
class RodState:
    """The rod state at given arc length(s), from :meth:`Solution.at`.

    For a scalar ``s``: ``position`` (3,), ``rotation`` (3, 3), ``force`` (3,), ``moment`` (3,);
    for an array of N arc lengths a leading axis of length N is added.

    Attributes
    ----------
    s : float or ndarray (N,)
        Arc length [m].
    position : ndarray
        Backbone position, world frame [m].
    rotation : ndarray
        Body-to-world rotation matrix.
    force : ndarray
        Internal backbone force n, world frame [N].
    moment : ndarray
        Internal backbone moment m, world frame [N m].
    tendon_tension : ndarray
        Each tendon's tension there [N], (ntendon,) (see ``Solution.tendon_tension``).
    """

    s: Any
    position: np.ndarray
    rotation: np.ndarray
    force: np.ndarray
    moment: np.ndarray
    tendon_tension: np.ndarray


def _in_rod_units(sol) -> str:
    """How large the scene's loads and the tendons' tensions are for its rod: the largest
    force in EI/L^2, moment in EI/L, tension in EI/r^2 (r: the tendon's largest radius),
    with those units in SI, so that a failure shows how far out the scene is."""
    scene = sol.scene
    if scene is None:
        return ""
    robot = scene.robot
    L, EI = robot.rod.length, robot.rod.bending_stiffness
    forces = [float(np.linalg.norm(p.force)) for p in scene.point_loads]
    forces += [
        float(np.linalg.norm(d.force)) * ((L if d.end is None else d.end) - d.start)
        for d in scene.partial_loads
    ]
    forces.append(float(np.linalg.norm(scene.distributed_force)) * L)
    moments = [float(np.linalg.norm(p.moment)) for p in scene.point_loads]
    parts = [f"the largest load {max(forces) * L * L / EI:.3g} EI/L^2 (EI/L^2 = {EI / L**2:.3g} N)"]
    if max(moments, default=0.0) > 0.0:
        parts.append(f"moment {max(moments) * L / EI:.3g} EI/L (EI/L = {EI / L:.3g} N m)")
    worst = None
    for i, t in enumerate(robot.tendons):
        r = tendon_radius(t, robot.tendon_end(i))
        tau = float(sol.tension[i]) if i < len(sol.tension) else math.nan
        given = scene.tension[i] if scene.tension is not None else None
        if not math.isfinite(tau) and given is not None:
            tau = float(given)  # the prescribed one
        if r > 0.0 and math.isfinite(tau) and (worst is None or tau * r * r > worst[0]):
            worst = (tau * r * r, i, r)
    if worst is not None:
        x, i, r = worst
        parts.append(
            f"tension {x / EI:.3g} EI/r^2 (tendon {i}, r = {r:.3g} m: EI/r^2 = {EI / r**2:.3g} N)"
        )
    return "; in the rod's units: " + ", ".join(parts)


def _report(sol, strict: bool, who: str) -> None:
    """A failed solve is never silent: ConvergenceError (strict) or ConvergenceWarning.
    A success the core flags with a caveat its message explains (only as accurate as its
    truncation error; held by friction only, its frictionless twin unstable; converged to
    its round-off floor above tol) warns too."""
    if sol.success:
        if sol.status in (
            _core.STATUS_TRUNCATION,
            _core.STATUS_FRICTION_HELD,
            _core.STATUS_ROUNDOFF,
        ):
            warnings.warn(
                f"{who}: {sol.message}", ConvergenceWarning, stacklevel=_user_stacklevel()
            )
        return
    msg = (
        f"{who} did not converge: {sol.message} (status {sol.status}, "
        f"nit {sol.nit}, nfev {sol.nfev}, residual {sol.residual_norm:.3g})"
        f"{_in_rod_units(sol)}"
    )
    report_failure(sol, strict, msg)
