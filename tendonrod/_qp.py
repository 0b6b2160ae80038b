"""A small dense convex quadratic program, the step of :func:`tendonrod.actuate`'s outer
iteration:

    minimise   1/2 u^T H u + g^T u
    subject to A u = b,  G u >= h

with H symmetric positive definite, a handful of unknowns (the actuated tendons) and a
few dozen constraints.  Solved by the primal active-set method (Nocedal and Wright,
Numerical Optimization, algorithm 16.3) from a feasible point the caller knows (the
iteration always has one: no step, or a step it took already): each subproblem is the
equality-constrained minimiser on the working set, found in the null space of its
constraints; a blocking constraint joins the working set, one with a negative multiplier
leaves it.  A constraint the starting point violates is relaxed to what that point
satisfies (the outer iteration's merit function accounts for it).
"""

from __future__ import annotations

import numpy as np

__all__ = ["solve_qp", "QPResult"]


class QPResult:
    """``u`` (n,) the minimiser, ``lam`` (m_eq,) and ``mu`` (m_in,) the multipliers
    (``H u + g = A^T lam + G^T mu``, ``mu >= 0``, zero off the active set), ``active``
    the indices of the inequalities that hold with equality at ``u``."""

    def __init__(self, u, lam, mu, active):
        self.u, self.lam, self.mu, self.active = u, lam, mu, active


def _null_space(C, n):
    """An orthonormal basis (n, n - rank) of the null space of C (k, n)."""
    if C.shape[0] == 0:
        return np.eye(n)
    _, sv, Vt = np.linalg.svd(C)
    rank = int(np.sum(sv > 1e-12 * max(sv[0], 1e-300)))
    return Vt[rank:].T


def _equality_minimiser(H, g, A, b, x):
    """(u, lam) minimising under A u = b (x satisfies it), or None if that fails."""
    n = len(g)
    try:
        if A.shape[0] == 0:
            return np.linalg.solve(H, -g), np.zeros(0)
        Z = _null_space(A, n)
        q = H @ x + g
        u = x - Z @ np.linalg.solve(Z.T @ H @ Z, Z.T @ q) if Z.shape[1] else x.copy()
        lam = np.linalg.lstsq(A.T, H @ u + g, rcond=None)[0]
        return u, lam
    except np.linalg.LinAlgError:
        return None


def solve_qp(H, g, A, b, G, h, x0, max_iter=200) -> QPResult:
    """Solve the QP (see the module docstring) from ``x0``, which must satisfy the
    equalities (the inequalities it violates are relaxed to its values)."""
    H = np.asarray(H, dtype=float)
    g = np.asarray(g, dtype=float)
    n = len(g)
    A = np.asarray(A, dtype=float).reshape(-1, n)
    G = np.asarray(G, dtype=float).reshape(-1, n)
    b = np.asarray(b, dtype=float).ravel()
    x = np.array(x0, dtype=float)
    # the minimiser under the equalities alone, when it satisfies the inequalities too
    free = _equality_minimiser(H, g, A, b, x)
    if free is not None and np.all(G @ free[0] >= np.asarray(h, dtype=float).ravel()):
        return QPResult(free[0], free[1], np.zeros(G.shape[0]), ())
    Gx = G @ x
    h = np.minimum(np.asarray(h, dtype=float).ravel(), Gx)  # relax what x0 violates
    scale = 1.0 + np.abs(Gx).max(initial=0.0) + np.abs(h).max(initial=0.0)
    tol = 1e-12 * scale
    work = [int(i) for i in np.flatnonzero(Gx - h <= tol)]
    # the starting working set: the active constraints that are independent
    chosen: list[int] = []
    for i in work:
        C = np.vstack([A, G[chosen + [i]]])
        if np.linalg.matrix_rank(C, tol=1e-10 * max(np.abs(C).max(), 1e-300)) == C.shape[0]:
            chosen.append(i)
    work = chosen
    row_max = np.abs(G).max(axis=1, initial=0.0)  # each constraint row's largest entry
    y = np.zeros(len(b) + len(work))
    at_min = False  # x minimises on the working set (after a full, unblocked step)
    for _ in range(max_iter):
        C = np.vstack([A, G[work]]) if work else A
        q = H @ x + g
        if at_min:
            p = np.zeros(n)
        else:
            Z = _null_space(C, n)
            p = -Z @ np.linalg.solve(Z.T @ H @ Z, Z.T @ q) if Z.shape[1] else np.zeros(n)
        at_min = False
        if np.abs(p).max(initial=0.0) <= 1e-14 * (1.0 + np.abs(x).max()):
            y = np.linalg.lstsq(C.T, q, rcond=None)[0] if C.shape[0] else np.zeros(0)
            mu_w = y[len(b) :]
            neg = np.flatnonzero(mu_w < -1e-10 * (1.0 + np.abs(y).max(initial=0.0)))
            if not neg.size:
                break
            # Bland's rule against cycling among nearly dependent constraints: the
            # lowest-numbered constraint leaves, the lowest-numbered blocking one joins
            del work[min(neg.tolist(), key=lambda k: work[k])]
            continue
        # the longest step along p that keeps the inequalities outside the working set:
        # over those that p decreases, (h_i - G_i x) / G_i p, at least 0
        Gp = G @ p
        moving = Gp < -1e-14 * row_max * np.abs(p).max()
        moving[work] = False
        cand = np.flatnonzero(moving)
        ratios = np.maximum((h[cand] - G[cand] @ x) / Gp[cand], 0.0)
        alpha = min(1.0, ratios.min(initial=1.0))
        blocking = cand[ratios <= alpha * (1.0 + 1e-12)]
        block = int(blocking.min()) if blocking.size else -1
        x = x + alpha * p
        if block >= 0:
            work.append(block)
        else:
            at_min = True
    mu = np.zeros(len(h))
    if work and len(y) == len(b) + len(work):
        mu[work] = np.maximum(y[len(b) :], 0.0)
    lam = y[: len(b)] if len(y) >= len(b) else np.zeros(len(b))
    active = tuple(int(i) for i in np.flatnonzero(G @ x - h <= tol)) if len(h) else ()
    return QPResult(x, lam, mu, active)
