"""Masses per spacer disk (tendonrod.PointMass.disks, the scene file's [disks] table),
their drawing, and the benchmark scenes of robots as built: against the small-deflection
superposition of point loads, an independent SciPy shooting of the dead-load
cantilever, the exact global balance of a robot carrying only point masses, and the
work-precision and stress references."""

import math

import numpy as np
import pytest

import tendonrod as tr
from tendonrod.bench import references as refs
from tendonrod.routing import Path

G = 9.81
# base at p0, base z along world +x, base x straight down: a horizontal robot, gravity -z
P0 = np.array([0.05, -0.02, 0.3])
R_H = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])


def _horizontal(rod, loads):
    robot = tr.Robot(rod, [], base_position=P0, base_rotation=R_H)
    return tr.Scene(robot, loads=loads, gravity=(0.0, 0.0, -G))


def test_disk_masses_small_deflection_is_the_superposition_of_point_loads():
    # short steel rod: w L^3/EI = 1.8e-4 and sum P L^2/EI = 6e-4, so the nonlinear
    # correction to the linear sag is ~(6e-4)^2 relative
    rod = tr.Rod(length=0.05, diameter=2e-3, E=207e9, G=79.6e9, density=7800.0, kirchhoff=True)
    L, EI = rod.length, rod.bending_stiffness
    s = L * np.arange(1, 6) / 5
    m = np.array([1.0, 2.0, 1.0, 2.0, 4.0]) * 1e-3  # [kg], one per disk
    sol = tr.solve(_horizontal(rod, tr.PointMass.disks(s, m)))
    assert sol.success
    w = rod.mass_per_length * G
    P = m * G
    # Euler-Bernoulli: w L^4/8EI plus, per point load P at a, P a^2 (3L - a)/(6 EI)
    delta = w * L**4 / (8 * EI) + float(np.sum(P * s**2 * (3 * L - s) / (6 * EI)))
    sag = P0[2] - sol.tip_position[2]
    # 1e-6 relative: above the nonlinear correction (~4e-7) and the solver (1e-10)
    assert sag == pytest.approx(delta, rel=1e-6)
    # five point loads split the integration into six segments (the last disk is the tip)
    assert sol.formulation.n_segments == 5 and sol.formulation.mounted


def test_disk_masses_large_sag_against_independent_shooting():
    # a soft rod with 8 disks: w L^3/EI = 2.7, the disks weigh twice the rod
    rod = tr.Rod(length=0.05, diameter=2e-3, E=2e6, G=0.7e6, density=1100.0, kirchhoff=True)
    L = rod.length
    s = L * np.arange(1, 9) / 8
    m = 2.0 * rod.mass_per_length * L / 8
    sol = tr.solve(_horizontal(rod, tr.PointMass.disks(s, m)))
    assert sol.success
    h, v = refs.cantilever_dead_loads(
        L, rod.bending_stiffness, rod.mass_per_length * G, s, [m * G] * 8
    )
    assert v > 0.3 * L  # really large
    expected = P0 + np.array([h, 0.0, -v])
    # the reference shoots at rtol 1e-12, the core solves to 1e-10 (scaled): 1e-9 L
    np.testing.assert_allclose(sol.tip_position, expected, rtol=0, atol=1e-9 * L)


def test_global_balance_of_a_spatial_robot_carrying_only_disk_masses():
    # a precurved, weightless (no density) rod on a tilted base: the only external
    # loads are the disks' weights, so the base reaction is their sum and their
    # moment about the base, exactly (no integral to approximate)
    rod = tr.Rod(0.15, EI=0.02, GJ=0.015, kirchhoff=False, EA=1e4, GA=1e4,
                 precurvature=(3.0, -5.0, 1.0))  # fmt: skip
    c, sn = math.cos(0.4), math.sin(0.4)
    R0 = np.array([[c, 0.0, sn], [0.0, 1.0, 0.0], [-sn, 0.0, c]]) @ R_H
    robot = tr.Robot(rod, [], base_position=P0, base_rotation=R0)
    s = rod.length * np.arange(1, 7) / 6
    m = [3e-3, 1e-3, 4e-3, 1e-3, 5e-3, 9e-3]
    sol = tr.solve(tr.Scene(robot, loads=tr.PointMass.disks(s, m), gravity=(0.0, 0.0, -G)))
    assert sol.success and not sol.formulation.planar
    W = np.array([0.0, 0.0, -G]) * np.asarray(m)[:, None]
    pos = sol.at(s).position
    scale = float(np.abs(W).sum())
    # balance holds to the integrator's truncation error (~1e-12, DESIGN.md)
    np.testing.assert_allclose(sol.force[0], W.sum(axis=0), rtol=0, atol=1e-10 * scale)
    M = np.cross(pos - sol.position[0], W).sum(axis=0)
    np.testing.assert_allclose(sol.moment[0], M, rtol=0, atol=1e-10 * scale * rod.length)


def test_point_mass_disks_input():
    path = Path.disks([0.0, 0.05, 0.1, 0.2], [[0.01, 0.0]] * 4)
    ms = tr.PointMass.disks(path, 2e-3)
    assert [p.s for p in ms] == [0.05, 0.1, 0.2]  # the base hole at s = 0 left out
    assert all(p.mass == 2e-3 for p in ms)
    assert [p.mass for p in tr.PointMass.disks([0.1, 0.2], [1e-3, 2e-3])] == [1e-3, 2e-3]
    with pytest.raises(ValueError, match=r"mass must be one number or one per disk \(2\)"):
        tr.PointMass.disks([0.1, 0.2], [1e-3])
    with pytest.raises(ValueError, match=r"disk 1: PointMass.mass must be >= 0"):
        tr.PointMass.disks([0.1, 0.2], [1e-3, -1.0])
    with pytest.raises(ValueError, match=r"PointMass.disks: s must be a 1-D"):
        tr.PointMass.disks([], 1e-3)
    rod = tr.Rod(0.2, 1e-3, 200e9, 80e9)
    with pytest.raises(ValueError, match=r"Scene.loads\[1\].s must be in \[0, L"):
        tr.Scene(tr.Robot(rod, []), loads=tr.PointMass.disks([0.1, 0.3], 1e-3))


