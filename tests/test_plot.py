"""Plot helpers: accept ax=, return the Axes, label both axes, never show or save."""

import math
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import tendonrod as tr  # noqa: E402
from tendonrod import paper as S  # noqa: E402
from tendonrod import plot as P  # noqa: E402
from tendonrod.paper import charts as C  # noqa: E402


@pytest.fixture(autouse=True)
def no_show_no_save(monkeypatch):
    def forbidden(*a, **k):
        raise AssertionError("library code must not call plt.show() or savefig()")

    monkeypatch.setattr(plt, "show", forbidden)
    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", forbidden)
    yield
    plt.close("all")


def labelled(ax, z=False):
    ok = bool(ax.get_xlabel()) and bool(ax.get_ylabel())
    return ok and (bool(ax.get_zlabel()) if z else True)


CLOSED = [
    (C.sigma_vs_zeta, lambda: S.closed_form_sigma_vs_zeta(slopes=(0.0, -1.0))),
    (C.tip_sigma_vs_alpha, S.closed_form_tip_sigma_vs_alpha),
    (C.prototype_deflection, lambda: S.prototype_curves("parallel")),
    (C.prototype_shapes, lambda: S.prototype_shapes("converging")),
    (
        C.prototype_tension,
        lambda: [S.prototype_curves("parallel"), S.prototype_curves("converging")],
    ),
]


@pytest.mark.parametrize("fn, data", CLOSED, ids=[c[0].__name__ for c in CLOSED])
def test_closed_form_charts(fn, data):
    fig, ax = plt.subplots()
    out = fn(data(), ax=ax)
    assert out is ax and labelled(ax) and len(ax.lines) >= 2
    out2 = fn(data())  # ax=None: draws on the current Axes
    assert isinstance(out2, matplotlib.axes.Axes) and labelled(out2)


def test_units_or_groups_in_labels():
    fig, ax = plt.subplots()
    C.sigma_vs_zeta(S.closed_form_sigma_vs_zeta(), ax=ax)
    assert "EI" in ax.get_ylabel() and "z / L" in ax.get_xlabel()
    fig, ax = plt.subplots()
    C.prototype_deflection(S.prototype_curves("converging"), ax=ax)
    assert "[mm]" in ax.get_xlabel() and "[mm]" in ax.get_ylabel()


def test_curve_values_are_the_data():
    d = S.closed_form_tip_sigma_vs_alpha(np.logspace(-1, 3, 9))
    fig, ax = plt.subplots()
    C.tip_sigma_vs_alpha(d, ax=ax)
    ys = [ln.get_ydata() for ln in ax.lines]
    assert any(np.array_equal(y, d["parallel"]) for y in ys)
    assert any(np.array_equal(y, d["converging"]) for y in ys)


def test_robot_planar_and_spatial():
    rod = S.paper_rod_ivb()
    robot = tr.Robot(rod, [tr.Tendon(offset=0.01, angle=2 * math.pi * i / 3) for i in range(3)])
    planar = tr.Scene(
        tr.Robot(rod, [tr.Tendon(offset=0.01)]),
        tension=[2.0],
        loads=[tr.PointLoad(s=0.1, force=(-0.2, 0.0, 0.0))],
    )
    sol = tr.solve(planar)
    assert P.is_planar(planar)
    ax = P.robot(sol)  # planar scene: the x-z view on 2D Axes
    assert ax.name != "3d" and ax.get_xlabel() == "x [m]" and ax.get_ylabel() == "z [m]"
    xs = ax.lines[0].get_xdata()
    assert np.array_equal(xs, sol.position[:, 0])  # the backbone is the solution
    # tendon line = backbone + R r(s): at the base it sits at x = offset
    assert ax.lines[1].get_xdata()[0] == pytest.approx(0.01, abs=1e-15)  # R(0) = I exactly
    spatial = tr.Scene(
        robot, tension=[2.0, 0.0, 0.0], loads=[tr.PointLoad(s=0.1, force=(0.0, 0.3, 0.0))]
    )
    assert not P.is_planar(spatial)
    sol3 = tr.solve(spatial)
    fig = plt.figure()
    ax3 = fig.add_subplot(projection="3d")
    out = P.robot(sol3, ax=ax3, disks=5)
    assert out is ax3 and labelled(ax3, z=True)
    assert len(ax3.lines) == 1 + 3 + 5  # backbone, tendons, disks


