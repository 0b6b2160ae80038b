"""Threads, determinism and pickling.

- Many threads solving different scenes at once give bitwise the same results
  as the same solves in series (the core keeps no global state, each solve
  owns its workspace, and the glue releases the GIL around the core).
- The same input gives bitwise the same output, run to run: in one process,
  and across fresh interpreter processes (spawned, so nothing is inherited).
- Scenes, robots, options and solutions pickle and unpickle (process pools
  and distributed executors send them between processes), and a solution
  that went through a process pool is bitwise the one solved here.
Speed-up with threads is measured by bench/threads.py, not asserted here.
"""

import concurrent.futures as cf
import hashlib
import math
import multiprocessing
import os
import pickle
import random
import subprocess
import sys
import warnings

import numpy as np
import pytest

import tendonrod as tr

# Some scenes of the thread tests do not converge on purpose.  solve_quiet's
# warnings.catch_warnings is not thread-safe (it swaps the process-wide filters, so one
# thread leaving it restores the suite's "error" filter under another thread's solve):
# the ConvergenceWarning is let through for the whole module instead.
pytestmark = pytest.mark.filterwarnings("ignore::tendonrod.ConvergenceWarning")

ROD = dict(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9)
FIELDS = ("s", "position", "rotation", "force", "moment", "tension", "slack", "displacement")
SCALARS = ("success", "status", "message", "nit", "nfev", "njev", "residual_norm")


def scenes():
    """24 different scenes: planar and spatial, Kirchhoff and Cosserat,
    displacement and tension control, tip, mid-span and distributed loads."""
    out = []
    L = ROD["length"]
    for i in range(6):
        # one parallel tendon, displacement-controlled, tip load growing
        robot = tr.Robot(tr.Rod(**ROD, kirchhoff=True), [tr.Tendon(offset=0.01)])
        out.append(
            tr.Scene(
                robot,
                displacement=[0.002 + 0.002 * i],
                loads=[tr.PointLoad(s=L, force=(-0.1 * i, 0, 0))],
            )
        )
    for i in range(6):
        # converging tendon, tension-controlled, Cosserat backbone, gravity
        robot = tr.Robot(tr.Rod(**ROD), [tr.Tendon.converging(offset=0.01, length=L)])
        out.append(
            tr.Scene(
                robot, tension=[0.5 + 0.5 * i], loads=[tr.DistributedLoad(force=(0, 0, -0.2 * i))]
            )
        )
    for i in range(6):
        # three tendons at 120 deg, spatial loads
        ts = [tr.Tendon(offset=0.01, angle=2 * math.pi * k / 3, EA=2e4) for k in range(3)]
        robot = tr.Robot(tr.Rod(**ROD), ts)
        out.append(
            tr.Scene(
                robot,
                displacement=[0.003 + 0.001 * i, 0.0, None],
                tension=[None, None, 0.2 * i],
                loads=[
                    tr.PointLoad(s=L, force=(0.05 * i, 0.1, 0), moment=(0, 0, 0.001 * i)),
                    tr.PointLoad(s=0.6 * L, force=(0, -0.05 * i, 0)),
                ],
            )
        )
    for i in range(6):
        # two tendons ending at different places (two segments), one slack-prone
        ts = [tr.Tendon(offset=0.008, end=0.5 * L), tr.Tendon(offset=0.008, angle=math.pi)]
        robot = tr.Robot(tr.Rod(**ROD, kirchhoff=True), ts)
        out.append(
            tr.Scene(
                robot,
                displacement=[0.004, -0.001 * i],
                loads=[tr.PointLoad(s=L, force=(0.2 * i, 0, 0))],
            )
        )
    return out


def solve_quiet(scene, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tr.ConvergenceWarning)
        return tr.solve(scene, **kw)


def fingerprint(sol):
    """Every output bit of a solution, as bytes (NaN-safe: compares bit patterns)."""
    h = hashlib.sha256()
    for f in FIELDS:
        a = np.ascontiguousarray(getattr(sol, f), dtype=np.float64)
        h.update(f.encode() + repr(a.shape).encode() + a.tobytes())
    for f in SCALARS:
        v = getattr(sol, f)
        h.update(
            f.encode() + (np.float64(v).tobytes() if isinstance(v, float) else repr(v).encode())
        )
    return h.hexdigest()