def test_scene_file_disks():
    from tendonrod.scenefile import SceneFileError, parse_scene

    base = {
        "gravity": [0.0, 0.0, -9.81],
        "rod": {"length": 0.2, "diameter": 1e-3, "E": 200e9, "G": 80e9},
    }
    spec = parse_scene({**base, "disks": {"count": 4, "mass": 2e-3}})
    assert spec.scene.loads == tr.PointMass.disks(0.2 * np.arange(1, 5) / 4, 2e-3)
    spec = parse_scene({**base, "disks": {"s": [0.1, 0.2], "mass": [1e-3, 3e-3]}})
    assert spec.scene.loads == tr.PointMass.disks([0.1, 0.2], [1e-3, 3e-3])
    for disks, key, words in [
        ({"count": 0, "mass": 1e-3}, "disks.count", "integer >= 1"),
        ({"count": 2.5, "mass": 1e-3}, "disks.count", "integer >= 1"),
        ({"s": [0.1, 0.3], "mass": 1e-3}, "disks.s[1]", "must lie on the rod"),
        ({"s": [0.1, "a"], "mass": 1e-3}, "disks.s[1]", "expected a number"),
        ({"count": 2}, "disks.mass", "missing"),
        ({"count": 2, "s": [0.1], "mass": 1e-3}, "disks", "exactly one of count"),
        ({"mass": 1e-3}, "disks", "exactly one of count"),
        ({"count": 2, "mass": [1e-3]}, "disks.mass", "1 or 2 masses"),
        ({"count": 2, "mass": [1e-3, "x"]}, "disks.mass[1]", "expected a number"),
        ({"count": 2, "mass": -1.0}, "disks", "PointMass.mass must be >= 0"),
        ({"count": 2, "mass": 1e-3, "radius": 0.01}, "disks.radius", "unknown key"),
    ]:
        with pytest.raises(SceneFileError) as exc:
            parse_scene({**base, "disks": disks})
        assert exc.value.key == key, (disks, exc.value)
        assert words in exc.value.problem, (disks, exc.value)


def test_plot_draws_point_masses_as_disks():
    plt = pytest.importorskip("matplotlib.pyplot")
    import matplotlib

    matplotlib.use("Agg")
    from tendonrod import plot

    rod = tr.Rod(0.2, 1e-3, 200e9, 80e9, density=7800.0)
    disks = tr.PointMass.disks([0.05, 0.1, 0.15, 0.2], [1e-3, 1e-3, 1e-3, 4e-3])
    F = tr.PointLoad(s=0.2, force=(0.05, 0.0, 0.0))
    sc = tr.Scene(tr.Robot(rod, [tr.Tendon(offset=0.01)]), displacement=[0.0],
                  loads=[*disks, F], gravity=(9.81, 0.0, 0.0))  # fmt: skip
    sol = tr.solve(sc)
    for planar in (True, False):
        ax = plot.robot(sol, disks=0, planar=planar, ax=None if not planar else plt.gca())
        brown = [ln for ln in ax.get_lines() if ln.get_color() == "tab:brown"]
        # per mass a disk (a line) and a dot
        assert len(brown) == 8
        dots = [ln.get_markersize() for ln in brown if ln.get_marker() == "o"]
        # dot area proportional to the mass: the 4x heavier disk's dot is 2x across
        assert max(dots) == pytest.approx(2 * min(dots))
        plt.close("all")
    # the tip force is still an arrow; the masses' weights are not
    ax = plot.robot(sol, disks=0, ax=plt.gca())
    assert len([c for c in ax.get_children() if type(c).__name__ == "Annotation"]) == 1
    plt.close("all")


def test_work_precision_scenes_of_robots_as_built_meet_their_references():
    from tendonrod.bench.work_precision import wp_scenes

    scs = {s.name: s for s in wp_scenes()}
    for name in ("helical", "precurved", "mounted"):
        sc = scs[name]
        sol = tr.solve(sc.scene)
        ref = sc.reference()
        # default options solve to 1e-10 (scaled) with the step verification near it;
        # the references are exact or at rtol 1e-12: 1e-9 of the tip's distance
        assert np.linalg.norm(sol.tip_position - ref) < 1e-9 * sc.scale(ref), name


@pytest.mark.parametrize(
    "name",
    [
        "asbuilt/precurved/u*=(0.0, 60.0, 0.0)/c=0.5EI/kirchhoff",
        "asbuilt/helical/turns=1.0/tension=5.0N",
        "asbuilt/mounted/wL3/EI=30/disks=10",
        "asbuilt/stepped-precurved-mounted/q=2mm/tau=1N",
    ],
)
def test_stress_cases_of_robots_as_built_verify(name):
    from tendonrod.bench.stress import all_stress_cases, run_case

    case = {c.name: c for c in all_stress_cases()}[name]
    rec = run_case(case)
    # verified: balance and refinement to 1e-6 (the suite's thresholds) and, where the
    # case has one, its independent check to 1e-6 L
    assert rec["outcome"] == "verified", rec
