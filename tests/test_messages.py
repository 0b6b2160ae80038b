"""Failure messages that say what happened: no advice about a guess nobody gave, no
claim that a push decided a side the answer did not take, and the scene's size in the
rod's own units (how far out it is)."""

import math
import re
import warnings

import numpy as np
import pytest

import tendonrod as tr

ROD = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
L = ROD.length
EI = ROD.bending_stiffness


def _quiet_solve(scene, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tr.ConvergenceWarning)
        return tr.solve(scene, **kw)


def test_a_cold_solve_does_not_advise_dropping_a_guess():
    """A tendon pulled by twice the rod's length has no equilibrium; the cold start's
    residual is not finite, and the message must not tell to "try no guess"."""
    scene = tr.Scene(tr.Robot(ROD, [tr.Tendon(offset=0.01)]), displacement=[2 * L])
    sol = _quiet_solve(scene)
    assert not sol.success
    assert "try no guess" not in sol.message, sol.message


def test_a_cause_met_directly_and_along_the_load_path_is_said_once():
    """Three tendons under a hopeless tip load (1e6 N and 1e3 N m): the direct solve and
    the load path fail for the same reason, which the message gives once, not twice."""
    rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9)
    robot = tr.Robot(rod, tr.Tendon.ring(3, 0.01))
    load = tr.PointLoad(s=0.2, force=(1e6, -1e6, 1e6), moment=(1e3, 0.0, 0.0))
    sol = _quiet_solve(tr.Scene(robot, displacement=[0.01, 0.0, 0.0], loads=[load]))
    assert not sol.success
    clauses = [c.strip() for c in re.split(r"[;(]", sol.message) if len(c.strip()) > 20]
    repeated = {c for c in clauses if clauses.count(c) > 1}
    assert not repeated, sol.message


def test_a_perfect_column_names_no_side_it_did_not_take():
    """At 3 P_E the perfect column buckles to one side; a message that names the
    symmetry-breaking push as deciding the side must name the side the answer took."""
    P = math.pi**2 * EI / (4 * L**2)
    scene = tr.Scene(tr.Robot(ROD, []), loads=[tr.PointLoad(s=L, force=(0, 0, -3 * P))])
    sol = tr.solve(scene)
    assert sol.success, sol.message
    m = re.search(r"world direction \(([-\d.]+), ([-\d.]+), ([-\d.]+)\)", sol.message)
    assert m, sol.message
    u = np.array([float(x) for x in m.groups()])
    took_its_side = float(u @ sol.tip_position) > 0.0
    assert took_its_side or "broke the symmetry" not in sol.message, (
        sol.tip_position,
        sol.message,
    )


def test_a_failure_gives_the_scene_in_the_rods_units():
    """A tip force of 1e4 EI/L^2 and a tension of 0.5 EI/r^2: the warning says both, with
    the units in N, computed here from the scene alone."""
    r = 0.01
    F = 1e4 * EI / L**2
    tau = 0.5 * EI / r**2
    scene = tr.Scene(
        tr.Robot(ROD, [tr.Tendon(offset=r)]),
        tension=[tau],
        loads=[tr.PointLoad(s=L, force=(F, 0.0, -F))],
    )
    with pytest.warns(tr.ConvergenceWarning) as rec:
        sol = tr.solve(scene, options=tr.Options(max_work=1e5))
    assert not sol.success
    text = str(rec[-1].message)
    # |F| = sqrt(2) 1e4 EI/L^2; printed to 3 significant digits
    assert f"the largest load {math.sqrt(2) * 1e4:.3g} EI/L^2 (EI/L^2 = {EI / L**2:.3g} N)" in text
    # the last iterate's tension of a tension-controlled tendon is the prescribed one
    assert f"tension {0.5:.3g} EI/r^2 (tendon 0, r = 0.01 m: EI/r^2 = {EI / r**2:.3g} N)" in text


def test_compliance_and_actuate_failures_give_the_scene_in_the_rods_units():
    """The same note on the ConvergenceError of tr.compliance and the message of a failed
    tr.actuate: a tip force of 2e4 EI/L^2 the work budget cannot solve."""
    F = 2e4 * EI / L**2
    scene = tr.Scene(
        tr.Robot(ROD, [tr.Tendon(offset=0.01)]),
        tension=[0.0],
        loads=[tr.PointLoad(s=L, force=(F, 0.0, 0.0))],
    )
    want = f"the largest load {2e4:.3g} EI/L^2 (EI/L^2 = {EI / L**2:.3g} N)"
    with pytest.raises(tr.ConvergenceError) as e:
        tr.compliance(scene, options=tr.Options(max_work=1e5))
    assert want in str(e.value), str(e.value)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tr.ConvergenceWarning)
        sol = tr.actuate(scene, tip_angle=0.1, options=tr.Options(max_work=1e5))
    assert not sol.success and want in sol.message, sol.message
