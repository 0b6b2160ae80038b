"""tendonrod.sweep: paths into frozen dataclasses; results equal the same solves in
series (bitwise, same chunking); executors honoured; failed points recorded; a sweep
killed with SIGKILL resumes and ends with identical results."""

import concurrent.futures as cf
import json
import math
import multiprocessing
import os
import pickle
import signal
import subprocess
import sys
import textwrap
import time
import warnings

import numpy as np
import pytest

import tendonrod as tr
from tendonrod.sweeps import (
    OUTCOME_ERROR,
    OUTCOME_NOT_CONVERGED,
    OUTCOME_OK,
    STATUS_NONE,
    SweepResult,
    get_path,
    set_path,
    tip_measure,
)


def ivb_robot(n=1, EA=math.inf):
    rod = tr.Rod(length=0.1, diameter=1.04e-3, E=210e9, G=80e9, kirchhoff=True)
    return tr.Robot(
        rod, [tr.Tendon(offset=0.01, angle=2 * math.pi * i / n, EA=EA) for i in range(n)]
    )


def base_scene():
    """One locked parallel tendon (q = 0) and a tip load to be varied."""
    return tr.Scene(
        ivb_robot(), displacement=[0.0], loads=[tr.PointLoad(s=0.1, force=(0.0, 0.0, 0.0))]
    )


FORCES = [(-f, 0.0, 0.0) for f in np.linspace(0.1, 1.2, 8)]


# --------------------------------------------------------------------------- paths
def test_set_get_path():
    sc = base_scene()
    assert get_path(sc, "robot.tendons[0].offset") == 0.01
    sc2 = set_path(sc, "robot.tendons[0].EA", 1e5)
    assert (
        sc2.robot.tendons[0].EA == 1e5 and sc.robot.tendons[0].EA == math.inf
    )  # copy, not mutation
    assert set_path(sc, "loads[0].force", (1.0, 2.0, 3.0)).loads[0].force == (1.0, 2.0, 3.0)
    assert set_path(sc, "loads[0].force[2]", -4.0).loads[0].force == (0.0, 0.0, -4.0)
    assert set_path(sc, "displacement[0]", 0.003).displacement == (0.003,)
    assert set_path(sc, "robot.rod.length", 0.2).robot.rod.length == 0.2
    for bad, words in [
        ("robot.tendonz[0]", "no field"),
        ("robot.tendons[3]", "out of range"),
        ("robot..rod", "cannot parse"),
        ("robot.rod[0]", "not a sequence"),
    ]:
        with pytest.raises(ValueError, match=words):
            set_path(sc, bad, 1.0)
    with pytest.raises(ValueError, match="offset"):  # the dataclass's own validation runs
        set_path(sc, "robot.tendons[0].offset", -1.0)


def test_bad_arguments():
    sc = base_scene()
    with pytest.raises(ValueError, match="equal lengths"):
        tr.sweep(sc, {"loads[0].force": FORCES, "robot.rod.length": [0.1]}, grid=False)
    with pytest.raises(ValueError, match="no field"):
        tr.sweep(sc, {"robot.rodd.length": [0.1]})
    with pytest.raises(ValueError, match="chunksize"):
        tr.sweep(sc, {"loads[0].force": FORCES}, chunksize=0)


# --------------------------------------------------------------------------- equals series
def series(scenes, chunksize, options=None, measure=tip_measure):
    """The same solves by hand: warm start from the previous converged solution,
    restarting cold at every chunk boundary."""
    out = []
    for c in range(0, len(scenes), chunksize):
        guess = None
        for sc in scenes[c : c + chunksize]:
            sol = tr.solve(sc, guess=guess, options=options)
            out.append((sol.success, measure(sc, sol)))
            if sol.success:
                guess = sol
    return out


