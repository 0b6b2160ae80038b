"""The step QP of ``tr.actuate`` (``csrc/tr_qp.c`` through ``_core.qp``): minimise
1/2 u^T H u + g^T u subject to A u = b, G u >= h from a point x0 with A x0 = b.

The reference is independent of the active-set method: every subset of the inequalities
taken as equalities, its equality-constrained minimiser solved from the KKT system, and
the best of those that satisfy all the constraints kept (H positive definite: the optimum
is unique and is the minimiser on its own active set).
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from tendonrod import _core


def _enumerated(H, g, A, b, G, h):
    """The optimum by enumeration of the active sets (small problems only)."""
    n, me, mi = len(g), len(A), len(G)
    best, best_f = None, np.inf
    for size in range(0, min(mi, n - me) + 1):
        for S in itertools.combinations(range(mi), size):
            C = np.vstack([A, G[list(S)]])
            d = np.concatenate([b, h[list(S)]])
            K = np.block([[H, C.T], [C, np.zeros((len(C), len(C)))]])
            try:
                sol = np.linalg.solve(K, np.concatenate([-g, d]))
            except np.linalg.LinAlgError:
                continue  # dependent rows: another subset holds the same point
            u = sol[:n]
            if len(G) and np.min(G @ u - h) < -1e-9:
                continue
            f = 0.5 * u @ H @ u + g @ u
            if f < best_f:
                best, best_f = u, f
    return best


def _random_qp(rng, n, me, mi):
    M = rng.normal(size=(n, n))
    H = M @ M.T + 0.1 * np.eye(n)
    g = rng.normal(size=n)
    A = rng.normal(size=(me, n))
    x0 = 0.1 * rng.normal(size=n)
    G = rng.normal(size=(mi, n))
    # x0 feasible, some constraints active at it (as the iteration's trust-region box is)
    h = G @ x0 - rng.uniform(0.0, 1.0, size=mi) * (rng.uniform(size=mi) < 0.7)
    return H, g, A, x0, G, h


@pytest.mark.parametrize("seed", range(40))
def test_matches_the_enumerated_optimum(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 5))
    me = int(rng.integers(0, n))
    mi = int(rng.integers(0, 2 * n + 3))
    H, g, A, x0, G, h = _random_qp(rng, n, me, mi)
    u, lam, mu, active = _core.qp(H, g, A, G, h, x0)
    ref = _enumerated(H, g, A, A @ x0, G, h)
    scale = 1.0 + np.abs(ref).max()
    # both are the solution of a well-conditioned linear system: round-off
    np.testing.assert_allclose(u, ref, rtol=0, atol=1e-10 * scale)
    # the multipliers: stationarity, dual feasibility, complementarity (round-off)
    r = H @ u + g - A.T @ lam - G.T @ mu
    assert np.abs(r).max() <= 1e-10 * (1.0 + np.abs(g).max() + np.abs(mu).max(initial=0.0))
    assert np.all(mu >= 0.0)
    slack = G @ u - h
    assert np.all(slack >= -1e-12 * scale)
    assert np.all(mu[slack > 1e-9] == 0.0)
    level = 1.0 + np.abs(h).max(initial=0.0) + np.abs(G @ x0).max(initial=0.0)
    assert set(active) == set(np.flatnonzero(slack <= 1e-12 * level))


def test_the_box_of_a_trust_region_step():
    """The shape actuate asks for: a least-change step under a linearised target and a
    max-norm box, the box binding on two controls (u0 >= -0.3, then u1 <= 0.3: by hand,
    u = (-0.3, 0.3, 0))."""
    H, g = np.eye(3), np.array([1.0, -0.5, 0.2])
    A = np.array([[1.0, 1.0, 1.0]])
    x0 = np.zeros(3)
    G = np.vstack([np.eye(3), -np.eye(3)])
    h = np.full(6, -0.3)
    u, lam, mu, active = _core.qp(H, g, A, G, h, x0)
    ref = _enumerated(H, g, A, A @ x0, G, h)
    np.testing.assert_allclose(u, ref, atol=1e-14)  # exact arithmetic but for round-off
    np.testing.assert_allclose(u, [-0.3, 0.3, 0.0], atol=1e-15)
    assert active == (0, 4)


def test_dependent_constraints():
    """A constraint repeated (the working set keeps independent rows only)."""
    H, g = np.eye(2), np.array([-2.0, -2.0])
    G = np.array([[-1.0, 0.0], [-1.0, 0.0], [-2.0, 0.0], [0.0, -1.0]])
    h = np.array([-1.0, -1.0, -2.0, -0.5])  # u0 <= 1 three times, u1 <= 0.5
    u, lam, mu, active = _core.qp(H, g, np.zeros((0, 2)), G, h, np.zeros(2))
    np.testing.assert_allclose(u, [1.0, 0.5], atol=1e-14)  # round-off of exact numbers
    assert set(active) == {0, 1, 2, 3}
    np.testing.assert_allclose(H @ u + g - G.T @ mu, 0.0, atol=1e-14)


def test_a_violated_start_is_relaxed():
    """x0 violates u0 >= 1: the constraint becomes u0 >= x0[0] (what x0 satisfies)."""
    H, g = np.eye(2), np.array([1.0, 0.0])  # unconstrained optimum u = (-1, 0)
    G = np.array([[1.0, 0.0]])
    x0 = np.array([0.25, 0.0])
    u, lam, mu, active = _core.qp(H, g, np.zeros((0, 2)), G, np.array([1.0]), x0)
    np.testing.assert_allclose(u, [0.25, 0.0], atol=1e-15)
    assert mu[0] == pytest.approx(1.25, abs=1e-14) and active == (0,)


def test_bad_input():
    H, g, A, G, h, x0 = np.eye(2), np.zeros(2), np.zeros((0, 2)), np.eye(2), np.zeros(2), np.ones(2)
    with pytest.raises(ValueError, match="shapes"):
        _core.qp(H, g, A, G, np.zeros(3), x0)
    with pytest.raises(ValueError, match="g must be"):
        _core.qp(H, "x", A, G, h, x0)
    with pytest.raises(ValueError, match="H has a non-finite"):
        _core.qp(np.full((2, 2), np.nan), g, A, G, h, x0)
    with pytest.raises(ArithmeticError, match="singular reduced Hessian"):
        _core.qp(np.zeros((2, 2)), g, A, np.zeros((0, 2)), np.zeros(0), x0)
