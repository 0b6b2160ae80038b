"""Bounded work: every solve is capped by its options, and pathological input
returns within those caps -- with success=False and a message, or with a
solution that is correct.

Each case runs in a subprocess so that a hang or a crash fails that case and
not the run; the subprocess has a generous CPU-time limit (HANG_GUARD, set with
RLIMIT_CPU: the work the child did, whatever the load of the machine) that is a
hang detector, not a speed requirement, and a wall-clock backstop far beyond it
for a child blocked without using CPU.  What is asserted is the work the solver
reports:
  - nfev <= max_nfev + NFEV_SLACK (see below),
  - continuation_steps <= max_continuation,
  - nit <= max_iter * (1 + continuation_steps) (each continuation stage is a
    Newton run capped by max_iter),
  - a failure has a message that says what to do, and strict=True raises
    ConvergenceError.
"""

import math
import os
import pickle
import signal
import subprocess
import sys

import numpy as np
import pytest
from cpu_guard import limited

import tendonrod as tr

# CPU seconds; a capped solve takes milliseconds to ~1 s (one work budget, the dense
# linear algebra of 64 shooting segments included).  cpu_guard stretches it by
# TR_HANG_GUARD_SCALE for instrumented runs (make sanitize).
HANG_GUARD = 120.0
# The nfev cap is tested between Newton trials: one finite-difference Jacobian
# (n_unknowns <= 6 + n_tendons evaluations), the step-count verification (a
# couple of evaluations) and the recording pass may follow the last check.
NFEV_SLACK = 32

ROD = dict(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9)
L = ROD["length"]
EI = 207e9 * math.pi * 0.8e-3**4 / 64


def _k():
    return tr.Rod(**ROD, kirchhoff=True)


def _c():
    return tr.Rod(**ROD)


def cases():
    """name -> (scene, options).  Pathological on purpose."""
    one = tr.Robot(_k(), [tr.Tendon(offset=0.01)])
    two = tr.Robot(_k(), [tr.Tendon(offset=0.01), tr.Tendon(offset=0.01, angle=math.pi)])
    cos3 = tr.Robot(
        _c(), [tr.Tendon(offset=0.01, angle=2 * math.pi * i / 3, EA=2e4) for i in range(3)]
    )
    P_euler = math.pi**2 * EI / (4 * L**2)
    tight = tr.Options(max_iter=5, max_nfev=200, max_continuation=3)
    return {
        # the tendon would have to be shorter than zero: no equilibrium
        "pull beyond the length": (tr.Scene(one, displacement=[2 * L]), tr.Options()),
        "pull into itself": (tr.Scene(one, displacement=[0.05]), tr.Options()),
        "push a tendon far": (tr.Scene(one, displacement=[-0.5]), tr.Options()),
        # opposing inextensible tendons on an inextensible backbone, both pulled
        "opposing pair pulled": (tr.Scene(two, displacement=[0.001, 0.001]), tr.Options()),
        "opposing pair at zero": (tr.Scene(two, displacement=[0.0, 0.0]), tr.Options()),
        # 100x the buckling load, straight down, with a tiny lateral push
        "far past buckling": (
            tr.Scene(
                one, displacement=[0.0], loads=[tr.PointLoad(s=L, force=(1e-6, 0, -100 * P_euler))]
            ),
            tr.Options(),
        ),
        # tensile load with L sqrt(T/EI) = 40 and a lateral load: single shooting's bane
        "stiff tensile": (
            tr.Scene(
                one,
                displacement=[0.004],
                loads=[tr.PointLoad(s=L, force=(0.5, 0, 1600 * EI / L**2))],
            ),
            tr.Options(),
        ),
        # fixed steps: with automatic steps this scene takes 164 s (finding F13)
        "huge force": (
            tr.Scene(
                cos3,
                displacement=[0.003, 0.0, 0.0],
                loads=[tr.PointLoad(s=L, force=(1e6, -1e6, 1e6), moment=(1e3, 0, -1e3))],
            ),
            tr.Options(steps=64),
        ),
        "huge tension": (tr.Scene(one, tension=[1e9]), tr.Options()),
        "tiny rod": (
            tr.Scene(
                tr.Robot(
                    tr.Rod(length=1e-6, diameter=1e-7, E=1e9, G=4e8, kirchhoff=True),
                    [tr.Tendon(offset=4e-8)],
                ),
                displacement=[1e-8],
                loads=[tr.PointLoad(s=1e-6, force=(1e-3, 0, 0))],
            ),
            tr.Options(),
        ),
        "unreachable tol": (
            tr.Scene(
                cos3,
                displacement=[0.003, 0.001, 0.0],
                loads=[tr.PointLoad(s=L, force=(0.1, 0.2, 0))],
            ),
            tr.Options(tol=1e-300, max_iter=20),
        ),
        "tight caps, hard scene": (
            tr.Scene(one, displacement=[0.03], loads=[tr.PointLoad(s=L, force=(-2, 0, 0))]),
            tight,
        ),
        "one evaluation": (
            tr.Scene(
                cos3, displacement=[0.01, 0.0, 0.0], loads=[tr.PointLoad(s=L, force=(0, 1, 0))]
            ),
            tr.Options(max_nfev=1),
        ),
        "adaptive, tight rtol": (
            tr.Scene(
                cos3, displacement=[0.01, 0.0, 0.0], loads=[tr.PointLoad(s=L, force=(0, 1, 0))]
            ),
            tr.Options(integrator="adaptive", rtol=1e-14, max_nfev=200),
        ),  # tightest accepted (F14)
        "many continuation stages": (
            tr.Scene(two, displacement=[0.05, 0.0], loads=[tr.PointLoad(s=L, force=(5, 0, -5))]),
            tr.Options(max_iter=3, max_continuation=1000, max_nfev=2000),
        ),
    }


