"""Closed-form small-deflection formulas (paper Sections II-III) as NumPy ufuncs.

An initially straight cantilever of length ``L`` [m] and flexural rigidity
``EI`` [N m^2], clamped at s = 0, carries a lateral point force ``F`` [N] at
arc length ``z`` [m].  One tendon runs in a frictionless channel on the linear
path r(s) = a s + b (slope ``a`` [-], base offset ``b`` [m]), is fixed at the
tip and, at the base, held by a spring of stiffness ``k`` [N/m] (a prescribed
tendon displacement of zero).  Parallel routing: a = 0, b = r; converging:
a = -b/L (the tendon ends on the centre line); anything else is
semi-converging.

=========================================  ================================================
``tension(F, z, L, EI, a, b, k)``          eq. 25 (eq. 6 parallel, eq. 13 k = inf)
``angle(s, F, z, L, EI, a, b, k)``         eq. 22 (eq. 3 parallel, eq. 5 at s = L)
``deflection(s, F, z, L, EI, a, b, k)``    eq. 26 (eq. 7; eqs. 8-12, 27-34 at s = z, z = L)
``equivalent_stiffness(k, k_backbone)``    eq. 17
``pattern_factor(n)``                      sum_{i=1..n} cos^2(2 pi i/n) (eqs. 19-20, 35-36)
``actuation_tension_for_angle``            eqs. 37-38 (theta_L, L, EI, a, b)
``actuation_tension_for_deflection``       eqs. 39-40 (delta_L, L, EI, a, b)
``planar_shape(s, F, z, L, EI, a, b, k)``  (axial, lateral) coordinates, paper Fig. 23
=========================================  ================================================

All but :func:`planar_shape` are real NumPy ufuncs written in C: they
broadcast over every argument and accept ``out=``, ``where=`` and any numeric
dtype (computed in float64).  Non-numeric input raises NumPy's ``TypeError``.

Sign convention
---------------
With the tendon at +x (b > 0), F > 0 is the world force -F e_x, pointing away
from the tendon side, so the tendon is stretched and its tension tau > 0.
theta(s) [rad] and delta(s) [m] are positive in the direction of F:
theta(s) = -(right-hand side of eq. 22)/EI, delta(s) = -(right-hand side of
eq. 26)/EI (the paper's eqs. 3, 7, 22 and 26 give -EI theta and -EI delta).
F < 0 (or b < 0) returns the formula's value: a negative tension is a
compressed tendon, which only a pretensioned set can carry.  The actuation
functions take theta_L and delta_L positive toward the tendon side (the paper
reverses its theta sign for eqs. 37-40) and return the tension that produces
them in free space.

Domain
------
0 < L < inf, 0 < EI < inf, 0 <= z <= L, 0 <= s <= L, 0 <= k <= inf, no NaN.
Outside it a ufunc returns NaN and raises NumPy's floating-point "invalid"
flag, element by element, as NumPy's own ufuncs do: by default a
``RuntimeWarning``, under ``np.errstate(invalid='raise')`` a
``FloatingPointError``.

Limits
------
- ``k = np.inf`` is the inextensible tendon, evaluated exactly (the tension is
  computed as F(a z^3 + 3 b z^2) / (6 EI/k + L Q), and 6 EI/inf = 0): eqs. 11-13,
  29-30, 33-34, with no NaN and no warning.
- ``k = 0`` is a tendon without stiffness: tau = 0, the plain cantilever.
- ``a = b = 0`` puts the tendon on the centre line.  It has no moment arm, so
  it does not stretch (to first order) and tau = 0 for every finite k; we
  return the same tau = 0, i.e. the plain cantilever, at k = inf (the limit
  k -> inf at fixed geometry).  This limit is not uniform: at k = inf and
  a = 0, b -> 0 the tension F z^2/(2 b L) (eq. 13) grows without bound while
  the tendon's moment b tau = F z^2/(2 L) stays finite, so the deflection tends
  to eq. 11, not to the plain cantilever.  Any b != 0 is handled by the
  formula; only the exact centre line is special.
- ``actuation_tension_for_angle`` needs b + a L/2 != 0 and
  ``actuation_tension_for_deflection`` needs b/2 + a L/6 != 0 (mean moment
  arms); where they vanish no tension reaches the target and the result is
  NaN with the invalid flag.

Several tendons, compressible backbone (docs/model.md)
------------------------------------------------------
- n >= 2 equally spaced, equally pretensioned tendons at the same path
  (a, b) and stiffness k act like one tendon of stiffness ``k * P`` with
  ``P = pattern_factor(n)`` (n/2 for n >= 3; eqs. 19-20, 35-36); the pretension
  tau_p cancels out of the deflection.  ``tension`` then returns the resultant
  T = sum_i cos(phi_i) tau_i, and tendon i (phi_i = 2 pi i/n, the load along
  phi = 0) carries tau_p + cos(phi_i) T / P.  Do not combine this with
  ``equivalent_stiffness``: the tension changes sum to zero, so the backbone
  length does not change.
- A single tendon (or a one-sided set) on a backbone of axial stiffness k_B
  [N/m] (E A / L): pass ``k = equivalent_stiffness(k, k_B)`` (eq. 17).

Example
-------
>>> import numpy as np
>>> from tendonrod import analytic as an
>>> L, EI, r = 0.2, 0.05, 0.01
>>> d0 = an.deflection(L, 1.0, L, L, EI, 0.0, r, 0.0)       # no tendon
>>> d1 = an.deflection(L, 1.0, L, L, EI, 0.0, r, np.inf)    # inextensible
>>> round(float(d1 / d0), 12)                              # eq. 12
0.25
"""

