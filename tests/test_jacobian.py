"""tr.jacobian and Problem.jacobian against central differences of full solves.

The reference derivatives come from two full solves at a tight tolerance (1e-13 scaled)
a small step either side of the parameter, each warm from the base solution: their
truncation error is O((h/scale)^2) ~ 1e-10 and their round-off ~1e-13 / (h/scale) ~ 1e-8
relative with the steps below (h/scale ~ 1e-5).  The linearisation under test uses the
default options.  Columns are compared in the scaled units [dx / L, dtheta] (a
position change measured in lengths of the rod, so that both halves of a column weigh
alike); the tolerance 1e-6 of the column's norm leaves a margin of ~100 over the
reference's error and of ~10 over the forward-difference linearisation's (the default:
~1e-7 at worst, a Cosserat rod's EA and GA; ~1e-8 elsewhere; see
test_at_switch_one_sided_taut_side for where it is not).
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np
import pytest

import tendonrod as tr

TIGHT = tr.Options(tol=1e-13)
RTOL = 1e-6  # see the module docstring


def _pose(sol, s):
    """[p (3), R (3x3)] of the backbone at s (the tip when s is L)."""
    L = sol.scene.robot.rod.length
    if abs(s - L) <= 1e-12 * L:
        return sol.tip_position, sol.tip_rotation
    st = sol.at(s)
    return st.position, st.rotation


def _fd(make, h, base, s, one_sided=False):
    """Central (or one-sided second-order, toward +h) difference of the pose at s and of
    the tensions, of full solves of make(delta) at the tight tolerance."""
    if one_sided:
        s1 = tr.solve(make(h), guess=base, options=TIGHT, strict=True)
        s2 = tr.solve(make(2 * h), guess=base, options=TIGHT, strict=True)
        p0, R0 = _pose(base, s)
        (p1, R1), (p2, R2) = _pose(s1, s), _pose(s2, s)
        dp = (-3 * p0 + 4 * p1 - p2) / (2 * h)
        dR = (-3 * R0 + 4 * R1 - R2) / (2 * h)
        dt = (-3 * base.tension + 4 * s1.tension - s2.tension) / (2 * h)
    else:
        sp = tr.solve(make(h), guess=base, options=TIGHT, strict=True)
        sm = tr.solve(make(-h), guess=base, options=TIGHT, strict=True)
        (pp, Rp), (pm, Rm) = _pose(sp, s), _pose(sm, s)
        R0 = _pose(base, s)[1]
        dp, dR, dt = (pp - pm) / (2 * h), (Rp - Rm) / (2 * h), (sp.tension - sm.tension) / (2 * h)
    W = dR @ R0.T
    dth = 0.5 * np.array([W[2, 1] - W[1, 2], W[0, 2] - W[2, 0], W[1, 0] - W[0, 1]])
    return np.r_[dp, dth], dt


def _close(col, ref, L, what, natural=0.0, rtol=RTOL):
    """col and ref agree to rtol of the larger of ref's norm and ``natural``, the size a
    derivative of this parameter has when it is not held back (for a derivative that
    vanishes, e.g. a tension pulling against a locked inextensible tendon)."""
    scale = np.r_[np.full(3, 1.0 / L), np.ones(3)]
    a, b = col * scale, ref * scale
    err = np.max(np.abs(a - b))
    assert err <= rtol * max(np.max(np.abs(b)), natural, 1e-300), (what, a, b, err)


def _with_value(scene, i, delta):
    disp, ten = list(scene.displacement), list(scene.tension)
    if disp[i] is not None:
        disp[i] += delta
    else:
        ten[i] += delta
    return dataclasses.replace(scene, displacement=disp, tension=ten)


def _control_scale(scene, i):
    """The solver's scale of tendon i's control value: its offset r [m] for a displacement,
    EI / (r L) [N] for a tension (either turns the tip by about a radian)."""
    t = scene.robot.tendons[i]
    if scene.displacement[i] is not None:
        return abs(t.offset)
    EI, L = scene.robot.rod.bending_stiffness, scene.robot.rod.length
    return EI / (abs(t.offset) * L)


def fig11c_scene():
    """Fig. 11(c)'s robot (three stretchable tendons at 120 deg), one paid out far enough
    to go slack, under an out-of-plane tip load: spatial, one slack tendon."""
    rod = tr.Rod(length=0.1, diameter=1.04e-3, E=210e9, G=80e9, kirchhoff=True)
    EI, r = rod.bending_stiffness, 0.01
    EA = 150.0 * EI / r**2
    tendons = [tr.Tendon(offset=r, angle=2 * math.pi * i / 3, EA=EA) for i in range(3)]
    return tr.Scene(
        tr.Robot(rod, tendons),
        displacement=[0.004, -0.0015, -0.0025],
        loads=[tr.PointLoad(s=0.1, force=(0.0, 0.5, 0.0))],
    )


def planar_mixed_scene():
    """Planar: a displacement-controlled inextensible tendon and a tension-controlled
    stretchable one on the other side, tip load down."""
    rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    tendons = [tr.Tendon(offset=0.01), tr.Tendon(offset=0.008, angle=math.pi, EA=2e3)]
    return tr.Scene(
        tr.Robot(rod, tendons),
        displacement=[0.008, None],
        tension=[None, 0.5],
        loads=[tr.PointLoad(s=0.2, force=(0.0, 0.0, -0.2))],
    )


def cosserat_midlength_scene():
    """A Cosserat rod with four tendons, two anchored at mid-length, mixed control, a
    distributed load and an oblique tip force: spatial, every feature at once."""
    rod = tr.Rod(length=0.2, diameter=1e-3, E=100e9, G=40e9)
    tendons = [
        tr.Tendon(offset=0.008, angle=0.0, EA=500.0),
        tr.Tendon(offset=0.008, angle=math.pi / 2, EA=500.0, end=0.12),
        tr.Tendon(offset=0.008, angle=math.pi, EA=500.0, end=0.12),
        tr.Tendon.converging(offset=0.008, angle=3 * math.pi / 2, length=0.2, EA=800.0),
    ]
    return tr.Scene(
        tr.Robot(rod, tendons),
        displacement=[0.003, None, -0.001, None],
        tension=[None, 1.0, None, 0.3],
        loads=[
            tr.DistributedLoad(force=(0.0, 0.0, -0.5)),
            tr.PointLoad(s=0.2, force=(0.1, 0.05, 0.0)),
        ],
    )


SCENES = {
    "fig11c": fig11c_scene,
    "planar_mixed": planar_mixed_scene,
    "cosserat_midlength": cosserat_midlength_scene,
}


@pytest.mark.parametrize("name", sorted(SCENES))
@pytest.mark.parametrize("method", ["forward", "central"])
def test_actuation_and_tension_against_full_solves(name, method):
    scene = SCENES[name]()
    L = scene.robot.rod.length
    base = tr.solve(scene, options=TIGHT, strict=True)
    s_list = [L, 0.12] if name == "cosserat_midlength" else [L]
    jac = tr.jacobian(tr.solve(scene, strict=True), s=s_list, method=method)
    assert jac.actuation.shape == (len(s_list), 6, scene.robot.n_tendons)
    assert not jac.at_switch.any()
    for i in range(scene.robot.n_tendons):
        h = 1e-5 * _control_scale(scene, i)
        for k, s in enumerate(s_list):
            ref, dt = _fd(lambda d: _with_value(scene, i, d), h, base, s)
            natural = 1.0 / _control_scale(scene, i)
            _close(jac.actuation[k][:, i], ref, L, (name, "tendon", i, "s", s), natural)
        # tensions [N] per unit control: relative to the column's largest entry (a
        # tension-controlled tendon's own entry is exactly 1)
        err = np.max(np.abs(jac.tension[:, i] - dt))
        natural = _control_scale(scene, 0) / _control_scale(scene, i)  # N per unit
        assert err <= RTOL * max(np.max(np.abs(dt)), natural), (name, i, jac.tension[:, i], dt)
    assert jac.control == tuple(
        "displacement" if c else "tension" for c in scene.displacement_controlled()
    )


def test_slack_tendon_has_no_effect_and_no_tension():
    scene = fig11c_scene()
    sol = tr.solve(scene, strict=True)
    assert sol.slack[1] > 0 and sol.tension[1] == 0.0
    jac = tr.jacobian(sol)
    # a slack tendon's displacement moves nothing and no tension follows it
    assert np.all(jac.actuation[:, 1] == 0.0)
    assert np.all(jac.tension[:, 1] == 0.0)
    assert np.all(jac.tension[1, :] == 0.0)


DESIGN = {
    "fig11c": ["EI", "GJ", "robot.tendons[0].EA", "tendons[2].EA", "tendons[0].offset"],
    "planar_mixed": ["robot.rod.EI", "tendons[1].EA", "tendons[0].offset", "tendons[0].slope"],
    "cosserat_midlength": ["EI", "EA", "GA", "tendons[1].EA", "tendons[0].slope"],
}


def _with_design(scene, path, delta):
    from tendonrod.linearization import design_parameter, design_value, with_design

    canon, _, _ = design_parameter(scene, path)
    return with_design(scene, {canon: design_value(scene, canon) + delta})


@pytest.mark.parametrize("name", sorted(SCENES))
def test_design_derivatives_against_full_solves(name):
    from tendonrod.linearization import design_parameter, design_value

    scene = SCENES[name]()
    L = scene.robot.rod.length
    base = tr.solve(scene, options=TIGHT, strict=True)
    jac = tr.jacobian(tr.solve(scene, strict=True), design=DESIGN[name])
    assert jac.design.shape == (6, len(DESIGN[name]))
    for j, path in enumerate(DESIGN[name]):
        canon = design_parameter(scene, path)[0]
        assert jac.design_names[j] == canon
        value = design_value(scene, canon)
        if canon in ("robot.rod.EA", "robot.rod.GA"):
            # a stiff backbone's strains n/EA ~ 1e-8 change by 1e-13 for a relative step
            # 1e-5 (the tight solves' tolerance): step its compliance c = 1/EA by 10 %
            # instead, on which the strains depend linearly (second-order terms of order
            # the strain change, 1e-9), and turn d/dc into d/dEA = -c^2 d/dc
            c = 1.0 / value
            ref, dt = _fd(
                lambda d: _with_design(scene, path, 1.0 / (c + d) - value), 0.1 * c, base, L
            )
            ref, dt = -ref * c * c, -dt * c * c
        else:
            # a relative step 1e-5 (an absolute one for a slope that may be 0)
            h = 1e-5 * (abs(value) if value != 0.0 else 1.0 / 100)
            ref, dt = _fd(lambda d: _with_design(scene, path, d), h, base, L)
        _close(jac.design[:, j], ref, L, (name, path))
        err = np.max(np.abs(jac.design_tension[:, j] - dt))
        assert err <= RTOL * max(np.max(np.abs(dt)), 1e-300) + 1e-12 * np.max(
            np.abs(jac.actuation)
        ), (name, path, jac.design_tension[:, j], dt)


def test_at_switch_one_sided_taut_side(rod):
    """The straight, unloaded robot with q = 0: every tendon exactly at its switch.  The
    derivatives given are the taut side's: pulling tendon 0 (the others stay slack)."""
    tendons = [tr.Tendon(offset=0.01, angle=a, EA=3e3) for a in (0.0, math.pi)]
    scene = tr.Scene(tr.Robot(rod, tendons), displacement=[0.0, 0.0])
    base = tr.solve(scene, options=TIGHT, strict=True)
    # central differences: the pair's common tension level (15 kN per m of pull) moves the
    # straight robot's pose by nothing, and the forward differences' rounding of the pose
    # (~1e-16 L / 5e-8 per scaled unknown) times that rate is ~1e-6 of a column here
    jac = tr.jacobian(tr.solve(scene, strict=True), method="central")
    assert jac.at_switch.tolist() == [True, True]
    h = 1e-5 * 0.01
    # pulling tendon 0 tightens it while tendon 1 (paid out relatively) goes slack: the
    # one-sided full-solve difference toward +q of the pair held taut is not this one,
    # so compare the whole taut-side linearisation with the pair pulled together (both
    # tighten, both stay taut): q0 = q1 = +h changes the tension level only
    ref, dt = _fd(
        lambda d: dataclasses.replace(scene, displacement=[d, d]), h, base, 0.2, one_sided=True
    )
    col = jac.actuation[:, 0] + jac.actuation[:, 1]
    _close(col, ref, 0.2, "pull both", natural=1.0 / 0.01)  # nothing moves: 0 against 1/r
    assert np.allclose(jac.tension.sum(axis=1), dt, rtol=1e-6), (jac.tension, dt)
    assert np.all(dt > 0)


