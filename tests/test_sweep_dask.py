"""tendonrod.sweep on a Dask cluster (dask[distributed] is in the test extra: these run,
never skip): bitwise equal to threads; a worker killed mid-sweep (Dask runs its task
again elsewhere); the driver killed mid-sweep and the sweep resumed from its file --
nothing lost, nothing duplicated."""

import json
import os
import pathlib
import signal
import subprocess
import sys
import time

import dask_sweep_helpers as helpers
import numpy as np
from dask.distributed import Client

import tendonrod as tr

HERE = pathlib.Path(__file__).resolve().parent
KW = dict(grid=False, chunksize=2, progress=False)


def _bitwise(a, b):
    assert a.data.keys() == b.data.keys()
    for k in a.data:
        assert a[k].tobytes() == b[k].tobytes(), k
    assert np.array_equal(a.outcome, b.outcome) and np.array_equal(a.status, b.status)


def _pythonpath(monkeypatch):
    # the workers are new processes: they import the helpers (and their measures) by name
    monkeypatch.setenv("PYTHONPATH", os.pathsep.join([str(HERE), os.environ.get("PYTHONPATH", "")]))


def test_local_cluster_bitwise_equal_to_threads(monkeypatch):
    _pythonpath(monkeypatch)
    base, vary = helpers.args(8)
    ref = tr.sweep(base, vary, **KW)
    with helpers.cluster() as cluster, Client(cluster) as client:
        res = tr.sweep(base, vary, executor=client.get_executor(), **KW)
        ran_on = set(client.run(os.getpid).values())
    assert os.getpid() not in ran_on  # the points were solved in the worker processes
    _bitwise(res, ref)


def test_worker_killed_mid_sweep(tmp_path, monkeypatch):
    """A worker dies (SIGKILL) inside a chunk; the nanny restarts it and the scheduler
    runs the lost chunk again: every point is there, equal bit for bit to threads."""
    _pythonpath(monkeypatch)
    base, vary = helpers.args(8)
    marker = tmp_path / "killed"
    measure = helpers.KillOnce(str(marker), vary["loads[0].force"][5][0])
    with helpers.cluster() as cluster, Client(cluster) as client:
        pids = set(client.run(os.getpid).values())
        res = tr.sweep(base, vary, measure=measure, executor=client.get_executor(), **KW)
    killed = int(marker.read_text())
    assert killed in pids  # a worker process ran the killing measure ...
    assert not pathlib.Path(f"/proc/{killed}").exists()  # ... and is gone
    assert res.success.all()
    ref = tr.sweep(base, vary, measure=measure, **KW)  # threads (the marker stops the kill)
    _bitwise(res, ref)


def test_driver_killed_then_resumed(tmp_path, monkeypatch):
    """The driver process (with its cluster) is killed with SIGKILL half way; the same
    sweep with the same file finishes it: every chunk once in the file, the chunks on disk
    before the kill kept and not run again, the result bitwise an uninterrupted run's."""
    _pythonpath(monkeypatch)
    path = tmp_path / "sweep.jsonl"
    # a session of its own: the kill takes the driver and its cluster's processes together
    # (no orphaned workers)
    proc = subprocess.Popen(
        # (imported by name, not run as __main__: the measure's name is in the fingerprint)
        [sys.executable, "-c", "import sys, dask_sweep_helpers as h; h.drive(sys.argv[1])", path],
        start_new_session=True,
    )
    try:
        # wait (no time limit asserted) until the header and 3 of 12 chunks are on disk
        while not (path.exists() and path.read_bytes().count(b"\n") >= 4):
            assert proc.poll() is None, "the sweep finished or died before it could be killed"
            time.sleep(0.02)
        os.killpg(proc.pid, signal.SIGKILL)
    finally:
        proc.wait()
    assert proc.returncode == -signal.SIGKILL
    before = path.read_bytes()
    before = before[: before.rfind(b"\n") + 1]
    n_done = before.count(b"\n") - 1
    assert 3 <= n_done < 12, n_done  # killed part way (9 chunks, >= 1.8 s of work, left)

    base, vary = helpers.args()
    with helpers.cluster() as cluster, Client(cluster) as client:
        resumed = tr.sweep(
            base,
            vary,
            measure=helpers.slow_measure,
            executor=client.get_executor(),
            file=str(path),
            **KW,
        )
    after = path.read_bytes()
    assert after.startswith(before)  # finished chunks kept, not redone
    chunks = [json.loads(line)["chunk"] for line in after.splitlines()[1:]]
    assert sorted(chunks) == list(range(12))  # every chunk exactly once
    assert resumed.success.all()
    # an uninterrupted run on threads (no file) gives bitwise the same result
    full = tr.sweep(base, vary, measure=helpers.slow_measure, **KW)
    _bitwise(resumed, full)
