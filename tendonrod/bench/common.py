"""What the benchmark suites share: the paper's two robots, quiet and timed solves,
and the CSV files the suites write."""

from __future__ import annotations

import csv
import math
import time
import warnings

import numpy as np

from ..model import Rod
from ..solver import solve

#: Paper Section IV-B (Figs. 11-16): Kirchhoff backbone L = 0.1 m, d = 1.04 mm,
#: E = 210 GPa, G = 80 GPa, tendon offset 0.01 m.
FIG11 = dict(L=0.1, d=1.04e-3, E=210e9, G=80e9, r=0.01)
#: Paper Figs. 17-18: L = 0.2 m, d = 0.8 mm, E = 207 GPa, G = 79.6 GPa, offset 0.01 m.
FIG17 = dict(L=0.2, d=0.8e-3, E=207e9, G=79.6e9, r=0.01)


def rod_of(p, kirchhoff=True, **kw):
    """The backbone of robot ``p`` (FIG11, FIG17, or a variant) as a :class:`~tendonrod.Rod`."""
    return Rod(p["L"], p["d"], p["E"], p["G"], kirchhoff=kirchhoff, **kw)


def EI_of(p):
    return p["E"] * math.pi * p["d"] ** 4 / 64.0


def EI_scale(scene):
    """The force scale EI / L^2 [N] of ``scene``'s rod."""
    rod = scene.robot.rod
    return rod.bending_stiffness / rod.length**2


def solve_quiet(scene, options, guess=None):
    """``tendonrod.solve`` with every warning silenced (the suites record failures)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return solve(scene, guess=guess, options=options)


def time_solve(scene, options, repeats, guess=None):
    """(median seconds of ``repeats`` solves, last Solution)."""
    ts = []
    sol = None
    for _ in range(repeats):
        t0 = time.perf_counter()
        sol = solve_quiet(scene, options, guess)
        ts.append(time.perf_counter() - t0)
    return float(np.median(ts)), sol


def write_csv(path, rows, cols):
    with open(path, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=cols, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})


def read_csv(path):
    with open(path) as fh:
        return list(csv.DictReader(fh))
