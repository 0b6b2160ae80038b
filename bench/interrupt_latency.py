"""Benchmark: how fast Ctrl-C stops a solve, and how long the default work budget lets a
hopeless solve run.

Interrupt latency: the child process of ``tests/test_interrupt.py`` runs a minute-long
solve; SIGINT is sent a second in; the latency is the time until the child catches
KeyboardInterrupt (both read CLOCK_MONOTONIC).  Modes: a single solve, a Problem, a
solve_batch on two threads, a sweep on two threads.  Budget: the wall time of hopeless
solves (a 1e6 N tip load) with default options, per formulation, and the work they
report.

    .venv/bin/python bench/interrupt_latency.py [--repeat 5]

Writes bench/results/interrupt.csv and prints a table.
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import pathlib
import statistics
import sys
import tempfile
import time
import warnings

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))

from test_interrupt import _interrupt  # noqa: E402

import tendonrod as tr  # noqa: E402


def hopeless(planar: bool, kirchhoff: bool, nt: int):
    rod = tr.Rod(length=0.1, diameter=1.04e-3, E=210e9, G=80e9, kirchhoff=kirchhoff)
    ang = [i * math.pi if planar else 2 * math.pi * i / max(nt, 1) for i in range(nt)]
    robot = tr.Robot(rod, [tr.Tendon(offset=0.01, angle=a, EA=1e5) for a in ang])
    F = (1e6, 0.0 if planar else 3e5, 0.0)
    return tr.Scene(robot, tension=[1.0] * nt, loads=[tr.PointLoad(s=0.1, force=F)])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for mode in ("solve", "problem", "batch", "sweep"):
            lats = []
            for k in range(args.repeat):
                d = pathlib.Path(tmp) / f"{mode}{k}"
                d.mkdir()
                lats.append(_interrupt(mode, d)["latency"])
            rows.append(
                {
                    "what": f"interrupt {mode}",
                    "median_s": statistics.median(lats),
                    "max_s": max(lats),
                    "n": len(lats),
                    "work": "",
                }
            )
    for planar, kirch, nt in (
        (True, True, 0),
        (True, True, 1),
        (True, False, 1),
        (False, True, 3),
        (False, False, 3),
        (False, False, 6),
    ):
        sc = hopeless(planar, kirch, nt)
        ts, sol = [], None
        for _ in range(args.repeat):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", tr.ConvergenceWarning)
                t0 = time.perf_counter()
                sol = tr.solve(sc)
                ts.append(time.perf_counter() - t0)
        name = f"hopeless {'planar' if planar else 'spatial'} {'Kirchhoff' if kirch else 'Cosserat'} {nt} tendons"
        rows.append(
            {
                "what": f"{name} (status {sol.status})",
                "median_s": statistics.median(ts),
                "max_s": max(ts),
                "n": len(ts),
                "work": f"{sol.raw['work']:.3g}",
            }
        )
    out = HERE / "results" / "interrupt.csv"
    with open(out, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"{'what':58s} {'median s':>9s} {'max s':>8s} {'work':>9s}")
    for r in rows:
        print(f"{r['what']:58s} {r['median_s']:9.4f} {r['max_s']:8.4f} {r['work']:>9s}")
    print(f"load average {os.getloadavg()}; wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