def assert_same(a, b, what):
    for f in FIELDS:
        x, y = np.asarray(getattr(a, f)), np.asarray(getattr(b, f))
        assert x.shape == y.shape and x.tobytes() == y.tobytes(), f"{what}: {f} differs"
    for f in SCALARS:
        x, y = getattr(a, f), getattr(b, f)
        assert (x == y) or (
            isinstance(x, float) and np.float64(x).tobytes() == np.float64(y).tobytes()
        ), f"{what}: {f} differs ({x!r} vs {y!r})"


@pytest.fixture(scope="module")
def serial():
    sc = scenes()
    sols = [solve_quiet(s) for s in sc]
    # most of them must really solve: a test of determinism on failures only
    # would prove little
    assert sum(s.success for s in sols) >= 20, [s.message for s in sols if not s.success]
    return sc, sols


def test_solve_is_deterministic_in_series(serial):
    sc, sols = serial
    for i, s in enumerate(sc):
        assert_same(solve_quiet(s), sols[i], f"scene {i}, second solve")


@pytest.mark.parametrize("workers", [2, 4, 8])
def test_threads_give_bitwise_the_serial_results(serial, workers):
    """Different scenes solved at once on several threads, in a shuffled
    order, three rounds: bitwise the serial results."""
    sc, sols = serial
    order = list(range(len(sc))) * 3
    random.Random(workers).shuffle(order)
    with cf.ThreadPoolExecutor(max_workers=workers) as ex:
        futs = [(i, ex.submit(solve_quiet, sc[i])) for i in order]
        for i, f in futs:
            assert_same(f.result(), sols[i], f"scene {i} on {workers} threads")


def test_threads_share_one_scene(serial):
    """Several threads solving the same Scene object at the same time."""
    sc, sols = serial
    with cf.ThreadPoolExecutor(max_workers=4) as ex:
        res = list(ex.map(solve_quiet, [sc[13]] * 16))
    for r in res:
        assert_same(r, sols[13], "shared scene")


def test_threads_warm_started(serial):
    """Warm starts from a shared Solution on several threads (the guess and
    its Jacobian are read, never written): bitwise the serial warm solves."""
    sc, sols = serial
    pairs = [(sc[i + 1], sols[i]) for i in (0, 6, 12, 18)]
    want = [solve_quiet(s, guess=g) for s, g in pairs]
    with cf.ThreadPoolExecutor(max_workers=4) as ex:
        got = list(ex.map(lambda p: solve_quiet(p[0], guess=p[1]), pairs * 4))
    for k, g in enumerate(got):
        assert_same(g, want[k % 4], f"warm start {k % 4} on threads")


def test_compliance_on_threads(serial):
    sc, _ = serial
    picks = [sc[1], sc[8], sc[14]]
    want = [tr.compliance(s) for s in picks]
    with cf.ThreadPoolExecutor(max_workers=3) as ex:
        got = list(ex.map(tr.compliance, picks * 3))
    for k, g in enumerate(got):
        assert np.asarray(g).tobytes() == np.asarray(want[k % 3]).tobytes()


# ------------------------------------------------------------------ pickling
def test_scene_objects_pickle(serial):
    sc, _ = serial
    objs = [
        sc[15],
        sc[15].robot,
        sc[15].robot.rod,
        sc[15].robot.tendons[0],
        sc[15].loads[0],
        tr.DistributedLoad(force=(0, 0, -1)),
        tr.Options(integrator="rk4", steps=40, nodes=np.linspace(0, 0.2, 5), tip_only=True),
        tr.Options(),
    ]
    for o in objs:
        for proto in (2, pickle.HIGHEST_PROTOCOL):
            u = pickle.loads(pickle.dumps(o, protocol=proto))
            assert type(u) is type(o) and u == o, (o, u)


