"""The work-precision scenes with channel friction (docs/model.md, Section 3): the exact
planar solution turned to 180 degrees (mu = 1, sliding out), and a displacement-
controlled tendon under a tip load that reverses the curvature (mu = 1, sliding out),
against the SciPy free-body reference (:mod:`tendonrod.bench.references_friction`).
:func:`friction_scenes` takes the benchmark's ``WPScene`` class (no import cycle with
:mod:`tendonrod.bench.work_precision`)."""

from __future__ import annotations

import math

import numpy as np

from .common import FIG17, EI_of
from .references_friction import friction_tendon_state
from .stress_friction import LOADED, _loaded_scene, exact_friction_scene, exact_friction_tip

__all__ = ["friction_scenes"]

#: The exact scene: mu [-], sliding, tip angle [rad] (r kappa reaches 0.55 at the tip).
EXACT = (1.0, "out", math.pi)


def _tip_scale(ref):
    return float(np.linalg.norm(ref))


def _loaded_tip(mu, sliding, F, kind, value, EA):
    p = FIG17
    kw = {"tension": value} if kind == "tension" else {"q": value}
    sig = 1.0 if sliding == "in" else -1.0
    ref = friction_tendon_state(p["L"], EI_of(p), p["r"], mu, sig, F, EA=EA, **kw)
    return np.array([ref["tip"][0], 0.0, ref["tip"][1]])


def friction_scenes(WPScene) -> list:
    """The two scenes as ``WPScene`` objects."""
    mu, sl, th = EXACT
    loaded = LOADED[1]
    return [
        WPScene(
            "friction_exact",
            "friction mu=1 sliding out, 180°, no load (exact)",
            exact_friction_scene(mu, sl, th),
            lambda: exact_friction_tip(*EXACT)[0],
            "exact",
            _tip_scale,
        ),
        WPScene(
            "friction_loaded",
            "friction mu=1 out, q=12 mm, tip force against the bend (SciPy)",
            _loaded_scene(*loaded),
            lambda: _loaded_tip(*loaded),
            "independent ODE",
            _tip_scale,
        ),
    ]
