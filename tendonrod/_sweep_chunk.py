"""The work of one chunk of a :func:`tendonrod.sweep`: its points solved in order,
each warm-started from the previous converged one; never raises for a point.

A chunk task is a plain dict (``chunk``, ``indices``, ``scenes``, ``measure``,
``options``, ``warm_start``, optionally ``batch``), so that an executor in another
process can run it.  The point statuses recorded here are the sweep's public
constants (re-exported by :mod:`tendonrod.sweep`).
"""

from __future__ import annotations

import threading
import warnings
from dataclasses import dataclass

import numpy as np

STATUS_OK = 0
"""The solve converged."""
STATUS_NOT_CONVERGED = 1
"""The solver finished without converging (values: its last iterate)."""
STATUS_ERROR = 2
"""Building or solving the point raised (values: NaN)."""
STATUS_NOT_RUN = -1
"""Only in results of a sweep that was interrupted before the point ran."""


@dataclass(frozen=True)
class _BuildFailure:
    """A point whose scene could not be built (its message; a plain string pickles
    anywhere, unlike some exception objects)."""

    message: str


def _run_chunk(task: dict) -> dict:
    """Solve one chunk in order with warm starts; never raises for a point."""
    import tendonrod as tr

    scenes, measure, options, warm = (
        task["scenes"],
        task["measure"],
        task["options"],
        task["warm_start"],
    )
    records, guess = [], None
    if task.get("batch"):
        # BEGIN batch path (issue 7, tendonrod/batch.py): the whole chunk in one C call
        from .batch import _sweep_chunk

        out = _sweep_chunk(task)
        if out is not None:
            return out
        # END batch path (None: this chunk cannot be batched; solve point by point)
    for index, scene in zip(task["indices"], scenes):
        if isinstance(scene, _BuildFailure):  # build failed in the parent: record, go on
            records.append(
                {
                    "i": index,
                    "status": STATUS_ERROR,
                    "nit": -1,
                    "message": scene.message,
                    "data": None,
                }
            )
            continue
        try:
            if threading.current_thread() is threading.main_thread():
                # a process-pool worker (or a serial run): non-convergence is recorded per
                # point, so silence the warning here.  Thread-pool workers must not touch the
                # (process-global) filters; sweep() silences them once, in the calling thread.
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", getattr(tr, "ConvergenceWarning", Warning))
                    sol = tr.solve(scene, guess=guess if warm else None, options=options)
            else:
                sol = tr.solve(scene, guess=guess if warm else None, options=options)
            values = {k: np.asarray(v, dtype=float) for k, v in dict(measure(scene, sol)).items()}
            ok = bool(sol.success)
            records.append(
                {
                    "i": index,
                    "status": STATUS_OK if ok else STATUS_NOT_CONVERGED,
                    "nit": int(getattr(sol, "nit", -1)),
                    "message": str(sol.message),
                    "data": {k: v.tolist() for k, v in values.items()},
                }
            )
            if ok:
                guess = sol
        except Exception as exc:  # noqa: BLE001 - a failed point never stops the sweep
            records.append(
                {
                    "i": index,
                    "status": STATUS_ERROR,
                    "nit": -1,
                    "message": f"{type(exc).__name__}: {exc}",
                    "data": None,
                }
            )
    return {"chunk": task["chunk"], "records": records}