def test_robot_tendon_legend_slack_dashed_and_tension_labels():
    """Two opposing displacement-controlled tendons, the second paid out: it is slack
    (drawn dashed, named "slack" in the legend), the first taut with its tension."""
    rod = S.paper_rod_ivb()
    robot = tr.Robot(rod, [tr.Tendon(offset=0.01), tr.Tendon(offset=0.01, angle=math.pi)])
    sol = tr.solve(tr.Scene(robot, displacement=[0.01, -0.012]))
    assert sol.tension[0] > 0.0 and sol.tension[1] == 0.0 and sol.slack[1] > 0.0
    ax = P.robot(sol, tension_labels=True)
    tendon_lines = [ln for ln in ax.lines if ln.get_label().startswith("tendon")]
    assert [ln.get_linestyle() for ln in tendon_lines] == ["-", "--"]
    texts = [t.get_text() for t in ax.get_legend().get_texts()]
    assert texts == [f"tendon 0: {sol.tension[0]:.3g} N", "tendon 1: slack"]
    assert any("slack" in t.get_text() for t in ax.texts)  # the label at the anchor
    # on a given Axes (several robots) no legend unless asked
    fig, ax2 = plt.subplots()
    P.robot(sol, ax=ax2)
    assert ax2.get_legend() is None


def test_shapes_and_tension_vs_load():
    fig, ax = plt.subplots()
    pts = np.stack([np.zeros(5), np.zeros(5), np.linspace(0, 0.1, 5)], axis=1)
    assert P.shapes({"a": pts}, ax=ax) is ax and labelled(ax)
    fig, ax = plt.subplots()
    assert P.tension_vs_load(np.arange(4.0), np.ones((4, 2)), ax=ax) is ax and labelled(ax)
    assert len(ax.lines) == 2


def test_sweep_lines():
    rod = S.paper_rod_ivb()
    base = tr.Scene(
        tr.Robot(rod, [tr.Tendon(offset=0.01)]),
        displacement=[0.0],
        loads=[tr.PointLoad(s=0.1, force=(0.0, 0.0, 0.0))],
    )
    EAs = [1e4, np.inf]
    mags = [0.1, 0.2, 0.3]
    res = tr.sweep(
        base,
        {"robot.tendons[0].EA": EAs, "loads[0].force": [(-f, 0.0, 0.0) for f in mags]},
        progress=False,
    )
    fig, ax = plt.subplots()
    out = P.sweep_lines(
        res,
        "loads[0].force",
        "tip_position",
        component=0,
        ax=ax,
        xlabel="tip load [N]",
        ylabel="tip x [m]",
    )
    assert out is ax and labelled(ax) and len(ax.lines) == len(EAs)  # one line per EA
    assert np.allclose(ax.lines[1].get_xdata(), mags, rtol=1e-15)  # |force| on x
    assert np.array_equal(ax.lines[1].get_ydata(), res["tip_position"][1, :, 0])
    assert "inf" in ax.lines[1].get_label()
    with pytest.raises(ValueError, match="component"):
        P.sweep_lines(res, "loads[0].force", "tip_position", ax=ax)


# --------------------------------------------------------------------------- layout
def _drawn_ticklabels(axis):
    """The tick labels an axis draws: those of ticks inside its view interval."""
    lo, hi = sorted(axis.get_view_interval())
    tol = 1e-9 * max(abs(lo), abs(hi), 1e-300)  # a tick at a limit, up to rounding
    out = []
    for tick in axis.get_major_ticks() + axis.get_minor_ticks():
        if lo - tol <= tick.get_loc() <= hi + tol:
            out += [t for t in (tick.label1, tick.label2) if t.get_visible() and t.get_text()]
    return out


