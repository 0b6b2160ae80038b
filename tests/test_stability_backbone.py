"""The stability verdict on robots as built: stepped (sectioned) and precurved backbones,
helical and general tendon routes.

Independent answers: the stepped cantilever column's buckling load from its own
characteristic equation; for precurved rods the bifurcations that tr.path finds from the
shooting system's determinant (another discretisation and another test: the verdict
comes from the energy's Hessian on a grid of elements, the path's from the sign of
det [J F_lambda; t^T] of the shooting equations).  General routes are checked against the
routes they reduce to (a straight path sampled as a spline, a helix of zero turns).
"""

from __future__ import annotations

import math

import pytest
from scipy.optimize import brentq

import tendonrod as tr

L = 0.2
WIRE = dict(E=207e9, G=79.6e9, kirchhoff=True)


def _stepped_critical(EI1, EI2, a, b):
    """Buckling load of a cantilever of EI1 on [0, a] and EI2 on [a, a + b] under a dead
    axial tip load P.  With v = (tip deflection - w), v'' + (P/EI) v = 0 on each part,
    v'(0) = 0, v(L) = 0 and v, v' continuous at a: on the base v = cos(k1 s) (k = sqrt(P /
    EI)), and v(L) = 0 gives cos(k1 a) cos(k2 b) = (k1 / k2) sin(k1 a) sin(k2 b) (uniform:
    cos(k L) = 0, the Euler load)."""

    def f(P):
        k1, k2 = math.sqrt(P / EI1), math.sqrt(P / EI2)
        return math.cos(k1 * a) * math.cos(k2 * b) - (k1 / k2) * math.sin(k1 * a) * math.sin(k2 * b)

    lo = math.pi**2 * min(EI1, EI2) / (4 * (a + b) ** 2)
    return brentq(f, 0.9 * lo, 4.0 * lo)


def test_stepped_column_buckles_at_its_characteristic_load():
    base = tr.Rod(length=0.1, diameter=1.0e-3, **WIRE)
    tip = tr.Rod(length=0.1, diameter=0.8e-3, **WIRE)
    rod = tr.Rod.segmented([base, tip])
    Pcr = _stepped_critical(base.bending_stiffness, tip.bending_stiffness, 0.1, 0.1)
    margins = {}
    for f in (0.97, 1.03):
        scene = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=L, force=(0, 0, -f * Pcr))])
        sol = tr.solve(scene, options=tr.Options(accept_unstable=True))
        margins[f] = sol.stability
        assert sol.stable is (f < 1.0), sol.stability_reason
    # the margin crosses zero within 0.2 % of the reference (measured: +0.098 EI/L at
    # 0.95 Pcr, +0.021 at 0.99, -0.017 at 1.01: zero at 1.001 Pcr), so 3 % on either side
    # decides with a tenfold room
    assert margins[0.97] > 0.0 > margins[1.03]


@pytest.mark.parametrize(
    "turns, comp, sign, what",
    [
        (0.5, 0, -1.0, "semicircle pushed back toward its base"),
        (0.75, 2, 1.0, "three-quarter curl pulled along the axis"),
    ],
)
def test_precurved_margin_changes_sign_where_the_path_bifurcates(turns, comp, sign, what):
    """A rod precurved into `turns` of a circle under a growing tip force: tr.path locates a bifurcation by the shooting determinant; the verdict's margin
    is positive just before it and negative just after (solves at 0.97 and 1.03 of the
    load, the straight-ahead branch kept by accept_unstable)."""
    kap = 2.0 * math.pi * turns / L
    rod = tr.Rod(length=L, diameter=0.8e-3, precurvature=(0.0, kap, 0.0), **WIRE)
    Fs = rod.bending_stiffness / L**2
    spatial = tr.Options(force_spatial=True)
    scene = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=L, force=(0.0, 0.0, 0.0))])
    p = tr.path(scene, f"loads[0].force[{comp}]", (0.0, sign * 8 * Fs), options=spatial)
    assert p.success, p.message
    bif = [sp for sp in p.special_points if sp.kind == "bifurcation"]
    assert len(bif) == 1, (what, p.special_points)
    # at the located point the margin is zero to the verdict's discretisation error
    # (measured 9e-5 and 4e-4 EI/L against +-0.03 to 0.06 at 3 % either side)
    assert abs(bif[0].margin) < 2e-3
    for f, stable in ((0.97, True), (1.03, False)):
        force = [0.0, 0.0, 0.0]
        force[comp] = f * bif[0].value
        sc = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=L, force=tuple(force))])
        sol = tr.solve(sc, options=tr.Options(force_spatial=True, accept_unstable=True))
        assert sol.stable is stable, (what, f, sol.stability_reason)


