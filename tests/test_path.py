"""tr.path: the load path of a scene through limit and bifurcation points.

Independent answers: the Euler load pi^2 EI / 4 L^2 of the cantilever; the exact elastica
of the post-buckled cantilever (elliptic integrals); a limit point found by SciPy (an
adaptive Runge-Kutta shooting of the planar elastica, a root in the load and an
extremum along the branch: another integrator, another parametrisation); and plain
tr.solve of the scenes along a path.
"""

import math
import re

import numpy as np
import pytest
from scipy.special import ellipe, ellipk

import tendonrod as tr
from tendonrod.bench import references as refs

ROD = dict(length=0.25, diameter=1.2e-3, E=60e9, G=23e9, kirchhoff=True)


def column(force=(0.0, 0.0, 0.0)):
    rod = tr.Rod(**ROD)
    EI, L = rod.bending_stiffness, rod.length
    scene = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=L, force=force)])
    return scene, EI, L, math.pi**2 * EI / (4 * L**2)


def test_euler_load_is_a_bifurcation():
    """The straight cantilever under a growing compressive tip load: one bifurcation, at
    the Euler load to 1e-8 relative (measured 2e-14: the point is located again with the
    steps doubled until it moves < 1e-11), stable before it and unstable after; the
    branch followed through it stays straight."""
    scene, EI, L, Pe = column()
    p = tr.path(scene, "loads[0].force[2]", (0.0, -3.0 * Pe))
    assert p.success, p.message
    assert [sp.kind for sp in p.special_points] == ["bifurcation"]
    sp = p.special_points[0]
    assert abs(-sp.value / Pe - 1.0) <= 1e-8, sp.value / -Pe - 1.0
    assert abs(sp.margin) < 2e-3 * 2.5  # the margin's own accuracy (test_stability.py)
    before, after = slice(0, sp.index), slice(sp.index + 1, None)
    assert all(s is True for s in p.stable[before])
    assert all(s is False for s in p.stable[after])
    assert np.allclose(p.tip_position[:, :2], 0.0, atol=1e-12)  # the trivial branch
    assert p.value[-1] == -3.0 * Pe and p.kind[sp.index] == "bifurcation"


def _post_buckled(side):
    """switch=+-1: past the bifurcation the path follows the buckled branch, one side each.
    Exact elastica of the cantilever under a tip load P with tip rotation alpha (k =
    sin(alpha/2)): L sqrt(P/EI) = K(k), tip x = 2k/sqrt(P/EI), z = (2E(k) - K(k))/sqrt(P/EI).
    Tolerance 1e-8 relative on P and 1e-8 L on the tip (measured 1.4e-10 and 7e-11:
    the truncation tolerance tol = 1e-10 of every point)."""
    scene, EI, L, Pe = column()
    p = tr.path(scene, "loads[0].force[2]", (0.0, -3.0 * Pe), switch=side)
    assert p.success, p.message
    assert p.special_points[0].kind == "bifurcation"
    post = p.branch == 1
    assert post.sum() >= 10
    P = -p.value[post]
    d3 = p.tip_rotation[post][:, :, 2]  # the tip tangent, world
    alpha = np.arctan2(np.abs(d3[:, 0]), d3[:, 2])
    assert np.all(alpha > 0.0) and alpha.max() > 2.0  # the branch goes far
    k = np.sin(alpha / 2)
    lam = np.sqrt(P / EI)
    P_exact = EI * ellipk(k**2) ** 2 / L**2
    assert np.max(np.abs(P / P_exact - 1.0)) <= 1e-8
    x = p.tip_position[post][:, 0]
    assert np.all(np.sign(x) == np.sign(x[0]))  # one side
    assert np.max(np.abs(np.abs(x) - 2 * k / lam)) <= 1e-8 * L
    z_exact = (2 * ellipe(k**2) - ellipk(k**2)) / lam
    assert np.max(np.abs(p.tip_position[post][:, 2] - z_exact)) <= 1e-8 * L
    return x[0]


def test_post_buckled_branch_is_the_elastica():
    """Both sides of the bifurcation, each the exact elastica (_post_buckled), opposite."""
    assert np.sign(_post_buckled(1)) == -np.sign(_post_buckled(-1))


