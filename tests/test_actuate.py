"""tr.actuate: the controls it returns reach the target when solved forward (a cold
tr.solve of the scene with them, to 1e-9 L and 1e-9 rad), the least change satisfies its
optimality conditions (checked with an independent central-difference linearisation),
least squares are stationary, and an unreachable target is reported, never raised.

Targets are made by forward solves at known controls wherever a target must be reachable
(so reachability is not an assumption of the test).  The residuals below are computed
here, independently of tendonrod's target code: angles by atan2 of the tip tangent,
directions by the angle between unit vectors, rotations by SciPy's rotation vector.
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import tendonrod as tr

# the acceptance of a reached target: 1e-9 of L and 1e-9 rad (the contract of tr.actuate); the
# iteration stops at 1e-10 and a cold forward solve differs from its warm one by about the
# solver's tolerance 1e-10, so 1e-9 leaves a margin of ~5
REPRO = 1e-9


def _rod(**kw):
    base = dict(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    base.update(kw)
    return tr.Rod(**base)


def _forward(scene, sol):
    """A cold solve of scene with the controls sol found (each tendon in its own kind)."""
    disp = [
        sol.displacement[i] if d is not None else None for i, d in enumerate(scene.displacement)
    ]
    ten = [sol.tension[i] if t is not None else None for i, t in enumerate(scene.tension)]
    return tr.solve(dataclasses.replace(scene, displacement=disp, tension=ten), strict=True)


def _angle_between(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return math.atan2(np.linalg.norm(np.cross(a, b)), a @ b)


# ----------------------------------------------------------------------------- square
@pytest.mark.parametrize("degrees", [45.0, 90.0, 200.0, -30.0])
def test_tip_angle_displacement_under_load(degrees):
    rod = _rod()
    robot = tr.Robot(
        rod, [tr.Tendon(offset=0.01, EA=3e3), tr.Tendon(offset=0.01, angle=math.pi, EA=3e3)]
    )
    load = tr.PointLoad(s=0.2, force=(-0.1, 0.0, -0.05))
    scene = tr.Scene(robot, displacement=[0.0, 0.0], loads=[load])
    theta = math.radians(degrees)
    sol = tr.actuate(scene, tip_angle=theta, tendons=[0 if degrees > 0 else 1])
    assert sol.success, sol.message
    assert sol.actuation.kind == "square" and sol.actuation.reached
    fwd = _forward(scene, sol)
    # unwrapped: a curl past 180 degrees reads past pi
    assert abs(fwd.tip_angle - theta) <= REPRO
    R = fwd.tip_rotation
    if abs(theta) < math.pi:
        assert abs(math.atan2(R[0, 2], R[2, 2]) - theta) <= REPRO


def test_tip_angle_tension_unloaded_matches_the_closed_form():
    # a tension-controlled parallel tendon on an unloaded robot bends it into a circle of
    # curvature tau r / EI: tau = theta EI / (r L) (eqs. 37-38, exact for the Cosserat model)
    rod = _rod()
    scene = tr.Scene(tr.Robot(rod, [tr.Tendon(offset=0.01)]), tension=[0.0])
    theta = 1.2
    sol = tr.actuate(scene, tip_angle=theta)
    assert sol.success, sol.message
    EI, L = rod.bending_stiffness, rod.length
    expect = float(tr.analytic.actuation_tension_for_angle(theta, L, EI, 0.0, 0.01))
    assert sol.tension[0] == pytest.approx(expect, rel=1e-9)
    assert abs(_forward(scene, sol).tip_angle - theta) <= REPRO


def four_tendon_robot(EA=4e3):
    rod = tr.Rod(length=0.25, diameter=1.2e-3, E=60e9, G=23e9)
    return tr.Robot(rod, [tr.Tendon(offset=0.008, angle=k * math.pi / 2, EA=EA) for k in range(4)])


def test_tip_direction_spatial_square_under_gravity():
    robot = four_tendon_robot()
    weight = tr.DistributedLoad(force=(0.0, 0.0, -0.6))
    goal = tr.solve(tr.Scene(robot, displacement=[0.004, 0.003, -0.002, -0.001], loads=[weight]))
    t_goal = goal.tip_rotation[:, 2]
    scene = tr.Scene(robot, displacement=[0.0, 0.0, 0.0, 0.0], loads=[weight])
    sol = tr.actuate(scene, tip_direction=t_goal, tendons=[0, 1])
    assert sol.success, sol.message
    assert sol.actuation.kind == "square"
    fwd = _forward(scene, sol)
    assert _angle_between(fwd.tip_rotation[:, 2], t_goal) <= REPRO


def test_tip_position_square_tension_controls():
    robot = four_tendon_robot()
    scene0 = tr.Scene(
        robot, tension=[0.0, 0.0, 0.0, 0.0], loads=[tr.PointLoad(s=0.25, force=(0, 0.05, 0))]
    )
    goal = tr.solve(dataclasses.replace(scene0, tension=[2.0, 1.0, 0.0, 0.5]))
    sol = tr.actuate(scene0, tip_position=goal.tip_position, tendons=[0, 1, 3])
    assert sol.success, sol.message
    fwd = _forward(scene0, sol)
    assert np.max(np.abs(fwd.tip_position - goal.tip_position)) <= REPRO * 0.25
    assert np.all(sol.tension >= 0.0)


def test_tip_pose_two_sections():
    """Six tendons, three ending at mid-length: a tip pose (6 components) is a square
    problem; the goal is a forward solve at other controls."""
    rod = tr.Rod(length=0.24, diameter=1.2e-3, E=60e9, G=23e9)
    tendons = [
        tr.Tendon(offset=0.008, angle=2 * math.pi * k / 3, EA=5e3, end=0.12) for k in range(3)
    ]
    tendons += [
        tr.Tendon(offset=0.008, angle=2 * math.pi * k / 3 + math.pi / 3, EA=5e3) for k in range(3)
    ]
    robot = tr.Robot(rod, tendons)
    goal = tr.solve(tr.Scene(robot, tension=[1.5, 0.2, 0.0, 0.0, 1.0, 0.3]))
    scene = tr.Scene(robot, tension=[0.5] * 6)
    pose = (goal.tip_position, goal.tip_rotation)
    sol = tr.actuate(scene, tip_pose=pose)
    assert sol.success, sol.message
    assert sol.actuation.kind == "square"
    fwd = _forward(scene, sol)
    assert np.max(np.abs(fwd.tip_position - goal.tip_position)) <= REPRO * 0.24
    rv = Rotation.from_matrix(fwd.tip_rotation @ goal.tip_rotation.T).as_rotvec()
    assert np.max(np.abs(rv)) <= REPRO


def test_tip_pose_with_helical_displacement_controls():
    """A tip pose is square and well posed with two sections of three helical tendons
    each (the first three end at mid-length; opposite hands): each section's tendons bend
    it two ways and twist it.  Steps on the linearisation recover the six displacements
    of a forward solve (the pose inside the shooting system is not tried: from the
    scene's state its Newton iteration converges erratically, bench/results/
    jacobian_actuate.md)."""
    rod = tr.Rod(length=0.24, diameter=1.2e-3, E=60e9, G=23e9)
    half = [
        tr.Tendon.helical(0.008, 2 * math.pi * k / 3, turns=0.5, length=0.12, end=0.12, EA=5e3)
        for k in range(3)
    ]
    full = [
        tr.Tendon.helical(0.008, 2 * math.pi * k / 3 + math.pi / 3, turns=-0.5, length=0.24, EA=5e3)
        for k in range(3)
    ]
    robot = tr.Robot(rod, half + full)
    load = tr.PointLoad(s=0.24, force=(0.0, 0.02, -0.03))
    q_goal = [1.5e-3, 5e-4, 0.0, 0.0, 1.2e-3, 4e-4]
    goal = tr.solve(tr.Scene(robot, displacement=q_goal, loads=[load]), strict=True)
    assert np.all(goal.tension > 0.0)  # every tendon taut: the pose fixes all six
    scene = tr.Scene(robot, displacement=[5e-4] * 6, loads=[load])
    sol = tr.actuate(scene, tip_pose=(goal.tip_position, goal.tip_rotation))
    assert sol.success, sol.message
    assert sol.actuation.kind == "square" and sol.actuation.route == "linearisation"
    fwd = _forward(scene, sol)
    assert np.max(np.abs(fwd.tip_position - goal.tip_position)) <= REPRO * 0.24
    rv = Rotation.from_matrix(fwd.tip_rotation @ goal.tip_rotation.T).as_rotvec()
    assert np.max(np.abs(rv)) <= REPRO
    # the pose met to 1e-10 pins displacements of ~1e-3 m (the tip turns ~1 rad per 1e-2
    # m of pull) to ~1e-12 m: measured 3e-12 m
    np.testing.assert_allclose(sol.displacement, q_goal, rtol=0, atol=1e-10)


# ----------------------------------------------------------------------------- minimum change
def _kkt(scene, sol, tendons=None, min_tension=0.0):
    """Check the least change's optimality conditions at sol with an independent
    linearisation (central differences): stationarity W^2 (c - c0) = A^T lam + T^T mu
    over the taut tendons, mu >= 0 where a tension sits at its floor, and feasibility."""
    nt = scene.robot.n_tendons
    idx = list(range(nt)) if tendons is None else list(tendons)
    disp = scene.displacement_controlled()
    rod = scene.robot.rod
    r = max(t.offset for t in scene.robot.tendons)
    scale = np.array([r if disp[i] else rod.bending_stiffness / (r * rod.length) for i in idx])
    c0 = np.array([scene.displacement[i] if disp[i] else scene.tension[i] for i in idx])
    c = np.array([sol.displacement[i] if disp[i] else sol.tension[i] for i in idx])
    # the tendons whose tension is held at a floor: those taut in the scene (min_tension),
    # and the actuated ones at their taut/slack switch (a least change puts a tendon that
    # would rather be slack exactly there: no tension, no slack)
    taut0 = tr.solve(scene).tension > 0
    at_floor = [
        i
        for i in range(nt)
        if (taut0[i] and sol.tension[i] <= min_tension + 1e-6)
        or (i in idx and disp[i] and sol.tension[i] <= 1e-6 and sol.slack[i] <= 1e-12)
    ]
    # a floor keeps its tendon on the taut side of the switch: the conditions involve that
    # side's derivatives (the slack side's of a tendon a hair slack would be zero)
    side = [1 if (i in at_floor and disp[i]) else 0 for i in range(nt)]
    jac = tr.jacobian(sol, method="central", load=False, side=side)
    t = sol.tip_rotation[:, 2]
    # the target tip_direction: 2 components of dt = dtheta x t, any basis normal to t
    e = np.eye(3)[int(np.argmin(np.abs(t)))]
    b1 = np.cross(t, e) / np.linalg.norm(np.cross(t, e))
    B = np.column_stack([b1, np.cross(t, b1)])
    A = (B.T @ np.cross(jac.actuation[3:].T, t).T)[:, idx] * scale
    grad = (c - c0) / scale  # of 1/2 |W (c - c0)|^2 in scaled units
    T = jac.tension[at_floor][:, idx] * scale
    # grad = A^T lam + T^T mu; the multipliers by least squares, then the fit checked
    M = np.vstack([A, T]).T
    y, *_ = np.linalg.lstsq(M, grad, rcond=None)
    resid = np.abs(M @ y - grad).max()
    mu = y[A.shape[0] :]
    return resid, mu, at_floor


def fig11c_locked_scene():
    rod = tr.Rod(length=0.1, diameter=1.04e-3, E=210e9, G=80e9, kirchhoff=True)
    EI, r = rod.bending_stiffness, 0.01
    tendons = [
        tr.Tendon(offset=r, angle=2 * math.pi * i / 3, EA=150.0 * EI / r**2) for i in range(3)
    ]
    return tr.Scene(
        tr.Robot(rod, tendons),
        displacement=[0.0, 0.0, 0.0],
        loads=[tr.PointLoad(s=0.1, force=(0.0, 0.5, 0.0))],
    )


@pytest.mark.parametrize("direction", [(1.0, 0.0, 0.0), (1.0, 0.0, 1.0), (0.3, 0.5, 1.0)])
def test_minimum_change_optimality(direction):
    scene = fig11c_locked_scene()
    sol = tr.actuate(scene, tip_direction=direction)
    assert sol.success, sol.message
    assert sol.actuation.kind == "minimum-change"
    fwd = _forward(scene, sol)
    assert _angle_between(fwd.tip_rotation[:, 2], direction) <= REPRO
    resid, mu, at_floor = _kkt(scene, sol)
    # stationarity to the accuracy of the stopping test (steps <= 1e-6 scaled) and of the
    # linearisation; multipliers of the tensions at their floor >= 0 (to that accuracy)
    assert resid <= 1e-6, (resid, sol.controls if hasattr(sol, "controls") else sol.actuation)
    assert np.all(mu >= -1e-6), (mu, at_floor)
    # the tendons taut in the scene stay taut (floor 0)
    taut0 = tr.solve(scene).tension > 0
    assert np.all(sol.tension[taut0] >= -1e-12)


def test_minimum_change_all_taut_is_stationary():
    """Co-contracted tendons that all stay taut: no tension floor is active, so the least
    change is a stationary point on the target's 1-d solution set (3 controls, 2
    components), where the stopping test's noise level matters."""
    scene = dataclasses.replace(fig11c_locked_scene(), displacement=[3e-4, 2e-4, 2.5e-4])
    goal = tr.solve(scene).tip_rotation[:, 2] + np.array([0.05, 0.02, 0.0])
    sol = tr.actuate(scene, tip_direction=goal)
    assert sol.success, sol.message
    assert sol.actuation.active == () and np.all(sol.tension > 1.0)
    assert _angle_between(_forward(scene, sol).tip_rotation[:, 2], goal) <= REPRO
    resid, mu, at_floor = _kkt(scene, sol)
    assert at_floor == []
    # the stopping test (1e-6 scaled) bounds the stationarity the forward-difference
    # linearisation sees; the independent central-difference one agrees to ~1e-7
    assert resid <= 1e-6, resid


