"""The sweep itself: :func:`sweep`, its default measures, its result (the design of
sweeps, chunks, files and failures: :mod:`tendonrod.sweeps`)."""

from __future__ import annotations

import concurrent.futures as cf
import itertools
import math
import numbers
import os
import warnings
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._deprecation import renamed_keywords
from .._interrupt import cancel_scope, new_token
from .._scene_paths import _parse_path, get_path, set_path
from ..options import Options, _check_options
from ..plausibility import Finding, PlausibilityWarning, summarize
from ..results import ConvergenceWarning, failed_points, report_failure
from ..solver import compliance
from ._chunk import (
    OUTCOME_NOT_RUN,
    STATUS_NONE,
    _BuildFailure,
    _run_chunk,
    _stable_value,
    sweep_can_batch,
)
from ._file import append_line, fingerprint_of, open_progress
from ._progress import progress_bar
from ._result import SweepResult

# what this module defines (the package, tendonrod.sweeps, re-exports it with the rest)
__all__ = ["sweep", "tip_measure", "ComplianceMeasure"]

_DEFAULT_LIST_CHUNK = 32


# ---- what is recorded per point ----
def tip_measure(scene: Any, sol: Any) -> dict:
    """Default per-point record: tip pose, tendon tensions, slacks, displacements and the
    solve's stability verdict (1.0 / 0.0, NaN where None or not judged).

    Examples
    --------
    >>> robot = tr.Robot(tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True), [tr.Tendon(0.01)])
    >>> sorted(tr.tip_measure(None, tr.solve(tr.Scene(robot, displacement=[0.01]))))
    ['displacement', 'slack', 'stable', 'tension', 'tip_position', 'tip_rotation']
    """
    verdict = sol._get("stability_verdict") or {"stable": None}  # not built from raw
    return {
        "tip_position": np.asarray(sol.tip_position, dtype=float),  # (3,) world [m]
        "tip_rotation": np.asarray(sol.tip_rotation, dtype=float),  # (3, 3) body-to-world
        "tension": np.asarray(sol.tension, dtype=float),  # (nt,) [N]
        "slack": np.asarray(sol.slack, dtype=float),  # (nt,) [m]
        "displacement": np.asarray(sol.displacement, dtype=float),  # (nt,) [m]
        "stable": _stable_value(verdict["stable"]),
    }


@dataclass(frozen=True)
class ComplianceMeasure:
    """Per-point record of ``tr.compliance(scene, s)`` for each s in ``s``: the tangent,
    the secant over the load step ``step``, or both.

    Records ``"compliance"`` (the tangent, when ``tangent``) and, when ``step`` is
    given, ``"secant_compliance"`` (``tr.compliance(scene, s, step=step)``), each with
    shape (len(s), 6, 6) (world frame; rows [dx, dtheta], columns [force, moment]), plus
    the :func:`tip_measure` fields.  ``step``: a signed load step, one for all columns or
    six ([N], [N m]); the tangent misleads near a tendon's slack switch or a limit point
    (:func:`tendonrod.compliance`).  Picklable, so it works with process pools.

    Examples
    --------
    >>> robot = tr.Robot(tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True), [tr.Tendon(0.01)])
    >>> m = tr.ComplianceMeasure(s=(0.1, None))  # at mid-length and at the tip
    >>> m(scene := tr.Scene(robot, displacement=[0.01]), tr.solve(scene))["compliance"].shape
    (2, 6, 6)
    """

    s: tuple = (None,)
    step: Any = None
    tangent: bool = True

    def __call__(self, scene, sol):
        out = tip_measure(scene, sol)
        if self.tangent:
            out["compliance"] = np.stack(
                [np.asarray(compliance(scene, s=s), dtype=float) for s in self.s]
            )
        if self.step is not None:
            out["secant_compliance"] = np.stack(
                [np.asarray(compliance(scene, s=s, step=self.step), dtype=float) for s in self.s]
            )
        return out