@pytest.mark.parametrize("side", [1, -1])
def test_side_asked_at_the_switch(side, rod):
    """One tendon at q = 0 on the straight, unloaded robot: exactly at its switch.  The
    side asked for is given, and matches the one-sided full-solve difference toward it
    (pulling: the taut side bends the rod; paying out: the slack side moves nothing)."""
    scene = tr.Scene(tr.Robot(rod, [tr.Tendon(offset=0.01, EA=3e3)]), displacement=[0.0])
    base = tr.solve(scene, options=TIGHT, strict=True)
    jac = tr.jacobian(tr.solve(scene, strict=True), side=[side])
    assert jac.switch_side.tolist() == [side]
    h = side * 1e-5 * 0.01
    ref, dt = _fd(lambda d: _with_value(scene, 0, d), h, base, 0.2, one_sided=True)
    # the slack side's column vanishes: compare against the 1/r = 100 rad/m of the taut one
    _close(jac.actuation[:, 0], ref, 0.2, f"side {side}", natural=1.0 / 0.01)
    # tension per unit q: 1e-6 of the tendon's own stiffness EA / L [N/m] (0 on the slack side)
    assert np.allclose(jac.tension[0, 0], dt[0], rtol=1e-6, atol=1e-6 * 3e3 / 0.2)
    with pytest.raises(ValueError, match="side"):
        tr.jacobian(base, side=[2])


