"""Stability at a taut/slack switch: tendons locked at zero tension and zero slack resist
only the perturbations that stretch them.

The independent reference: a straight rod clamped at s = 0 under an axial tip load P,
with parallel tendons of stiffness k = EA / L locked at the switch.  A bend whose tip
turns by phi (relative to the base) stretches the tendons on its outer side by r phi
(their share adds to k r^2 phi^2 / 2 for any bending plane when four tendons sit at
90 degrees), and a bend with no net turn stretches none.  So the straight state is a
clamped column whose tip is free laterally and held by a rotational spring K = EA r^2 / L:
w = A (1 - cos a s), a^2 = P / EI, and the tip moment EI w''(L) = -K w'(L) gives
EI a cos(aL) + K sin(aL) = 0, whose root in (pi/2, pi) is the critical load (between the
free cantilever's pi^2 EI / 4L^2 and the guided column's pi^2 EI / L^2).
"""

from __future__ import annotations

import math
import warnings

import pytest
from scipy.optimize import brentq

import tendonrod as tr

ROD = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
EI, L = ROD.bending_stiffness, ROD.length
P_E = math.pi**2 * EI / (4 * L * L)  # the free cantilever's Euler load
R, EA = 0.01, 3e3


def critical_load() -> float:
    K = EA * R * R / L
    aL = brentq(lambda x: EI * (x / L) * math.cos(x) + K * math.sin(x), math.pi / 2, math.pi)
    return EI * (aL / L) ** 2


def four_locked(P):
    robot = tr.Robot(ROD, [tr.Tendon(offset=R, angle=k * math.pi / 2, EA=EA) for k in range(4)])
    return tr.Scene(robot, displacement=[0.0] * 4, loads=[tr.PointLoad(s=L, force=(0, 0, -P))])


def test_reference_lies_between_the_free_and_guided_columns():
    Pcr = critical_load()
    assert P_E < Pcr < 4 * P_E
    assert Pcr / P_E == pytest.approx(3.8913, rel=1e-4)  # K L / EI = 72


# The test's margin crosses zero within 0.3 % of the reference load (measured: +0.074 EI/L
# at 0.995 Pcr, -0.022 at 1.005 Pcr on its 24-element grid, a second-order discretisation);
# 3 % on either side leaves a tenfold margin.
@pytest.mark.parametrize("factor", [0.5, 0.97])
def test_locked_tendons_hold_a_rod_beyond_its_euler_load(factor):
    P = factor * critical_load()
    assert P > P_E  # beyond the bare rod's buckling load: the slack side alone is unstable
    sol = tr.solve(four_locked(P), strict=True)
    assert sol.stable is True, sol.stability_reason
    assert "taut/slack switch" in sol.stability_reason and sol.stability > 0.0
    # the straight equilibrium itself: tip on the axis, no tension
    assert abs(sol.tip_position[0]) < 1e-12 and abs(sol.tip_position[1]) < 1e-12
    assert max(sol.tension) == 0.0


def test_locked_tendons_buckle_past_the_critical_load():
    sol = tr.solve(four_locked(1.03 * critical_load()), options=tr.Options(accept_unstable=True))
    assert sol.stable is False and sol.stability < 0.0
    assert "stretches" in sol.stability_reason
    # without accept_unstable the straight state is not a success
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        plain = tr.solve(four_locked(1.03 * critical_load()))
    assert not (plain.success and plain.stable is False)


def test_tendons_in_one_plane_do_not_hold_the_other():
    """Two tendons in the x-z plane resist bending in it, not across it: beyond the bare
    rod's Euler load the straight state is unstable by a bend about x that keeps both
    tendons at their length (the lateral buckling the slack side alone also shows)."""
    robot = tr.Robot(ROD, [tr.Tendon(offset=R, EA=EA), tr.Tendon(offset=R, angle=math.pi, EA=EA)])
    scene = tr.Scene(
        robot, displacement=[0.0, 0.0], loads=[tr.PointLoad(s=L, force=(0, 0, -1.5 * P_E))]
    )
    sol = tr.solve(scene, options=tr.Options(accept_unstable=True))
    assert sol.stable is False
    assert "keeps 0, 1 at their length" in sol.stability_reason
    # the lateral mode is the bare cantilever's: the margin of the tendon-free rod at
    # 1.5 P_E (measured equal to all printed digits; both from the same grid and bisection,
    # whose tolerance is 1e-5 relative, so 1e-3 is loose)
    bare = tr.solve(
        tr.Scene(tr.Robot(ROD, []), loads=[tr.PointLoad(s=L, force=(0, 0, -1.5 * P_E))]),
        options=tr.Options(accept_unstable=True),
    )
    assert sol.stability == pytest.approx(bare.stability, rel=1e-3)
