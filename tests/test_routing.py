"""General tendon routing (tendonrod.routing, csrc/tr_routing.c) against an independent
SciPy shooting reference (tendonrod.bench.references.helical_tendon_state) written from
the equations of docs/model.md (states p, R, n_b
and the curvature u itself, not the core's moment; helix r, r', r'' by hand), and the
special cases: a helix of zero turns is the parallel tendon, a sampled straight path is
the linear routing."""

import math

import numpy as np
import pytest

import tendonrod as tr
from tendonrod.bench import references as refs
from tendonrod.routing import Path

pytest.importorskip("scipy.integrate")  # the reference's shooting

L, EI, GJ = 0.2, 0.05, 0.035  # [m], [N m^2]


def _reference(b, phi, twist, tip_force, tension=None, q=None):
    """(tip position, tension) of the SciPy shooting reference
    (tendonrod.bench.references.helical_tendon_state: never calls the core)."""
    return refs.helical_tendon_state(L, EI, GJ, b, phi, twist, tip_force, tension=tension, q=q)


_ROD = tr.Rod(L, EI=EI, GJ=GJ, kirchhoff=True)


@pytest.mark.parametrize("turns", [0.75, 1.5])
def test_helical_tendon_under_tension_against_scipy(turns):
    b, phi, tau = 0.004, 0.3, 2.5
    F = np.array([0.05, -0.08, 0.0])
    t = tr.Tendon.helical(b, phi, turns=turns, length=L)
    sol = tr.solve(
        tr.Scene(tr.Robot(_ROD, [t]), tension=[tau], loads=[tr.PointLoad(L, force=tuple(F))])
    )
    assert sol.success and sol.formulation.n_routed_tendons == 1
    p_ref, _ = _reference(b, phi, 2 * math.pi * turns / L, F, tension=tau)
    # two solvers at tol 1e-10 (scaled) and rtol 1e-12: agreement to ~1e-10 L
    assert np.abs(sol.position[-1] - p_ref).max() < 1e-8 * L


def test_helical_tendon_under_displacement_against_scipy():
    b, phi, q = 0.004, -0.5, 4e-4
    F = np.array([0.0, 0.06, 0.0])
    twist = 2 * math.pi * 1.25 / L
    t = tr.Tendon.helical(b, phi, pitch=2 * math.pi / twist)
    sol = tr.solve(
        tr.Scene(tr.Robot(_ROD, [t]), displacement=[q], loads=[tr.PointLoad(L, force=tuple(F))])
    )
    assert sol.success
    p_ref, tau_ref = _reference(b, phi, twist, F, q=q)
    # as above; the tension is a shooting unknown of both (relative 1e-8)
    assert np.abs(sol.position[-1] - p_ref).max() < 1e-8 * L
    assert sol.tension[0] == pytest.approx(tau_ref, rel=1e-8)


@pytest.mark.parametrize("control", ["tension", "displacement"])
def test_helix_of_zero_turns_is_the_parallel_tendon(control):
    kw = dict(tension=[2.0]) if control == "tension" else dict(displacement=[3e-4])
    F = tr.PointLoad(L, force=(0.02, 0.03, 0.0))
    helix = tr.Scene(
        tr.Robot(_ROD, [tr.Tendon.helical(0.004, 0.4, turns=0.0, length=L)]), loads=[F], **kw
    )
    par = tr.Scene(tr.Robot(_ROD, [tr.Tendon(0.004, 0.4)]), loads=[F], **kw)
    a, b_ = tr.solve(helix), tr.solve(par)
    assert a.success and b_.success and a.formulation.n_routed_tendons == 1
    # the same equations through the routed code path: tol 1e-10 (scaled) apart at most
    assert np.abs(a.position[-1] - b_.position[-1]).max() < 1e-9 * L
    assert a.tension[0] == pytest.approx(b_.tension[0], rel=1e-8)


@pytest.mark.parametrize("kind", ["sampled", "disks", "function"])
def test_straight_path_is_the_linear_routing(kind):
    """A converging tendon given as samples of its straight path (5 knots: 4 breakpoints)."""
    b, a, phi = 0.005, -0.01, 0.7
    s = np.linspace(0.0, L, 5)
    d = np.array([math.cos(phi), math.sin(phi)])
    pts = (a * s + b)[:, None] * d
    if kind == "sampled":
        path = Path.sampled(s, pts)
    elif kind == "disks":
        path = Path.disks(s, pts)
    else:
        path = Path.function(lambda x: (a * x + b) * d, L, n=4)
    for kw in (dict(tension=[3.0]), dict(displacement=[2e-4])):
        lin = tr.solve(tr.Scene(tr.Robot(_ROD, [tr.Tendon(b, phi, slope=a)]), **kw))
        routed = tr.solve(tr.Scene(tr.Robot(_ROD, [tr.Tendon(path=path)]), **kw))
        assert routed.success and routed.formulation.n_segments == 4
        # the spline reproduces the line exactly; only the integration differs (tol 1e-10)
        assert np.abs(routed.position[-1] - lin.position[-1]).max() < 1e-9 * L
        assert routed.tension[0] == pytest.approx(lin.tension[0], rel=1e-8)


