"""The work of one chunk of a :func:`tendonrod.sweep`: its points solved in order,
each warm-started from the previous converged one; never raises for a point.

A chunk task is a plain dict (``chunk``, ``indices``, ``scenes``, ``measure``,
``options``, ``warm_start``, optionally ``batch``), so that an executor in another
process can run it.  When only actuation and point-load values vary and the record is
the default tip measure (:func:`sweep_can_batch`), the whole chunk is one
:func:`tendonrod.solve_batch` call instead.

Each point record holds ``"outcome"`` (the sweep's own code, one of the ``OUTCOME_*``
constants below) and ``"status"`` (the core's status of the point's solve, or
:data:`STATUS_NONE`); both constants are re-exported by :mod:`tendonrod.sweep`.  The
outcome is decided from the solve's ``success``, never from the status number.
"""

from __future__ import annotations

import math
import re
import threading
import warnings
from dataclasses import dataclass

import numpy as np

from ..batch import solve_batch
from ..compiled import is_planar
from ..model import PointLoad, Scene
from ..plausibility import PlausibilityWarning
from ..results import ConvergenceWarning
from ..solver import solve

OUTCOME_OK = 0
"""The solve succeeded (its ``success`` is True; its status may carry a caveat)."""
OUTCOME_NOT_CONVERGED = 1
"""The solve finished without success (values: its last iterate)."""
OUTCOME_ERROR = 2
"""Building, solving or measuring the point raised (values: NaN)."""
OUTCOME_NOT_RUN = -1
"""Only in results of a sweep that was interrupted before the point ran."""

STATUS_NONE = -1000
"""The ``status`` of a point without a core status: no solve returned for it (the
build or the solve raised, or it did not run).  Outside the core's status range."""


def _record(index, outcome, status, nit, message, data, findings=(), nfev=-1) -> dict:
    """One point's record, as stored in the sweep's file (plain JSON types; ``findings``
    the point's plausibility findings, stored as dicts)."""
    return {
        "i": index,
        "outcome": outcome,
        "status": status,
        "nit": nit,
        "nfev": nfev,
        "message": message,
        "data": data,
        "plausibility": [f.to_dict() for f in findings],
    }


@dataclass(frozen=True)
class _BuildFailure:
    """A point whose scene could not be built (its message; a plain string pickles
    anywhere, unlike some exception objects)."""

    message: str


def _run_chunk(task: dict) -> dict:
    """Solve one chunk in order with warm starts; never raises for a point."""
    scenes, measure, options, warm = (
        task["scenes"],
        task["measure"],
        task["options"],
        task["warm_start"],
    )
    records, guess = [], None
    if task.get("batch"):
        # the whole chunk in one C call; None: its scenes do not share one design, so it
        # is solved point by point below
        if threading.current_thread() is threading.main_thread():
            with warnings.catch_warnings():  # recorded per point (see below)
                warnings.simplefilter("ignore", PlausibilityWarning)
                out = _batch_chunk(task)
        else:
            out = _batch_chunk(task)
        if out is not None:
            return out
    for index, scene in zip(task["indices"], scenes):
        if isinstance(scene, _BuildFailure):  # build failed in the parent: record, go on
            records.append(_record(index, OUTCOME_ERROR, STATUS_NONE, -1, scene.message, None))
            continue
        sol = None
        try:
            if threading.current_thread() is threading.main_thread():
                # a process-pool worker (or a serial run): non-convergence is recorded per
                # point, so silence the warnings here (plausibility findings too: sweep()
                # summarises them).  Thread-pool workers must not touch the (process-global)
                # filters; sweep() silences them once, in the calling thread.
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", ConvergenceWarning)
                    warnings.simplefilter("ignore", PlausibilityWarning)
                    sol = solve(scene, guess=guess if warm else None, options=options)
            else:
                sol = solve(scene, guess=guess if warm else None, options=options)
            values = {k: np.asarray(v, dtype=float) for k, v in dict(measure(scene, sol)).items()}
            ok = bool(sol.success)  # the verdict is the solve's, never re-derived from status
            records.append(
                _record(
                    index,
                    OUTCOME_OK if ok else OUTCOME_NOT_CONVERGED,
                    int(sol.status),
                    int(getattr(sol, "nit", -1)),
                    str(sol.message),
                    {k: v.tolist() for k, v in values.items()},
                    sol.plausibility,
                    int(getattr(sol, "nfev", -1)),
                )
            )
            if ok:
                guess = sol
        except Exception as exc:  # noqa: BLE001 - a failed point never stops the sweep
            # a solve that returned before ``measure`` raised keeps its status and nit
            status = STATUS_NONE if sol is None else int(sol.status)
            nit = -1 if sol is None else int(getattr(sol, "nit", -1))
            nfev = -1 if sol is None else int(getattr(sol, "nfev", -1))
            message = f"{type(exc).__name__}: {exc}"
            records.append(_record(index, OUTCOME_ERROR, status, nit, message, None, (), nfev))
    return {"chunk": task["chunk"], "records": records}


