"""What the plausibility checks cost, through the public API, in one process.

    python bench/plausibility_cost.py [--rounds 7] [--no-write]

(run it with the package under test first on ``sys.path``: the repository's venv after
``make install``, or ``PYTHONPATH=.`` in a work tree.)

Two kinds of measurement, each the median over rounds:

* whole loops, alternating the checks on and off in each round (off: the check replaced
  by a no-op, what the tree did before it), the ratio on/off per round:

  1. a warm load ramp of 200 solves through ``tr.Problem.solve``, a new Scene per call
     (the load ramp of docs/guide/solving.md): the bounds clear, so the checks cost their screen only;
  2. ``tr.solve_batch``, 2,000 points, lean (``steps=4``): the vectorised screen;
  3. the ramp of 1 on a robot bent 200 deg (past the half turn, so the bounds cannot
     clear): every solve records its states once for the state rules;

* the check alone (``_plausible.Checker.check`` on solutions of that ramp, the
  solutions' cached findings and the scenes' cached screens cleared before each pass),
  so that the cost per solve is not a small difference of two noisy loop times.

Prints a table and writes ``bench/results/plausibility_cost.md``.
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import statistics
import sys
import time
import warnings

import numpy as np

import tendonrod as tr
from tendonrod import _plausible, batch

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "results", "plausibility_cost.md")
L = 0.2


def _scene(robot, q, f):
    return tr.Scene(robot, displacement=[q], loads=[tr.PointLoad(s=L, force=(0, 0, -f))])


def _problem_loop(robot, q, n=200):
    """Seconds per Problem.solve of a ramp (scenes built in the loop, as users do)."""
    prob = tr.Problem(_scene(robot, q, 0.0), tr.Options(tip_only=True))
    t0 = time.perf_counter()
    for f in np.linspace(0.0, 0.2, n):
        prob.solve(_scene(robot, q, f))
    return (time.perf_counter() - t0) / n


def _batch(robot, q, n=2000):
    F = np.zeros((n, 1, 3))
    F[:, 0, 2] = -np.linspace(0.0, 0.2, n)
    t0 = time.perf_counter()
    tr.solve_batch(_scene(robot, q, 0.0), forces=F, options=tr.Options(steps=4))
    return (time.perf_counter() - t0) / n


def _check_alone(robot, q, n=200):
    """A callable returning the seconds per ``Checker.check`` of n solutions of the ramp
    (each pass on fresh state: no cached findings, no cached screens)."""
    prob = tr.Problem(_scene(robot, q, 0.0), tr.Options(tip_only=True))
    sols = [prob.solve(_scene(robot, q, f)) for f in np.linspace(0.0, 0.2, n)]

    def run():
        for s in sols:
            s.__dict__.pop("_plausibility", None)
            s.scene.__dict__.pop("_plausibility_screen", None)
        checker = _plausible.Checker()
        t0 = time.perf_counter()
        for s in sols:
            checker.check(s, "bench", once=True)
        return (time.perf_counter() - t0) / n

    return run


class _Off:
    """The checks replaced by no-ops while inside (what the tree did before them)."""

    def __enter__(self):
        self.saved = (_plausible.Checker.check, batch.batch_findings)
        _plausible.Checker.check = lambda self, sol, who, once: None

        def none(scene, options, raw, *a):
            out = np.empty(len(raw["success"]), dtype=object)
            out.fill(())
            return out

        batch.batch_findings = none

    def __exit__(self, *exc):
        _plausible.Checker.check, batch.batch_findings = self.saved


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--no-write", action="store_true", help="print only")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    rod = tr.Rod(length=L, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    robot = tr.Robot(rod, [tr.Tendon(offset=0.01)])
    q90, q200 = 0.01 * math.pi / 2, 0.01 * math.radians(200.0)
    loops = {
        "Problem.solve ramp, bent 90 deg (us/solve)": lambda: _problem_loop(robot, q90),
        "solve_batch lean, 2,000 points (us/point)": lambda: _batch(robot, q90),
        "Problem.solve ramp, bent 200 deg: states read (us/solve)": lambda: _problem_loop(
            robot, q200
        ),
    }
    alone = {
        "check alone, bent 90 deg: screen only (us/solve)": _check_alone(robot, q90),
        "check alone, bent 200 deg: states read (us/solve)": _check_alone(robot, q200),
    }
    lines = ["| measurement | checks off | checks on | on/off |", "|---|---|---|---|"]
    for name, run in loops.items():
        run()  # warm up (imports, caches)
        on, off, ratio = [], [], []
        for _ in range(args.rounds):
            with _Off():
                a = run()
            b = run()
            off.append(a)
            on.append(b)
            ratio.append(b / a)
        lines.append(
            f"| {name} | {1e6 * statistics.median(off):.1f} | "
            f"{1e6 * statistics.median(on):.1f} | {statistics.median(ratio):.3f} |"
        )
    for name, run in alone.items():
        run()
        t = statistics.median(run() for _ in range(args.rounds))
        lines.append(f"| {name} | | {1e6 * t:.1f} | |")
    print("\n".join(lines))
    if args.no_write:
        return
    machine = (
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} cpus, "
        f"python {platform.python_version()}, numpy {np.__version__}"
    )
    with open(OUT, "w", encoding="utf-8") as fh:
        fh.write(
            "# What the plausibility checks cost\n\n"
            f"Written by `bench/plausibility_cost.py --rounds {args.rounds}` ({machine}; "
            "medians over rounds; loops alternate the checks off and on in each round).\n"
            "Times are wall-clock and drift between runs on a shared machine: read the "
            "ratios and the check-alone rows.\n\n" + "\n".join(lines) + "\n"
        )
    print(f"wrote {os.path.relpath(OUT, os.getcwd())}", file=sys.stderr)


if __name__ == "__main__":
    main()
