"""Batch solves: many scenes of one robot design in one call.

>>> res = tr.solve_batch(scene, forces=F)          # F: (n, nloads, 3)   # doctest: +SKIP
>>> res.tip_position, res.success, res.message                            # doctest: +SKIP

Every point shares the scene's robot (rod, tendon routing), its control modes
(which tendons are displacement- and which tension-controlled) and its load
positions; what varies per point are values only: tendon displacements or
tensions, point-load forces and moments, the distributed force.  The points are
solved in C (``csrc/tr_batch.c``) with the GIL released, in contiguous chunks of
``chunksize`` points; within a chunk each point is warm-started from the previous
converged one (its unknowns and final Jacobian, as ``tr.solve(scene,
guess=previous)`` does), each chunk starts cold.  Results depend on the order and
the chunking only, never on the number of threads (bitwise).  Only tip quantities
are returned.
"""

from __future__ import annotations

import concurrent.futures as cf
import dataclasses
from dataclasses import dataclass

import numpy as np

from . import _core, plausibility
from ._deprecation import renamed_keywords
from ._interrupt import current_token, new_token
from ._plausible import batch_findings
from .compiled import _TD, _with_dloads, is_planar, pack_scene
from .model import Scene
from .mounting import base_pose, points_out, rotations_out, vectors_in
from .options import Options, _check_options
from .results import failed_points, report_failure

__all__ = ["solve_batch", "BatchResult", "DEFAULT_CHUNKSIZE"]

DEFAULT_CHUNKSIZE = 1000
"""Points per warm-started chunk when ``chunksize`` is not given (fixed, so that results
do not depend on the machine or the number of threads)."""


@dataclass(frozen=True, repr=False)
class BatchResult:
    """Tip quantities of ``n`` solved points (arrays over the points, in input order).

    A :class:`~tendonrod.Result`: ``success``, ``status``, ``message``, ``nit``, ``nfev``
    mean the same on every result type.

    Attributes
    ----------
    tip_position : (n, 3) world frame [m]
    tip_rotation : (n, 3, 3) tip body-to-world rotation
    tension, slack, displacement : (n, ntendon) [N], [m], [m] (actuator displacement
        consistent with the solution, as ``Solution.displacement``)
    taut : (n, ntendon) bool, the tendons that carry tension (as ``Solution.taut``)
    status : (n,) int, the core's status (0 ok, > 0 converged with a caveat, < 0 failed;
        ``tendonrod._core.strerror``)
    success : (n,) bool, the core's verdict per point (as ``Solution.success``: status
        >= 0 except 3, an equilibrium found off the load path that a second formulation
        did not confirm, and 5, an unstable one: see ``message``)
    stable : (n,) object array of True / False / None, the stability verdict per point
        (as ``Solution.stable``; None where not judged: no solution, a margin within the
        test's accuracy, a world-fixed moment, or ``Options(accept_unstable=True)``)
    message : (n,) object array of str, the solver's message per point
    nit, nfev : (n,) int, iterations and residual evaluations per point
    residual_norm : (n,) final scaled residual max-norm
    cold : (n,) bool, the point was solved without a warm start
    formulation : dict, what was solved (planar, kirchhoff, n_unknowns, n_states)
    chunksize : int, points per warm-started chunk
    plausibility : (n,) object array, each point's findings (a tuple of
        :class:`~tendonrod.plausibility.Finding`, as ``Solution.plausibility``)

    Examples
    --------
    >>> rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    >>> robot = tr.Robot(rod, [tr.Tendon(offset=0.01, angle=0.0)])
    >>> res = tr.solve_batch(tr.Scene(robot, displacement=[0.0]), displacement=[[0.005], [0.01]])
    >>> res.tip_position.shape, res.success.tolist(), res.failures()
    ((2, 3), [True, True], [])
    """

    tip_position: np.ndarray
    tip_rotation: np.ndarray
    tension: np.ndarray
    slack: np.ndarray
    displacement: np.ndarray
    status: np.ndarray
    message: np.ndarray
    nit: np.ndarray
    nfev: np.ndarray
    residual_norm: np.ndarray
    cold: np.ndarray
    success: np.ndarray
    stable: np.ndarray
    formulation: dict
    chunksize: int
    plausibility: np.ndarray | None = None

    def __len__(self) -> int:
        return int(self.status.shape[0])

    @property
    def taut(self) -> np.ndarray:
        """(n, ntendon) bool: the tendons that carry tension at each point (``tension > 0``,
        as ``Solution.taut``)."""
        return np.asarray(self.tension) > 0.0

    def __repr__(self) -> str:
        return (
            f"BatchResult(n={len(self)}, {int(np.count_nonzero(self.success))} converged, "
            f"chunksize={self.chunksize}, formulation={self.formulation})"
        )

    def failures(self) -> list:
        """``[(index, status, message), ...]`` for every point that did not converge."""
        return [
            (int(i), int(self.status[i]), str(self.message[i]))
            for i in np.flatnonzero(~self.success)
        ]


