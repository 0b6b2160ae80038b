"""Throughput of a 10,000-point load sweep, measured in one run.

Scene: a three-tendon robot (tendons at 0, 120, 240 deg, offset 10 mm, 0.8 mm
nitinol-like steel rod 0.2 m long, Cosserat, inextensible tendons): tendon 0 is
retracted by q = r pi/2 (a ~90 deg bend), tendons 1 and 2 are tension-controlled at
0 N; a tip force (Fx, Fy) is varied over a grid of +-0.1 N (about +-1 EI/L^2) in each
direction: 100 x 100 = 10,000 points, one grid line (100 points) per warm-started chunk.

Measured, all in this process, one after the other:
  * single tr.solve calls: cold, and warm (guess = the neighbouring point), median us;
  * a loop of single tr.solve(scene, guess=previous) calls over the first grid lines
    (as a user would write it), solves/s;
  * tr.sweep (default options: automatic steps, tol 1e-10; its chunks go through the
    batch path, bit for bit equal to that loop), and with the throughput options below
    (the batch's lean loop), 1 and 2 threads;
  * tr.solve_batch with default options, 1 and 2 threads;
  * tr.solve_batch with the throughput options (rk8, 4 fixed steps, tol 3e-9: the
    lean warm loop + quadratic predictor), 1 and 2 threads, with and without the
    recording pass (tension_tendon_displacement=False: the tip pose, tensions and
    slacks come from the last residual evaluation; only the actuator displacement of
    the two tension-controlled tendons is then not computed), and tip only with
    ``accept_unstable=True`` (no stability verdict per point: what judging costs);
  * max |tip - reference| / L over a sample of points, the reference solved point by
    point with the adaptive integrator (rtol 1e-13, tol 1e-12);
  * peak resident memory of the sweep, in fresh subprocesses at N and 4 N points
    (growth per point against the size of the results).
The machine is shared: the load average is recorded before and after, and the
ratios between configurations (measured in one run) are the robust numbers.

    .venv/bin/python bench/throughput.py            # the full benchmark (~2-4 min)
    .venv/bin/python bench/throughput.py --fast     # 30 x 30 grid, smoke test

Writes bench/results/throughput.csv and throughput.png and prints a table.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import resource
import subprocess
import sys
import time
import warnings

import numpy as np

import tendonrod as tr

HERE = os.path.dirname(os.path.abspath(__file__))
RESULTS = os.path.join(HERE, "results")

L, R_OFF = 0.2, 0.01
FMAX = 0.1  # N, grid half-width of each tip-force component
FAST_OPTIONS = dict(steps=4, tol=3e-9)
GOAL_SOLVES_PER_S = 60_000  # solve_batch, tip only, 2 threads
GOAL_TIP_ERR = 1e-8  # of L


def bare_batch(m: int):
    """CPU time of the bare C batch (bench/batch_harness.c, built with the extension's
    flags) on the same m x m grid: {"cpu_s", "nit", "nfev"}, or None without a compiler."""
    import re
    import shlex
    import tempfile

    root = os.path.dirname(HERE)
    cdir = os.path.join(root, "csrc")
    csrc = sorted(os.path.join(cdir, f) for f in os.listdir(cdir) if f.endswith(".c"))
    with tempfile.TemporaryDirectory() as tmp:
        exe = os.path.join(tmp, "batch_harness")
        try:
            gc = subprocess.run(["pkg-config", "--cflags", "gsl"], capture_output=True, text=True)
            gl = subprocess.run(["pkg-config", "--libs", "gsl"], capture_output=True, text=True)
            with open(os.path.join(cdir, "CFLAGS")) as fh:
                flags = [ln.strip() for ln in fh if ln.strip() and not ln.startswith("#")]
            subprocess.run(
                ["gcc", *flags, "-fPIC", "-D_POSIX_C_SOURCE=200809L", "-I" + cdir]
                + shlex.split(gc.stdout)
                + [os.path.join(HERE, "batch_harness.c"), *csrc, "-o", exe]
                + shlex.split(gl.stdout or "-lgsl -lgslcblas")
                + ["-lm"],
                check=True,
            )
        except (OSError, subprocess.CalledProcessError):
            return None
        out = subprocess.run(
            [exe, str(m), str(FAST_OPTIONS["steps"]), repr(FAST_OPTIONS["tol"]), "1", "1"],
            capture_output=True,
            text=True,
            check=True,
        ).stdout
    us = float(re.search(r"([0-9.]+) us CPU per solve", out).group(1))
    nit = float(re.search(r"nit ([0-9.]+)", out).group(1))
    nfev = float(re.search(r"nfev ([0-9.]+)", out).group(1))
    return {"cpu_s": us * 1e-6 * m * m, "nit": nit, "nfev": nfev}


def make_scene() -> tr.Scene:
    rod = tr.Rod(length=L, diameter=0.8e-3, E=207e9, G=79.6e9)
    tendons = [tr.Tendon(offset=R_OFF, angle=2 * math.pi * i / 3) for i in range(3)]
    return tr.Scene(
        tr.Robot(rod, tendons),
        displacement=[R_OFF * math.pi / 2, None, None],
        tension=[None, 0.0, 0.0],
        loads=[tr.PointLoad(s=L, force=(0.0, 0.0, 0.0))],
    )


def grid_forces(m: int) -> np.ndarray:
    """(m*m, 1, 3) tip forces, C order (Fy varies fastest along a grid line)."""
    f = np.linspace(-FMAX, FMAX, m)
    F = np.zeros((m * m, 1, 3))
    F[:, 0, 0] = np.repeat(f, m)
    F[:, 0, 1] = np.tile(f, m)
    return F


def scene_at(scene, force):
    return tr.Scene(
        scene.robot,
        displacement=scene.displacement,
        tension=scene.tension,
        loads=[tr.PointLoad(s=L, force=tuple(float(v) for v in force))],
    )


def load_avg() -> float:
    return os.getloadavg()[0]


def timed(fn):
    w0, c0 = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - w0, time.process_time() - c0


def memory_child(n_side: int) -> None:
    """Run in a subprocess: peak RSS before and after a solve_batch of n_side^2 points."""
    scene = make_scene()
    F = grid_forces(n_side)
    opts = tr.Options(**FAST_OPTIONS)

    def rss_kb():
        with open("/proc/self/status") as fh:
            return next(int(line.split()[1]) for line in fh if line.startswith("VmRSS:"))

    tr.solve_batch(scene, forces=F[:200], options=opts, chunksize=n_side)  # warm up imports
    base = rss_kb()
    res = tr.solve_batch(scene, forces=F, options=opts, chunksize=n_side, threads=2)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss  # high-water mark of the process
    now = rss_kb()  # while the results are held
    nbytes = sum(
        getattr(res, k).nbytes
        for k in (
            "tip_position",
            "tip_rotation",
            "tension",
            "slack",
            "displacement",
            "status",
            "nit",
            "nfev",
            "residual_norm",
            "cold",
            "message",
        )
    )
    nbytes += sum(sys.getsizeof(m) for m in res.message)
    print(
        json.dumps(
            {
                "points": int(F.shape[0]),
                "rss_before_kb": base,
                "rss_peak_kb": peak,  # noqa
                "rss_after_kb": now,
                "result_bytes": int(nbytes),
                "inputs_bytes": int(F.nbytes),
            }
        )
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--fast", action="store_true", help="30 x 30 grid (smoke test)")
    ap.add_argument("--side", type=int, default=None, help="grid side (default 100)")
    ap.add_argument("--memory-child", type=int, default=None, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.memory_child:
        memory_child(args.memory_child)
        return
    m = args.side or (30 if args.fast else 100)
    n = m * m
    scene = make_scene()
    F = grid_forces(m)
    warnings.simplefilter("ignore", tr.ConvergenceWarning)
    rows = []
    la0 = load_avg()
    print(
        f"tendonrod throughput: {n} points ({m} x {m} tip-force grid, +-{FMAX} N), "
        f"load average {la0:.2f} on {os.cpu_count()} cores"
    )

    # ---- reference: adaptive integrator, point by point, on a sample
    rng = np.random.default_rng(0)
    sample = np.sort(rng.choice(n, size=min(n, 100), replace=False))
    ref_opts = tr.Options(integrator="adaptive", rtol=1e-13, tol=1e-12, tip_only=True)
    ref = np.array(
        [tr.solve(scene_at(scene, F[p, 0]), options=ref_opts).tip_position for p in sample]
    )

    def err(tip):
        return float(np.max(np.linalg.norm(tip[sample] - ref, axis=1)) / L)

    # ---- single solves (cold, warm), median of repeats
    tip_opts = tr.Options(tip_only=True)
    sc0, sc1 = scene_at(scene, F[n // 2, 0]), scene_at(scene, F[n // 2 + 1, 0])
    g = tr.solve(sc0, options=tip_opts)
    cold, warm = [], []
    for _ in range(30):
        t0 = time.perf_counter()
        tr.solve(sc1, options=tip_opts)
        cold.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        tr.solve(sc1, guess=g, options=tip_opts)
        warm.append(time.perf_counter() - t0)
    full = []
    for _ in range(30):
        t0 = time.perf_counter()
        tr.solve(sc1)
        full.append(time.perf_counter() - t0)
    singles = {
        "cold_us": 1e6 * float(np.median(cold)),
        "warm_us": 1e6 * float(np.median(warm)),
        "cold_full_us": 1e6 * float(np.median(full)),
    }

    # ---- loop of single tr.solve calls (warm within each grid line), on the first lines
    nloop = min(n, 10 * m)

    def loop():
        tips, guess = np.empty((nloop, 3)), None
        for p in range(nloop):
            if p % m == 0:
                guess = None
            sol = tr.solve(scene_at(scene, F[p, 0]), guess=guess, options=tip_opts)
            tips[p] = sol.tip_position
            guess = sol if sol.success else guess
        return tips

    tips_loop, wall, cpu = timed(loop)
    in_sample = sample[sample < nloop]
    loop_err = (
        float(np.max(np.linalg.norm(tips_loop[in_sample] - ref[sample < nloop], axis=1)) / L)
        if in_sample.size
        else math.nan
    )
    rows.append(
        dict(
            config="loop of tr.solve (warm)",
            threads=1,
            points=nloop,
            wall_s=wall,
            cpu_s=cpu,
            solves_per_s=nloop / wall,
            nit=math.nan,
            nfev=math.nan,
            max_rel_tip_err=loop_err,
        )
    )

    # ---- tr.sweep (its default options; batch path, exact mode)
    forces = [tuple(F[p, 0]) for p in range(0, m * m, m)]
    fy = list(np.linspace(-FMAX, FMAX, m))
    fx = list(np.linspace(-FMAX, FMAX, m))

    def build_forces():
        return [(x, y, 0.0) for x in fx for y in fy]

    for label, sopts in (
        ("tr.sweep (default options)", None),
        ("tr.sweep (rk8 x4 steps, tol 3e-9)", tr.Options(tip_only=True, **FAST_OPTIONS)),
    ):
        for threads in (1, 2):
            res, wall, cpu = timed(
                lambda: tr.sweep(
                    scene,
                    {"loads[0].force": build_forces()},
                    grid=False,
                    chunksize=m,
                    max_workers=threads,
                    progress=False,
                    options=sopts,
                )
            )
            tip = res["tip_position"]
            rows.append(
                dict(
                    config=label,
                    threads=threads,
                    points=n,
                    wall_s=wall,
                    cpu_s=cpu,
                    solves_per_s=n / wall,
                    nit=float(np.mean(res.nit)),
                    nfev=math.nan,
                    max_rel_tip_err=err(tip),
                )
            )
    del forces

    # ---- solve_batch, default options and throughput options
    for label, opts, ttd in (
        ("solve_batch (default options)", tr.Options(), True),
        ("solve_batch (rk8 x4 steps, tol 3e-9)", tr.Options(**FAST_OPTIONS), True),
        ("solve_batch (rk8 x4, tol 3e-9, tip only)", tr.Options(**FAST_OPTIONS), False),
        # the same without the stability verdict of every point: what judging costs
        (
            "solve_batch (rk8 x4, tol 3e-9, tip only, accept_unstable)",
            tr.Options(accept_unstable=True, **FAST_OPTIONS),
            False,
        ),
    ):
        for threads in (1, 2):
            res, wall, cpu = timed(
                lambda: tr.solve_batch(
                    scene,
                    forces=F,
                    options=opts,
                    chunksize=m,
                    threads=threads,
                    tension_tendon_displacement=ttd,
                )
            )
            assert res.success.all(), res.failures()[:3]
            rows.append(
                dict(
                    config=label,
                    threads=threads,
                    points=n,
                    wall_s=wall,
                    cpu_s=cpu,
                    solves_per_s=n / wall,
                    nit=float(res.nit.mean()),
                    nfev=float(res.nfev.mean()),
                    max_rel_tip_err=err(res.tip_position),
                )
            )
    # ---- the bare C batch on the same grid (bench/batch_harness.c, the extension's flags)
    bare = bare_batch(m)
    if bare is not None:
        rows.append(
            dict(
                config="bare C tr_batch_solve (tip only)",
                threads=1,
                points=n,
                wall_s=bare["cpu_s"],
                cpu_s=bare["cpu_s"],
                solves_per_s=n / bare["cpu_s"],
                nit=bare["nit"],
                nfev=bare["nfev"],
                max_rel_tip_err=math.nan,
            )
        )
    la1 = load_avg()

    # ---- memory, in fresh processes (N and 4 N points)
    mem = []
    for side in (m, 2 * m):
        out = subprocess.run(
            [sys.executable, os.path.abspath(__file__), "--memory-child", str(side)],
            capture_output=True,
            text=True,
            check=True,
        )
        mem.append(json.loads(out.stdout.strip().splitlines()[-1]))

    # ---- output
    os.makedirs(RESULTS, exist_ok=True)
    path = os.path.join(RESULTS, "throughput.csv")
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(
            [
                "# tendonrod bench/throughput.py",
                f"grid {m}x{m}",
                f"load_avg_before {la0:.2f}",
                f"load_avg_after {la1:.2f}",
                f"cpus {os.cpu_count()}",
                time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
            ]
        )
        keys = [
            "config",
            "threads",
            "points",
            "wall_s",
            "cpu_s",
            "solves_per_s",
            "solves_per_cpu_s",
            "nit",
            "nfev",
            "max_rel_tip_err",
        ]
        w.writerow(keys)
        for r in rows:
            r["solves_per_cpu_s"] = r["points"] / r["cpu_s"]
            w.writerow([r[k] if not isinstance(r[k], float) else f"{r[k]:.6g}" for k in keys])
        w.writerow([])
        w.writerow(
            [
                "single solve",
                "cold_tip_only_us",
                f"{singles['cold_us']:.1f}",
                "warm_tip_only_us",
                f"{singles['warm_us']:.1f}",
                "cold_101_nodes_us",
                f"{singles['cold_full_us']:.1f}",
            ]
        )
        for mm in mem:
            w.writerow(
                [
                    "memory",
                    "points",
                    mm["points"],
                    "rss_before_kb",
                    mm["rss_before_kb"],
                    "rss_peak_kb",
                    mm["rss_peak_kb"],
                    "rss_after_kb",
                    mm["rss_after_kb"],
                    "result_bytes",
                    mm["result_bytes"],
                ]
            )

    print(
        f"\nsingle tr.solve (tip only): cold {singles['cold_us']:.0f} us, warm {singles['warm_us']:.0f} us; "
        f"cold with 101 nodes {singles['cold_full_us']:.0f} us"
    )
    print(
        f"\n{'configuration':40s} {'thr':>3s} {'points':>6s} {'wall s':>7s} {'cpu s':>7s} {'solves/s':>9s} "
        f"{'nit':>5s} {'nfev':>5s} {'tip err/L':>9s}"
    )
    for r in rows:
        print(
            f"{r['config']:40s} {r['threads']:3d} {r['points']:6d} {r['wall_s']:7.2f} {r['cpu_s']:7.2f} "
            f"{r['solves_per_s']:9.0f} {r['solves_per_cpu_s']:7.0f} {r['nit']:5.2f} {r['nfev']:5.2f} {r['max_rel_tip_err']:9.1e}"
        )
    loop_rate, loop_cpu = rows[0]["solves_per_s"], rows[0]["solves_per_cpu_s"]
    print(
        "\nspeed-up over the loop of tr.solve, wall clock (per CPU-second; robust to the load): "
        + ", ".join(
            f"{r['config']} x{r['threads']}: {r['solves_per_s'] / loop_rate:.1f} "
            f"({r['solves_per_cpu_s'] / loop_cpu:.1f})"
            for r in rows[1:]
        )
    )
    print(
        "cores kept busy (cpu s / wall s): "
        + ", ".join(f"{r['config']} x{r['threads']}: {r['cpu_s'] / r['wall_s']:.2f}" for r in rows)
    )
    for mm in mem:
        grow = (mm["rss_after_kb"] - mm["rss_before_kb"]) * 1024
        print(
            f"memory: {mm['points']} points: peak RSS {mm['rss_peak_kb'] / 1024:.1f} MB, "
            f"RSS {mm['rss_before_kb'] / 1024:.1f} MB before -> {mm['rss_after_kb'] / 1024:.1f} MB holding "
            f"the results ({grow / 1e6:+.1f} MB; results {mm['result_bytes'] / 1e6:.1f} MB, "
            f"inputs {mm['inputs_bytes'] / 1e6:.1f} MB)"
        )
    print(f"load average before {la0:.2f}, after {la1:.2f}")
    best = [r for r in rows if r["config"] == "solve_batch (rk8 x4, tol 3e-9, tip only)"]
    two = [r for r in best if r["threads"] == 2]
    if two:
        r = two[0]
        ok = r["solves_per_s"] >= GOAL_SOLVES_PER_S and r["max_rel_tip_err"] <= GOAL_TIP_ERR
        print(
            f"goal: solve_batch tip only >= {GOAL_SOLVES_PER_S:,.0f} solves/s on 2 threads at "
            f"<= {GOAL_TIP_ERR:g} L tip error: {r['solves_per_s']:,.0f} solves/s, "
            f"{r['max_rel_tip_err']:.1e} L: {'ok' if ok else 'MISS'}"
        )
    print(f"wrote {path}")

    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    fig, ax = plt.subplots(figsize=(8, 4.2))
    labels = [
        f"{r['config']}\n{r['threads']} thread{'s' if r['threads'] > 1 else ''}" for r in rows
    ]
    vals = [r["solves_per_s"] for r in rows]
    ax.barh(
        range(len(rows)),
        vals,
        color=["0.6"] + ["C0"] * 2 + ["C4"] * 2 + ["C1"] * 2 + ["C2"] * 2 + ["C3"] * 2,
    )
    for i, v in enumerate(vals):
        ax.text(v, i, f" {v:,.0f}/s", va="center", fontsize=8)
    ax.axvline(20000, color="k", ls="--", lw=0.8)
    ax.axvline(35000, color="k", ls=":", lw=0.8)
    ax.set_yticks(range(len(rows)))
    ax.set_yticklabels(labels, fontsize=7)
    ax.set_xscale("log")
    from matplotlib.ticker import NullFormatter

    ax.xaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel("solves per second (wall clock)")
    ax.set_title(
        f"{n}-point tip-force sweep, 3-tendon robot at 90 deg "
        f"(load avg {la0:.1f}->{la1:.1f}, {os.cpu_count()} cores)",
        fontsize=9,
    )
    fig.tight_layout()
    fig.savefig(os.path.join(RESULTS, "throughput.png"), dpi=120)


if __name__ == "__main__":
    main()
