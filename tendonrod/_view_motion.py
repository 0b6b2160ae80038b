"""The animated 3-D view of a :class:`~tendonrod.Trajectory` (:func:`tendonrod.plot.view`).

One animation frame per drawn time (at most ``max_frames``, evenly chosen, the first and
last kept), with a slider labelled by the time and a play button:

- per frame, the backbone as a closed tube mesh around the recorded centre line (the
  trajectory's ``backbone``, world frame) and the tip as a marker;
- fixed, the tip's path over the whole run (every row, not only the drawn ones), and with
  ``scene=`` the world frame, the robot's base frame when mounted and the direction of
  gravity (as for a solution).

A trajectory records the centre line only (no rotations, no tendon states along the
rod): the rings of the tube are carried along it by rotation-minimising frames, and the
tendons are not drawn.  Nothing is solved.
"""

from __future__ import annotations

import numpy as np

from ._mesh import backbone_radius, tube
from ._view import _animate, _bounds, _layout, _mesh_trace, _plotly, _static_traces, _subsample

__all__ = ["view_trajectory"]


def _radius(traj, scene) -> tuple[np.ndarray, str]:
    """The tube's radius per backbone node [m] and the legend's name of the backbone."""
    from .model import Scene

    s = np.asarray(traj.s, dtype=float)
    L = float(s[-1])
    if scene is None:
        return np.full(len(s), L / 100), "backbone (its diameter unknown: drawn L/50)"
    if not isinstance(scene, Scene):
        raise ValueError(
            "view: scene= of a Trajectory must be the Scene it was simulated in (for the "
            f"rod's diameter, the frames and gravity) or None, got {type(scene).__name__}"
        )
    if abs(scene.robot.rod.length - L) > 1e-12 * L:
        raise ValueError(
            f"view: the scene's rod is {scene.robot.rod.length!r} m long, the trajectory's "
            f"backbone {L!r} m: pass the Scene the trajectory was simulated in"
        )
    r = backbone_radius(scene, s)
    return r, f"backbone (d = {2e3 * float(r[0]):.3g} mm)"


def view_trajectory(traj, scene=None, *, sides: int = 24, max_frames: int = 60, title=None):
    """The figure of :func:`tendonrod.plot.view` for a Trajectory (see the module); the
    keywords of a solution's view that do not apply to a motion (tendons, loads, disks,
    options) are refused by the call (TypeError)."""
    go = _plotly()
    if traj.backbone is None or traj.s is None:
        raise ValueError(
            "view: this Trajectory has no backbone states to draw: run "
            'tr.simulate(..., options={"backbone": True})'
        )
    bb = np.asarray(traj.backbone, dtype=float)
    t = np.asarray(traj.t, dtype=float)
    r, name = _radius(traj, scene)
    idx = _subsample(len(t), max_frames)
    labels = [f"t = {t[i]:.6g} s" for i in idx]
    per_step = []
    for i in idx:
        P = bb[i]
        per_step.append(
            [
                _mesh_trace(go, tube(P, None, r, sides), name, "#8c8c8c", hoverinfo="name"),
                go.Scatter3d(
                    x=P[-1:, 0],
                    y=P[-1:, 1],
                    z=P[-1:, 2],
                    mode="markers",
                    marker=dict(size=4, color="#d62728"),
                    name="tip",
                    hoverinfo="name",
                ),
            ]
        )
    tip = np.asarray(traj.tip_position, dtype=float)
    path = go.Scatter3d(
        x=tip[:, 0],
        y=tip[:, 1],
        z=tip[:, 2],
        mode="lines",
        line=dict(color="#d62728", width=2),
        name="tip path",
        hoverinfo="name",
    )
    # the axes' box: every recorded node of every row, so no frame leaves the view
    flat = bb.reshape(-1, 3)
    box = np.stack([flat.min(axis=0), flat.max(axis=0)])
    static = [path]
    if scene is not None:
        static += _static_traces(go, scene, float(traj.s[-1]), box)
        box = _bounds(per_step[0] + static + [_points(go, box)])
    fig = go.Figure(data=per_step[0] + static)
    done = "" if traj.success else f" (stopped: {traj.message})"
    _layout(fig, box, (title or "tendonrod: motion") + done)
    fig.update_layout(meta=dict(tendonrod_steps=labels, tendonrod_rows=idx))
    if len(idx) > 1:
        _animate(go, fig, [(lb, None) for lb in labels], per_step)
    return fig


def _points(go, box):
    """An invisible trace of the box's corners (to take them into :func:`_bounds`)."""
    return go.Scatter3d(x=box[:, 0], y=box[:, 1], z=box[:, 2], mode="markers", visible=False)
