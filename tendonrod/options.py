"""Numerical options of :func:`tendonrod.solve` (:class:`Options`) and their validation.

Each option maps onto the raw ``tendonrod._core.solve`` keyword of the same name;
bad values raise ``ValueError`` here, before any C runs.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Sequence
from dataclasses import dataclass, fields

import numpy as np

__all__ = ["Options"]

_INTEGRATORS = ("rk8", "rk4", "adaptive")
_JACOBIANS = ("fd", "newton", "hybrid")
# Adaptive-integrator tolerances below ~50 ulp cannot be met in double precision (the
# step shrinks to underflow, seconds per evaluation): refused (TR_RTOL_MIN in the core).
_RTOL_MIN = 1e-14
_SLACK_MODELS = ("linear", "squared")


@dataclass(frozen=True)
class Options:
    """Numerical options of :func:`tendonrod.solve` (each maps onto the raw ``_core.solve``
    keyword of the same name).

    Attributes
    ----------
    integrator : str
        ``"rk8"`` (default: a fixed-step 8th-order Runge-Kutta reaches 1e-8 relative tip
        accuracy in a handful of steps on this non-stiff ODE), ``"rk4"`` (classical RK4),
        or ``"adaptive"`` (GSL's adaptive embedded RK with tolerance ``rtol``: slow,
        for reference solutions).
    steps : int
        Fixed-step integrators: steps over the rod; 0 (default) lets the core choose
        from the curvature scale of the scene.
    rtol : float
        Relative tolerance of the adaptive integrator (default 1e-10: well below the
        1e-8 the fixed-step methods aim at, so references are references).
    tol : float
        Convergence tolerance on the scaled residual (forces by EI/L^2, moments by EI/L,
        lengths by L). Default 1e-10: about 1e-10 relative accuracy of the tip, well
        below the integrator's truncation error with default steps, so the iteration is
        never the accuracy bottleneck.
    max_iter : int
        Cap on Newton/trust-region iterations per solve (default 50: converged solves
        take 2-10; 50 leaves room for hard continuation stages without hiding a stall).
    max_nfev : int
        Cap on right-hand-side integrations counted as shooting evaluations, continuation
        included (default 20000: bounds the time of a hopeless solve to well under a second).
    jacobian_method : str
        ``"fd"`` (default: one forward-difference Jacobian in scaled unknowns, then Broyden
        updates, refreshed on poor progress: fewest integrations per solve) or ``"newton"``
        (a fresh forward-difference Jacobian every iteration: more robust, slower) or
        ``"hybrid"`` (GSL's hybridsj dogleg trust region on the same scaled residual; kept
        for comparison in the work-precision benchmark, no general gain measured).
    slack_model : str
        ``"linear"`` (default: tension = max(gamma, 0), slack = max(-gamma, 0), whose
        Jacobian stays nonsingular at the taut/slack switch) or ``"squared"`` (the
        paper's gamma^2, kept to measure its singular Jacobian at the switch).
    continuation : bool
        If a cold solve fails, ramp load and actuation from a solved state (default True:
        users should not have to hand-tune continuation).
    max_continuation : int
        Cap on continuation stages (default 64: a ramp halved six times).
    nodes : int or array of float
        Output nodes: a count of equally spaced arc lengths on [0, L] (default 101: a
        smooth plot), to which every interior breakpoint (point load, tendon anchor) is
        added twice (the states before and after its jump); or a non-decreasing array of
        arc lengths [m] in [0, L] (a node at a breakpoint gives the state after the jump,
        unless the next node has the same s). Nodes do not change the integration (the
        integrator steps are independent of them).
    force_spatial : bool
        Solve a planar scene with the full spatial formulation (default False: planar
        scenes are solved as planar problems, which is faster and gives the same answer).
    tip_only : bool
        Fill only the tip state (``s``, ``position`` ... have one row, at s = L;
        default False). For sweeps that need tip quantities only.
    shooting_segments : int
        M > 1: multiple shooting with full-state unknowns and continuity residuals at
        j L / M (default 1: single shooting is fastest and suffices unless a tensile axial
        load has L sqrt(T/EI) >~ 7, where single shooting diverges).
    """

    integrator: str = "rk8"
    steps: int = 0
    rtol: float = 1e-10
    tol: float = 1e-10
    max_iter: int = 50
    max_nfev: int = 20000
    jacobian_method: str = "fd"
    slack_model: str = "linear"
    continuation: bool = True
    max_continuation: int = 64
    nodes: int | Sequence[float] | np.ndarray = 101
    force_spatial: bool = False
    tip_only: bool = False
    shooting_segments: int = 1

    def __post_init__(self):
        own = "Options"
        for name, allowed in (
            ("integrator", _INTEGRATORS),
            ("jacobian_method", _JACOBIANS),
            ("slack_model", _SLACK_MODELS),
        ):
            v = getattr(self, name)
            if not isinstance(v, str) or v not in allowed:
                raise ValueError(f"{own}.{name} must be one of {allowed}, got {v!r}")
        for name, lo in (
            ("steps", 0),
            ("max_iter", 1),
            ("max_nfev", 1),
            ("max_continuation", 0),
            ("shooting_segments", 1),
        ):
            v = getattr(self, name)
            if (
                isinstance(v, (bool, np.bool_))
                or not isinstance(v, (numbers.Integral, np.integer))
                or v < lo
            ):
                raise ValueError(f"{own}.{name} must be an integer >= {lo}, got {v!r}")
            object.__setattr__(self, name, int(v))
        for name, lo in (("rtol", _RTOL_MIN), ("tol", 0.0)):
            v = getattr(self, name)
            ok = isinstance(v, (numbers.Real, np.floating)) and not isinstance(v, bool)
            if not ok or not (
                math.isfinite(float(v)) and lo < float(v) < 1.0 or float(v) == lo > 0.0
            ):
                rng = f"[{lo:g}, 1)" if lo > 0.0 else "(0, 1)"
                raise ValueError(f"{own}.{name} must be a real number in {rng}, got {v!r}")
            object.__setattr__(self, name, float(v))
        for name in ("continuation", "force_spatial", "tip_only"):
            v = getattr(self, name)
            if not isinstance(v, (bool, np.bool_)):
                raise ValueError(f"{own}.{name} must be True or False, got {v!r}")
            object.__setattr__(self, name, bool(v))
        nodes = self.nodes
        if isinstance(nodes, (numbers.Integral, np.integer)) and not isinstance(
            nodes, (bool, np.bool_)
        ):
            if nodes < 2:
                raise ValueError(
                    f"{own}.nodes must be >= 2 (or an array of arc lengths), got {nodes!r}"
                )
            object.__setattr__(self, "nodes", int(nodes))
        else:
            try:
                arr = np.array(nodes, dtype=float).ravel()
            except (TypeError, ValueError):
                raise ValueError(
                    f"{own}.nodes must be an int or an array of arc lengths, got {nodes!r}"
                ) from None
            if (
                arr.size < 1
                or not np.all(np.isfinite(arr))
                or np.any(np.diff(arr) < 0)
                or arr[0] < 0
            ):
                raise ValueError(
                    f"{own}.nodes must be a non-empty, non-decreasing array of finite "
                    f"arc lengths >= 0, got {nodes!r}"
                )
            arr.setflags(write=False)
            object.__setattr__(self, "nodes", arr)
        # the raw keyword arguments, built once (solve() is called in tight loops)
        object.__setattr__(self, "_raw", {f.name: getattr(self, f.name) for f in fields(self)})

    def __hash__(self):  # nodes may be an array
        return hash(tuple((f.name, self._key(getattr(self, f.name))) for f in fields(self)))

    def __eq__(self, other):
        if not isinstance(other, Options):
            return NotImplemented
        return all(
            np.array_equal(getattr(self, f.name), getattr(other, f.name))
            if isinstance(getattr(self, f.name), np.ndarray)
            or isinstance(getattr(other, f.name), np.ndarray)
            else getattr(self, f.name) == getattr(other, f.name)
            for f in fields(self)
        )

    @staticmethod
    def _key(v):
        return tuple(v.tolist()) if isinstance(v, np.ndarray) else v

    def raw(self) -> dict:
        """The keyword arguments of ``_core.solve`` (nodes as int or float64 array); a copy."""
        return dict(self._raw)


def _replace(options: Options, **changes) -> Options:
    """A copy of ``options`` with ``changes`` (validated again)."""
    kw = options.raw()
    kw.update(changes)
    return Options(**kw)


_DEFAULT_OPTIONS = Options()


def _check_options(options) -> Options:
    """``options`` as an :class:`Options` (None: the defaults; a dict: its keywords)."""
    if options is None:
        return _DEFAULT_OPTIONS
    if isinstance(options, dict):
        return Options(**options)
    if not isinstance(options, Options):
        raise ValueError(f"options must be a tendonrod.Options (or dict), got {options!r}")
    return options
