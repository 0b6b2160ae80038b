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

With ``--scenes`` (the certified-and-fast goals), each round also runs, per build, every
scene of ``bench/solve.py`` (the new checkout's scene list, public API only):
  * ``<scene> | cold`` -- ``tr.solve`` with default options [us];
  * ``<scene> | warm 1%`` -- ``tr.solve(scene at 1.01, guess=the solution at 1.00)`` [us];
  * ``<scene> | Problem`` -- ``Problem.solve`` alternating between the two load sets [us];
and ``batch tip+verdict`` -- ``solve_batch`` over ``bench/throughput.py``'s 30 x 30 grid
with ``Options(steps=4, tol=3e-9, tip_only=True)`` and the verdict on, one thread [us per
point, process CPU time, so the batch's worker thread counts].  The report then says,
goal by goal, met or missed: cold <= 0.4x the old build and warm ``Problem`` <= 0.3x on
every scene, a warm 1 % step never slower than a cold solve (new build), and the batch's
throughput >= 1.4x the old build's.

    .venv/bin/python bench/compare_builds.py --old /path/to/old/checkout [--rounds 5] [--scenes]

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


SCENES = r"""
import json, statistics, sys, time, warnings
sys.path.insert(0, BENCH)
import tendonrod as tr
import solve as S
import throughput as T
warnings.simplefilter("ignore")

def med(fn, n, clock=time.thread_time):
    ts, cs = [], []
    for _ in range(n):
        t0, c0 = time.perf_counter(), clock()
        fn()
        cs.append(clock() - c0); ts.append(time.perf_counter() - t0)
    return 1e6 * statistics.median(ts), 1e6 * statistics.median(cs)

out = {}
def put(key, wc, per=1.0):
    out[key] = wc[0] / per
    out[key + " cpu"] = wc[1] / per

for name, (scene, klass, _) in S.scenes().items():
    a, b = S.scaled(scene, 1.0), S.scaled(scene, 1.01)
    ga = tr.solve(a)
    put(name + " | cold", med(lambda: tr.solve(b), REPS))
    put(name + " | warm 1%", med(lambda: tr.solve(b, guess=ga), REPS))
    prob = tr.Problem(a)
    prob.solve()
    pair = [b, a]
    def step():
        pair.reverse()
        prob.solve(pair[0])
    put(name + " | Problem", med(step, 2 * REPS))
F = T.grid_forces(30)
ob = tr.Options(steps=4, tol=3e-9, tip_only=True)
bs = T.make_scene()
tr.solve_batch(bs, forces=F[:30], options=ob, threads=1)
put("batch tip+verdict", med(lambda: tr.solve_batch(bs, forces=F, options=ob, threads=1), 3,
                             time.process_time), len(F))
print(json.dumps(out))
"""


def run(checkout: str, py: str, suite: str = SUITE) -> dict:
    env = dict(os.environ, PYTHONPATH=checkout, OMP_NUM_THREADS="1")
    res = subprocess.run(
        [py, "-c", suite], env=env, capture_output=True, text=True, check=True, cwd="/"
    )
    return json.loads(res.stdout.strip().splitlines()[-1])


def goals(rounds: list[dict]) -> list[tuple[str, float, float, bool]]:
    """(goal, wall value, CPU value, met) for the certified-and-fast goals; a ratio is
    new/old (median over rounds), met when both clocks meet it."""
    med = statistics.median
    keys = [k for k in rounds[0]["new"] if " | " in k and not k.endswith(" cpu")]
    names = list(dict.fromkeys(k.split(" | ")[0] for k in keys))
    out = []

    def ratio(key):
        return med(r["new"][key] / r["old"][key] for r in rounds)

    for nm in names:
        for kind, bound in (("cold", 0.4), ("Problem", 0.3)):
            k = f"{nm} | {kind}"
            w, c = ratio(k), ratio(k + " cpu")
            out.append((f"{k} <= {bound}x old", w, c, w <= bound and c <= bound))
        w = med(r["new"][f"{nm} | warm 1%"] / r["new"][f"{nm} | cold"] for r in rounds)
        c = med(r["new"][f"{nm} | warm 1% cpu"] / r["new"][f"{nm} | cold cpu"] for r in rounds)
        out.append((f"{nm} | warm 1% <= cold (new)", w, c, w <= 1.0 and c <= 1.0))
    if "batch tip+verdict" in rounds[0]["new"]:
        w, c = ratio("batch tip+verdict"), ratio("batch tip+verdict cpu")
        out.append(("batch tip+verdict throughput >= 1.4x (time <= 0.714x)", w, c, c <= 1 / 1.4))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old", required=True, help="checkout of the old build (built in place)")
    ap.add_argument("--new", default=NEW, help="checkout of the new build (default: this one)")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--json", help="write the per-round numbers to this file")
    ap.add_argument(
        "--scenes", action="store_true", help="also every bench/solve.py scene, and the goals"
    )
    ap.add_argument("--reps", type=int, default=25, help="solves per scene and round (--scenes)")
    args = ap.parse_args(argv)
    py = sys.executable
    scenes = SCENES.replace("BENCH", repr(HERE)).replace("REPS", str(args.reps))
    rounds = []
    load0 = os.getloadavg()[0]
    for i in range(args.rounds):
        order = [("old", args.old), ("new", args.new)]
        if i % 2:
            order.reverse()  # alternate which build runs first in a round
        res = {}
        for name, path in order:
            res[name] = run(path, py)
            if args.scenes:
                res[name].update(run(path, py, scenes))
        rounds.append(res)
        print(f"round {i + 1}/{args.rounds} done", file=sys.stderr)
    keys = list(rounds[0]["new"])
    print(
        f"{'measurement':44s} {'old':>10s} {'new':>10s} {'new/old':>8s}   (medians of {args.rounds} rounds)"
    )
    for k in keys:
        old = statistics.median(r["old"][k] for r in rounds)
        new = statistics.median(r["new"][k] for r in rounds)
        ratio = statistics.median(r["new"][k] / r["old"][k] for r in rounds)
        print(f"{k:44s} {old:10.1f} {new:10.1f} {ratio:8.3f}")
    if args.scenes:
        print("\ngoal (new/old unless marked new)                       wall    CPU")
        for text, w, c, ok in goals(rounds):
            print(f"{text:52s} {w:6.3f} {c:6.3f}  {'met' if ok else 'missed'}")
    print(f"load average {load0:.2f} before, {os.getloadavg()[0]:.2f} after")
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rounds, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
