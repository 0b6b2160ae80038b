"""Load paths (:func:`tendonrod.path`): the equilibrium branch (:class:`Branch`) of a scene
as one scalar parameter varies.

>>> p = tr.path(scene, "loads[0].force[2]", (0.0, -3.0))      # doctest: +SKIP
>>> p.special_points                                           # doctest: +SKIP
[SpecialPoint(kind='bifurcation', value=-0.79..., index=15, ...)]

:func:`path` follows the branch through the scene's equilibrium at the start of the span
by pseudo-arclength continuation (``csrc/tr_path.c``), through limit points where the
parameter turns back, so that past a fold one parameter value carries every equilibrium
met on the branch.  Limit points (the parameter is extremal along the branch) and simple
bifurcation points (another branch crosses) are located on the way, each to about 1e-10
relative; with ``switch=+1`` or ``-1`` the path turns onto the crossing branch at the
first bifurcation.  Every point is converged, verified (step doubling, like any solve)
and judged (the stability verdict and margin of :class:`~tendonrod.Solution`).
"""

from __future__ import annotations

import dataclasses
import math
import numbers

import numpy as np

from . import _core
from ._interrupt import current_token
from ._scene_paths import get_path, set_path
from .compiled import _with_dloads, pack_scene, structure_difference, value_vector
from .linearization import PARAM_KIND, design_parameter
from .model import Scene
from .options import Options, _check_options
from .results import report_failure

__all__ = ["path", "Branch", "SpecialPoint"]

# the kind of a value-vector entry in _core.path (TR_PATH_SLOT)
_SLOT = -1
_KINDS = {0: "regular", 1: "limit", 2: "bifurcation"}
_DESIGN = ("EI", "GJ", "EA", "GA", "tendon_EA")  # kinds tr_path can vary (no rest lengths)


@dataclasses.dataclass(frozen=True)
class SpecialPoint:
    """A limit or bifurcation point of a :class:`Branch`.

    Attributes
    ----------
    kind : str
        ``"limit"`` (the parameter is extremal along the branch: a fold, where a load path
        snaps) or ``"bifurcation"`` (another branch crosses: e.g. Euler buckling).
    value : float
        The parameter's value there [the parameter's unit].
    index : int
        Its row in the path's arrays.
    tip_position : ndarray (3,)
        Tip position there, world frame [m].
    margin : float
        The stability margin there [EI/L] (zero in exact arithmetic).

    Examples
    --------
    An Euler column under a growing axial load meets its bifurcation at
    P_E = pi^2 EI / (4 L^2):

    >>> rod = tr.Rod(length=0.25, diameter=1.2e-3, E=60e9, G=23e9, kirchhoff=True)
    >>> P_E = np.pi**2 * rod.bending_stiffness / (4 * rod.length**2)
    >>> scene = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=0.25, force=(0, 0, 0))])
    >>> p = tr.path(scene, "loads[0].force[2]", (0.0, -3.0 * P_E))
    >>> sp = p.special_points[0]
    >>> sp.kind, round(-sp.value / P_E, 3)
    ('bifurcation', 1.0)
    """

    kind: str
    value: float
    index: int
    tip_position: np.ndarray
    margin: float