def _points(arr, name: str, tail: tuple, what: str, n: int | None):
    """float64 (n, *tail) array of a per-point argument; ValueError naming it."""
    if arr is None:
        return None, n
    a = np.asarray(arr)
    if a.dtype.kind not in "biuf":
        try:
            if a.dtype.kind in "cUSV":
                raise TypeError
            a = a.astype(float)
        except (TypeError, ValueError, OverflowError):
            raise ValueError(
                f"{name} must be an array of real numbers, got dtype {a.dtype} "
                f"({np.asarray(arr).ravel()[:3]!r}...)"
            ) from None
    a = a.astype(float, copy=False)
    want = ("n" if n is None else str(n),) + tuple(str(t) for t in tail)
    if a.ndim != 1 + len(tail) or a.shape[1:] != tuple(tail) or (n is not None and a.shape[0] != n):
        raise ValueError(
            f"{name} must have shape ({', '.join(want)}) -- {what} -- got shape {a.shape}"
        )
    if not np.all(np.isfinite(a)):
        bad = tuple(int(i) for i in np.argwhere(~np.isfinite(a))[0])
        raise ValueError(f"{name} must be finite; {name}[{', '.join(map(str, bad))}] = {a[bad]!r}")
    return np.ascontiguousarray(a), a.shape[0]


