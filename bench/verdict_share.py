"""The stability verdict's share of a default cold solve, two builds interleaved in one run.

Per scene of ``bench/solve.py`` (this checkout's scene list, for both builds), per build
and round, in a fresh subprocess whose ``PYTHONPATH`` puts that build first:
  * ``cold``  -- ``tr.solve(scene)`` with default options [us];
  * ``bare``  -- the same with ``Options(accept_unstable=True)`` (no verdict) [us];
  * ``verdict`` -- the verdict alone: ``Problem.stability(unknowns, steps, quick=True)``,
    what a default cold solve runs at its answer (record on the grid, elements, counts) [us];
each the median of ``--reps`` calls, in the calling thread's CPU time and in wall time.
The share is verdict / cold (per round, then the median over rounds); ``bench/solve.py``'s
``1 - bare / cold`` mixes in the path a solve takes without a verdict (the predictor's
direct try stands only if the verdict calls it stable).  Prints a table; writes nothing.

    .venv/bin/python bench/verdict_share.py --old /path/to/old/checkout [--rounds 7]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

CHILD = r"""
import json, math, os, statistics, sys, time, warnings
warnings.simplefilter("ignore")
sys.path.insert(0, {bench!r})
import tendonrod as tr
from tendonrod.solution import _compile
import solve as S
reps = {reps}
def med(fn):
    w, c = [], []
    for _ in range(reps):
        t0, c0 = time.perf_counter(), time.thread_time()
        fn()
        c.append(time.thread_time() - c0); w.append(time.perf_counter() - t0)
    return 1e6 * statistics.median(w), 1e6 * statistics.median(c)
out = {{}}
bare = tr.Options(accept_unstable=True)
for name, (scene, _, _) in S.scenes().items():
    sol = tr.solve(scene, options=bare)
    prob = _compile(sol.scene, sol.options)
    steps = max(1, sol.raw["formulation"]["steps"])
    row = {{}}
    row["cold"] = med(lambda: tr.solve(scene))
    row["bare"] = med(lambda: tr.solve(scene, options=bare))
    row["verdict"] = med(lambda: prob.stability(sol.unknowns, steps, quick=True))
    out[name] = row
out["__file__"] = tr.__file__
print(json.dumps(out))
"""


def run(checkout: str, reps: int) -> dict:
    env = dict(os.environ, PYTHONPATH=checkout)
    code = CHILD.format(bench=HERE, reps=reps)
    res = subprocess.run(
        [sys.executable, "-c", code],
        env=env,
        cwd=checkout,
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(res.stdout.strip().splitlines()[-1])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old", required=True, help="checkout of the old build (built in place)")
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--reps", type=int, default=15)
    a = ap.parse_args(argv)
    builds = {"old": os.path.abspath(a.old), "new": ROOT}
    rounds = {"old": [], "new": []}
    load0 = os.getloadavg()[0]
    for _ in range(a.rounds):
        for b, path in builds.items():
            rounds[b].append(run(path, a.reps))
    for b in builds:
        print(f"{b}: {rounds[b][0].pop('__file__')}")
        for r in rounds[b][1:]:
            r.pop("__file__")
    names = list(rounds["new"][0])
    print(
        "| scene | cold CPU us old / new | verdict CPU us old / new (ratio) | "
        "verdict share of cold, CPU old / new | wall old / new | 1 - bare/cold, CPU old / new |"
    )
    print("|---|---|---|---|---|---|")
    for n in names:

        def m(b, key, i):
            return statistics.median(r[n][key][i] for r in rounds[b])

        def share(b, i):
            return statistics.median(r[n]["verdict"][i] / r[n]["cold"][i] for r in rounds[b])

        def bare_share(b):
            return statistics.median(1 - r[n]["bare"][1] / r[n]["cold"][1] for r in rounds[b])

        ratio = statistics.median(
            rn[n]["verdict"][1] / ro[n]["verdict"][1]
            for ro, rn in zip(rounds["old"], rounds["new"])
        )
        print(
            f"| {n} | {m('old', 'cold', 1):.0f} / {m('new', 'cold', 1):.0f} | "
            f"{m('old', 'verdict', 1):.0f} / {m('new', 'verdict', 1):.0f} ({ratio:.2f}) | "
            f"{100 * share('old', 1):.0f} % / {100 * share('new', 1):.0f} % | "
            f"{100 * share('old', 0):.0f} % / {100 * share('new', 0):.0f} % | "
            f"{100 * bare_share('old'):.0f} % / {100 * bare_share('new'):.0f} % |"
        )
    print(
        f"\nmedians of {a.rounds} interleaved rounds x {a.reps} calls; load average "
        f"{load0:.2f} -> {os.getloadavg()[0]:.2f}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
