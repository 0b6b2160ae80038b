"""Python overhead of a solve through the public API over the bare C core, for two builds
measured interleaved in one run.

The bare core is ``bench/solve.py``'s harness (``bench/solve_harness.c`` through ctypes,
the extension's flags), built once from this checkout, twice: timing wall time and
timing the thread's CPU time; the two checkouts must have the same ``csrc`` (this
compares the Python and glue layers).  Per build one worker process (``PYTHONPATH`` =
that build's checkout) loads both; then, round after round, the driver asks each worker in turn
for one round of every scene: the harness's warm sweep and cold solve, then the same
through the public API (``Problem.solve`` along the sweep of 21 load sets 1 % apart,
``tr.solve`` cold; ``Problem.solve`` along the sweep again with new Scene objects of the
same values, built before the clock starts, so that nothing cached on a scene helps),
each as the median of REPS repetitions, in wall time and in the
thread's CPU time.  The overhead of a round is API - C; the report gives the medians
over rounds, per build, and the ratio new/old of the warm ``Problem.solve``.

Scenes: ``bench/solve.py``'s Fig. 11c, Till T0, Fig. 17 and Rao R (tip 0.1 N x).

    .venv/bin/python bench/python_overhead.py --old /path/to/old/checkout [--rounds 9]
    PYTHONPATH=$PWD .venv/bin/python bench/python_overhead.py --split "Till T0 (gravity +x)"
    .venv/bin/python bench/python_overhead.py --old /path/to/old/checkout --glue --rounds 6

``--glue``: the raw ``_core.Problem.solve`` call alone (no Python layer), the two builds
in alternating processes.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
NEW = os.path.dirname(HERE)
SCENES = (
    "fig11c 3 tendons, out-of-plane load",
    "Till T0 (gravity +x)",
    "fig17 slack 0.5 N (planar)",
    "Rao R (tip 0.1 N x)",
)

WORKER = r"""
import dataclasses, json, os, statistics, sys, time, warnings
sys.path.insert(0, os.path.join(sys.argv[1], "bench"))
import solve as B
import tendonrod as tr
warnings.simplefilter("ignore")
REPS = int(sys.argv[2])
import ctypes

def load(path):
    # a bench/solve.py Harness of the library at path (built once by the driver)
    h = B.Harness.__new__(B.Harness)
    h._lib = ctypes.CDLL(path)
    h._lib.harness_run_text.argtypes = [
        ctypes.c_char_p, ctypes.c_int, ctypes.POINTER(ctypes.c_double)]
    h._out = (ctypes.c_double * 6)()
    return h

harness, harness_cpu = load(sys.argv[4]), load(sys.argv[5])
names = json.loads(sys.argv[3])
all_scenes = B.scenes()
data = {}
for name in names:
    sw = B.sweep_of(all_scenes[name][0])
    data[name] = (sw, B.harness_input(sw, 101))

def api(sw):
    wall, cpu = [], []
    for _ in range(REPS):
        prob = tr.Problem(sw[0])
        prob.solve()
        t0, c0 = time.perf_counter(), time.thread_time()
        for i in range(1, len(sw)):
            prob.solve(sw[i])
        cpu.append((time.thread_time() - c0) / (len(sw) - 1))
        wall.append((time.perf_counter() - t0) / (len(sw) - 1))
    fw, fc = [], []
    for _ in range(REPS):
        # new Scene objects of the same values, made before the clock starts: what a
        # loop that builds its scene per call costs beyond the scene's own construction
        fresh = [dataclasses.replace(sc) for sc in sw]
        prob = tr.Problem(fresh[0])
        prob.solve()
        t0, c0 = time.perf_counter(), time.thread_time()
        for i in range(1, len(sw)):
            prob.solve(fresh[i])
        fc.append((time.thread_time() - c0) / (len(sw) - 1))
        fw.append((time.perf_counter() - t0) / (len(sw) - 1))
    cw, cc = [], []
    for _ in range(REPS):
        t0, c0 = time.perf_counter(), time.thread_time()
        tr.solve(sw[0])
        cc.append(time.thread_time() - c0)
        cw.append(time.perf_counter() - t0)
    med = statistics.median
    return {"warm": 1e6 * med(wall), "warm_cpu": 1e6 * med(cpu),
            "fresh": 1e6 * med(fw), "fresh_cpu": 1e6 * med(fc),
            "cold": 1e6 * med(cw), "cold_cpu": 1e6 * med(cc)}

print("ready", flush=True)
for line in sys.stdin:
    out = {}
    for name in names:
        sw, text = data[name]
        c = harness.run(text, REPS)
        cc = harness_cpu.run(text, REPS)
        p = api(sw)
        out[name] = {"c_warm": c["warm_us"], "c_cold": c["cold_us"],
                     "c_warm_cpu": cc["warm_us"], "c_cold_cpu": cc["cold_us"], **p}
    print(json.dumps(out), flush=True)
