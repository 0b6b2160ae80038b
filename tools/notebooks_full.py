#!/usr/bin/env python3
"""Re-make the committed outputs of the notebooks (notebooks/*.ipynb) in place.

The documentation renders the outputs stored in the notebooks and never executes them
(``make docs``); ``make test`` runs every notebook through nbmake at the fast setting
and discards what it computes.  This script is how the stored outputs are made:

    python tools/notebooks_full.py                 # every notebook, full resolution
    python tools/notebooks_full.py 04 07           # the notebooks whose names start so
    python tools/notebooks_full.py --fast 05       # the fast (CI) setting instead

Each notebook runs in a fresh kernel of this Python, from the notebooks/ directory, with
the checkout first on PYTHONPATH, ``TENDONROD_FULL=1`` (the notebooks' own switch: a
notebook with a fast setting reads ``os.environ["TENDONROD_FULL"]``; the others ignore it)
and the inline matplotlib backend, so every figure is stored as a PNG.  An error in a cell
stops that notebook, leaves its file untouched and makes the script exit non-zero.
Prints the wall and CPU time of each notebook (the kernel's CPU time: user + system).
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
NOTEBOOKS = ROOT / "notebooks"


def _cpu_children() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run(path: Path, full: bool, timeout: int) -> tuple[float, float]:
    """Execute one notebook in place; return (wall seconds, kernel CPU seconds)."""
    import nbformat
    from nbclient import NotebookClient

    env = {
        "TENDONROD_FULL": "1" if full else "0",
        "MPLBACKEND": "module://matplotlib_inline.backend_inline",
        "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])),
    }
    saved = {k: os.environ.get(k) for k in env}
    os.environ.update(env)  # the kernel inherits this process's environment
    try:
        nb = nbformat.read(path, as_version=4)
        client = NotebookClient(
            nb,
            timeout=timeout,
            kernel_name="python3",
            resources={"metadata": {"path": str(path.parent)}},
            record_timing=False,  # no timestamps in the committed file
        )
        wall0, cpu0 = time.perf_counter(), _cpu_children()
        client.execute()
        wall, cpu = time.perf_counter() - wall0, _cpu_children() - cpu0
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
    nbformat.write(nb, path)
    return wall, cpu


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("prefixes", nargs="*", help="notebook name prefixes (default: all)")
    ap.add_argument("--fast", action="store_true", help="the fast (CI) setting")
    ap.add_argument("--timeout", type=int, default=3600, help="per cell, seconds")
    args = ap.parse_args(argv)
    paths = sorted(NOTEBOOKS.glob("*.ipynb"))
    if args.prefixes:
        paths = [p for p in paths if any(p.name.startswith(x) for x in args.prefixes)]
        if not paths:
            ap.error(f"no notebook in {NOTEBOOKS} starts with {args.prefixes}")
    failed = []
    for path in paths:
        print(f"{path.name}: running ({'fast' if args.fast else 'full'} setting)", flush=True)
        try:
            wall, cpu = run(path, full=not args.fast, timeout=args.timeout)
        except Exception as exc:  # a failing cell: report it, keep the file, go on
            print(f"{path.name}: FAILED, file left as it was\n{exc}", file=sys.stderr, flush=True)
            failed.append(path.name)
            continue
        size = path.stat().st_size / 1024
        print(f"{path.name}: {wall:.1f} s wall, {cpu:.1f} s CPU, {size:.0f} KiB", flush=True)
    if failed:
        print("failed: " + ", ".join(failed), file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