def test_minimum_change_with_an_active_tension_floor():
    """Two pretensioned opposing tendons on an extensible backbone: bending toward one
    slackens the other; with min_tension it must keep that much, and the constraint is
    active at the optimum (a positive multiplier)."""
    rod = tr.Rod(length=0.2, diameter=1e-3, E=60e9, G=23e9)
    robot = tr.Robot(
        rod,
        [tr.Tendon(offset=0.01, angle=a, EA=2e3, pretension=3.0) for a in (0.0, math.pi)],
    )
    scene = tr.Scene(robot, displacement=[0.0, 0.0])
    theta = 0.8
    free = tr.actuate(scene, tip_angle=theta)
    assert free.success, free.message
    floor = float(free.tension[1]) + 0.5  # more than the free optimum keeps
    sol = tr.actuate(scene, tip_angle=theta, min_tension=floor)
    assert sol.success, sol.message
    assert sol.tension[1] == pytest.approx(floor, abs=1e-6)
    assert 1 in sol.actuation.active
    assert sol.actuation.tension_multipliers[1] > 0
    assert abs(_forward(scene, sol).tip_angle - theta) <= REPRO
    # more tension holds the same angle with more pull on both: a larger change
    dist = lambda s: np.sum(np.asarray(s.displacement) ** 2)  # noqa: E731
    assert dist(sol) > dist(free)