@dataclasses.dataclass(frozen=True, eq=False)
class Branch:
    """The branch of a scene's equilibria along one parameter, point by point.

    A :class:`~tendonrod.Result`: ``success``, ``status``, ``message``, ``nit``, ``nfev``
    mean the same on every result type.

    Row ``i`` of every array is the ``i``-th point along the branch (special points where
    they lie on it).  Past a limit point the parameter runs back, so one value can appear
    on several rows, one per equilibrium.

    Attributes
    ----------
    scene : Scene
        The scene at the start of the span.
    parameter : str
        The path (sweep syntax) of the parameter varied, e.g. ``"loads[0].force[2]"``.
    span : tuple (2,)
        ``(start, end)`` of the parameter [its unit].
    value : ndarray (n,)
        The parameter at each point [its unit].
    tip_position : ndarray (n, 3)
        Tip position, world frame [m].
    tip_rotation : ndarray (n, 3, 3)
        Tip rotation, body-to-world.
    tip_force, tip_moment : ndarray (n, 3)
        Internal force [N] and moment [N m] at the tip, world frame.
    tension : ndarray (n, ntendon)
        Tendon tensions [N].
    stable : ndarray (n,) of object
        True (stable), False (unstable) or None (not decided: critical or neutral), the
        verdict of :attr:`Solution.stable`.
    margin : ndarray (n,)
        The stability margin [EI/L] (:attr:`Solution.stability`; NaN: not computed).
    kind : ndarray (n,) of str
        ``"regular"``, ``"limit"`` or ``"bifurcation"``.
    branch : ndarray (n,) of int
        0 on the branch the path started on, 1 after a switch at a bifurcation.
    steps : ndarray (n,) of int
        The verified step count of each point.
    residual : ndarray (n,)
        Scaled residual max-norm of each point.
    truncation : ndarray (n,)
        Step-doubling truncation estimate of each point (scaled; NaN: carried or fixed).
    special_points : list of SpecialPoint
        The limit and bifurcation points in path order.
    success : bool
        True when the path reached the end of the span.
    status : int
        0, or the core status of the stop (:attr:`message` says why).
    message : str
        What happened: where the path ended and why.
    nit : int
        Continuation steps taken: the points of the path.
    nfev : int
        Residual evaluations: -1, not counted (the core's path does not report them).

    Examples
    --------
    >>> rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    >>> robot = tr.Robot(rod, [tr.Tendon(offset=0.01, angle=0.0)])
    >>> p = tr.path(tr.Scene(robot, displacement=[0.0]), "displacement[0]", (0.0, 0.01))
    >>> p.value[[0, -1]], all(p.stable), p.kind[0]
    (array([0.  , 0.01]), True, 'regular')
    """

    scene: Scene
    parameter: str
    span: tuple
    value: np.ndarray
    tip_position: np.ndarray
    tip_rotation: np.ndarray
    tip_force: np.ndarray
    tip_moment: np.ndarray
    tension: np.ndarray
    stable: np.ndarray
    margin: np.ndarray
    kind: np.ndarray
    branch: np.ndarray
    steps: np.ndarray
    residual: np.ndarray
    truncation: np.ndarray
    special_points: list
    success: bool
    status: int
    message: str
    unknowns: np.ndarray | None = dataclasses.field(repr=False, default=None)
    nit: int = 0
    nfev: int = -1

    def __len__(self) -> int:
        return int(self.value.shape[0])

    def __repr__(self) -> str:
        sp = ", ".join(f"{p.kind} at {p.value:.6g}" for p in self.special_points) or "none"
        return (
            f"Branch({self.parameter!r}, {len(self)} points, span {self.span}, "
            f"special points: {sp}, success={self.success})"
        )

    def scene_at(self, i: int) -> Scene:
        """The scene of point ``i``: the start scene with the parameter set to ``value[i]``."""
        return set_path(self.scene, self.parameter, float(self.value[i]))


def _scalar(v, name: str) -> float:
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, (numbers.Real, np.floating)):
        raise ValueError(f"{name} must be a real number, got {v!r}")
    try:
        v = float(v)
    except OverflowError:  # an int beyond a double, like 10**400
        raise ValueError(f"{name} must be finite, got {v!r}") from None
    if not math.isfinite(v):
        raise ValueError(f"{name} must be finite, got {v!r}")
    return v


def _span(span) -> tuple:
    try:
        p0, p1 = span
    except (TypeError, ValueError):
        raise ValueError(f"span must be (start, end), got {span!r}") from None
    p0, p1 = _scalar(p0, "span[0]"), _scalar(p1, "span[1]")
    if p0 == p1:
        raise ValueError(f"span = {span!r}: start and end must differ")
    return p0, p1


