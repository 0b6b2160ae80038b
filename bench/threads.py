"""Throughput of tr.solve on 1 and 2 threads, measured in one run.

    python bench/threads.py [--seconds 3] [--repeat 5] [--threads 1 2]

A fixed batch of different scenes (the scene set of tests/test_threads.py:
planar and spatial, Kirchhoff and Cosserat, displacement and tension control)
is solved cold, through the public API as users call it, first on one thread
and then split over 2 threads (concurrent.futures.ThreadPoolExecutor; the glue
releases the GIL around the C core, so the core runs in parallel while the
Python packing and unpacking around it takes turns).  Each configuration is
timed `--repeat` times over batches that last about `--seconds`; the median
rate is reported.  The same batch is also run through the raw entry point
`tendonrod._core.solve` (arrays packed once, outside the timing) to show how
much of the scaling is lost to the Python layer.

Writes bench/results/threads.csv (one row per configuration) and prints a
table.  The machine's CPU count is recorded: on a 2-core machine the ideal
speed-up is 2.  Also recorded: the process's CPU seconds per wall second
(about 2 when both threads really ran at once) and the 1-minute load
average when the configuration started -- on a shared machine other
processes take cores, and these two columns say how much.  Solves per
CPU-second stays the same from 1 to 2 threads when nothing serialises them
(GIL released, no locks in the core).
"""

import argparse
import csv
import importlib.util
import os
import statistics
import sys
import time
import warnings
from concurrent.futures import ThreadPoolExecutor

import tendonrod as tr
from tendonrod.solver import pack_scene

HERE = os.path.dirname(os.path.abspath(__file__))
RESULTS = os.path.join(HERE, "results", "threads.csv")


def load_scenes():
    path = os.path.join(HERE, "..", "tests", "test_threads.py")
    spec = importlib.util.spec_from_file_location("tt", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod.scenes()


def run_batch(fn, items, threads):
    """Wall time and process CPU time of solving every item on `threads` threads."""
    c0, t0 = time.process_time(), time.perf_counter()
    if threads == 1:
        for it in items:
            fn(it)
    else:
        with ThreadPoolExecutor(max_workers=threads) as ex:
            for _ in ex.map(fn, items, chunksize=max(1, len(items) // (4 * threads))):
                pass
    return time.perf_counter() - t0, time.process_time() - c0


def measure(fn, base, threads, seconds, repeat):
    # size the batch so one batch takes about `seconds` on one thread
    t1, _ = run_batch(fn, base, 1)
    reps = max(1, int(seconds / max(t1, 1e-6)))
    items = base * reps
    rates, cpu = [], []
    for _ in range(repeat):
        dt, ct = run_batch(fn, items, threads)
        rates.append(len(items) / dt)
        cpu.append(ct / dt)
    # cpu: CPU seconds per wall second of this process (about `threads` when
    # the threads really ran in parallel; less when other processes took cores)
    return len(items), statistics.median(rates), min(rates), max(rates), statistics.median(cpu)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seconds", type=float, default=3.0)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    a = ap.parse_args(argv)

    scenes = load_scenes()
    warnings.simplefilter("ignore", tr.ConvergenceWarning)
    ok = sum(tr.solve(s).success for s in scenes)
    packed = [pack_scene(s) for s in scenes]
    opts = tr.Options().raw()

    def public(scene):
        return tr.solve(scene)

    def raw(p):
        return tr._core.solve(*p, **opts)

    rows = []
    for name, fn, base in (("tr.solve", public, scenes), ("_core.solve", raw, packed)):
        ref = None
        for th in a.threads:
            load0 = os.getloadavg()[0]
            n, med, lo, hi, cpu = measure(fn, base, th, a.seconds, a.repeat)
            ref = med if th == a.threads[0] else ref
            rows.append(
                dict(
                    api=name,
                    threads=th,
                    solves=n,
                    solves_per_s=round(med, 1),
                    min_per_s=round(lo, 1),
                    max_per_s=round(hi, 1),
                    speedup=round(med / ref, 3),
                    cpu_per_wall=round(cpu, 2),
                    solves_per_cpu_s=round(med / cpu, 1),
                    loadavg_1min=round(load0, 2),
                    cpus=os.cpu_count(),
                    scenes=len(base),
                    converged=ok,
                )
            )
            print(
                f"{name:12s} {th} thread(s): {med:9.1f} solves/s (min {lo:.1f}, max {hi:.1f}, "
                f"{n} solves per batch)  speed-up {med / ref:.2f}x  "
                f"CPU/wall {cpu:.2f}  {med / cpu:.0f} solves per CPU-s  load avg {load0:.2f}"
            )
    os.makedirs(os.path.dirname(RESULTS), exist_ok=True)
    with open(RESULTS, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {RESULTS} ({os.cpu_count()} CPUs, {len(scenes)} scenes, {ok} converged)")


if __name__ == "__main__":
    sys.exit(main())
