"""Plotting helpers (matplotlib, imported inside each function).

Every plot function takes ``ax=None`` (None: a new figure and Axes, 3-D where one is
needed; never pyplot's current Axes), draws, labels the axes with units or as the
nondimensional group, and returns the Axes.  Nothing here calls ``plt.show()`` or
``savefig``.

- :func:`robot` -- the solved robot: backbone, tendons along their routes
  r(s) (linear, helical or a path) mapped through the solved frames, spacer disks,
  segment joints, point loads as arrows; a 3D view, or the x-z plane for planar scenes.
- :func:`shapes` -- several backbones in the x-z plane (deflection curves).
- :func:`sweep_lines` -- a recorded quantity of a sweep against one varied parameter.
- :func:`tension_vs_load` -- tendon tensions against a load.
- :func:`branch` -- a load path (:func:`tendonrod.path`, a :class:`tendonrod.Branch`):
  parameter against a tip displacement (:func:`path` before 0.2).
- :func:`savefig` -- a figure to PNG, PDF or SVG by the file's suffix (reproducible
  metadata, the bounding box fitted to what is drawn).
- :func:`view` -- an interactive 3-D view (Plotly, the ``view`` extra) of a solution, a
  load path, a sweep or a list of solutions; :func:`save_html` writes it as a standalone
  page (see :mod:`tendonrod._view`).

The paper's own charts and figures are in :mod:`tendonrod.paper.charts` and
:mod:`tendonrod.paper.figures`.
"""

from __future__ import annotations

import math

import numpy as np

from ._mesh import state_at as _state_at
from ._mesh import tendon_route
from ._plot_scene import draw_frame, draw_masses, equal_3d, without_masses
from .compiled import is_planar

__all__ = [
    "is_planar",
    "branch",
    "modes",
    "robot",
    "shapes",
    "sweep_lines",
    "tension_vs_load",
    "view",
    "save_html",
    "savefig",
]

FORMATS = ("png", "pdf", "svg")
"""The file formats :func:`savefig` writes (by the path's suffix)."""


def _ax(ax, projection=None):
    """``ax``, or a new figure's Axes (3-D with ``projection="3d"``): a plot never draws
    into whatever Axes happens to be current (a planar plot after a spatial one would land
    in the 3-D Axes)."""
    if ax is not None:
        return ax
    from ._extras import optional_import

    plt = optional_import("matplotlib.pyplot", "tendonrod.plot")
    return plt.figure().add_subplot(projection=projection)