def _parameter(scene: Scene, parameter, p0: float, p1: float):
    """(kind, index, start scene) of ``parameter`` for _core.path; ValueError naming it
    when it is not one scalar value of a fixed structure."""
    if not isinstance(parameter, str):
        raise ValueError(
            f"parameter must be a path string like 'loads[0].force[2]', got {parameter!r}"
        )
    current = get_path(scene, parameter)
    if isinstance(current, (bool, np.bool_)) or not isinstance(
        current, (numbers.Real, np.floating, type(None))
    ):
        raise ValueError(
            f"parameter {parameter!r} is {current!r}: tr.path varies one scalar value "
            "(index into a vector, e.g. 'loads[0].force[2]')"
        )
    s0 = set_path(scene, parameter, p0)
    s1 = set_path(scene, parameter, p1)
    diff = structure_difference(s0, s1)
    if diff is None:
        v0, v1 = value_vector(s0), value_vector(s1)
        moved = np.flatnonzero(v0 != v1)
        pre0 = pack_scene(s0)[1][:, 7]
        pre1 = pack_scene(s1)[1][:, 7]
        mid = value_vector(set_path(scene, parameter, 0.5 * (p0 + p1)))
        if (
            moved.size == 1
            and np.array_equal(pre0, pre1)
            and v0[moved[0]] == p0
            and v1[moved[0]] == p1
            and mid[moved[0]] == 0.5 * (p0 + p1)
        ):
            return _SLOT, int(moved[0]), s0
        what = (
            "changes nothing the solver sees"
            if moved.size == 0 and np.array_equal(pre0, pre1)
            else f"changes {moved.size} value(s) of the compiled problem, not one, or a "
            "pretension, or not in proportion"
        )
        raise ValueError(
            f"parameter {parameter!r}: varying it {what}; tr.path varies exactly one "
            "actuation, load or distributed-load component (or a rigidity: "
            "'robot.tendons[i].EA')"
        )
    try:
        _, kind, index = design_parameter(scene, parameter)
    except ValueError:
        kind = None
    if kind is None or kind not in {PARAM_KIND[k] for k in _DESIGN if k in PARAM_KIND}:
        raise ValueError(
            f"parameter {parameter!r} changes the problem's structure ({diff}); tr.path "
            "varies one scalar value of a fixed structure: an actuation value, a load or "
            "distributed-load component, or a rigidity ('robot.tendons[i].EA')"
        )
    return kind, index, s0