def test_function_path_of_a_helix_approaches_the_helix():
    """The spline through 65 samples of the helix: r'' to O(h^2), so the tip to ~1e-5."""
    b, phi, twist = 0.004, 0.2, 2 * math.pi / L
    path = Path.function(
        lambda s: b * np.array([math.cos(phi + twist * s), math.sin(phi + twist * s)]), L, n=64
    )
    F = tr.PointLoad(L, force=(0.03, 0.0, 0.0))
    a = tr.solve(tr.Scene(tr.Robot(_ROD, [tr.Tendon(path=path)]), tension=[2.0], loads=[F]))
    h = tr.solve(
        tr.Scene(
            tr.Robot(_ROD, [tr.Tendon.helical(b, phi, turns=1.0, length=L)]),
            tension=[2.0],
            loads=[F],
        )
    )
    assert a.success and h.success
    dev = np.abs(a.position[-1] - h.position[-1]).max()
    # interpolation error of r'' ~ (h twist)^2 / 12 relative, h = L/64: ~1e-3 of the tendon
    # load's effect (~1e-2 L here)
    assert dev < 1e-4 * L


def test_disk_routing_kinks_at_the_disks():
    """Straight pieces between holes on a helix: a piecewise path whose knots are
    breakpoints, and whose pulls balance the backbone at the base."""
    b, twist = 0.004, 2 * math.pi / L
    s = np.linspace(0.0, L, 9)
    pts = b * np.stack([np.cos(twist * s), np.sin(twist * s)], axis=1)
    path = Path.disks(s, pts)
    sol = tr.solve(tr.Scene(tr.Robot(_ROD, [tr.Tendon(path=path)]), tension=[2.0]))
    assert sol.success and sol.formulation.n_segments == 8
    # no external load: the base reaction of the whole section is zero, so the backbone
    # carries exactly minus the tendon's pull at s = 0: force tau t(0) with t along
    # w = e3 + u x r + r' (r' the first piece's chord slope, u = m_b / K at the base)
    u = sol.moment[0] / np.array([EI, EI, GJ])
    r0 = np.array([*pts[0], 0.0])
    w = np.array([0.0, 0.0, 1.0]) + np.cross(u, r0) + np.array([*(pts[1] - pts[0]) / s[1], 0.0])
    t0 = w / np.linalg.norm(w)
    assert np.abs(sol.force[0] + 2.0 * t0).max() < 1e-9 * 2.0  # tol 1e-10 scaled by EI/L^2
    assert np.abs(sol.moment[0] + 2.0 * np.cross(r0, t0)).max() < 1e-9 * 2.0 * L


def test_bad_routes_name_themselves():
    with pytest.raises(ValueError, match="turns= or pitch="):
        tr.Tendon.helical(0.004, turns=1.0, pitch=0.1, length=L)
    with pytest.raises(ValueError, match="increasing"):
        Path.sampled([0.0, 0.1, 0.1], np.zeros((3, 2)))
    with pytest.raises(ValueError, match="s\\[0\\] = 0"):
        Path.disks([0.01, 0.2], np.zeros((2, 2)))
    with pytest.raises(ValueError, match="path must span"):
        tr.Robot(_ROD, [tr.Tendon(path=Path.sampled([0.0, 0.1], [[0.004, 0], [0.004, 0]]))])
    with pytest.raises(ValueError, match="pretension"):
        tr.Robot(
            tr.Rod(L, EI=EI, GJ=GJ, EA=1e5, GA=1e5),
            [
                tr.Tendon.helical(0.004, 0.0, turns=1, length=L, pretension=1.0),
                tr.Tendon.helical(0.004, math.pi, turns=1, length=L, pretension=1.0),
            ],
        )


def test_plot_draws_helical_tendons_and_segment_joints():
    plt = pytest.importorskip("matplotlib.pyplot")
    import matplotlib

    matplotlib.use("Agg")
    from tendonrod import plot

    seg = tr.Rod.segmented(
        [
            tr.Rod(0.08, EI=0.1, GJ=0.07, kirchhoff=True, precurvature=(0.0, 3.0, 0.0)),
            tr.Rod(0.12, EI=EI, GJ=GJ, kirchhoff=True),
        ]
    )
    t = tr.Tendon.helical(0.004, 0.0, turns=1.0, length=L)
    sol = tr.solve(tr.Scene(tr.Robot(seg, [t]), tension=[1.0]))
    ax = plot.robot(sol, disks=0, loads=False)
    lines = ax.get_lines()
    # backbone, the tendon, the joint marker
    assert len(lines) == 3
    _, y, _ = lines[1].get_data_3d()
    # the helical tendon winds once around the backbone, which stays near y = 0 (a
    # planar precurvature, tension mostly in the x-z plane): it visits both sides in y
    assert np.ptp(y) > 1.5 * 0.004
    assert lines[2].get_marker() == "o"
    plt.close("all")


