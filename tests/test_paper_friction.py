"""The friction study on the Sec. V prototype (tendonrod.paper.friction), against what is
known without it:
- mu = 0 is the frictionless prototype of tendonrod.paper.prototype, actuated and loaded
  by hand with the plain API;
- a small mu moves every curve by O(mu) (first order: doubling mu doubles the change);
- static friction's band contains the frictionless state at the same locked displacement
  (the frictionless tension profile lies between the two capstan extremes);
- an inextensible parallel tendon on a Kirchhoff rod fixes the tip angle at q / r
  whatever the friction (the channel's length is L - r theta_tip);
- at q = 0 the tendon carries no tension, so the hysteresis loop closes there;
- the sign conventions: pulling needs more tension than releasing; an axial load down
  the base axis slackens the locked tendon and deflects the tip along it.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import tendonrod as tr
from tendonrod.paper import PROTOTYPE, actuate, friction, tip_angle
from tendonrod.paper.prototype import _prototype_robot

TH30, TH60 = friction.TIP_ANGLES


@pytest.fixture(scope="module")
def study():
    return friction.axial_load_study()


@pytest.fixture(scope="module")
def hysteresis():
    return friction.actuation_hysteresis(n=11)


def test_frictionless_curve_is_the_plain_prototype(study):
    # built independently: the prototype module's robot (no friction field at all)
    robot = _prototype_robot("parallel")
    for theta, band in study.items():
        act = actuate(robot, theta)
        rec = band[0.0]
        # the same calls on an equal robot (friction 0 compiles to the same problem,
        # bitwise): the same number
        assert rec["q"] == act.displacements[0]
        for F, tip in zip(band["forces"], rec["none"]["tip"]):
            load = tr.PointLoad(s=PROTOTYPE.L, force=(0.0, 0.0, -F))
            sol = tr.solve(tr.Scene(robot, displacement=[rec["q"]], loads=[load]))
            # mu = 0 compiles to the frictionless problem; the study warm-starts along
            # the load ramp and this solve starts cold: equal to the solver tolerance
            # (1e-10 scaled), 1e-9 of L is ample
            assert np.max(np.abs(tip - sol.tip_position)) <= 1e-9 * PROTOTYPE.L


def test_small_friction_is_first_order():
    # deflections at 0.5 N, 60 deg: (mu, 2 mu) changes from the frictionless curve
    d = friction.axial_load_band(TH60, frictions=(1e-4, 2e-4), forces=(0.0, 0.5))
    free = d[0.0]["none"]["deflection"][-1]
    for sliding in ("in", "out"):
        d1 = d[1e-4][sliding]["deflection"][-1] - free
        d2 = d[2e-4][sliding]["deflection"][-1] - free
        assert abs(d1) > 0.0  # friction does act
        # linear to O(mu^2): the ratio is 2 within ~mu (1e-4) relative; 1e-2 leaves room
        # for the solver's 1e-10 in a difference of ~1e-6 m
        assert abs(d2 / d1 - 2.0) < 1e-2


def test_band_contains_the_frictionless_state_at_the_same_displacement(study):
    free_robot = friction.friction_robot(0.0)
    for theta, band in study.items():
        for mu in band["frictions"]:
            rec = band[mu]
            z_in, z_out = rec["in"]["tip"][:, 2], rec["out"]["tip"][:, 2]
            for i, F in enumerate(band["forces"]):
                load = tr.PointLoad(s=PROTOTYPE.L, force=(0.0, 0.0, -F))
                z = tr.solve(
                    tr.Scene(free_robot, displacement=[rec["q"]], loads=[load])
                ).tip_position[2]
                # slid in the tip sits lower (more bent), slid out higher; the margins
                # are >= 1e-5 m at mu = 0.05, far above the solver's 1e-10 scaled tolerance
                assert z_in[i] < z < z_out[i], (theta, mu, F)


def test_band_widens_with_friction_and_more_at_60_than_at_30(study):
    rel = {}
    for theta, band in study.items():
        free = band[0.0]["none"]["deflection"][-1]
        widths = [
            band[mu]["in"]["deflection"][-1] - band[mu]["out"]["deflection"][-1]
            for mu in band["frictions"]
        ]
        assert np.all(np.diff(widths) > 0) and widths[0] > 0
        rel[theta] = np.array(widths) / free
    # the paper's observation (Fig. 25): friction matters more at 60 deg than at 30 deg
    assert np.all(rel[TH60] > rel[TH30])


def test_axial_load_slackens_and_deflects(study):
    for band in study.values():
        for mu in (0.0, *band["frictions"]):
            for key in ("none",) if mu == 0.0 else ("in", "out"):
                br = band[mu][key]
                # the load bends the robot further toward its tendon: the locked tendon's
                # tension falls (the paper: "such that tendon slack could develop") and
                # the tip moves down the base axis, more with every load step
                assert np.all(np.diff(br["tension"]) < 0) and br["tension"][-1] > 0
                assert np.all(np.diff(br["deflection"]) > 0)
        # the actuated state is the reference: the sliding-in edge starts at 0 (the same
        # scene solved twice, once warm from the actuation: equal to the solver's 1e-10
        # scaled tolerance; 1e-9 of L is ample)
        for mu in band["frictions"]:
            assert abs(band[mu]["in"]["deflection"][0]) < 1e-9 * PROTOTYPE.L
            # pulled with the tendon sliding in: the unloaded tip angle is the target
            # (actuate's tolerance 1e-11 rad; 1e-9 for the repeated solve)
            assert abs(band[mu]["in"]["theta"][0] - band["theta"]) < 1e-9


def test_hysteresis_loop_closes_at_zero_and_orders(hysteresis):
    h = hysteresis
    free = h[0.0]["none"]
    for mu in h["frictions"]:
        b_in, b_out = h[mu]["in"], h[mu]["out"]
        # q = 0: the tendon is exactly taut with no tension, nothing to rub: straight
        # (1e-9 rad: the solver's 1e-10 scaled tolerance, with room)
        for b in (b_in, b_out):
            assert abs(b["theta"][0]) < 1e-9 and abs(b["tension"][0]) < 1e-9
            assert np.all(np.diff(b["theta"]) > 0)  # more displacement, more bend
        # pulling needs more tension than the frictionless tendon, releasing holds less
        assert np.all(b_in["tension"][1:] > free["tension"][1:])
        assert np.all(free["tension"][1:] > b_out["tension"][1:])
        # the tip angle: the stretch follows the tensions, so pulling bends a little less
        assert np.all(b_in["theta"][1:] < free["theta"][1:])
        assert np.all(free["theta"][1:] < b_out["theta"][1:])
    # the frictionless robot is actuated to theta_max at the last q (actuate's tolerance)
    assert abs(free["theta"][-1] - h["theta_max"]) < 1e-9


def test_inextensible_tendon_fixes_the_tip_angle():
    # channel length L - r theta_tip = L - q for an inextensible parallel tendon on a
    # Kirchhoff rod, whatever the tension profile: no hysteresis in the tip angle
    stiff = dataclasses.replace(PROTOTYPE, k_parallel=math.inf)
    h = friction.actuation_hysteresis(frictions=(0.3,), n=5, proto=stiff)
    for b in (h[0.0]["none"], h[0.3]["in"], h[0.3]["out"]):
        # 1e-9 rad: the length constraint is solved to the 1e-10 scaled tolerance
        assert np.max(np.abs(b["theta"] - h["q"] / PROTOTYPE.r)) < 1e-9
    # but friction still moves the bending along s (the tips differ by millimetres)
    assert abs(h[0.3]["in"]["tip"][-1, 0] - h[0.3]["out"]["tip"][-1, 0]) > 1e-3


def _rest_to_anchor_by_chords(sol, EA, n=401):
    """The tendon's rest length from each of n channel points to the anchor, from the
    solver's positions of the tendon path p + R r by the chord rule: independent of the
    recording pass's rest-length state that tendonrod.slip reads."""
    r = np.array([PROTOTYPE.r, 0.0, 0.0])
    s = np.linspace(0.0, PROTOTYPE.L, n)
    st = sol.at(s)
    pts = st.position + np.einsum("nij,j->ni", st.rotation, r)
    tau = st.tendon_tension[:, 0]
    seg = np.linalg.norm(np.diff(pts, axis=0), axis=1) / (1.0 + 0.5 * (tau[1:] + tau[:-1]) / EA)
    return s, np.append(np.cumsum(seg[::-1])[::-1], 0.0)


