"""The secant (finite-load) compliance, ``tr.compliance(scene, s, step=h)``, against
independent answers: the exact elastica, its h^2 approach to the tangent, the closed
forms on both sides of a taut/slack switch, and the tangent trap near a switch (a
four-tendon robot whose side tendons are slack by 31 um).

Sign convention of the closed forms: with the tendon at +x, a world force -F e_x
(F > 0) tightens it."""

from __future__ import annotations

import math
import warnings

import closed_ref
import numpy as np
import pytest
import reference as ref

import tendonrod as tr
from tendonrod._secant import rotation_vector

# Paper Figs. 17-18 robot (Kirchhoff): L = 0.2 m, d = 0.8 mm, E = 207 GPa, G = 79.6 GPa.
L17 = 0.2
KIRCH17 = tr.Rod(L17, 0.8e-3, 207e9, 79.6e9, kirchhoff=True)
EI17 = KIRCH17.bending_stiffness
# A superelastic wire robot: L = 0.25 m, d = 1.2 mm, E = 60 GPa, G = 23 GPa, Cosserat backbone.
L13 = 0.25
ROD13 = tr.Rod(L13, 1.2e-3, 60e9, 23e9)


def plain_scene(rod, F=(0.0, 0.0, 0.0)):
    return tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=rod.length, force=F)])


def four_tendons(r):
    return tr.Robot(ROD13, [tr.Tendon(offset=r, angle=k * math.pi / 2) for k in range(4)])


def test_secant_of_the_plain_cantilever_is_the_elastica():
    """Column Fx at the tip is (x(h) - x(0)) / h with x(h) the exact elastica under the
    tip force h e_x (elliptic integrals, tests/reference.py): position and rotation."""
    EI, L = EI17, L17
    h = 0.2 * EI / L**2  # h L^2 / EI = 0.2: a deflection of 7 % of L
    C = tr.compliance(plain_scene(KIRCH17), step=h)
    x, z, th = ref.elastica_transverse_tip_force(h, L, EI)  # under -h e_x: x < 0
    # the solver's tip is exact to ~1e-11 L (scaled tolerance 1e-10); divided by a
    # deflection of 0.07 L that is ~1e-9 relative: 1e-8 leaves room for the reference
    assert abs(C[0, 0] - (-x) / h) <= 1e-8 * abs(x / h)
    assert abs(C[2, 0] - (z - L) / h) <= 1e-8 * abs((z - L) / h)
    # the tip turns about +y by theta (the reference's tip angle from +z, sign: -x side)
    assert abs(C[4, 0] - abs(th) / h) <= 1e-8 * abs(th / h)
    # nothing moves out of the plane of the load (a planar scene: zero up to round-off)
    assert np.all(np.abs(C[[1, 3, 5], 0]) <= 1e-12 * abs(C[0, 0]))


def test_secant_tends_to_the_tangent_like_h_squared():
    """For the plain cantilever the transverse tip deflection is odd in the load
    (x'' = 0 at F = 0), so secant - tangent = h^2 x'''/6 + O(h^4): halving h divides the
    difference by 4.  The tangent is L^3 / (3 EI) (Euler-Bernoulli)."""
    EI, L = EI17, L17
    sc = plain_scene(KIRCH17)
    Ct = tr.compliance(sc)
    assert abs(Ct[0, 0] - L**3 / (3 * EI)) <= 1e-9 * L**3 / (3 * EI)
    hs = [0.2 * EI / L**2 / 2**k for k in range(4)]
    diff = [abs(tr.compliance(sc, step=h)[0, 0] - Ct[0, 0]) for h in hs]
    for a, b in zip(diff, diff[1:]):
        # 4 (1 + O((h L^2/EI)^2)): the h^4 term changes the ratio by < 1 % at h L^2/EI
        # <= 0.2; 3 % more for the solver's ~1e-11 relative error over a difference
        # that falls to ~3e-5 of the compliance at the smallest h
        assert 3.85 < a / b < 4.15, diff
    # the secant's columns are where the tangent's are, to O(h): a bent robot under a
    # small load, where x'' != 0: the one-sided secants straddle the tangent and their
    # mean approaches it like h^2
    robot = tr.Robot(KIRCH17, [tr.Tendon(offset=0.01)])
    bent = tr.Scene(robot, displacement=[0.01 * math.pi / 2], loads=[tr.PointLoad(s=L)])
    Ct = tr.compliance(bent)
    steps = np.array([1.0, 1.0, 1.0, L, L, L]) * 0.02 * EI / L**2  # 2 % of EI/L^2 and EI/L
    one, mean = [], []
    for k in range(3):
        h = steps / 2**k
        Cp, Cm = tr.compliance(bent, step=h), tr.compliance(bent, step=-h)
        one.append(np.linalg.norm(Cp - Ct) / np.linalg.norm(Ct))
        mean.append(np.linalg.norm((Cp + Cm) / 2 - Ct) / np.linalg.norm(Ct))
    for k in range(2):
        # O(h): halving h halves the one-sided difference; O(h^2): the mean's quarters
        # (the next order changes the ratios by ~h L^2/EI = 2 %: 5 % bounds)
        assert 1.9 < one[k] / one[k + 1] < 2.1, one
        assert 3.8 < mean[k] / mean[k + 1] < 4.2, mean
    assert mean[-1] < 0.05 * one[-1]


