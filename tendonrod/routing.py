"""General tendon routing: helices, paths given by a function or by sampled points, and
disk-by-disk straight pieces, all in the body frame.

A :class:`Path` is a piecewise cubic ``r(s) = (x(s), y(s), 0)`` [m] on knots
``0 = s_0 < ... < s_K = end`` (the tendon's anchor), ``x(s) = c0 + c1 h + c2 h^2 + c3 h^3``
with ``h = s - s_k`` on ``[s_k, s_k+1]``: the right-hand side evaluates ``r``, ``r'`` and
``r''`` from it in C (no Python callback in the solve), and every knot is a breakpoint of
the integration (a Runge-Kutta step across a kink in ``r''`` would lose its order).

- :meth:`Path.sampled`: the not-a-knot cubic spline through sampled points (a straight
  or cubic path is reproduced exactly);
- :meth:`Path.function`: the same spline through ``n + 1`` samples of a function ``r(s)``
  (error O(h^4) in r, O(h^2) in r'');
- :meth:`Path.disks`: straight pieces between the holes of discrete disks (the tendon
  kinks at each disk and presses on it: a point force at that breakpoint).

A helix (:meth:`tendonrod.Tendon.helical`) is evaluated in closed form instead:
``r(s) = (slope s + offset)(cos(angle + twist s), sin(angle + twist s), 0)``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

__all__ = ["Path", "route_rows", "offsets"]

# Core routing kinds (csrc/tendonrod.h, tr_route_kind) and the row width.
_HELIX, _PIECE, _NCOL = 1, 2, 12
# Knots closer than this fraction of the path length are refused (a zero-length piece).
_KNOT_RTOL = 1e-12


def _points(points, n: int, who: str) -> np.ndarray:
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[0] != n or p.shape[1] not in (2, 3):
        raise ValueError(
            f"{who}: points must have shape ({n}, 2) or ({n}, 3) (body-frame x, y[, 0]) [m], "
            f"got shape {p.shape}"
        )
    if not np.all(np.isfinite(p)):
        raise ValueError(f"{who}: points must be finite, got {points!r}")
    if p.shape[1] == 3 and np.any(p[:, 2] != 0.0):
        raise ValueError(
            f"{who}: a tendon path lies in the cross-section plane (z = 0), got z = {p[:, 2]!r}"
        )
    return p[:, :2]


def _knots(s, who: str, minimum: int) -> np.ndarray:
    k = np.asarray(s, dtype=float)
    if k.ndim != 1 or k.size < minimum or not np.all(np.isfinite(k)):
        raise ValueError(f"{who}: s must be {minimum} or more finite arc lengths [m], got {s!r}")
    if k[0] != 0.0:
        raise ValueError(f"{who}: s must start at the base, s[0] = 0, got {k[0]!r}")
    if not np.all(np.diff(k) > _KNOT_RTOL * k[-1]):
        raise ValueError(f"{who}: s must be strictly increasing, got {s!r}")
    return k


def _not_a_knot(s: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Coefficients (K, 4) in h = s - s_k of the not-a-knot cubic spline through (s, y)
    (with two points: the straight line; three: the parabola)."""
    n = s.size
    h = np.diff(s)
    if n == 2:
        slope = (y[1] - y[0]) / h[0]
        return np.array([[y[0], slope, 0.0, 0.0]])
    # unknown slopes m_k at the knots: continuity of y'' inside, not-a-knot at the ends
    A = np.zeros((n, n))
    b = np.zeros(n)
    d = np.diff(y) / h
    for k in range(1, n - 1):
        A[k, k - 1] = h[k]
        A[k, k] = 2.0 * (h[k - 1] + h[k])
        A[k, k + 1] = h[k - 1]
        b[k] = 3.0 * (h[k] * d[k - 1] + h[k - 1] * d[k])
    if n == 3:  # the parabola through the three points
        A[0, 0], A[0, 1], b[0] = 1.0, 1.0, 2.0 * d[0]
        A[-1, -2], A[-1, -1], b[-1] = 1.0, 1.0, 2.0 * d[-1]
    else:  # third derivative continuous at s_1 and s_{n-2}
        A[0, 0], A[0, 1] = h[1], h[0] + h[1]
        b[0] = ((h[0] + 2.0 * (h[0] + h[1])) * h[1] * d[0] + h[0] ** 2 * d[1]) / (h[0] + h[1])
        A[-1, -2], A[-1, -1] = h[-1] + h[-2], h[-2]
        b[-1] = (h[-1] ** 2 * d[-2] + (2.0 * (h[-1] + h[-2]) + h[-1]) * h[-2] * d[-1]) / (
            h[-1] + h[-2]
        )
    m = np.linalg.solve(A, b)
    c2 = (3.0 * d - 2.0 * m[:-1] - m[1:]) / h
    c3 = (m[:-1] + m[1:] - 2.0 * d) / h**2
    return np.stack([y[:-1], m[:-1], c2, c3], axis=1)