def test_equals_series_bitwise_and_shapes():
    sc = base_scene()
    res = tr.sweep(sc, {"loads[0].force": FORCES}, grid=False, chunksize=3, progress=False)
    # the default measure reads tip quantities only, so the sweep solves with tip_only=True
    ref = series(
        [set_path(sc, "loads[0].force", f) for f in FORCES], 3, options=tr.Options(tip_only=True)
    )
    assert res.shape == (8,) and res.success.all()
    for i, (ok, m) in enumerate(ref):
        assert ok
        for k, v in m.items():
            assert np.array_equal(res[k][i], v), (i, k)  # bitwise: same solves, same order
    assert np.array_equal(res["loads[0].force"], np.array(FORCES))
    # the tendon tightens as the load pushes the tip away from it (closed-form sign)
    assert np.all(np.diff(res["tension"][:, 0]) > 0)


def test_grid_shape_and_chunking_independence():
    sc = base_scene()
    EAs = [1e4, 1e6, math.inf]
    res = tr.sweep(sc, {"robot.tendons[0].EA": EAs, "loads[0].force": FORCES[:4]}, progress=False)
    assert res.shape == (3, 4) and res["tip_position"].shape == (3, 4, 3) and res.chunksize == 4
    assert res["robot.tendons[0].EA"][:, 0].tolist() == EAs
    res1 = tr.sweep(
        sc, {"robot.tendons[0].EA": EAs, "loads[0].force": FORCES[:4]}, chunksize=1, progress=False
    )
    # other chunking, other warm starts: equal to the solver tolerance (1e-10 scaled residual;
    # 1e-12 m on a 0.1 m robot is well above it and far below anything physical)
    assert np.allclose(res["tip_position"], res1["tip_position"], rtol=0, atol=1e-12)
    # stiffer tendon -> smaller deflection under the same load (eq. 9)
    assert np.all(np.diff(-res["tip_position"][:, -1, 0]) < 0)


@pytest.mark.parametrize("kind", ["thread", "process"])
def test_executor_honoured(kind):
    sc = base_scene()
    ref = tr.sweep(
        sc, {"loads[0].force": FORCES}, grid=False, chunksize=2, workers=1, progress=False
    )
    submitted = []

    if kind == "thread":
        ex = cf.ThreadPoolExecutor(max_workers=3)
    else:
        ex = cf.ProcessPoolExecutor(max_workers=2, mp_context=multiprocessing.get_context("spawn"))

    class Counting(cf.Executor):  # proves the sweep used *our* executor
        def submit(self, fn, *a, **k):
            submitted.append(1)
            return ex.submit(fn, *a, **k)

    try:
        res = tr.sweep(
            sc,
            {"loads[0].force": FORCES},
            grid=False,
            chunksize=2,
            executor=Counting(),
            progress=False,
        )
    finally:
        ex.shutdown()
    assert len(submitted) == 4
    for k in ref.data:
        assert np.array_equal(res[k], ref[k]), k  # bitwise across executors
    assert pickle.loads(pickle.dumps(res)).data.keys() == res.data.keys()


