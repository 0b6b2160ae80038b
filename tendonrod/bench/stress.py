"""The stress suite: every case runs in a child process with a timeout and its
result is checked.  A well-posed case must converge to a *verified* answer
(:mod:`tendonrod.bench.verify`); an ill-posed case must return ``success=False``
with a message naming the problem.  Writes ``DIR/stress.csv`` and ``DIR/stress.png``.
"""

from __future__ import annotations

import math
import os
import resource
import signal
import time
import traceback

import numpy as np

from .common import solve_quiet, write_csv
from .plots import plot_stress
from .stress_asbuilt import asbuilt_cases
from .stress_cases import StressCase, stress_cases
from .stress_friction import friction_cases
from .verify import verify

__all__ = [
    "all_stress_cases",
    "run_stress",
    "run_case",
    "run_case_isolated",
    "classify",
    "GOOD",
    "STRESS_COLS",
]


def all_stress_cases() -> list[StressCase]:
    """Every stress case: :func:`~tendonrod.bench.stress_cases.stress_cases`, then the
    groups of robots as built (:mod:`tendonrod.bench.stress_asbuilt`) and of channel
    friction (:mod:`tendonrod.bench.stress_friction`)."""
    return stress_cases() + asbuilt_cases(StressCase) + friction_cases(StressCase)


def run_case(case: StressCase) -> dict:
    """Run one stress case in this process (the child of :func:`run_case_isolated`)."""
    rec = dict(case=case.name, group=case.group, well_posed=case.well_posed)
    try:
        if case.ramp is not None:
            r = case.ramp()
            rec.update(r)
        else:
            assert case.build is not None  # a case without a ramp builds its scene
            scene, opts = case.build()
            t0 = time.perf_counter()
            sol = solve_quiet(scene, opts)
            rec["seconds"] = time.perf_counter() - t0
            finite = all(np.all(np.isfinite(a)) for a in (sol.position, sol.tension))
            rec.update(
                converged=bool(sol.success),
                iterations=sol.nit,
                nfev=sol.nfev,
                residual=sol.residual_norm,
                jacobian_cond=sol.jacobian_cond,
                continuation_steps=sol.continuation_steps,
                message=sol.message,
                status=sol.status,
                formulation=repr(sol.formulation),
            )
            if sol.success:
                v = verify(sol, case.check)
                rec.update(
                    verified=v["verified"],
                    balance=v["balance"],
                    refine=v["refine"],
                    check_error=v["check_error"],
                )
                if v["note"]:
                    rec["message"] = f"{sol.message} | {v['note']}"
            else:
                rec.update(verified=False, balance=math.nan, refine=math.nan, check_error=math.nan)
                rec["finite_on_failure"] = finite
    except ValueError as exc:
        # the API rejects the scene before any C runs: honest for an ill-posed scene
        # (the message must then name the problem), a finding for a well-posed one
        rec.update(
            converged=False,
            verified=False,
            message=f"ValueError before solving: {exc}",
            outcome="honest failure" if not case.well_posed else "REJECTED",
        )
    except Exception as exc:  # noqa: BLE001 - an exception is itself a finding
        rec.update(
            converged=False,
            verified=False,
            outcome="exception",
            message=f"{type(exc).__name__}: {exc}",
            traceback=traceback.format_exc(),
        )
    rec["outcome"] = rec.get("outcome") or classify(rec)
    return rec


def classify(rec):
    """outcome: 'verified' (well-posed, converged, verified), 'honest failure'
    (ill-posed, success False, message with an expected word), and the bad ones:
    'UNVERIFIED' (converged to something that fails verification), 'FAILED'
    (well-posed but did not converge), 'WRONG SUCCESS' (ill-posed but success),
    'VAGUE FAILURE' (ill-posed, failed, message without the diagnosis), 'REJECTED'
    (well-posed but the API raised ValueError)."""
    if rec.get("outcome") in ("exception", "timeout", "REJECTED", "honest failure"):
        return rec["outcome"]
    if rec["well_posed"]:
        if rec.get("converged"):
            return "verified" if rec.get("verified") else "UNVERIFIED"
        return "FAILED"
    if rec.get("converged"):
        return "WRONG SUCCESS"
    return "honest failure"


