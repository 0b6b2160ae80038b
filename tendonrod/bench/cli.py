"""Command line of the benchmark suites (routed here by ``python -m tendonrod bench ...``)::

    python -m tendonrod bench work-precision --out DIR [--quick]
    python -m tendonrod bench stress --out DIR [--quick] [--timeout SECONDS] [--only SUBSTRING]

Exit status: 0, or for ``stress`` 1 when a case is neither verified nor an honest failure.
"""

from __future__ import annotations

import argparse

from .model_choice import run_model_choice
from .stress import GOOD, run_stress
from .work_precision import run_work_precision

__all__ = ["main"]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(
        prog="python -m tendonrod bench",
        description="tendonrod benchmarks: work-precision (error vs run time, and "
        "the choice of model) and the stress suite.",
    )
    sub = ap.add_subparsers(dest="which", metavar="{work-precision,stress}")
    sub.required = True
    w = sub.add_parser(
        "work-precision", help="error vs run time per scene, method and setting; model choice"
    )
    w.add_argument("--out", required=True, help="output directory")
    w.add_argument("--quick", action="store_true", help="few settings and repeats (CI)")
    w.add_argument(
        "--repeats", type=int, default=None, help="solves per timing (median); default 7 (quick: 3)"
    )
    w.add_argument("--skip-model-choice", action="store_true", help="only the work-precision chart")
    w.add_argument("--scenes", default="", help="comma-separated scene names (default: all)")
    s = sub.add_parser(
        "stress",
        help="stress suite: every case converges verified or fails honestly",
        epilog="Exit status: 0 if every case is verified or an honest failure, 1 otherwise "
        "(the report is written either way).",
    )
    s.add_argument("--out", required=True, help="output directory")
    s.add_argument("--quick", action="store_true", help="the fast subset (the one the tests run)")
    s.add_argument(
        "--timeout", type=float, default=60.0, help="seconds per case before it counts as a hang"
    )
    s.add_argument("--only", default="", help="run only cases whose name contains this string")
    args = ap.parse_args(argv)
    if args.which == "work-precision":
        names = [x.strip() for x in args.scenes.split(",") if x.strip()]
        run_work_precision(args.out, quick=args.quick, repeats=args.repeats, scenes=names or None)
        if not args.skip_model_choice:
            run_model_choice(args.out, quick=args.quick)
        return 0
    rows = run_stress(args.out, quick=args.quick, timeout=args.timeout, only=args.only)
    return 0 if all(r["outcome"] in GOOD for r in rows) else 1
