"""Base pose, gravity, point masses: against closed forms, an independent collocation
elastica, global balance, and the rotated answer of a rotated base."""

import dataclasses
import math

import numpy as np
import pytest
from scipy.integrate import simpson, solve_bvp

import tendonrod as tr


def _rot_y(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _rot_z(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _rot_vec(w):
    """Rodrigues' formula: the rotation by |w| about w."""
    th = np.linalg.norm(w)
    k = np.asarray(w) / th
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    return np.eye(3) + math.sin(th) * K + (1.0 - math.cos(th)) * (K @ K)


# A horizontal cantilever: its axis along the horizontal unit vector `axis`, gravity -z.
_HEADING = 0.7
_AXIS = np.array([math.cos(_HEADING), math.sin(_HEADING), 0.0])
# base z -> _AXIS, base x -> straight down
_R_HORIZONTAL = _rot_z(_HEADING) @ _rot_y(math.pi / 2)
_P0 = np.array([0.05, -0.02, 0.3])
_G = (0.0, 0.0, -9.81)


def _horizontal(rod, masses=(), loads=()):
    robot = tr.Robot(rod, [], base_position=_P0, base_rotation=_R_HORIZONTAL)
    return tr.Scene(robot, loads=[*loads, *masses], gravity=_G)


def _elastica(L, EI, w, P, *, nodes=801):
    """Independent reference: a planar inextensible cantilever, clamped horizontal, under a
    uniform downward load w [N/m] and a downward tip force P [N], by collocation.  States
    along the arc: h (horizontal, along the axis), v (downward), theta (tangent angle from
    the axis toward down), m (bending moment).  The internal force is known in closed
    form, n(s) = (0, P + w (L - s)) (horizontal, downward), so
    m' = -(h' n_v - v' n_h) = -cos(theta) (P + w (L - s)), theta' = m / EI,
    with h = v = theta = 0 at the clamp and m(L) = 0."""

    def f(s, y):
        h, v, th, m = y
        nv = P + w * (L - s)
        return np.vstack([np.cos(th), np.sin(th), m / EI, -np.cos(th) * nv])

    def bc(ya, yb):
        return np.array([ya[0], ya[1], ya[2], yb[3]])

    s = np.linspace(0.0, L, nodes)
    sol = solve_bvp(f, bc, s, np.zeros((4, s.size)), tol=1e-11, max_nodes=200000)
    assert sol.success, sol.message
    return sol.sol(L)[:2]  # (h_L, v_L)


def test_horizontal_rod_own_weight_small_load_matches_w_L4_over_8EI():
    # a short steel rod: w L^3 / EI = 1.8e-4, so the large-deflection correction to the
    # linear tip deflection is ~(w L^3/EI)^2 ~ 3e-8 relative
    rod = tr.Rod(length=0.05, diameter=2e-3, E=207e9, G=79.6e9, density=7800.0, kirchhoff=True)
    sol = tr.solve(_horizontal(rod))
    assert sol.success
    w = rod.mass_per_length * 9.81
    EI = rod.bending_stiffness
    assert w * rod.length**3 / EI < 2e-4
    delta = w * rod.length**4 / (8 * EI)
    tip = sol.tip_position - _P0
    # sag downward; measured 1.7e-11 relative; 1e-6 bounds the nonlinear correction
    # (<= (w L^3/EI)^2 = 3e-8) and the solver tolerance (1e-10 of the scaled residual)
    assert -tip[2] == pytest.approx(delta, rel=1e-6)
    # and it stays in the vertical plane of the axis, to round-off of the rotation
    assert abs(np.cross(_AXIS, tip)[2]) <= 1e-15 * rod.length
    assert sol.formulation.planar  # gravity lies in the base frame's x-z plane
    assert sol.formulation.mounted and sol.formulation.distributed_load
    assert "mounted base" in repr(sol.formulation)


def test_horizontal_rod_large_sag_with_tip_mass_matches_collocation_elastica():
    # a soft rod: w L^3/EI = 2.7 and a tip mass with P L^2/EI = 1
    rod = tr.Rod(length=0.05, diameter=2e-3, E=2e6, G=0.7e6, density=1100.0, kirchhoff=True)
    mass = 6.4e-5
    sol = tr.solve(_horizontal(rod, masses=[tr.PointMass(s=0.05, mass=mass)]))
    assert sol.success
    w = rod.mass_per_length * 9.81
    h, v = _elastica(rod.length, rod.bending_stiffness, w, mass * 9.81)
    assert v > 0.2 * rod.length  # really large
    expected = _P0 + h * _AXIS - v * np.array([0.0, 0.0, 1.0])
    # measured 9e-13 L; both solvers run at ~1e-10 relative accuracy (collocation tol
    # 1e-11, the shooting tolerance 1e-10 on the scaled residual)
    np.testing.assert_allclose(sol.tip_position, expected, rtol=0, atol=1e-10 * rod.length)


def _spatial_scene(robot, R):
    """A spatial scene with tendons, point loads, a point mass, a distributed load and
    gravity, its world-frame loads the base-frame ones rotated by R."""
    return tr.Scene(
        robot,
        displacement=[0.002, None],
        tension=[None, 0.3],
        loads=[
            tr.PointLoad(s=0.12, force=R @ [0.1, -0.05, 0.02], moment=R @ [0.0, 0.001, 0.0]),
            tr.DistributedLoad(force=R @ [0.0, 0.3, 0.0]),
            tr.PointMass(s=0.2, mass=0.003),
            tr.PointMass(s=0.07, mass=0.002),
            tr.DistributedLoad(force=R @ [0.2, 0.0, -0.1], start=0.05, end=0.15),
        ],
        gravity=R @ [0.0, -3.0, -9.81],
    )


_ROD = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, density=7800.0)
_TENDONS = [tr.Tendon(offset=0.01, angle=0.4), tr.Tendon(offset=0.008, angle=2.0)]
_R = _rot_vec([0.3, -1.1, 0.7])
_PB = np.array([0.1, -0.2, 0.05])


@pytest.fixture(scope="module")
def pair():
    a = tr.solve(_spatial_scene(tr.Robot(_ROD, _TENDONS), np.eye(3)))
    robot = tr.Robot(_ROD, _TENDONS, base_position=_PB, base_rotation=_R)
    b = tr.solve(_spatial_scene(robot, _R))
    assert a.success and b.success
    return a, b


# The mounted scene solves the same base-frame problem from loads R^T (R F) that differ
# from F by round-off: measured differences 3e-17 m in position (L = 0.2 m), 2e-16 in
# rotation, 3e-16 relative in force and 3e-15 relative in tension; 1e-13 relative allows
# that round-off to be amplified through the Newton iterations by a condition of ~100.
_BITWISE_CLOSE = 1e-13


def test_rotated_base_gives_rotated_answer(pair):
    a, b = pair
    L = _ROD.length
    assert np.abs(b.tip_position - (_PB + _R @ a.tip_position)).max() <= _BITWISE_CLOSE * L
    assert np.abs(b.tip_rotation - _R @ a.tip_rotation).max() <= _BITWISE_CLOSE
    assert np.abs(b.position - (_PB + a.position @ _R.T)).max() <= _BITWISE_CLOSE * L
    assert np.abs(b.rotation - _R @ a.rotation).max() <= _BITWISE_CLOSE
    fs = np.abs(a.force).max()
    assert np.abs(b.force - a.force @ _R.T).max() <= _BITWISE_CLOSE * fs
    assert np.abs(b.moment - a.moment @ _R.T).max() <= _BITWISE_CLOSE * fs * L
    np.testing.assert_allclose(b.tension, a.tension, rtol=_BITWISE_CLOSE, atol=0)
    np.testing.assert_allclose(b.displacement, a.displacement, rtol=0, atol=_BITWISE_CLOSE * L)
    sa, sb = a.at([0.05, 0.15]), b.at([0.05, 0.15])
    assert np.abs(sb.position - (_PB + sa.position @ _R.T)).max() <= _BITWISE_CLOSE * L
    assert np.abs(sb.force - sa.force @ _R.T).max() <= _BITWISE_CLOSE * fs


def test_rotated_base_entry_points_agree(pair):
    a, b = pair
    # the compliance is a linearisation (finite differences of the shooting residual):
    # round-off in the loads moves it by ~1e-11 relative (measured 1.5e-11)
    T = np.kron(np.eye(2), _R)
    Ca, Cb = tr.compliance(a.scene), tr.compliance(b.scene)
    assert np.abs(Cb - T @ Ca @ T.T).max() <= 1e-9 * np.abs(Ca).max()
    # the linearisation: rows [dx, dtheta] and load columns rotated, tensions unchanged;
    # central differences of the residual: measured 2e-11 relative (actuation, load), 1e-10
    # (the EI column, a relative step in EI) (the default forward ones round to ~2e-9 of
    # the load block here, which would hide a frame slip of that size)
    ja = tr.jacobian(a, design=("EI",), method="central")
    jb = tr.jacobian(b, design=("EI",), method="central")
    for x, y in ((ja.actuation, jb.actuation), (ja.design, jb.design)):
        assert np.abs(y - T @ x).max() <= 1e-9 * np.abs(x).max()
    assert np.abs(jb.load - T @ ja.load @ T.T).max() <= 1e-9 * np.abs(ja.load).max()
    assert np.abs(jb.tension - ja.tension).max() <= 1e-9 * np.abs(ja.tension).max()
    # a compiled Problem and a batch run the same pipeline as tr.solve on the same scene
    prob = tr.Problem(b.scene)
    assert prob.formulation.mounted
    p = prob.solve()
    np.testing.assert_array_equal(p.tip_position, b.tip_position)
    np.testing.assert_array_equal(p.tip_rotation, b.tip_rotation)
    res = tr.solve_batch(b.scene, tension=[[0.3], [0.35]], exact=True)
    assert res.success.all()
    # same scene, one warm-start convention apart: to the solver tolerance
    np.testing.assert_allclose(res.tip_position[0], b.tip_position, rtol=0, atol=1e-9)
    # the second point: a batch varies world-frame loads, rotated in like the scene's
    # (point loads: the PointLoads, then the point masses' weights in their order)
    F = np.array([[ld.force for ld in b.scene.point_loads]] * 2)
    F[1, 0] *= 1.5
    res2 = tr.solve_batch(b.scene, forces=F, exact=True)
    assert res2.success.all()
    np.testing.assert_allclose(res2.tip_position[0], b.tip_position, rtol=0, atol=1e-9)
    c = tr.solve(
        tr.Scene(
            a.scene.robot,
            displacement=[0.002, None],
            tension=[None, 0.3],
            loads=[
                tr.PointLoad(
                    s=0.12, force=1.5 * np.array([0.1, -0.05, 0.02]), moment=[0.0, 0.001, 0.0]
                ),
                *a.scene.loads[1:],
            ],
            gravity=a.scene.gravity,
        )
    )
    np.testing.assert_allclose(res2.tip_position[1], _PB + _R @ c.tip_position, rtol=0, atol=1e-9)


def test_global_balance_with_masses_and_gravity(pair):
    _, b = pair
    scene = b.scene
    g = np.asarray(scene.gravity)
    L = _ROD.length
    s = np.linspace(0.0, L, 2001)
    st = b.at(s)
    w = _ROD.mass_per_length * g + np.asarray(scene.loads[1].force)
    # the external loads on the robot (backbone and tendons) ...
    F = L * w + sum(np.asarray(ld.force) for ld in scene.point_loads)
    # Simpson over 2001 nodes: error ~(L/2000)^4 x the fourth derivative, < 1e-15
    M = simpson(np.cross(st.position - _PB, w), x=s, axis=0)
    # the partial load on [0.05, 0.15], integrated on its own interval (its ends are kinks)
    part = scene.loads[-1]
    sp = np.linspace(part.start, part.end, 1001)
    F = F + (part.end - part.start) * np.asarray(part.force)
    M = M + simpson(np.cross(b.at(sp).position - _PB, part.force), x=sp, axis=0)
    for ld in scene.point_loads:
        M = M + np.cross(b.at(ld.s).position - _PB, ld.force) + np.asarray(ld.moment)
    # ... balance the base reaction: the backbone's n(0), m(0) and the tendons' pulls at
    # the base, tension along each tendon's tangent there (body frame: u x r + v with
    # u = m_b / (EI, EI, GJ), v = e3 + n_b / (GA, GA, EA); parallel tendons, r' = 0)
    R0 = st.rotation[0]
    nb, mb = R0.T @ st.force[0], R0.T @ st.moment[0]
    EI, GJ = _ROD.bending_stiffness, _ROD.torsional_stiffness
    EA, GA = _ROD.axial_stiffness, _ROD.shear_stiffness
    u = mb / np.array([EI, EI, GJ])
    v = np.array([0.0, 0.0, 1.0]) + nb / np.array([GA, GA, EA])
    n_base, m_base = st.force[0].copy(), st.moment[0].copy()
    for t, tau in zip(_TENDONS, b.tension):
        r = t.offset * np.array([math.cos(t.angle), math.sin(t.angle), 0.0])
        tw = np.cross(u, r) + v
        pull = tau * (R0 @ (tw / np.linalg.norm(tw)))
        n_base += pull
        m_base += np.cross(R0 @ r, pull)
    scale = np.abs(F).max()
    # balance holds to the integrator's truncation error (~1e-12, DESIGN.md)
    np.testing.assert_allclose(n_base, F, rtol=0, atol=1e-10 * scale)
    np.testing.assert_allclose(m_base, M, rtol=0, atol=1e-10 * scale * L)


def test_unmounted_defaults_are_untouched():
    robot = tr.Robot(_ROD, _TENDONS)
    assert not robot.mounted
    assert tr.Robot(_ROD, _TENDONS, base_position=(0, 0, 1e-3)).mounted
    # no gravity: a density and point masses add nothing
    sc = tr.Scene(robot, tension=[0.1, 0.2], loads=[tr.PointMass(s=0.1, mass=1.0)])
    assert sc.point_loads == ()
    assert not sc.distributed_force.any()


@pytest.mark.parametrize(
    "kwargs, match",
    [
        (dict(base_rotation=np.diag([1.0, 1.0, -1.0])), r"Robot\.base_rotation.*det \+1"),
        (
            dict(base_rotation=[[1, 0, 0], [0, 0.7071, -0.7071], [0, 0.7071, 0.7071]]),
            r"Robot\.base_rotation must be orthonormal",
        ),
        (dict(base_rotation=np.eye(2)), r"Robot\.base_rotation.*shape \(3, 3\)"),
        (
            dict(base_rotation=[[math.nan, 0, 0], [0, 1, 0], [0, 0, 1]]),
            r"Robot\.base_rotation must be finite",
        ),
        (dict(base_rotation="I"), r"Robot\.base_rotation must be a 3x3"),
        (dict(base_position=(0, 1)), r"Robot\.base_position"),
        (dict(base_position=(0, math.inf, 0)), r"Robot\.base_position must be finite"),
    ],
)
def test_base_pose_validation(kwargs, match):
    with pytest.raises(ValueError, match=match):
        tr.Robot(_ROD, [], **kwargs)


def test_mass_validation():
    with pytest.raises(ValueError, match=r"Rod\.density must be >= 0, got -1"):
        tr.Rod(length=0.2, diameter=1e-3, E=1e9, G=1e9, density=-1.0)
    with pytest.raises(ValueError, match=r"Rod\.density=7800\.0 needs a diameter"):
        tr.Rod(length=0.2, EI=1.0, GJ=1.0, kirchhoff=True, density=7800.0)
    with pytest.raises(ValueError, match=r"PointMass\.mass must be >= 0"):
        tr.PointMass(s=0.1, mass=-0.1)
    with pytest.raises(ValueError, match=r"Scene\.loads\[0\]\.s must be in \[0, L"):
        tr.Scene(tr.Robot(_ROD, []), loads=[tr.PointMass(s=0.3, mass=0.1)])
    with pytest.raises(ValueError, match=r"Scene\.gravity must be a 3-vector"):
        tr.Scene(tr.Robot(_ROD, []), gravity=9.81)


def test_actuate_on_a_mounted_robot_is_the_rotated_answer(pair):
    """tr.actuate takes world-frame targets on a mounted robot: the controls it finds are
    those of the unmounted robot for the target carried into the base frame, and a cold
    forward solve of the mounted scene with them meets the world-frame target."""
    a, b = pair
    goal = tr.solve(dataclasses.replace(a.scene, displacement=[0.004, None], tension=[None, 0.5]))
    t_base = goal.tip_rotation[:, 2]
    sa = tr.actuate(a.scene, tip_direction=t_base)
    sb = tr.actuate(b.scene, tip_direction=_R @ t_base)
    assert sa.success and sb.success, (sa.message, sb.message)
    # the two iterations see the same base-frame problem up to the loads' round-off
    # (3e-16 relative): controls ~1e-3 m and ~1 N agree to 1e-9 relative
    np.testing.assert_allclose(sb.actuation.controls, sa.actuation.controls, rtol=1e-9)
    fwd = tr.solve(
        dataclasses.replace(
            b.scene, displacement=[sb.displacement[0], None], tension=[None, sb.tension[1]]
        )
    )
    t = fwd.tip_rotation[:, 2]
    # reached to the contract of tr.actuate, 1e-9 rad (test_actuate.py)
    assert np.arctan2(np.linalg.norm(np.cross(t, _R @ t_base)), t @ (_R @ t_base)) <= 1e-9
    # both tendons displacement-controlled: the augmented shooting system, its world
    # target carried into the base frame (the core compares base-frame states)
    da = dataclasses.replace(a.scene, displacement=[0.002, 0.001], tension=[None, None])
    db = dataclasses.replace(b.scene, displacement=[0.002, 0.001], tension=[None, None])
    goal = tr.solve(dataclasses.replace(da, displacement=[0.004, 0.0]))
    pa = tr.actuate(da, tip_direction=goal.tip_rotation[:, 2])
    pb = tr.actuate(db, tip_direction=_R @ goal.tip_rotation[:, 2])
    assert pa.success and pb.success, (pa.message, pb.message)
    assert pb.actuation.route == "augmented"
    # displacements of ~1e-3 m (one at zero): 1e-12 m, the target's 1e-10 tolerance
    # times the ~1e-2 m per radian of a tendon's pull
    np.testing.assert_allclose(pb.displacement, pa.displacement, rtol=0, atol=1e-12)


def test_actuate_mounted_planar_tip_angle_and_augmented_route():
    """A horizontally mounted planar robot (base z along world x, base x up) under its
    own weight: the tip angle is measured in the base frame, and the augmented shooting
    system (world targets carried into the base frame) agrees with the unmounted robot
    under the rotated gravity."""
    rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, density=7800.0)
    tendons = [tr.Tendon(offset=0.01, EA=3e3), tr.Tendon(offset=0.01, angle=np.pi, EA=3e3)]
    R0 = np.array([[0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]])  # columns: base axes
    g = np.array([0.0, 0.0, -9.81])
    mounted = tr.Scene(
        tr.Robot(rod, tendons, base_position=(0.0, 0.0, 0.5), base_rotation=R0),
        displacement=[0.0, 0.0],
        gravity=g,
    )
    flat = tr.Scene(tr.Robot(rod, tendons), displacement=[0.0, 0.0], gravity=R0.T @ g)
    for kw in ({"tip_angle": 0.7}, {"tip_position": None}):
        if "tip_position" in kw:
            goal = tr.solve(dataclasses.replace(flat, displacement=[0.003, 0.0]))
            kw_flat = {"tip_position": goal.tip_position}
            kw_mnt = {"tip_position": (0.0, 0.0, 0.5) + R0 @ goal.tip_position}
        else:
            kw_flat = kw_mnt = kw
        sf = tr.actuate(flat, tendons=[0], **kw_flat) if "tip_angle" in kw else None
        sm = tr.actuate(mounted, tendons=[0], **kw_mnt) if "tip_angle" in kw else None
        if sf is None:
            # a planar position has two components: both tendons
            sf = tr.actuate(flat, **kw_flat)
            sm = tr.actuate(mounted, **kw_mnt)
        else:
            # one displacement control for the angle: solved inside the shooting system
            assert sm.actuation.route == "augmented"
        assert sf.success and sm.success, (sf.message, sm.message)
        # the same base-frame problem up to the gravity's round-off (~1e-16 relative): the
        # controls agree to what the target tolerance fixes, tol / sigma_min of the tip's
        # derivative by them (scaled by L): for the angle ~1e-10 / 100 m, for the position
        # ~1e-10 / 0.19 = 5e-10 m (both tendons taut: the tip's rows for a common pull
        # differ by the backbone's compression alone)
        np.testing.assert_allclose(sm.displacement, sf.displacement, rtol=0, atol=1e-9)
    assert sm.tip_position == pytest.approx((0.0, 0.0, 0.5) + R0 @ sf.tip_position, abs=1e-12)


