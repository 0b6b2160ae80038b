"""Plausibility warnings (tendonrod.plausibility): each rule fires where an independent
answer says it must and stays silent just inside its limit; legal input stays legal;
every entry point finds the same; many points give one warning per rule, not a flood;
the bounds that spare a solve its state read never hide a finding."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy import optimize

import tendonrod as tr
from tendonrod import _plausible_rules as PR
from tendonrod import plausibility as P
from tendonrod._plausible import Recorder, _scene_screen, _state_findings
from tendonrod.sweeps import tip_measure

PW = tr.PlausibilityWarning
# A superelastic wire robot: L = 0.25 m, d = 1.2 mm, E = 60 GPa, G = 23 GPa.
L13, D13 = 0.25, 1.2e-3
KIRCH = tr.Rod(L13, D13, 60e9, 23e9, kirchhoff=True)
COSS = tr.Rod(L13, D13, 60e9, 23e9)
EI = KIRCH.bending_stiffness
R5 = 0.005
# the paper's Fig. 11 robot (L = 0.1 m, d = 1.04 mm, E = 210 GPa, r = 10 mm)
ROD11 = tr.Rod(0.1, 1.04e-3, 210e9, 80e9, kirchhoff=True)


def rules(findings):
    return sorted(f.rule for f in findings)


def circle(deg, rod=KIRCH, r=R5):
    """A lone tendon at a free tip: a circle of total angle ``deg`` (kappa = tau r/EI)."""
    tau = math.radians(deg) * rod.bending_stiffness / (r * rod.length)
    return tr.Scene(tr.Robot(rod, [tr.Tendon(offset=r)]), tension=[tau])


def quiet(f, *a, **k):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PW)
        warnings.simplefilter("ignore", tr.ConvergenceWarning)  # (checked where it matters)
        return f(*a, **k)


# ------------------------------------------------------------------ input rules
def test_angle_in_degrees_warns_at_the_users_line_and_stays_legal():
    with pytest.warns(PW, match=r"Tendon.angle = 90 rad .* degrees .* 1.5708 rad") as rec:
        t = tr.Tendon(offset=R5, angle=90)
    assert rec[0].filename == __file__  # the user's line, not the dataclass's
    assert t.angle == 90.0 and rec[0].message.finding.rule == "angle"
    with warnings.catch_warnings():
        warnings.simplefilter("error", PW)
        tr.Tendon(offset=0.01, angle=2 * math.pi)  # the limit itself is plausible
        tr.Tendon(offset=0.01, angle=-2 * math.pi)
    with pytest.warns(PW, match="angle"):
        tr.Tendon(offset=0.01, angle=-7.0)


def test_friction_as_a_percentage_warns_and_stays_legal(rod):
    with pytest.warns(
        PW, match=r"Tendon.friction = 30 is a Coulomb coefficient beyond 2: .* percentage"
    ):
        t = tr.Tendon(offset=R5, friction=30.0)
    assert t.friction == 30.0
    with warnings.catch_warnings():
        warnings.simplefilter("error", PW)
        tr.Tendon(offset=0.01, friction=2.0)  # the limit itself is plausible
        tr.Tendon(offset=0.01, friction=0.3)
    # a scene's input findings name the tendon
    robot = quiet(tr.Robot, rod, [quiet(tr.Tendon, offset=0.01, friction=25.0)])
    found = P.input_findings(tr.Scene(robot, tension=[0.1]))
    assert [f.rule for f in found] == ["friction"] and "robot.tendons[0].friction" in found[
        0
    ].message


def test_slenderness_and_offset_warn_with_value_and_slip():
    with pytest.warns(PW, match=r"L/d = 5 is below 10 .* diameter") as rec:
        tr.Rod(0.01, 2e-3, 60e9, 23e9)
    # L/d = 0.01 / 2e-3 is one floating division: within an ulp or two of 5
    assert rec[0].message.finding.value == pytest.approx(5.0, rel=1e-15)
    with warnings.catch_warnings():
        warnings.simplefilter("error", PW)
        tr.Rod(0.02, 2e-3, 60e9, 23e9)  # L/d = 10: the limit
        tr.Rod(0.1, EI=1.0, GJ=1.0, kirchhoff=True)  # no diameter, no EA: unknown, silent
    # no diameter: the round section's 4 sqrt(EI/EA) (here 4 sqrt(1e-6) = 4 mm)
    with pytest.warns(PW, match="4 sqrt"):
        tr.Rod(0.03, EI=1e3, GJ=1e3, EA=1e9, GA=1e9)
    # a tendon offset of 0.5 m on a 0.25 m rod (a typo for 5 mm, say)
    with pytest.warns(PW, match=r"tendon 0's radius 0.5 m .* 2 L, beyond 0.5 L .* mm given as m"):
        robot = tr.Robot(COSS, [tr.Tendon(offset=0.5)])
    sol = quiet(tr.solve, tr.Scene(robot, displacement=[0.0]))  # legal: it solves
    assert sol.success and rules(sol.plausibility) == ["offset"]
    # a sloped tendon: the radius that counts is the largest on [0, end]
    with pytest.warns(PW, match=r"at s = 0.25 m"):
        tr.Robot(COSS, [tr.Tendon(offset=0.01, slope=0.5)])  # 0.135 m = 0.54 L at the tip
    with warnings.catch_warnings():
        warnings.simplefilter("error", PW)
        tr.Robot(COSS, [tr.Tendon(offset=0.01, slope=0.5, end=0.2)])  # 0.11 m at its end


def test_modulus_in_gpa_given_as_pa_warns():
    """E = 60, G = 23 (NiTi's 60 GPa and 23 GPa given as Pa) warns for each modulus,
    naming it, its value and what it would be in GPa; the robot's solution lists it."""
    with pytest.warns(PW) as rec:
        rod = tr.Rod(length=0.2, diameter=0.8e-3, E=60, G=23)
    assert sorted(w.message.finding.subject for w in rec) == ["E", "G"]
    assert "Rod.E = 60 Pa is below 1000 Pa" in str(rec[0].message), rec[0].message
    assert "as GPa it would be 6e+10 Pa" in str(rec[0].message), rec[0].message
    assert rec[0].message.finding.value == 60.0 and rec[0].message.finding.limit == 1e3
    robot = quiet(tr.Robot, rod, [quiet(tr.Tendon, offset=0.01)])
    assert rules(P.input_findings(tr.Scene(robot, tension=[0.0]))) == ["modulus", "modulus"]
    # 207e12 (GPa given as kPa): stiffer than any solid
    with pytest.warns(PW, match=r"Rod.E = 2.07e\+14 Pa is above"):
        tr.Rod(length=0.2, diameter=0.8e-3, E=207e12, G=79.6e9)
    with warnings.catch_warnings():
        warnings.simplefilter("error", PW)
        tr.Rod(length=0.2, diameter=5e-3, E=1e3, G=4e2 * 2.5)  # a hydrogel: at the limit
        tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9)
        tr.Rod(length=0.2, EI=60.0, GJ=23.0, kirchhoff=True)  # rigidities are not judged