def _stable_value(stable) -> float:
    """A stability verdict True / False / None as 1.0 / 0.0 / NaN."""
    return math.nan if stable is None else float(bool(stable))


# --------------------------------------------------------------------------- batch path
# The paths whose values solve_batch can vary: an actuation value, or a point load's
# force/moment (or one component of it).
_BATCH_PATH = re.compile(
    r"^(?:(displacement|tension)\[(\d+)\]|loads\[(\d+)\]\.(?:force|moment)"
    r"(?:\[[0-2]\])?)$"
)


def sweep_can_batch(base, names) -> bool:
    """True if every varied path of a sweep of ``base`` is an actuation value
    (``displacement[i]``, ``tension[i]``) or a point load's force/moment (or one
    component of it): then the sweep's chunks can go through
    :func:`~tendonrod.solve_batch`."""
    if not isinstance(base, Scene) or not names:
        return False
    for n in names:
        mt = _BATCH_PATH.match(n)
        if not mt:
            return False
        if mt.group(3) is not None:
            j = int(mt.group(3))
            if j >= len(base.loads) or not isinstance(base.loads[j], PointLoad):
                return False
    return True


def _batch_chunk(task: dict):
    """The records of one sweep chunk solved by :func:`~tendonrod.solve_batch`, or None if
    the chunk's scenes do not share one design (then the chunk is solved point by point)."""
    scenes, options = task["scenes"], task["options"]
    if not scenes or not all(isinstance(s, Scene) for s in scenes):
        return None
    if options is not None and not options.tip_only:
        return None  # the per-point path warm-starts from recorded base states then
    first = scenes[0]
    planar = is_planar(first)
    if any(is_planar(s) != planar for s in scenes):
        return None  # the per-point path switches formulation within the chunk
    ctl = first.displacement_controlled()
    pos = [(type(ld), getattr(ld, "s", None)) for ld in first.loads]
    for s in scenes:
        if (
            (s.robot is not first.robot and s.robot != first.robot)
            or s.displacement_controlled() != ctl
            or [(type(ld), getattr(ld, "s", None)) for ld in s.loads] != pos
        ):
            return None
    idisp = [i for i, c in enumerate(ctl) if c]
    iten = [i for i, c in enumerate(ctl) if not c]
    n = len(scenes)
    disp = np.array([[s.displacement[i] for i in idisp] for s in scenes], dtype=float).reshape(
        n, len(idisp)
    )
    ten = np.array([[s.tension[i] for i in iten] for s in scenes], dtype=float).reshape(
        n, len(iten)
    )
    pls = [[ld for ld in s.loads if isinstance(ld, PointLoad)] for s in scenes]
    npl = len(pls[0])
    forces = np.array([[p.force for p in pl] for pl in pls], dtype=float).reshape(n, npl, 3)
    moments = np.array([[p.moment for p in pl] for pl in pls], dtype=float).reshape(n, npl, 3)
    dist = np.array([s.distributed_force for s in scenes], dtype=float)
    # automatic steps: exact mode, bit for bit the per-point loop (each point verifies its
    # steps); a fixed step count: the lean loop with the predictor (equal to the loop to
    # the solver tolerance, several times faster)
    exact = options is None or options.steps == 0 or options.integrator == "adaptive"
    try:
        with warnings.catch_warnings():  # the sweep reports its failures at the end
            warnings.simplefilter("ignore", ConvergenceWarning)
            res = solve_batch(
                first,
                displacement=disp if idisp else None,
                tension=ten if iten else None,
                forces=forces if npl else None,
                moments=moments if npl else None,
                distributed=dist,
                options=options,
                chunksize=n,
                warm_start=bool(task["warm_start"]),
                exact=exact,
                retry_cold=False,
            )
    except ValueError:
        return None
    records = []
    for k, index in enumerate(task["indices"]):
        ok = bool(res.success[k])
        data = {
            "tip_position": res.tip_position[k].tolist(),
            "tip_rotation": res.tip_rotation[k].tolist(),
            "tension": res.tension[k].tolist(),
            "slack": res.slack[k].tolist(),
            "displacement": res.displacement[k].tolist(),
            "stable": _stable_value(res.stable[k]),
        }
        records.append(
            _record(
                index,
                OUTCOME_OK if ok else OUTCOME_NOT_CONVERGED,
                int(res.status[k]),
                int(res.nit[k]),
                str(res.message[k]),
                data,
                res.plausibility[k] if res.plausibility is not None else (),
                int(res.nfev[k]),
            )
        )
    return {"chunk": task["chunk"], "records": records}