def robot(
    sol,
    scene=None,
    ax=None,
    planar=None,
    disks: int = 8,
    disk_radius=None,
    tendons: bool = True,
    loads: bool = True,
    load_scale=None,
    color="k",
    label=None,
    alpha: float = 1.0,
    joints: bool = True,
    masses: bool = True,
    legend: bool | None = None,
    tension_labels: bool = False,
    frame: bool = True,
):
    """Draw a solved robot (a precurved or segmented backbone as solved: its shape is
    the recorded one).  ``joints``: mark the joints of a segmented rod (black dots).

    Parameters
    ----------
    sol : tendonrod.Solution
    scene : tendonrod.Scene, optional
        Default ``sol.scene``.
    ax : Axes, optional
        A 3D Axes (spatial view) or 2D Axes (x-z view).  None: a new figure's Axes, 2D
        for planar scenes, else 3D.
    planar : bool, optional
        Force the x-z view (True) or the 3D view (False); default from ``ax`` or
        :func:`is_planar`.
    disks : int
        Spacer disks drawn at evenly spaced arc lengths (0: none).
    disk_radius : float, optional
        [m], default 1.3 times the largest tendon offset (or L/30 without tendons).
    loads : bool
        Point loads as arrows (length ``load_scale`` [m/N], default: the largest
        force drawn L/4 long).
    masses : bool
        Point masses (:class:`tendonrod.PointMass`, e.g. ``PointMass.disks``) as disks of
        radius ``disk_radius`` in brown at their arc lengths, with a dot whose area grows
        with the mass (the heaviest 6 pt across); their weights are not drawn as arrows.
    tendons : bool
        The tendons along their routes, one colour each; a slack tendon (no tension, some
        slack) dashed.
    legend : bool, optional
        A legend naming each tendon with its tension [N] (or "slack"); default: when the
        Axes is made here (one robot), not on a given Axes (several robots).
    tension_labels : bool
        Each tendon's tension [N] written at its anchor.
    frame : bool
        The base frame as arrows L/8 long at the base (x red, y green, z blue; the x-z
        view shows x and z) and, when the scene has gravity, an arrow "g" along it beside
        the robot.  The axis limits take in these arrows and the load arrows.

    Returns
    -------
    Axes
        ``ax``, or the new one.
    """
    scene = getattr(sol, "scene", None) if scene is None else scene
    if scene is None:
        raise ValueError("robot(): pass scene= (the solution does not carry its scene)")
    legend = ax is None if legend is None else legend
    if ax is not None:
        is3d = getattr(ax, "name", "") == "3d"
        planar = (not is3d) if planar is None else planar
    else:
        planar = is_planar(scene) if planar is None else planar
        ax = _ax(None, None if planar else "3d")
    L = scene.robot.rod.length
    P = np.asarray(sol.position)

    def draw(pts, **kw):
        pts = np.asarray(pts)
        if planar:
            return ax.plot(pts[:, 0], pts[:, 2], **kw)
        return ax.plot(pts[:, 0], pts[:, 1], pts[:, 2], **kw)

    draw(P, color=color, lw=2.0, label=label, alpha=alpha)
    offsets = [t.offset for t in scene.robot.tendons]
    rad = (
        disk_radius
        if disk_radius is not None
        else (1.3 * max(offsets) if offsets and max(offsets) > 0 else L / 30)
    )
    tcolors = ["tab:red", "tab:blue", "tab:green", "tab:orange", "tab:purple", "tab:brown"]
    tension = np.asarray(getattr(sol, "tension", []), dtype=float)
    slack = np.asarray(getattr(sol, "slack", np.zeros_like(tension)), dtype=float)
    if tendons:
        for i in range(scene.robot.n_tendons):
            _, pts = tendon_route(sol, scene, i)
            tau = float(tension[i]) if i < tension.size else math.nan
            is_slack = tau == 0.0 and i < slack.size and slack[i] > 0.0
            state = "slack" if is_slack else f"{tau:.3g} N"
            draw(
                pts,
                color=tcolors[i % len(tcolors)],
                lw=1.0,
                ls="--" if is_slack else "-",
                alpha=alpha,
                label=f"tendon {i}: {state}" if legend else None,
            )
            if tension_labels:
                q = pts[-1]
                xy = (q[0], q[2]) if planar else (q[0], q[1], q[2])
                ax.text(*xy, f" {state}", color=tcolors[i % len(tcolors)], fontsize="small")
    if disks:
        sd = np.linspace(0.0, L, disks + 1)[1:]
        Ps, Rs = _state_at(sol, sd)
        ang = np.linspace(0.0, 2 * math.pi, 33)
        ring = rad * np.stack([np.cos(ang), np.sin(ang), np.zeros_like(ang)], axis=-1)
        for p, R in zip(Ps, Rs):
            if planar:
                ends = p + np.array([R @ np.array([-rad, 0, 0]), R @ np.array([rad, 0, 0])])
                draw(ends, color="0.5", lw=1.5, alpha=alpha)
            else:
                draw(p + ring @ R.T, color="0.5", lw=0.8, alpha=alpha)
    if joints and scene.robot.rod.segments:
        sj = np.cumsum([p.length for p in scene.robot.rod.segments])[:-1]
        Pj, _ = _state_at(sol, sj)
        draw(Pj, color="k", ls="", marker="o", ms=4, alpha=alpha)
    if masses:
        draw_masses(sol, scene, draw, planar, rad, alpha)
    # the arrows below are the point loads: a point mass has no force of its own
    scene = without_masses(scene)
    extra: list = []  # points the axis limits must take in besides the backbone
    if frame:
        extra += draw_frame(ax, scene, P, L, planar)
    if loads:
        pls = [ld for ld in scene.loads if hasattr(ld, "s")]
        fmax = max([np.linalg.norm(ld.force) for ld in pls] + [0.0])
        scale = load_scale if load_scale is not None else (0.25 * L / fmax if fmax > 0 else 0.0)
        for ld in pls:
            f = np.asarray(ld.force, dtype=float)
            if not np.any(f) or scale == 0.0:
                continue
            p, _ = _state_at(sol, [ld.s])
            p = p[0]
            v = f * scale
            extra.append(p - v)
            if planar:
                ax.annotate(
                    "",
                    xy=(p[0], p[2]),
                    xytext=(p[0] - v[0], p[2] - v[2]),
                    arrowprops=dict(arrowstyle="->", color="tab:purple", lw=1.5),
                )
            else:
                ax.quiver(
                    p[0] - v[0], p[1] - v[1], p[2] - v[2], v[0], v[1], v[2], color="tab:purple"
                )
    if planar:
        ax.set_xlabel("x [m]")
        ax.set_ylabel("z [m]")
        if extra:
            ax.update_datalim(np.asarray(extra)[:, [0, 2]])
            ax.autoscale_view()
        ax.set_aspect("equal", adjustable="datalim")
    else:
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        ax.set_zlabel("z [m]")
        equal_3d(ax, np.concatenate([P, np.reshape(extra, (-1, 3))]), L)
    if legend and tendons and scene.robot.tendons:
        ax.legend(fontsize="small")
    return ax


