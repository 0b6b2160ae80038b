"""Design sweeps (:func:`tendonrod.sweep`): solve a grid or list of scenes, in parallel,
resumably.

The subpackage: :mod:`~tendonrod.sweeps.run` the sweep, ``_chunk`` a chunk of points,
``_file`` the resumable record, ``_progress`` the bar, ``_result`` :class:`SweepResult`
(the names of what varies, :func:`set_path` and :func:`get_path`, are the package's:
load paths and linearisations name their parameters the same way).

What is varied is named by a *path* into the scene's frozen dataclasses and
replaced with :func:`dataclasses.replace`: ``"robot.rod.length"``,
``"robot.tendons[0].EA"``, ``"displacement[0]"``, ``"loads[1].force"``,
``"loads[0].force[2]"`` (one component of a vector).  Anything a path cannot
express (a converging tendon whose slope follows its offset, say) goes through
``build=``: a function ``build(base, **values) -> Scene``.

Order, chunks, warm starts, determinism
    Points are numbered in C order of the grid (the last name varies fastest)
    or in list order.  They are cut into contiguous chunks of ``chunksize``
    points; within a chunk each solve is warm-started from the previous
    converged solution, so a chunk is a continuation path (sweep a load from
    zero upwards along the last axis and large loads become reachable).  Each
    chunk starts cold.  Results therefore depend only on the order and the
    chunking, never on the workers: bitwise identical for the same chunking.
    The default chunk is one line of the last axis (grid) or 32 points (list)
    -- independent of the machine, so that results are too.

Parallelism
    Chunks are handed to a :class:`concurrent.futures.Executor`; by default a
    thread pool with one thread per core (the C core releases the GIL).  Pass
    any executor -- ``ProcessPoolExecutor``, ``dask.distributed``'s
    ``client.get_executor()``, Ray's -- and its workers run the chunks
    (scenes, options and solutions pickle; ``measure``/``build`` must too,
    so use module-level functions with process pools).

Files, resume
    With ``file=`` every finished chunk is appended to a JSON-lines file and
    flushed to disk (``os.fsync``) before the next is recorded.  Calling the
    same sweep with the same path again reads what is there (a half-written
    last line from a killed process is discarded) and runs only the missing
    chunks, so nothing finished is lost and the result equals an uninterrupted
    run.  The file's header holds a fingerprint of the sweep; a different
    sweep refuses to resume from it.  A file written by another tendonrod
    version is not resumed from: the sweep warns, keeps it as
    ``<path>.tendonrod-<version>`` and computes every point again.

Failures
    Every point has two codes.  ``outcome`` (int8) is the sweep's own:
    :data:`OUTCOME_OK` (0) the solve succeeded; :data:`OUTCOME_NOT_CONVERGED`
    (1) it finished without success and the values are its last iterate;
    :data:`OUTCOME_ERROR` (2) building, solving or measuring the point raised
    and the values are NaN; :data:`OUTCOME_NOT_RUN` (-1) the sweep was
    interrupted before the point ran.  ``status`` (int16) is the solver core's
    status of the point's solve (:attr:`tendonrod.Solution.status`, or
    ``BatchResult.status`` on the batch path): 0 ok, > 0 converged with a caveat
    (3 off the load path and unconfirmed, 5 unstable: not successes), < 0 failed;
    :data:`STATUS_NONE` (-1000) where no solve returned.  The outcome follows the
    solve's ``success``; ``message`` is the solver's or the exception's.  No
    failure stops the sweep.
"""

from .._scene_paths import get_path, set_path
from ._chunk import (
    OUTCOME_ERROR,
    OUTCOME_NOT_CONVERGED,
    OUTCOME_NOT_RUN,
    OUTCOME_OK,
    STATUS_NONE,
)
from ._result import SweepResult
from .run import ComplianceMeasure, sweep, tip_measure

__all__ = [
    "sweep",
    "SweepResult",
    "set_path",
    "get_path",
    "tip_measure",
    "ComplianceMeasure",
    "OUTCOME_OK",
    "OUTCOME_NOT_CONVERGED",
    "OUTCOME_ERROR",
    "OUTCOME_NOT_RUN",
    "STATUS_NONE",
]