def test_secant_sees_a_slack_switch_the_tangent_cannot():
    """A straight Kirchhoff robot with one inextensible tendon at +x locked at q = 0 is
    exactly at its taut/slack switch when unloaded.  Under a tip force +F e_x the tendon
    goes slack (the bare cantilever, F L^3 / 3EI); under -F e_x it locks the tip angle
    (eq. 12, F L^3 / 12EI).  From a small load on the slack side the tangent is the bare
    rod's, and so is a secant that stays on that side; a secant into the taut side is
    the piecewise-linear answer, up to 4x stiffer."""
    EI, L = EI17, L17
    robot = tr.Robot(KIRCH17, [tr.Tendon(offset=0.01)])
    F0 = 1e-4 * EI / L**2  # slack side, by a hair (the tendon's slack is ~1e-9 m)
    sc = tr.Scene(robot, displacement=[0.0], loads=[tr.PointLoad(s=L, force=(F0, 0.0, 0.0))])
    sol = tr.solve(sc)
    assert sol.tension[0] == 0.0 and sol.slack[0] > 0.0
    bare = closed_ref.eq9(1.0, L, EI, 0.01, 0.0)  # k = 0: the bare cantilever
    taut = closed_ref.eq12(1.0, L, EI)
    # all loads here are below 1e-2 EI/L^2: the closed forms' (F L^2/EI)^2 error < 1e-4
    tol = 1e-3
    assert abs(tr.compliance(sc)[0, 0] - bare) <= tol * bare
    h = 1e-2 * EI / L**2
    assert abs(tr.compliance(sc, step=h)[0, 0] - bare) <= tol * bare
    Cs = tr.compliance(sc, step=-h)[0, 0]
    # from F0 down to 0 the bare rod, from 0 to F0 - h the locked one
    want = (bare * F0 + taut * (h - F0)) / h
    assert abs(Cs - want) <= tol * want
    assert Cs < 0.27 * bare  # the direction the physics says: stiffer by nearly 4