def test_minimum_change_leaves_unneeded_slack_tendons():
    rod = _rod()
    robot = tr.Robot(
        rod, [tr.Tendon(offset=0.01, EA=2e3), tr.Tendon(offset=0.01, angle=math.pi, EA=2e3)]
    )
    # the far tendon paid out by 2 cm: slack at the start, and still slack at the target
    # (bending by 0.6 rad toward +x lengthens its path by r theta = 6 mm only)
    scene = tr.Scene(
        robot, displacement=[0.0, -0.02], loads=[tr.PointLoad(s=0.2, force=(-0.1, 0, 0))]
    )
    sol = tr.actuate(scene, tip_angle=0.6)
    assert sol.success, sol.message
    # it is not needed to bend toward +x: untouched
    assert sol.displacement[1] == pytest.approx(-0.02, rel=1e-12) and sol.slack[1] > 0
    assert abs(_forward(scene, sol).tip_angle - 0.6) <= REPRO


# ----------------------------------------------------------------------------- least squares
def test_minimum_change_across_slack_tendons_under_weight():
    """Four tendons under their own weight, all at q = 0 (exactly at their switch): the tip
    position of the robot with tendon 0 pulled 3 mm and tendon 2 paid out 3 mm (reachable
    by construction) needs two tendons pulled and the others slack at the least change.
    Reached, and reproduced by a forward solve; the controls are the construction's, to
    the accuracy the target fixes them (a slack tendon's own control is free up to its
    switch: the least change holds it there)."""
    rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9)
    tendons = [tr.Tendon(offset=0.01, angle=i * math.pi / 2, EA=2e3) for i in range(4)]
    weight = tr.DistributedLoad(force=(0.0, 0.0, -0.5))
    scene = tr.Scene(tr.Robot(rod, tendons), displacement=[0.0] * 4, loads=[weight])
    goal = tr.solve(dataclasses.replace(scene, displacement=[3e-3, 0.0, -3e-3, 0.0]), strict=True)
    sol = tr.actuate(scene, tip_position=tuple(goal.tip_position))
    assert sol.success, sol.message
    fwd = _forward(scene, sol)
    assert np.max(np.abs(fwd.tip_position - goal.tip_position)) <= REPRO * 0.2
    # tendon 0 carries the goal's tension (1e-6 relative: the target tolerance 1e-10 L
    # through the tension's sensitivity to the tip position)
    assert sol.tension[0] == pytest.approx(goal.tension[0], rel=1e-6)


