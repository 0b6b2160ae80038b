"""The paper's closed-form charts (Figs. 3, 6, 7) and the design question of notebook
07, from :mod:`tendonrod.analytic`."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .. import analytic
from .robots import paper_rod_ivb, tendon_EA

__all__ = ["closed_form_sigma_vs_zeta", "closed_form_tip_sigma_vs_alpha", "design_study"]


def closed_form_sigma_vs_zeta(zeta=None, slopes=(0.0,), alpha: float = math.inf) -> dict:
    """Figs. 3 and 6: sigma(zeta) at the loaded point (eqs. 10, 29, 33).

    ``slopes`` are a L / b (0: parallel, -1: converging); ``alpha`` = b^2 k L / EI.
    Returns zeta, 'no tendon' (4 zeta^3) and one curve per slope.
    """
    zeta = np.linspace(0.0, 1.0, 101) if zeta is None else np.asarray(zeta, dtype=float)
    out = {
        "zeta": zeta,
        "no tendon": 12.0 * analytic.deflection(zeta, 1.0, zeta, 1.0, 1.0, 0.0, 1.0, 0.0),
    }
    for a in slopes:
        out[a] = 12.0 * analytic.deflection(zeta, 1.0, zeta, 1.0, 1.0, a, 1.0, alpha)
    return out


def closed_form_tip_sigma_vs_alpha(alpha=None) -> dict:
    """Fig. 7: tip sigma against alpha = r^2 k L / EI for parallel and converging routing
    (eqs. 9-10 and 32)."""
    alpha = np.logspace(-2, 4, 121) if alpha is None else np.asarray(alpha, dtype=float)
    return {
        "alpha": alpha,
        "parallel": 12.0 * analytic.deflection(1.0, 1.0, 1.0, 1.0, 1.0, 0.0, 1.0, alpha),
        "converging": 12.0 * analytic.deflection(1.0, 1.0, 1.0, 1.0, 1.0, -1.0, 1.0, alpha),
    }


def design_study(
    target_sigma: float = 1.0, rod=None, offset: float = 0.01, alphas=None, theta: float = 0.0
) -> dict:
    """Notebook 07: which routing and tendon stiffness reach a target tip stiffness?

    Closed forms (theta = 0, straight robot): tip sigma(alpha) for parallel (eq. 10) and
    converging (eq. 32) routing, the smallest alpha reaching ``target_sigma`` for each
    (parallel cannot go below sigma = 1), the tendon EA [N] that alpha means for ``rod``
    and ``offset``, and the actuation tension per radian of tip angle (eqs. 37-38).
    """
    rod = paper_rod_ivb() if rod is None else rod
    EI, L = rod.bending_stiffness, rod.length
    alphas = np.logspace(-1, 5, 241) if alphas is None else np.asarray(alphas, dtype=float)
    cf = closed_form_tip_sigma_vs_alpha(alphas)
    out: dict[Any, Any] = {
        "alpha": alphas,
        "target": target_sigma,
        "parallel": cf["parallel"],
        "converging": cf["converging"],
    }
    for routing, a in (("parallel", 0.0), ("converging", -offset / L)):
        # sigma is decreasing in alpha: invert the closed form exactly where possible
        if routing == "parallel":
            # 4 - 3 alpha/(1+alpha) = s  ->  alpha = (4 - s)/(s - 1)
            need = (
                (4.0 - target_sigma) / (target_sigma - 1.0)
                if 1.0 < target_sigma < 4.0
                else (0.0 if target_sigma >= 4.0 else math.inf)
            )
        else:
            # 12/(3+alpha) = s  ->  alpha = 12/s - 3
            need = max(12.0 / target_sigma - 3.0, 0.0) if target_sigma > 0 else math.inf
        out[(routing, "alpha_needed")] = need
        out[(routing, "EA_needed")] = (
            tendon_EA(need, EI, offset) if math.isfinite(need) else math.inf
        )
        out[(routing, "tension_per_rad")] = float(
            analytic.actuation_tension_for_angle(1.0, L, EI, a, offset)
        )
    return out
