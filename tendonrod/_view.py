"""The interactive 3-D view (:func:`tendonrod.plot.view`), drawn with Plotly.

One figure shows one solved robot, or steps through several (the points of a load path,
of a sweep or batch, a list of solutions) with a slider and a play button:

- the backbone as a tube at its true diameter (a closed mesh, :mod:`tendonrod._mesh`);
- spacer disks (the scene's point masses, a tendon routed disk by disk, or ``disks=``);
- each tendon along its route, coloured by its local tension [N] on one colour scale
  shared by every step (a colour bar), dashed when slack;
- point loads as arrows ending at their point, length ``load_scale`` [m/N] times the
  force (the scale is in the title and the legend);
- the world frame at the origin (x red, y green, z blue) and the robot's base frame when
  it is mounted elsewhere; the direction of gravity when the scene has one.

Nothing is solved for a single solution or a load path (whose points are recorded again
from their converged unknowns); a sweep's or batch's points are solved again, warm, one
after the other (those results keep only tip quantities).  Plotly is imported here, on
first use; :func:`save_html` writes a page with plotly.js inlined (no network needed).
"""

from __future__ import annotations

import math

import numpy as np

from ._extras import optional_import
from ._mesh import (
    Mesh,
    backbone_radius,
    backbone_tube,
    disk_arcs,
    disks_mesh,
    state_at,
    tendon_route,
)

__all__ = ["view", "save_html"]

COLORSCALE = "Viridis"  # sequential, its lightness rising with tension
_AXES = (("x", "#d62728"), ("y", "#2ca02c"), ("z", "#1f77b4"))


def _plotly():
    return optional_import("plotly.graph_objects", "tendonrod.plot.view")


# --------------------------------------------------------------------------- what to show
def _steps(x, scene, options, max_frames: int) -> list:
    """``[(label, Solution), ...]`` of what ``x`` holds (see :func:`view`)."""
    from .batch import BatchResult
    from .continuation import Branch
    from .solution import Solution
    from .sweeps import SweepResult

    if isinstance(x, Solution):
        return [("", x)]
    if isinstance(x, Branch):
        return _path_steps(x, options, max_frames)
    if isinstance(x, SweepResult):
        return _sweep_steps(x, scene, options, max_frames)
    if isinstance(x, BatchResult):
        return _batch_steps(x, scene, options, max_frames)
    if isinstance(x, (list, tuple)) and x and all(isinstance(s, Solution) for s in x):
        idx = _subsample(len(x), max_frames)
        return [(f"solution {i}", x[i]) for i in idx]
    raise ValueError(
        "view: x must be a Solution, a list of Solutions, a load path (tr.path's result), "
        f"a SweepResult, a BatchResult or a Trajectory, got {type(x).__name__}"
    )


def _subsample(n: int, max_frames: int) -> list:
    if isinstance(max_frames, bool) or not isinstance(max_frames, int) or max_frames < 1:
        raise ValueError(f"max_frames must be an int >= 1, got {max_frames!r}")
    if n <= max_frames:
        return list(range(n))
    return sorted(set(np.round(np.linspace(0, n - 1, max_frames)).astype(int).tolist()))


def _path_steps(p, options, max_frames: int) -> list:
    from .compiled import _compile
    from .options import _check_options
    from .solution import Solution

    if len(p) == 0:
        raise ValueError(f"view: the load path has no points ({p.message})")
    opts = _check_options(options)
    out = []
    for i in _subsample(len(p), max_frames):
        sc = p.scene_at(i)
        # the point's own equilibrium, recorded from its converged unknowns (no solve)
        raw = _compile(sc, opts).record_from(p.unknowns[i], max(1, int(p.steps[i])))
        out.append((f"{p.parameter} = {p.value[i]:.4g}", Solution(raw, sc, opts)))
    return out


def _warm(scenes_labels, options) -> list:
    from .problem import Problem

    out, prob = [], None
    for label, sc in scenes_labels:
        prob = Problem(sc, options=options) if prob is None else prob
        sol = prob.solve(sc)
        if sol.success:
            out.append((label, sol))
    if not out:
        raise ValueError("view: no point could be solved again")
    return out


