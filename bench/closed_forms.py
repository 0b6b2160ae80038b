"""Throughput of the closed-form ufuncs against the same formula in plain NumPy.

For each ufunc of tendonrod.analytic: evaluations per second on 10^6-element
float64 arrays (every argument an array of random, valid designs: parallel,
converging and semi-converging paths, finite k), beside the same formula
written as a plain NumPy expression (what a user would write without the
library: the paper's piecewise formulas with np.where, no domain checks).
Both are timed in the same run, in the same process, alternately, median of
REPEATS repeats.  `angle` and `deflection` are also timed in their common "shape"
form: s an array, every design parameter a scalar.

Run:  MPLBACKEND=Agg .venv/bin/python bench/closed_forms.py
Writes bench/results/closed_forms.csv and bench/results/closed_forms.png.
Goal: ufunc >= 2x the NumPy expression, and >= 5e7 evaluations/s
for `deflection` on one core.  (The one-line formulas -- equivalent_stiffness,
pattern_factor, actuation tensions -- are memory-bound: NumPy's SIMD loops
run them at about the same speed as, or faster than, our scalar loops with
their per-element domain checks; they matter for correctness, not speed.)
"""

import csv
import os
import platform
import time

import numpy as np

from tendonrod import analytic as an

N = 1_000_000
REPEATS = 15
HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "results")


# ---------------------------------------------------------------- plain NumPy formulas


def np_tension(F, z, L, EI, a, b, k):
    return (
        k
        * F
        * (a * z**3 + 3 * b * z**2)
        / (6 * EI + k * L * (2 * a**2 * L**2 + 6 * a * b * L + 6 * b**2))
    )


def np_angle(s, F, z, L, EI, a, b, k):
    tau = np_tension(F, z, L, EI, a, b, k)
    rhs = np.where(
        s < z,
        0.5 * (F + a * tau) * s**2 + (b * tau - F * z) * s,
        0.5 * a * tau * s**2 + b * tau * s - 0.5 * F * z**2,
    )
    return -rhs / EI


def np_deflection(s, F, z, L, EI, a, b, k):
    tau = np_tension(F, z, L, EI, a, b, k)
    rhs = np.where(
        s < z,
        (F + a * tau) * s**3 / 6 + 0.5 * (b * tau - F * z) * s**2,
        a * tau * s**3 / 6 + 0.5 * b * tau * s**2 - 0.5 * F * z**2 * s + F * z**3 / 6,
    )
    return -rhs / EI


def np_equivalent_stiffness(k, kB):
    return kB * k / (kB + k)


def np_pattern_factor(n):
    return np.where(n >= 3, 0.5 * n, n)


def np_actuation_angle(th, L, EI, a, b):
    return EI * th / (L * (b + a * L / 2))


def np_actuation_deflection(d, L, EI, a, b):
    return EI * d / (L**2 * (b / 2 + a * L / 6))


# ---------------------------------------------------------------- inputs


def make_inputs(n, seed=0):
    rng = np.random.default_rng(seed)
    L = rng.uniform(0.05, 0.5, n)
    EI = 10.0 ** rng.uniform(-3, 0, n)
    b = rng.uniform(1e-3, 0.03, n)
    a = -rng.choice([0.0, 0.5, 1.0], n) * b / L  # parallel / semi / converging
    k = 10.0 ** rng.uniform(-2, 4, n) * EI / (b**2 * L)
    F = rng.uniform(-5, 5, n)
    z = rng.uniform(0, 1, n) * L
    s = rng.uniform(0, 1, n) * L
    return dict(
        s=s,
        F=F,
        z=z,
        L=L,
        EI=EI,
        a=a,
        b=b,
        k=k,
        kB=10.0 ** rng.uniform(0, 6, n),
        n=rng.integers(1, 13, n).astype(float),
        th=rng.uniform(-1, 1, n),
    )


def paired_median_times(f, g, args, repeats=REPEATS):
    """Median wall time of f(*args) and of g(*args), timed alternately so that
    both see the same machine load (the ratio is the figure of merit)."""
    f(*args), g(*args)  # warm up (page faults, caches)
    tf, tg = [], []
    for _ in range(repeats):
        for fn, ts in ((f, tf), (g, tg)):
            t0 = time.perf_counter()
            fn(*args)
            ts.append(time.perf_counter() - t0)
    return float(np.median(tf)), float(np.median(tg))


