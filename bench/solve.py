"""Benchmark: single solves through the public API against the bare C core, with the
default ``tr.Options()`` (automatic steps verified by step doubling, tol 1e-10).

Scenes: the paper's Fig. 11c robot (L = 0.1 m, d = 1.04 mm, three tendons at 10 mm,
r^2 k L / 3EI = 50, the first retracted to a 90 deg tip angle, out-of-plane tip load) and
four tendons under gravity (spatial); Fig. 11a and Fig. 17 slack (planar); the peers'
own loaded scenes (``../shared/peers.md``: Till's displacement-controlled T0-T3, Rao's
scene R with a tip force of +x and -y), whose peer times are the fixed reference times
recorded there (medians of 31 cold solves of each peer's C++ code on this machine kind);
with ``--peer-src DIR`` the peers' own codes are built from their checkouts in DIR and
timed in rounds alternating with tendonrod's (``bench/peers_build.py``), and the table
and csv say per scene which peer times were used.

For each scene a sweep of 21 load sets, 1 % apart (the loads scaled by 1 + i/100; a scene
without loads scales its actuation instead), and, per round:
  * python: ``tr.solve(scene)`` cold; ``tr.solve(scene_i, guess=sol_{i-1})`` along the
    sweep (warm, tr.solve); ``Problem.solve(scene_i)`` along the sweep (warm, Problem);
  * C: the same three through ``bench/solve_harness.c`` (compiled here with the flags of
    setup.py into a library called through ctypes): the bare core, no Python, lazy
    outputs like the public API.
Rounds alternate C and Python in one process (these machines drift by tens of percent
between runs); the medians over rounds are reported, with the Python overhead per call
(the median over rounds of Python - C), the tip error of the default cold solve
against an adaptive reference (rtol 1e-13, tol 1e-12) and the goals of the issue.
Not a test: it prints a table and writes bench/results/solve.csv and solve.png.

    .venv/bin/python bench/solve.py [--rounds 15] [--quick] [--peer-src DIR]
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import math
import os
import platform
import shlex
import statistics
import subprocess
import sys
import tempfile
import time
import warnings

import numpy as np
from peers_build import built_peers  # --peer-src: the peers' own codes, built and timed

import tendonrod as tr
from tendonrod.compiled import _TD, pack_scene

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
OUT = os.path.join(HERE, "results")
REF = tr.Options(integrator="adaptive", rtol=1e-13, tol=1e-12)


def reference(scene: tr.Scene) -> tr.Solution:
    """The adaptive reference solve; a failure raises.  On scenes with large tensions tol
    1e-12 lies below the residual's round-off floor: the core then stops at the floor
    (status ``STATUS_ROUNDOFF``, a success with a warning), as close as double precision
    gets, and that is the reference."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tr.ConvergenceWarning)
        return tr.solve(scene, options=REF, strict=True)


SWEEP = 21  # load sets per sweep, 1 % apart
REPS = 5  # solves (or sweeps) per round and measurement
NO_VERDICT = tr.Options(accept_unstable=True)
# the peers' cold solves in thread CPU time [ms], measured interleaved on a loaded
# machine of this kind (../shared/peers.md, "how to measure on a loaded machine")
PEER_CPU_MS = {
    "Till T0 (gravity +x)": 90.7,
    "Till T1 (no load)": 68.5,
    "Till T2 (tip -0.2 N x)": 90.5,
    "Till T3 (tip 0.2 N y)": 87.3,
    "Rao R (tip 0.1 N x)": 107.6,
    "Rao R (tip -0.1 N y)": 57.8,
}

# goals (us): spatial scenes; planar ones "about half"; peers: cold ratio
GOAL = {"spatial": (200.0, 30.0, 20.0), "planar": (100.0, 15.0, 10.0)}
GOAL_OVERHEAD_US = 5.0
GOAL_PEER_RATIO = 200.0


# --------------------------------------------------------------------------- scenes
def fig11_rod():
    return tr.Rod(0.1, 1.04e-3, 210e9, 80e9, kirchhoff=True)


def lock(robot, tensions, loads):
    """Actuate by tension, then lock the actuators: the displacement-controlled scene."""
    free = reference(tr.Scene(robot, tension=tensions))
    return tr.Scene(robot, displacement=list(free.displacement), loads=loads)