RUNNER = r"""
import pickle, sys, warnings
import tendonrod as tr
scene, options = pickle.load(sys.stdin.buffer)
try:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tr.ConvergenceWarning)
        sol = tr.solve(scene, options=options)
except (ValueError, TypeError) as e:     # refused before (or instead of) solving
    sys.stdout.buffer.write(pickle.dumps(dict(refused=type(e).__name__, message=str(e))))
    sys.exit(0)
try:
    tr.solve(scene, options=options, strict=True)
    strict = "returned"
except tr.ConvergenceError as e:
    strict = "raised"
out = dict(success=sol.success, status=sol.status, message=sol.message, nit=sol.nit,
           nfev=sol.nfev, njev=sol.njev, cont=sol.continuation_steps, work=sol.raw["work"],
           residual=sol.residual_norm, strict=strict, sol=sol)
sys.stdout.buffer.write(pickle.dumps(out))
"""


def run_guarded(args, cpu, **kwargs):
    """subprocess.run(args) with tendonrod on the path, under cpu_guard's limits: stopped
    by the kernel (SIGXCPU) after ``cpu`` seconds of CPU time, or by the wall-clock
    backstop; a stopped child fails the test as unbounded work."""
    root = os.path.dirname(os.path.dirname(os.path.abspath(tr.__file__)))
    env = dict(os.environ)
    env["PYTHONPATH"] = root + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    env["OPENBLAS_NUM_THREADS"] = "1"  # CPU time is the solve's, not idle BLAS threads'
    guard = limited(cpu)
    try:
        p = subprocess.run(args, capture_output=True, env=env, **guard, **kwargs)
    except subprocess.TimeoutExpired:
        pytest.fail(f"the child did not return within {guard['timeout']} s: blocked")
    if p.returncode == -signal.SIGXCPU:
        pytest.fail(f"the child used more than {cpu} s of CPU time: unbounded work")
    return p


def run_isolated(scene, options):
    p = run_guarded(
        [sys.executable, "-c", RUNNER], HANG_GUARD, input=pickle.dumps((scene, options))
    )
    assert p.returncode == 0, (
        f"the solve crashed (exit {p.returncode}):\n{p.stderr.decode()[-3000:]}"
    )
    return pickle.loads(p.stdout)


CASES = cases()


@pytest.mark.parametrize("name", list(CASES))
def test_pathological_solves_stay_within_their_caps(name):
    scene, opts = CASES[name]
    r = run_isolated(scene, opts)
    if "refused" in r:
        # a scene the core can tell has no (unique) equilibrium is refused up front,
        # with a message that names the tendons and says what to change
        assert "tendon" in r["message"] and len(r["message"]) > 40, r
        return
    note = (
        f"{name}: {r['message']!r} nit {r['nit']} nfev {r['nfev']} cont {r['cont']} "
        f"work {r['work']:.3g}"
    )
    assert r["nfev"] <= opts.max_nfev + NFEV_SLACK, note
    assert r["cont"] <= opts.max_continuation, note
    assert r["nit"] <= opts.max_iter * (1 + r["cont"]), note
    # the work the solver counted (budget units, the dense LU included), within one
    # budget whatever the formulation: an LU the budget cannot pay for is not started,
    # and the checks sit inside every integration; the final outputs (recording pass,
    # condition estimate) are computed beyond it (1e6 units covers them here)
    assert r["work"] <= opts.max_work + 1e6, note
    if r["success"]:
        sol = r["sol"]
        # above tol only at the residual's round-off floor, and then saying so
        assert r["residual"] <= opts.tol or (
            r["status"] == tr._core.STATUS_ROUNDOFF and "round-off floor" in r["message"]
        ), note
        for f in ("position", "rotation", "force", "moment", "tension", "slack"):
            assert np.all(np.isfinite(getattr(sol, f))), note
        assert np.all(sol.tension >= 0) and np.all(sol.slack >= 0), note
        assert r["strict"] == "returned", note
    else:
        assert isinstance(r["message"], str) and len(r["message"]) > 10, note
        assert r["strict"] == "raised", note