def test_solution_pickles(serial):
    sc, sols = serial
    for i in (0, 9, 15, 20):
        u = pickle.loads(pickle.dumps(sols[i]))
        assert isinstance(u, tr.Solution)
        assert_same(u, sols[i], f"unpickled solution {i}")
        assert u.scene == sc[i] and u.formulation == sols[i].formulation
        # an unpickled solution still warm-starts and answers at(s)
        assert_same(
            solve_quiet(sc[i], guess=u),
            solve_quiet(sc[i], guess=sols[i]),
            "warm start from an unpickled solution",
        )
        st = u.at(0.1)
        assert np.asarray(st.position).shape == (3,)


def test_unpickled_scene_solves_bitwise_the_same(serial):
    sc, sols = serial
    for i in (2, 11, 16):
        assert_same(solve_quiet(pickle.loads(pickle.dumps(sc[i]))), sols[i], f"scene {i}")


def test_convergence_error_pickles():
    """A ConvergenceError raised in a worker process comes back whole."""
    robot = tr.Robot(tr.Rod(**ROD, kirchhoff=True), [tr.Tendon(offset=0.01)])
    scene = tr.Scene(robot, displacement=[0.01], loads=[tr.PointLoad(s=0.2, force=(-3, 0, 0))])
    opts = tr.Options(max_iter=1, continuation=False)
    with pytest.raises(tr.ConvergenceError) as e:
        tr.solve(scene, options=opts, strict=True)
    u = pickle.loads(pickle.dumps(e.value))
    assert type(u) is tr.ConvergenceError and str(u) == str(e.value)
    assert isinstance(u.solution, tr.Solution) and u.solution.success is False


# --------------------------------------------------------------- processes
def test_process_pool_results_are_bitwise_the_local_ones(serial):
    """Scenes sent to spawned worker processes (fresh interpreters: a different
    address-space layout, nothing inherited) and solutions sent back: bitwise
    the solutions of this process."""
    sc, sols = serial
    ctx = multiprocessing.get_context("spawn")
    picks = list(range(0, 24, 3))
    with cf.ProcessPoolExecutor(max_workers=2, mp_context=ctx) as ex:
        got = list(ex.map(solve_quiet, [sc[i] for i in picks]))
    for i, g in zip(picks, got):
        assert_same(g, sols[i], f"scene {i} from a process pool")


FP_SCRIPT = r"""
import sys, warnings, importlib.util
spec = importlib.util.spec_from_file_location("tt", sys.argv[1])
tt = importlib.util.module_from_spec(spec); spec.loader.exec_module(tt)
for s in tt.scenes():
    print(tt.fingerprint(tt.solve_quiet(s)))
"""


def test_fingerprints_match_a_fresh_process(serial):
    """Run to run: a fresh `python` process computes the same SHA-256 of every
    output bit of every scene."""
    from cpu_guard import limited  # (here: the child imports this module without tests/)

    sc, sols = serial
    root = os.path.dirname(os.path.dirname(os.path.abspath(tr.__file__)))
    env = dict(os.environ)
    env["PYTHONPATH"] = root + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    out = subprocess.run(
        [sys.executable, "-c", FP_SCRIPT, os.path.abspath(__file__)],
        capture_output=True,
        text=True,
        env=env,
        **limited(600),  # a hang guard of 600 s of CPU
    )
    assert out.returncode == 0, out.stderr[-3000:]
    theirs = out.stdout.split()
    assert theirs == [fingerprint(s) for s in sols]


def test_solve_batch_threads_bitwise():
    """tr.solve_batch: for a given chunking the result does not depend on the
    number of threads (chunks are independent), bitwise."""
    sc = scenes()[12]  # three tendons, spatial
    n = 40
    q = np.column_stack([np.linspace(0.0, 0.006, n), np.linspace(0.0, 0.002, n)])
    t = np.linspace(0.0, 1.0, n)[:, None]
    F = np.zeros((n, 2, 3))
    F[:, 0, 1] = np.linspace(0.0, 0.2, n)
    runs = [
        tr.solve_batch(sc, displacement=q, tension=t, forces=F, workers=th, chunksize=7)
        for th in (1, 2, 4, 1)
    ]
    for r in runs[1:]:
        for f in ("tip_position", "tip_rotation", "tension", "slack", "status", "nit", "nfev"):
            assert (
                np.asarray(getattr(r, f)).tobytes() == np.asarray(getattr(runs[0], f)).tobytes()
            ), f
    assert np.all(np.asarray(runs[0].status) >= 0)