"""


def build_harnesses(tmp: str) -> tuple[str, str]:
    """This checkout's bench/solve_harness.c built twice (bench/solve.py's Harness): timing
    wall time, and timing the calling thread's CPU time (its clock_gettime renamed to a
    function that reads CLOCK_THREAD_CPUTIME_ID; tr_poll's cadence then follows CPU
    time).  Both builds call the same bare core: the csrc of the two checkouts must
    agree (checked by the caller)."""
    sys.path.insert(0, HERE)
    import solve as B

    B.Harness(tmp)
    clock_c = os.path.join(tmp, "thread_clock.c")
    with open(clock_c, "w") as fh:
        fh.write(
            "#include <time.h>\n#undef clock_gettime\n"
            "int clock_gettime(clockid_t, struct timespec *);\n"
            "int bench_thread_clock(clockid_t c, struct timespec *t)"
            "{ (void)c; return clock_gettime(CLOCK_THREAD_CPUTIME_ID, t); }\n"
        )
    flags = B.setup_flags
    B.setup_flags = lambda: flags() + ["-Dclock_gettime=bench_thread_clock", clock_c]
    cpu = os.path.join(tmp, "cpu")
    os.makedirs(cpu)
    B.Harness(cpu)
    B.setup_flags = flags
    return os.path.join(tmp, "libsolve_harness.so"), os.path.join(cpu, "libsolve_harness.so")


def same_core(old: str) -> bool:
    """Whether the two checkouts' csrc (the bare core the harness builds) are identical."""
    names = sorted(os.listdir(os.path.join(NEW, "csrc")))
    if names != sorted(os.listdir(os.path.join(old, "csrc"))):
        return False
    for n in names:
        a, b = os.path.join(NEW, "csrc", n), os.path.join(old, "csrc", n)
        if os.path.isfile(a):
            with open(a, "rb") as fa, open(b, "rb") as fb:
                if fa.read() != fb.read():
                    return False
    return True


class Worker:
    def __init__(self, checkout: str, reps: int, libs: tuple[str, str]):
        env = dict(os.environ, PYTHONPATH=checkout)
        self.p = subprocess.Popen(
            [sys.executable, "-c", WORKER, checkout, str(reps), json.dumps(SCENES), *libs],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
            env=env,
            cwd=checkout,
        )
        assert self.p.stdout is not None and self.p.stdin is not None
        if self.p.stdout.readline().strip() != "ready":
            raise RuntimeError(f"the worker of {checkout} did not start")

    def round(self) -> dict:
        assert self.p.stdout is not None and self.p.stdin is not None
        self.p.stdin.write("go\n")
        self.p.stdin.flush()
        return json.loads(self.p.stdout.readline())

    def close(self):
        assert self.p.stdin is not None
        self.p.stdin.close()
        self.p.wait()


def split(name: str, reps: int = 100) -> None:
    """This checkout only, one process: ``Problem.solve(scene_i)`` along the sweep against
    the raw ``_core.Problem.solve(record=False)`` of a second Problem (values set, same
    sequence), alternated call by call, thread CPU time: the Python layer's share (the
    raw call includes the glue)."""
    import time

    sys.path.insert(0, HERE)
    import solve as B

    import tendonrod as tr
    from tendonrod.compiled import value_vector

    sw = B.sweep_of(B.scenes()[name][0])
    pa, pb = tr.Problem(sw[0]), tr.Problem(sw[0])
    pa.solve()
    pb.solve()
    c, tt, api, raw = pb._c, time.thread_time, [], []
    for _ in range(reps):
        for i in range(1, len(sw)):
            t0 = tt()
            pa.solve(sw[i])
            t1 = tt()
            c.set_value_vector(value_vector(sw[i]))
            c.solve(record=False)
            t2 = tt()
            api.append(t1 - t0)
            raw.append(t2 - t1)
    med = statistics.median
    print(
        f"{name}: API {1e6 * med(api):.1f} us, raw {1e6 * med(raw):.1f} us, median of the "
        f"per-call differences {1e6 * med(a - b for a, b in zip(api, raw)):.1f} us (thread CPU; "
        f"load average {os.getloadavg()[0]:.2f})"
    )


GLUE = r"""
import json, statistics, time
import tendonrod as tr
robot = tr.Robot(tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True), [tr.Tendon(0.01)])
p = tr.Problem(tr.Scene(robot, displacement=[0.01]))
p.solve()
c, tt, out = p._c, time.thread_time_ns, []
for _ in range(30):
    t0 = tt()
    for _ in range(2000):
        c.solve(record=False)
    t1 = tt()
    for _ in range(2000):
        c.solve(record=False, warm=True, cancel=None)
    out.append(((t1 - t0) / 2000e3, (tt() - t1) / 2000e3))
print(json.dumps([statistics.median(o[k] for o in out) for k in (0, 1)]))
"""