def test_tension_controlled_at_zero_is_flagged_and_one_sided(rod):
    scene = tr.Scene(tr.Robot(rod, [tr.Tendon(offset=0.01)]), tension=[0.0])
    base = tr.solve(scene, options=TIGHT, strict=True)
    jac = tr.jacobian(tr.solve(scene, strict=True))
    assert jac.at_switch.tolist() == [True]
    h = 1e-5 * rod.bending_stiffness / (0.01 * 0.2)
    ref, _ = _fd(lambda d: _with_value(scene, 0, d), h, base, 0.2, one_sided=True)
    _close(jac.actuation[:, 0], ref, 0.2, "tension from 0")


def test_load_block_is_the_compliance():
    for make in (fig11c_scene, planar_mixed_scene):
        scene = make()
        sol = tr.solve(scene, strict=True)
        C = tr.compliance(scene, guess=sol)
        central = tr.jacobian(sol, method="central").load
        forward = tr.jacobian(sol).load
        scale = np.max(np.abs(C))
        # the same routine at states that agree to the solver's tolerance (the compliance
        # solves the spatial formulation again from sol): central differences agree to
        # their accuracy ~1e-10, forward ones to theirs ~1e-8
        assert np.max(np.abs(central - C)) <= 1e-8 * scale
        assert np.max(np.abs(forward - C)) <= 1e-6 * scale