def test_scene_file_routing_keys():
    from tendonrod.scenefile import SceneFileError, parse_scene

    rod = {"length": L, "EI": EI, "GJ": GJ, "kirchhoff": True}
    doc = {
        "rod": rod,
        "tendon": [
            {"offset": 0.004, "routing": "helical", "turns": 1.0, "tension": 1.0},
            {
                "routing": "disks",
                "path": [[0.0, 0.0, 0.004], [0.1, -0.004, 0.0], [L, 0.0, -0.004]],
                "tension": 0.5,
            },
        ],
    }
    sc = parse_scene(doc).scene
    t0, t1 = sc.robot.tendons
    assert t0.twist == pytest.approx(2 * math.pi / L) and t1.path.kind == "disks"
    assert tr.solve(sc).success
    bad = {"rod": rod, "tendon": [{"offset": 0.004, "turns": 1.0, "tension": 1.0}]}
    with pytest.raises(SceneFileError, match=r"tendon\[0\]\.turns"):
        parse_scene(bad)
    bad = {"rod": rod, "tendon": [{"routing": "spline", "path": [[0.0, 0.0]], "tension": 1.0}]}
    with pytest.raises(SceneFileError, match=r"tendon\[0\]\.path"):
        parse_scene(bad)
    bad = {"rod": rod, "tendon": [{"offset": 0.004, "routing": "helical", "tension": 1.0}]}
    with pytest.raises(SceneFileError, match="turns, pitch"):
        parse_scene(bad)


def test_routed_segmented_scene_through_multiple_shooting_and_batch():
    """The sections and routes travel with every compiled copy: multiple shooting (its
    nodes), solve_batch (its own compile) and a rotated base give the same equilibrium."""
    seg = tr.Rod.segmented(
        [
            tr.Rod(0.08, EI=0.1, GJ=0.07, kirchhoff=True, precurvature=(0.0, 3.0, 0.0)),
            tr.Rod(0.12, EI=EI, GJ=GJ, kirchhoff=True),
        ]
    )
    tendons = [tr.Tendon.helical(0.004, 0.3, turns=1.0, length=L), tr.Tendon(0.004, math.pi)]
    sc = tr.Scene(
        tr.Robot(seg, tendons),
        displacement=[3e-4, -1e-4],
        loads=[tr.PointLoad(L, force=(0.02, 0.01, 0.0))],
    )
    a = tr.solve(sc)
    b = tr.solve(sc, options=tr.Options(shooting_segments=4))
    res = tr.solve_batch(sc, displacement=np.array([[3e-4, -1e-4]]))
    assert a.success and b.success and res.status[0] == 0
    # the same equations and tolerance (1e-10 scaled), other shooting formulations
    assert np.abs(a.position[-1] - b.position[-1]).max() < 1e-9 * L
    assert np.abs(res.tip_position[0] - a.position[-1]).max() < 1e-9 * L


def test_actuate_precurved_and_helical():
    """tr.actuate inside the shooting system: on an arc u* = (0, k*, 0) the tip angle
    theta needs q = L b (theta/L - k*) exactly; a helical robot's tip position from a
    forward solve gives back that solve's displacements."""
    ks, b = 3.0, 0.004
    rod = tr.Rod(L, EI=EI, GJ=GJ, kirchhoff=True, precurvature=(0.0, ks, 0.0))
    r = tr.actuate(tr.Scene(tr.Robot(rod, [tr.Tendon(b)]), displacement=[0.0]), tip_angle=1.0)
    assert r.success
    assert r.displacement[0] == pytest.approx(L * b * (1.0 / L - ks), rel=1e-9)  # tol 1e-10
    tendons = [tr.Tendon.helical(b, 0.0, turns=0.5, length=L), tr.Tendon(b, 2.0), tr.Tendon(b, 4.0)]
    robot = tr.Robot(rod, tendons)
    q = [2e-4, 1e-4, 3e-4]
    f = tr.solve(tr.Scene(robot, displacement=q))
    r2 = tr.actuate(tr.Scene(robot, displacement=[0.0] * 3), tip_position=tuple(f.position[-1]))
    assert r2.success
    # the target's residual and the solve's tolerance are both 1e-10 L in position; the
    # axial tip position moves by only ~(b theta)^2 per displacement, so the 3 x 3 map from
    # displacements to the tip is poorly conditioned (measured: 1e-6 relative in q)
    assert r2.displacement == pytest.approx(q, rel=1e-5)
