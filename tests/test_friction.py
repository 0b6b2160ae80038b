"""Friction between the tendons and their channels (docs/model.md, Section 3).

Checked against what is known independently of the solver's equations:
- the planar exact solution of a tension-controlled parallel tendon without loads
  (tau(s) = tau0 / (1 + sigma mu r tau0 s / EI), theta(s) = ln(1 + sigma mu r tau0 s/EI) /
  (sigma mu)), derived in docs/model.md from the distal free body;
- a SciPy shooting reference under tip loads that never uses the distributed tendon loads
  (tendonrod.bench.references_friction: the moment of the distal free body plus the
  capstan law), including loads that reverse the curvature (a kink of the friction law);
- global force and moment balance of the whole robot;
- the frictionless problem itself (mu = 0 compiles to it, bitwise; mu = 1e-9 is 1e-9 away);
- consistency of the two control kinds: a tension's displacement fed back as a
  displacement gives that tension.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import tendonrod as tr
from tendonrod import _core
from tendonrod.bench.references_friction import friction_tendon_state

L, D, E, G = 0.2, 0.8e-3, 207e9, 79.6e9
EI = E * math.pi * D**4 / 64
R = 0.01
TIGHT = tr.Options(tol=1e-12)


def _robot(mu, *, EA=math.inf, kirchhoff=True, **kw):
    rod = tr.Rod(length=L, diameter=D, E=E, G=G, kirchhoff=kirchhoff)
    return tr.Robot(rod, [tr.Tendon(offset=R, EA=EA, friction=mu, **kw)])


def _exact(mu, sigma, tau0, s):
    c = sigma * mu * R * tau0 / EI
    return tau0 / (1.0 + c * s), np.log1p(c * s) / (sigma * mu)


@pytest.mark.parametrize("sliding", ["in", "out"])
@pytest.mark.parametrize("spatial", [False, True])
def test_exact_planar_solution(sliding, spatial):
    mu, tau0 = 0.3, 2.0
    sigma = 1 if sliding == "in" else -1
    scene = tr.Scene(_robot(mu), tension=[tau0], sliding=sliding)
    sol = tr.solve(scene, options=dataclasses.replace(TIGHT, force_spatial=spatial))
    assert sol.success and sol.formulation.planar is not spatial
    tau, theta = _exact(mu, sigma, tau0, sol.s)
    # tol 1e-12 (scaled residual) and a verified step count: 1e-10 relative is ample
    assert np.max(np.abs(sol.tendon_tension[:, 0] - tau)) <= 1e-10 * tau0
    Rt = sol.tip_rotation
    assert abs(math.atan2(Rt[0, 2], Rt[2, 2]) - theta[-1]) <= 1e-10
    # friction takes tension away sliding in and adds it sliding out
    assert (sol.tendon_tension[-1, 0] < tau0) == (sliding == "in")
    assert sol.tension[0] == tau0
    # no energy, no stability verdict: said, not hidden
    assert sol.stable is None and "friction" in sol.stability_reason


@pytest.mark.parametrize("sliding", ["in", "out"])
@pytest.mark.parametrize("force", [(-0.3, 0.0), (-0.5, -0.2), (0.2, -0.3)])
def test_tip_loads_against_free_body_reference(sliding, force):
    # (-0.3, 0) and (-0.5, -0.2) push against the bend: the curvature, and so the
    # normal load, changes sign along the rod (a kink of |tau t'| the steps must locate)
    mu, tau0 = 0.4, 3.0
    sigma = 1 if sliding == "in" else -1
    scene = tr.Scene(
        _robot(mu),
        tension=[tau0],
        sliding=sliding,
        loads=[tr.PointLoad(L, force=(force[0], 0.0, force[1]))],
    )
    sol = tr.solve(scene, options=TIGHT)
    ref = friction_tendon_state(L, EI, R, mu, sigma, force, tension=tau0)
    assert sol.success
    # the reference is DOP853 at rtol 1e-13 with shooting to 1e-14: both to ~1e-12
    assert np.max(np.abs(sol.tip_position[[0, 2]] - ref["tip"])) <= 1e-10 * L
    assert abs(sol.tip_angle - ref["tip_angle"]) <= 1e-10
    assert abs(sol.tendon_tension[-1, 0] - ref["tension_tip"]) <= 1e-10 * tau0
    # a tension-controlled tendon's displacement comes from the recording pass (RK4 at an
    # eighth of the shooting step, ~1e-9 relative; docs/model.md)
    assert abs(sol.displacement[0] - ref["displacement"]) <= 1e-9 * R
    # and the displacement-controlled scene with that displacement
    sd = tr.Scene(
        scene.robot, displacement=[ref["displacement"]], sliding=sliding, loads=scene.loads
    )
    sold = tr.solve(sd, options=TIGHT)
    assert sold.success and abs(sold.tension[0] - tau0) <= 1e-9 * tau0
    assert abs(sold.tip_angle - ref["tip_angle"]) <= 1e-10


def test_reversal_needs_no_more_steps():
    # the kink where the curvature changes sign is located, so the automatic step count
    # stays that of a smooth scene (without it: the 8192-step cap and a 5e-9 error)
    scene = tr.Scene(
        _robot(0.4), tension=[3.0], sliding="out", loads=[tr.PointLoad(L, force=(-0.3, 0, 0))]
    )
    sol = tr.solve(scene)
    assert sol.success and sol.status == 0 and sol.formulation.steps <= 64
    assert sol.truncation_estimate <= 1e-10


@pytest.mark.parametrize("sliding", ["in", "out"])
def test_stretch_and_both_control_kinds(sliding):
    # an extensible tendon: its stretch integrates tau(s)/EA along it
    mu, tau0, EA = 0.3, 4.0, 2e3
    sigma = 1 if sliding == "in" else -1
    scene = tr.Scene(_robot(mu, EA=EA), tension=[tau0], sliding=sliding)
    sol = tr.solve(scene, options=TIGHT)
    ref = friction_tendon_state(L, EI, R, mu, sigma, tension=tau0, EA=EA)
    # exact by quadrature as well: q = (1 + tau0/EA) (L - int (1 - r kappa)/(1 + tau/EA) ds)
    from scipy.integrate import quad

    def integrand(s):
        tau, _ = _exact(mu, sigma, tau0, s)
        return (1.0 - R * R * tau / EI) / (1.0 + tau / EA)

    q_exact = (1.0 + tau0 / EA) * (L - quad(integrand, 0.0, L, epsabs=1e-16, epsrel=1e-12)[0])
    assert abs(ref["displacement"] - q_exact) <= 1e-13
    assert abs(sol.displacement[0] - q_exact) <= 1e-9 * R  # recording pass, as above
    sold = tr.solve(tr.Scene(scene.robot, displacement=[q_exact], sliding=sliding), options=TIGHT)
    assert sold.success and abs(sold.tension[0] - tau0) <= 1e-9 * tau0
    assert np.max(np.abs(sold.tendon_tension - sol.tendon_tension)) <= 1e-9 * tau0


def _whole_section_base(sol):
    """Force and moment about the base carried by the whole section at s = 0 (world):
    the backbone's n(0), m(0) plus each tendon's pull tau(0) t(0) at r(0)."""
    st = sol.at(0.0)
    n, m = st.force.copy(), st.moment.copy()
    robot = sol.scene.robot
    u = m / np.array([EI, EI, G * math.pi * D**4 / 32])  # body = world at the base
    for i, t in enumerate(robot.tendons):
        r = np.array([math.cos(t.angle), math.sin(t.angle), 0.0]) * t.offset
        w = (
            np.array([0.0, 0.0, 1.0])
            + np.cross(u, r)
            + np.array([math.cos(t.angle), math.sin(t.angle), 0.0]) * t.slope
        )
        th = w / np.linalg.norm(w)
        n += sol.tension[i] * th
        m += sol.tension[i] * np.cross(r, th)
    return n, m


def test_global_balance_spatial_with_interior_anchor():
    # two frictional tendons (one anchored mid-length, one sliding out), a frictionless
    # one, a mid-length point load and a tip load, Kirchhoff: the whole robot's base
    # reaction balances the external loads exactly (the friction loads are internal)
    rod = tr.Rod(length=L, diameter=D, E=E, G=G, kirchhoff=True)
    robot = tr.Robot(
        rod,
        [
            tr.Tendon(offset=R, angle=0.0, friction=0.5),
            tr.Tendon(offset=R, angle=2.0, friction=0.3, end=0.12),
            tr.Tendon(offset=R, angle=4.0),
        ],
    )
    F1, F2 = np.array([0.05, -0.1, -0.2]), np.array([-0.1, 0.2, 0.05])
    scene = tr.Scene(
        robot,
        tension=[2.0, 3.0, None],
        displacement=[None, None, 0.002],
        sliding=["in", "out", "in"],
        loads=[tr.PointLoad(0.08, force=F1), tr.PointLoad(L, force=F2)],
    )
    sol = tr.solve(scene, options=TIGHT)
    assert sol.success and not sol.formulation.planar
    n, m = _whole_section_base(sol)
    p1 = sol.at(0.08).position
    # residual tol 1e-12 of EI/L^2 and EI/L: balance to 1e-10 of the loads
    assert np.max(np.abs(n - (F1 + F2))) <= 1e-10 * np.abs(F2).sum()
    moment = np.cross(p1, F1) + np.cross(sol.tip_position, F2)
    assert np.max(np.abs(m - moment)) <= 1e-10 * L * np.abs(F2).sum()
    # the tensions along the anchored tendon stop at its anchor; friction changed both
    tt = sol.tendon_tension
    assert np.all(tt[sol.s > 0.12 + 1e-12, 1] == 0.0)
    assert tt[-1, 0] < 2.0 and tt[np.searchsorted(sol.s, 0.12), 1] > 3.0
    # multiple shooting carries the friction states across its nodes
    ms = tr.solve(scene, options=dataclasses.replace(TIGHT, shooting_segments=3))
    assert ms.success and np.max(np.abs(ms.tip_position - sol.tip_position)) <= 1e-10 * L
    assert np.max(np.abs(ms.tendon_tension[-1] - tt[-1])) <= 1e-9


@pytest.mark.parametrize("kirchhoff", [True, False])
def test_zero_friction_is_the_frictionless_problem(kirchhoff):
    rod = np.array([L, EI, 2 * EI / 2.6, 1e5, 4e4, 1.0 if kirchhoff else 0.0])
    tendons = np.array(
        [[R, 0.0, 0.0, 3e3, L, 0, 0.004, 0.0], [R, math.pi, 0.0, math.inf, L, 1, 0.5, 0.0]]
    )
    loads = np.array([[L, 0.1, 0.0, -0.1, 0.0, 0.0, 0.0]])
    dist = np.zeros(3)
    plain = _core.solve(rod, tendons, loads, dist)
    zero = _core.solve(rod, tendons, loads, dist, friction=np.array([[0.0, 1.0], [0.0, -1.0]]))
    for key in ("position", "rotation", "tension", "unknowns", "displacement"):
        assert np.array_equal(plain[key], zero[key]), key  # bitwise: the same problem
    tiny = _core.solve(rod, tendons, loads, dist, friction=np.array([[1e-9, 1.0], [1e-9, -1.0]]))
    # a friction of 1e-9 perturbs the solution by ~1e-9 relative (the tip turns ~1 rad)
    dp = np.max(np.abs(tiny["position"] - plain["position"])) / L
    assert 1e-12 < dp <= 1e-8
    assert np.max(np.abs(tiny["tension"] - plain["tension"])) <= 1e-8 * plain["tension"].max()


def test_slack_tendon_stays_slack():
    scene = tr.Scene(_robot(0.5), displacement=[-0.001], loads=[tr.PointLoad(L, force=(0.1, 0, 0))])
    sol = tr.solve(scene, options=TIGHT)
    assert sol.success and sol.tension[0] == 0.0 and sol.slack[0] > 0.0
    assert np.all(sol.tendon_tension == 0.0)


def test_problem_and_state_at():
    scene = tr.Scene(_robot(0.2), tension=[1.0])
    prob = tr.Problem(scene)
    a = prob.solve()
    b = prob.solve(dataclasses.replace(scene, tension=[1.5]))
    ref = tr.solve(dataclasses.replace(scene, tension=[1.5]), options=prob.options)
    assert a.success and b.success
    assert np.max(np.abs(b.tip_position - ref.tip_position)) <= 1e-10 * L
    st = b.at([0.05, 0.1])
    assert st.tendon_tension.shape == (2, 1)
    tau, _ = _exact(0.2, 1, 1.5, np.array([0.05, 0.1]))
    assert np.max(np.abs(st.tendon_tension[:, 0] - tau)) <= 1e-9
    # the sliding direction is part of the compiled problem
    with pytest.raises(ValueError, match="sliding"):
        prob.solve(dataclasses.replace(scene, sliding="out"))


def test_bad_input_names_the_field():
    with pytest.raises(ValueError, match="friction"):
        tr.Tendon(offset=R, friction=-0.1)
    with pytest.raises(ValueError, match="friction"):
        tr.Tendon(offset=R, friction=math.nan)
    robot = _robot(0.1)
    with pytest.raises(ValueError, match=r"sliding\[0\]"):
        tr.Scene(robot, tension=[1.0], sliding=["sideways"])
    with pytest.raises(ValueError, match="sliding"):
        tr.Scene(robot, tension=[1.0], sliding=["in", "out"])
    core = (
        np.array([L, EI, EI, math.inf, math.inf, 1.0]),
        np.array([[R, 0.0, 0.0, math.inf, L, 1, 1.0, 0.0]]),
        np.zeros((0, 7)),
        np.zeros(3),
    )
    with pytest.raises(ValueError, match="sliding of tendon 0"):
        _core.solve(*core, friction=np.array([[0.1, 0.0]]))
    with pytest.raises(ValueError, match="friction of tendon 0"):
        _core.solve(*core, friction=np.array([[-0.1, 1.0]]))
    with pytest.raises(ValueError, match="one row per tendon"):
        _core.solve(*core, friction=np.array([[0.1, 1.0], [0.1, 1.0]]))


def test_slip_of_a_pull_and_a_release():
    # pulled from rest by q, an inextensible tendon's material at the base moved in by q
    # exactly (its rest length is its channel length) and nowhere out
    robot = _robot(0.2)
    pulled = tr.solve(tr.Scene(robot, displacement=[0.01], sliding="in"), options=TIGHT)
    check = tr.slip(pulled)
    assert check.consistent and "slid the way" in check.message
    assert abs(check.slip[0, 0] - 0.01) <= 1e-10 * R  # the recording pass's accuracy
    assert abs(check.slip[-1, 0]) <= 1e-12 * L  # the anchor does not move
    assert np.all(check.slip[:, 0] >= -1e-12 * L)
    # the same pull computed as sliding out is flagged: it slid in
    wrong = tr.slip(tr.solve(tr.Scene(robot, displacement=[0.01], sliding="out")))
    assert not wrong.consistent and wrong.conflicts[0][0] == 0
    assert 'against the assumed "out"' in wrong.message
    # released from the pulled state, the tendon slides out: "out" is consistent, "in" not
    for sliding, ok in (("out", True), ("in", False)):
        rel = tr.solve(tr.Scene(robot, displacement=[0.006], sliding=sliding), options=TIGHT)
        assert tr.slip(rel, reference=pulled).consistent is ok
    # a slack tendon presses on nothing: no friction, no contradiction
    slack = tr.solve(
        tr.Scene(robot, displacement=[0.01], loads=[tr.PointLoad(L, force=(0.5, 0, 0))])
    )
    assert slack.tension[0] == 0.0 and tr.slip(slack, reference=pulled).consistent
    # frictionless tendons have no slip to report
    mixed = tr.Robot(robot.rod, [robot.tendons[0], tr.Tendon(offset=R, angle=math.pi)])
    both = tr.solve(tr.Scene(mixed, displacement=[0.01, None], tension=[None, 0.0]))
    assert np.all(np.isnan(tr.slip(both).slip[:, 1]))
    with pytest.raises(ValueError, match="same robot"):
        tr.slip(both, reference=pulled)


def _lever(mu, F):
    robot = _robot(mu, EA=3e3)
    return tr.Scene(robot, displacement=[0.01], loads=[tr.PointLoad(L, force=(F, 0.0, -0.1))])


def test_friction_as_a_design_parameter():
    # d(tip)/d(mu) by the implicit function theorem against central differences of full
    # solves (step 1e-4: truncation ~1e-8 relative, solves at tol 1e-13)
    sol = tr.solve(_lever(0.3, 0.1), options=TIGHT)
    opt = tr.Options(tol=1e-13)
    h = 1e-4
    fd = (
        tr.solve(_lever(0.3 + h, 0.1), options=opt).tip_position
        - tr.solve(_lever(0.3 - h, 0.1), options=opt).tip_position
    ) / (2 * h)
    for method, rel in (("central", 1e-7), ("forward", 1e-6)):
        J = tr.jacobian(sol, design=["robot.tendons[0].friction"], method=method)
        assert J.design_names == ("robot.tendons[0].friction",)
        assert np.max(np.abs(J.design[:3, 0] - fd)) <= rel * np.max(np.abs(fd))
    # a frictionless tendon has no friction state to differentiate
    with pytest.raises(ValueError, match="frictionless"):
        tr.jacobian(tr.solve(_lever(0.0, 0.1)), design=["tendons[0].friction"])


def test_fit_recovers_the_friction():
    # synthetic tip measurements of the lever at mu = 0.25 under five loads; the fit from
    # mu = 0.1 recovers it (noise-free data: to the solver's accuracy)
    forces = (-0.2, -0.1, 0.0, 0.1, 0.2)
    measured = np.array([tr.solve(_lever(0.25, F), options=TIGHT).tip_position for F in forces])
    res = tr.fit([_lever(0.1, F) for F in forces], measured, ["tendons[0].friction"])
    assert abs(res.values[0] - 0.25) <= 1e-6