def glue(old: str, rounds: int) -> None:
    """The glue's share of a call, both builds in alternating processes: the raw
    ``_core.Problem.solve`` of a scene already solved (the warm solve returns at its
    first residual), with one keyword and with three, thread CPU time per call (median
    of 30 x 2,000 calls per process)."""
    res: dict = {"old": [], "new": []}
    for r in range(rounds):
        order = (("old", old), ("new", NEW)) if r % 2 == 0 else (("new", NEW), ("old", old))
        for b, path in order:
            env = dict(os.environ, PYTHONPATH=path)
            o = subprocess.run(
                [sys.executable, "-c", GLUE], env=env, cwd=path, capture_output=True, text=True
            )
            res[b].append(json.loads(o.stdout))
    med = statistics.median
    for k, what in enumerate(
        ("solve(record=False)", "solve(record=False, warm=True, cancel=None)")
    ):
        o, n = med(x[k] for x in res["old"]), med(x[k] for x in res["new"])
        d = med(b[k] - a[k] for a, b in zip(res["old"], res["new"]))
        print(f"{what}: old {o:.2f} us, new {n:.2f} us, new - old per round {d:+.2f} us")
    print(f"{rounds} rounds; load average {os.getloadavg()[0]:.2f}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--split", metavar="SCENE", help="only the in-process split of one scene")
    ap.add_argument("--old", help="checkout of the old build (built in place)")
    ap.add_argument("--glue", action="store_true", help="only the raw call's glue, old vs new")
    ap.add_argument("--rounds", type=int, default=9)
    ap.add_argument("--reps", type=int, default=5)
    args = ap.parse_args(argv)
    if args.split:
        split(args.split)
        return 0
    if not args.old:
        ap.error("--old is required (or --split SCENE)")
    old = os.path.abspath(args.old)
    if args.glue:
        glue(old, args.rounds)
        return 0
    if not same_core(old):
        raise SystemExit("the checkouts' csrc differ: the bare-core harness would not be one")
    tmp = tempfile.mkdtemp()
    libs = build_harnesses(tmp)
    la0 = os.getloadavg()
    builds = {"old": Worker(old, args.reps, libs), "new": Worker(NEW, args.reps, libs)}
    rounds: dict = {"old": [], "new": []}
    for r in range(args.rounds):
        order = ("old", "new") if r % 2 == 0 else ("new", "old")
        for b in order:
            rounds[b].append(builds[b].round())
    for w in builds.values():
        w.close()
    la1 = os.getloadavg()
    med = statistics.median
    print(
        f"{'scene':<38s} {'build':>5s} | warm Problem.solve: C, API, overhead (wall; CPU) | "
        f"cold tr.solve: C, API, overhead (wall; CPU)   [us]"
    )
    for name in SCENES:
        for b in ("old", "new"):
            rs = [x[name] for x in rounds[b]]

            def m(key, rs=rs):
                return med(x[key] for x in rs)

            def over(api, c, rs=rs):
                return med(x[api] - x[c] for x in rs)

            print(
                f"{name:<38s} {b:>5s} | {m('c_warm'):7.1f} {m('warm'):7.1f} "
                f"{over('warm', 'c_warm'):6.1f}; {m('c_warm_cpu'):7.1f} {m('warm_cpu'):7.1f} "
                f"{over('warm_cpu', 'c_warm_cpu'):6.1f} | {m('c_cold'):7.1f} {m('cold'):7.1f} "
                f"{over('cold', 'c_cold'):6.1f}; {m('c_cold_cpu'):7.1f} {m('cold_cpu'):7.1f} "
                f"{over('cold_cpu', 'c_cold_cpu'):6.1f}"
            )
        for b in ("old", "new"):
            rs = [x[name] for x in rounds[b]]
            print(
                f"{'':<38s} {b:>5s} | warm Problem.solve of new Scene objects: overhead "
                f"{med(x['fresh'] - x['c_warm'] for x in rs):6.1f} wall; "
                f"{med(x['fresh_cpu'] - x['c_warm_cpu'] for x in rs):6.1f} CPU"
            )
        for key in ("warm", "cold", "fresh"):
            wall = med(x[name][key] / y[name][key] for x, y in zip(rounds["new"], rounds["old"]))
            cpu = med(
                x[name][key + "_cpu"] / y[name][key + "_cpu"]
                for x, y in zip(rounds["new"], rounds["old"])
            )
            print(f"{'':<38s} new/old API {key}: {wall:.3f} wall, {cpu:.3f} CPU")
    print(
        f"\nmedians of {args.rounds} rounds x {args.reps} reps; load average "
        f"{la0[0]:.2f} -> {la1[0]:.2f}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