@renamed_keywords("tendonrod.solve_batch", threads="workers")
def solve_batch(
    scene: Scene,
    *,
    displacement=None,
    tension=None,
    forces=None,
    moments=None,
    distributed=None,
    options: Options | None = None,
    workers: int = 1,
    chunksize: int | None = None,
    warm_start: bool = True,
    retry_cold: bool = True,
    predict: bool = True,
    exact: bool = False,
    tension_tendon_displacement: bool = True,
    strict: bool = False,
) -> BatchResult:
    """Solve ``n`` variants of ``scene`` that differ only in actuation and load values.

    Parameters
    ----------
    scene : tendonrod.Scene
        The design: robot, control modes (which tendons have a displacement and which a
        tension), load positions, and the values used for whatever is not varied.
    displacement : array (n, n_displacement), optional
        Per point, the displacement [m] (> 0 retracts) of every displacement-controlled
        tendon of ``scene``, in tendon order.
    tension : array (n, n_tension), optional
        Per point, the tension [N] (>= 0) of every tension-controlled tendon, in order.
    forces, moments : array (n, n_pointloads, 3), optional
        Per point, the force [N] / moment [N m] (world frame) of every point load of
        ``scene`` (in the order of ``scene.point_loads``; their positions stay).
    distributed : array (n, 3), optional
        Per point, the uniform distributed force [N/m], world frame (replaces the sum of
        the scene's distributed loads).
    options : tendonrod.Options, optional
        As for :func:`tendonrod.solve`; ``tip_only`` is implied and ``nodes`` ignored.
    workers : int
        Worker threads (the C core runs with the GIL released); chunks are shared out
        (``threads=`` before 0.2).
    chunksize : int, optional
        Points per warm-started chunk (default :data:`DEFAULT_CHUNKSIZE`).
    warm_start : bool
        Warm-start each point from the previous converged point of its chunk.
    retry_cold : bool
        Retry a point whose warm-started solve failed from a cold start.
    predict : bool
        When a point continues the line through the previous converged points, start from
        the (secant, quadratic or, for equally spaced points, cubic) extrapolation of
        their solutions; when it does not, start from the nearer (in values scaled by
        EI/L^2, EI/L, the tendon offset) of the previous converged point and the first
        point of the last line (on a grid swept line by line: the neighbour of a line's
        first point on the line before, instead of the far end of that line).
    exact : bool
        Reproduce, bit for bit, a loop of ``tr.solve(scene_p, guess=previous_solution,
        options=Options(tip_only=True, ...))`` restarted cold at every chunk (what
        :func:`tendonrod.sweep` does point by point): no predictor, no lean iteration,
        no cold retry.  Slower than the default, which agrees with that loop to the
        solver tolerance.

    tension_tendon_displacement : bool
        False: the lean loop (below) skips the recording pass, whose only product
        beyond the tip pose, tensions and slacks is the actuator displacement of
        tension-controlled tendons: that is then NaN at the points the lean loop solved
        (about 20 % faster; scenes whose tendons are all displacement-controlled skip the
        pass anyway).
    strict : bool
        Raise :class:`~tendonrod.ConvergenceError` (its ``solution`` the
        :class:`BatchResult`) instead of a :class:`~tendonrod.ConvergenceWarning` when
        some point did not succeed.

    With ``options.steps > 0`` (a fixed step count) warm points first run a lean
    Newton/Broyden loop on the core's residual (the carried Jacobian, cubic
    predictor, no step verification, no polish) and fall back to the full solve if it
    does not converge within a few iterations; with automatic steps every point runs
    the full solve, step verification included.

    At least one of the per-point arrays must be given; they fix ``n``.

    Returns
    -------
    BatchResult

    Points that look like a slip (:mod:`tendonrod.plausibility`) give one
    :class:`~tendonrod.PlausibilityWarning` per rule and subject for the whole batch (how
    many points, the worst); ``BatchResult.plausibility`` lists every point's findings.

    Examples
    --------
    >>> rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    >>> robot = tr.Robot(rod, [tr.Tendon(offset=0.01, angle=0.0)])
    >>> scene = tr.Scene(robot, displacement=[0.0157], loads=[tr.PointLoad(s=0.2, force=(0, 0, 0))])
    >>> F = np.zeros((5, 1, 3)); F[:, 0, 2] = -np.linspace(0.0, 0.2, 5)  # (points, loads, 3)
    >>> res = tr.solve_batch(scene, forces=F)
    >>> bool(res.success.all()), res.tension[:, 0].round(3)
    (True, array([3.267, 2.854, 2.426, 1.983, 1.525]))
    """
    options, chunksize = _check_arguments(scene, options, workers, chunksize)
    rod, tendons, loads, dist = pack_scene(scene)
    controls = scene.displacement_controlled()
    idisp = [i for i, c in enumerate(controls) if c]
    iten = [i for i, c in enumerate(controls) if not c]
    n, displacement, tension, forces, moments, distributed = _per_point_arrays(
        displacement, tension, forces, moments, distributed, len(idisp), len(iten), loads.shape[0]
    )
    pose = base_pose(scene.robot)  # the core solves in the base frame
    if pose is not None:
        forces, moments, distributed = (
            None if w is None else vectors_in(pose, w) for w in (forces, moments, distributed)
        )
    values = _tendon_values(tendons, n, idisp, iten, displacement, tension)
    point_loads = _point_load_values(loads, n, forces, moments)
    force_spatial = _force_spatial(scene, options, point_loads, distributed)

    kw = dict(options._raw)
    kw.pop("nodes", None)
    kw.pop("tip_only", None)
    kw["force_spatial"] = force_spatial
    kw.update(
        warm=bool(warm_start),
        retry_cold=bool(retry_cold) and not exact,
        predict=bool(predict) and not exact,
        exact=bool(exact),
        skip_tension_displacement=not tension_tendon_displacement,
    )
    kw = _with_dloads(kw, scene)
    packed = (rod, tendons, loads, dist)
    parts = _run_chunks(packed, values, point_loads, distributed, kw, n, chunksize, workers)
    res = _assemble(parts, n, chunksize, options)
    if pose is not None:
        res = dataclasses.replace(
            res,
            tip_position=points_out(pose, res.tip_position),
            tip_rotation=rotations_out(pose, res.tip_rotation),
        )
    raw = {
        "success": res.success,
        "tension": res.tension,
        "formulation": res.formulation,
        "unknowns": np.concatenate([p["unknowns"] for p in parts]),
        "steps": np.concatenate([p["steps"] for p in parts]),
    }
    found = batch_findings(scene, options, raw, values, point_loads, distributed)
    plausibility.summarize(found, "tendonrod.solve_batch", where="BatchResult.plausibility")
    res = dataclasses.replace(res, plausibility=found)
    msg = failed_points("tendonrod.solve_batch", res.success, res.failures())
    report_failure(res, strict, msg)
    return res


