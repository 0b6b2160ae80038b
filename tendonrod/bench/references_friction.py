"""An independent reference for a tendon with channel friction (SciPy; never calls the core).

A planar Kirchhoff cantilever of length ``L`` [m] and bending rigidity ``EI`` [N m^2]
carries one parallel tendon at the offset ``r`` [m] on its +x side, anchored at the tip,
in a channel with Coulomb coefficient ``mu``, sliding in (``sliding=+1``: tension falls
from the actuator toward the anchor) or out (``-1``); a dead force ``F = (Fx, Fz)`` [N]
(world) acts at the tip.  Conventions of ``docs/model.md``: base at the origin,
undeformed rod along +z, ``theta`` the rotation about +y (positive toward +x).

The formulation is not the solver's.  The free body distal of ``s`` (rod and tendon
beyond ``s``) is loaded by the tip force and by the cut tendon, whose pull
``-tau(s) t`` acts at the offset ``r`` along the section's tangent; the channel forces,
friction included, are internal to it.  So the bending moment is

    EI theta' = (Z - z) Fx - (X - x) Fz + r tau(s),     (X, Z) = p(L),

with no distributed tendon load at all, and the tangent of a parallel tendon on a
Kirchhoff rod turns with the section, ``|t'| = |theta'|``, so the tension follows the
capstan law ``tau' = -sliding mu tau |theta'|``.  The unknown tip ``(X, Z)`` is found by
shooting (``solve_ivp`` DOP853, ``scipy.optimize.fsolve``).  A displacement-controlled
tendon adds its tension at the actuator as a third unknown and the length constraint
(docs/model.md, Section 5): the rest length of the material inside the channel,
``int (1 - r theta') / (1 + tau/EA) ds``, plus the pulled-out part
``q / (1 + tau(0)/EA)``, is ``L``.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["friction_tendon_state"]


def _integrate(L, EI, r, mu, sliding, F, EA, tau0, tip, s_out=None):
    from scipy.integrate import solve_ivp

    Fx, Fz = F
    X, Z = tip

    def rhs(s, y):
        x, z, th, tau, _ = y
        kap = ((Z - z) * Fx - (X - x) * Fz + r * tau) / EI
        return [
            math.sin(th),
            math.cos(th),
            kap,
            -sliding * mu * tau * abs(kap),
            (1.0 - r * kap) / (1.0 + tau / EA),
        ]

    sol = solve_ivp(
        rhs,
        (0.0, L),
        [0.0, 0.0, 0.0, tau0, 0.0],
        method="DOP853",
        rtol=1e-13,
        atol=1e-15,
        t_eval=s_out,
    )
    return sol


def friction_tendon_state(
    L, EI, r, mu, sliding, F=(0.0, 0.0), *, tension=None, q=None, EA=math.inf
):
    """The state of the robot above under the tendon's ``tension`` [N] at the actuator or
    its displacement ``q`` [m] (> 0 retracts): a dict with ``tip`` (x, z) [m],
    ``tip_angle`` [rad], ``tension`` (at the actuator) and ``tension_tip`` [N], and
    ``displacement`` q [m] (given or consistent with the solution)."""
    from scipy.optimize import brentq, fsolve

    if (tension is None) == (q is None):
        raise ValueError("give exactly one of tension= and q=")
    F = (float(F[0]), float(F[1]))

    def state(tau0):
        def resid(u):
            y = _integrate(L, EI, r, mu, sliding, F, EA, tau0, u).y[:, -1]
            return [(y[0] - u[0]) / L, (y[1] - u[1]) / L]

        u = fsolve(resid, [0.0, L], xtol=1e-14, full_output=True)[0]
        y = _integrate(L, EI, r, mu, sliding, F, EA, tau0, u).y[:, -1]
        disp = (1.0 + tau0 / EA) * (L - y[4])
        return y, disp, float(np.max(np.abs(resid(u))))

    if tension is None:
        # the displacement grows with the tension: bracket q, then Brent
        hi = EI / (r * L)
        while state(hi)[1] < q:
            hi *= 2.0
        tension = brentq(lambda t: state(t)[1] - q, 0.0, hi, xtol=1e-15, rtol=1e-15)
    y, disp, res = state(tension)
    return {
        "tip": np.array([y[0], y[1]]),
        "tip_angle": float(y[2]),
        "tension": float(tension),
        "tension_tip": float(y[3]),
        "displacement": float(disp if q is None else q),
        "residual": res,
    }