def test_limit_point_against_an_independent_elastica_solve():
    """The column buckled at P = 1.5 P_E, pushed back by a lateral tip force H: the planar
    branch folds at a limit point H* (it snaps through) and returns to the straight state
    at H = 0.  H* against SciPy's own shooting of the elastica (tendonrod.bench.references.elastica_limit_force) to 1e-8
    relative (measured 3e-15).  Past the fold one H carries two equilibria of the path."""
    scene, EI, L, Pe = column()
    P = 1.5 * Pe
    scene = tr.Scene(scene.robot, loads=[tr.PointLoad(s=L, force=(0.0, 0.0, -P))])
    x0 = tr.solve(scene).tip_position[0]
    assert abs(x0) > 0.1 * L  # buckled
    with pytest.warns(tr.ConvergenceWarning, match="tendonrod.path stopped early"):
        p = tr.path(scene, "loads[0].force[0]", (0.0, -math.copysign(0.5 * Pe, x0)))
    kinds = [sp.kind for sp in p.special_points]
    assert kinds == ["limit"], p
    lim = p.special_points[0]
    ref = refs.elastica_limit_force(P, EI, L) * math.copysign(1.0, x0)
    assert abs(lim.value / ref - 1.0) <= 1e-8, (lim.value, ref)
    # the branch turns back at the fold: t_lambda changes sign, the path returns to the
    # straight column at H = 0 (success False: it left the span at its start)
    assert not p.success and "returned to the start" in p.message
    assert abs(p.tip_position[-1, 0]) < 1e-9 * L and p.value[-1] == 0.0
    # two equilibria at H = H*/2: one on each side of the fold
    h = 0.5 * lim.value
    before = p.value[: lim.index + 1]
    after = p.value[lim.index :]

    def x_at(values, xs):  # values monotone on one side of the fold
        order = np.argsort(values)
        return np.interp(h, values[order], xs[order])

    xa = x_at(before, p.tip_position[: lim.index + 1, 0])
    xb = x_at(after, p.tip_position[lim.index :, 0])
    assert abs(xa - xb) > 0.05 * L