def test_tangent_trap_four_tendon_robot():
    """The tangent trap: a four-tendon robot bent 60 deg by the tendon at +x (the one at -x paid
    out) compresses its backbone, so the side tendons at +-y, on the neutral plane of the
    bend, are slack by exactly that compression, tau L / EA = 31 um.  The tangent
    out-of-plane compliance is blind to them (it equals that of the robot without the
    side tendons); a load of 0.1 N makes the convex-side tendon take up its slack, and
    the secant is 2.6x stiffer."""
    r, q = 3e-3, 3e-3 * math.pi / 3
    sc = tr.Scene(four_tendons(r), displacement=[q, 0.0, -q, 0.0], loads=[tr.PointLoad(s=L13)])
    sol = tr.solve(sc)
    tau = sol.tension[0]
    assert sol.tension[1:].tolist() == [0.0, 0.0, 0.0]
    # the backbone carries -tau e3 only (no external load), so its centre line and the
    # side tendons' paths (where u x r = 0) shorten by tau L / EA: exact to the solver's
    # tolerance (1e-10 of L, ~1e-6 of the slack)
    compression = tau * L13 / ROD13.axial_stiffness
    assert abs(sol.slack[1] - compression) <= 1e-5 * compression
    assert abs(sol.slack[3] - compression) <= 1e-5 * compression
    assert 30e-6 < compression < 32e-6  # tau L / EA: 31 um
    Ct = tr.compliance(sc)
    # without the side tendons (and the slack one at -x), the same bent backbone
    alone = tr.Scene(tr.Robot(ROD13, [tr.Tendon(offset=r)]), displacement=[q], loads=sc.loads)
    Ca = tr.compliance(alone)
    # the slack tendons add nothing to the linearisation: equal to the solver tolerance
    # amplified by the shooting condition (~1e4 here)
    assert abs(Ct[1, 1] - Ca[1, 1]) <= 1e-6 * Ca[1, 1]
    steps = [0.1, 0.1, 0.1, 0.01, 0.01, 0.01]  # 0.1 N; 0.01 N m (0.4 rad of bending)
    Cp = tr.compliance(sc, step=steps)
    Cm = tr.compliance(sc, step=[-h for h in steps])
    # the robot is symmetric about its x-z plane: +-0.1 N along y are mirror images
    assert abs(Cp[1, 1] - Cm[1, 1]) <= 1e-7 * Cp[1, 1]
    ratio = Ct[1, 1] / Cp[1, 1]
    assert 2.5 < ratio < 2.8, ratio  # 2.6x softer than the secant at 0.1 N
    # at +0.1 N the tendon on the convex side (-y) is taut, the other still slack
    loaded = tr.Scene(
        sc.robot, displacement=sc.displacement, loads=[tr.PointLoad(s=L13, force=(0, 0.1, 0))]
    )
    s1 = tr.solve(loaded)
    assert s1.tension[3] > 0.0 and s1.slack[3] == 0.0 and s1.tension[1] == 0.0


def test_secant_against_piecewise_closed_forms_straight_four_tendons():
    """The straight four-tendon robot with the tendons at +-x pulled 31 um: the backbone
    compresses by eps = 2 tau / EA, the side tendons are slack by 31 um.  Out of plane:
    the tangent is the Timoshenko cantilever shortened by eps, (1 - eps)^2 L^3 / 3EI +
    L / GA; under a force F along y the tendon at -y lengthens by r theta_tip, takes up
    its slack at F_s = 2 EI slack / (r L^2 (1 - eps)), and beyond that holds the tip
    angle: (1 - eps)^2 L^3 / 12EI + L / GA.  The secant at h is the piecewise-linear
    mean."""
    r, q = 5e-3, 31e-6
    sc = tr.Scene(four_tendons(r), displacement=[q, 0.0, q, 0.0], loads=[tr.PointLoad(s=L13)])
    sol = tr.solve(sc)
    EI, EA, GA = ROD13.bending_stiffness, ROD13.axial_stiffness, ROD13.shear_stiffness
    eps = 2 * sol.tension[0] / EA
    slack = sol.slack[1]
    assert abs(slack - q) <= 1e-6 * q  # the pulled tendons' 31 um, all of it compression
    bare = (1 - eps) ** 2 * L13**3 / (3 * EI) + L13 / GA
    held = (1 - eps) ** 2 * L13**3 / (12 * EI) + L13 / GA
    Ct = tr.compliance(sc)
    # linear theory is exact for the tangent: the solver's tolerance, amplified ~1e2
    assert abs(Ct[1, 1] - bare) <= 1e-7 * bare
    Fs = slack * 2 * EI / (r * L13**2 * (1 - eps))
    h = 0.02  # h L^2 / EI = 0.2
    Cs = tr.compliance(sc, step=[h, h, h, h * L13, h * L13, h * L13])
    want = (bare * Fs + held * (h - Fs)) / h
    # the piecewise-linear answer leaves out the geometric nonlinearity, O((h L^2/EI)^2)
    # with a small coefficient: 3.4e-4 measured at 0.2 (and 2e-3 at 0.5, 8e-3 at 1)
    assert abs(Cs[1, 1] - want) <= 1e-3 * want
    assert Cs[1, 1] < 0.3 * Ct[1, 1]