# ------------------------------------------------------------------ solution rules
def test_strain_is_the_axial_and_shear_force_over_the_rigidity():
    """A tip force F on a rod whose EA, GA are known: axial strain F_z/EA everywhere
    along a straight rod, shear strain F_x/GA at the clamp (where R = I)."""
    EA = COSS.axial_stiffness
    # the 2.6 kN on the 1.2 mm wire, as tension: 3.8 %, within the default budget (a pure
    # tension: the cold solve's direct try converges, no load continuation)
    sc = tr.Scene(tr.Robot(COSS, []), loads=[tr.PointLoad(s=L13, force=(0, 0, 2600.0))])
    with pytest.warns(PW, match=r"backbone axial strain 3.83 %") as rec:
        sol = tr.solve(sc)
    assert rec[0].filename == __file__
    (f,) = sol.plausibility
    # uniform n3 = 2600 N: the strain is exact to the solver's force tolerance
    assert (f.rule, f.subject) == ("strain", "axial")
    assert f.value == pytest.approx(2600.0 / EA, rel=1e-9)
    ok = tr.Scene(tr.Robot(COSS, []), loads=[tr.PointLoad(s=L13, force=(0, 0, 0.019 * EA))])
    assert quiet(tr.solve, ok).plausibility == ()
    # a Kirchhoff rod: the strain its section would take (the model neglects it)
    kir = tr.Scene(tr.Robot(KIRCH, []), loads=[tr.PointLoad(s=L13, force=(0, 0, 2600.0))])
    (f,) = quiet(tr.solve, kir).plausibility
    # n3 = 2600 N exactly (a straight rod under an axial load): as above
    assert "Kirchhoff" in f.message and f.value == pytest.approx(2600.0 / EA, rel=1e-9)
    # shear: a stiff-in-bending section (explicit rigidities), F_x = 0.03 GA
    rod = tr.Rod(0.1, EI=1e3, GJ=1e3, EA=1e9, GA=1e4)
    sc = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=0.1, force=(300.0, 0, 0))])
    (f,) = quiet(tr.solve, sc).plausibility
    # at the clamp R = I and n = (300, 0, 0) N exactly, by the balance of the whole rod; the
    # largest shear strain is there: 1e-9 for the solver's force tolerance
    assert (f.subject, f.value) == ("shear", pytest.approx(0.03, rel=1e-9))