def test_the_two_routes_agree_on_a_square_target():
    """Two displacement controls for a tip direction: the augmented shooting system (the
    target inside the solve) and steps on the linearisation are independent routes to the
    same unique controls."""
    scene = fig11c_locked_scene()
    goal = tr.solve(dataclasses.replace(scene, displacement=[2e-3, -1e-3, 0.0]), strict=True)
    target = tuple(goal.tip_rotation[:, 2])
    aug = tr.actuate(scene, tip_direction=target, tendons=[0, 1])
    lin = tr.actuate(scene, tip_direction=target, tendons=[0, 1], method="linearisation")
    assert aug.success and lin.success, (aug.message, lin.message)
    assert aug.actuation.route == "augmented" and lin.actuation.route == "linearisation"
    # both reach the target to 1e-10 rad; the controls (~1e-3 m, ~1 rad per 1e-2 m) then
    # agree to ~1e-12 m: 1e-9 relative leaves a margin
    np.testing.assert_allclose(aug.actuation.controls, [2e-3, -1e-3], rtol=1e-9)
    np.testing.assert_allclose(lin.actuation.controls, [2e-3, -1e-3], rtol=1e-9)
    with pytest.raises(ValueError, match="method"):
        tr.actuate(scene, tip_direction=target, method="newton")