def layout_problems(fig):
    """What is wrong with a drawn figure's layout, in words (empty: nothing): a text artist
    reaching outside the figure, tick labels of one axis overlapping (2D Axes), a title
    smaller than its tick labels, a legend entry without a visible artist."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.text import Text

    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    r = canvas.get_renderer()
    fb = fig.bbox

    def outside(bb):  # one pixel of slack: antialiasing at the edge
        return bb.x0 < fb.x0 - 1 or bb.y0 < fb.y0 - 1 or bb.x1 > fb.x1 + 1 or bb.y1 > fb.y1 + 1

    out, tick_texts = [], set()
    for ax in fig.axes:
        for axis in ax._axis_map.values():
            for tick in axis.get_major_ticks() + axis.get_minor_ticks():
                tick_texts |= {id(tick.label1), id(tick.label2)}
    for t in fig.findobj(Text):
        if id(t) in tick_texts or not t.get_visible() or not t.get_text().strip():
            continue
        if outside(t.get_window_extent(r)):
            out.append(f"text outside the figure: {t.get_text()!r}")
    for ax in fig.axes:
        for name, axis in ax._axis_map.items():
            boxes = [(t.get_text(), t.get_window_extent(r)) for t in _drawn_ticklabels(axis)]
            out += [f"{name} tick label outside: {s!r}" for s, bb in boxes if outside(bb)]
            if ax.name == "3d":  # projected tick labels: matplotlib places them
                continue
            for i, (sa, a) in enumerate(boxes):
                for sb, b in boxes[i + 1 :]:
                    if a.overlaps(b):
                        out.append(f"{name} tick labels overlap: {sa!r}, {sb!r}")
        sizes = [t.get_fontsize() for t in _drawn_ticklabels(ax.xaxis)]
        if ax.get_title() and sizes and ax.title.get_fontsize() < max(sizes):
            out.append(f"title smaller than its tick labels: {ax.get_title()!r}")
        leg = ax.get_legend()
        if leg is not None:
            for text, h in zip(leg.get_texts(), leg.legend_handles):
                style = getattr(h, "get_linestyle", lambda: "-")()
                marker = getattr(h, "get_marker", lambda: "o")()
                drawn = h.get_visible() and (style not in ("None", "", " ") or marker != "None")
                if not drawn:
                    out.append(f"legend entry without an artist: {text.get_text()!r}")
    return out


def test_layout_check_finds_what_it_looks_for():
    from matplotlib.figure import Figure

    fig = Figure(figsize=(3, 2))
    ax = fig.add_subplot()
    ax.set_xticks(np.linspace(0, 1, 40))  # 40 labels on 3 inches
    ax.set_title("t", fontsize="x-small")
    ax.text(1.5, 0.5, "far right", transform=ax.transAxes)
    ax.plot([0, 1], [0, 1], ls="none", label="nothing drawn")
    ax.legend()
    found = " | ".join(layout_problems(fig))
    for what in ("outside the figure", "overlap", "title smaller", "without an artist"):
        assert what in found, what


FIGURES = list(S.figures.figure_registry())


@pytest.mark.parametrize("key", FIGURES)
def test_paper_figure_layout(key):
    """Every figure of `python -m tendonrod figures` (fast grids: the same drawing)."""
    fig = S.figures.figure_registry()[key].make(fast=True)
    assert layout_problems(fig) == []


def test_savefig_formats(tmp_path, monkeypatch):
    monkeypatch.undo()  # the autouse fixture forbids savefig in library code; this is the API
    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    magic = {"png": b"\x89PNG", "pdf": b"%PDF-", "svg": b"<?xml"}
    for fmt, head in magic.items():
        path = P.savefig(ax, tmp_path / f"f.{fmt}")  # an Axes: its figure
        data = pathlib.Path(path).read_bytes()
        assert data.startswith(head), fmt
        # no creation date: the same figure gives the same bytes
        P.savefig(fig, tmp_path / f"g.{fmt}")
        assert (tmp_path / f"g.{fmt}").read_bytes() == data, fmt
    assert b"<svg" in (tmp_path / "f.svg").read_bytes()
    with pytest.raises(ValueError, match=r"'\.jpg'"):
        P.savefig(fig, tmp_path / "f.jpg")
    names = S.figures.write_figure(fig, str(tmp_path), "fig99", "svg,PDF")
    assert names == ["fig99.svg", "fig99.pdf"]
    assert all((tmp_path / n).stat().st_size > 0 for n in names)
    assert S.figures.parse_formats(".png, svg") == ("png", "svg")
    with pytest.raises(ValueError, match="'eps'"):
        S.figures.parse_formats("png,eps")


def test_robot_frame_gravity_and_arrows_inside_the_limits():
    rod = tr.Rod(0.2, 1e-3, 200e9, 80e9, density=7800.0)
    R0 = np.array([[0.0, 0, 1], [0, 1, 0], [-1, 0, 0]])  # the rod along world +x
    robot = tr.Robot(rod, [tr.Tendon(0.01, 0.0), tr.Tendon(0.01, 2.0)], base_rotation=R0)
    F = np.array([0.0, 0.0, 0.8])
    scene = tr.Scene(robot, tension=[1.0, 0.0], loads=[tr.PointLoad(0.2, F)], gravity=(0, 0, -9.81))
    sol = tr.solve(scene)
    ax = P.robot(sol, load_scale=0.1)
    quivers = [c for c in ax.collections if type(c).__name__ == "Line3DCollection"]
    assert len(quivers) == 1 + 3 + 1  # the load, the base frame's axes, gravity
    assert [t.get_text() for t in ax.texts] == [" g"]
    # the load arrow ends at the tip and starts 0.1 m/N * 0.8 N before it: inside the box
    tail = sol.position[-1] - 0.1 * F
    for lim, v in zip((ax.get_xlim(), ax.get_ylim(), ax.get_zlim()), tail):
        assert lim[0] <= v <= lim[1]
    # without the frame: only the load's arrow
    ax = P.robot(sol, frame=False)
    assert len([c for c in ax.collections if type(c).__name__ == "Line3DCollection"]) == 1


def test_plots_own_their_axes(rod):
    """Without ax= every plot draws on a new figure's Axes (never pyplot's current one): a
    planar plot after a spatial one stays planar, tension labels included; with ax= it
    draws there.  Each returns its Axes."""
    spatial = tr.solve(
        tr.Scene(
            tr.Robot(rod, [tr.Tendon(0.01)]),
            displacement=[0.01],
            loads=[tr.PointLoad(s=0.2, force=(0.0, 0.05, 0.0))],
        )
    )
    planar = tr.solve(tr.Scene(tr.Robot(rod, [tr.Tendon(0.01)]), displacement=[0.01]))
    plt.close("all")
    a3 = P.robot(spatial)
    a2 = P.robot(planar, tension_labels=True)
    assert a3.name == "3d" and a2.name != "3d" and a2.figure is not a3.figure
    others = [
        P.shapes({"a": planar.position}),
        P.tension_vs_load([0.0, 1.0], [[1.0], [2.0]]),
    ]
    figures = {id(a.figure) for a in [a3, a2, *others]}
    assert len(figures) == 4  # one new figure each
    fig, ax = plt.subplots()
    assert P.shapes({"a": planar.position}, ax=ax) is ax
    assert P.robot(planar, ax=ax) is ax and P.tension_vs_load([0.0], [[1.0]], ax=ax) is ax
    plt.close("all")
