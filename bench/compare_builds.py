"""Compare the speed of two builds of tendonrod, interleaved in one run.

Absolute times on these shared machines drift by tens of percent between runs; the
ratio of two builds measured alternately, round after round, in fresh processes,
does not.  Each round runs the same micro-suite (public API only, so an older build
can run it too) once per build, in a subprocess whose ``PYTHONPATH`` puts that
build's checkout first; the report gives, per measurement, the median over rounds
of each build's median and of the ratio new/old.

Micro-suite (one thread):
  * ``solve_cold``  -- ``tr.solve`` with default options, the Fig. 11c three-tendon
    robot (L = 0.1 m, d = 1.04 mm, r^2 k L / 3EI = 50, out-of-plane tip load) [us];
  * ``solve_warm``  -- the same, ``guess=`` the solution at 99 % of the load [us];
  * ``solve_warm_tip4`` -- warm, ``Options(steps=4, tip_only=True)`` [us];
  * ``batch_lean`` -- ``solve_batch`` over 2,000 points of a tip-force line with
    ``Options(steps=4, tol=3e-9)`` (the lean warm solve) [us per point];
  * ``batch_exact`` -- ``solve_batch`` over 300 points with default options [us per point];
  * ``planar_cold`` -- ``tr.solve`` of the Fig. 17 robot (L = 0.2 m, d = 0.8 mm, one
    inextensible tendon at 10 mm, q = 15 mm, 0.2 N down at the tip), planar Kirchhoff [us];
  * ``planar_cosserat`` -- the same robot as a Cosserat rod with EA = 3e3 N tendons [us].

Each in wall time and, as ``<name> cpu``, in the calling thread's CPU time (what the
machine's load does not inflate; ``solve_batch``'s own threads are not counted).

    .venv/bin/python bench/compare_builds.py --old /path/to/old/checkout [--rounds 5]

The old checkout must have its extension built in place
(``python setup.py build_ext --inplace`` there).  Writes nothing; prints a table and,
with ``--json FILE``, the numbers.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
NEW = os.path.dirname(HERE)

SUITE = r"""
import json, math, statistics, time, warnings
import numpy as np
import tendonrod as tr

CPU = {}
def med(fn, n, key=None, scale=1e6):
    ts, cs = [], []
    for _ in range(n):
        t0, c0 = time.perf_counter(), time.thread_time()
        fn()
        cs.append(time.thread_time() - c0); ts.append(time.perf_counter() - t0)
    if key:
        CPU[key + " cpu"] = statistics.median(cs) * scale
    return statistics.median(ts)

rod = tr.Rod(length=0.1, diameter=1.04e-3, E=210e9, G=80e9, kirchhoff=True)
EI, L, r = rod.bending_stiffness, rod.length, 0.01
EA = 50.0 * 3 * EI / r**2
robot = tr.Robot(rod, [tr.Tendon(offset=r, angle=2 * math.pi * i / 3, EA=EA) for i in range(3)])
q = [r * math.pi / 2 * 0.98, -0.001, -0.001]
def scene(f):
    return tr.Scene(robot, displacement=q, loads=[tr.PointLoad(s=L, force=(0, f, 0))])
sc, near = scene(0.5), scene(0.495)
out = {}
g = tr.solve(near, strict=True)
out["solve_cold"] = med(lambda: tr.solve(sc), 200, "solve_cold") * 1e6
out["solve_warm"] = med(lambda: tr.solve(sc, guess=g), 300, "solve_warm") * 1e6
o4 = tr.Options(steps=4, tip_only=True)
g4 = tr.solve(near, options=o4, strict=True)
out["solve_warm_tip4"] = med(lambda: tr.solve(sc, guess=g4, options=o4), 300, "solve_warm_tip4") * 1e6
F = np.zeros((2000, 1, 3)); F[:, 0, 1] = np.linspace(0.0, 0.5, 2000)
ol = tr.Options(steps=4, tol=3e-9)
out["batch_lean"] = med(lambda: tr.solve_batch(sc, forces=F, options=ol), 3, "batch_lean", 1e6 / 2000) * 1e6 / 2000
Fe = F[::7][:300]
out["batch_exact"] = med(lambda: tr.solve_batch(sc, forces=Fe), 3, "batch_exact", 1e6 / len(Fe)) * 1e6 / len(Fe)
def planar(kirchhoff, EA):
    rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=kirchhoff)
    rob = tr.Robot(rod, [tr.Tendon(offset=0.01, EA=EA)])
    return tr.Scene(rob, displacement=[0.015], loads=[tr.PointLoad(s=0.2, force=(0, 0, -0.2))])
pk, pc = planar(True, math.inf), planar(False, 3e3)
out["planar_cold"] = med(lambda: tr.solve(pk), 300, "planar_cold") * 1e6
out["planar_cosserat"] = med(lambda: tr.solve(pc), 300, "planar_cosserat") * 1e6
out.update(CPU)
print(json.dumps(out))
"""


def run(checkout: str, py: str) -> dict:
    env = dict(os.environ, PYTHONPATH=checkout, OMP_NUM_THREADS="1")
    res = subprocess.run(
        [py, "-c", SUITE], env=env, capture_output=True, text=True, check=True, cwd="/"
    )
    return json.loads(res.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old", required=True, help="checkout of the old build (built in place)")
    ap.add_argument("--new", default=NEW, help="checkout of the new build (default: this one)")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--json", help="write the per-round numbers to this file")
    args = ap.parse_args(argv)
    py = sys.executable
    rounds = []
    for i in range(args.rounds):
        order = [("old", args.old), ("new", args.new)]
        if i % 2:
            order.reverse()  # alternate which build runs first in a round
        rounds.append({name: run(path, py) for name, path in order})
        print(f"round {i + 1}/{args.rounds} done", file=sys.stderr)
    keys = list(rounds[0]["new"])
    print(
        f"{'measurement':18s} {'old':>10s} {'new':>10s} {'new/old':>8s}   (medians of {args.rounds} rounds)"
    )
    for k in keys:
        old = statistics.median(r["old"][k] for r in rounds)
        new = statistics.median(r["new"][k] for r in rounds)
        ratio = statistics.median(r["new"][k] / r["old"][k] for r in rounds)
        print(f"{k:18s} {old:10.1f} {new:10.1f} {ratio:8.3f}")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rounds, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
