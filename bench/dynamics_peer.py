"""Till's dynamic tendon robot: tendonrod against Till's own code, side by side.

Till's ``02_Dynamics/03_Tendon_Robot/Cpp/main.cpp`` (ContinuumRobotExamples) is built
outside this repository (its headers against the system Eigen, ``g++ -O3``, dt and N from
``-D`` flags, the tip written per step, CPU time from ``clock()``); this script reads its
tip files from --peer-dir (``tip_<dt>_<N>.dat``: rows ``t x y z``, and
``log_<dt>_<N>.txt``: its CPU time) and runs ``tr.simulate`` on the same scene
(bench/dynamics.py: ``till_scene``, ``till_motor``).  Till's loop solves step i with the
motor at t = i dt and stores the state as the time level i + 1: its actuation lags one
step, an O(dt) difference that vanishes as dt does.  Error: the largest tip distance /
L over the samples every 0.05 s, against tendonrod's finest run.  Not a test.

    .venv/bin/python bench/dynamics_peer.py --peer-dir /work/peers/till/build
"""

from __future__ import annotations

import argparse
import glob
import os
import re
import sys
import time

import numpy as np

import tendonrod as tr

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from dynamics import till_motor, till_scene  # noqa: E402


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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--peer-dir", required=True)
    args = ap.parse_args()
    L = 0.7144
    _, ref = ours(0.003125, 40)
    ts, xr = sample(ref.t, ref.tip_position)
    print(
        f"tendonrod reference (dt 0.003125 s, 40 RK4 steps): first overshoot "
        f"{ref.tip_position[:, 0].max():.4f} m"
    )
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
