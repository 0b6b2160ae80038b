"""The result of a sweep: :class:`SweepResult` (tidy arrays over the points)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._chunk import (
    OUTCOME_ERROR,
    OUTCOME_NOT_CONVERGED,
    OUTCOME_NOT_RUN,
    OUTCOME_OK,
)

__all__ = ["SweepResult"]

_OUTCOME_NAMES = {
    OUTCOME_OK: "ok",
    OUTCOME_NOT_CONVERGED: "not converged",
    OUTCOME_ERROR: "error",
    OUTCOME_NOT_RUN: "not run",
}


@dataclass(frozen=True, repr=False)
class SweepResult:
    """Tidy arrays of a sweep.  Indexing ``res[name]`` returns ``data[name]``
    or, for a varied parameter, its value at every point.

    A :class:`~tendonrod.Result`: ``success``, ``status``, ``message``, ``nit``, ``nfev``
    mean the same on every result type.

    Attributes
    ----------
    names : tuple of str
        The varied parameters (paths or ``build`` keywords), in order.
    shape : tuple of int
        Grid shape (one axis per name) or ``(npoints,)`` for a list sweep.
    values : dict name -> ndarray
        The parameter value at every point, shape ``shape + value shape``.
    outcome : ndarray of int8, shape ``shape``
        The sweep's own code per point: :data:`OUTCOME_OK` (0, the solve's ``success`` is
        True), :data:`OUTCOME_NOT_CONVERGED` (1, the solve finished without success; values
        are its last iterate), :data:`OUTCOME_ERROR` (2, building, solving or measuring the
        point raised; values are NaN) or :data:`OUTCOME_NOT_RUN` (-1, the sweep was
        interrupted before the point ran).
    status : ndarray of int16, shape ``shape``
        The solver core's status of the point's solve (:attr:`tendonrod.Solution.status`, or
        ``BatchResult.status`` on the batch path; name it with
        ``tendonrod._core.strerror``): 0 ok, > 0 converged with a caveat, < 0 failed.
        :data:`STATUS_NONE` (-1000) where no solve returned: the build or the solve raised
        (an :data:`OUTCOME_ERROR` raised by ``measure`` keeps its solve's status), or the
        point did not run.
    message : ndarray of object (str), shape ``shape``
        The solver's message, or the exception's ("not run" if it did not run).
    nit, nfev : ndarray of int64, shape ``shape``
        Solver iterations and residual evaluations (-1 where no solve returned).
    data : dict name -> ndarray
        What ``measure`` returned, stacked: shape ``shape + item shape``;
        NaN where a point raised.
    chunksize : int
        Points per warm-started chunk (results depend on it).
    plausibility : ndarray of object, shape ``shape``
        Each point's plausibility findings, a tuple of
        :class:`~tendonrod.plausibility.Finding` (as ``Solution.plausibility``; ``()``
        where all is plausible or the point did not run).

    Examples
    --------
    >>> robot = tr.Robot(tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True), [tr.Tendon(0.01)])
    >>> res = tr.sweep(tr.Scene(robot, displacement=[0.0]), {"displacement[0]": [0.005, 0.01]})
    >>> res["displacement[0]"], res["tip_position"].shape, res.failures()
    (array([0.005, 0.01 ]), (2, 3), [])
    """

    names: tuple
    shape: tuple
    values: dict
    outcome: np.ndarray
    status: np.ndarray
    message: np.ndarray
    nit: np.ndarray
    nfev: np.ndarray
    data: dict
    chunksize: int
    plausibility: np.ndarray | None = None

    @property
    def success(self) -> np.ndarray:
        """Boolean array ``shape``: the point's solve succeeded (``outcome == OUTCOME_OK``)."""
        return self.outcome == OUTCOME_OK

    def __getitem__(self, key: str) -> np.ndarray:
        if key in self.data:
            return self.data[key]
        if key in self.values:
            return self.values[key]
        raise KeyError(
            f"{key!r}: not a recorded quantity ({', '.join(self.data)}) "
            f"nor a varied parameter ({', '.join(self.values)})"
        )

    def __repr__(self) -> str:
        counts = [
            f"{int(np.count_nonzero(self.outcome == code))} {name}"
            for code, name in _OUTCOME_NAMES.items()
            if code != OUTCOME_OK and np.any(self.outcome == code)
        ]
        ok = int(np.count_nonzero(self.success))
        failed = f" ({', '.join(counts)})" if counts else ""
        return (
            f"SweepResult(shape={self.shape}, names={list(self.names)}, {ok}/{self.outcome.size} "
            f"ok{failed}, recorded={list(self.data)}, chunksize={self.chunksize})"
        )

    def failures(self) -> list:
        """Every point whose outcome is not :data:`OUTCOME_OK`, in C order, as
        ``[(index, outcome, status, message), ...]``: ``index`` the point's index
        tuple into ``shape``, ``outcome`` its ``OUTCOME_*`` code, ``status`` the
        core's status (:data:`STATUS_NONE` if no solve returned), ``message`` the
        solver's or the exception's message (all plain Python ints and str)."""
        return [
            (
                tuple(int(i) for i in ix),
                int(self.outcome[tuple(ix)]),
                int(self.status[tuple(ix)]),
                str(self.message[tuple(ix)]),
            )
            for ix in np.argwhere(self.outcome != OUTCOME_OK)
        ]
