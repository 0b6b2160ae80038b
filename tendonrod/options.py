"""Numerical options of :func:`tendonrod.solve` (:class:`Options`) and their validation.

Each option maps onto the raw ``tendonrod._core.solve`` keyword of the same name;
bad values raise ``ValueError`` here, before any C runs.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Sequence
from dataclasses import dataclass, fields
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from . import _core

__all__ = ["Options"]

# Defaults, accepted names and ranges are the core's (tr_default_options,
# tr_options_check): read from the extension, never written here again.
_DEFAULTS = _core.DEFAULT_OPTIONS
_CHOICES = _core.CHOICES
_LIMITS = _core.LIMITS
_INTEGRATORS = _CHOICES["integrator"]
_JACOBIANS = _CHOICES["jacobian_method"]
_SLACK_MODELS = _CHOICES["slack_model"]
_RTOL_MIN = _LIMITS["rtol"][0]


def _as_float(v) -> float:
    """float(v), inf for a number too large for a double (2**2000)."""
    try:
        return float(v)
    except OverflowError:
        return math.inf


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
        j L / M (default 1: single shooting, fastest; see ``auto_shooting``).
    auto_shooting : bool
        True (default): with ``shooting_segments=1``, a scene whose tensile axial loads
        make the single-shooting sensitivities grow like exp(g), g = int sqrt(T/EI) ds
        (L sqrt(T/EI) for a tip load) above 11, is compiled with ceil(g / 4) shooting
        segments instead; :attr:`Solution.formulation` reports ``shooting_auto`` and
        ``shooting_growth``.  Chosen from the loads the scene is compiled with (a
        :class:`Problem` whose loads later grow keeps its choice).  False: exactly
        ``shooting_segments``.
    max_work : float
        Work budget of one solve, everything included (continuation, step verification,
        the confirmation of an equilibrium found off the load path), in units of one
        right-hand-side evaluation of a planar Kirchhoff rod (~25-30 ns here; one of a
        spatial Cosserat rod with three tendons counts ~9; the LU factorisations and the
        condition estimate count their CPU time in the same units).  Default 3.5e7: a
        hopeless solve gives up after about 1 s whatever the formulation, with a
        message that says the budget ran out; converged solves take 10^2-10^6, and up to ~1.6e7 where a warm solve
        lands on an unstable equilibrium and continues from its guess.  Deterministic: a
        solve stays bitwise reproducible.
    max_time : float
        Wall-clock limit of one solve [s]; 0 (default) for none.  Opt-in and not
        deterministic: where a solve stops depends on the machine.
    accept_unstable : bool
        False (default): every solve judges the stability of its answer and never reports
        success on an unstable equilibrium -- a cold solve that lands on one follows the
        load path from the unloaded robot instead (breaking a symmetric bifurcation with a
        small imperfection it names in the message), a warm one continues from its guess;
        where no stable equilibrium is found the solve fails with the unstable one as data
        (status 5, :attr:`Solution.stable` False).  True: a converged equilibrium is a
        success whatever its stability, which the solve does not judge
        (:attr:`Solution.stable` computes it on first access).

    Examples
    --------
    >>> opts = tr.Options(steps=4, tol=3e-9, tip_only=True)  # faster, about 1e-9 L
    >>> opts.integrator, opts.steps
    ('rk8', 4)
    """

    integrator: str = _DEFAULTS["integrator"]
    steps: int = _DEFAULTS["steps"]
    rtol: float = _DEFAULTS["rtol"]
    tol: float = _DEFAULTS["tol"]
    max_iter: int = _DEFAULTS["max_iter"]
    max_nfev: int = _DEFAULTS["max_nfev"]
    jacobian_method: str = _DEFAULTS["jacobian_method"]
    slack_model: str = _DEFAULTS["slack_model"]
    continuation: bool = _DEFAULTS["continuation"]
    max_continuation: int = _DEFAULTS["max_continuation"]
    nodes: int | Sequence[float] | np.ndarray = _DEFAULTS["nodes"]
    force_spatial: bool = _DEFAULTS["force_spatial"]
    tip_only: bool = _DEFAULTS["tip_only"]
    shooting_segments: int = _DEFAULTS["shooting_segments"]
    auto_shooting: bool = _DEFAULTS["auto_shooting"]
    max_work: float = _DEFAULTS["max_work"]
    max_time: float = _DEFAULTS["max_time"]
    accept_unstable: bool = _DEFAULTS["accept_unstable"]
    if TYPE_CHECKING:  # set per instance in __post_init__; not a field
        _raw: ClassVar[dict[str, Any]]
        _core_kw: ClassVar[dict[str, Any]]

    def __post_init__(self):
        own = "Options"
        for name, allowed in _CHOICES.items():
            v = getattr(self, name)
            if not isinstance(v, str) or v not in allowed:
                raise ValueError(f"{own}.{name} must be one of {allowed}, got {v!r}")
        for name in ("steps", "max_iter", "max_nfev", "max_continuation", "shooting_segments"):
            lo, hi = _LIMITS[name]
            v = getattr(self, name)
            if (
                isinstance(v, (bool, np.bool_))
                or not isinstance(v, (numbers.Integral, np.integer))
                or not lo <= v <= hi
            ):
                raise ValueError(f"{own}.{name} must be an integer in [{lo}, {hi}], got {v!r}")
            object.__setattr__(self, name, int(v))
        for name in ("max_work", "max_time"):
            lo, hi = _LIMITS[name]
            v = getattr(self, name)
            ok = isinstance(v, (numbers.Real, np.floating)) and not isinstance(v, bool)
            if not ok or not (math.isfinite(_as_float(v)) and lo <= _as_float(v) <= hi):
                raise ValueError(
                    f"{own}.{name} must be a real number in [{lo:g}, {hi:g}], got {v!r}"
                )
            object.__setattr__(self, name, float(v))
        for name in ("rtol", "tol"):
            lo, hi = _LIMITS[name]
            v = getattr(self, name)
            ok = isinstance(v, (numbers.Real, np.floating)) and not isinstance(v, bool)
            x = _as_float(v) if ok else math.nan
            # rtol in [lo, hi) (lo > 0), tol in (lo, hi) (lo = 0)
            if not ok or not (math.isfinite(x) and lo < x < hi or x == lo > 0.0):
                rng = f"[{lo:g}, {hi:g})" if lo > 0.0 else f"({lo:g}, {hi:g})"
                raise ValueError(f"{own}.{name} must be a real number in {rng}, got {v!r}")
            object.__setattr__(self, name, float(v))
        for name in (
            "continuation",
            "force_spatial",
            "tip_only",
            "auto_shooting",
            "accept_unstable",
        ):
            v = getattr(self, name)
            if not isinstance(v, (bool, np.bool_)):
                raise ValueError(f"{own}.{name} must be True or False, got {v!r}")
            object.__setattr__(self, name, bool(v))
        nodes = self.nodes
        if isinstance(nodes, (numbers.Integral, np.integer)) and not isinstance(
            nodes, (bool, np.bool_)
        ):
            lo, hi = _LIMITS["nodes"]
            if not lo <= nodes <= hi:
                raise ValueError(
                    f"{own}.nodes must be in [{lo}, {hi}] (or an array of arc lengths), "
                    f"got {nodes!r}"
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
                not 1 <= arr.size <= _LIMITS["nodes"][1]
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
        raw = {f.name: getattr(self, f.name) for f in fields(self)}
        object.__setattr__(self, "_raw", raw)
        # what the core must be told: the options that differ from its defaults (a
        # compiled problem starts from those), so the default options parse as nothing
        object.__setattr__(
            self,
            "_core_kw",
            {
                k: v
                for k, v in raw.items()
                if not (type(v) is type(_DEFAULTS[k]) and v == _DEFAULTS[k])
            },
        )

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
