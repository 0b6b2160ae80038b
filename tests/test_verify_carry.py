"""The step verification carried between warm solves (Options.steps = 0).

A warm solve that ends close to a solution whose step count was verified by step
doubling does not verify again: the verification's estimate e_v, grown by
2 (1 + delta)^(p+1) for a relative move delta of the scaled unknowns, bounds the
truncation error (csrc/tr_verify.c, tr_verify_carried).  Checked here against what is
known independently: the growth of an independent step doubling of the tip (two
fixed-step solves at N and 2N steps) must stay within the growth the bound claims, and
the tip must agree with a tight adaptive reference as well as a verified solve's does.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import tendonrod as tr

REF = tr.Options(integrator="adaptive", rtol=1e-13, tol=1e-12)
TOL = tr.Options().tol


def fig11c():
    """Fig. 11c: three tendons at 10 mm, the first retracted by r pi/2, out-of-plane tip
    load (spatial formulation)."""
    rod = tr.Rod(0.1, 1.04e-3, 210e9, 80e9, kirchhoff=True)
    r = 0.01
    EA = 50.0 * 3 * rod.bending_stiffness / r**2
    tendons = [tr.Tendon(offset=r, angle=2 * math.pi * i / 3, EA=EA) for i in range(3)]
    return tr.Scene(
        tr.Robot(rod, tendons),
        displacement=[r * math.pi / 2 * 0.9, 0.0, 0.0],
        loads=[tr.PointLoad(s=0.1, force=(0.0, 0.5, 0.0))],
    )


def fig11a():
    """Fig. 11a: one tendon at 10 mm retracted to a ~90 deg bend, transverse tip load
    (planar formulation)."""
    rod = tr.Rod(0.1, 1.04e-3, 210e9, 80e9, kirchhoff=True)
    return tr.Scene(
        tr.Robot(rod, [tr.Tendon(offset=0.01)]),
        displacement=[0.01 * math.pi / 2],
        loads=[tr.PointLoad(s=0.1, force=(-1.0, 0.0, 0.0))],
    )


def with_load(scene, factor):
    ld = scene.loads[0]
    return dataclasses.replace(
        scene, loads=[dataclasses.replace(ld, force=tuple(factor * np.asarray(ld.force)))]
    )


def doubling_tip(scene, steps):
    """Independent step doubling of the tip: |tip(N) - tip(2N)| / L / (1 - 2^-8), the
    tip part of what the core's verification estimates (rk8, order 8)."""
    fine = tr.Options(steps=steps, tol=1e-12)
    coarse = tr.solve(scene, options=fine, strict=True).tip_position
    double = tr.solve(scene, options=tr.Options(steps=2 * steps, tol=1e-12), strict=True)
    return np.linalg.norm(coarse - double.tip_position) / scene.robot.rod.length / (1 - 2**-8)


@pytest.mark.parametrize("make", [fig11c, fig11a], ids=["fig11c-spatial", "fig11a-planar"])
def test_carried_bound_is_honest_along_a_sweep(make):
    """A Problem swept over a tip load from 1x to 2x in 2.5 % steps: most solves carry the
    verification (that is the saving), some re-verify (the drift is bounded).  At every
    carried point the truncation measured independently (the tip's step doubling) grew
    from the verification point by no more than the carried bound grew from the
    verification's estimate; and the tip error against the adaptive reference is as
    small as at verified points."""
    scene = make()
    L = scene.robot.rod.length
    prob = tr.Problem(scene)
    carried, verified, last = [], [], None
    for f in np.linspace(1.0, 2.0, 41):
        sc = with_load(scene, f)
        sol = prob.solve(sc, strict=True)
        assert sol.truncation_estimate <= TOL
        err = np.linalg.norm(sol.tip_position - tr.solve(sc, options=REF).tip_position) / L
        steps = sol.formulation.steps
        if sol.truncation_carried:
            sc_v, sol_v, dbl_v = last
            assert steps == sol_v.formulation.steps
            grown = doubling_tip(sc, steps) / dbl_v
            assert grown <= sol.truncation_estimate / sol_v.truncation_estimate, (f, grown)
            carried.append(err)
        else:
            last = (sc, sol, doubling_tip(sc, steps))
            verified.append(err)
    assert len(carried) >= 10 and len(verified) >= 2, (len(carried), len(verified))
    # tip errors: truncation (<= tol scaled) plus the residual tolerance's share; a
    # carried solve is as accurate as a verified one up to a factor 3 (the errors are
    # themselves at the 1e-11 level, where that is round-off of the comparison)
    assert max(carried) <= max(3 * max(verified), 2 * TOL), (max(carried), max(verified))


def test_a_far_jump_verifies_again():
    """From 1x to 3x the load in one warm solve the unknowns move far: no carry.  (At 4x
    the planar state is unstable out of its plane: lateral buckling, C_yy < 0.)"""
    scene = fig11a()
    prob = tr.Problem(scene)
    prob.solve(strict=True)
    sol = prob.solve(with_load(scene, 3.0), strict=True)
    assert not sol.truncation_carried
    assert sol.truncation_estimate <= TOL


def test_carry_needs_the_same_structure_and_a_verification():
    """A guess from a scene of another structure (another rod), a cold solve and fixed
    steps never carry; a guess of the same structure does (tr.solve, not only Problem)."""
    scene = fig11a()
    base = tr.solve(scene, strict=True)
    near = with_load(scene, 1.02)
    assert tr.solve(near, guess=base, strict=True).truncation_carried
    stiffer = dataclasses.replace(
        near,
        robot=dataclasses.replace(
            near.robot, rod=tr.Rod(0.1, 1.05e-3, 210e9, 80e9, kirchhoff=True)
        ),
    )
    assert not tr.solve(stiffer, guess=base, strict=True).truncation_carried
    prob = tr.Problem(scene)
    prob.solve(strict=True)
    assert not prob.solve(near, guess="cold", strict=True).truncation_carried
    fixed = tr.solve(near, guess=base, options=tr.Options(steps=6), strict=True)
    # fixed steps report their own step-doubling estimate (never a carried bound)
    assert not fixed.truncation_carried and fixed.truncation_estimate > 0


@pytest.mark.parametrize("via", ["problem", "guess"])
def test_a_prescribed_tension_is_part_of_the_record(via, rod):
    # a helical tendon's tension turns the robot while the unknowns (the base reaction,
    # which balances the external loads: none here) stay near 0: the record of the
    # straight robot (2 steps, exact there) must not vouch for the turned one
    robot = tr.Robot(rod, [tr.Tendon.helical(0.01, turns=1.0, length=0.2)])
    straight = tr.Scene(robot, tension=[0.0])
    prob = tr.Problem(straight)
    first = prob.solve()
    for t in (1.0, 3.0):
        scene = tr.Scene(robot, tension=[t])
        sol = prob.solve(scene) if via == "problem" else tr.solve(scene, guess=first)
        ref = tr.solve(scene, options=tr.Options(tol=1e-12))
        assert sol.success and not sol.truncation_carried
        # the solve's tolerance 1e-10 (scaled): 1e-9 L with a margin
        assert np.max(np.abs(sol.tip_position - ref.tip_position)) <= 1e-9 * 0.2
    # a record without the values it was measured at does not vouch for such a model
    raw = first.raw
    out = prob._c.solve(
        guess=raw["base_state"],
        verified=(
            int(raw["formulation"]["steps"]),
            raw["verified_estimate"],
            raw["verified_unknowns"],
        ),
    )
    assert not out["truncation_carried"]