# --------------------------------------------------------------------------- failures
def test_failed_points_recorded_and_sweep_continues():
    sc = base_scene()
    offsets = [0.01, -0.01, 0.02]  # -0.01: the Tendon rejects it (build fails)
    with pytest.warns(tr.ConvergenceWarning, match="2 of 6"):
        res = tr.sweep(
            sc, {"robot.tendons[0].offset": offsets, "loads[0].force": FORCES[:2]}, progress=False
        )
    # a scene the builder cannot build: an error without a core status, NaN values
    assert res.outcome[1].tolist() == [OUTCOME_ERROR] * 2
    assert res.status[1].tolist() == [STATUS_NONE] * 2
    assert "offset" in res.message[1, 0] and np.isnan(res["tip_position"][1]).all()
    assert res.success[[0, 2]].all() and (res.status[[0, 2]] == 0).all()
    assert res.outcome.dtype == np.int8 and res.status.dtype == np.int16
    fails = res.failures()
    assert [f[:3] for f in fails] == [((1, 0), OUTCOME_ERROR, STATUS_NONE)] + [
        ((1, 1), OUTCOME_ERROR, STATUS_NONE)
    ]
    assert all("offset" in f[3] for f in fails)
    assert "4/6 ok (2 error)" in repr(res)
    # non-convergence: one iteration, no continuation, cold starts -- a tip load of
    # F L^2/EI = 2.5 cannot be solved in one step; the unloaded robot is solved by the
    # initial guess itself
    opts = tr.Options(max_iter=1, continuation=False)
    with pytest.warns(tr.ConvergenceWarning, match="1 of 3"):
        res2 = tr.sweep(
            sc,
            {"loads[0].force": [(0.0, 0.0, 0.0), (-3.0, 0.0, 0.0), (0.0, 0.0, 0.0)]},
            grid=False,
            options=opts,
            warm_start=False,
            progress=False,
        )
    assert res2.outcome.tolist() == [OUTCOME_OK, OUTCOME_NOT_CONVERGED, OUTCOME_OK]
    # the non-converged point keeps its solve's (negative) core status, named by the core
    with pytest.warns(tr.ConvergenceWarning):  # the same cold solve
        one = tr.solve(set_path(sc, "loads[0].force", (-3.0, 0.0, 0.0)), options=opts)
    assert not one.success and one.status < 0
    assert res2.status.tolist() == [0, one.status, 0]
    assert res2.message[1] == one.message and res2.nit[1] >= 1
    assert tr._core.strerror(int(res2.status[1])) != "unknown status"
    assert res2.failures() == [((1,), OUTCOME_NOT_CONVERGED, one.status, one.message)]


def _series_status(scenes, chunksize, options):
    """The core status of each point solved by hand as the sweep does (warm within a
    chunk from the previous success, cold at each chunk boundary)."""
    out = []
    for c in range(0, len(scenes), chunksize):
        guess = None
        for sc in scenes[c : c + chunksize]:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", tr.ConvergenceWarning)
                sol = tr.solve(sc, guess=guess, options=options)
            out.append((sol.status, sol.success))
            if sol.success:
                guess = sol
    return out


@pytest.mark.parametrize("kind", ["batch", "per_point"])
def test_status_is_the_core_status_of_each_solve(kind, monkeypatch):
    """res.status is the status tr.solve gives the same point (same warm starts), on the
    batch path (a load component) and the per-point path (a design parameter); res.success
    is the solve's success and res.outcome follows it."""
    import tendonrod.sweeps._chunk as chunk_mod

    sc = set_path(base_scene(), "loads[0].force", (-1.0, 0.0, 0.0))
    # few iterations, no continuation: some points fail (warm-started from far away)
    opts = tr.Options(tip_only=True, max_iter=4, continuation=False)
    if kind == "batch":
        name, values = "loads[0].force[2]", [0.0, -0.5, -200.0, -1.0, 2.0, 0.5]
    else:
        name, values = "robot.rod.length", [0.1, 0.104, 0.2, 0.108, 0.1, 0.112]
    batched = []
    real_batch = chunk_mod.solve_batch
    monkeypatch.setattr(
        chunk_mod, "solve_batch", lambda *a, **k: batched.append(1) or real_batch(*a, **k)
    )
    with pytest.warns(tr.ConvergenceWarning, match="did not succeed"):
        res = tr.sweep(sc, {name: values}, grid=False, chunksize=3, options=opts, progress=False)
    assert bool(batched) == (kind == "batch")  # the path under test was taken
    ref = _series_status([set_path(sc, name, v) for v in values], 3, opts)
    assert res.status.tolist() == [st for st, _ in ref]
    assert res.success.tolist() == [ok for _, ok in ref]
    assert res.outcome.tolist() == [OUTCOME_OK if ok else OUTCOME_NOT_CONVERGED for _, ok in ref]
    assert res.status.dtype == np.int16 and res.outcome.dtype == np.int8
    assert any(ok for _, ok in ref) and not all(ok for _, ok in ref), ref  # both kinds


