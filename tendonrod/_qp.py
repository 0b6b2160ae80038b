"""The step of :func:`tendonrod.actuate`'s outer iteration, a small dense convex
quadratic program:

    minimise   1/2 u^T H u + g^T u
    subject to A u = b,  G u >= h

with H symmetric positive definite, a handful of unknowns (the actuated tendons) and a
few dozen constraints, solved in C (``csrc/tr_qp.c``: the primal active-set method,
Nocedal and Wright, Numerical Optimization, algorithm 16.3) from a feasible point the
caller knows (the iteration always has one: no step, or a step it took already), which
also fixes b = A x0.  A constraint the starting point violates is relaxed to what that
point satisfies (the outer iteration's merit function accounts for it).
"""

from __future__ import annotations

import numpy as np

from . import _core

__all__ = ["solve_qp", "QPResult"]


class QPResult:
    """``u`` (n,) the minimiser, ``lam`` (m_eq,) and ``mu`` (m_in,) the multipliers
    (``H u + g = A^T lam + G^T mu``, ``mu >= 0``, zero off the active set), ``active``
    the indices of the inequalities that hold with equality at ``u``."""

    __slots__ = ("u", "lam", "mu", "active")

    def __init__(self, u, lam, mu, active):
        self.u, self.lam, self.mu, self.active = u, lam, mu, active


def solve_qp(H, g, A, G, h, x0, max_iter=200) -> QPResult:
    """Solve the QP (see the module docstring) from ``x0``, which satisfies the
    equalities (the inequalities it violates are relaxed to its values)."""
    n = len(g)
    A = np.asarray(A, dtype=float).reshape(-1, n)
    G = np.asarray(G, dtype=float).reshape(-1, n)
    return QPResult(*_core.qp(H, g, A, G, np.ravel(h), x0, max_iter))