def test_curl_and_self_intersection_of_exact_circles():
    """A lone tendon under a prescribed tension bends a Kirchhoff rod into a circle of
    angle tau r L / EI.  Beyond 360 deg it curls and crosses itself; just short of 360
    deg its tip comes within 2 R sin(theta/2) of its base (R = L/theta): contact when
    that is less than the diameter."""
    with pytest.warns(PW) as rec:
        sol = tr.solve(circle(400.0))
    assert sol.success and rules(sol.plausibility) == ["curl", "self-intersection"]
    curl = [f for f in sol.plausibility if f.rule == "curl"][0]
    # constant curvature: the trapezoidal bending angle is exact to round-off
    assert curl.value == pytest.approx(math.radians(400.0), rel=1e-9)
    assert any("400 deg" in str(w.message) for w in rec)
    assert quiet(tr.solve, circle(300.0)).plausibility == ()
    for deg, touches in ((358.0, False), (359.5, True)):
        th = math.radians(deg)
        gap = 2 * (L13 / th) * math.sin(th / 2)  # 1.4 mm and 0.35 mm vs d = 1.2 mm
        found = quiet(tr.solve, circle(deg)).plausibility
        assert (rules(found) == ["self-intersection"]) is touches, (deg, gap, found)
        if touches:
            # the closest polyline segments are the first and the last: their distance is
            # the exact gap to the polyline's chord sag, (L/100)^2 / (8 R) ~ 3e-6 m
            assert found[0].value == pytest.approx(gap, abs=5e-6)


def _closest_far_pair(s, position, T):
    """Brute force: the smallest distance between two polyline segments whose turning
    between them is >= 180 deg, every pair measured (no pre-filter)."""
    ia, ib = np.triu_indices(len(s) - 1, 2)
    far = T[ib] - T[ia + 1] >= math.pi
    ia, ib = ia[far], ib[far]
    if ia.size == 0:
        return math.inf
    P_ = position
    return float(PR._segment_distance(P_[ia], P_[ia + 1], P_[ib], P_[ib + 1]).min())