def _tendon_values(tendons, n, idisp, iten, displacement, tension):
    """(n, nt) control values per point (the scene's where not varied), or None."""
    values = None
    if displacement is not None or tension is not None:
        values = np.repeat(tendons[None, :, _TD["value"]], n, axis=0)
        if displacement is not None:
            values[:, idisp] = displacement
        if tension is not None:
            values[:, iten] = tension
    return values


def _point_load_values(loads, n, forces, moments):
    """(n, nl, 6) force and moment per point and point load (the scene's where not
    varied), or None."""
    point_loads = None
    if forces is not None or moments is not None:
        point_loads = np.repeat(loads[None, :, 1:7], n, axis=0)
        if forces is not None:
            point_loads[:, :, 0:3] = forces
        if moments is not None:
            point_loads[:, :, 3:6] = moments
    return point_loads


def _run_chunks(packed, values, point_loads, distributed, kw, n, chunksize, workers) -> list:
    """The core's result of every chunk of ``chunksize`` points, in order (chunks shared
    out to ``workers`` worker threads; each chunk starts cold)."""
    rod, tendons, loads, dist = packed
    bounds = [(a, min(a + chunksize, n)) for a in range(0, n, chunksize)] or [(0, 0)]
    # Ctrl-C: on this thread the core sees it itself; worker threads stop at their next
    # poll once the token is set (a solve_batch inside a sweep worker polls the sweep's)
    serial = workers == 1 or len(bounds) == 1
    token = current_token() if serial else new_token()

    def run(b):
        a, e = b
        return _core.solve_batch(
            rod,
            tendons,
            loads,
            dist,
            values=None if values is None else values[a:e],
            point_loads=None if point_loads is None else point_loads[a:e],
            dists=None if distributed is None else distributed[a:e],
            cancel=token,
            **kw,
        )

    if serial:
        return [run(b) for b in bounds]
    with cf.ThreadPoolExecutor(max_workers=min(int(workers), len(bounds))) as ex:
        try:
            return list(ex.map(run, bounds))
        except BaseException:
            token.set()  # the workers stop at their next poll; the pool then shuts down
            raise


