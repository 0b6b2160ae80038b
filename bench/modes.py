"""Benchmark: the first 6 natural frequencies of a three-tendon robot (``tr.modes``), their
accuracy and their cost.

Robot: a 0.2 m Cosserat rod of 1 mm steel wire (density 7800 kg/m^3), three tendons at
5 mm, 120 degrees apart, EA = 2000 N; bent by tendon 0 (the other two held at zero
displacement, or at their tensions of that state), with a small lateral tip load so that
no pair of frequencies is degenerate.  Per setting (coarsest grid's elements x grids):
the frequencies' error against a reference (32 elements x 4 grids: 256 on the finest,
Richardson to h^8), the accuracy estimate the result reports, and the cost of the C call
(``_core.modes``: thread CPU time and wall time, medians over rounds) and of the whole
``tr.modes(solution)``.  Not a test: it prints a table and writes
bench/results/modes.md and modes.csv.

    .venv/bin/python bench/modes.py [--rounds 20]
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import statistics
import time

import numpy as np

import tendonrod as tr
from tendonrod import _core
from tendonrod.compiled import _compile
from tendonrod.vibration import _mass_table

HERE = os.path.dirname(os.path.abspath(__file__))
SETTINGS = [(12, 3), (16, 3), (24, 3), (32, 3), (24, 2)]
REFERENCE = (32, 4)


NOTES = """
Notes.

- Errors are against the 32 x 4 reference (256 elements, Richardson to h^8); at 256
  elements the round-off of the lowest eigenvalue is ~1e-8 of it, so errors below ~3e-8
  are the reference's as much as the setting's.  The estimate (`Modes.accuracy`) is the
  difference of the last two extrapolations plus 0.3 eps times Gershgorin's bound on the
  largest eigenvalue: conservative by 10 to 40 times here.
- Default (24 x 3): every frequency to 1e-7 or better, the estimate below 1e-6 -- the
  goal's accuracy, certified by the result itself.  16 x 3 reaches 3e-7 at two thirds of
  the cost, but its estimate (up to 5e-6) does not certify 1e-6.  Two grids (24 x 2) are
  not enough: 1e-5.
- Cost: the goal is 2 ms; the default takes 6 to 7 ms of CPU (11 to 13 ms before the
  element Hessians went from 78 hyper-dual passes to 45 on Cosserat elements:
  `bench/results/verdict_cost.md`).  The element energies of the verdict's assembly
  (tr_stab_energy.c) are still ~45 % of it (168 elements over the three grids, plus 9
  first-order passes per taut displacement-held tendon for its bordered column), then the
  shift-invert sweeps (8 a grid: the subspace iteration stops at the Ritz values'
  round-off) and the LDL^T counts; the recording of the solution at the finest grid's
  nodes is ~1 %.  Multi-directional jets were tried for the Hessians and were slower (a
  55-double jet lives in memory, not registers); what is left is the closed-form second
  variation, or fewer elements with a higher-order element.