def test_core_target_refuses_what_it_cannot_solve():
    scene = fig11c_locked_scene()
    prob = tr.Problem(scene)
    prob.solve()
    c = prob._c
    for kind, values, tendons, what in (
        (1, [0.5], [0], "planar"),  # a tip angle on a spatial formulation
        (2, [1.0, 0.0, 1.0], [0], "components"),  # two components, one tendon
        (3, [0.0, 0.0, 0.1], [0, 1, 1], "twice"),
        (3, [0.0, 0.0, 0.1], [0, 1, 5], "tendon 5"),
        (2, [0.0, 0.0, 0.0], [0, 1], "zero"),
        (7, [0.0], [], "kind"),
    ):
        with pytest.raises(ValueError, match=what):
            c.set_target(kind, np.array(values, dtype=float), np.array(tendons, dtype=float))


def test_least_squares_is_stationary():
    """One tendon, a tip position off its reachable curve: the closest point."""
    rod = _rod()
    scene = tr.Scene(tr.Robot(rod, [tr.Tendon(offset=0.01)]), displacement=[0.0])
    sol = tr.actuate(scene, tip_position=(0.12, 0.0, 0.12))
    assert sol.success and sol.actuation.kind == "least-squares"
    assert not sol.actuation.reached and sol.actuation.distance > 1e-3
    # stationarity of 1/2 |r|^2: A^T r = 0, A from an independent linearisation
    jac = tr.jacobian(sol, method="central", load=False)
    r = (sol.tip_position - np.array([0.12, 0.0, 0.12]))[[0, 2]] / 0.2
    A = jac.actuation[[0, 2]][:, [0]] / 0.2
    assert abs((A.T @ r).item()) <= 1e-7 * np.linalg.norm(A) * np.linalg.norm(r)