class _Restated:
    """A solve's result with ``status`` and ``success`` restated (everything else is the
    real result's): what the core returns for a caveat (status 1, 2, 4: success) or an
    unconfirmed off-path equilibrium (status 3: not a success)."""

    def __init__(self, real, status, success):
        self._real, self.status, self.success = real, status, success

    def __getattr__(self, name):
        return getattr(self._real, name)


@pytest.mark.parametrize("kind", ["batch", "per_point"])
def test_caveat_status_kept_and_outcome_from_success(kind, monkeypatch):
    """A converged solve with a caveat status (1 truncation) counts as a success and keeps
    its status; status 3 with success False does not: the outcome is read from the
    solve's success, never from the status number."""
    import tendonrod.sweeps._chunk as chunk_mod

    sc = base_scene()
    restated = {1: (1, True), 2: (3, False)}  # point -> (status, success)
    if kind == "batch":
        real = chunk_mod.solve_batch

        def fake(*a, **k):
            res = real(*a, **k)
            st, ok = res.status.copy(), res.success.copy()
            for p, (s, o) in restated.items():
                st[p], ok[p] = s, o
            return _Restated(res, st, ok)

        monkeypatch.setattr(chunk_mod, "solve_batch", fake)
        monkeypatch.setattr(chunk_mod, "solve", None)  # the per-point path must not run
    else:
        real = chunk_mod.solve
        count = iter(range(100))

        def fake(scene, guess=None, **k):
            guess = guess._real if isinstance(guess, _Restated) else guess  # warm starts
            sol, p = real(scene, guess=guess, **k), next(count)
            return _Restated(sol, *restated[p]) if p in restated else sol

        monkeypatch.setattr(chunk_mod, "solve", fake)
        monkeypatch.setattr(chunk_mod, "solve_batch", None)  # the batch path must not run
    vary = (
        {"loads[0].force": FORCES[:4]}
        if kind == "batch"
        else {"robot.tendons[0].EA": [1e5, 2e5, 3e5, 4e5]}
    )
    with pytest.warns(tr.ConvergenceWarning, match="1 of 4"):
        res = tr.sweep(sc, vary, grid=False, chunksize=4, workers=1, progress=False)
    assert res.status.tolist() == [0, 1, 3, 0]
    assert res.outcome.tolist() == [OUTCOME_OK, OUTCOME_OK, OUTCOME_NOT_CONVERGED, OUTCOME_OK]
    assert res.success.tolist() == [True, True, False, True]
    assert np.isfinite(res["tip_position"]).all()  # values of every solved point kept
    assert [f[:3] for f in res.failures()] == [((2,), OUTCOME_NOT_CONVERGED, 3)]
    assert "3/4 ok (1 not converged)" in repr(res)


def test_measure_error_keeps_the_solve_status():
    """measure raising after a solve returned: OUTCOME_ERROR, but the solve's status and
    nit are kept (STATUS_NONE is only for points no solve returned for)."""

    def bad_measure(scene, sol):
        raise RuntimeError("measure broke")

    with pytest.warns(tr.ConvergenceWarning, match="1 of 2|2 of 2"):
        res = tr.sweep(
            base_scene(),
            {"loads[0].force": FORCES[:2]},
            grid=False,
            measure=bad_measure,
            progress=False,
        )
    assert res.outcome.tolist() == [OUTCOME_ERROR] * 2
    assert res.status.tolist() == [0, 0] and (res.nit >= 0).all()
    assert all("measure broke" in f[3] for f in res.failures())