@renamed_keywords("tendonrod.sweep", max_workers="workers", path="file")
def sweep(
    base: Any,
    vary: Mapping[str, Any] | None = None,
    *,
    grid: bool = True,
    build: Callable[..., Any] | None = None,
    measure: Callable[[Any, Any], Mapping] | None = None,
    options: Any = None,
    executor: cf.Executor | None = None,
    workers: int | None = None,
    chunksize: int | None = None,
    warm_start: bool = True,
    file: str | os.PathLike | None = None,
    progress: bool | None = None,
    strict: bool = False,
) -> SweepResult:
    """Solve ``base`` with parameters varied over a grid (or a list) of points.

    Parameters
    ----------
    base : tendonrod.Scene
        The scene every point starts from.
    vary : mapping name -> sequence
        Name is a path into the scene (``"robot.tendons[0].EA"``,
        ``"loads[0].force"``, ``"displacement[0]"``) or, with ``build``, a
        keyword of ``build``.  Values are a sequence of scalars or of arrays
        (a force vector per point, say).
    grid : bool
        True: every combination (outer product, C order, shape = lengths of
        the sequences).  False: the sequences are zipped (equal lengths).
    build : callable, optional
        ``build(base, **point) -> Scene``; replaces the path mechanism.
    measure : callable, optional
        ``measure(scene, solution) -> {name: array}``, recorded per point;
        default :func:`tip_measure`.  See also :class:`ComplianceMeasure`.
    options : tendonrod.Options, optional
        Passed to every :func:`tendonrod.solve`.  Default: ``Options(tip_only=True)``
        with the default ``measure`` (it reads only tip quantities), else ``Options()``.
    executor : concurrent.futures.Executor, optional
        Runs the chunks; default a ``ThreadPoolExecutor`` with ``workers`` threads,
        shut down at the end.  An
        executor you pass is left running.
    workers : int, optional
        Worker threads of the default executor (default ``os.cpu_count()``;
        ``max_workers=`` before 0.2).
    chunksize : int, optional
        Points per warm-started chunk (see the module docstring).
    warm_start : bool
        Pass the previous converged solution of the chunk as ``guess``.
    file : str or PathLike, optional
        JSON-lines file recording finished chunks; resumes from it if present
        (``path=`` before 0.2).
    progress : bool, optional
        A tqdm progress bar.  None: shown on a sweep that runs longer than 2 s in an
        interactive session (a terminal or a notebook), never in CI (``CI`` set) nor
        with ``TENDONROD_PROGRESS=0`` (:mod:`tendonrod.sweeps._progress`).
    strict : bool
        Raise :class:`~tendonrod.ConvergenceError` (its ``solution`` the
        :class:`SweepResult`) instead of a :class:`~tendonrod.ConvergenceWarning` when
        some point did not succeed (after the whole sweep ran: no failure stops it).

    Returns
    -------
    SweepResult

    Points that look like a slip (:mod:`tendonrod.plausibility`) give one
    :class:`~tendonrod.PlausibilityWarning` per rule and subject for the whole sweep (how
    many points, the worst and its index), never one per point;
    ``SweepResult.plausibility`` lists every point's findings.

    Examples
    --------
    >>> robot = tr.Robot(tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True), [tr.Tendon(0.01)])
    >>> res = tr.sweep(tr.Scene(robot, displacement=[0.0]), {"displacement[0]": [0.005, 0.01]})
    >>> res.shape, bool(res.success.all()), res["tension"][:, 0].round(3)
    ((2,), True, array([1.04 , 2.081]))
    """
    names, shape, point_values = _points(vary, grid)
    npoints = len(point_values)
    if chunksize is None:
        chunksize = shape[-1] if (grid and shape) else min(npoints, _DEFAULT_LIST_CHUNK)
    # a chunk never holds more than every point
    chunksize = min(_count("chunksize", chunksize), max(npoints, 1))
    if workers is not None:
        workers = _count("workers", workers)
    if options is not None:
        options = _check_options(options)
    if measure is None:
        measure = tip_measure
        if options is None:
            # only tip quantities are recorded: do not fill backbone arrays (~30% faster
            # per solve)
            options = Options(tip_only=True)
    if build is None:
        for n in names:
            _parse_path(n)  # fail early on a malformed path
            get_path(base, n)  # ... or one that does not exist

    scenes = _build_scenes(base, names, point_values, build)
    done: dict = {}
    fh = None
    fp = fingerprint_of(base, names, point_values, chunksize, measure, build, options, warm_start)
    if file is not None:
        done, fh = open_progress(file, fp, npoints, chunksize, names, shape)
    tasks = _tasks(scenes, chunksize, done, measure, options, warm_start)
    # batch path: only values of actuation and point loads vary and the record is the
    # default tip measure -> each chunk is one tr.solve_batch call (same chunking and
    # warm starts; with automatic steps bit for bit the per-point path, with a fixed step
    # count the batch's lean loop, equal to it to the solver tolerance)
    if build is None and measure is tip_measure and sweep_can_batch(base, names):
        for t in tasks:
            t["batch"] = True
    bar = progress_bar(progress, npoints, done)
    _run(tasks, done, fh, bar, executor, workers)
    res = _assemble(names, shape, point_values, done, npoints, chunksize)
    assert res.plausibility is not None  # _assemble fills it
    summarize(
        res.plausibility.ravel().tolist(),
        "tendonrod.sweep",
        index=lambda i: f"index {tuple(int(j) for j in np.unravel_index(i, res.shape))}",
        where="SweepResult.plausibility",
    )
    report_failure(res, strict, failed_points("tendonrod.sweep", res.success, res.failures()))
    return res


