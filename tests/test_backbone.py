"""Precurved and segmented backbones (tendonrod.backbone, csrc/tr_backbone.c) against
exact answers: constant-curvature shapes (circles, helices) under end moments and
tendon tensions, the stepped cantilever's small-deflection formula, and the balance of
a segment joint."""

import math

import numpy as np
import pytest

import tendonrod as tr

EI, GJ = 0.05, 0.035  # [N m^2]
L = 0.2  # [m]


def _exp_pose(u, L):
    """Tip position and rotation of a rod with constant body curvature u from the clamped
    base (p' = R e3, R' = R u^): Rodrigues' formula and its integral."""
    u = np.asarray(u, float)
    w = np.linalg.norm(u)
    if w == 0.0:
        return np.array([0.0, 0.0, L]), np.eye(3)
    k = u / w
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    R = np.eye(3) + math.sin(w * L) * K + (1 - math.cos(w * L)) * K @ K
    e3 = np.array([0.0, 0.0, 1.0])
    p = (
        e3 * math.sin(w * L) / w
        + np.cross(k, e3) * (1 - math.cos(w * L)) / w
        + k * k[2] * (L - math.sin(w * L) / w)
    )
    return p, R


def test_unloaded_precurved_rod_is_its_helix():
    us = (1.5, 4.0, 2.5)
    rod = tr.Rod(L, EI=EI, GJ=GJ, kirchhoff=True, precurvature=us)
    sol = tr.solve(tr.Scene(tr.Robot(rod)))
    assert sol.success and sol.formulation.precurved and not sol.formulation.planar
    p, R = _exp_pose(us, L)
    # zero unknowns: only the integration's truncation, which the step verification holds
    # near tol = 1e-10 (scaled by L), with a factor 10 of room
    assert np.abs(sol.position[-1] - p).max() < 1e-9 * L
    assert np.abs(sol.rotation[-1] - R).max() < 1e-9


@pytest.mark.parametrize("kirchhoff", [True, False])
def test_precurved_helix_under_end_moment(kirchhoff):
    """A world tip moment M = c u along the deformed curvature keeps u constant:
    u_i = u*_i / (1 - c / K_i) with K = (EI, EI, GJ), the exact helix exp(s u^)."""
    us = np.array([1.0, 3.0, 2.0])
    c = 0.004  # [N m / (1/m)]
    K = np.array([EI, EI, GJ])
    u = us / (1.0 - c / K)
    kw = dict(kirchhoff=True) if kirchhoff else dict(EA=1e4, GA=1e4)
    rod = tr.Rod(L, EI=EI, GJ=GJ, precurvature=tuple(us), **kw)
    sc = tr.Scene(tr.Robot(rod), loads=[tr.PointLoad(L, moment=tuple(c * u))])
    sol = tr.solve(sc)
    assert sol.success
    p, R = _exp_pose(u, L)
    # no force anywhere, so the Cosserat rod neither shears nor stretches: both exact to
    # the solver's tolerance (1e-10 scaled) times the conditioning (~10)
    assert np.abs(sol.position[-1] - p).max() < 1e-9 * L
    assert np.abs(sol.rotation[-1] - R).max() < 1e-9
    assert sol.stable is None and "not tested" in sol.stability_reason


@pytest.mark.parametrize("kirchhoff", [True, False])
def test_precurved_arc_under_tendon_tension(kirchhoff):
    """A parallel tendon at offset b in the bending plane of an arc u* = (0, k*, 0): the
    whole section carries no load, so m_b = tau b e2 and n_b = -tau e3; the shape is the
    circle of curvature k* + tau b / EI traversed at speed 1 - tau/EA."""
    ks, b, tau, EA = 4.0, 0.004, 3.0, 2e3
    kw = dict(kirchhoff=True) if kirchhoff else dict(EA=EA, GA=1e3)
    rod = tr.Rod(L, EI=EI, GJ=GJ, precurvature=(0.0, ks, 0.0), **kw)
    sc = tr.Scene(tr.Robot(rod, [tr.Tendon(offset=b)]), tension=[tau])
    sol = tr.solve(sc)
    assert sol.success and sol.formulation.planar
    k = ks + tau * b / EI
    v3 = 1.0 if kirchhoff else 1.0 - tau / EA
    p, _ = _exp_pose((0.0, k, 0.0), L)
    p_exact = p * v3 if kirchhoff else _exp_pose((0.0, k, 0.0), L)[0]
    if not kirchhoff:
        # arc length of the deformed centre line is v3 L along a circle of curvature k per
        # unit s: p(s) = v3 (1 - cos ks) / k, v3 sin(ks) / k
        p_exact = v3 * np.array([(1 - math.cos(k * L)) / k, 0.0, math.sin(k * L) / k])
    # exact solution: solver tolerance 1e-10 (scaled) times the conditioning
    assert np.abs(sol.position[-1] - p_exact).max() < 1e-9 * L