def test_problem_compliance_step_and_errors():
    """Problem.compliance(step=) is tr.compliance(step=) from the problem's last solution;
    a bad step is a ValueError naming it; a step whose scene does not solve raises
    ConvergenceError naming the column."""
    EI, L = EI17, L17
    sc = plain_scene(KIRCH17, F=(0.1 * EI / L**2, 0.0, 0.0))
    prob = tr.Problem(sc)
    sol = prob.solve()
    h = 0.05 * EI / L**2
    # the same seven solves from the same solution: bitwise
    assert np.array_equal(
        prob.compliance(step=h), tr.compliance(sc, guess=sol, options=prob.options, step=h)
    )
    C = prob.compliance(s=0.1, step=h)
    assert C.shape == (6, 6) and np.all(np.isfinite(C))
    for bad in (0, 0.0, math.nan, math.inf, "0.1", [1.0, 2.0], [1.0] * 5 + [0.0], True):
        with pytest.raises(ValueError, match="step"):
            tr.compliance(sc, step=bad)
    # a moment step of 1e3 EI/L curls the rod hundreds of turns: not on any path
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(tr.ConvergenceError, match="load step"):
            tr.compliance(sc, step=[h, h, h, 1e3 * EI / L, 1e3 * EI / L, 1e3 * EI / L])


def test_rotation_vector():
    """The rotation vector of R: exact for angles up to pi (axis-angle built with
    Rodrigues' formula), including the small and the near-pi ones."""
    rng = np.random.default_rng(13)
    for theta in (1e-12, 1e-6, 0.3, 2.0, 3.0, math.pi - 1e-9, math.pi):
        a = rng.normal(size=3)
        a /= np.linalg.norm(a)
        K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
        R = np.eye(3) + math.sin(theta) * K + (1 - math.cos(theta)) * K @ K
        w = rotation_vector(R)
        if theta < math.pi - 1e-6:
            # atan2 of the skew and symmetric parts: R's entries carry ~1e-16 of round-off,
            # so the angle and axis are good to ~1e-15 (1e-12 leaves room)
            assert np.allclose(w, theta * a, rtol=0, atol=1e-12 * max(theta, 1e-3)), theta
        else:  # at pi, a and -a are the same rotation
            # the axis from (R + I)/2 with R's round-off: sqrt(1e-16) ~ 1e-8 at worst
            assert min(np.linalg.norm(w - theta * a), np.linalg.norm(w + theta * a)) < 1e-7


def test_sweep_compliance_measure_offers_both():
    """ComplianceMeasure(step=h) records the secant beside the tangent, each what
    tr.compliance gives for the point's scene (the same cold solves: bitwise)."""
    from tendonrod.sweeps import ComplianceMeasure, set_path

    EI, L = EI17, L17
    base = plain_scene(KIRCH17)
    forces = [(f * EI / L**2, 0.0, 0.0) for f in (0.1, 0.3)]
    h = 0.05 * EI / L**2
    res = tr.sweep(
        base,
        {"loads[0].force": forces},
        measure=ComplianceMeasure(s=(0.1, None), step=h),
        progress=False,
    )
    assert res["compliance"].shape == res["secant_compliance"].shape == (2, 2, 6, 6)
    for i, f in enumerate(forces):
        sc = set_path(base, "loads[0].force", f)
        assert np.array_equal(res["secant_compliance"][i, 1], tr.compliance(sc, step=h))
        assert np.array_equal(res["secant_compliance"][i, 0], tr.compliance(sc, s=0.1, step=h))
        assert np.array_equal(res["compliance"][i, 1], tr.compliance(sc))
    only = tr.sweep(
        base,
        {"loads[0].force": forces[:1]},
        measure=ComplianceMeasure(step=h, tangent=False),
        progress=False,
    )
    assert "compliance" not in only.data and only["secant_compliance"].shape == (1, 1, 6, 6)