def scenes() -> dict:
    """name -> (scene, class "spatial" / "planar", peer's cold time [ms] or None)."""
    out = {}
    rod = fig11_rod()
    EI, L, r = rod.bending_stiffness, rod.length, 0.01
    EA = 50.0 * 3 * EI / r**2
    three = tr.Robot(rod, [tr.Tendon(offset=r, angle=2 * math.pi * i / 3, EA=EA) for i in range(3)])
    tau90 = EI * (math.pi / 2) / (r * L)
    out["fig11c 3 tendons, out-of-plane load"] = (
        lock(three, [tau90, 0.0, 0.0], [tr.PointLoad(s=L, force=(0, 0.5, 0))]),
        "spatial",
        None,
    )
    c17 = tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9)
    four = tr.Robot(c17, [tr.Tendon(offset=r, angle=i * math.pi / 2) for i in range(4)])
    out["4 tendons, gravity"] = (
        tr.Scene(
            four,
            displacement=[4e-3, 2e-3, -5e-3, -3e-3],
            loads=[tr.DistributedLoad(force=(0, 0, -0.5))],
        ),
        "spatial",
        None,
    )
    # the same robot co-contracted: stiff tendons (EA = 1e5 N), the first retracted
    # r pi/2 and the other two held at 0 (tensions ~5 kN), out-of-plane tip load -- the
    # scene where the stability verdict is hardest
    stiff = tr.Robot(
        rod, [tr.Tendon(offset=r, angle=2 * math.pi * i / 3, EA=1e5) for i in range(3)]
    )
    out["3 tendons co-contracted, EA 1e5 N"] = (
        tr.Scene(
            stiff,
            displacement=[r * math.pi / 2, 0.0, 0.0],
            loads=[tr.PointLoad(s=L, force=(0, 0.5, 0))],
        ),
        "spatial",
        None,
    )
    # a plain Cosserat cantilever under a transverse tip load F L^2/EI = 10: direct Newton
    # converges where a cold solve goes by load continuation
    plain = tr.Rod(0.2, 2e-3, 1e7, 1e7 / 3)
    out["plain cantilever F L^2/EI = 10"] = (
        tr.Scene(
            tr.Robot(plain, []),
            loads=[tr.PointLoad(s=0.2, force=(10 * plain.bending_stiffness / 0.2**2, 0, 0))],
        ),
        "spatial",
        None,
    )
    one = tr.Robot(rod, [tr.Tendon(offset=r)])
    out["fig11a transverse (planar)"] = (
        tr.Scene(one, displacement=[r * math.pi / 2], loads=[tr.PointLoad(s=L, force=(-1, 0, 0))]),
        "planar",
        None,
    )
    k17 = tr.Robot(tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True), [tr.Tendon(offset=r)])
    out["fig17 slack 0.5 N (planar)"] = (
        tr.Scene(
            k17, displacement=[r * math.pi / 2], loads=[tr.PointLoad(s=0.2, force=(0, 0, -0.5))]
        ),
        "planar",
        None,
    )
    # Till's displacement-control example (peers.md)
    till = tr.Robot(
        tr.Rod(length=0.5, diameter=2e-3, E=200e9, G=80e9),
        [tr.Tendon(offset=0.01506, angle=i * math.pi / 2, EA=1e4) for i in range(4)],
    )
    q = [5e-3, 0.0, -5e-3, 0.0]
    w = 8000 * 9.81 * math.pi * 1e-6  # N/m: steel, radius 1 mm
    for name, loads, ms in (
        ("Till T0 (gravity +x)", [tr.DistributedLoad(force=(w, 0, 0))], 80.6),
        ("Till T1 (no load)", [], 62.3),
        ("Till T2 (tip -0.2 N x)", [tr.PointLoad(s=0.5, force=(-0.2, 0, 0))], 77.7),
        ("Till T3 (tip 0.2 N y)", [tr.PointLoad(s=0.5, force=(0, 0.2, 0))], 95.6),
    ):
        out[name] = (tr.Scene(till, displacement=q, loads=loads), "spatial", ms)
    rao = tr.Robot(
        tr.Rod(length=0.4, diameter=1.4e-3, E=54e9, G=54e9 / 2.6),
        [tr.Tendon(offset=0.01, angle=math.pi / 2)],
    )
    for name, f, ms in (
        ("Rao R (tip 0.1 N x)", (0.1, 0, 0), 70.3),
        ("Rao R (tip -0.1 N y)", (0, -0.1, 0), 32.0),
    ):
        out[name] = (
            tr.Scene(rao, tension=[2.0], loads=[tr.PointLoad(s=0.4, force=f)]),
            "spatial",
            ms,
        )
    return out