def test_fit_on_mounted_robots_matches_the_unmounted_fit(pair):
    """tr.fit with world-frame markers on a mounted robot: the fitted EI equals the
    unmounted fit of the base-frame markers, and both recover the true value."""
    a, b = pair
    zs = [0.1, 0.2]

    def scaled(sc, k):
        rod = dataclasses.replace(sc.robot.rod, EI=k * _ROD.bending_stiffness)
        return dataclasses.replace(sc, robot=dataclasses.replace(sc.robot, rod=rod))

    meas_a = np.array([[tr.solve(a.scene).at(z).position for z in zs]])
    meas_b = np.array([[tr.solve(b.scene).at(z).position for z in zs]])
    fa = tr.fit([scaled(a.scene, 0.8)], meas_a, ["EI"], s=zs)
    fb = tr.fit([scaled(b.scene, 0.8)], meas_b, ["EI"], s=zs)
    assert fa.success and fb.success, (fa.message, fb.message)
    # noise-free markers: the truth back to the solver's tolerance amplified by the
    # fit's conditioning (1e-7, as in test_fit.py); the two fits agree to the same level
    assert fa.values[0] == pytest.approx(_ROD.bending_stiffness, rel=1e-7)
    assert fb.values[0] == pytest.approx(fa.values[0], rel=1e-7)