def test_self_intersection_prefilter_loses_no_pair():
    """The rule measures exact distances only for segment pairs whose midpoints are
    within reach: on noisy helices whose turns pass within, near and beyond the
    diameter of each other, it finds exactly what measuring every pair finds; and the
    segment distance agrees with a dense sampling of both segments."""
    rng = np.random.default_rng(1313)
    d, L = 1e-3, 0.3
    seen = {True: 0, False: 0}
    for pitch in np.linspace(0.05e-3, 0.4e-3, 10):  # turns 0.3 to 2.5 mm apart in z
        for _ in range(3):
            phi = np.linspace(0.0, rng.uniform(2.2, 5.0) * math.pi, 151)  # 1.1 to 2.5 turns
            P_ = np.stack([0.02 * np.cos(phi), 0.02 * np.sin(phi), pitch * phi], axis=1)
            P_ += rng.normal(scale=0.1e-3, size=P_.shape)
            s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(P_, axis=0), axis=1))])
            T = phi.copy()  # a helix's tangent turns (about) as its phase
            want = _closest_far_pair(s, P_, T)
            got = PR.self_intersection_finding(s, P_, T, d, L)
            assert (got is not None) is (want < d), (pitch, want, got)
            if got is not None:
                assert got.value == want  # the same pair, the same arithmetic
            seen[want < d] += 1
    # hairpins: an arm, a bend of pi + delta on radius rho, an arm converging on the
    # first; the closest far pairs are barely more than a half turn apart
    for _ in range(30):
        rho, delta, arm = rng.uniform(0.3e-3, 1.5e-3), rng.uniform(0.01, 0.1), 0.01
        s = np.linspace(0.0, 2 * arm + math.pi * rho, 301)
        theta = np.clip((s - arm) / (math.pi * rho), 0.0, 1.0) * (math.pi + delta)
        ds = np.diff(s)
        x = np.concatenate([[0.0], np.cumsum(ds * np.sin(0.5 * (theta[1:] + theta[:-1])))])
        z = np.concatenate([[0.0], np.cumsum(ds * np.cos(0.5 * (theta[1:] + theta[:-1])))])
        P_ = np.stack([x, np.zeros_like(x), z], axis=1)
        want = _closest_far_pair(s, P_, theta)
        got = PR.self_intersection_finding(s, P_, theta, d, L)
        assert (got is not None) is (want < d), (rho, delta, want, got)
        if got is not None:
            assert got.value == want
        seen[want < d] += 1
    assert seen[True] >= 10 and seen[False] >= 10
    # the segment distance against a dense sampling of two skew segments: the sampled
    # minimum is an upper bound within (segment length / 400) of the true one
    for _ in range(20):
        p0, p1, q0, q1 = rng.normal(size=(4, 1, 3))
        exact = float(PR._segment_distance(p0, p1, q0, q1)[0])
        t = np.linspace(0.0, 1.0, 401)[:, None]
        a, b = p0 + t * (p1 - p0), q0 + t * (q1 - q0)
        sampled = np.linalg.norm(a[:, None, :] - b[None, :, :], axis=2).min()
        slack = (np.linalg.norm(p1 - p0) + np.linalg.norm(q1 - q0)) / 400
        assert exact <= sampled + 1e-12 and sampled - exact <= slack


def test_tension_rule_measures_how_close_a_tendon_comes_to_the_centre_of_curvature():
    """A lone parallel tendon at a free tip bends the rod to kappa = tau r / EI: r kappa is
    the tension over EI/r^2, the rule.  A converging tendon is tilted by its slope
    a, so at the base r kappa = x solves x = (tau r^2/EI) (1 - x) / sqrt(a^2 + (1 - x)^2)
    (moment balance of the distal part): 1.4 EI/r^2 takes it to only 0.914 of the way."""
    found = quiet(tr.solve, circle(0.95 * 180 / math.pi * L13 / R5)).plausibility  # 0.95 EI/r^2
    (f,) = [f for f in found if f.rule == "tension"]
    # a circle: r kappa = tau r^2 / EI = 0.95 at every node, to the solver's tolerance (1e-10)
    assert f.value == pytest.approx(0.95, rel=1e-9) and f.subject == "tendon 0"
    assert "tension" not in rules(
        quiet(tr.solve, circle(0.85 * 180 / math.pi * L13 / R5)).plausibility
    )
    r, L = 0.01, ROD11.length
    E11 = ROD11.bending_stiffness
    for k, fires in ((1.2, False), (1.4, True)):
        sc = tr.Scene(
            tr.Robot(ROD11, [tr.Tendon.converging(offset=r, length=L)]), tension=[k * E11 / r**2]
        )
        sol = quiet(tr.solve, sc)
        x = optimize.brentq(lambda x: x - k * (1 - x) / math.hypot(r / L, 1 - x), 0, 1, xtol=1e-15)
        got = [f for f in sol.plausibility if f.rule == "tension"]
        assert bool(got) is fires, (k, x, got)
        if fires:
            # 0.9138 at the base (the largest r kappa): x is exact to 1e-15 (brentq), the
            # solver's base moment to its tolerance 1e-10: 1e-9 leaves room
            assert got[0].value == pytest.approx(x, rel=1e-9)