def scaled(scene: tr.Scene, factor: float) -> tr.Scene:
    """The loads scaled by ``factor``; a scene without loads scales its actuation."""
    if scene.loads:
        loads = []
        for ld in scene.loads:
            if isinstance(ld, tr.PointLoad):
                f, mo = np.asarray(ld.force) * factor, np.asarray(ld.moment) * factor
                loads.append(dataclasses.replace(ld, force=tuple(f), moment=tuple(mo)))
            else:
                loads.append(dataclasses.replace(ld, force=tuple(np.asarray(ld.force) * factor)))
        return dataclasses.replace(scene, loads=loads)
    disp = [None if v is None else v * factor for v in scene.displacement]
    ten = [None if v is None else v * factor for v in scene.tension]
    return dataclasses.replace(scene, displacement=disp, tension=ten)


def sweep_of(scene):
    return [scaled(scene, 1.0 + i / 100) for i in range(SWEEP)]


# --------------------------------------------------------------------------- the bare core
def setup_flags() -> list[str]:
    """The C flags of the extension build (csrc/CFLAGS, as setup.py reads them)."""
    with open(os.path.join(ROOT, "csrc", "CFLAGS")) as fh:
        flags = [ln.strip() for ln in fh if ln.strip() and not ln.startswith("#")]
    return flags + ["-fPIC", "-D_POSIX_C_SOURCE=200809L"]


class Harness:
    """bench/solve_harness.c built as a shared library (with the extension's flags),
    called through ctypes so that C and Python measurements alternate in one process."""

    def __init__(self, tmp: str):
        import ctypes

        gsl_c = subprocess.run(["pkg-config", "--cflags", "gsl"], capture_output=True, text=True)
        gsl_l = subprocess.run(["pkg-config", "--libs", "gsl"], capture_output=True, text=True)
        lib = os.path.join(tmp, "libsolve_harness.so")
        cdir = os.path.join(ROOT, "csrc")
        csrc = sorted(os.path.join(cdir, f) for f in os.listdir(cdir) if f.endswith(".c"))
        cmd = (
            ["gcc", *setup_flags(), "-shared", "-DHARNESS_LIBRARY", "-I" + cdir]
            + shlex.split(gsl_c.stdout)
            + [os.path.join(HERE, "solve_harness.c"), *csrc, "-o", lib]
            + shlex.split(gsl_l.stdout or "-lgsl -lgslcblas")
            + ["-lm"]
        )
        subprocess.run(cmd, check=True)
        self._lib = ctypes.CDLL(lib)
        self._lib.harness_run_text.argtypes = [
            ctypes.c_char_p,
            ctypes.c_int,
            ctypes.POINTER(ctypes.c_double),
        ]
        self._out = (ctypes.c_double * 6)()

    def run(self, text: str, reps: int) -> dict:
        if self._lib.harness_run_text(text.encode(), reps, self._out) != 0:
            raise RuntimeError("solve_harness failed (its message is on stderr)")
        keys = ("cold_us", "warm_guess_us", "warm_us", "nfev_cold", "nfev_warm_guess", "nfev_warm")
        return dict(zip(keys, self._out))


def harness_input(sweep, nodes: int) -> str:
    """The sweep in the harness's text format (see bench/solve_harness.c)."""
    rod, tendons, loads, _ = pack_scene(sweep[0])
    nt, nl = tendons.shape[0], loads.shape[0]
    lines = [f"{nt} {nl} {nodes} {len(sweep)}", " ".join(repr(float(v)) for v in rod)]
    lines += [" ".join(repr(float(v)) for v in row) for row in tendons]
    for sc in sweep:
        _, t, ld, dist = pack_scene(sc)
        lines.append(" ".join(repr(float(v)) for v in t[:, _TD["value"]]))
        lines += [" ".join(repr(float(v)) for v in row) for row in ld]
        lines.append(" ".join(repr(float(v)) for v in dist))
    return "\n".join(lines) + "\n"


# --------------------------------------------------------------------------- python
def median_time(fn, reps: int) -> float:
    return median_times(fn, reps)[0]


def median_times(fn, reps: int) -> tuple[float, float]:
    """Medians [s] of wall time and of this thread's CPU time over ``reps`` calls."""
    wall, cpu = [], []
    for _ in range(reps):
        t0, c0 = time.perf_counter(), time.thread_time()
        fn()
        cpu.append(time.thread_time() - c0)
        wall.append(time.perf_counter() - t0)
    return statistics.median(wall), statistics.median(cpu)