def _check_arguments(scene, options, workers, chunksize):
    """``(options, chunksize)`` checked, with their defaults; ValueError otherwise."""
    if not isinstance(scene, Scene):
        raise ValueError(f"scene must be a tendonrod.Scene, got {scene!r}")
    options = _check_options(options)
    if isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1:
        raise ValueError(f"workers must be an int >= 1, got {workers!r}")
    if not (isinstance(options, Options)):
        raise ValueError(f"options must be a tendonrod.Options, got {options!r}")
    if chunksize is None:
        chunksize = DEFAULT_CHUNKSIZE
    if isinstance(chunksize, bool) or not isinstance(chunksize, (int, np.integer)) or chunksize < 1:
        raise ValueError(f"chunksize must be an int >= 1, got {chunksize!r}")
    return options, chunksize


def _per_point_arrays(displacement, tension, forces, moments, distributed, ndisp, nten, npl):
    """``(n, displacement, tension, forces, moments, distributed)``: the per-point
    arguments as float64 arrays of their documented shapes (None where not given) and
    the number of points they agree on; ValueError naming the first bad one."""
    n = None
    displacement, n = _points(
        displacement,
        "displacement",
        (ndisp,),
        "one column per displacement-controlled tendon",
        n,
    )
    tension, n = _points(tension, "tension", (nten,), "one column per tension-controlled tendon", n)
    forces, n = _points(forces, "forces", (npl, 3), "a force per point and point load", n)
    moments, n = _points(moments, "moments", (npl, 3), "a moment per point and point load", n)
    distributed, n = _points(distributed, "distributed", (3,), "a distributed force per point", n)
    if n is None:
        raise ValueError(
            "solve_batch needs at least one of displacement, tension, forces, moments, "
            "distributed (they set the number of points)"
        )
    if tension is not None and np.any(tension < 0.0):
        bad = tuple(int(i) for i in np.argwhere(tension < 0.0)[0])
        raise ValueError(
            f"tension must be >= 0 (a tendon cannot push); tension[{bad[0]}, {bad[1]}] "
            f"= {tension[bad]!r}"
        )
    return n, displacement, tension, forces, moments, distributed


def _force_spatial(scene, options, point_loads, distributed) -> bool:
    """One formulation for the whole batch: spatial as soon as any point leaves the plane
    (or the options ask for it)."""
    force_spatial = bool(options.force_spatial)
    if not force_spatial and is_planar(scene):
        out_of_plane = (
            point_loads is not None
            and np.any(
                (point_loads[:, :, 1] != 0)
                | (point_loads[:, :, 3] != 0)
                | (point_loads[:, :, 5] != 0)
            )
        ) or (distributed is not None and np.any(distributed[:, 1] != 0))
        force_spatial = bool(out_of_plane)
    return force_spatial


def _assemble(parts, n, chunksize, options) -> BatchResult:
    cat = {
        k: np.concatenate([p[k] for p in parts])
        for k in (
            "tip_position",
            "tip_rotation",
            "tension",
            "slack",
            "displacement",
            "residual_norm",
            "status",
            "nit",
            "nfev",
            "cold",
            "success",
            "stable",
        )
    }
    stable = np.empty(n, dtype=object)
    stable[:] = [None if v < 0 else bool(v) for v in cat["stable"]]
    message = np.empty(n, dtype=object)
    message[:] = [m for p in parts for m in p["message"]]
    return BatchResult(
        tip_position=cat["tip_position"],
        tip_rotation=cat["tip_rotation"],
        tension=cat["tension"],
        slack=cat["slack"],
        displacement=cat["displacement"],
        status=cat["status"].astype(np.int64),
        message=message,
        nit=cat["nit"].astype(np.int64),
        nfev=cat["nfev"].astype(np.int64),
        residual_norm=cat["residual_norm"],
        cold=cat["cold"].astype(bool),
        success=cat["success"].astype(bool),
        stable=stable,
        formulation=dict(parts[0]["formulation"]),
        chunksize=int(chunksize),
    )
