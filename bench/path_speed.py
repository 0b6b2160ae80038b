"""Benchmark: the cost of a point of ``tr.path`` against a warm ``Problem.solve`` of the
same scenes, interleaved over rounds (medians; these machines drift).

Scenes: the Euler column of tests/test_path.py (planar, 3 unknowns) over 0..-3 P_E with the
switch onto the buckled branch; the Fig. 17 robot (locked single tendon, downward tip load
0..1 N through the slack switch; planar, 4 unknowns).  Per path point: the path's wall time
/ its points.  Warm solve: ``Problem.solve`` of the path's own scenes in order (each from
the previous), per solve.  Not a test: it prints a table.

    .venv/bin/python bench/path_speed.py [--rounds 5]
"""

from __future__ import annotations

import argparse
import dataclasses
import math
import statistics
import time

import tendonrod as tr


def euler():
    rod = tr.Rod(length=0.25, diameter=1.2e-3, E=60e9, G=23e9, kirchhoff=True)
    EI, L = rod.bending_stiffness, rod.length
    Pe = math.pi**2 * EI / (4 * L**2)
    scene = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=L, force=(0.0, 0.0, 0.0))])
    return scene, "loads[0].force[2]", (0.0, -3 * Pe), dict(switch=1)


def fig17():
    from tendonrod.paper.robots import actuate, paper_rod_slack, single_tendon_robot

    rod = paper_rod_slack()
    act = actuate(single_tendon_robot(rod, "parallel", 0.01, math.inf), math.pi / 2)
    scene = dataclasses.replace(
        act.locked_scene, loads=[tr.PointLoad(s=rod.length, force=(0.0, 0.0, 0.0))]
    )
    return scene, "loads[0].force[2]", (0.0, -1.0), {}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=5)
    args = ap.parse_args()
    print(
        f"{'scene':8s} {'points':>6s} {'path/point ms':>14s} {'warm solve ms':>14s} {'ratio':>6s}"
    )
    for name, make in (("euler", euler), ("fig17", fig17)):
        scene, par, span, kw = make()
        per_point, per_solve = [], []
        for _ in range(args.rounds):
            t0 = time.perf_counter()
            p = tr.path(scene, par, span, **kw)
            per_point.append((time.perf_counter() - t0) / len(p))
            scenes = [p.scene_at(i) for i in range(len(p))]
            prob = tr.Problem(scenes[0])
            prob.solve()
            t0 = time.perf_counter()
            for s in scenes[1:]:
                prob.solve(s)
            per_solve.append((time.perf_counter() - t0) / (len(scenes) - 1))
        a, b = statistics.median(per_point), statistics.median(per_solve)
        print(f"{name:8s} {len(p):6d} {1e3 * a:14.3f} {1e3 * b:14.3f} {a / b:6.2f}")


if __name__ == "__main__":
    main()
