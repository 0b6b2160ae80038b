"""Distributed loads over part of the rod: the small-deflection closed form, an
independent collocation elastica, splitting a load, structure and validation."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_bvp

import tendonrod as tr

_ROD = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)


def _scene(*loads, robot=None):
    return tr.Scene(robot or tr.Robot(_ROD), loads=list(loads))


@pytest.mark.parametrize("a, b", [(0.0, 0.08), (0.05, 0.2), (0.06, 0.14)])
def test_small_load_matches_superposed_beam_formula(a, b):
    # Euler-Bernoulli: a point force F at x deflects the tip by F x^2 (3 L - x) / (6 EI);
    # integrating w dx over [a, b]: w / (6 EI) [L x^3 - x^4 / 4]_a^b
    L, EI = _ROD.length, _ROD.bending_stiffness
    w = 1e-4 * EI / L**3  # w L^3/EI = 1e-4: the nonlinear correction is ~1e-8 relative

    def tail(c):
        return -w / (6 * EI) * (L * c**3 - c**4 / 4)

    sol = tr.solve(_scene(tr.DistributedLoad(force=(w, 0, 0), start=a, end=b)))
    assert sol.success
    form = sol.formulation
    assert form.planar and form.n_segments == 1 + (a > 0) + (b < L)
    assert form.n_partial_loads == 1 and form.distributed_load and not form.mounted
    # 1e-6 relative: bounds the nonlinear correction (~(w L^3/EI)^2) and the solver
    # tolerance (1e-10 of the scaled residual) with room
    assert sol.tip_position[0] == pytest.approx(tail(a) - tail(b), rel=1e-6)


def _elastica(L, EI, w, a, b, P):
    """Independent reference: a planar inextensible cantilever along +z under a load w
    [N/m] along +x on [a, b] and a tip force P along +x, by collocation on the three
    pieces [0, a], [a, b], [b, L] (solve_bvp's multi-point form: the load's ends are mesh
    points).  The internal force is known: n_x(s) = P + w |[max(s, a), b]|, so
    theta' = m / EI, m' = -cos(theta) n_x (moment about +y, theta from z toward x)."""

    def nx(s):
        return P + w * np.clip(b - np.maximum(s, a), 0.0, None)

    def f(s, y):
        return np.vstack([np.sin(y[2]), np.cos(y[2]), y[3] / EI, -np.cos(y[2]) * nx(s)])

    def bc(ya, yb):
        return np.array([ya[0], ya[1], ya[2], yb[3]])

    s = np.unique(
        np.concatenate([np.linspace(0, a, 200), np.linspace(a, b, 400), np.linspace(b, L, 200)])
    )
    sol = solve_bvp(f, bc, s, np.zeros((4, s.size)), tol=1e-11, max_nodes=400000)
    assert sol.success, sol.message
    return sol.sol(L)[:2]


def test_large_deflection_matches_collocation_elastica():
    L, EI = _ROD.length, _ROD.bending_stiffness
    w, a, b = 8.0 * EI / L**3, 0.05, 0.15  # w (b - a) L^2 / EI = 4: a large bend
    P = 0.5 * EI / L**2
    sol = tr.solve(
        _scene(
            tr.DistributedLoad(force=(w, 0, 0), start=a, end=b),
            tr.PointLoad(s=L, force=(P, 0, 0)),
        )
    )
    assert sol.success
    x, z = _elastica(L, EI, w, a, b, P)
    assert x > 0.4 * L
    # measured 1.3e-13 L; collocation tol 1e-11 and the shooting tolerance 1e-10
    np.testing.assert_allclose(sol.tip_position, (x, 0.0, z), rtol=0, atol=2e-9 * L)


def test_split_load_equals_whole_and_spatial_equals_planar():
    f = (0.3, 0.0, -0.1)
    whole = tr.solve(_scene(tr.DistributedLoad(force=f)))
    split = tr.solve(
        _scene(
            tr.DistributedLoad(force=f, end=0.08),
            tr.DistributedLoad(force=f, start=0.08, end=0.13),
            tr.DistributedLoad(force=f, start=0.13),
        )
    )
    # the same load, integrated with breakpoints at 0.08 and 0.13: the integrators'
    # truncation differs (measured 2.6e-12 m); 1e-10 L is the solver tolerance
    np.testing.assert_allclose(split.tip_position, whole.tip_position, rtol=0, atol=2e-11)
    sc = _scene(tr.DistributedLoad(force=(0.5, 0.0, 0.1), start=0.03, end=0.11))
    planar = tr.solve(sc)
    spatial = tr.solve(sc, options=tr.Options(force_spatial=True))
    assert planar.formulation.planar and not spatial.formulation.planar
    np.testing.assert_allclose(spatial.tip_position, planar.tip_position, rtol=0, atol=2e-11)
    out = tr.solve(_scene(tr.DistributedLoad(force=(0.0, 0.3, 0.0), start=0.1)))
    assert not out.formulation.planar  # an out-of-plane partial load is spatial


def test_whole_rod_loads_compile_as_before():
    # start = 0 and end = L (or None) is a whole-rod load: a per-solve value, no breakpoint
    a = _scene(tr.DistributedLoad(force=(0.3, 0, 0), end=_ROD.length))
    b = _scene(tr.DistributedLoad(force=(0.3, 0, 0)))
    assert a.partial_loads == () and b.partial_loads == ()
    np.testing.assert_array_equal(tr.solve(a).tip_position, tr.solve(b).tip_position)


def test_problem_structure_names_a_changed_partial_load():
    prob = tr.Problem(_scene(tr.DistributedLoad(force=(0.3, 0, 0), start=0.1)))
    prob.solve()
    with pytest.raises(ValueError, match=r"partial distributed load 0"):
        prob.solve(_scene(tr.DistributedLoad(force=(0.4, 0, 0), start=0.1)))


@pytest.mark.parametrize(
    "kw, match",
    [
        (dict(start=-0.1), r"DistributedLoad\.start must be >= 0"),
        (dict(start=0.1, end=0.1), r"DistributedLoad\.end must be > start = 0\.1, got 0\.1"),
        (dict(end=math.nan), r"DistributedLoad\.end must not be NaN"),
    ],
)
def test_distributed_load_validation(kw, match):
    with pytest.raises(ValueError, match=match):
        tr.DistributedLoad(force=(1, 0, 0), **kw)


def test_scene_file_reads_a_partial_distributed_load():
    from tendonrod.scenefile import SceneFileError, parse_scene

    doc = {"rod": {"length": 0.2, "EI": 1.0, "GJ": 1.0, "kirchhoff": True}}
    sc = parse_scene({**doc, "distributed": {"force": [1, 0, 0], "start": 0.05}}).scene
    assert sc.partial_loads == (tr.DistributedLoad(force=(1, 0, 0), start=0.05),)
    with pytest.raises(SceneFileError, match=r"distributed\.end: expected a number"):
        parse_scene({**doc, "distributed": {"force": [1, 0, 0], "end": "tip"}})
    with pytest.raises(SceneFileError, match=r"scene: Scene\.loads\[0\]\.end must be <= L"):
        parse_scene({**doc, "distributed": {"force": [1, 0, 0], "end": 0.3}})


def test_scene_checks_the_interval_against_the_rod():
    with pytest.raises(ValueError, match=r"Scene\.loads\[0\]\.end must be <= L=0\.2, got 0\.3"):
        _scene(tr.DistributedLoad(force=(1, 0, 0), end=0.3))
    with pytest.raises(ValueError, match=r"Scene\.loads\[0\]\.start must be < L=0\.2"):
        _scene(tr.DistributedLoad(force=(1, 0, 0), start=0.2))