def python_round(sw, chain, reps: int) -> dict:
    """Per-call medians [us] of the three kinds on one sweep (wall time), the cold solve
    in thread CPU time too, and the cold solve without the stability verdict
    (``accept_unstable=True``: what the verdict costs)."""
    cold, cold_cpu = median_times(lambda: tr.solve(sw[0]), reps)
    bare, bare_cpu = median_times(lambda: tr.solve(sw[0], options=NO_VERDICT), reps)

    def warm_guess():
        for i in range(1, len(sw)):
            tr.solve(sw[i], guess=chain[i - 1])

    def warm_problem():
        prob = tr.Problem(sw[0])
        prob.solve()
        t0 = time.perf_counter()
        for i in range(1, len(sw)):
            prob.solve(sw[i])
        return time.perf_counter() - t0

    wg = median_time(warm_guess, reps) / (len(sw) - 1)
    wp = statistics.median(warm_problem() for _ in range(reps)) / (len(sw) - 1)
    return {
        "cold_us": 1e6 * cold,
        "warm_guess_us": 1e6 * wg,
        "warm_us": 1e6 * wp,
        "cold_cpu_us": 1e6 * cold_cpu,
        "noverdict_us": 1e6 * bare,
        "noverdict_cpu_us": 1e6 * bare_cpu,
    }


def bench_scene(name, scene, klass, peer_ms, harness, rounds, peer=None):
    L = scene.robot.rod.length
    sw = sweep_of(scene)
    chain, guess = [], None
    for sc in sw:
        guess = tr.solve(sc, guess=guess, strict=True)
        chain.append(guess)
    text = harness_input(sw, 101)
    py, c = [], []
    peer_runs = []
    for _ in range(rounds):
        c.append(harness.run(text, REPS))
        py.append(python_round(sw, chain, REPS))
        if peer is not None:  # the built peer's round alternates with tendonrod's
            peer_runs.append(peer.run(name))
    med = {}
    for key in ("cold_us", "warm_guess_us", "warm_us"):
        med["py_" + key] = statistics.median(r[key] for r in py)
        med["c_" + key] = statistics.median(r[key] for r in c)
        med["overhead_" + key] = statistics.median(p[key] - q[key] for p, q in zip(py, c))
    for key in ("cold_cpu_us", "noverdict_us", "noverdict_cpu_us"):
        med["py_" + key] = statistics.median(r[key] for r in py)
    # the verdict's share of a default cold solve, per round (CPU time), then the median
    med["verdict_share"] = statistics.median(
        1.0 - r["noverdict_cpu_us"] / r["cold_cpu_us"] for r in py
    )
    cold = tr.solve(scene)
    warm = tr.solve(sw[1], guess=chain[0])
    prob = tr.Problem(sw[0])
    prob.solve()
    pw = prob.solve(sw[1])
    ref = reference(scene)
    goal = GOAL[klass]
    peer_cpu, peer_times = PEER_CPU_MS.get(name), "fixed table" if peer_ms else ""
    if peer_runs:
        peer_cpu = statistics.median(t for r in peer_runs for t in r["cpu_ms"])
        peer_ms = statistics.median(t for r in peer_runs for t in r["wall_ms"])
        peer_times = "built, interleaved" + (
            "" if all(r["ok"] for r in peer_runs) else " (peer failed)"
        )
    row = dict(
        scene=name,
        formulation=repr(cold.formulation),
        steps=cold.formulation.steps,
        tip_err=float(np.linalg.norm(cold.tip_position - ref.tip_position) / L),
        nit_cold=cold.nit,
        nfev_cold=cold.nfev,
        nfev_warm_guess=warm.nfev,
        nfev_warm=pw.nfev,
        c_nfev_cold=c[-1]["nfev_cold"],
        c_nfev_warm_guess=c[-1]["nfev_warm_guess"],
        c_nfev_warm=c[-1]["nfev_warm"],
        **med,
        goal_cold_us=goal[0],
        goal_warm_guess_us=goal[1],
        goal_warm_us=goal[2],
        peer_ms=peer_ms if peer_ms else math.nan,
        peer_ratio=(1e3 * peer_ms / med["py_cold_us"]) if peer_ms else math.nan,
        peer_cpu_ms=peer_cpu if peer_cpu else math.nan,
        peer_cpu_ratio=1e3 * peer_cpu / med["py_cold_cpu_us"] if peer_cpu else math.nan,
        peer_times=peer_times,
    )
    return row