def main():
    d = make_inputs(N)
    P = ("F", "z", "L", "EI", "a", "b", "k")
    S = ("s",) + P
    A = ("th", "L", "EI", "a", "b")
    scal = {key: float(d[key][0]) for key in P}
    s_only = [d["s"] * scal["L"] / d["L"]] + [scal[key] for key in P]  # s in [0, L0]
    cases = [
        ("tension", an.tension, np_tension, [d[x] for x in P]),
        ("angle", an.angle, np_angle, [d[x] for x in S]),
        ("deflection", an.deflection, np_deflection, [d[x] for x in S]),
        ("angle (s array, scalar design)", an.angle, np_angle, s_only),
        ("deflection (s array, scalar design)", an.deflection, np_deflection, s_only),
        (
            "equivalent_stiffness",
            an.equivalent_stiffness,
            np_equivalent_stiffness,
            [d["k"], d["kB"]],
        ),
        ("pattern_factor", an.pattern_factor, np_pattern_factor, [d["n"]]),
        (
            "actuation_tension_for_angle",
            an.actuation_tension_for_angle,
            np_actuation_angle,
            [d[x] for x in A],
        ),
        (
            "actuation_tension_for_deflection",
            an.actuation_tension_for_deflection,
            np_actuation_deflection,
            [d[x] for x in A],
        ),
    ]
    rows = []
    for name, uf, npf, args in cases:
        # the two must compute the same thing (round-off aside) before timing means anything
        u, v = uf(*args), npf(*args)
        scale = np.max(np.abs(v))
        assert np.max(np.abs(u - v)) <= 1e-12 * scale, name
        tu, tn = paired_median_times(uf, npf, args)
        rows.append(
            dict(
                function=name,
                n=N,
                ufunc_s=tu,
                numpy_s=tn,
                ufunc_evals_per_s=N / tu,
                numpy_evals_per_s=N / tn,
                ratio=tn / tu,
            )
        )

    w = max(len(r["function"]) for r in rows)
    print(
        f"tendonrod closed forms, {N:.0e} elements, median of {REPEATS}, one thread, "
        f"NumPy {np.__version__}, {platform.processor() or platform.machine()}"
    )
    print(f"{'function':<{w}}  {'ufunc [1/s]':>12}  {'NumPy [1/s]':>12}  {'speed-up':>8}")
    for r in rows:
        print(
            f"{r['function']:<{w}}  {r['ufunc_evals_per_s']:12.3e}  "
            f"{r['numpy_evals_per_s']:12.3e}  {r['ratio']:7.1f}x"
        )

    os.makedirs(OUT, exist_ok=True)
    with open(os.path.join(OUT, "closed_forms.csv"), "w", newline="") as fh:
        wr = csv.DictWriter(fh, fieldnames=list(rows[0]))
        wr.writeheader()
        for r in rows:
            wr.writerow({k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in r.items()})

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    fig, ax = plt.subplots(figsize=(7, 3.6), dpi=100)
    y = np.arange(len(rows))
    ax.barh(y + 0.2, [r["ufunc_evals_per_s"] for r in rows], 0.4, label="tendonrod ufunc")
    ax.barh(y - 0.2, [r["numpy_evals_per_s"] for r in rows], 0.4, label="plain NumPy")
    ax.axvline(5e7, color="k", ls=":", lw=1, label="goal for deflection (5e7/s)")
    ax.set_yticks(y, [r["function"] for r in rows], fontsize=7)
    ax.invert_yaxis()
    ax.set_xscale("log")
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    lo = min(min(r["ufunc_evals_per_s"], r["numpy_evals_per_s"]) for r in rows)
    hi = max(max(r["ufunc_evals_per_s"], r["numpy_evals_per_s"]) for r in rows)
    ax.set_xlim(lo / 2, hi * 20)
    ax.set_xlabel("evaluations per second (10^6-element arrays, one thread)")
    ax.legend(fontsize=7, loc="upper right")
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "closed_forms.png"))
    return rows


if __name__ == "__main__":
    main()
