"""Benchmark: run time of cold and warm-started solves through the public API.

Scenes (paper Section IV): Fig. 11 a-c (Kirchhoff rod L = 0.1 m, d = 1.04 mm, E = 210 GPa,
G = 80 GPa, tendon offset 0.01 m, actuated to a 90 deg tip angle), the Fig. 17 slack
scene (taut and slack), and a four-tendon displacement-controlled robot under gravity.

For each scene the fixed-step rk8 step count is the smallest that reaches 1e-8
relative tip accuracy (|tip - tip_ref| <= 1e-8 L) against a converged reference
(adaptive integrator, rtol 1e-13, residual tol 1e-13). Then the median wall time of
  - cold: tr.solve(scene) from the core's own default guess,
  - warm: tr.solve(scene, guess=previous) where previous solved the same scene with
          the loads scaled by 0.99 (a 1 % step of a sweep),
on one thread, through the public API (packing, GIL release, result object included).
Not a test: it prints a table and writes bench/results/solve.csv (+ solve.png).

    .venv/bin/python bench/solve.py [--repeat 201] [--quick]
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import platform
import statistics
import sys
import time
import warnings

import numpy as np

import tendonrod as tr

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "results")
REL_TIP = 1e-8  # target relative tip accuracy (of L)
REF = tr.Options(integrator="adaptive", rtol=1e-13, tol=1e-13)


def fig11_rod():
    return tr.Rod(0.1, 1.04e-3, 210e9, 80e9, kirchhoff=True)


def scaled(scene, factor):
    loads = []
    for ld in scene.loads:
        if isinstance(ld, tr.PointLoad):
            loads.append(
                tr.PointLoad(
                    s=ld.s,
                    force=tuple(factor * np.array(ld.force)),
                    moment=tuple(factor * np.array(ld.moment)),
                )
            )
        else:
            loads.append(tr.DistributedLoad(force=tuple(factor * np.array(ld.force))))
    return tr.Scene(
        scene.robot, displacement=scene.displacement, tension=scene.tension, loads=loads
    )


def lock(robot, tensions, loads):
    """Actuate by tension, then lock the actuators: the displacement-controlled scene."""
    free = tr.solve(tr.Scene(robot, tension=tensions), options=REF, strict=True)
    return tr.Scene(robot, displacement=list(free.displacement), loads=loads)


def scenes():
    out = {}
    rod = fig11_rod()
    EI, L, r = rod.bending_stiffness, rod.length, 0.01
    tau90 = EI * (math.pi / 2) / (r * L)
    one = tr.Robot(rod, [tr.Tendon(offset=r)])
    q90 = r * math.pi / 2
    out["fig11a transverse"] = tr.Scene(
        one, displacement=[q90], loads=[tr.PointLoad(s=L, force=(-1.0, 0, 0))]
    )
    out["fig11b axial"] = tr.Scene(
        one, displacement=[q90], loads=[tr.PointLoad(s=L, force=(0, 0, -1.0))]
    )
    for alpha in (50.0, 5e4):  # r^2 k L/(3 EI) with k = EA/L
        EA = alpha * 3 * EI / r**2
        three = tr.Robot(
            rod, [tr.Tendon(offset=r, angle=2 * math.pi * i / 3, EA=EA) for i in range(3)]
        )
        out[f"fig11c out-of-plane a={alpha:g}"] = lock(
            three, [tau90, 0.0, 0.0], [tr.PointLoad(s=L, force=(0, 0.5, 0))]
        )
    k17 = tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True)
    t17 = tr.Robot(k17, [tr.Tendon(offset=r)])
    out["fig17 taut 0.2 N"] = tr.Scene(
        t17, displacement=[r * math.pi / 2], loads=[tr.PointLoad(s=0.2, force=(0, 0, -0.2))]
    )
    out["fig17 slack 0.5 N"] = tr.Scene(
        t17, displacement=[r * math.pi / 2], loads=[tr.PointLoad(s=0.2, force=(0, 0, -0.5))]
    )
    c17 = tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9)
    four = tr.Robot(c17, [tr.Tendon(offset=r, angle=i * math.pi / 2) for i in range(4)])
    out["4 tendons, gravity"] = tr.Scene(
        four,
        displacement=[4e-3, 2e-3, -5e-3, -3e-3],
        loads=[tr.DistributedLoad(force=(0, 0, -0.5))],
    )
    return out


def timeit(fn, repeat):
    ts = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t0)
    return statistics.median(ts), ts


def bench_scene(name, scene, repeat, max_steps=64):
    L = scene.robot.rod.length
    ref = tr.solve(scene, options=REF, strict=True)
    steps_needed, err = None, math.nan
    for n in range(1, max_steps + 1):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", tr.ConvergenceWarning)
            s = tr.solve(scene, options=tr.Options(steps=n))
        if not s.success:
            continue
        err = np.linalg.norm(s.tip_position - ref.tip_position) / L
        if err <= REL_TIP:
            steps_needed = n
            break
    opts = tr.Options(steps=steps_needed or max_steps)
    auto = tr.solve(scene)
    auto_err = np.linalg.norm(auto.tip_position - ref.tip_position) / L
    near = tr.solve(scaled(scene, 0.99), options=opts, strict=True)
    cold = tr.solve(scene, options=opts, strict=True)
    warm = tr.solve(scene, guess=near, options=opts, strict=True)
    t_cold, _ = timeit(lambda: tr.solve(scene, options=opts), repeat)
    t_warm, _ = timeit(lambda: tr.solve(scene, guess=near, options=opts), repeat)
    tip_opts = tr.Options(steps=opts.steps, tip_only=True)
    t_tip_cold, _ = timeit(lambda: tr.solve(scene, options=tip_opts), repeat)
    t_tip, _ = timeit(lambda: tr.solve(scene, guess=near, options=tip_opts), repeat)
    near_d = tr.solve(scaled(scene, 0.99), strict=True)
    t_cold_d, _ = timeit(lambda: tr.solve(scene), repeat)
    t_warm_d, _ = timeit(lambda: tr.solve(scene, guess=near_d), repeat)
    return dict(
        scene=name,
        formulation=repr(cold.formulation),
        steps=opts.steps,
        tip_err=err,
        auto_steps=auto.formulation.steps,
        auto_err=auto_err,
        cold_us=t_cold * 1e6,
        cold_nfev=cold.nfev,
        cold_nit=cold.nit,
        cold_continuation=cold.continuation_steps,
        warm_us=t_warm * 1e6,
        warm_nfev=warm.nfev,
        warm_nit=warm.nit,
        cold_tip_only_us=t_tip_cold * 1e6,
        warm_tip_only_us=t_tip * 1e6,
        default_cold_us=t_cold_d * 1e6,
        default_warm_us=t_warm_d * 1e6,
    )


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=201)
    ap.add_argument("--quick", action="store_true", help="repeat 21")
    args = ap.parse_args(argv)
    repeat = 21 if args.quick else args.repeat
    rows = []
    for name, sc in scenes().items():
        rows.append(bench_scene(name, sc, repeat))
        r = rows[-1]
        print(
            f"{r['scene']:<30s} steps {r['steps']:2d} (err {r['tip_err']:.0e}) | 101 nodes: cold "
            f"{r['cold_us']:8.1f} (nfev {r['cold_nfev']:4d}, cont {r['cold_continuation']:2d}) warm "
            f"{r['warm_us']:6.1f} (nfev {r['warm_nfev']}) | tip only: cold {r['cold_tip_only_us']:8.1f} "
            f"warm {r['warm_tip_only_us']:6.1f} | default Options() (auto {r['auto_steps']} steps, err "
            f"{r['auto_err']:.0e}): cold {r['default_cold_us']:8.1f} warm {r['default_warm_us']:6.1f}  [us]",
            flush=True,
        )
    os.makedirs(OUT, exist_ok=True)
    path = os.path.join(OUT, "solve.csv")
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(
        f"\nmachine: {platform.processor() or platform.machine()}, {os.cpu_count()} cpus, "
        f"python {sys.version.split()[0]}, numpy {np.__version__}, GSL {tr.gsl_version}; "
        f"median of {repeat}; goals cold <= 300 us, warm <= 50 us"
    )
    print(f"wrote {path}")
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        fig, ax = plt.subplots(figsize=(9, 5))
        y = np.arange(len(rows))
        w = 0.2
        ax.barh(y - 1.5 * w, [r["cold_us"] for r in rows], w, label="cold, 101 nodes")
        ax.barh(
            y - 0.5 * w, [r["warm_us"] for r in rows], w, label="warm (1 % load step), 101 nodes"
        )
        ax.barh(y + 0.5 * w, [r["cold_tip_only_us"] for r in rows], w, label="cold, tip only")
        ax.barh(y + 1.5 * w, [r["warm_tip_only_us"] for r in rows], w, label="warm, tip only")
        ax.axvline(300, color="C0", ls="--", lw=0.8)
        ax.axvline(50, color="C1", ls="--", lw=0.8)
        ax.set_yticks(y, [r["scene"] for r in rows])
        ax.set_xscale("log")
        ax.set_xlabel("median solve time [us] (1e-8 relative tip accuracy)")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(os.path.join(OUT, "solve.png"), dpi=120)
    except ImportError:  # pragma: no cover
        pass


if __name__ == "__main__":
    main()
