"""Benchmark: the work-precision of ``tr.simulate`` -- the error of the motion against
its CPU time, for several time steps and grids.

Two scenes:

* Till's dynamic tendon robot (Till, Aloi and Rucker, IJRR 2019;
  ContinuumRobotExamples 02_Dynamics/03_Tendon_Robot): a 0.7144 m, 1.35 mm steel rod of
  34 g spread evenly, gravity along world -x, one tendon at 15.06 mm (EA from its
  compliance 1e-4 1/N over rod plus 0.0518 m to the motor), Kelvin-Voigt damping of
  retardation time 5e-4 N m^2 s / EI on every strain rate (Till: the curvature rates
  only), air drag 1e-4, the motor ramp 0 -> 16.19 mm retraction over 3.652-3.967 s and
  back over 17.63-17.94 s, 25 s; BDF2 as Till.
* A cantilever released from a static tip load (0.2 m, 2 mm steel, 1e-4 N), three
  periods of its first mode (omega dt = 0.4 ... 0.1, the reference 0.05), undamped; BDF2 and the
  trapezoidal rule; error relative to the initial amplitude.

Till's scene: plain BDF2 for dt = 0.05 ... 1.5625 ms (the shooting segments of each step
chosen from dt, the default), and ``extrapolate=True`` (Richardson from runs at dt, dt/2,
dt/4) for dt = 0.05 ... 6.25 ms with its error estimate.  Error: the largest tip distance
over the 25 s, at every time the run and the reference both have, from the reference
(Richardson of dt = 1.5625 and 0.78125 ms at 40 RK4 steps, at the times of 3.125 ms),
divided by L.  Cantilever: sampled every step of the coarsest dt.  CPU: thread
CPU time of the whole ``tr.simulate`` call (the static start included), median of
--rounds.  Not a test: prints a table, writes bench/results/dynamics.csv and
dynamics.png.

    .venv/bin/python bench/dynamics.py [--rounds 3] [--quick]
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import re
import statistics
import time

import numpy as np

import tendonrod as tr

# Till's code at its defaults (dt = 0.05 s, 200 nodes): its CPU time [s] on this machine,
# bench/dynamics_peer.py --rerun (the median of the runs interleaved with tendonrod's)
TILL_CPU = 4.0
HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "results")


def till_scene():
    L, d, E = 0.7144, 1.35e-3, 207e9
    A = math.pi * d * d / 4
    EI = E * math.pi * d**4 / 64
    rod = tr.Rod(L, d, E, E / 2.6, density=0.034 / (L * A), damping=5e-4 / EI)
    EA = L / (1e-4 * (L + 0.0518))
    robot = tr.Robot(rod, [tr.Tendon(offset=0.01506, angle=0.0, EA=EA)])
    return tr.Scene(robot, displacement=[0.0], gravity=(-9.81, 0.0, 0.0))


def till_motor(t):
    """Till's motor: the tendon's retraction [m] at t [s] (his z(t), sign flipped)."""
    zb, t1, t2, t3, t4 = 0.01619, 3.652, 3.967, 17.63, 17.94
    if t1 < t <= t2:
        return [zb * (t - t1) / (t2 - t1)]
    if t2 < t <= t3:
        return [zb]
    if t3 < t <= t4:
        return [zb * (1.0 - (t - t3) / (t4 - t3))]
    return [0.0]


def cantilever():
    rod = tr.Rod(0.2, 2e-3, 207e9, 79.6e9, density=7800.0)
    free = tr.Scene(tr.Robot(rod, []))
    f1 = float(tr.modes(free, n=1).frequencies[0])
    return rod, free, f1


def timed(fn, rounds):
    cpus, out = [], None
    for _ in range(rounds):
        t0 = time.thread_time()
        out = fn()
        cpus.append(time.thread_time() - t0)
    return statistics.median(cpus), out


def till_sim(steps, dt, extrapolate=False):
    """Till's scene over 25 s: BDF2, the shooting segments chosen per dt (the default)."""
    return tr.simulate(
        till_scene(),
        25.0,
        dt,
        actuation=till_motor,
        options={"steps": steps, "drag": 1e-4, "extrapolate": extrapolate},
    )


def till_reference(quick=False):
    """The reference: Richardson of BDF2 at dt = 1.5625 and 0.78125 ms (40 RK4 steps; 3 and
    4 shooting segments), at the times of dt = 3.125 ms (the quick one: 20 steps, 12.5 ms)."""
    return (20, 0.0125) if quick else (40, 0.003125)


def till_error(tj, dt, ref, ref_dt):
    """The largest tip distance from the reference at the times both have, / L."""
    a, b = tj.tip_position, ref.tip_position
    if dt >= ref_dt:
        b = b[:: int(round(dt / ref_dt))]
    else:
        a = a[:: int(round(ref_dt / dt))]
    n = min(len(a), len(b))
    return float(np.linalg.norm(a[:n] - b[:n], axis=1).max()) / till_scene().robot.rod.length