from __future__ import annotations

import operator

import numpy as np

from . import _core

__all__ = [
    "tension",
    "angle",
    "deflection",
    "equivalent_stiffness",
    "pattern_factor",
    "actuation_tension_for_angle",
    "actuation_tension_for_deflection",
    "planar_shape",
]

tension = _core.tension
angle = _core.angle
deflection = _core.deflection
equivalent_stiffness = _core.equivalent_stiffness
pattern_factor = _core.pattern_factor
actuation_tension_for_angle = _core.actuation_tension_for_angle
actuation_tension_for_deflection = _core.actuation_tension_for_deflection

_MAX_NODES = 100


def planar_shape(s, F, z, L, EI, a, b, k, *, nodes=16):
    """Planar Cartesian shape of the loaded cantilever, small-deflection model.

    Integrates the closed-form tangent angle theta(s) of eq. 22 (with tau from
    eq. 25, as :func:`angle`) along the arc length, as the paper does for its
    Fig. 23::

        axial(s)   = int_0^s cos(theta(u)) du
        lateral(s) = int_0^s sin(theta(u)) du

    theta is a quadratic polynomial on [0, min(s, z)] and on [z, s]; each piece
    is integrated with ``nodes``-point Gauss-Legendre quadrature, so no node
    straddles the kink at z.  cos and sin of a quadratic are entire functions,
    and the quadrature error falls faster than exponentially with ``nodes``:
    with the default 16 nodes it is at round-off (below 1e-15 L; measured
    <= 3e-16 L against adaptive quadrature in tests/test_closed_forms.py, for
    shapes up to ``|theta| ~ 3`` rad, far past where the small-deflection model
    itself holds; 8 nodes suffice for ``|theta| <~ 0.3`` rad).

    Parameters
    ----------
    s : array_like
        Arc length(s) [m], 0 <= s <= L.
    F, z, L, EI, a, b, k : array_like
        As for :func:`deflection` (broadcast with ``s``).
    nodes : int
        Gauss-Legendre nodes per piece, 1 <= nodes <= 100 (default 16; more
        than a few dozen gains nothing in double precision).

    Returns
    -------
    ndarray, shape ``broadcast(s, F, ...).shape + (2,)``
        (axial, lateral) coordinates [m] in the bending plane, base at the
        origin, the undeformed rod along the axial direction; lateral is
        positive in the direction of F (as :func:`deflection`).  For small
        angles lateral(s) ~ deflection(s) and axial(s) ~ s.

    Out-of-domain input gives NaN with the "invalid" flag, as the ufuncs;
    non-numeric input raises TypeError naming the argument, a bad ``nodes``
    TypeError or ValueError naming ``nodes``.

    Examples
    --------
    >>> from tendonrod import analytic as an
    >>> xy = an.planar_shape(np.linspace(0.0, 0.2, 3), 0.5, 0.2, 0.2, 0.0112, 0.0, 0.008, np.inf)
    >>> xy.round(5)  # (axial, lateral) [m] at s = 0, L/2, L
    array([[0.     , 0.     ],
           [0.09868, 0.0148 ],
           [0.19735, 0.02959]])
    """
    try:
        nodes = operator.index(nodes)
    except TypeError:
        raise TypeError(f"planar_shape: nodes must be an integer, got {nodes!r}") from None
    if not 1 <= nodes <= _MAX_NODES:
        raise ValueError(
            f"planar_shape: nodes must be an integer in [1, {_MAX_NODES}], got {nodes!r}"
        )
    arrays = []
    for name, v in zip(("s", "F", "z", "L", "EI", "a", "b", "k"), (s, F, z, L, EI, a, b, k)):
        arr = np.asarray(v)
        if arr.dtype.kind not in "biuf":  # as the ufuncs: real numbers only
            raise TypeError(f"planar_shape: {name} must be real numbers, got {v!r}")
        arrays.append(arr.astype(float, copy=False))
    args = np.broadcast_arrays(*arrays)
    s_, F_, z_, L_, EI_, a_, b_, k_ = (v[..., np.newaxis] for v in args)
    x, w = np.polynomial.legendre.leggauss(nodes)
    t = 0.5 * (x + 1.0)  # nodes on [0, 1]
    m = np.minimum(s_, z_)  # end of the loaded piece
    out = np.zeros(args[0].shape + (2,))
    # piece 1: [0, m] (load ahead of u), piece 2: [m, s] (empty when s <= z)
    for lo, hi in ((np.zeros_like(m), m), (m, s_)):
        h = hi - lo
        u = lo + h * t
        th = angle(u, F_, z_, L_, EI_, a_, b_, k_)
        half = 0.5 * h[..., 0]
        out[..., 0] += half * (np.cos(th) @ w)
        out[..., 1] += half * (np.sin(th) @ w)
    return out