@dataclass(frozen=True, eq=False)
class Path:
    """A tendon path in the body frame: piecewise cubic in s (see the module docstring).

    Attributes
    ----------
    knots : ndarray (K + 1,)
        Arc lengths [m], ``knots[0] = 0``, the last the tendon's anchor (its ``end``, or
        the rod length).
    coefficients : ndarray (K, 2, 4)
        Per piece, x and y [m] as cubic polynomials in ``h = s - knots[k]``.
    kind : str
        ``"spline"`` or ``"disks"`` (straight pieces).
    """

    knots: np.ndarray
    coefficients: np.ndarray
    kind: str = "spline"

    def __post_init__(self):
        k = _knots(self.knots, "Path", 2)
        c = np.asarray(self.coefficients, dtype=float)
        if c.shape != (k.size - 1, 2, 4) or not np.all(np.isfinite(c)):
            raise ValueError(
                f"Path.coefficients must be finite with shape ({k.size - 1}, 2, 4), got {c.shape}"
            )
        for a in (k, c):
            a.setflags(write=False)
        object.__setattr__(self, "knots", k)
        object.__setattr__(self, "coefficients", c)

    @classmethod
    def sampled(cls, s, points) -> Path:
        """The not-a-knot cubic spline through ``points`` (N, 2) [m] (body x, y; or (N, 3)
        with z = 0) at arc lengths ``s`` (N,) [m] from 0 to the anchor, N >= 2."""
        k = _knots(s, "Path.sampled", 2)
        p = _points(points, k.size, "Path.sampled")
        coef = np.stack([_not_a_knot(k, p[:, 0]), _not_a_knot(k, p[:, 1])], axis=1)
        return cls(k, coef, "spline")

    @classmethod
    def function(cls, r: Callable, end: float, n: int = 32) -> Path:
        """The spline through ``r(s)`` [m] (a function returning body x, y[, 0]) sampled at
        ``n + 1`` equally spaced arc lengths on [0, end] [m]: the function is called here,
        never during a solve."""
        if not (isinstance(n, int) and n >= 1):
            raise ValueError(f"Path.function: n must be an int >= 1, got {n!r}")
        end = float(end)
        if not (math.isfinite(end) and end > 0.0):
            raise ValueError(f"Path.function: end must be a finite length > 0 [m], got {end!r}")
        s = np.linspace(0.0, end, n + 1)
        return cls.sampled(s, [np.asarray(r(x), dtype=float) for x in s])

    @classmethod
    def disks(cls, s, points) -> Path:
        """Straight pieces between the holes ``points`` (N, 2) [m] of disks at arc lengths
        ``s`` (N,) [m] (``s[0] = 0`` the base's hole, the last the anchor)."""
        k = _knots(s, "Path.disks", 2)
        p = _points(points, k.size, "Path.disks")
        h = np.diff(k)[:, None]
        slope = np.diff(p, axis=0) / h
        zero = np.zeros_like(slope)
        coef = np.stack([p[:-1], slope, zero, zero], axis=2)
        return cls(k, coef, "disks")

    def __call__(self, s, derivative: int = 0) -> np.ndarray:
        """r(s) (or its first or second derivative) [m, -, 1/m], shape (N, 3), z = 0."""
        x = np.atleast_1d(np.asarray(s, dtype=float))
        j = np.clip(np.searchsorted(self.knots, x, side="right") - 1, 0, self.knots.size - 2)
        h = (x - self.knots[j])[:, None]
        c = self.coefficients[j]  # (N, 2, 4)
        if derivative == 0:
            v = c[..., 0] + h * (c[..., 1] + h * (c[..., 2] + h * c[..., 3]))
        elif derivative == 1:
            v = c[..., 1] + h * (2.0 * c[..., 2] + 3.0 * h * c[..., 3])
        else:
            v = 2.0 * c[..., 2] + 6.0 * h * c[..., 3]
        return np.concatenate([v, np.zeros((x.size, 1))], axis=1)

    def polar(self) -> tuple[float, float, float]:
        """(offset [m], angle [rad], slope [-]) of the linear tendon that best stands in for
        this path: its polar position at the base and its mean radial slope."""
        r0, r1 = self(0.0)[0], self(self.knots[-1])[0]
        b = float(math.hypot(r0[0], r0[1]))
        ang = float(math.atan2(r0[1], r0[0])) if b > 0.0 else 0.0
        return b, ang, float((math.hypot(r1[0], r1[1]) - b) / self.knots[-1])


def offsets(tendon, s, end: float) -> np.ndarray:
    """Body-frame offsets r(s) [m], shape (N, 3), of ``tendon`` (linear, helical or a
    :class:`Path`) at arc lengths ``s`` on [0, end]."""
    s = np.atleast_1d(np.asarray(s, dtype=float))
    if tendon.path is not None:
        return tendon.path(s)
    rho = tendon.slope * s + tendon.offset
    ang = tendon.angle + (tendon.twist or 0.0) * s
    return np.stack([rho * np.cos(ang), rho * np.sin(ang), np.zeros_like(s)], axis=1)


def route_rows(tendons, ends) -> np.ndarray | None:
    """The core's routing rows (nroute, 12) ``[tendon, kind, s0, s1, p (8)]`` of the helical
    and path tendons (None when every tendon is linear); ``ends`` their anchors [m]."""
    rows = []
    for i, (t, end) in enumerate(zip(tendons, ends)):
        if t.path is not None:
            kn, co = t.path.knots, t.path.coefficients
            for k in range(kn.size - 1):
                row = np.zeros(_NCOL)
                row[:4] = (i, _PIECE, kn[k], end if k == kn.size - 2 else kn[k + 1])
                row[4:8], row[8:12] = co[k, 0], co[k, 1]
                rows.append(row)
        elif t.twist is not None:
            row = np.zeros(_NCOL)
            row[:5] = (i, _HELIX, 0.0, end, t.twist)
            rows.append(row)
    if not rows:
        return None
    out = np.array(rows)
    out.setflags(write=False)
    return out