def shapes(
    curves: dict,
    ax=None,
    plane: str = "xz",
    styles: dict | None = None,
    scale: float = 1.0,
    unit: str = "m",
):
    """Backbones ``{label: (N, 3) positions [m]}`` projected on ``plane`` ('xz', 'yz'
    or 'xy'); ``scale`` multiplies coordinates (1e3 with unit='mm').  Returns the Axes
    (``ax``, or a new figure's)."""
    ax = _ax(ax)
    i, j = ("xyz".index(plane[0]), "xyz".index(plane[1]))
    for label, P in curves.items():
        P = np.asarray(P) * scale
        ax.plot(P[:, i], P[:, j], label=label, **(styles or {}).get(label, {}))
    ax.set_xlabel(f"{plane[0]} [{unit}]")
    ax.set_ylabel(f"{plane[1]} [{unit}]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend(fontsize="small")
    return ax


def sweep_lines(res, x: str, y: str, component=None, ax=None, xlabel=None, ylabel=None, **kwargs):
    """Plot a recorded quantity of a :class:`tendonrod.SweepResult` against one varied
    parameter: one line per combination of the other grid axes (labelled with their
    values); points that did not converge are left out (NaN).

    ``x``: a varied name (its values must be scalars, or vectors, which are plotted by
    their norm); ``y``: a recorded key; ``component``: index into the item shape (e.g.
    ``0`` for the x of ``tip_position``, ``(2, 2)`` for a rotation entry).  Give
    ``xlabel``/``ylabel`` with units; the defaults are the names.  Returns the Axes
    (``ax``, or a new figure's).
    """
    ax = _ax(ax)
    names = list(res.names)
    if x not in names:
        raise ValueError(f"x={x!r} is not a varied parameter ({', '.join(names)})")
    shape = tuple(res.shape)
    nd = len(shape)
    ys = np.asarray(res[y], dtype=float)
    if component is not None:
        comp = component if isinstance(component, tuple) else (component,)
        ys = ys[(slice(None),) * nd + comp]
    if ys.shape != shape:
        raise ValueError(f"{y!r} has item shape {ys.shape[nd:]}; choose a component")
    ys = np.where(res.success, ys, np.nan)
    xv = np.asarray(res[x], dtype=float)
    if xv.ndim > nd:
        xv = np.linalg.norm(xv.reshape(shape + (-1,)), axis=-1)
        xlabel = xlabel or f"|{x}|"
    axis = names.index(x) if nd == len(names) else 0
    others = [k for k in range(nd) if k != axis]
    for combo in np.ndindex(*[shape[k] for k in others]):
        idx = [0] * nd
        for k, c in zip(others, combo):
            idx[k] = c
        sl: list = list(idx)
        sl[axis] = slice(None)
        lab = ", ".join(
            f"{names[k]} = {_fmt(np.asarray(res[names[k]])[tuple(idx)])}" for k in others
        )
        ax.plot(xv[tuple(sl)], ys[tuple(sl)], label=lab or None, **kwargs)
    if others:
        ax.legend(fontsize="x-small")
    ax.set_xlabel(xlabel or x)
    ax.set_ylabel(ylabel or (y if component is None else f"{y}[{component}]"))
    ax.grid(alpha=0.3)
    return ax


def _fmt(v):
    v = np.asarray(v)
    if v.ndim:
        return "(" + ", ".join(_fmt(e) for e in v.ravel()) + ")"
    try:
        return f"{float(v):.4g}"
    except (TypeError, ValueError):
        return str(v)


def tension_vs_load(F, tension, ax=None, labels=None, ylabel: str = "tendon tension [N]"):
    """Tendon tension(s) (K, nt) [N] against load F (K,) [N] (the paper's Figs. 17-18).
    Returns the Axes (``ax``, or a new figure's)."""
    ax = _ax(ax)
    T = np.asarray(tension).reshape(len(F), -1)
    for i in range(T.shape[1]):
        lab = labels[i] if labels else f"tendon {i}"
        ax.plot(F, T[:, i], marker=".", label=lab)
    ax.set_xlabel("tip load F [N]")
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.legend(fontsize="small")
    return ax


def branch(
    p, displacement: str = "x", ax=None, scale: float = 1.0, ylabel=None, color=None, **kwargs
):
    """Plot a :class:`tendonrod.Branch` (the result of :func:`tendonrod.path`): its parameter (divided by ``scale``, e.g. EI/L^2 for
    a force) against a tip displacement [m] (``"x"``, ``"y"``, ``"z"``: that component of
    the tip position minus its start value; ``"norm"``: the distance from the start's tip).
    Stable stretches solid, unstable dashed, undecided dotted; limit points as circles,
    bifurcation points as squares.  ``ylabel`` (default the parameter's path) should give
    the unit.  Returns the Axes (``ax``, or a new figure's)."""
    from ._plot_branch import draw

    return draw(p, _ax(ax), displacement, float(scale), ylabel, color, **kwargs)


def modes(m, which=None, ax=None, scale=None, plane: str = "xz", **kwargs):
    """Plot the mode shapes of a :class:`tendonrod.Modes` (:func:`tendonrod.modes`): the
    equilibrium's centre line and, per mode in ``which`` (indices; default the first three),
    the centre line displaced by ``+-scale`` times its shape (``scale`` [m] default 0.15 L;
    the shapes are normalised to a largest displacement of 1 m), world frame, projected on
    ``plane`` (``"xz"``, ``"yz"``, ``"xy"``) or in 3-D (``"3d"``).  Returns the Axes.

    Examples
    --------
    >>> rod = tr.Rod(0.2, 1e-3, 207e9, 79.6e9, density=7800.0, kirchhoff=True)
    >>> m = tr.modes(tr.Scene(tr.Robot(rod, [])), n=3)
    >>> ax = tr.plot.modes(m, which=[0, 2])
    >>> len(ax.lines)  # the equilibrium, each mode at +- scale
    5
    """
    from ._plot_modes import draw

    return draw(m, lambda proj: _ax(ax, proj), which, scale, plane, **kwargs)


def path(*args, **kwargs):
    """Deprecated since 0.2 (removed in 0.3): :func:`branch`."""
    from ._deprecation import deprecated

    deprecated("tendonrod.plot.path", "tendonrod.plot.branch")
    return branch(*args, **kwargs)


def view(x, scene=None, **kwargs):
    """An interactive 3-D view of solved robot(s): a :class:`plotly.graph_objects.Figure`.

    Parameters
    ----------
    x : Solution, list of Solution, Branch, SweepResult, BatchResult or Trajectory
        What to show; several (a path's points, a sweep's or batch's converged points, a
        list of solutions) get a slider and a play button, one step per point.  A
        :class:`~tendonrod.Trajectory` recorded with ``options={"backbone": True}`` is
        animated, one frame per drawn time (slider labelled ``t = ... s``): the backbone
        as a tube around its recorded centre line (rings carried by rotation-minimising
        frames: a trajectory keeps no rotations) and the tip as a marker, with the tip's
        path over every row fixed; no tendons or loads (not recorded along the rod: their
        keywords and ``disks``, ``options`` are refused).  A trajectory without backbone
        states is refused (ValueError).
    scene : Scene or list of Scene, optional
        A sweep's base scene (its points are rebuilt from it and solved again, warm), or
        a batch's scenes in input order; a trajectory's scene (the rod's diameter, the
        frames and gravity; without it the tube is drawn L/50 thick); unused otherwise.
    options : Options, optional
        Options of the re-solves (a sweep's or batch's) and of a path's recording.
    disks : int or sequence of float, optional
        Spacer disks: a count spread evenly, or arc lengths [m]; default the scene's point
        masses, or the holes of a tendon routed disk by disk, else none.
    tendons, loads : bool
        Draw the tendons (coloured by tension [N], slack dashed) and the point loads.
    load_scale : float, optional
        Arrow length per force [m/N]; default: the largest force of all steps drawn L/4
        long.  Written in the title.
    sides : int
        Vertices per ring of the tube meshes.
    max_frames : int
        At most this many steps or frames (evenly chosen, first and last kept).
    title : str, optional
        Default: what is shown and the load scale.

    Returns
    -------
    plotly.graph_objects.Figure
        Save it with :func:`save_html` (a standalone page) or ``fig.show()``.

    Raises
    ------
    ImportError
        plotly is missing (the message names the extra: ``pip install 'tendonrod[view]'``).

    Examples
    --------
    >>> robot = tr.Robot(tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True), [tr.Tendon(0.01)])
    >>> scene = tr.Scene(robot, displacement=[0.01], loads=[tr.PointLoad(0.2, (0, 0, -0.1))])
    >>> fig = tr.plot.view(tr.solve(scene))
    >>> [t.name for t in fig.data][:3]
    ['backbone (d = 0.8 mm)', 'tendon 0', 'loads (1 N = 500 mm)']

    A load path, one slider step per point:

    >>> p = tr.path(scene, "displacement[0]", (0.0, 0.0157))
    >>> len(tr.plot.view(p).frames) == len(p)
    True

    A motion, at most 20 frames of its 51 rows:

    >>> rod = tr.Rod(0.2, 2e-3, 207e9, 79.6e9, density=7800.0)
    >>> held = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(0.2, (1e-3, 0, 0))])
    >>> start = tr.solve(held, options=tr.simulation_options())
    >>> free = tr.Scene(tr.Robot(rod, []))
    >>> traj = tr.simulate(free, 0.01, 2e-4, initial=start, options={"backbone": True})
    >>> fig = tr.plot.view(traj, free, max_frames=20)
    >>> len(fig.frames), fig.layout.sliders[0].steps[-1].label
    (20, 't = 0.01 s')
    """
    from ._view import view as _view
    from .dynamics import Trajectory

    if isinstance(x, Trajectory):
        from ._view_motion import view_trajectory

        return view_trajectory(x, scene, **kwargs)
    return _view(x, scene, **kwargs)


def save_html(fig, path) -> None:
    """Write a :func:`view` figure to ``path`` as a standalone HTML page: plotly.js
    inlined (about 4.6 MB), so it opens without a network.

    Examples
    --------
    >>> import os, tempfile
    >>> robot = tr.Robot(tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True), [tr.Tendon(0.01)])
    >>> fig = tr.plot.view(tr.solve(tr.Scene(robot, displacement=[0.01])))
    >>> tr.plot.save_html(fig, page := os.path.join(tempfile.mkdtemp(), "robot.html"))
    >>> os.path.getsize(page) > 4e6
    True
    """
    from ._view import save_html as _save

    _save(fig, path)


def savefig(fig, path, dpi: float = 200.0) -> str:
    """Write ``fig`` (a matplotlib Figure, or an Axes: its figure) to ``path``, the format by
    the suffix: ``.png`` (raster at ``dpi``), ``.pdf`` or ``.svg`` (vector, for papers).
    The bounding box is fitted to what is drawn (no text cut off); the files carry no
    creation date, so the same figure gives the same bytes.  Returns the path.

    Raises ``ValueError`` naming the suffix if it is none of :data:`FORMATS`.

    Examples
    --------
    >>> import os, tempfile
    >>> robot = tr.Robot(tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True), [tr.Tendon(0.01)])
    >>> ax = tr.plot.robot(tr.solve(tr.Scene(robot, displacement=[0.01])))
    >>> out = tr.plot.savefig(ax, os.path.join(tempfile.mkdtemp(), "robot.pdf"))
    >>> open(out, "rb").read(5)
    b'%PDF-'
    """
    import os

    fig = getattr(fig, "figure", fig) if not hasattr(fig, "savefig") else fig
    if not hasattr(fig, "savefig"):
        raise TypeError(f"savefig: fig must be a matplotlib Figure or Axes, got {fig!r}")
    p = os.fspath(path)
    fmt = os.path.splitext(p)[1].lower().lstrip(".")
    if fmt not in FORMATS:
        raise ValueError(
            f"savefig: path={p!r} has suffix {'.' + fmt if fmt else '(none)'!r}; "
            f"known: {', '.join('.' + f for f in FORMATS)}"
        )
    import matplotlib

    meta = {"png": {"Software": None}, "pdf": {"CreationDate": None}, "svg": {"Date": None}}
    # a fixed salt for the SVG's element ids (random otherwise)
    with matplotlib.rc_context({"svg.hashsalt": "tendonrod"}):
        fig.savefig(
            p, format=fmt, dpi=dpi, bbox_inches="tight", pad_inches=0.05, metadata=meta[fmt]
        )
    return p
