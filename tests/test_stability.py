"""The stability verdict (`Solution.stable`, `.stability`, `.stability_index`) against
what is known exactly: the Euler cantilever (the straight state's margin and the number
of its unstable modes at any compressive load), a tendon along the centre line (which
compresses the rod without destabilising it, unlike the same dead load), the paper's
Fig. 17 robot on both sides of its slack switch, the post-buckled cantilever (stable up to
an exact symmetry), and the load that the test cannot judge.  The straight states above
the Euler load are unstable: they are judged with ``Options(accept_unstable=True)``; the
default solve returns the stable buckled state instead (test_stable_branch.py).

The exact margin of the straight cantilever under a compressive dead load P, in the norm
(1/L) int |dtheta|^2 ds and scaled by EI/L, is (pi^2/4)(1 - P/P_E) for the first bending
mode; the torsional mode is (pi^2/4) GJ/EI whatever P; the bending modes below zero are two
per kL in (pi/2 + j pi) (two planes), k = sqrt(P/EI).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import tendonrod as tr

ROD = dict(length=0.25, diameter=1.2e-3, E=60e9, G=23e9)
ANY = tr.Options(accept_unstable=True)  # judge whatever equilibrium the solve reaches


def euler(kirchhoff=True):
    rod = tr.Rod(**ROD, kirchhoff=kirchhoff)
    EI, L = rod.bending_stiffness, rod.length
    return rod, math.pi**2 * EI / (4 * L**2)


def column(rod, P, side=0.0):
    return tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=rod.length, force=(side, 0.0, -P))])


def exact_index(f):
    """Bending modes below zero of the straight column at P = f P_E: two per odd multiple
    of pi/2 below kL = (pi/2) sqrt(f)."""
    kL = 0.5 * math.pi * math.sqrt(f)
    return 2 * sum(1 for j in range(100) if (0.5 + j) * math.pi < kL)


@pytest.mark.parametrize("kirchhoff", [True, False], ids=["kirchhoff", "cosserat"])
@pytest.mark.parametrize("f", [0.5, 0.95, 1.05, 3.0, 10.0, 41.0])
def test_euler_column_margin_and_index(kirchhoff, f):
    """Stable below the Euler load, unstable above, the margin on the exact first mode and
    the count of unstable modes exact.  Tolerance 2e-3 (1 + |margin|): the 24-element
    discretisation is second order (measured 4e-4 to 1.9e-3 of that scale at these loads;
    bench/results/stability_design.md); shear and extension of the Cosserat rod shift the
    Euler load by ~EI/(GA L^2) ~ 1e-6."""
    rod, Pe = euler(kirchhoff)
    sol = tr.solve(column(rod, f * Pe), options=ANY, strict=True)
    assert np.allclose(sol.tip_position[:2], 0.0, atol=1e-12)  # the straight state
    exact = (math.pi**2 / 4) * (1 - f)
    assert sol.stable is (f < 1), sol.stability_reason
    assert abs(sol.stability - exact) <= 2e-3 * (1 + abs(exact)), (sol.stability, exact)
    assert sol.stability_index == exact_index(f)


def test_centre_line_tendon_compresses_without_destabilising():
    """A tendon through the centre line at 5 P_E leaves the rod as stable as unloaded (the
    tendon's pull and its pressure on the duct cancel for every shape): the margin is the
    unloaded cantilever's first mode, here torsion, (pi^2/4) GJ/EI; the same force as a
    dead load buckles it."""
    rod, Pe = euler()
    tendon = tr.Scene(tr.Robot(rod, [tr.Tendon(offset=0.0)]), tension=[5 * Pe])
    sol = tr.solve(tendon, strict=True)
    torsion = (math.pi**2 / 4) * rod.torsional_stiffness / rod.bending_stiffness
    assert sol.stable is True
    # the torsional mode is discretised like the bending one (2e-3 as above)
    assert abs(sol.stability - torsion) <= 2e-3 * (1 + torsion), (sol.stability, torsion)
    dead = tr.solve(column(rod, 5 * Pe), options=ANY, strict=True)
    assert dead.stable is False and dead.stability_index == exact_index(5.0)


def fig17(F):
    rod = tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True)
    r = 0.01
    return tr.Scene(
        tr.Robot(rod, [tr.Tendon(offset=r)]),
        displacement=[r * math.pi / 2],
        loads=[tr.PointLoad(s=0.2, force=(0, 0, -F))],
    )


@pytest.mark.parametrize("F", [0.2, 0.35, 0.36, 0.5])
def test_fig17_stable_on_both_sides_of_the_slack_switch(F):
    """The paper's Fig. 17 robot under a compressive tip load, taut below 0.35768 N and
    slack above: stable on both sides (the switch is a kink of the load path, not a loss
    of stability).  On the slack side the rod is isotropic and its load on the base
    tangent, so the bent shape may turn about the vertical: an exact zero mode, reported
    as neutral (a margin at round-off, below 1e-7)."""
    sol = tr.solve(fig17(F), strict=True)
    assert sol.stable is True, sol.stability_reason
    if F > 0.35768:
        assert sol.slack[0] > 0 and abs(sol.stability) <= 1e-7
        assert "neutral" in sol.stability_reason
    else:
        assert sol.tension[0] > 0 and sol.stability > 0.01


def test_post_buckled_cantilever_is_stable_and_the_straight_one_not():
    """At 1.5 P_E: the buckled branch, reached by ramping the load with a small side force
    that is then removed, is stable (neutral about the vertical: an exact symmetry); the
    straight state that a cold solve returns is unstable with two modes (both planes)."""
    rod, Pe = euler()
    prob = tr.Problem(column(rod, 0.5 * Pe, side=1e-3))
    for f in np.linspace(0.5, 1.5, 21):
        sol = prob.solve(column(rod, f * Pe, side=1e-3 if f < 1.2 else 0.0), strict=True)
    assert sol.tip_position[0] > 0.1 * rod.length  # buckled
    assert sol.stable is True, sol.stability_reason
    straight = tr.solve(column(rod, 1.5 * Pe), options=ANY, strict=True)
    assert np.allclose(straight.tip_position[:2], 0.0, atol=1e-12)
    assert straight.stable is False and straight.stability_index == 2


def test_world_moment_is_not_judged():
    """A point moment fixed in the world is not conservative for spatial perturbations:
    the verdict is None and says why."""
    rod, Pe = euler()
    sc = tr.Scene(
        tr.Robot(rod, []),
        loads=[tr.PointLoad(s=rod.length, force=(0, 0, -0.5 * Pe), moment=(0, 1e-3, 0))],
    )
    sol = tr.solve(sc, strict=True)
    assert sol.stable is None and math.isnan(sol.stability)
    assert "not conservative" in sol.stability_reason


def test_same_verdict_from_problem_and_solve_and_a_failed_solve_has_none():
    """Problem.solve and tr.solve judge the same solution the same way (one C routine);
    an unconverged solve is not judged."""
    rod, Pe = euler()
    sc = column(rod, 3 * Pe)
    a = tr.solve(sc, strict=True)
    b = tr.Problem(sc).solve(strict=True)
    assert (a.stable, a.stability, a.stability_index) == (b.stable, b.stability, b.stability_index)
    with pytest.warns(tr.ConvergenceWarning):
        bad = tr.solve(
            dataclasses.replace(sc, loads=[tr.PointLoad(s=rod.length, force=(1e6, 0, 0))]),
            options=tr.Options(max_work=1e4),
        )
    assert not bad.success and bad.stable is None and "no solution" in bad.stability_reason
