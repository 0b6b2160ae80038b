"""Till's dynamic tendon robot: tendonrod against Till's own code, side by side.

Till's ``02_Dynamics/03_Tendon_Robot/Cpp/main.cpp`` (ContinuumRobotExamples) is built
outside this repository (its headers against the system Eigen, ``g++ -O3``, dt and N from
``-D`` flags, the tip written per step, CPU time from ``clock()``); this script reads its
tip files from --peer-dir (``tip_<dt>_<N>.dat``: rows ``t x y z``, and
``log_<dt>_<N>.txt``: its CPU time) and runs ``tr.simulate`` on the same scene
(bench/dynamics.py: ``till_scene``, ``till_motor``).  Till's loop solves step i with the
motor at t = i dt and stores the state as the time level i + 1: its actuation lags one
step, an O(dt) difference that vanishes as dt does.  Error: the largest tip distance /
L over the samples every 0.05 s, against tendonrod's converged reference (Richardson of
dt = 1.5625 and 0.78125 ms, 40 RK4 steps: bench/dynamics.py).  With --rerun N, Till's
code at its defaults (dt = 0.05 s, 200 nodes: ``till_dt0.05_N200`` in --peer-dir, run in
a scratch folder) and tendonrod's converged run (``extrapolate=True`` at dt = 12.5 ms)
alternate N times: their CPU times side by side (Till's by its clock(), ours thread
time).  Not a test.

    .venv/bin/python bench/dynamics_peer.py --peer-dir /work/peers/till/build [--rerun 3]
"""

from __future__ import annotations

import argparse
import glob
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import tendonrod as tr

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from dynamics import till_motor, till_scene, till_sim  # noqa: E402


def ours(dt, steps):
    t0 = time.thread_time()
    tj = tr.simulate(
        till_scene(), 25.0, dt, actuation=till_motor, options={"steps": steps, "drag": 1e-4}
    )
    return time.thread_time() - t0, tj


def sample(t, x, every=0.05):
    """x at the multiples of `every` within t (rows of x), by nearest time."""
    ts = np.arange(every, 25.0 + 1e-9, every)
    idx = np.clip(np.searchsorted(t, ts - 1e-9), 0, len(t) - 1)
    return ts, x[idx]


def side_by_side(args, ref, L):
    """Till's code at its defaults and tendonrod's converged run, alternating."""
    exe = os.path.join(os.path.abspath(args.peer_dir), "till_dt0.05_N200")
    till_cpu, our_cpu = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(args.rerun):
            out = subprocess.run([exe], cwd=tmp, capture_output=True, text=True, check=True)
            till_cpu.append(float(re.findall(r"cpu ([0-9.]+)", out.stdout)[0]))
            d = np.loadtxt(os.path.join(tmp, "tip.dat"))
            t0 = time.thread_time()
            tj = till_sim(20, 0.0125, extrapolate=True)
            our_cpu.append(time.thread_time() - t0)
    k = int(round(0.0125 / 0.003125))
    n = min(len(tj.t), len(ref.t[::k]))
    err = np.linalg.norm(tj.tip_position[:n] - ref.tip_position[::k][:n], axis=1).max() / L
    _, x = sample(d[:, 0], d[:, 1:4])
    _, xr = sample(ref.t, ref.tip_position)
    terr = np.abs(x - xr).max() / L
    tc, oc = statistics.median(till_cpu), statistics.median(our_cpu)
    print(f"side by side, {args.rerun} rounds, load average {os.getloadavg()[0]:.1f}:")
    print(f"  Till dt 0.05 s, 200 nodes: CPU {till_cpu} s, median {tc:.3f}; error {terr:.2e} L")
    print(
        f"  tendonrod extrapolated dt 12.5 ms (20 RK4 steps): CPU "
        f"{[round(c, 3) for c in our_cpu]} s, median {oc:.3f}; error {err:.2e} L at every "
        f"12.5 ms, its estimate {tj.time_error.max() / L:.2e} L; {tc / oc:.1f}x less CPU"
    )


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--peer-dir", required=True)
    ap.add_argument("--rerun", type=int, default=0)
    args = ap.parse_args()
    L = 0.7144
    ref = till_sim(40, 0.003125, extrapolate=True)
    ts, xr = sample(ref.t, ref.tip_position)
    print(
        f"tendonrod reference (Richardson of dt 1.5625 and 0.78125 ms, 40 RK4 steps): "
        f"first overshoot {ref.tip_position[:, 0].max():.4f} m"
    )
    if args.rerun:
        side_by_side(args, ref, L)
    print(
        f"{'code':10s} {'dt [s]':>8s} {'grid':>5s} {'CPU [s]':>8s} {'err / L':>9s} "
        f"{'overshoot':>9s}"
    )
    for f in sorted(glob.glob(os.path.join(args.peer_dir, "tip_*.dat"))):
        dt, n = re.findall(r"tip_([0-9.]+)_(\d+)\.dat", f)[0]
        d = np.loadtxt(f)
        log = open(os.path.join(args.peer_dir, f"log_{dt}_{n}.txt")).read()
        cpu = float(re.findall(r"cpu ([0-9.]+)", log)[0])
        _, x = sample(d[:, 0], d[:, 1:4])
        err = np.abs(x - xr).max() / L
        print(
            f"{'Till':10s} {float(dt):8.4g} {int(n):5d} {cpu:8.3f} {err:9.2e} {d[:, 1].max():9.4f}"
        )
    for dt, steps in ((0.05, 10), (0.05, 20), (0.025, 20), (0.0125, 20), (0.00625, 20)):
        cpu, tj = ours(dt, steps)
        _, x = sample(tj.t, tj.tip_position)
        err = np.abs(x - xr).max() / L
        print(
            f"{'tendonrod':10s} {dt:8.4g} {steps:5d} {cpu:8.3f} {err:9.2e} "
            f"{tj.tip_position[:, 0].max():9.4f}"
        )


if __name__ == "__main__":
    main()