# ----------------------------------------------------------------------------- unreachable
def test_unreachable_returns_the_closest_state():
    # a tension can only pull toward its side: -45 degrees is out of reach, the closest
    # reachable state is the robot with no tension
    rod = _rod()
    scene = tr.Scene(tr.Robot(rod, [tr.Tendon(offset=0.01)]), tension=[0.5])
    with pytest.warns(tr.ConvergenceWarning, match="not reached"):
        sol = tr.actuate(scene, tip_angle=-math.pi / 4)
    assert not sol.success
    assert sol.tension[0] == 0.0
    assert sol.actuation.distance == pytest.approx(math.pi / 4, abs=1e-9)
    with pytest.raises(tr.ConvergenceError, match="not reached"):
        tr.actuate(scene, tip_angle=-math.pi / 4, strict=True)


def test_a_scene_that_does_not_solve_is_reported():
    # opposing inextensible tendons on an inextensible backbone: no unique equilibrium
    rod = _rod()
    robot = tr.Robot(rod, [tr.Tendon(offset=0.01), tr.Tendon(offset=0.01, angle=math.pi)])
    scene = tr.Scene(robot, displacement=[0.0, 0.0])
    with pytest.warns(tr.ConvergenceWarning):
        sol = tr.actuate(scene, tip_angle=0.3)
    assert not sol.success and "did not solve" in sol.message


def test_bad_input_names_the_parameter():
    rod = _rod()
    planar = tr.Scene(tr.Robot(rod, [tr.Tendon(offset=0.01)]), displacement=[0.0])
    spatial = fig11c_locked_scene()
    cases = [
        (planar, {}, "exactly one target"),
        (planar, dict(tip_angle=0.1, tip_position=(0, 0, 0.2)), "exactly one target"),
        (spatial, dict(tip_angle=0.1), "tip_angle.*planar"),
        (planar, dict(tip_angle=float("nan")), "tip_angle"),
        (spatial, dict(tip_direction=(0, 0, 0)), "tip_direction"),
        (spatial, dict(tip_direction="up"), "tip_direction"),
        (spatial, dict(tip_position=(0, 0)), "tip_position"),
        (spatial, dict(tip_pose=(0, 0, 0.1)), "tip_pose"),
        (spatial, dict(tip_pose=((0, 0, 0.1), np.ones((3, 3)))), "rotation"),
        (spatial, dict(tip_direction=(1, 0, 0), tendons=[3]), "tendons"),
        (spatial, dict(tip_direction=(1, 0, 0), tendons=[0, 0]), "tendons"),
        (spatial, dict(tip_direction=(1, 0, 0), tendons=[]), "tendons"),
        (spatial, dict(tip_direction=(1, 0, 0), min_tension=-1.0), "min_tension"),
        (spatial, dict(tip_direction=(1, 0, 0), tol=0.0), "tol"),
        (spatial, dict(tip_direction=(1, 0, 0), max_iter=0), "max_iter"),
        ("scene", dict(tip_angle=0.1), "scene"),
    ]
    for scene, kw, match in cases:
        with pytest.raises(ValueError, match=match):
            tr.actuate(scene, **kw)
    with pytest.raises(ValueError, match="no tendons"):
        tr.actuate(tr.Scene(tr.Robot(rod, [])), tip_angle=0.1)


