"""Command line: ``python -m tendonrod {solve,actuate,figures,bench} ...`` (``--help`` on
each).

Exit codes: 0 success; 1 a solve did not converge (or a figure failed); 2 bad
input (malformed scene file, unknown option, unreadable file); 3 an optional dependency
the command needs is not installed (the message names the extra: ``pip install
'tendonrod[plot]'``).
"""

from __future__ import annotations

import argparse
import sys

from .cli._common import (
    EXIT_BAD_INPUT,
    EXIT_CODES,
    EXIT_MISSING_DEPENDENCY,
    EXIT_NOT_CONVERGED,
    EXIT_OK,
)
from .cli.actuate import _cmd_actuate
from .cli.bench import _bench, _cmd_bench
from .cli.figures import _cmd_figures
from .cli.solve import _cmd_solve

__all__ = [
    "EXIT_OK",
    "EXIT_NOT_CONVERGED",
    "EXIT_BAD_INPUT",
    "EXIT_MISSING_DEPENDENCY",
    "EXIT_CODES",
    "build_parser",
    "main",
]


class _Parser(argparse.ArgumentParser):
    """argparse exits with 2 on usage errors already; keep that, and our own messages."""


# --------------------------------------------------------------------------- parser
def _sliding_option(p) -> None:
    p.add_argument(
        "--sliding",
        choices=("in", "out"),
        help="the direction every frictional tendon slides in its channel (in: toward the "
        "actuator, out: toward the anchor), over the scene file's 'sliding'",
    )


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(
        prog="python -m tendonrod",
        description="tendonrod: deflection of tendon-driven continuum robots under loads "
        "with prescribed tendon displacements or tensions.",
        epilog=EXIT_CODES,
    )
    from tendonrod._version import __version__

    p.add_argument("-V", "--version", action="version", version=f"tendonrod {__version__}")
    sub = p.add_subparsers(dest="command", metavar="{solve,actuate,figures,bench}")
    sub.required = True

    ps = sub.add_parser(
        "solve",
        help="solve a scene file (TOML) and write the solution",
        description="Solve a scene file and write solution.json (summary), "
        "solution.npz (arrays) and, with --plot, solution.png. The scene "
        "file format is documented in examples/README.md.",
        epilog="Exit codes: 0 converged, 1 did not converge (files still written), "
        "2 bad input (the message names the key; the file is not modified), 3 --plot "
        "without matplotlib (pip install 'tendonrod[plot]'; nothing solved or written).",
    )
    ps.add_argument("scene", help="scene file (TOML)")
    ps.add_argument("--out", required=True, help="output directory (created if missing)")
    ps.add_argument("--plot", action="store_true", help="also write solution.png")
    _sliding_option(ps)
    ps.set_defaults(func=_cmd_solve)

    pa = sub.add_parser(
        "actuate",
        help="find the tendon controls that reach a tip target under the scene's loads",
        description="Find the controls (displacements or tensions, each tendon's kind in "
        "the scene file) of the chosen tendons that bring the tip to a target under the "
        "scene's loads (tendonrod.actuate), and write solution.json (summary, controls, "
        "residual), solution.npz and, with --plot, solution.png. The target comes from "
        "the options below or from a [target] table in the scene file "
        "(examples/README.md).",
        epilog="Exit codes: 0 target reached, 1 not reached (the closest state is still "
        "written), 2 bad input (the message names the option or key), 3 --plot without "
        "matplotlib (pip install 'tendonrod[plot]'; nothing solved or written).",
    )
    pa.add_argument("scene", help="scene file (TOML)")
    pa.add_argument("--out", required=True, help="output directory (created if missing)")
    pa.add_argument(
        "--tip-angle", help="planar scenes: tip angle from +z toward +x, e.g. 45deg or 0.8rad"
    )
    pa.add_argument(
        "--tip-direction", type=float, nargs=3, metavar=("X", "Y", "Z"), help="tip tangent, world"
    )
    pa.add_argument(
        "--tip-position", type=float, nargs=3, metavar=("X", "Y", "Z"), help="tip position [m]"
    )
    pa.add_argument(
        "--tip-pose",
        type=float,
        nargs=6,
        metavar=("X", "Y", "Z", "RX", "RY", "RZ"),
        help="tip position [m] and rotation vector [rad], world frame",
    )
    pa.add_argument(
        "--tendons", help="comma-separated indices of the actuated tendons (default all)"
    )
    pa.add_argument("--min-tension", type=float, help="[N] floor of the taut tendons' tensions")
    pa.add_argument("--plot", action="store_true", help="also write solution.png")
    _sliding_option(pa)
    pa.set_defaults(func=_cmd_actuate)

    pf = sub.add_parser(
        "figures",
        help="regenerate the paper's figures (PNG, PDF or SVG) plus index.md",
        description="Regenerate the paper's figures (1, 3, 6-8, 10-18, 20-23) and the "
        "friction study its Fig. 25 asks for (fig25, fig25_hysteresis) as PNG files with an "
        "index.md listing files and captions.",
        epilog="Exit codes: 0 every figure written, 1 a figure failed (the others are "
        "still written), 2 bad input, 3 matplotlib is not installed (pip install "
        "'tendonrod[plot]').",
    )
    pf.add_argument("--out", required=True, help="output directory (created if missing)")
    pf.add_argument(
        "--fast",
        action="store_true",
        help="coarse grids (for CI); same figures (also: environment TENDONROD_FAST=1)",
    )
    pf.add_argument("--only", default="", help="comma-separated figure keys (see --list)")
    pf.add_argument("--list", action="store_true", help="list figure keys and captions, then exit")
    pf.add_argument("--dpi", type=int, default=110, help="PNG resolution (default 110)")
    pf.add_argument(
        "--format",
        default="png",
        help="comma-separated file formats: png, pdf, svg (default png; PDF and SVG are "
        "vector, for papers)",
    )
    pf.add_argument("-v", "--verbose", action="store_true", help="print tracebacks of failures")
    pf.set_defaults(func=_cmd_figures)

    pb = sub.add_parser(
        "bench",
        help="benchmarks: work-precision | stress (see 'bench --help')",
        description="Benchmarks, implemented in tendonrod.bench: "
        "'bench work-precision --out DIR [--quick]' and "
        "'bench stress --out DIR [--quick]'. Arguments after 'bench' "
        "are passed to tendonrod.bench.main.",
        add_help=False,
    )
    pb.add_argument(
        "bench_args",
        nargs=argparse.REMAINDER,
        help="arguments for tendonrod.bench.main (e.g. work-precision --out DIR)",
    )
    pb.set_defaults(func=_cmd_bench)
    return p


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    try:
        if argv and argv[0] == "bench":
            # everything after 'bench' belongs to tendonrod.bench.main, options included
            # (argparse's REMAINDER would not pass a leading '--help' through)
            return _bench(argv[1:])
        parser = build_parser()
        args = parser.parse_args(argv)
        return args.func(args)
    except ModuleNotFoundError as exc:
        # an optional dependency missing: one line naming the extra, exit 3 (any other
        # missing module is a broken installation: its traceback stays)
        from tendonrod._extras import MissingExtraError, install_hint

        hint = install_hint(exc.name or "")
        if not isinstance(exc, MissingExtraError) and hint is None:
            raise
        prog = f"tendonrod {argv[0]}" if argv and not argv[0].startswith("-") else "tendonrod"
        msg = str(exc) if isinstance(exc, MissingExtraError) else f"{exc}: {hint}"
        print(f"{prog}: error: {msg}", file=sys.stderr)
        return EXIT_MISSING_DEPENDENCY


if __name__ == "__main__":
    sys.exit(main())