def test_antagonistic_tension_is_not_a_slip():
    """The paper's Fig. 11(c): three stiff tendons, bent 90 deg, out-of-plane 0.5 N.  They
    pull against each other at about EI/r^2 (127 N), yet bend the backbone only to
    r kappa ~ 0.16: the literal 'tension within 10 % of EI/r^2' would cry wolf here."""
    from tendonrod.paper import studies

    with warnings.catch_warnings():
        warnings.simplefilter("error", PW)
        d = studies.out_of_plane_comparison()
    assert max(d[("tension", 50e3)]) > 0.9 * 120.0


# ------------------------------------------------------------------ entry points, floods
def _ramp():
    """Tension-controlled curls from 300 to 420 deg: the same solution at every entry
    point (no warm-start history matters for a tension-controlled lone tendon)."""
    base = circle(300.0)
    taus = np.linspace(1.0, 1.4, 13) * base.tension[0]
    return base, taus


def test_every_entry_point_finds_the_same():
    base, taus = _ramp()
    scenes = [tr.Scene(base.robot, tension=[t]) for t in taus]
    one = [quiet(tr.solve, s).plausibility for s in scenes]
    prob = tr.Problem(base)
    pro = [quiet(prob.solve, s).plausibility for s in scenes]
    bat = quiet(tr.solve_batch, base, tension=taus[:, None]).plausibility
    swp = quiet(tr.sweep, base, {"tension[0]": taus}, progress=False).plausibility  # batch path
    per = quiet(  # a measure of its own: the per-point path
        tr.sweep, base, {"tension[0]": taus}, measure=lambda s, x: tip_measure(s, x), progress=False
    ).plausibility
    assert any(one) and not all(one)  # both sides of 360 deg
    for k in range(len(taus)):
        want = [(f.rule, f.subject) for f in one[k]]
        for other in (pro[k], bat[k], swp[k], per[k]):
            assert [(f.rule, f.subject) for f in other] == want
            # the values (a curl in rad, a gap in m) from solutions that agree to the solver's
            # tolerance, 1e-10 of L in position: 1e-9 absolute leaves room
            for a, b in zip(other, one[k]):
                assert abs(a.value - b.value) <= 1e-9, (k, a, b)


def test_problem_warns_when_its_values_turn_implausible():
    """A Problem screens every solve: a curl of 300 deg stays silent, and the same
    Problem with the tension of a 400 deg curl warns (curl and self-intersection), the
    screen run on the new values, not kept from the first solve."""
    base, taus = _ramp()
    prob = tr.Problem(base)
    with warnings.catch_warnings():
        warnings.simplefilter("error", PW)
        assert prob.solve().plausibility == ()
    with pytest.warns(PW) as rec:
        sol = prob.solve(tr.Scene(base.robot, tension=[taus[-1]]))
    assert {f.rule for f in sol.plausibility} == {"curl", "self-intersection"}
    assert len([w for w in rec if issubclass(w.category, PW)]) == 2


def test_many_points_give_one_warning_per_rule():
    base, taus = _ramp()
    taus = np.repeat(taus[-3:], 40)  # 120 points, all beyond 360 deg
    with pytest.warns(PW) as rec:
        res = tr.sweep(base, {"tension[0]": taus}, progress=False)
    texts = [str(w.message) for w in rec if issubclass(w.category, PW)]
    assert len(texts) == 2, texts  # curl and self-intersection, each once
    assert all("120 of 120 points" in t and "SweepResult.plausibility" in t for t in texts)
    assert all(w.filename == __file__ for w in rec)
    assert len(res.plausibility[0]) == 2
    with pytest.warns(PW) as rec:
        tr.solve_batch(base, tension=taus[:, None])
    assert len([w for w in rec if issubclass(w.category, PW)]) == 2
    # a Problem warns once per rule for its life; tr.solve at every call
    prob = tr.Problem(base)
    with pytest.warns(PW) as rec:
        for t in taus[:10]:
            prob.solve(tr.Scene(base.robot, tension=[t]))
    assert len(rec) == 2 and all(w.filename == __file__ for w in rec)
    with pytest.warns(PW) as rec:
        for t in taus[:3]:
            tr.solve(tr.Scene(base.robot, tension=[t]))
    assert len(rec) == 6


