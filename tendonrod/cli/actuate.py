"""``tendonrod actuate SCENE --out DIR``: the tendon controls that reach a tip target."""

from __future__ import annotations

import sys
import time

from ._common import EXIT_BAD_INPUT, EXIT_NOT_CONVERGED, EXIT_OK, _read_spec, _require_plot
from ._output import _write_solution


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

    spec = _read_spec("actuate", args.scene, args.sliding)
    if spec is None:
        return EXIT_BAD_INPUT
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
