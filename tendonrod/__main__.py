"""Command line: ``python -m tendonrod {solve,actuate,figures,bench} ...`` (``--help`` on
each).

Exit codes: 0 success; 1 a solve did not converge (or a figure failed); 2 bad
input (malformed scene file, unknown option, unreadable file); 3 an optional dependency
the command needs is not installed (the message names the extra: ``pip install
'tendonrod[plot]'``).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
import traceback

EXIT_OK = 0
EXIT_NOT_CONVERGED = 1
EXIT_BAD_INPUT = 2
EXIT_MISSING_DEPENDENCY = 3
EXIT_CODES = (
    "Exit codes: 0 ok; 1 did not converge / a figure failed; 2 bad input; 3 an optional "
    "dependency is not installed (the message names the extra to install)."
)


class _Parser(argparse.ArgumentParser):
    """argparse exits with 2 on usage errors already; keep that, and our own messages."""


def _jsonable(x):
    import numpy as np

    if isinstance(x, dict):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return _jsonable(x.tolist())
    if isinstance(x, (np.floating, float)):
        v = float(x)
        return v if np.isfinite(v) else repr(v)  # JSON has no inf/nan: write "inf", "nan"
    if isinstance(x, (np.integer,)):
        return int(x)
    if isinstance(x, (np.bool_,)):
        return bool(x)
    if x is None or isinstance(x, (bool, int, str)):
        return x
    return repr(x)


# --------------------------------------------------------------------------- solve
def _cmd_solve(args) -> int:
    import numpy as np

    import tendonrod as tr
    from tendonrod.scenefile import SceneFileError, load_scene

    try:
        spec = load_scene(args.scene)
    except SceneFileError as exc:
        print(f"tendonrod solve: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except OSError as exc:
        print(
            f"tendonrod solve: error: cannot read scene file {args.scene!r}: {exc.strerror or exc}",
            file=sys.stderr,
        )
        return EXIT_BAD_INPUT
    spec = _with_sliding(spec, args.sliding)
    _require_plot(args)
    t0 = time.perf_counter()
    try:
        import warnings

        with warnings.catch_warnings():
            warnings.simplefilter("ignore", getattr(tr, "ConvergenceWarning", Warning))
            sol = tr.solve(spec.scene, options=spec.options)
    except ValueError as exc:
        print(f"tendonrod solve: error: {args.scene}: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    elapsed = time.perf_counter() - t0
    written = _write_solution(args, spec, sol, elapsed, "solution", {})
    status = "converged" if sol.success else "DID NOT CONVERGE"
    print(
        f"{args.scene}: {status} ({sol.message}); tip at {np.round(sol.tip_position, 6).tolist()} m"
        f"{_friction_line(sol)}; wrote {', '.join(written)} to {args.out}"
    )
    return EXIT_OK if sol.success else EXIT_NOT_CONVERGED


def _require_plot(args) -> None:
    """With --plot, matplotlib must be there before the solve starts (else exit 3)."""
    if args.plot:
        from tendonrod._extras import optional_import

        optional_import("matplotlib.pyplot", "--plot")


def _with_sliding(spec, sliding):
    """``spec`` with every tendon's sliding direction set to ``sliding`` ("in" / "out"),
    or unchanged when it is None (the command line's --sliding over the file's)."""
    import dataclasses

    if sliding is None:
        return spec
    return dataclasses.replace(spec, scene=dataclasses.replace(spec.scene, sliding=sliding))


def _anchor_tensions(sol):
    """The tension [N] of every tendon at its anchor (with friction it differs from the
    tension at the actuator, ``sol.tension``)."""
    import numpy as np

    robot = sol.scene.robot
    if robot.n_tendons == 0:
        return np.zeros(0)
    return np.array([sol.at(robot.tendon_end(i)).tendon_tension[i] for i in range(robot.n_tendons)])


def _frictional(scene):
    return [i for i, t in enumerate(scene.robot.tendons) if t.friction > 0.0]


def _friction_line(sol) -> str:
    """For a scene with channel friction: the frictional tendons' tensions at their
    anchors and that stability was not judged (empty otherwise)."""
    import numpy as np

    idx = _frictional(sol.scene)
    if not idx or not sol.success:
        return ""
    anchor = _anchor_tensions(sol)
    parts = [
        f"tendon {i} ({sol.scene.sliding[i]}) {sol.tension[i]:.6g} N at the actuator, "
        f"{anchor[i]:.6g} N at the anchor"
        for i in idx
        if np.isfinite(anchor[i])
    ]
    return f"; friction: {', '.join(parts)}; stability {sol.stability_reason}"


def _write_solution(args, spec, sol, elapsed, name, extra) -> list:
    """Write NAME.json (summary, with ``extra``), NAME.npz (arrays) and, with --plot,
    NAME.png to args.out; the names written."""
    import numpy as np

    import tendonrod as tr

    os.makedirs(args.out, exist_ok=True)
    summary = {
        "scene": os.path.abspath(args.scene),
        "title": spec.title,
        "tendonrod_version": tr.__version__,
        "success": bool(sol.success),
        "message": str(sol.message),
        "nit": getattr(sol, "nit", None),
        "nfev": getattr(sol, "nfev", None),
        "residual_norm": getattr(sol, "residual_norm", None),
        "solve_time_s": elapsed,
        "formulation": getattr(sol, "formulation", None),
        "tip_position_m": sol.tip_position,
        "tip_rotation": sol.tip_rotation,
        "tension_N": sol.tension,
        "slack_m": sol.slack,
        "displacement_m": sol.displacement,
        "friction": [t.friction for t in sol.scene.robot.tendons],
        "sliding": list(sol.scene.sliding),
        "anchor_tension_N": _anchor_tensions(sol) if sol.success else None,
        "stable": sol.stable,
        "stability_reason": sol.stability_reason,
        "units": {"length": "m", "force": "N", "moment": "N m", "angle": "rad"},
        "arrays": f"{name}.npz: s (N,) [m], position (N,3) [m] world, rotation (N,3,3) body-to-world, "
        "force (N,3) [N] world, moment (N,3) [N m] world, tension (nt,) [N], "
        "slack (nt,) [m], displacement (nt,) [m], tendon_tension (N, nt) [N] along s "
        "(0 distal of each anchor)",
    }
    summary.update(extra)
    with open(os.path.join(args.out, f"{name}.json"), "w", encoding="utf-8") as fh:
        json.dump(_jsonable(summary), fh, indent=2)
        fh.write("\n")
    np.savez(
        os.path.join(args.out, f"{name}.npz"),
        s=sol.s,
        position=sol.position,
        rotation=sol.rotation,
        force=sol.force,
        moment=sol.moment,
        tension=sol.tension,
        slack=sol.slack,
        displacement=sol.displacement,
        tendon_tension=sol.tendon_tension,
    )
    written = [f"{name}.json", f"{name}.npz"]
    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from tendonrod import plot as trplot

        fig = plt.figure(figsize=(6, 6))
        if trplot.is_planar(spec.scene):
            ax = fig.add_subplot(111)
        else:
            ax = fig.add_subplot(111, projection="3d")
        trplot.robot(sol, sol.scene, ax=ax)
        import textwrap

        ax.set_title(
            textwrap.fill(spec.title or os.path.basename(args.scene), 60), fontsize="medium"
        )
        trplot.savefig(fig, os.path.join(args.out, f"{name}.png"), dpi=120)
        plt.close(fig)
        written.append(f"{name}.png")
    return written


# --------------------------------------------------------------------------- actuate
def _cli_target(args, spec):
    """The target of tendonrod.actuate: the command line's, else the file's [target]
    table; (kwargs, None) or (None, message naming the option or key)."""
    from tendonrod.scenefile import SceneFileError, parse_angle

    given = {}
    try:
        if args.tip_angle is not None:
            given["tip_angle"] = parse_angle(args.tip_angle, "--tip-angle")
    except SceneFileError as exc:
        return None, f"{exc.key}: {exc.problem}"
    if args.tip_direction is not None:
        given["tip_direction"] = tuple(args.tip_direction)
    if args.tip_position is not None:
        given["tip_position"] = tuple(args.tip_position)
    if args.tip_pose is not None:
        from tendonrod._scene_fields import rotation_from_vector

        given["tip_pose"] = (
            tuple(args.tip_pose[:3]),
            rotation_from_vector(list(args.tip_pose[3:]), "--tip-pose"),
        )
    kinds = ("tip_angle", "tip_direction", "tip_position", "tip_pose")
    if len(given) > 1:
        return None, "give one of --tip-angle, --tip-direction, --tip-position, --tip-pose"
    target = dict(spec.target or {})
    if given:
        for kind in kinds:
            target.pop(kind, None)
        target.update(given)
    if not any(k in target for k in kinds):
        return None, (
            "no target: give --tip-angle, --tip-direction, --tip-position or --tip-pose, or "
            "a [target] table in the scene file"
        )
    if args.tendons is not None:
        try:
            target["tendons"] = [int(i) for i in args.tendons.split(",") if i.strip()]
        except ValueError:
            return None, f"--tendons: expected comma-separated tendon indices, got {args.tendons!r}"
    if args.min_tension is not None:
        target["min_tension"] = args.min_tension
    return target, None


def _cmd_actuate(args) -> int:
    import warnings

    import numpy as np

    import tendonrod as tr
    from tendonrod.scenefile import SceneFileError, load_scene

    try:
        spec = load_scene(args.scene)
    except SceneFileError as exc:
        print(f"tendonrod actuate: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except OSError as exc:
        print(
            f"tendonrod actuate: error: cannot read scene file {args.scene!r}: "
            f"{exc.strerror or exc}",
            file=sys.stderr,
        )
        return EXIT_BAD_INPUT
    spec = _with_sliding(spec, args.sliding)
    _require_plot(args)
    target, problem = _cli_target(args, spec)
    if problem:
        print(f"tendonrod actuate: error: {args.scene}: {problem}", file=sys.stderr)
        return EXIT_BAD_INPUT
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", tr.ConvergenceWarning)
            sol = tr.actuate(spec.scene, options=spec.options, **target)
    except ValueError as exc:
        print(f"tendonrod actuate: error: {args.scene}: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    elapsed = time.perf_counter() - t0
    a = sol.actuation
    extra = {
        "target": target,
        "actuation": {
            "kind": a.kind,
            "tendons": a.tendons,
            "controls": a.controls,
            "controls_units": "m for displacement-controlled tendons, N for tension-controlled",
            "residual": a.residual,
            "distance": a.distance,
            "reached": a.reached,
            "iterations": a.iterations,
            "solves": a.solves,
            "message": a.message,
        },
    }
    written = _write_solution(args, spec, sol, elapsed, "solution", extra)
    status = "target reached" if sol.success else "TARGET NOT REACHED"
    print(
        f"{args.scene}: {status} ({a.message}); controls {np.round(a.controls, 9).tolist()} "
        f"of tendons {list(a.tendons)}; wrote {', '.join(written)} to {args.out}"
    )
    return EXIT_OK if sol.success else EXIT_NOT_CONVERGED


# --------------------------------------------------------------------------- figures
def _cmd_figures(args) -> int:
    from tendonrod._extras import optional_import
    from tendonrod.paper.figures import fast_mode, figure_registry

    args.fast = bool(args.fast or fast_mode())  # --fast or TENDONROD_FAST=1
    registry = figure_registry()
    keys = list(registry)
    if args.only:
        wanted = [k.strip() for k in args.only.split(",") if k.strip()]
        unknown = [k for k in wanted if k not in registry]
        if unknown:
            print(
                f"tendonrod figures: error: --only: unknown figure(s) {', '.join(unknown)}; "
                f"known: {', '.join(keys)}",
                file=sys.stderr,
            )
            return EXIT_BAD_INPUT
        keys = wanted
    if args.list:
        for k in keys:
            print(f"{k}: {registry[k].caption}")
        return EXIT_OK
    from tendonrod.paper.figures import parse_formats, write_figure

    try:
        formats = parse_formats(args.format)
    except ValueError as exc:
        print(f"tendonrod figures: error: --format: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    matplotlib = optional_import("matplotlib", "the figures command")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(args.out, exist_ok=True)
    lines = [
        "# tendonrod: the paper's figures, regenerated",
        "",
        f"Command: `python -m tendonrod figures --out {args.out}{' --fast' if args.fast else ''}"
        f"{' --format ' + ','.join(formats) if formats != ('png',) else ''}`  ",
        "Paper: *Continuum Robot Deflection under External Loads and Prescribed Tendon "
        "Displacements*.  Nondimensional compliance sigma = 12 EI delta / (F L^3) (the "
        "paper's definition) unless a label says otherwise.",
        "",
    ]
    failed = []
    t_all = time.perf_counter()
    for k in keys:
        entry = registry[k]
        t0 = time.perf_counter()
        try:
            fig = entry.make(fast=args.fast)
        except Exception as exc:  # noqa: BLE001 - one figure's failure must not lose the others
            failed.append(k)
            print(f"  {k}: FAILED: {type(exc).__name__}: {exc}", file=sys.stderr)
            if args.verbose:
                traceback.print_exc()
            lines.append(f"- **{k}** — FAILED ({type(exc).__name__}: {exc})")
            continue
        names = write_figure(fig, args.out, k, formats, dpi=args.dpi)
        plt.close(fig)
        dt = time.perf_counter() - t0
        print(f"  {', '.join(names)}  ({dt:.1f} s)")
        # the index shows the first format a browser draws (PNG or SVG), links the others
        shown = next((n for n in names if n.endswith((".png", ".svg"))), None)
        lines += [f"## {k}", ""]
        if shown:
            lines += [f"![{k}]({shown})", ""]
        others = [n for n in names if n != shown]
        if others:
            lines += ["Also: " + ", ".join(f"[{n}]({n})" for n in others), ""]
        lines += [entry.caption, ""]
        notes = getattr(fig, "_tendonrod_notes", None)
        if notes:
            lines += [notes, ""]
    lines.append(
        f"_{len(keys) - len(failed)} figures in {time.perf_counter() - t_all:.0f} s"
        f"{' (fast setting)' if args.fast else ''}._"
    )
    with open(os.path.join(args.out, "index.md"), "w", encoding="utf-8") as fh:
        fh.write("\n".join(lines) + "\n")
    print(
        f"wrote {len(keys) - len(failed)} figures and index.md to {args.out}"
        + (f"; FAILED: {', '.join(failed)}" if failed else "")
    )
    return EXIT_OK if not failed else EXIT_NOT_CONVERGED


# --------------------------------------------------------------------------- bench
def _cmd_bench(args) -> int:
    return _bench(list(args.bench_args))


def _bench(argv) -> int:
    from tendonrod._extras import MissingExtraError

    try:
        from tendonrod import bench
    except MissingExtraError:
        raise
    except ImportError as exc:
        print(
            f"tendonrod bench: error: the benchmark suites are not available ({exc})",
            file=sys.stderr,
        )
        return EXIT_BAD_INPUT
    try:
        rc = bench.main(list(argv))
    except MissingExtraError:
        raise
    except SystemExit as exc:  # its argparse: --help (0), usage errors (2)
        return int(exc.code or 0)
    return int(rc or 0)


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