def test_loading_slips_the_tendon_out():
    d = friction.loading_slip(TH60)
    check, s, slip = d["check"], d["s"], d["slip"]
    # loading the locked robot slides the tendon out (toward the anchor) inside the channel,
    # against the "in" edge it was solved on: the check says so
    assert not check.consistent and check.conflicts[0][0] == 0
    inner = (s > 0.05 * PROTOTYPE.L) & (s < 0.95 * PROTOTYPE.L)
    assert np.all(slip[inner] < -1e-5)
    assert slip[-1] == 0.0  # the anchor does not slip
    # the same slip from the chord rule on the solved tendon paths: where the material that
    # now lies between s and the anchor sat unloaded (the chord rule's error, kappa^2 h^2/24
    # relative over the path, ~1e-8 m at 401 points, and the recording pass's 1e-9 set the
    # 1e-7 m tolerance)
    robot = friction.friction_robot(0.1)
    EA = robot.tendons[0].EA
    load = tr.PointLoad(s=PROTOTYPE.L, force=(0.0, 0.0, -0.5))
    sol0 = tr.solve(tr.Scene(robot, displacement=[d["q"]], sliding="in"))
    sol1 = tr.solve(tr.Scene(robot, displacement=[d["q"]], sliding="in", loads=[load]))
    s0, Y0 = _rest_to_anchor_by_chords(sol0, EA)
    s1, Y1 = _rest_to_anchor_by_chords(sol1, EA)
    s_ref = np.interp(Y0[-1] - Y1, Y0[-1] - Y0, s0)  # where Y1(s) of material sat unloaded
    expect = np.interp(s, s1, s_ref - s1)
    assert np.max(np.abs(slip[s <= 0.999 * PROTOTYPE.L] - expect[s <= 0.999 * PROTOTYPE.L])) < 1e-7
    # and the locked displacement reaches the angle the band starts from
    assert abs(tip_angle(sol0) - TH60) < 1e-9
