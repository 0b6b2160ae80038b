"""Raw-core timings (tendonrod._core.solve, no Python API on top): cold and warm solves of
the paper's Fig. 11 a-c and Fig. 17 scenes at 1e-8 relative tip accuracy.

For each scene: the smallest fixed rk8 (and rk4) step count whose tip is within 1e-8 L of
an adaptive reference (rtol 1e-13); then the median CPU time (time.process_time, robust
against other processes on a shared machine) of
  cold      solve from the core's own guess,
  warm      solve with guess + jacobian of the same scene with the loads scaled by 0.99,
each with 101 output nodes and tip-only.  Run from the repository root:

    .venv/bin/python csrc/tests/measure_raw.py [--repeat 201]
"""

import argparse
import math
import statistics
import time

import numpy as np

from tendonrod import _core

REL = 1e-8


def rod_row(L, d, E, G, kirchhoff=True):
    A, I = math.pi * d**2 / 4, math.pi * d**4 / 64
    return np.array([L, E * I, G * 2 * I, E * A, G * A, 1.0 if kirchhoff else 0.0]), E * I


def scenes():
    out = {}
    rod, EI = rod_row(0.1, 1.04e-3, 210e9, 80e9)
    L, r = 0.1, 0.01
    q90 = r * math.pi / 2
    one = np.array([[r, 0, 0, np.inf, L, 0, q90, 0]])
    out["fig11a transverse 1 N"] = (rod, one, np.array([[L, -1.0, 0, 0, 0, 0, 0]]))
    out["fig11b axial 1 N"] = (rod, one, np.array([[L, 0, 0, -1.0, 0, 0, 0]]))
    for alpha in (50.0, 5e4):
        EAt = alpha * 3 * EI / r**2
        tau90 = EI * (math.pi / 2) / (r * L)
        tt = np.array(
            [[r, 2 * math.pi * i / 3, 0, EAt, L, 1, tau90 if i == 0 else 0.0, 0] for i in range(3)]
        )
        free = _core.solve(
            rod, tt, np.zeros((0, 7)), np.zeros(3), integrator="adaptive", rtol=1e-13, tol=1e-13
        )
        td = tt.copy()
        td[:, 5] = 0
        td[:, 6] = free["displacement"]
        out[f"fig11c out-of-plane 0.5 N a={alpha:g}"] = (
            rod,
            td,
            np.array([[L, 0, 0.5, 0, 0, 0, 0]]),
        )
    rod17, _ = rod_row(0.2, 0.8e-3, 207e9, 79.6e9)
    t17 = np.array([[r, 0, 0, np.inf, 0.2, 0, r * math.pi / 2, 0]])
    out["fig17 taut 0.2 N"] = (rod17, t17, np.array([[0.2, 0, 0, -0.2, 0, 0, 0]]))
    out["fig17 slack 0.5 N"] = (rod17, t17, np.array([[0.2, 0, 0, -0.5, 0, 0, 0]]))
    return out


def med(fn, n):
    ts = []
    for _ in range(n):
        t0 = time.process_time()
        fn()
        ts.append(time.process_time() - t0)
    return statistics.median(ts) * 1e6


def steps_needed(rod, t, lo, ref, integrator, cap):
    L = rod[0]
    for n in range(1, cap + 1):
        s = _core.solve(rod, t, lo, np.zeros(3), integrator=integrator, steps=n, tip_only=True)
        if s["success"] and np.abs(s["position"][-1] - ref).max() <= REL * L:
            return n
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=201)
    n = ap.parse_args().repeat
    print(f"{'scene':34s} rk8 rk4 | cold us (nit/nfev) tip-only | warm us (nit/nfev) tip-only")
    for name, (rod, t, lo) in scenes().items():
        ref = _core.solve(rod, t, lo, np.zeros(3), integrator="adaptive", rtol=1e-13, tol=1e-13)
        p_ref = ref["position"][-1]
        s8 = steps_needed(rod, t, lo, p_ref, "rk8", 64)
        s4 = steps_needed(rod, t, lo, p_ref, "rk4", 400)
        kw = dict(integrator="rk8", steps=s8)
        z = np.zeros(3)
        near = _core.solve(rod, t, 0.99 * lo, z, **kw)
        g = np.concatenate([near["force"][0], near["moment"][0], near["tension"], near["slack"]])
        cold = _core.solve(rod, t, lo, z, **kw)
        warm = _core.solve(rod, t, lo, z, guess=g, jacobian=near["jacobian"], **kw)
        tc = med(lambda: _core.solve(rod, t, lo, z, **kw), n)
        tct = med(lambda: _core.solve(rod, t, lo, z, tip_only=True, **kw), n)
        tw = med(lambda: _core.solve(rod, t, lo, z, guess=g, jacobian=near["jacobian"], **kw), n)
        twt = med(
            lambda: _core.solve(
                rod, t, lo, z, guess=g, jacobian=near["jacobian"], tip_only=True, **kw
            ),
            n,
        )
        err = np.abs(cold["position"][-1] - p_ref).max() / rod[0]
        print(
            f"{name:34s} {s8:3d} {s4:3d} | {tc:7.1f} ({cold['nit']}/{cold['nfev']}) {tct:7.1f} | "
            f"{tw:6.1f} ({warm['nit']}/{warm['nfev']}) {twt:6.1f}   tip err {err:.1e}"
        )


if __name__ == "__main__":
    main()