def run_till(rounds, quick):
    L = till_scene().robot.rod.length
    plain = [(10, 0.05), (20, 0.05), (20, 0.025), (20, 0.0125), (40, 0.0125), (20, 0.00625)]
    plain += [(20, 0.003125), (20, 0.0015625)]
    extra = [(20, 0.05), (20, 0.025), (20, 0.0125), (20, 0.00625)]
    ref_set = till_reference(quick)
    if quick:
        plain, extra = plain[:3], extra[:2]
    ref = till_sim(*ref_set, extrapolate=True)
    rows = []
    for method, grid in (("plain", plain), ("extrapolated", extra)):
        for steps, dt in grid:
            ex = method == "extrapolated"
            cpu, tj = timed(lambda: till_sim(steps, dt, ex), rounds)
            seg = re.findall(r"\((\d+) shooting segment", tj.message)
            rows.append(
                dict(
                    scene="till",
                    method=method,
                    alpha=0.0,
                    steps=steps,
                    dt=dt,
                    segments=int(seg[0]) if seg else -1,
                    cpu=cpu,
                    error=till_error(tj, dt, ref, ref_set[1]),
                    estimate=float(tj.time_error.max()) / L if ex else math.nan,
                    nit=tj.nit,
                    nsteps=len(tj.t) - 1,
                    overshoot=tj.tip_position[:, 0].max(),
                )
            )
    return rows, ref


def run_cantilever(rounds, quick):
    rod, free, f1 = cantilever()
    held = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(0.2, (1e-4, 0.0, 0.0))])
    w = 2 * math.pi * f1
    rows = []
    for alpha in (0.0, -0.5):
        base = 0.4 / w
        dts = [base, base / 2] if quick else [base, base / 2, base / 4]
        fine = base / 8  # omega dt = 0.05: much finer steps make single shooting ill-posed

        def sim(steps, dt, alpha=alpha):
            start = tr.solve(held, options=tr.simulation_options(steps))
            return tr.simulate(
                free, 48 * base, dt, initial=start, options={"steps": steps, "alpha": alpha}
            )

        ref = sim(40, fine)
        for steps in (20, 40):
            for dt in dts:
                cpu, tj = timed(lambda: sim(steps, dt), rounds)
                k = int(round(base / dt))
                amp = abs(ref.tip_position[0, 0])
                err = np.abs(tj.tip_position[::k] - ref.tip_position[::8]).max() / amp
                rows.append(
                    dict(
                        scene="cantilever",
                        method="plain",
                        alpha=alpha,
                        steps=steps,
                        dt=dt,
                        segments=1,
                        cpu=cpu,
                        error=err,
                        estimate=math.nan,
                        nit=tj.nit,
                        nsteps=len(tj.t) - 1,
                        overshoot=math.nan,
                    )
                )
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    till, ref = run_till(args.rounds, args.quick)
    cant = run_cantilever(args.rounds, args.quick)
    rows = till + cant
    print(f"load average {os.getloadavg()[0]:.1f}")
    print(
        f"{'scene':11s} {'method':12s} {'alpha':>5s} {'steps':>5s} {'dt [s]':>10s} {'M':>2s} "
        f"{'CPU [s]':>8s} {'error':>9s} {'estimate':>9s} {'nit':>6s} {'overshoot':>9s}"
    )
    for r in rows:
        print(
            f"{r['scene']:11s} {r['method']:12s} {r['alpha']:5.1f} {r['steps']:5d} "
            f"{r['dt']:10.3g} {r['segments']:2d} {r['cpu']:8.3f} {r['error']:9.2e} "
            f"{r['estimate']:9.2e} {r['nit']:6d} {r['overshoot']:9.4f}"
        )
    print(
        f"Till reference {till_reference(args.quick)} (steps, dt of the Richardson run): "
        f"first overshoot {ref.tip_position[:, 0].max():.4f} m, "
        f"tension at rest {ref.tension[0, 0]:.4f} N"
    )
    os.makedirs(OUT, exist_ok=True)
    with open(os.path.join(OUT, "dynamics.csv"), "w", newline="") as f:
        wr = csv.DictWriter(f, fieldnames=list(rows[0]))
        wr.writeheader()
        wr.writerows(rows)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, name, unit in ((axes[0], "till", "L"), (axes[1], "cantilever", "initial amplitude")):
        for method in ("plain", "extrapolated"):
            for alpha in (0.0, -0.5):
                for steps in sorted({r["steps"] for r in rows if r["scene"] == name}):
                    pts = [
                        r
                        for r in rows
                        if r["scene"] == name
                        and r["steps"] == steps
                        and r["alpha"] == alpha
                        and r["method"] == method
                    ]
                    if not pts:
                        continue
                    lab = f"{'BDF2' if alpha == 0 else 'trapezoidal'}, {steps} RK4 steps"
                    if method == "extrapolated":
                        lab += ", Richardson (dt, dt/2, dt/4)"
                    ax.loglog(
                        [p["cpu"] for p in pts],
                        [p["error"] for p in pts],
                        "s--" if method == "extrapolated" else "o-",
                        label=lab,
                    )
                    if method == "extrapolated":
                        ax.loglog(
                            [p["cpu"] for p in pts],
                            [p["estimate"] for p in pts],
                            "x:",
                            label="its error estimate",
                        )
        if name == "till":
            ax.axhline(1e-4, color="k", lw=0.8, ls=":")
            ax.axvline(TILL_CPU, color="r", lw=0.8, ls=":")
            ax.text(TILL_CPU, 2e-4, " Till's code, dt 0.05 s", color="r", fontsize=7)
        ax.set_xlabel("thread CPU time [s]")
        ax.set_ylabel(f"max tip error / {unit}")
        ax.set_title(name)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "dynamics.png"), dpi=110)
    print("wrote bench/results/dynamics.csv and dynamics.png")


if __name__ == "__main__":
    main()