def mark(ok: bool) -> str:
    return "ok" if ok else "MISS"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=15)
    ap.add_argument("--quick", action="store_true", help="3 rounds")
    ap.add_argument(
        "--peer-src",
        metavar="DIR",
        help="build and time the peers' own codes from their checkouts in DIR "
        "(bench/peers_build.py), interleaved; else their fixed table",
    )
    args = ap.parse_args(argv)
    rounds = 3 if args.quick else args.rounds
    warnings.simplefilter("error", tr.ConvergenceWarning)
    la0 = os.getloadavg()[0]
    rows, all_scenes = [], scenes()
    peers, peer_note = built_peers(args.peer_src, all_scenes) if args.peer_src else ({}, "")
    with tempfile.TemporaryDirectory() as tmp:
        harness = Harness(tmp)
        print(
            f"{'scene':<38s} {'steps':>5s} {'tip err/L':>9s} | {'cold us (C)':>16s} "
            f"{'warm tr.solve (C)':>18s} {'warm Problem (C)':>17s} | overhead cold/warm/P "
            f"| goals | peer x | verdict % | nit"
        )
        for name, (scene, klass, peer_ms) in all_scenes.items():
            r = bench_scene(name, scene, klass, peer_ms, harness, rounds, peers.get(name))
            rows.append(r)
            goals = [
                r["py_cold_us"] <= r["goal_cold_us"],
                r["py_warm_guess_us"] <= r["goal_warm_guess_us"],
                r["py_warm_us"] <= r["goal_warm_us"],
                r["overhead_warm_us"] <= GOAL_OVERHEAD_US,
            ]
            peer = (
                f"{r['peer_ratio']:.0f}x wall, {r['peer_cpu_ratio']:.0f}x CPU "
                f"{mark(r['peer_cpu_ratio'] >= GOAL_PEER_RATIO)} ({r['peer_times']})"
                if peer_ms
                else ""
            )
            print(
                f"{name:<38s} {r['steps']:5d} {r['tip_err']:9.1e} | "
                f"{r['py_cold_us']:7.1f} ({r['c_cold_us']:6.1f}) "
                f"{r['py_warm_guess_us']:8.1f} ({r['c_warm_guess_us']:6.1f}) "
                f"{r['py_warm_us']:8.1f} ({r['c_warm_us']:6.1f}) | "
                f"{r['overhead_cold_us']:5.1f} {r['overhead_warm_guess_us']:5.1f} "
                f"{r['overhead_warm_us']:5.1f} | {' '.join(mark(g) for g in goals)} | {peer} | "
                f"{100 * r['verdict_share']:4.0f} | {r['nit_cold']}",
                flush=True,
            )
    la1 = os.getloadavg()[0]
    os.makedirs(OUT, exist_ok=True)
    path = os.path.join(OUT, "solve.csv")
    with open(path, "w", newline="") as f:
        f.write(
            f"# bench/solve.py {time.strftime('%Y-%m-%dT%H:%M:%SZ', time.gmtime())}; "
            f"{platform.processor() or platform.machine()}, {os.cpu_count()} cpus, python "
            f"{sys.version.split()[0]}, numpy {np.__version__}, GSL {tr.gsl_version}; "
            f"{rounds} rounds x {REPS}; load average {la0:.2f} -> {la1:.2f}"
            f"{'; ' + peer_note if peer_note else ''}\n"
        )
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(
        f"\nmedians of {rounds} rounds; goals (us) spatial cold/warm/Problem "
        f"{GOAL['spatial']}, planar {GOAL['planar']}, Python overhead of a warm Problem solve "
        f"<= {GOAL_OVERHEAD_US}, peers cold >= {GOAL_PEER_RATIO:.0f}x; load average "
        f"{la0:.2f} -> {la1:.2f}\nwrote {path}"
    )
    if peer_note:
        print(peer_note)
    plot(rows)


def plot(rows):
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:  # pragma: no cover
        return
    fig, axes = plt.subplots(1, 3, figsize=(13, 5.5), sharey=True)
    y = np.arange(len(rows))
    for ax, key, title in zip(
        axes,
        ("cold_us", "warm_guess_us", "warm_us"),
        ("tr.solve cold", "tr.solve warm (1 % load step)", "Problem.solve warm"),
    ):
        ax.barh(y - 0.2, [r["py_" + key] for r in rows], 0.4, label="public API")
        ax.barh(y + 0.2, [r["c_" + key] for r in rows], 0.4, label="bare C core")
        goals = [r["goal_" + key] for r in rows]
        ax.scatter(goals, y, marker="|", s=300, color="k", label="goal")
        ax.set_xscale("log")
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("median time per solve [us]")
    axes[0].set_yticks(y, [r["scene"] for r in rows], fontsize=8)
    axes[0].invert_yaxis()
    axes[-1].legend(fontsize=8)
    fig.suptitle("default tr.Options(): public API against the bare core (bench/solve.py)")
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "solve.png"), dpi=120)


if __name__ == "__main__":
    main()