def _count(name: str, value) -> int:
    """An int >= 1 (a chunk size, a number of workers); ValueError naming it."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Integral, np.integer)):
        raise ValueError(f"{name} must be an int >= 1, got {value!r}")
    if value < 1:
        raise ValueError(f"{name} must be >= 1, got {value!r}")
    return int(value)


def _points(vary, grid: bool):
    """``(names, shape, point_values)``: the varied names, the result shape, and the
    values of every point (a list per point, in the order of ``names``)."""
    if vary is None:
        vary = {}
    if not isinstance(vary, Mapping):
        raise TypeError(
            f"vary must be a mapping name -> sequence of values, got {type(vary).__name__}"
        )
    names = tuple(vary)
    columns = []
    for n in names:
        v = vary[n]
        if isinstance(v, (str, bytes)) or not isinstance(v, Iterable):
            raise ValueError(f"vary[{n!r}] must be a sequence of values, got {v!r}")
        columns.append(list(v))
    for n, col in zip(names, columns):
        if len(col) == 0:
            raise ValueError(f"vary[{n!r}]: no values")
    if grid:
        shape = tuple(len(c) for c in columns)
        point_values = [list(p) for p in itertools.product(*columns)] if names else [[]]
    else:
        lengths = {len(c) for c in columns}
        if len(lengths) > 1:
            raise ValueError(
                "grid=False zips the sequences, which need equal lengths; got "
                + ", ".join(f"{n}: {len(c)}" for n, c in zip(names, columns))
            )
        npts = lengths.pop() if lengths else 1
        shape = (npts,)
        point_values = [list(p) for p in zip(*columns)] if names else [[]]
    return names, shape, point_values


def _build_scenes(base, names, point_values, build) -> list:
    """The scene of every point, built in the parent (cheap); a failed build becomes a
    :class:`_BuildFailure`, recorded as an error when its chunk runs."""
    scenes: list = []
    # a dataclass built here warns of its plausibility findings; they are per point data
    # (the points' findings), summarised once the sweep ends
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PlausibilityWarning)
        for pv in point_values:
            scenes.append(_build_one(base, names, pv, build))
    return scenes


def _build_one(base, names, pv, build):
    """The scene of one point, or a :class:`_BuildFailure`."""
    try:
        if build is not None:
            return build(base, **dict(zip(names, pv)))
        scene = base
        for n, v in zip(names, pv):
            scene = set_path(scene, n, v)
        return scene
    except Exception as exc:  # noqa: BLE001 - recorded as a failed point
        return _BuildFailure(f"{type(exc).__name__}: {exc}")


def _tasks(scenes, chunksize, done, measure, options, warm_start) -> list:
    """One task per chunk not already in ``done`` (see :mod:`tendonrod.sweeps._chunk`)."""
    npoints = len(scenes)
    nchunks = math.ceil(npoints / chunksize)
    todo = [c for c in range(nchunks) if c not in done]
    return [
        {
            "chunk": c,
            "indices": list(range(c * chunksize, min((c + 1) * chunksize, npoints))),
            "scenes": scenes[c * chunksize : (c + 1) * chunksize],
            "measure": measure,
            "options": options,
            "warm_start": warm_start,
        }
        for c in todo
    ]


def _run(tasks, done, fh, bar, executor, workers) -> None:
    """Run the chunks on ``executor`` (default: a thread pool, shut down at the end),
    with the solver's convergence warnings silenced, then close the file and the bar."""
    own = executor is None
    if own and tasks:
        n = workers or os.cpu_count() or 1
        executor = cf.ThreadPoolExecutor(max_workers=min(n, len(tasks)))
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            warnings.simplefilter("ignore", PlausibilityWarning)  # summarised at the end
            _drive(executor, tasks, done, fh, bar)
    finally:
        if own and executor is not None:
            executor.shutdown(wait=True, cancel_futures=True)
        if fh is not None:
            fh.close()
        if bar is not None:
            bar.close()


