"""Plot helpers: accept ax=, return the Axes, label both axes, never show or save."""

import math

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