def _child(case_name, conn, quick, cpu=None):
    if cpu is not None:
        # the hang guard: the kernel stops the child (SIGXCPU) after ``cpu`` seconds of
        # CPU time, the work it did whatever the load of the machine
        resource.setrlimit(resource.RLIMIT_CPU, (int(math.ceil(cpu)), int(math.ceil(cpu)) + 5))
    try:
        case = {c.name: c for c in all_stress_cases()}[case_name]
        rec = run_case(case)
        if case.expect_words and rec["outcome"] == "honest failure":
            msg = rec.get("message", "").lower()
            if not any(w in msg for w in case.expect_words):
                rec["outcome"] = "VAGUE FAILURE"
        conn.send(rec)
    except BaseException as exc:  # noqa: BLE001
        conn.send(
            dict(
                case=case_name,
                outcome="exception",
                converged=False,
                verified=False,
                message=f"{type(exc).__name__}: {exc}",
                traceback=traceback.format_exc(),
            )
        )
    finally:
        conn.close()


# The wall-clock backstop of a case, in multiples of its CPU-time limit: only a child
# blocked without using CPU (a deadlock) reaches it, even on a machine loaded 10x.
WALL_BACKSTOP = 20


def run_case_isolated(case: StressCase, timeout: float) -> dict:
    """Run ``case`` in a child process that may use ``timeout`` seconds of CPU time (a
    hang is a finding: outcome 'timeout'), with a wall-clock backstop of WALL_BACKSTOP
    times that for a child that blocks.  A crash of the child (segfault) is outcome
    'crash'."""
    import multiprocessing as mp

    ctx = mp.get_context("fork")
    parent, child = ctx.Pipe(duplex=False)
    t0 = time.perf_counter()
    proc = ctx.Process(target=_child, args=(case.name, child, False, timeout))
    proc.start()
    child.close()
    rec = None
    if parent.poll(WALL_BACKSTOP * timeout):
        try:
            rec = parent.recv()
        except EOFError:
            rec = None
    wall = time.perf_counter() - t0
    if proc.is_alive():
        proc.join(1.0)
    if proc.is_alive():
        proc.kill()
        proc.join()
    if rec is None:
        if proc.exitcode == -signal.SIGXCPU:
            rec = dict(outcome="timeout", message=f"more than {timeout:g} s of CPU time (killed)")
        elif wall >= WALL_BACKSTOP * timeout:
            rec = dict(
                outcome="timeout",
                message=f"no answer within {WALL_BACKSTOP * timeout:g} s (blocked; killed)",
            )
        else:
            rec = dict(outcome="crash", message=f"child process died (exit code {proc.exitcode})")
        rec.update(case=case.name, converged=False, verified=False, seconds=wall)
    rec.setdefault("group", case.group)
    rec.setdefault("well_posed", case.well_posed)
    rec["wall_seconds"] = wall
    return rec


STRESS_COLS = [
    "case",
    "group",
    "well_posed",
    "outcome",
    "converged",
    "verified",
    "iterations",
    "nfev",
    "residual",
    "jacobian_cond",
    "seconds",
    "wall_seconds",
    "continuation_steps",
    "balance",
    "refine",
    "check_error",
    "message",
]

GOOD = ("verified", "honest failure")


def run_stress(out: str, quick: bool = False, timeout: float = 60.0, only: str = "", log=print):
    os.makedirs(out, exist_ok=True)
    cases = [c for c in all_stress_cases() if (c.quick or not quick) and (only in c.name)]
    rows = []
    for c in cases:
        rec = run_case_isolated(c, timeout)
        rows.append(rec)
        flag = "  " if rec["outcome"] in GOOD else "!!"
        log(
            f"{flag} {c.name:55s} {rec['outcome']:15s} nit {rec.get('iterations', '-')!s:>4} "
            f"t {rec.get('seconds', math.nan) * 1e3:9.2f} ms  {str(rec.get('message', ''))[:140]}"
        )
    write_csv(os.path.join(out, "stress.csv"), rows, STRESS_COLS)
    plot_stress(rows, os.path.join(out, "stress.png"))
    bad = [r for r in rows if r["outcome"] not in GOOD]
    log(
        f"{len(rows)} cases: {len(rows) - len(bad)} good (verified or honest failure), {len(bad)} not"
    )
    return rows
