"""What channel friction costs per shooting evaluation, and per solve.

The same scenes with every tendon frictionless (mu = 0: compiled without friction
states) and with friction (mu = 0.3, sliding in), interleaved round by round in one
process: the time of one shooting evaluation (a solve's time over its evaluations, at a
fixed step count so that both integrate the same steps) and of a default cold solve.
Scenes: the Fig. 17 robot (planar, one tendon, q = 15 mm, 0.2 N down at the tip), the
same solved spatially (force_spatial), and Fig. 11c's three-tendon robot (spatial,
out-of-plane tip load).  The ratio per evaluation sets ``TR_FRIC_WORK``, the work a
frictional tendon adds to an evaluation (csrc/tr_internal.h).

    PYTHONPATH=. .venv/bin/python bench/friction_cost.py [--rounds 7] [--out bench/results]

Prints a table and writes ``friction_cost.csv`` to ``--out``.
"""

from __future__ import annotations

import argparse
import csv
import math
import os
import statistics
import sys
import time
import warnings

import tendonrod as tr


def _scenes(mu: float) -> dict:
    rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    fig17 = tr.Scene(
        tr.Robot(rod, [tr.Tendon(offset=0.01, friction=mu)]),
        displacement=[0.015],
        loads=[tr.PointLoad(s=0.2, force=(0.0, 0.0, -0.2))],
    )
    rod11 = tr.Rod(length=0.1, diameter=1.04e-3, E=210e9, G=80e9, kirchhoff=True)
    r = 0.01
    EA = 50.0 * 3 * rod11.bending_stiffness / r**2
    tendons = [tr.Tendon(offset=r, angle=2 * math.pi * i / 3, EA=EA, friction=mu) for i in range(3)]
    fig11c = tr.Scene(
        tr.Robot(rod11, tendons),
        displacement=[r * math.pi / 2 * 0.98, -0.001, -0.001],
        loads=[tr.PointLoad(s=0.1, force=(0.0, 0.5, 0.0))],
    )
    return {
        "fig17 planar": (fig17, False),
        "fig17 spatial": (fig17, True),
        "fig11c": (fig11c, True),
    }


def _time(fn, n: int) -> float:
    ts = []
    for _ in range(n):
        t0 = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t0)
    return statistics.median(ts)


def measure(scene, spatial: bool, n: int) -> dict:
    fixed = tr.Options(steps=32, force_spatial=spatial)
    sol = tr.solve(scene, options=fixed, strict=True)
    per_eval = _time(lambda: tr.solve(scene, options=fixed), n) / sol.nfev
    cold_opts = tr.Options(force_spatial=spatial)
    cold = _time(lambda: tr.solve(scene, options=cold_opts), n)
    return {"eval_us": per_eval * 1e6, "cold_us": cold * 1e6}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--n", type=int, default=30, help="solves per measurement")
    ap.add_argument("--out", default=None)
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore", tr.PlausibilityWarning)
    plain, fric = _scenes(0.0), _scenes(0.3)
    rows = {name: {"plain": [], "fric": []} for name in plain}
    for k in range(args.rounds):
        for name in plain:
            order = [("plain", plain), ("fric", fric)]
            if k % 2:
                order.reverse()
            for label, sc in order:
                scene, spatial = sc[name]
                rows[name][label].append(measure(scene, spatial, args.n))
        print(f"round {k + 1}/{args.rounds} done", file=sys.stderr)
    out = []
    print(
        f"{'scene':16s} {'eval mu=0':>10s} {'eval mu=.3':>11s} {'ratio':>6s} "
        f"{'cold mu=0':>10s} {'cold mu=.3':>11s} {'ratio':>6s}   [us, medians]"
    )
    for name, r in rows.items():
        rec = {"scene": name}
        for key in ("eval_us", "cold_us"):
            p = statistics.median(x[key] for x in r["plain"])
            f = statistics.median(x[key] for x in r["fric"])
            ratio = statistics.median(b[key] / a[key] for a, b in zip(r["plain"], r["fric"]))
            rec.update({f"{key}_plain": p, f"{key}_friction": f, f"{key}_ratio": ratio})
        out.append(rec)
        print(
            f"{name:16s} {rec['eval_us_plain']:10.2f} {rec['eval_us_friction']:11.2f} "
            f"{rec['eval_us_ratio']:6.2f} {rec['cold_us_plain']:10.1f} "
            f"{rec['cold_us_friction']:11.1f} {rec['cold_us_ratio']:6.2f}"
        )
    if args.out:
        os.makedirs(args.out, exist_ok=True)
        with open(os.path.join(args.out, "friction_cost.csv"), "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(out[0]))
            w.writeheader()
            w.writerows(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