def test_load_block_at_interior_points_and_without():
    scene = cosserat_midlength_scene()
    sol = tr.solve(scene, strict=True)
    jac = tr.jacobian(sol, s=[0.05, 0.12, 0.2], method="central")
    for k, s in enumerate((0.05, 0.12, 0.2)):
        C = tr.compliance(scene, s=s, guess=sol)
        assert np.max(np.abs(jac.load[k] - C)) <= 1e-8 * np.max(np.abs(C)), s
    assert tr.jacobian(sol, load=False).load is None


def test_problem_jacobian_reuses_the_workspace():
    scene = fig11c_scene()
    prob = tr.Problem(scene)
    sol = prob.solve()
    jac = prob.jacobian(design=["EI"])
    ref = tr.jacobian(sol, design=["EI"])
    # the state of sol in both: bitwise the same numbers
    assert np.array_equal(jac.actuation, ref.actuation)
    assert np.array_equal(jac.design, ref.design)
    assert np.array_equal(jac.load, ref.load)
    assert jac.solution is sol
    # the linearisation leaves the warm state alone: the next warm solve is bitwise the
    # one without it
    nxt = dataclasses.replace(scene, displacement=[0.0041, -0.0015, -0.0025])
    other = tr.Problem(scene)
    other.solve()
    a, b = prob.solve(nxt), other.solve(nxt)
    assert np.array_equal(a.unknowns, b.unknowns) and a.nfev == b.nfev


def test_planar_problem_gives_in_plane_derivatives():
    scene = planar_mixed_scene()
    jac = tr.Problem(scene)
    jac.solve()
    J = jac.jacobian()
    assert np.all(J.actuation[[1, 3, 5]] == 0.0)
    assert J.load.shape == (6, 6) and J.load[1, 1] > 0  # out of plane from the spatial form


def test_tip_angle_of_planar_solutions_is_unwrapped(rod):
    robot = tr.Robot(rod, [tr.Tendon(offset=0.01)])
    # a circle: tip angle q / r; 0.05 m retracted curls the rod through 5 rad > pi
    sol = tr.solve(tr.Scene(robot, displacement=[0.05]), strict=True)
    assert sol.tip_angle == pytest.approx(5.0, rel=1e-9)
    spatial = tr.solve(tr.Scene(robot, displacement=[0.01]), options=tr.Options(force_spatial=True))
    assert math.isnan(spatial.tip_angle)