def test_sensible_scenes_stay_silent(rod):
    """The README's robot, the paper's Fig. 11 and 17 robots under their loads."""
    robot = tr.Robot(rod, [tr.Tendon(offset=0.01, angle=0.0)])
    with warnings.catch_warnings():
        warnings.simplefilter("error", PW)
        for f in np.linspace(0.0, 1.0, 11):
            sc = tr.Scene(
                robot, displacement=[0.0157], loads=[tr.PointLoad(s=0.2, force=(0, 0, -f))]
            )
            tr.solve(sc)
        three = tr.Robot(
            ROD11, [tr.Tendon(offset=0.01, angle=2 * math.pi * i / 3) for i in range(3)]
        )
        sc = tr.Scene(
            three,
            displacement=[0.015, None, None],
            tension=[None, 0.5, 0.5],
            loads=[tr.PointLoad(s=0.1, force=(0.3, 0.3, -0.3))],
        )
        assert tr.solve(sc).success


def test_the_bounds_never_hide_a_finding():
    """Where the load/tension bounds say no rule can fire, reading the states finds
    nothing either; checked on scenes that straddle every limit (strain, curl, a half
    turn, the tension rule), with loads, sloped and off-tip tendons, both backbones."""
    cases = []
    ea = COSS.axial_stiffness
    short = tr.Robot(KIRCH, [tr.Tendon(offset=0.01, end=0.01)])  # r kappa = tau r^2 / EI
    sloped = tr.Robot(
        COSS, [tr.Tendon(offset=R5, slope=-0.01, end=0.2), tr.Tendon(offset=R5, angle=math.pi)]
    )
    for k in np.linspace(0.5, 1.5, 6):
        cases.append(circle(300.0 * k))  # curls from 150 to 450 deg
        cases.append(circle(150.0 * k))  # around the half turn
        cases.append(tr.Scene(short, tension=[0.75 * k * EI / 0.01**2]))  # r kappa 0.375..1.1
        cases.append(
            tr.Scene(tr.Robot(COSS, []), loads=[tr.PointLoad(s=L13, force=(0, 0, 0.02 * ea * k))])
        )
        cases.append(
            tr.Scene(
                sloped,
                displacement=[0.004 * k, None],
                tension=[None, 0.5],
                loads=[tr.PointLoad(s=0.1, force=(0.2 * k, 0.1, 0), moment=(0, 0.01 * k, 0))],
            )
        )
    checked = found = 0
    for sc in cases:
        sol = quiet(tr.solve, sc)
        if not sol.success:
            continue
        rec = Recorder(sc, sol.options).record(sol.unknowns, sol.formulation.steps)
        forced = _state_findings(sc.robot, rec, sol.tension.tolist())
        clear = PR.screen_clear(_scene_screen(sc), sol.tension.tolist())
        if clear:
            assert forced == [], (sc, forced)
            checked += 1
        else:  # what a solve reports is what the states say
            assert rules(sol.plausibility) == rules(list(P.input_findings(sc)) + forced)
            found += bool(forced)
    assert checked >= 10 and found >= 5  # both sides of the limits were visited


def test_sweep_file_keeps_the_findings(tmp_path):
    """A sweep written to a file and resumed from it has the same findings (and warns
    the same summary)."""
    base, taus = _ramp()
    path = tmp_path / "sweep.jsonl"
    with pytest.warns(PW):
        a = tr.sweep(base, {"tension[0]": taus}, file=path, chunksize=4, progress=False)
    with pytest.warns(PW) as rec:
        b = tr.sweep(base, {"tension[0]": taus}, file=path, chunksize=4, progress=False)
    assert len(rec) == 2
    assert [tuple(x) for x in b.plausibility] == [tuple(x) for x in a.plausibility]
    assert any(a.plausibility) and isinstance(b.plausibility[-1][0], P.Finding)