def _drive(executor, tasks, done, fh, bar) -> None:
    """Submit every chunk, record each as it finishes (file first, then the bar).
    Interrupted (Ctrl-C), the chunks not started are cancelled and thread workers stop
    at their next poll (a Cancel token); what was recorded stays, so a sweep with a
    file resumes."""
    if not tasks:
        return
    token = new_token()
    threads = isinstance(executor, cf.ThreadPoolExecutor)
    if threads:
        futures = [executor.submit(_run_chunk_polled, t, token) for t in tasks]
    else:
        futures = [executor.submit(_run_chunk, t) for t in tasks]
    try:
        for fut in cf.as_completed(futures):
            out = fut.result()
            done[out["chunk"]] = out["records"]
            if fh is not None:
                append_line(fh, {"chunk": out["chunk"], "records": out["records"]})
            if bar is not None:
                bar.update(len(out["records"]))
    except BaseException:
        token.set()
        for f in futures:
            f.cancel()
        raise


def _run_chunk_polled(task: dict, token) -> dict:
    """:func:`_run_chunk` in a worker thread, its solves polling ``token``."""
    with cancel_scope(token):
        return _run_chunk(task)


def _assemble(names, shape, point_values, done, npoints, chunksize) -> SweepResult:
    outcome = np.full(npoints, OUTCOME_NOT_RUN, dtype=np.int8)
    status = np.full(npoints, STATUS_NONE, dtype=np.int16)
    message = np.empty(npoints, dtype=object)
    message[:] = "not run"
    nit = np.full(npoints, -1, dtype=np.int64)
    nfev = np.full(npoints, -1, dtype=np.int64)
    items: list = [None] * npoints
    found = np.empty(npoints, dtype=object)
    found.fill(())
    for recs in done.values():
        for r in recs:
            i = int(r["i"])
            outcome[i] = r["outcome"]
            status[i] = r["status"]
            message[i] = r["message"]
            nit[i] = r["nit"]
            nfev[i] = r.get("nfev", -1)  # (files of 0.1 did not record it)
            items[i] = r["data"]
            # (files written before plausibility findings were recorded have none)
            found[i] = tuple(Finding.from_dict(f) for f in r.get("plausibility", ()))
    keys: list = []
    item_shapes: dict = {}
    for it in items:
        if it is None:
            continue
        for k, v in it.items():
            shp = np.shape(v)
            if k not in item_shapes:
                keys.append(k)
                item_shapes[k] = shp
            elif item_shapes[k] != shp:
                item_shapes[k] = None  # ragged: stored as objects
    data = {}
    for k in keys:
        if item_shapes[k] is None:
            arr = np.empty(npoints, dtype=object)
            for i, it in enumerate(items):
                arr[i] = None if (it is None or k not in it) else np.asarray(it[k], dtype=float)
            data[k] = arr.reshape(shape)
        else:
            arr = np.full((npoints,) + item_shapes[k], np.nan)
            for i, it in enumerate(items):
                if it is not None and k in it:
                    arr[i] = np.asarray(it[k], dtype=float)
            data[k] = arr.reshape(tuple(shape) + item_shapes[k])
    values = {}
    for j, n in enumerate(names):
        col = [np.asarray(pv[j]) for pv in point_values]
        try:
            values[n] = np.stack(col).reshape(tuple(shape) + col[0].shape)
        except ValueError:
            arr = np.empty(npoints, dtype=object)
            arr[:] = [pv[j] for pv in point_values]
            values[n] = arr.reshape(shape)
    return SweepResult(
        names=names,
        shape=tuple(shape),
        values=values,
        outcome=outcome.reshape(shape),
        status=status.reshape(shape),
        message=message.reshape(shape),
        nit=nit.reshape(shape),
        nfev=nfev.reshape(shape),
        data=data,
        chunksize=chunksize,
        plausibility=found.reshape(shape),
    )