def test_precurved_spatial_tendon_gives_constant_curvature():
    """A tendon at angle pi/2 on the arc u* = (0, k*, 0): m_b = -tau b e1, so u =
    (-tau b / EI, k*, 0) is constant and the shape is exp(s u^) (a spatial scene)."""
    ks, b, tau = 4.0, 0.004, 2.0
    rod = tr.Rod(L, EI=EI, GJ=GJ, kirchhoff=True, precurvature=(0.0, ks, 0.0))
    sc = tr.Scene(tr.Robot(rod, [tr.Tendon(offset=b, angle=math.pi / 2)]), tension=[tau])
    sol = tr.solve(sc)
    assert sol.success and not sol.formulation.planar
    p, R = _exp_pose((-tau * b / EI, ks, 0.0), L)
    assert np.abs(sol.position[-1] - p).max() < 1e-9 * L  # exact, solver tolerance
    assert np.abs(sol.rotation[-1] - R).max() < 1e-9


def test_precurved_displacement_control_refers_to_the_unstressed_arc():
    """q = 0 is the unstressed precurved robot (no tension); a retraction q shortens the
    channel s_i = L (1 - k b) by q, so k = k* + q / (L b) and tau = EI q / (L b^2)."""
    ks, b = 4.0, 0.004
    rod = tr.Rod(L, EI=EI, GJ=GJ, kirchhoff=True, precurvature=(0.0, ks, 0.0))
    robot = tr.Robot(rod, [tr.Tendon(offset=b)])
    sol0 = tr.solve(tr.Scene(robot, displacement=[0.0]))
    assert sol0.success and sol0.tension[0] == pytest.approx(0.0, abs=1e-9)
    p0, _ = _exp_pose((0.0, ks, 0.0), L)
    assert np.abs(sol0.position[-1] - p0).max() < 1e-10 * L
    for q in (1e-4, 5e-4):
        sol = tr.solve(tr.Scene(robot, displacement=[q]))
        assert sol.success
        k = ks + q / (L * b)
        # exact: solver tolerance 1e-10 scaled
        assert np.abs(sol.position[-1] - _exp_pose((0.0, k, 0.0), L)[0]).max() < 1e-9 * L
        assert sol.tension[0] == pytest.approx(EI * q / (L * b * b), rel=1e-8)


def test_stepped_cantilever_small_deflection():
    """Tip load P on a cantilever with EI1 on [0, a] and EI2 on [a, L]: by the unit-load
    method delta = P int (L - s)^2 / EI(s) ds, theta = P int (L - s) / EI(s) ds."""
    a, EI1, EI2 = 0.08, 0.2, 0.03
    base = tr.Rod(a, EI=EI1, GJ=0.1, kirchhoff=True)
    tip = tr.Rod(L - a, EI=EI2, GJ=0.02, kirchhoff=True)
    rod = tr.Rod.segmented([base, tip])
    assert rod.length == pytest.approx(L) and rod.bending_stiffness == EI1
    P = 1e-5 * EI2 / L**2
    sol = tr.solve(tr.Scene(tr.Robot(rod), loads=[tr.PointLoad(L, force=(P, 0.0, 0.0))]))
    assert sol.success and sol.formulation.n_sections == 2
    c = L - a
    delta = P * ((L**3 - c**3) / (3 * EI1) + c**3 / (3 * EI2))
    theta = P * ((L**2 - c**2) / (2 * EI1) + c**2 / (2 * EI2))
    # the linear theory's relative error is O((P L^2/EI)^2) = 1e-10
    assert sol.position[-1, 0] == pytest.approx(delta, rel=1e-8)
    assert math.atan2(sol.rotation[-1, 0, 2], sol.rotation[-1, 2, 2]) == pytest.approx(
        theta, rel=1e-8
    )


def _tendon_pull(sol, i, k, tau, r_body, rod_part):
    """World force tau t^ and moment about p of tendon i at node k, from the recorded
    state and the constitutive law of the segment it lies in."""
    R = sol.rotation[k]
    nb = R.T @ sol.force[k]
    mb = R.T @ sol.moment[k]
    K = np.array([rod_part.bending_stiffness] * 2 + [rod_part.torsional_stiffness])
    u = np.asarray(rod_part.precurvature) + mb / K
    v = np.array(
        [
            nb[0] / rod_part.shear_stiffness,
            nb[1] / rod_part.shear_stiffness,
            1 + nb[2] / rod_part.axial_stiffness,
        ]
    )
    w = v + np.cross(u, r_body)
    t = w / np.linalg.norm(w)
    return tau * (R @ t), tau * (R @ np.cross(r_body, t))