def path(
    scene: Scene,
    parameter: str,
    span,
    *,
    options: Options | None = None,
    step: float = 0.05,
    max_step: float = 0.2,
    max_points: int = 400,
    switch: int = 0,
    strict: bool = False,
) -> Branch:
    """The equilibrium branch of ``scene`` as ``parameter`` runs over ``span``.

    Parameters
    ----------
    scene : Scene
        The scene; its value of the parameter is replaced by ``span[0]``.
    parameter : str
        What varies, in the sweep's path syntax: ``"loads[0].force[2]"``,
        ``"displacement[0]"``, ``"tension[1]"``, ``"robot.tendons[1].EA"``.  One scalar
        value of a fixed structure; anything else raises ``ValueError`` saying so.
    span : tuple of 2 floats
        ``(start, end)``, the parameter's range [its unit]; the path starts with a solve
        at ``start``.
    options : Options, optional
        Numerical options of every point (``tol``, ``steps``, budget per point).
    step, max_step : float
        First and largest step along the path, measured in the scaled unknowns and the
        parameter's fraction of the span (defaults 0.05 and 0.2).
    max_points : int
        Capacity of the path (default 400); a full path stops with ``success=False``.
    switch : 0, +1 or -1
        0: follow the branch through bifurcations.  +1 / -1: at the first bifurcation,
        turn onto the crossing branch (the two signs give its two sides).
    strict : bool
        Raise :class:`~tendonrod.ConvergenceError` (its ``solution`` the result) instead of
        a :class:`~tendonrod.ConvergenceWarning` when the path stops before the end of
        the span.

    Returns
    -------
    Branch
        The points; ``success`` False with the reason in ``message`` (and the failure
        rule: a warning, or the error with ``strict``) when the path stopped before the
        end of the span (the points up to there are kept).

    Examples
    --------
    Follow the bent robot as its tendon is pulled further:

    >>> rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    >>> robot = tr.Robot(rod, [tr.Tendon(offset=0.01, angle=0.0)])
    >>> p = tr.path(tr.Scene(robot, displacement=[0.0]), "displacement[0]", (0.0, 0.0157))
    >>> p.success, len(p.special_points), round(float(p.tension[-1, 0]), 3)
    (True, 0, 3.267)
    """
    if not isinstance(scene, Scene):
        raise ValueError(f"scene must be a tendonrod.Scene, got {scene!r}")
    if scene.robot.mounted:
        raise ValueError("tr.path: a mounted robot is not supported (give the unmounted robot)")
    options = _check_options(options)
    p0, p1 = _span(span)
    step = _scalar(step, "step")
    max_step = _scalar(max_step, "max_step")
    if not (0.0 < step <= max_step):
        raise ValueError(f"step = {step!r}, max_step = {max_step!r}: need 0 < step <= max_step")
    if isinstance(max_points, bool) or not isinstance(max_points, numbers.Integral):
        raise ValueError(f"max_points must be an int, got {max_points!r}")
    if abs(max_points) >= 2**62:  # beyond the core's C long: far too many either way
        raise ValueError(f"max_points is far too large, got {max_points!r}")
    if switch not in (0, 1, -1) or isinstance(switch, bool):
        raise ValueError(f"switch must be 0, +1 or -1, got {switch!r}")
    kind, index, s0 = _parameter(scene, parameter, p0, p1)
    rod, tendons, loads, dist = pack_scene(s0)
    kw = _with_dloads(dict(options._raw, nodes=2), s0)
    raw = _core.path(
        rod,
        tendons,
        loads,
        dist,
        kind=kind,
        index=index,
        p0=p0,
        p1=p1,
        ds0=step,
        ds_max=max_step,
        max_points=int(max_points),
        side=int(switch),
        cancel=current_token(),
        **kw,
    )
    res = _path_of(s0, parameter, (p0, p1), raw)
    report_failure(res, strict, f"tendonrod.path stopped early: {res.message}")
    return res


def _path_of(scene: Scene, parameter: str, span: tuple, raw: dict) -> Branch:
    tip = raw["tip"]
    stable = np.array([None if s < 0 else bool(s) for s in raw["stable"]], dtype=object)
    kinds = np.array([_KINDS[int(k)] for k in raw["kind"]], dtype=object)
    special = [
        SpecialPoint(
            kind=kinds[i],
            value=float(raw["par"][i]),
            index=int(i),
            tip_position=tip[i, :3].copy(),
            margin=float(raw["margin"][i]),
        )
        for i in np.flatnonzero(raw["kind"] != 0)
    ]
    return Branch(
        scene=scene,
        parameter=parameter,
        span=span,
        value=raw["par"],
        tip_position=tip[:, :3],
        tip_rotation=tip[:, 3:12].reshape(-1, 3, 3),
        tip_force=tip[:, 12:15],
        tip_moment=tip[:, 15:18],
        tension=raw["tension"],
        stable=stable,
        margin=raw["margin"],
        kind=kinds,
        branch=raw["branch"].astype(int),
        steps=raw["steps"].astype(int),
        residual=raw["residual"],
        truncation=raw["truncation"],
        special_points=special,
        success=raw["status"] == 0,
        status=int(raw["status"]),
        message=raw["message"],
        unknowns=raw["unknowns"],
        nit=int(raw["par"].shape[0]),
    )


def __getattr__(name: str):
    if name == "Path":  # the result's name before 0.2
        from ._deprecation import deprecated

        deprecated("tendonrod.continuation.Path", "tendonrod.Branch")
        return Branch
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
