"""Calibration: :func:`fit`, design parameters fitted to measured positions over a set of
loaded scenes, by nonlinear least squares (SciPy's ``least_squares``, the optional
``fit`` extra) on the design Jacobians of :func:`tendonrod.jacobian`.

Every evaluation solves each scene at the current parameter values (warm from its last
solution) and linearises it: the residuals' Jacobian is the design block of the
linearisation, by the implicit function theorem, not differences of full solves.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np

from ._deprecation import renamed_keywords
from ._linearize import jacobian
from .linearization import _design_names, design_value, with_design
from .model import Scene
from .options import _check_options
from .problem import _probe_scene
from .results import ConvergenceError, ConvergenceWarning, report_failure
from .solver import solve

__all__ = ["fit", "FitResult"]


@dataclass(frozen=True, eq=False)
class FitResult:
    """What :func:`fit` found.

    A :class:`~tendonrod.Result`: ``success``, ``status``, ``message``, ``nit``, ``nfev``
    mean the same on every result type.

    Attributes
    ----------
    names : tuple of str
        Canonical paths of the fitted parameters (see :mod:`tendonrod.linearization`).
    values : ndarray (p,)
        Fitted values (SI units of each parameter).
    stderr : ndarray (p,)
        Their standard errors: square roots of the covariance's diagonal.
    covariance : ndarray (p, p)
        ``s^2 (J^T J)^-1`` with the Jacobian J of the residuals [m per unit] at the fit and
        ``s^2`` the residual variance ``|r|^2 / (N - p)`` (``sigma`` None), or
        ``(J^T W J)^-1`` with the weights ``1 / sigma^2`` (``sigma`` given: known noise).
    initial : ndarray (p,)
        The starting values.
    residuals : ndarray (nscene, ns, 3)
        Model minus measurement at the fit [m], world frame (ns = 1 for tip positions).
    rms : float
        Root mean square of the residuals' components [m].
    success : bool
        SciPy's verdict (a convergence test met) and every scene solved.
    message : str
        SciPy's message, or what failed.
    nfev, njev : int
        Evaluations of the residuals (each a solve per scene) and of their Jacobian (a
        linearisation per scene).
    solutions : tuple of Solution
        Each scene solved at the fitted values (empty when a scene did not solve).
    status : int
        SciPy's status (``least_squares``: > 0 a convergence test met, 0 the evaluation
        budget spent), or -1: a scene did not solve.
    nit : int
        Levenberg-Marquardt iterations (one Jacobian evaluation each: ``njev``).

    Examples
    --------
    >>> truth = tr.Robot(tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True, EI=4.6e-3), [])
    >>> scenes = [tr.Scene(truth, loads=[tr.PointLoad(s=0.2, force=(-0.02, 0, 0))])]
    >>> res = tr.fit(scenes, [tr.solve(scenes[0]).tip_position], ["EI"], x0=[4e-3])
    >>> res.names, res.rms < 1e-12
    (('robot.rod.EI',), True)
    """

    names: tuple
    values: np.ndarray
    stderr: np.ndarray
    covariance: np.ndarray
    initial: np.ndarray
    residuals: np.ndarray
    rms: float
    success: bool
    message: str
    nfev: int
    njev: int
    solutions: tuple
    status: int = 0
    nit: int = 0

    def as_dict(self) -> dict:
        """``{name: (value, stderr)}``."""
        return {n: (float(v), float(e)) for n, v, e in zip(self.names, self.values, self.stderr)}

    def __repr__(self):
        body = ", ".join(
            f"{n}={v:.6g} +- {e:.2g}" for n, v, e in zip(self.names, self.values, self.stderr)
        )
        return f"FitResult({body}; rms {self.rms:.3g} m, success={self.success})"


def _scenes(scenes) -> list:
    try:
        out = list(scenes)
    except TypeError:
        raise ValueError(f"scenes must be a sequence of tendonrod.Scene, got {scenes!r}") from None
    if not out or not all(isinstance(sc, Scene) for sc in out):
        raise ValueError(f"scenes must be a non-empty sequence of tendonrod.Scene, got {scenes!r}")
    return out


def _floats(value, name: str, what: str) -> np.ndarray:
    """``value`` as a float array; ValueError naming ``name`` for what is no real number or
    beyond a double (an int like 10**400)."""
    try:
        return np.array(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"{name} must be {what}, got {value!r}") from None


def _arc_lengths(s, scenes):
    """The marker arc lengths (ns,) or None (the tip); ValueError naming ``s``."""
    if s is None:
        return None
    arr = np.atleast_1d(_floats(s, "s", "arc lengths [m]"))
    L = min(sc.robot.rod.length for sc in scenes)
    if arr.ndim != 1 or arr.size == 0 or not np.all((arr > 0.0) & (arr <= L)):
        raise ValueError(f"s must be arc lengths in (0, L = {L:g}] m, got {s!r}")
    return arr


def _measured(measured, n: int, ns: int) -> np.ndarray:
    arr = _floats(measured, "measured", "an array of positions [m]")
    if arr.shape == (n, 3) and ns == 1:
        arr = arr[:, None, :]
    if arr.shape != (n, ns, 3) or not np.all(np.isfinite(arr)):
        want = f"({n}, 3)" if ns == 1 else f"({n}, {ns}, 3)"
        raise ValueError(f"measured must be finite with shape {want}, got shape {arr.shape}")
    return arr


def _sigma(sigma, shape) -> np.ndarray | None:
    if sigma is None:
        return None
    try:
        arr = np.broadcast_to(_floats(sigma, "sigma", "a noise level [m]"), shape)
    except ValueError:
        raise ValueError(
            f"sigma must broadcast to the measurements {shape}, got {sigma!r}"
        ) from None
    if not np.all(np.isfinite(arr) & (arr > 0.0)):
        raise ValueError(f"sigma must be finite and > 0 [m], got {sigma!r}")
    return arr


class _Model:
    """The scenes at parameter values, solved warm and linearised, cached per value."""

    def __init__(self, scenes, paths, s, options):
        self.paths, self.s, self.options = paths, s, options
        # zero point loads at the markers: breakpoints, so the linearisation reports there
        self.scenes = [sc if s is None else _probe_scene(sc, s) for sc in scenes]
        self.guess = [None] * len(scenes)
        self.key = None
        self.sols = None
        self.nfev = self.njev = 0

    def solve(self, p):
        key = tuple(float(v) for v in p)
        if key == self.key:
            return self.sols
        sols = []
        for i, sc in enumerate(self.scenes):
            scene = with_design(sc, dict(zip(self.paths, p)))
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ConvergenceWarning)
                sol = solve(scene, guess=self.guess[i], options=self.options)
            if not sol.success:
                raise ConvergenceError(
                    f"tendonrod.fit: scene {i} did not solve at {dict(zip(self.paths, key))}: "
                    f"{sol.message}",
                    sol,
                )
            sols.append(sol)
        self.guess = sols
        self.key, self.sols = key, sols
        self.nfev += 1
        return sols

    def positions(self, p) -> np.ndarray:
        """(nscene, ns, 3) [m]."""
        out = []
        for sol in self.solve(p):
            if self.s is None:
                out.append(np.asarray(sol.tip_position)[None, :])
            else:
                out.append(np.array([sol.at(x).position for x in self.s]))
        return np.array(out)

    def jacobian(self, p) -> np.ndarray:
        """(nscene, ns, 3, p) [m per unit of each parameter]."""
        self.njev += 1
        out = []
        for sol in self.solve(p):
            jac = jacobian(sol, s=self.s, design=self.paths, load=False, strict=True)
            d = np.asarray(jac.design)
            out.append(d[None, :3, :] if self.s is None else d[:, :3, :])
        return np.array(out)


@renamed_keywords("tendonrod.fit", xtol="tol", max_nfev="max_iter")
def fit(
    scenes,
    measured,
    parameters,
    *,
    s=None,
    sigma=None,
    x0=None,
    options=None,
    tol: float = 1e-10,
    max_iter: int = 50,
    strict: bool = False,
) -> FitResult:
    """Fit design parameters to positions measured on a set of loaded scenes.

    Parameters
    ----------
    scenes : sequence of Scene
        The experiments: one robot design under different loads or actuations.  The
        parameters are set in every scene (each keeps everything else).
    measured : array (nscene, 3) or (nscene, ns, 3)
        Measured tip positions [m] (``s`` None), or positions of markers at the arc
        lengths ``s``, world frame (a mounted robot's too: its base pose is part of the model).
    parameters : sequence of str
        Design parameter names (``"EI"``, ``"tendons[0].EA"``, ``"tendons[0].offset"``,
        ... as in :mod:`tendonrod.linearization`).
    s : array (ns,), optional
        Marker arc lengths [m] (default: the tip).
    sigma : float or array, optional
        The measurement noise [m] (standard deviation; broadcast to ``measured``): the
        residuals are weighted by ``1 / sigma`` and the covariance taken as known noise.
        Default: unweighted, the covariance scaled by the residual variance.
    x0 : sequence (p,), optional
        Starting values (default: the first scene's values).
    options : Options, optional
        Solver options of every solve.
    tol : float
        The relative step tolerance on the parameters (SciPy's ``xtol``; ``xtol=`` before
        0.2).
    max_iter : int
        Most iterations, counted as SciPy's ``least_squares`` counts them: residual
        evaluations, each a solve of every scene (``max_nfev=`` before 0.2).
    strict : bool
        Raise :class:`~tendonrod.ConvergenceError` (its ``solution`` the
        :class:`FitResult`) instead of a :class:`~tendonrod.ConvergenceWarning` when the
        fit does not succeed (no convergence test met, or a scene did not solve at some
        parameter values: then the values are NaN and ``message`` says which).

    Returns
    -------
    FitResult
        Values, standard errors, covariance, residuals [m], the solutions at the fit.

    Raises
    ------
    ValueError
        For bad input (naming the argument).
    ImportError
        Without SciPy (``pip install tendonrod[fit]``).
    ConvergenceError
        With ``strict=True``, if the fit does not succeed.

    Examples
    --------
    EI of a bare rod from its tip positions under three loads (synthetic data):

    >>> truth = tr.Robot(tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True, EI=4.6e-3), [])
    >>> loads = [[tr.PointLoad(s=0.2, force=(-f, 0, 0))] for f in (0.01, 0.02, 0.03)]
    >>> measured = [tr.solve(tr.Scene(truth, loads=ld)).tip_position for ld in loads]
    >>> model = tr.Robot(tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True), [])
    >>> res = tr.fit([tr.Scene(model, loads=ld) for ld in loads], measured, ["EI"])
    >>> res.success, round(float(res.values[0]), 9)
    (True, 0.0046)
    """
    try:
        from scipy.optimize import least_squares
    except ImportError as exc:  # pragma: no cover - scipy is in the test environment
        raise ImportError("tendonrod.fit needs SciPy: pip install 'tendonrod[fit]'") from exc
    scenes = _scenes(scenes)
    # every scene must have the parameters (the same paths: one robot design)
    for sc in scenes:
        paths = [p for p, _, _ in _design_names(sc, parameters, "parameters")]
    if not paths:
        raise ValueError("parameters must name at least one design parameter")
    sv = _arc_lengths(s, scenes)
    ns = 1 if sv is None else len(sv)
    meas = _measured(measured, len(scenes), ns)
    sig = _sigma(sigma, meas.shape)
    # (an upper bound far beyond any fit, that SciPy's C long takes)
    if isinstance(max_iter, bool) or not isinstance(max_iter, int) or not 1 <= max_iter <= 10**9:
        raise ValueError(f"max_iter must be an int in [1, 1e9], got {max_iter!r}")
    if not (isinstance(tol, (int, float)) and 0.0 < tol < 1.0):
        raise ValueError(f"tol must be in (0, 1), got {tol!r}")
    p0 = _floats(
        [design_value(scenes[0], p) for p in paths] if x0 is None else x0, "x0", "real numbers"
    )
    if p0.shape != (len(paths),) or not np.all(np.isfinite(p0) & (p0 != 0.0)):
        raise ValueError(f"x0 must hold {len(paths)} finite nonzero values, got {x0!r}")
    options = _check_options(options)
    model = _Model(scenes, paths, sv, options)
    w = 1.0 if sig is None else 1.0 / sig
    # unknowns: the parameters relative to their starting values (all of order 1)
    scale = np.abs(p0)

    def resid(x):
        return ((model.positions(x * scale) - meas) * w).ravel()

    def jac(x):
        J = model.jacobian(x * scale) * (w[..., None] if sig is not None else 1.0)
        return J.reshape(-1, len(paths)) * scale

    try:
        res = least_squares(resid, p0 / scale, jac=jac, method="lm", xtol=tol, max_nfev=max_iter)
    except ConvergenceError as exc:
        nan = np.full(len(paths), np.nan)
        out = FitResult(
            names=tuple(paths),
            values=nan,
            stderr=nan,
            covariance=np.full((len(paths), len(paths)), np.nan),
            initial=p0,
            residuals=np.full(meas.shape, np.nan),
            rms=math.nan,
            success=False,
            message=str(exc),
            nfev=model.nfev,
            njev=model.njev,
            solutions=(),
            status=-1,
            nit=model.njev,
        )
        report_failure(out, strict, out.message)
        return out
    p = res.x * scale
    r = model.positions(p) - meas
    J = model.jacobian(p).reshape(-1, len(paths))
    if sig is not None:
        Jw = J / sig.reshape(-1, 1)
        cov = np.linalg.pinv(Jw.T @ Jw)
    else:
        dof = max(r.size - len(paths), 1)
        cov = np.linalg.pinv(J.T @ J) * float(r.ravel() @ r.ravel()) / dof
    out = FitResult(
        names=tuple(paths),
        values=p,
        stderr=np.sqrt(np.maximum(np.diag(cov), 0.0)),
        covariance=cov,
        initial=p0,
        residuals=r,
        rms=float(math.sqrt(np.mean(r**2))),
        success=bool(res.success),
        message=str(res.message),
        nfev=model.nfev,
        njev=model.njev,
        solutions=tuple(model.solve(p)),
        status=int(res.status),
        nit=model.njev,
    )
    report_failure(out, strict, f"tendonrod.fit did not succeed: {out.message}")
    return out