def _sweep_steps(res, scene, options, max_frames: int) -> list:
    from ._scene_paths import set_path
    from .model import Scene

    if not isinstance(scene, Scene):
        raise ValueError(
            "view: a SweepResult keeps tip quantities only; pass scene= (the sweep's base "
            f"Scene) to solve its points again, got scene={scene!r}"
        )
    pts = [ix for ix in np.ndindex(*res.shape) if res.success[ix]]
    todo = []
    for k in _subsample(len(pts), max_frames):
        ix = pts[k]
        sc, parts = scene, []
        for name in res.names:
            v = np.asarray(res.values[name])[ix]
            try:
                sc = set_path(sc, name, v.tolist() if v.ndim else float(v))
            except (ValueError, TypeError, AttributeError, IndexError) as exc:
                raise ValueError(
                    f"view: the sweep's parameter {name!r} is not a path into the scene "
                    f"(a build= keyword?): solve the points and pass the Solutions ({exc})"
                ) from None
            parts.append(f"{name} = {_fmt(v)}")
        todo.append((", ".join(parts), sc))
    return _warm(todo, options)


def _batch_steps(res, scene, options, max_frames: int) -> list:
    from .model import Scene

    if not (
        isinstance(scene, (list, tuple))
        and len(scene) == len(res)
        and all(isinstance(s, Scene) for s in scene)
    ):
        raise ValueError(
            "view: a BatchResult keeps tip quantities only; pass scene= the list of its "
            f"{len(res)} Scenes (in input order) to solve them again"
        )
    ok = [i for i in range(len(res)) if res.success[i]]
    return _warm(
        [(f"point {ok[k]}", scene[ok[k]]) for k in _subsample(len(ok), max_frames)], options
    )


def _fmt(v) -> str:
    v = np.asarray(v)
    if v.ndim:
        return "(" + ", ".join(f"{float(e):.4g}" for e in v.ravel()) + ")"
    return f"{float(v):.4g}"


# --------------------------------------------------------------------------- geometry
def _point_loads(scene) -> list:
    """``[(s, force (3,)), ...]``: the scene's point forces (point masses weigh only under
    gravity, which the gravity marker shows)."""
    from .loads import PointLoad

    return [
        (ld.s, np.asarray(ld.force, dtype=float))
        for ld in scene.loads
        if isinstance(ld, PointLoad) and np.any(ld.force)
    ]