def test_result_record():
    rod = _rod()
    scene = tr.Scene(tr.Robot(rod, [tr.Tendon(offset=0.01)]), displacement=[0.0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a success warns nothing
        sol = tr.actuate(scene, tip_angle=0.5)
    rec = sol.actuation
    assert rec.target == {"tip_angle": 0.5} and rec.tendons == (0,)
    assert rec.controls.shape == (1,) and rec.controls[0] == sol.displacement[0]
    assert rec.residual.shape == (1,) and rec.distance <= 1e-10 and rec.reached
    assert rec.solves >= rec.iterations >= 1
    # the iterates are solved without a stability verdict; the state returned has one
    assert sol.stable is True and sol.options.accept_unstable is False
    # one displacement control for one component: solved inside the shooting system, with
    # no linearisation
    assert rec.route == "augmented" and rec.jacobians == 0
    # a tension control for the same target takes the linearisation's route
    ten = tr.actuate(dataclasses.replace(scene, displacement=[None], tension=[0.0]), tip_angle=0.5)
    assert ten.success and ten.actuation.route == "linearisation" and ten.actuation.jacobians >= 1
    assert "target reached" in rec.message


def test_a_target_held_only_by_an_unstable_equilibrium_is_not_reached():
    """A column at 1.5 times its Euler load with two opposing tension-controlled tendons:
    a straight tip (angle 0) is an equilibrium only with equal tensions, and unstable
    there (a tendon at a prescribed tension does not hold a bend back).  No bent state of
    a clamped column under this load turns its tip back to the axis (that needs the
    guided column's load, 4 P_E), so the target is reachable only by the unstable state:
    tr.actuate must not return it as a success, and returns the closest stable state."""
    rod = _rod()
    EI, L = rod.bending_stiffness, rod.length
    P_E = math.pi**2 * EI / (4 * L**2)
    robot = tr.Robot(rod, [tr.Tendon(offset=0.01), tr.Tendon(offset=0.01, angle=math.pi)])
    scene = tr.Scene(robot, tension=[1.0, 1.0], loads=[tr.PointLoad(s=L, force=(0, 0, -1.5 * P_E))])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tr.ConvergenceWarning)
        sol = tr.actuate(scene, tip_angle=0.0)
    assert not sol.success and not sol.actuation.reached
    # what is returned is a stable equilibrium, the buckled column (tip angle 1.72 rad)
    assert sol.stable is True
    assert sol.actuation.distance > 1.0
    # the unstable straight state does exist: with the verdict switched off, a cold solve
    # of the scene's own controls stops at it
    straight = tr.solve(scene, options=tr.Options(accept_unstable=True))
    assert straight.stable is False and abs(straight.tip_angle) < 1e-12


def test_tip_position_across_tendons_held_at_their_switch():
    """Fig. 11c (three tendons, the first retracted, locked, 0.5 N out of plane): a tip
    position reached with all three taut, from a path where two tendons sit at their
    taut/slack switch and the step would slacken them through the third (their taut-side
    derivatives then predict the wrong motion; the step is retaken on the slack side)."""
    rod = tr.Rod(length=0.1, diameter=1.04e-3, E=210e9, G=80e9, kirchhoff=True)
    EI, r = rod.bending_stiffness, 0.01
    tendons = [
        tr.Tendon(offset=r, angle=2 * math.pi * i / 3, EA=50.0 * 3 * EI / r**2) for i in range(3)
    ]
    q0 = [0.015812683023068652, -r * math.pi / 4, -r * math.pi / 4]  # bench/solve.py's
    scene = tr.Scene(
        tr.Robot(rod, tendons), displacement=q0, loads=[tr.PointLoad(s=0.1, force=(0, 0.5, 0))]
    )
    q_goal = [0.01603314, -0.0060875, -0.00978068]
    goal = tr.solve(dataclasses.replace(scene, displacement=q_goal)).tip_position
    sol = tr.actuate(scene, tip_position=goal)
    assert sol.success, sol.message
    fwd = _forward(scene, sol)
    # the target tolerance (1e-10 L) and the forward solve's own accuracy
    assert np.abs(fwd.tip_position - goal).max() <= 1e-9 * 0.1


def test_a_target_met_at_an_unaccepted_state_leads_with_the_reason():
    """The controls meet the target but the final solve does not accept the state (here:
    a column at 3 P_E pushed toward its unstable side, success=False): the verdict's
    reason comes first, never "target reached" before a failure."""
    from tendonrod.actuation import _finish

    rod = _rod()
    L = rod.length
    P = math.pi**2 * rod.bending_stiffness / (4 * L**2)
    scene = tr.Scene(
        tr.Robot(rod, [tr.Tendon(offset=0.01)]),
        displacement=[0.0],
        loads=[tr.PointLoad(s=L, force=(-1e-4, 0.0, -3 * P))],
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tr.ConvergenceWarning)
        sol = tr.solve(scene)
    assert not sol.success and "unstable" in sol.message, sol.message
    reason = sol.message
    report = dict(
        kind="square",
        tol=1e-10,
        target={"tip_angle": 0.0},
        tendons=(0,),
        controls=[0.0],
        residual=[1e-12],
        optimal=True,
        outcome="done",
        iterations=2,
        solves=3,
        jacobians=2,
    )
    with pytest.warns(tr.ConvergenceWarning) as rec:
        out = _finish(sol, report, strict=False)
    assert not out.success and out.actuation.reached
    assert out.message.startswith(f"tr.actuate: {reason}"), out.message
    assert "target reached" not in out.message, out.message
    assert str(rec[0].message) == out.message
