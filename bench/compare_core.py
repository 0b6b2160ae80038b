"""Speed of the bare C core of two checkouts on existing scenes, interleaved in one process.

bench/solve_harness.c is built twice with the extension's flags (csrc/CFLAGS): once from
this checkout's csrc/, once from the other's (``--old``), into two shared libraries that
ctypes loads side by side (each resolves its own symbols: RTLD_LOCAL).  Each round runs,
per scene, the harness's cold, warm-from-guess and warm (one model) solves through the old
and then the new library (the order alternating between rounds), so both see the same
machine load; the report gives the median over rounds of each time and of the ratio
new/old.  Scenes from bench/solve.py: Fig. 11c (spatial, three tendons, out-of-plane
load), Fig. 11a (planar) and Till's T3 (spatial, four extensible tendons, Cosserat).

    .venv/bin/python bench/compare_core.py --old /path/to/old/checkout [--rounds 15]

(``--new`` another checkout instead of this one: ``--new`` = ``--old`` gives the noise.)
"""

from __future__ import annotations

import argparse
import ctypes
import os
import shlex
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import solve as bench_solve  # noqa: E402  (bench/solve.py: scenes, sweeps, harness input)

SCENES = (
    "fig11c 3 tendons, out-of-plane load",
    "fig11a transverse (planar)",
    "Till T3 (tip 0.2 N y)",
)


def build(root: str, out: str) -> ctypes.CDLL:
    gsl_c = subprocess.run(["pkg-config", "--cflags", "gsl"], capture_output=True, text=True)
    gsl_l = subprocess.run(["pkg-config", "--libs", "gsl"], capture_output=True, text=True)
    cdir = os.path.join(root, "csrc")
    csrc = sorted(os.path.join(cdir, f) for f in os.listdir(cdir) if f.endswith(".c"))
    cmd = (
        ["gcc", *bench_solve.setup_flags(), "-shared", "-DHARNESS_LIBRARY", "-I" + cdir]
        + shlex.split(gsl_c.stdout)
        + [os.path.join(HERE, "solve_harness.c"), *csrc, "-o", out]
        + shlex.split(gsl_l.stdout or "-lgsl -lgslcblas")
        + ["-lm"]
    )
    subprocess.run(cmd, check=True)
    lib = ctypes.CDLL(out)
    lib.harness_run_text.argtypes = [ctypes.c_char_p, ctypes.c_int, ctypes.POINTER(ctypes.c_double)]
    return lib


def run(lib, text: bytes, reps: int) -> tuple:
    out = (ctypes.c_double * 6)()
    if lib.harness_run_text(text, reps, out) != 0:
        raise RuntimeError("solve_harness failed")
    return out[0], out[1], out[2]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old", required=True)
    ap.add_argument("--new", default=bench_solve.ROOT, help="default: this checkout")
    ap.add_argument("--rounds", type=int, default=15)
    ap.add_argument("--reps", type=int, default=5)
    args = ap.parse_args(argv)
    all_scenes = bench_solve.scenes()
    texts = {
        name: bench_solve.harness_input(bench_solve.sweep_of(all_scenes[name][0]), 101).encode()
        for name in SCENES
    }
    with tempfile.TemporaryDirectory() as tmp:
        libs = {
            "old": build(args.old, os.path.join(tmp, "old.so")),
            "new": build(args.new, os.path.join(tmp, "new.so")),
        }
        times = {(n, b): [] for n in SCENES for b in libs}
        for r in range(args.rounds):
            order = ("old", "new") if r % 2 == 0 else ("new", "old")
            for name in SCENES:
                for b in order:
                    times[(name, b)].append(run(libs[b], texts[name], args.reps))
            print(f"round {r + 1}/{args.rounds} done", file=sys.stderr)
    kinds = ("cold", "warm_guess", "warm")
    print(f"{'scene':40s} {'kind':10s} {'old us':>9s} {'new us':>9s} {'new/old':>8s}")
    for name in SCENES:
        for k, kind in enumerate(kinds):
            old = [t[k] for t in times[(name, "old")]]
            new = [t[k] for t in times[(name, "new")]]
            ratio = statistics.median(n / o for n, o in zip(new, old))
            print(
                f"{name[:40]:40s} {kind:10s} {statistics.median(old):9.1f} "
                f"{statistics.median(new):9.1f} {ratio:8.3f}"
            )


if __name__ == "__main__":
    main()