def arrow(tail, vec, head_fraction: float = 0.25, sides: int = 12) -> tuple:
    """An arrow from ``tail`` along ``vec`` [m]: its shaft (2, 3) from the tail to the
    base of the head, and the head as a closed cone mesh whose apex is ``tail + vec``."""
    tail, vec = np.asarray(tail, float), np.asarray(vec, float)
    n = float(np.linalg.norm(vec))
    t = vec / n
    hl = head_fraction * n
    neck = tail + vec - hl * t
    a = np.array([1.0, 0.0, 0.0]) if abs(t[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    e1 = np.cross(t, a)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(t, e1)
    th = 2 * math.pi * np.arange(sides) / sides
    ring = neck + 0.35 * hl * (np.cos(th)[:, None] * e1 + np.sin(th)[:, None] * e2)
    V = np.concatenate([ring, [tail + vec, neck]])
    j = np.arange(sides)
    jn = (j + 1) % sides
    F = np.concatenate(
        [
            np.stack([j, jn, np.full(sides, sides)], -1),
            np.stack([jn, j, np.full(sides, sides + 1)], -1),
        ]
    )
    return np.stack([tail, neck]), Mesh(V, F)


def _tension_along(sol, i: int, s: np.ndarray) -> np.ndarray:
    """Tendon ``i``'s tension [N] at arc lengths ``s``, interpolated between the nodes."""
    tt = np.asarray(sol.tendon_tension)
    if tt.ndim == 2 and tt.shape[1] > i:
        return np.interp(s, np.asarray(sol.s), tt[:, i])
    return np.full(len(s), float(np.asarray(sol.tension)[i]))


def _is_slack(sol, i: int) -> bool:
    return float(sol.tension[i]) == 0.0 and float(np.asarray(sol.slack)[i]) > 0.0


# --------------------------------------------------------------------------- traces
def _mesh_trace(go, m: Mesh, name: str, color: str, **kw):
    V, F = m.vertices, m.faces
    return go.Mesh3d(
        x=V[:, 0],
        y=V[:, 1],
        z=V[:, 2],
        i=F[:, 0],
        j=F[:, 1],
        k=F[:, 2],
        name=name,
        color=color,
        showlegend=True,
        flatshading=False,
        lighting=dict(ambient=0.45, diffuse=0.8, specular=0.3, roughness=0.5),
        **kw,
    )


def _step_traces(go, sol, cfg: dict) -> list:
    """The traces that change from step to step, always the same number in the same order."""
    scene = sol.scene
    d0 = 2e3 * float(backbone_radius(scene, [0.0])[0])
    traces = [
        _mesh_trace(
            go,
            backbone_tube(sol, cfg["sides"]),
            f"backbone (d = {d0:.3g} mm)",
            "#8c8c8c",
            hoverinfo="name",
        )
    ]
    if cfg["disks"] is not None:
        m = disks_mesh(sol, scene, cfg["disks"], sides=cfg["sides"])
        traces.append(_mesh_trace(go, m, "disks", "#b5835a", opacity=0.85, hoverinfo="name"))
    for i in range(cfg["ntendons"] if cfg["tendons"] else 0):
        st, pts = tendon_route(sol, scene, i)
        ten = _tension_along(sol, i, st)
        slack = _is_slack(sol, i)
        state = "slack" if slack else f"{float(sol.tension[i]):.3g} N"
        traces.append(
            go.Scatter3d(
                x=pts[:, 0],
                y=pts[:, 1],
                z=pts[:, 2],
                mode="lines",
                name=f"tendon {i}",
                legendgroup=f"tendon {i}",
                line=dict(
                    color=ten,
                    colorscale=COLORSCALE,
                    cmin=0.0,
                    cmax=cfg["tmax"],
                    width=5,
                    dash="dash" if slack else "solid",
                    showscale=i == 0,
                    colorbar=dict(title=dict(text="tension [N]"), len=0.6) if i == 0 else None,
                ),
                text=[f"tendon {i}: {state}; here {t:.3g} N" for t in ten],
                hoverinfo="text",
            )
        )
    if cfg["loads"]:
        shafts, heads = [], []
        for sl, f in _point_loads(scene):
            p, _ = state_at(sol, [sl])
            v = cfg["scale"] * f
            shaft, head = arrow(p[0] - v, v)
            shafts += [shaft, np.full((1, 3), np.nan)]
            heads.append(head)
        xyz = np.concatenate(shafts) if shafts else np.full((1, 3), np.nan)
        traces.append(
            go.Scatter3d(
                x=xyz[:, 0],
                y=xyz[:, 1],
                z=xyz[:, 2],
                mode="lines",
                name=cfg["load_name"],
                legendgroup="loads",
                line=dict(color="#9467bd", width=6),
                hoverinfo="name",
            )
        )
        traces.append(
            _mesh_trace(
                go,
                Mesh.join(heads) if heads else Mesh(np.full((1, 3), np.nan), np.zeros((0, 3), int)),
                "load heads",
                "#9467bd",
                legendgroup="loads",
                hoverinfo="skip",
            )
        )
        traces[-1].showlegend = False
    return traces


def _triad(go, origin, R, length: float, name: str, width: float) -> list:
    out = []
    for j, (ax, col) in enumerate(_AXES):
        end = np.asarray(origin) + length * np.asarray(R)[:, j]
        out.append(
            go.Scatter3d(
                x=[origin[0], end[0]],
                y=[origin[1], end[1]],
                z=[origin[2], end[2]],
                mode="lines+text",
                text=["", f"{ax}"],
                textfont=dict(color=col),
                line=dict(color=col, width=width),
                name=name,
                legendgroup=name,
                showlegend=j == 0,
                hoverinfo="name",
            )
        )
    return out


def _static_traces(go, scene, L: float, box: np.ndarray) -> list:
    out = _triad(go, np.zeros(3), np.eye(3), 0.15 * L, "world frame", 4)
    robot = scene.robot
    if robot.mounted:
        out += _triad(
            go,
            np.asarray(robot.base_position),
            np.asarray(robot.base_rotation),
            0.1 * L,
            "base frame",
            7,
        )
    g = np.asarray(scene.gravity, dtype=float)
    if np.any(g):
        gn = float(np.linalg.norm(g))
        tail = np.array([box[0, 0], box[0, 1], box[1, 2]])  # a top corner of the scene
        shaft, head = arrow(tail, 0.2 * L * g / gn)
        out.append(
            go.Scatter3d(
                x=shaft[:, 0],
                y=shaft[:, 1],
                z=shaft[:, 2],
                mode="lines+text",
                text=["g", ""],
                line=dict(color="black", width=5),
                name=f"gravity ({gn:.3g} m/s²)",
                legendgroup="gravity",
                hoverinfo="name",
            )
        )
        out.append(_mesh_trace(go, head, "gravity head", "black", legendgroup="gravity"))
        out[-1].showlegend = False
    return out


def _bounds(traces) -> np.ndarray:
    pts = []
    for t in traces:
        xyz = np.stack([np.asarray(t.x, float), np.asarray(t.y, float), np.asarray(t.z, float)], -1)
        pts.append(xyz[np.all(np.isfinite(xyz), axis=1)])
    P = np.concatenate(pts)
    return np.stack([P.min(axis=0), P.max(axis=0)])


# --------------------------------------------------------------------------- the figure
def view(
    x,
    scene=None,
    *,
    options=None,
    disks=None,
    tendons: bool = True,
    loads: bool = True,
    load_scale: float | None = None,
    sides: int = 24,
    max_frames: int = 60,
    title: str | None = None,
):
    """The figure of :func:`tendonrod.plot.view` (its docstring says the parameters)."""
    go = _plotly()
    steps = _steps(x, scene, options, max_frames)
    first = steps[0][1].scene
    L = first.robot.rod.length
    fmax = max(
        [float(np.linalg.norm(f)) for _, s in steps for _, f in _point_loads(s.scene)] + [0.0]
    )
    if load_scale is None:
        scale = 0.25 * L / fmax if fmax > 0 else 0.0
    else:
        scale = float(load_scale)
        if not (math.isfinite(scale) and scale >= 0):
            raise ValueError(
                f"load_scale must be a finite length per force >= 0 [m/N], got {load_scale!r}"
            )
    arcs = disk_arcs(first, disks)
    tmax = max([float(np.nanmax(np.asarray(s.tension, float), initial=0.0)) for _, s in steps])
    cfg = dict(
        sides=sides,
        disks=arcs if arcs.size else None,
        ntendons=first.robot.n_tendons,
        tendons=tendons,
        tmax=tmax if tmax > 0 else 1.0,
        loads=loads and fmax > 0 and scale > 0,
        scale=scale,
        load_name=f"loads (1 N = {1e3 * scale:.3g} mm)",
    )
    per_step = [_step_traces(go, sol, cfg) for _, sol in steps]
    box = _bounds([t for tr_ in per_step for t in tr_])
    static = _static_traces(go, first, L, box)
    box = _bounds([t for tr_ in per_step for t in tr_] + static)
    scale_txt = f"; load arrows: 1 N = {1e3 * scale:.3g} mm" if cfg["loads"] else ""
    fig = go.Figure(data=per_step[0] + static)
    _layout(fig, box, (title or "tendonrod") + scale_txt)
    fig.update_layout(
        meta=dict(tendonrod_load_scale=scale, tendonrod_steps=[lb for lb, _ in steps]),
    )
    if len(steps) > 1:
        _animate(go, fig, steps, per_step)
    return fig


def _layout(fig, box: np.ndarray, title: str) -> None:
    """A cube of axes around ``box`` (2, 3) [m] (world frame), the title and legend."""
    c, h = box.mean(axis=0), 0.55 * float(np.ptp(box, axis=0).max())
    rng = [[c[k] - h, c[k] + h] for k in range(3)]
    fig.update_layout(
        title=dict(text=title, x=0.02),
        scene=dict(
            xaxis=dict(title=dict(text="x [m]"), range=rng[0]),
            yaxis=dict(title=dict(text="y [m]"), range=rng[1]),
            zaxis=dict(title=dict(text="z [m]"), range=rng[2]),
            aspectmode="cube",
        ),
        legend=dict(x=0.0, y=1.0, bgcolor="rgba(255,255,255,0.6)"),
        margin=dict(l=0, r=0, t=40, b=0),
    )


def _animate(go, fig, steps, per_step) -> None:
    n = len(per_step[0])
    names = [f"{k}: {lb}" for k, (lb, _) in enumerate(steps)]
    fig.frames = [
        go.Frame(data=tr_, traces=list(range(n)), name=nm) for tr_, nm in zip(per_step, names)
    ]
    play = dict(
        frame=dict(duration=150, redraw=True), transition=dict(duration=0), fromcurrent=True
    )
    still = dict(frame=dict(duration=0, redraw=True), mode="immediate", transition=dict(duration=0))
    fig.update_layout(
        updatemenus=[
            dict(
                type="buttons",
                direction="left",
                x=0.02,
                y=0.02,
                xanchor="left",
                yanchor="bottom",
                buttons=[
                    dict(label="play", method="animate", args=[None, play]),
                    dict(label="pause", method="animate", args=[[None], still]),
                ],
            )
        ],
        sliders=[
            dict(
                active=0,
                x=0.15,
                len=0.8,
                y=0.02,
                currentvalue=dict(prefix="", visible=True),
                steps=[
                    dict(label=lb, method="animate", args=[[nm], still])
                    for (lb, _), nm in zip(steps, names)
                ],
            )
        ],
    )


def save_html(fig, path) -> None:
    """Write ``fig`` (from :func:`view`) to ``path`` as a standalone HTML page: plotly.js
    inlined (about 4.6 MB; opens without a network)."""
    fig.write_html(path, include_plotlyjs=True, full_html=True, auto_play=False)