def test_path_points_are_solves():
    """Each point of a path in a tendon displacement is the equilibrium tr.solve reaches
    for that scene: tip within 1e-9 L (both converged to tol = 1e-10 and verified), the
    tension within 1e-8 relative."""
    from tendonrod.paper.robots import paper_rod_ivb

    rod = paper_rod_ivb()
    robot = tr.Robot(rod, [tr.Tendon(offset=0.01)])
    scene = tr.Scene(
        robot, displacement=[0.0], loads=[tr.PointLoad(s=rod.length, force=(0.3, 0.0, 0.0))]
    )
    p = tr.path(scene, "displacement[0]", (0.0, 0.01 * math.pi / 2))
    assert p.success, p.message
    assert len(p) >= 5 and p.value[-1] == 0.01 * math.pi / 2
    for i in range(0, len(p), max(1, len(p) // 4)):
        sol = tr.solve(p.scene_at(i), strict=True)
        assert np.max(np.abs(sol.tip_position - p.tip_position[i])) <= 1e-9 * rod.length
        assert np.allclose(sol.tension, p.tension[i], rtol=1e-8, atol=1e-10)
        assert p.stable[i] is sol.stable


def test_design_parameter_path():
    """A tendon's EA as the parameter: the end of the path is tr.solve's answer there."""
    from tendonrod.paper.robots import paper_rod_ivb

    rod = paper_rod_ivb()
    EI = rod.bending_stiffness
    robot = tr.Robot(rod, [tr.Tendon(offset=0.01, EA=1e3 * EI / 1e-4)])
    scene = tr.Scene(
        robot, displacement=[0.01], loads=[tr.PointLoad(s=rod.length, force=(0.0, 0.2, 0.0))]
    )
    p = tr.path(scene, "robot.tendons[0].EA", (1e3 * EI / 1e-4, 10 * EI / 1e-4))
    assert p.success, p.message
    end = tr.solve(p.scene_at(len(p) - 1), strict=True)
    assert np.max(np.abs(end.tip_position - p.tip_position[-1])) <= 1e-9 * rod.length


def test_bad_parameters_are_named():
    scene, EI, L, Pe = column()
    with pytest.raises(ValueError, match="scalar"):
        tr.path(scene, "loads[0].force", (0.0, 1.0))
    with pytest.raises(ValueError, match="structure"):
        tr.path(scene, "robot.rod.length", (0.25, 0.3))
    with pytest.raises(ValueError, match="has no field"):
        tr.path(scene, "loads[0].nothing", (0.0, 1.0))
    with pytest.raises(ValueError, match="span"):
        tr.path(scene, "loads[0].force[2]", (1.0, 1.0))
    with pytest.raises(ValueError, match="span"):
        tr.path(scene, "loads[0].force[2]", (0.0, math.nan))
    with pytest.raises(ValueError, match="switch"):
        tr.path(scene, "loads[0].force[2]", (0.0, 1.0), switch=2)
    with pytest.raises(ValueError, match="step"):
        tr.path(scene, "loads[0].force[2]", (0.0, 1.0), step=0.0)


def test_full_path_stops_honestly():
    scene, EI, L, Pe = column()
    with pytest.warns(tr.ConvergenceWarning, match="tendonrod.path stopped early"):
        p = tr.path(scene, "loads[0].force[2]", (0.0, -3.0 * Pe), max_points=5)
    assert not p.success and len(p) == 5 and "max_points" in p.message


def test_plot_path():
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scene, EI, L, Pe = column()
    P = 1.5 * Pe
    scene = tr.Scene(scene.robot, loads=[tr.PointLoad(s=L, force=(0.0, 0.0, -P))])
    x0 = tr.solve(scene).tip_position[0]
    with pytest.warns(tr.ConvergenceWarning, match="tendonrod.path stopped early"):
        p = tr.path(scene, "loads[0].force[0]", (0.0, -math.copysign(0.5 * Pe, x0)))
    fig, ax = plt.subplots()
    out = tr.plot.branch(p, "x", ax=ax, scale=EI / L**2, ylabel="H L²/EI")
    assert out is ax
    styles = {ln.get_linestyle() for ln in ax.lines}
    assert "--" in styles  # the unstable stretch
    assert any(ln.get_marker() == "o" for ln in ax.lines)  # the limit point
    plt.close(fig)


def _robot90():
    from tendonrod.bench.stress_cases import _fig11, one_tendon_scene

    p11, L, EI, r, fs = _fig11()
    return one_tendon_scene(p11, math.pi / 2), EI, r, fs


def _named(message):
    """The tendon, arc length [m], tension [N] and EI/r^2 [N] a path's message names (the
    wording of a stalled tr.solve, tr_watch.c)."""
    m = re.search(
        r"tendon (\d+) would pass the centre of curvature: .* at s = ([0-9.e+-]+) m, with "
        r"tension ([0-9.e+-]+) N against the limit EI/r\^2 = ([0-9.e+-]+) N",
        message,
    )
    assert m, message
    return int(m.group(1)), float(m.group(2)), float(m.group(3)), float(m.group(4))


def test_path_stops_where_the_tendon_reaches_ei_over_r2():
    """The 90 deg robot of Fig. 11 pushed by -x: the tendon tension climbs to EI/r^2, where
    the equations become singular (det J vanishes there, as at a bifurcation); the path
    ends at that point naming the tendon, the arc length, the tension and EI/r^2 as a
    stalled solve does, not with a bifurcation."""
    scene, EI, r, fs = _robot90()
    with pytest.warns(tr.ConvergenceWarning, match="tendonrod.path stopped early"):
        p = tr.path(scene, "loads[0].force[0]", (0.0, -60 * fs), max_step=1.0)
    assert not p.success and p.special_points == []
    assert p.message.startswith("the path ends at "), p.message
    i, s, tau, limit = _named(p.message)
    assert i == 0
    # the limit from the robot's data (4 significant digits printed)
    assert abs(limit - EI / r**2) < 1e-3 * EI / r**2
    # a moment-free tip with one parallel tendon: kappa(L) = tau r/EI, the largest
    # curvature, so the approach is at the tip (to the walk's L/32 resolution)
    L = scene.robot.rod.length
    assert abs(s - L) <= L / 32
    # there tau = EI/r^2 (printed to 4 significant digits); the last point carries it to
    # 1e-6 relative (measured 1.5e-8: the located zero of det J)
    assert abs(tau - EI / r**2) < 1e-3 * EI / r**2
    assert abs(p.tension[-1, 0] / (EI / r**2) - 1.0) < 1e-6


def test_path_stops_where_the_equations_are_singular():
    """The same robot pushed by +x: the bending gathers at the base until r kappa(0) = 1
    at F L^2/EI ~ 50 (the tendon would pass the centre of curvature there, at a tension
    far below EI/r^2); det J jumps sign there without vanishing, and the path ends naming
    the tendon at the base, its tension and EI/r^2, not with a bifurcation (the stress
    suite's 'snap near 58' was this point)."""
    scene, EI, r, fs = _robot90()
    with pytest.warns(tr.ConvergenceWarning, match="tendonrod.path stopped early"):
        p = tr.path(scene, "loads[0].force[0]", (0.0, 60 * fs), max_step=2.0)
    assert not p.success and p.special_points == []
    assert p.message.startswith("the path ends at ") and "singular" in p.message, p.message
    i, s, tau, limit = _named(p.message)
    assert i == 0
    # the base, to the walk's L/32 resolution
    assert s <= scene.robot.rod.length / 32
    # the limit from the robot's data; the tension the last point's (4 digits printed)
    assert abs(limit - EI / r**2) < 1e-3 * EI / r**2
    assert abs(tau - p.tension[-1, 0]) < 1e-3 * p.tension[-1, 0] and tau < 0.01 * limit
    # independently, moment balance about the base of the whole robot with the tendon
    # cut there (straight base, tip force F e_x at height z): EI kappa(0) = z F + r tau,
    # so r kappa(0) = 1 at the last point (measured 1 - 2.6e-8: the located jump)
    z, F = p.tip_position[-1, 2], p.value[-1]
    assert abs((z * F + r * p.tension[-1, 0]) * r / EI - 1.0) < 1e-6
    assert 49.0 < p.value[-1] / fs < 50.5


def test_cancel_stops_a_path():
    """A set Cancel token (what a worker thread polls) stops the path at once with
    KeyboardInterrupt, as it stops a solve (the C core polls it throughout)."""
    from tendonrod._interrupt import cancel_scope, new_token

    scene, EI, L, Pe = column()
    token = new_token()
    token.set()
    with cancel_scope(token), pytest.raises(KeyboardInterrupt):
        tr.path(scene, "loads[0].force[2]", (0.0, -3.0 * Pe), switch=1)


def test_raw_path_loop_does_not_leak():
    """1000 raw _core.path calls (each compiles a model, a workspace and the path's work
    arrays, each several KiB, and frees them), with a ValueError every tenth: resident
    memory flat within 4 MiB (catches a leak of >= 4.2 KiB per call), Python's allocated
    blocks within 200 (one leaked object per call would add 1000), the arguments'
    refcounts unchanged."""
    import gc
    import os
    import sys

    if not os.path.exists("/proc/self/statm") or "libasan" in os.environ.get("LD_PRELOAD", ""):
        pytest.skip("RSS from /proc/self/statm, not under ASan")
    from tendonrod.compiled import pack_scene

    scene, EI, L, Pe = column()
    rod, tend, loads, dist = pack_scene(scene)
    args = (rod, tend, loads, dist)
    before = [sys.getrefcount(a) for a in args]
    page = os.sysconf("SC_PAGE_SIZE")

    def rss():
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * page

    def loop(n):
        for i in range(n):
            if i % 10 == 9:
                with pytest.raises(ValueError):
                    tr._core.path(rod, tend, loads, dist, kind=-1, index=99, p0=0.0, p1=1.0)
                continue
            r = tr._core.path(
                rod, tend, loads, dist, kind=-1, index=2, p0=0.0, p1=-0.3 * Pe, nodes=2
            )
            assert r["status"] == 0

    loop(200)
    gc.collect()
    r0, b0 = rss(), sys.getallocatedblocks()
    loop(1000)
    gc.collect()
    assert rss() - r0 < 4 * 1024 * 1024
    assert sys.getallocatedblocks() - b0 < 200
    assert [sys.getrefcount(a) for a in args] == before


def test_a_path_point_exactly_at_the_bifurcation(rod):
    """The 0.2 m, 0.8 mm steel column: the refinement lands on the Euler load exactly,
    where the bordered Jacobian is singular to the last bit; that point is the bifurcation
    (to 1e-8 relative, measured 2e-14), and switching there follows the buckled branch."""
    Pe = math.pi**2 * rod.bending_stiffness / (4 * 0.2**2)
    scene = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=0.2, force=(0.0, 0.0, 0.0))])
    for side in (0, 1):
        p = tr.path(scene, "loads[0].force[2]", (0.0, -1.5 * Pe), switch=side)
        assert p.success, p.message
        (sp,) = p.special_points
        assert sp.kind == "bifurcation" and abs(-sp.value / Pe - 1.0) <= 1e-8
    assert (p.branch == 1).sum() > 0 and abs(p.tip_position[-1, 0]) > 0.1 * 0.2