def test_segment_joint_carries_force_and_moment():
    """A stiff precurved base and a soft tip segment, a taut spatial tendon crossing the
    joint and a tip load: the backbone's force and moment jump at the joint (the tendon
    kinks there), the whole section's (backbone plus tendon pull) do not."""
    a = 0.07
    base = tr.Rod(a, EI=0.3, GJ=0.2, EA=2e5, GA=1e5, precurvature=(0.0, 2.0, 0.0))
    tip = tr.Rod(L - a, EI=0.04, GJ=0.03, EA=5e3, GA=3e3, precurvature=(1.0, 0.0, 0.5))
    rod = tr.Rod.segmented([base, tip])
    b, ang, tau = 0.005, 0.7, 4.0
    robot = tr.Robot(rod, [tr.Tendon(offset=b, angle=ang)])
    eps = 1e-9
    sc = tr.Scene(robot, tension=[tau], loads=[tr.PointLoad(L, force=(0.3, -0.2, 0.1))])
    sol = tr.solve(sc, options=tr.Options(nodes=np.array([0.0, a - eps, a + eps, L])))
    assert sol.success
    r = b * np.array([math.cos(ang), math.sin(ang), 0.0])
    f1, m1 = _tendon_pull(sol, 0, 1, tau, r, base)
    f2, m2 = _tendon_pull(sol, 0, 2, tau, r, tip)
    N1, N2 = sol.force[1] + f1, sol.force[2] + f2
    M1, M2 = sol.moment[1] + m1, sol.moment[2] + m2
    scale_f, scale_m = tau + 0.4, (tau + 0.4) * L
    # the backbone alone jumps by a visible amount ...
    assert np.abs(sol.moment[2] - sol.moment[1]).max() > 1e-5 * scale_m
    # ... the whole section is continuous to the joint-implicit solve (1e-15) and the
    # 2e-9 m between the nodes (gradients ~ scale / L)
    assert np.abs(N2 - N1).max() < 1e-7 * scale_f
    assert np.abs(M2 - M1).max() < 1e-7 * scale_m


def test_compliance_of_precurved_scene_against_finite_differences():
    """tr.compliance (implicit function theorem on the shooting system) on a precurved,
    segmented, tendon-loaded robot against central differences of full solves."""
    base = tr.Rod(0.08, EI=0.1, GJ=0.07, kirchhoff=True, precurvature=(0.0, 3.0, 0.0))
    tip = tr.Rod(0.12, EI=0.04, GJ=0.03, kirchhoff=True, precurvature=(0.5, -2.0, 1.0))
    robot = tr.Robot(tr.Rod.segmented([base, tip]), [tr.Tendon(offset=0.004, angle=0.3)])
    sc = tr.Scene(robot, displacement=[2e-4])
    C = tr.compliance(sc)
    h = 1e-3  # [N]: central differences, truncation ~ h^2 |C''| ~ 1e-8 relative
    for j in range(3):
        dF = np.zeros(3)
        dF[j] = h
        ps = [
            tr.solve(
                tr.Scene(robot, displacement=[2e-4], loads=[tr.PointLoad(L, force=tuple(sg * dF))])
            ).position[-1]
            for sg in (1, -1)
        ]
        fd = (ps[0] - ps[1]) / (2 * h)
        assert np.abs(C[:3, j] - fd).max() < 1e-6 * np.abs(C[:3, :3]).max()


def test_bad_backbone_fields_name_themselves():
    with pytest.raises(ValueError, match="precurvature"):
        tr.Rod(L, EI=EI, GJ=GJ, kirchhoff=True, precurvature=(0.0, math.nan, 0.0))
    with pytest.raises(ValueError, match="kirchhoff"):
        tr.Rod.segmented(
            [tr.Rod(0.1, EI=EI, GJ=GJ, kirchhoff=True), tr.Rod(0.1, EI=EI, GJ=GJ, EA=1e5, GA=1e5)]
        )
    with pytest.raises(ValueError, match="segments"):
        tr.Rod(
            L, EI=EI, GJ=GJ, kirchhoff=True, segments=(tr.Rod(0.1, EI=EI, GJ=GJ, kirchhoff=True),)
        )
    rod = tr.Rod(L, EI=EI, GJ=GJ, EA=1e5, GA=1e5, precurvature=(0.0, 3.0, 0.5))
    with pytest.raises(ValueError, match="pretension"):
        tr.Robot(
            rod,
            [
                tr.Tendon(offset=0.004, pretension=1.0),
                tr.Tendon(offset=0.004, angle=math.pi, pretension=1.0),
            ],
        )
    with pytest.raises(ValueError, match="fold back"):
        tr.solve(
            tr.Scene(
                tr.Robot(
                    tr.Rod(L, EI=EI, GJ=GJ, kirchhoff=True, precurvature=(0.0, 300.0, 0.0)),
                    [tr.Tendon(offset=0.004)],
                ),
                tension=[1.0],
            )
        )