def test_bad_input_names_the_parameter():
    scene = fig11c_scene()
    sol = tr.solve(scene, strict=True)
    with pytest.raises(ValueError, match="design parameter 'tendons\\[5\\].EA'"):
        tr.jacobian(sol, design=["tendons[5].EA"])
    with pytest.raises(ValueError, match="design parameter 'EA'.*Kirchhoff"):
        tr.jacobian(sol, design=["EA"])
    with pytest.raises(ValueError, match="design parameter 'colour'"):
        tr.jacobian(sol, design=["colour"])
    with pytest.raises(ValueError, match="twice"):
        tr.jacobian(sol, design=["EI", "robot.rod.EI"])
    with pytest.raises(ValueError, match="method"):
        tr.jacobian(sol, method="complex-step")
    with pytest.raises(ValueError, match="s must be"):
        tr.jacobian(sol, s=0.5)
    with pytest.raises(ValueError, match="s must be"):
        tr.jacobian(sol, s=[[0.05]])
    with pytest.raises(ValueError, match="scene_or_solution"):
        tr.jacobian("scene")
    inext = tr.Scene(tr.Robot(scene.robot.rod, [tr.Tendon(offset=0.01)]), displacement=[0.001])
    with pytest.raises(ValueError, match="inextensible"):
        tr.jacobian(inext, design=["tendons[0].EA"])
    pre = tr.Scene(
        tr.Robot(
            tr.Rod(length=0.2, diameter=1e-3, E=100e9, G=40e9),
            [tr.Tendon(offset=0.01, angle=a, EA=1e3, pretension=2.0) for a in (0, math.pi)],
        ),
        displacement=[0.0, 0.0],
    )
    with pytest.raises(ValueError, match="pretensioned"):
        tr.jacobian(pre, design=["tendons[0].offset"])
    # the rest of a pretensioned set's design is fine
    tr.jacobian(pre, design=["tendons[0].EA", "EI"])


def test_unconverged_is_refused():
    scene = fig11c_scene()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tr.ConvergenceWarning)
        bad = tr.solve(scene, options=tr.Options(max_iter=1, continuation=False))
    assert not bad.success
    with pytest.raises(ValueError, match="did not converge"):
        tr.jacobian(bad)
    opts = tr.Options(max_iter=1, continuation=False)
    with pytest.raises(tr.ConvergenceError, match="the scene did not solve"):
        tr.jacobian(scene, options=opts, strict=True)
    # the failure rule's default: a warning and a result that says so, its numbers NaN
    with pytest.warns(tr.ConvergenceWarning, match="the scene did not solve"):
        J = tr.jacobian(scene, options=opts, design=["EI"])
    assert not J.success and J.status < 0 and "did not solve" in J.message
    assert J.actuation.shape == (6, 3) and np.isnan(J.actuation).all()
    assert J.load.shape == (6, 6) and J.design.shape == (6, 1)
    with pytest.raises(RuntimeError, match="successful solve first"):
        tr.Problem(scene).jacobian()


def test_squared_slack_model_gives_the_same_derivatives(rod):
    """The paper's squared slack variable (tension and slack flat at the switch) and the
    linear one describe one model: the same derivatives, at the switch too (where the
    squared variable is differentiated through gamma |gamma|)."""
    robot = tr.Robot(rod, [tr.Tendon(offset=0.01, EA=3e3)])
    for q in (0.0, 0.004):
        scene = tr.Scene(robot, displacement=[q], loads=[tr.PointLoad(s=0.2, force=(0.1, 0, 0))])
        lin = tr.jacobian(scene)
        sq = tr.jacobian(scene, options=tr.Options(slack_model="squared"))
        assert lin.switch_side.tolist() == sq.switch_side.tolist()
        # two solves that agree to their tolerance 1e-10, linearised to ~1e-10 each
        assert np.allclose(sq.actuation, lin.actuation, rtol=1e-7, atol=1e-7)
        assert np.allclose(sq.tension, lin.tension, rtol=1e-7)


def test_taut_side_singular_falls_back_to_the_slack_side():
    """Two inextensible tendons on one path, both exactly at the switch: held taut they
    share a tension they cannot split (a singular Jacobian), so the slack side is given:
    paying out moves nothing and no tension follows."""
    rod = tr.Rod(length=0.2, diameter=1e-3, E=100e9, G=40e9)
    robot = tr.Robot(rod, [tr.Tendon(offset=0.01), tr.Tendon(offset=0.01)])
    sol = tr.solve(tr.Scene(robot, displacement=[0.0, 0.0]), strict=True)
    jac = tr.jacobian(sol)
    assert jac.at_switch.tolist() == [True, True]
    assert jac.switch_side.tolist() == [-1, -1]
    # nothing moves: 0 to round-off against the 1/r = 100 rad/m a taut tendon would give
    assert np.max(np.abs(jac.actuation)) <= 1e-8 * 100 and np.all(jac.tension == 0.0)