# --------------------------------------------------------------------------- resume
WORKER = textwrap.dedent("""
    import math, sys, time
    import numpy as np
    import tendonrod as tr
    from tendonrod.sweeps import tip_measure

    def slow_measure(scene, sol):
        time.sleep(0.1)          # slows the sweep down so that the test can kill it half way
        return tip_measure(scene, sol)

    def args():
        rod = tr.Rod(length=0.1, diameter=1.04e-3, E=210e9, G=80e9, kirchhoff=True)
        base = tr.Scene(tr.Robot(rod, [tr.Tendon(offset=0.01)]), displacement=[0.0],
                        loads=[tr.PointLoad(s=0.1, force=(0.0, 0.0, 0.0))])
        forces = [(-f, 0.0, 0.0) for f in np.linspace(0.05, 1.2, 24)]
        return base, {"loads[0].force": forces}

    def run(path):
        base, vary = args()
        return tr.sweep(base, vary, grid=False, chunksize=2, measure=slow_measure, file=path,
                        workers=1, progress=False)
""")


def _lines(path):
    with open(path, "rb") as fh:
        return fh.read().split(b"\n")


def test_resume_after_sigkill(tmp_path, monkeypatch):
    (tmp_path / "sweep_worker.py").write_text(WORKER)
    monkeypatch.syspath_prepend(str(tmp_path))
    import sweep_worker

    path = tmp_path / "sweep.jsonl"
    env = dict(os.environ, PYTHONPATH=str(tmp_path) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    proc = subprocess.Popen(
        [sys.executable, "-c", f"import sweep_worker; sweep_worker.run({str(path)!r})"], env=env
    )
    try:
        # wait (no time limit asserted) until the header and 4 of 12 chunks are on disk
        while not (path.exists() and len(_lines(path)) >= 6):
            assert proc.poll() is None, "the sweep finished or died before it could be killed"
            time.sleep(0.01)
        os.kill(proc.pid, signal.SIGKILL)
    finally:
        proc.wait()
    assert proc.returncode == -signal.SIGKILL
    before = path.read_bytes()
    n_done = before.count(b"\n") - 1
    assert 4 <= n_done < 12, n_done  # killed half way

    resumed = sweep_worker.run(str(path))
    after = path.read_bytes()
    assert after.startswith(before[: before.rfind(b"\n") + 1])  # finished chunks kept, not redone
    chunks = [json.loads(line)["chunk"] for line in after.splitlines()[1:]]
    assert sorted(chunks) == list(range(12))  # every chunk exactly once
    # an uninterrupted run (no file) gives bitwise the same result
    base, vary = sweep_worker.args()
    # (options as the resumed run had them: a custom measure gets the default Options())
    full = tr.sweep(base, vary, grid=False, chunksize=2, options=tr.Options(), progress=False)
    assert resumed.success.all()
    for k in full.data:
        assert np.array_equal(resumed[k], full[k]), k
    # a second call reads everything and solves nothing
    again = tr.sweep(
        base,
        vary,
        grid=False,
        chunksize=2,
        measure=sweep_worker.slow_measure,
        file=str(path),
        progress=False,
    )  # same sweep: nothing left to run
    assert path.read_bytes() == after
    assert all(np.array_equal(again[k], full[k]) for k in full.data)


def test_torn_last_line_and_foreign_file(tmp_path):
    sc = base_scene()
    path = tmp_path / "s.jsonl"
    full = tr.sweep(
        sc, {"loads[0].force": FORCES}, grid=False, chunksize=2, file=path, progress=False
    )
    text = path.read_bytes()
    path.write_bytes(text[:-25])  # a write cut short by a crash
    res = tr.sweep(
        sc, {"loads[0].force": FORCES}, grid=False, chunksize=2, file=path, progress=False
    )
    for k in full.data:
        assert np.array_equal(res[k], full[k]), k
    assert path.read_bytes().count(b"\n") == text.count(b"\n")
    with pytest.raises(ValueError, match="different sweep"):
        tr.sweep(
            sc, {"loads[0].force": FORCES[:3]}, grid=False, chunksize=2, file=path, progress=False
        )
    other = tmp_path / "notes.txt"
    other.write_text("my notes\n")
    with pytest.raises(ValueError, match="no sweep header"):
        tr.sweep(sc, {"loads[0].force": FORCES}, grid=False, file=other, progress=False)
    assert other.read_text() == "my notes\n"


def test_old_format_file_refused(tmp_path):
    """Format 2 stores "outcome" and "status" per point; a format-1 file (one "status",
    the sweep's own codes) is refused with a message naming the versions, never resumed
    from (its codes would read as core statuses) nor overwritten."""
    sc = base_scene()
    path = tmp_path / "s.jsonl"
    kw = dict(grid=False, chunksize=2, file=path, progress=False)
    tr.sweep(sc, {"loads[0].force": FORCES[:4]}, **kw)
    header, *chunks = [json.loads(line) for line in path.read_text().splitlines()]
    assert header["tendonrod_sweep"] == 2
    for rec in (r for c in chunks for r in c["records"]):
        assert rec["outcome"] == OUTCOME_OK and rec["status"] == 0
    # the same sweep as format 1 wrote it: version 1, the sweep's code under "status"
    lines = [dict(header, tendonrod_sweep=1)]
    for c in chunks:
        recs = [{k: v for k, v in r.items() if k != "outcome"} for r in c["records"]]
        for r, old in zip(recs, c["records"]):
            r["status"] = old["outcome"]
        lines.append(dict(c, records=recs))
    old_text = "".join(json.dumps(obj) + "\n" for obj in lines)
    path.write_text(old_text)
    with pytest.raises(ValueError, match=r"format version 1\b.*format version 2"):
        tr.sweep(sc, {"loads[0].force": FORCES[:4]}, **kw)
    assert path.read_text() == old_text
    path.write_text(json.dumps(dict(header, tendonrod_sweep=3)) + "\n")  # a newer one too
    with pytest.raises(ValueError, match="format version 3"):
        tr.sweep(sc, {"loads[0].force": FORCES[:4]}, **kw)


class PlainMeasure:
    """A callable object without a stable repr (its default repr holds its address)."""

    def __call__(self, scene, sol):
        return {"tip": sol.tip_position}


def test_resume_with_callable_object_measure(tmp_path):
    path = tmp_path / "m.jsonl"
    a = tr.sweep(
        base_scene(),
        {"loads[0].force": FORCES[:4]},
        grid=False,
        chunksize=2,
        measure=PlainMeasure(),
        file=path,
        progress=False,
    )
    size = path.stat().st_size
    b = tr.sweep(
        base_scene(),
        {"loads[0].force": FORCES[:4]},
        grid=False,
        chunksize=2,
        measure=PlainMeasure(),
        file=path,
        progress=False,
    )  # a new instance: same sweep, read back
    assert path.stat().st_size == size and np.array_equal(a["tip"], b["tip"])


def test_result_is_picklable_dataclass():
    res = tr.sweep(base_scene(), {"loads[0].force": FORCES[:2]}, grid=False, progress=False)
    back = pickle.loads(pickle.dumps(res))
    assert isinstance(back, SweepResult) and np.array_equal(
        back["tip_position"], res["tip_position"]
    )


def test_compliance_measure():
    from tendonrod.sweeps import ComplianceMeasure

    sc = base_scene()
    res = tr.sweep(
        sc,
        {"loads[0].force": FORCES[:3]},
        grid=False,
        measure=ComplianceMeasure(s=(0.05, None)),
        chunksize=1,
        progress=False,
    )
    assert res["compliance"].shape == (3, 2, 6, 6)
    for i, f in enumerate(FORCES[:3]):
        scene = set_path(sc, "loads[0].force", f)
        # same scene, same (cold) solve inside tr.compliance: bitwise equal
        assert np.array_equal(res["compliance"][i, 1], tr.compliance(scene))
        assert np.array_equal(res["compliance"][i, 0], tr.compliance(scene, s=0.05))