"""


def scenes():
    rod = tr.Rod(0.2, 1e-3, 207e9, 79.6e9, density=7800.0)
    tendons = [tr.Tendon(offset=0.005, angle=2 * math.pi * k / 3, EA=2e3) for k in range(3)]
    robot = tr.Robot(rod, tendons)
    load = [tr.PointLoad(s=0.2, force=(0.05, 0.02, 0.0))]
    held = tr.solve(tr.Scene(robot, displacement=[0.004, 0.0, 0.0], loads=load))
    tau = [float(x) for x in held.tendon_tension[0]]
    pulled = tr.solve(tr.Scene(robot, tension=tau, loads=load))
    return {"displacement-held": held, "tension-held": pulled}


def core_call(sol, elements, levels):
    prob = _compile(sol.scene, sol.options)
    mass = _mass_table(sol.scene.robot.rod)
    steps = int(sol.raw["formulation"]["steps"])
    pm = np.zeros((0, 2))
    return lambda: _core.modes(
        prob, sol.unknowns, steps, 6, mass, pm, elements=elements, levels=levels
    )


def timed(fn, rounds):
    cpu, wall = [], []
    for _ in range(rounds):
        c0, w0 = time.thread_time(), time.perf_counter()
        out = fn()
        cpu.append(time.thread_time() - c0)
        wall.append(time.perf_counter() - w0)
    return out, statistics.median(cpu), statistics.median(wall)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=20)
    args = ap.parse_args()
    rows = []
    for name, sol in scenes().items():
        ref = core_call(sol, *REFERENCE)()
        f_ref = np.sqrt(ref["omega2"]) / (2 * math.pi)
        print(
            f"{name}: bend {sol.bending_angle:.3f} rad, reference f [Hz] =",
            np.array2string(f_ref, precision=6),
        )
        _, cpu_py, wall_py = timed(lambda: tr.modes(sol), max(3, args.rounds // 4))
        for el, lv in SETTINGS:
            r, cpu, wall = timed(core_call(sol, el, lv), args.rounds)
            f = np.sqrt(r["omega2"]) / (2 * math.pi)
            err = np.abs(f / f_ref - 1)
            est = 0.5 * r["error"] / r["omega2"]
            rows.append(
                dict(
                    scene=name,
                    elements=el,
                    levels=lv,
                    fine=el << (lv - 1),
                    cpu_ms=1e3 * cpu,
                    wall_ms=1e3 * wall,
                    sweeps=r["nit"],
                    factorisations=r["nfac"],
                    max_error=err.max(),
                    max_estimate=est.max(),
                    errors=" ".join(f"{x:.1e}" for x in err),
                    estimates=" ".join(f"{x:.1e}" for x in est),
                )
            )
            print(
                f"  {el:3d} x {lv}: C {1e3 * cpu:6.2f} ms cpu {1e3 * wall:6.2f} ms wall, "
                f"max error {err.max():.1e}, max estimate {est.max():.1e}, "
                f"sweeps {r['nit']}"
            )
        print(
            f"  tr.modes(solution) (default 24 x 3, with compile and checks): "
            f"{1e3 * cpu_py:.2f} ms cpu {1e3 * wall_py:.2f} ms wall"
        )
        rows.append(
            dict(
                scene=name,
                elements=24,
                levels=3,
                fine=96,
                cpu_ms=1e3 * cpu_py,
                wall_ms=1e3 * wall_py,
                sweeps="",
                factorisations="",
                max_error="",
                max_estimate="",
                errors="tr.modes(solution)",
                estimates="",
            )
        )
    out = os.path.join(HERE, "results")
    with open(os.path.join(out, "modes.csv"), "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(out, "modes.md"), "w") as fh:
        fh.write("# tr.modes: six frequencies of a three-tendon robot\n\n")
        fh.write(
            "Written by `bench/modes.py` (the robot and the reference are described "
            "there); medians over rounds on this machine.\n\n"
        )
        fh.write(
            "| scene | elements x grids | finest | C cpu ms | C wall ms | sweeps | "
            "max rel. error | max estimate |\n|---|---|---|---|---|---|---|---|\n"
        )
        for r in rows:
            if r["errors"] == "tr.modes(solution)":
                fh.write(
                    f"| {r['scene']} | `tr.modes(sol)` default | 96 | {r['cpu_ms']:.2f} | "
                    f"{r['wall_ms']:.2f} | | | |\n"
                )
            else:
                fh.write(
                    f"| {r['scene']} | {r['elements']} x {r['levels']} | {r['fine']} | "
                    f"{r['cpu_ms']:.2f} | {r['wall_ms']:.2f} | {r['sweeps']} | "
                    f"{r['max_error']:.1e} | {r['max_estimate']:.1e} |\n"
                )
        fh.write(NOTES)
    print("wrote bench/results/modes.md, modes.csv")


if __name__ == "__main__":
    main()