def test_one_budget_whatever_the_formulation():
    """A hopeless solve with default options stops within one default budget (the
    promise of TR_DEFAULT_MAX_WORK: ~0.7 s whatever the formulation), counted in budget
    units, not seconds."""
    scene, _ = CASES["huge force"]
    opts = tr.Options()
    for o in (opts, tr.Options(steps=64)):  # 64 automatic segments; 64 segments, fixed steps
        r = run_isolated(scene, o)
        assert r["sol"].raw["formulation"]["n_segments"] == 64, r["sol"].raw["formulation"]
        # the final outputs are computed beyond the budget (1e6 units covers them here)
        assert not r["success"] and r["work"] <= opts.max_work + 1e6, (r["work"], r["message"])
        assert "max_work" in r["message"], r["message"]


def test_caps_are_reported_by_name():
    """A solve stopped by a cap says which cap, so the user knows what to raise."""
    scene, _ = CASES["tight caps, hard scene"]
    r = run_isolated(scene, tr.Options(max_iter=1, continuation=False))
    assert not r["success"] and "max_iter" in r["message"], r["message"]
    r = run_isolated(scene, tr.Options(max_nfev=3, continuation=False))
    assert not r["success"] and "max_nfev" in r["message"], r["message"]


@pytest.mark.parametrize("max_nfev", [1, 10, 65])
def test_max_nfev_holds_with_singular_jacobians(max_nfev):
    """Three identical displacement-controlled tendons (a singular Jacobian),
    found by the fuzzer: the evaluation cap must still hold."""
    Lf = 0.071038186956448798
    rob = tr.Robot(
        tr.Rod(length=Lf, EI=0.0181125, GJ=0.00084, EA=25000, GA=10000),
        [tr.Tendon(offset=0.0025)] * 3,
    )
    sc = tr.Scene(
        rob,
        displacement=[0.00125] * 3,
        loads=[tr.PointLoad(s=0.025, force=(0.125,) * 3, moment=(0.0025,) * 3)] * 4
        + [tr.DistributedLoad(force=(0.125,) * 3)],
    )
    opts = tr.Options(max_nfev=max_nfev, max_continuation=13)
    r = run_isolated(sc, opts)
    assert "refused" not in r
    # one finite-difference Jacobian (6 + 3 unknowns) may complete after the last check
    assert r["nfev"] <= max_nfev + 10, (r["nfev"], r["message"])


STEPS_RUNNER = r"""
import warnings, tendonrod as tr
warnings.simplefilter("ignore")
rob = tr.Robot(tr.Rod(length=0.2, diameter=8e-4, E=207e9, G=79.6e9),
               [tr.Tendon(offset=0.01), tr.Tendon(offset=0.01, angle=2)])
sc = tr.Scene(rob, displacement=[0.004, 0.0], loads=[tr.PointLoad(s=0.2, force=(0.1, 0.2, 0))])
try:
    s = tr.solve(sc, options=tr.Options(steps=10**9, max_nfev=50))
    print("returned", s.success, s.nfev)
except ValueError as e:
    print("refused", e)
"""


def test_huge_steps_refused_or_bounded():
    """steps=10**9: either refused up front (ValueError naming steps) or the
    solve returns within its evaluation cap (F9, fixed: steps <= 100000).  Before
    the fix it would have run for days, so the CPU-time guard here is short (10 s)."""
    p = run_guarded([sys.executable, "-c", STEPS_RUNNER], 10, text=True)
    assert p.returncode == 0, p.stderr
    assert p.stdout.startswith("returned") or ("refused" in p.stdout and "steps" in p.stdout), (
        p.stdout
    )
    if p.stdout.startswith("returned"):
        # max_nfev=50, plus the slack of one Jacobian and the recording (NFEV_SLACK)
        assert int(p.stdout.split()[-1]) <= 50 + NFEV_SLACK, p.stdout