def test_scene_file_reads_base_gravity_density_and_masses():
    from tendonrod.scenefile import SceneFileError, parse_scene

    doc = {
        "gravity": [0.0, 0.0, -9.81],
        "rod": {"length": 0.2, "diameter": 8e-4, "E": 207e9, "G": 79.6e9, "density": 7800.0},
        "mass": [{"s": 0.1, "mass": 0.002}],
        "base": {"position": [0.0, 0.0, 1.0], "rotation": [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]},
    }
    sc = parse_scene(doc).scene
    assert sc.robot.rod.density == 7800.0 and sc.gravity == (0.0, 0.0, -9.81)
    assert sc.robot.base_position == (0.0, 0.0, 1.0)
    assert sc.point_loads[0].force == pytest.approx((0.0, 0.0, -0.002 * 9.81), rel=1e-15)
    bad = [
        ({**doc, "base": {"rotation": [[1, 0, 0], [0, 1, 0], [0, 0, -1]]}}, r"base: .*det \+1"),
        ({**doc, "base": {"rotation": [[1, 0, 0], [0, 1, 0]]}}, r"base\.rotation: expected"),
        ({**doc, "base": {"pose": 1}}, r"base\.pose: unknown key"),
        ({**doc, "mass": [{"s": 0.1}]}, r"mass\[0\]\.mass: missing"),
        ({**doc, "mass": [{"s": 0.3, "mass": 1.0}]}, r"mass\[0\]\.s: must lie on the rod"),
        ({**doc, "gravity": [0.0, -9.81]}, r"gravity: expected an array of 3"),
        ({**doc, "rod": {**doc["rod"], "density": "steel"}}, r"rod\.density: expected a number"),
    ]
    for d, match in bad:
        with pytest.raises(SceneFileError, match=match):
            parse_scene(d)