def test_jacobian_design_EI_of_precurved_rod_against_finite_differences():
    """The design derivative d(tip)/dEI of a precurved, tension-driven robot (its one
    section perturbed with the rod) against central differences of full solves."""

    def scene(ei):
        rod = tr.Rod(L, EI=ei, GJ=GJ, kirchhoff=True, precurvature=(0.5, 3.0, 0.0))
        return tr.Scene(tr.Robot(rod, [tr.Tendon(offset=0.004, angle=0.3)]), tension=[3.0])

    J = tr.jacobian(scene(EI), design=["EI"], load=False)
    h = 1e-4 * EI  # central differences: truncation ~ (h/EI)^2 ~ 1e-8 relative
    fd = (tr.solve(scene(EI + h)).position[-1] - tr.solve(scene(EI - h)).position[-1]) / (2 * h)
    assert np.abs(J.design[:3, 0] - fd).max() < 1e-6 * np.abs(fd).max()
    with pytest.raises(ValueError, match="segmented"):
        seg = tr.Rod.segmented([tr.Rod(0.1, EI=EI, GJ=GJ, kirchhoff=True)] * 2)
        tr.jacobian(tr.Scene(tr.Robot(seg)), design=["EI"])


def test_scene_file_segments_and_precurvature():
    from tendonrod.scenefile import SceneFileError, parse_scene

    doc = {
        "rod": {"E": 60e9, "G": 23e9, "kirchhoff": True, "precurvature": [0.0, 2.0, 0.0]},
        "segment": [
            {"length": 0.05, "diameter": 1.5e-3},
            {"length": 0.15, "diameter": 1.0e-3, "precurvature": [0.0, 4.0, 1.0]},
        ],
        "tendon": [{"offset": 0.003, "tension": 1.0}],
    }
    rod = parse_scene(doc).scene.robot.rod
    assert rod.length == pytest.approx(0.2) and len(rod.segments) == 2
    assert rod.segments[0].precurvature == (0.0, 2.0, 0.0)  # inherited from [rod]
    assert rod.segments[1].precurvature == (0.0, 4.0, 1.0)
    bad = dict(doc, segment=[{"length": 0.05, "precurvature": [0.0, 4.0]}])
    with pytest.raises(SceneFileError, match=r"segment\[0\]\.precurvature"):
        parse_scene(bad)
    with pytest.raises(SceneFileError, match=r"segment\[1\]\.length"):
        parse_scene(dict(doc, segment=[{"length": 0.05, "diameter": 1e-3}, {"diameter": 1e-3}]))
    with pytest.raises(SceneFileError, match=r"rod\.length"):
        parse_scene(dict(doc, rod=dict(doc["rod"], length=0.3)))


def test_pretension_on_a_precurved_arc_holds_the_compressed_arc():
    """Two opposing parallel tendons with pretension tau_p on an arc u* = (0, k*, 0) of a
    Cosserat rod: at q = 0 both hold tau_p and the robot is the unstressed arc compressed
    to v3 = 1 - 2 tau_p / EA (whole section unloaded, n_b = -2 tau_p e3, m_b = 0)."""
    ks, b, tp, EA = 4.0, 0.004, 3.0, 1e5
    rod = tr.Rod(L, EI=EI, GJ=GJ, EA=EA, GA=5e4, precurvature=(0.0, ks, 0.0))
    robot = tr.Robot(rod, [tr.Tendon(b, 0.0, pretension=tp), tr.Tendon(b, math.pi, pretension=tp)])
    sol = tr.solve(tr.Scene(robot, displacement=[0.0, 0.0]))
    assert sol.success
    v3 = 1.0 - 2.0 * tp / EA
    p = v3 * np.array([(1 - math.cos(ks * L)) / ks, 0.0, math.sin(ks * L) / ks])
    # exact state: the solver's tolerance 1e-10 (scaled)
    assert np.abs(sol.position[-1] - p).max() < 1e-9 * L
    assert sol.tension == pytest.approx([tp, tp], rel=1e-9)
