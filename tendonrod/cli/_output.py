"""A solved scene written to files: NAME.json (summary), NAME.npz (arrays) and, with
--plot, NAME.png; the friction summary printed after a solve."""

from __future__ import annotations

import json
import os


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