def _three_tendon_robot(tendons):
    rod = tr.Rod(length=L, diameter=0.8e-3, **WIRE)
    P = 1.2 * math.pi**2 * rod.bending_stiffness / (4 * L**2)
    return tr.Scene(
        tr.Robot(rod, tendons),
        displacement=[1e-3, 4e-4, 4e-4],
        loads=[tr.PointLoad(s=L, force=(0.01, 0.0, -P))],
    )


def _margin(scene):
    return tr.solve(scene, options=tr.Options(force_spatial=True, accept_unstable=True)).stability


def test_general_routes_reduce_to_the_routes_they_equal():
    """A straight converging route given as sampled points, and a helix of zero turns,
    give the verdict of the linear routing (the same energy on another code path)."""
    linear = [
        tr.Tendon(offset=0.008, angle=2 * math.pi * k / 3, slope=-0.01, EA=3e3) for k in range(3)
    ]
    ref = _margin(_three_tendon_robot(linear))
    sampled = []
    for k in range(3):
        c, s_ = math.cos(2 * math.pi * k / 3), math.sin(2 * math.pi * k / 3)
        s = [0.0, 0.05, 0.1, 0.15, 0.2]
        pts = [((0.008 - 0.01 * x) * c, (0.008 - 0.01 * x) * s_) for x in s]
        sampled.append(tr.Tendon(path=tr.routing.Path.sampled(s, pts), EA=3e3))
    helix0 = [
        tr.Tendon.helical(0.008, 2 * math.pi * k / 3, turns=0.0, length=L, EA=3e3) for k in range(3)
    ]
    parallel = [tr.Tendon(offset=0.008, angle=2 * math.pi * k / 3, EA=3e3) for k in range(3)]
    # the same energy through the spline's evaluation (a cubic reproducing a straight line
    # to round-off): margins equal to the bisection's 1e-5 relative resolution
    assert _margin(_three_tendon_robot(sampled)) == pytest.approx(ref, rel=1e-4)
    assert _margin(_three_tendon_robot(helix0)) == pytest.approx(
        _margin(_three_tendon_robot(parallel)), rel=1e-4
    )


def test_helical_and_precurved_scenes_are_judged():
    """No scene is left unjudged for being precurved, sectioned or routed: a helical robot
    under a compressive load loses stability as the load grows (its margin falls through
    zero, as a column's does)."""
    rod = tr.Rod(length=L, diameter=0.8e-3, **WIRE)
    P_E = math.pi**2 * rod.bending_stiffness / (4 * L**2)
    tendons = [
        tr.Tendon.helical(0.008, 2 * math.pi * k / 3, turns=1.0, length=L, EA=3e3) for k in range(3)
    ]
    margins = []
    for f in (0.0, 0.5, 3.0):
        scene = tr.Scene(
            tr.Robot(rod, tendons),
            tension=[2.0, 2.0, 2.0],
            loads=[tr.PointLoad(s=L, force=(0.0, 0.0, -f * P_E))],
        )
        sol = tr.solve(scene, options=tr.Options(accept_unstable=True))
        assert sol.stable is not None, sol.stability_reason
        margins.append(sol.stability)
    assert margins[0] > margins[1] > 0.0 > margins[2]
