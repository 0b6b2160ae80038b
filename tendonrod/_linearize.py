"""The public linearisation :func:`jacobian` of a scene or a solution (the workspace's
own, :meth:`Problem.jacobian`, lives with :class:`~tendonrod.Problem`), and how a
linearisation that could not be taken is reported.
"""

from __future__ import annotations

from typing import Any, Literal, overload

import numpy as np
from numpy.typing import NDArray

from .linearization import Jacobian, _design_names, _forward, _sides
from .model import Scene
from .problem import Problem, _arc_lengths, _probe_scene
from .results import ConvergenceError, report_failure
from .solution import Solution, _in_rod_units

__all__ = ["jacobian"]


# the types: J.load is an array with load=True (the default), None only with load=False
# fmt: off
@overload
def jacobian(scene_or_solution, s=None, *, design=(), load: Literal[True] = True, method: str = "forward", side=None, guess=None, options=None, strict: bool = False) -> Jacobian[NDArray[np.float64]]: ...
@overload
def jacobian(scene_or_solution, s=None, *, design=(), load: bool, method: str = "forward", side=None, guess=None, options=None, strict: bool = False) -> Jacobian[NDArray[np.float64] | None]: ...
# fmt: on
def jacobian(
    scene_or_solution,
    s=None,
    *,
    design=(),
    load: bool = True,
    method: str = "forward",
    side=None,
    guess=None,
    options=None,
    strict: bool = False,
) -> Jacobian[Any]:
    """The linearisation of a solved scene at arc length ``s`` [m] (default: the tip):
    how the backbone point at ``s`` and the tendon tensions move per unit change of each
    tendon's control value, of a load applied at ``s`` and of named design parameters.

    By the implicit function theorem on the converged shooting system: linear solves
    with its Jacobian, no further nonlinear solve -- the derivatives of the solution the
    solver converged to.  Their accuracy is that of the differences of the shooting map
    over its k unknowns (``method``): forward by default (k + 1 evaluations, step 5e-8 in
    the solver's scaled units), within ~1e-7 of the exact derivatives relative to each
    column on the test scenes (~2e-8 on the Fig. 11c robot; ~1e-6 where a direction the
    pose barely feels moves the unknowns fast, e.g. the common tension level of a stiff
    taut tendon pair on a straight robot), or central (2 k + 1 evaluations, step 3e-6, a
    truncation error near 1e-11: the numbers of :func:`tendonrod.compliance`).  A
    parameter that does not enter the shooting map in closed form (a design parameter, a
    tension control, a load off the tip) is differenced centrally either way.

    Parameters
    ----------
    scene_or_solution : Scene or Solution
        A scene (solved first, from ``guess``) or a converged solution (its state is
        taken again in one or two shooting evaluations).
    s : float or array (N,), optional
        Arc length(s) in (0, L] [m]; default the tip.  Off the tip, anchors and point
        loads, the scene is solved once more with zero point loads there.
    design : sequence of str
        Design parameters to differentiate with respect to, by name (``"EI"``,
        ``"robot.tendons[0].EA"``, ``"tendons[1].offset"``; see
        :mod:`tendonrod.linearization`).
    load : bool
        Compute the compliance block (default True).
    method : {"forward", "central"}
        The differences of the shooting map over its unknowns: first-order (default;
        ~1e-7 relative at worst) or central (about twice the evaluations, ~1e-11).
    side : array (ntendon,) of +1 / -1 / 0, optional
        For a displacement-controlled tendon at its taut/slack switch: the taut (+1) or
        slack (-1) side's derivatives; 0 (default) the side it is on.
    guess, options
        As in :func:`tendonrod.solve`.
    strict : bool
        Raise :class:`~tendonrod.ConvergenceError` instead of a
        :class:`~tendonrod.ConvergenceWarning` when the scene does not solve or the
        linearisation fails; without it the Jacobian is returned with ``success`` False
        and NaN derivatives (``solution`` the unconverged state).

    Returns
    -------
    Jacobian
        ``actuation`` (6, ntendon), ``tension`` (ntendon, ntendon), ``load`` (6, 6),
        ``design`` (6, ndesign), ``design_tension`` (ntendon, ndesign), ``at_switch``.

    Raises
    ------
    ConvergenceError
        With ``strict=True``, if the scene does not solve or the linearisation fails.
    ValueError
        For a bad ``s``, an unknown design parameter, or a Solution that did not converge.

    Examples
    --------
    >>> robot = tr.Robot(tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True), [tr.Tendon(0.01)])
    >>> tr.jacobian(tr.Scene(robot, displacement=[0.01]), design=["EI"]).design.shape
    (6, 1)
    """
    from .solution import Solution as _Solution

    if isinstance(scene_or_solution, _Solution):
        sol = scene_or_solution
        if not sol.success:
            raise ValueError(
                "scene_or_solution: a Solution that did not converge cannot be linearised "
                f"(status {sol.status}: {sol.message})"
            )
        scene = sol.scene
        options = sol.options if options is None else options
        guess = sol if guess is None else guess
    elif isinstance(scene_or_solution, Scene):
        scene = scene_or_solution
    else:
        raise ValueError(
            f"scene_or_solution must be a tendonrod.Scene or Solution, got {scene_or_solution!r}"
        )
    L = scene.robot.rod.length
    s_vals, _ = _arc_lengths(s, L)
    _design_names(scene, design)
    _forward(method)
    _sides(side, scene.robot.n_tendons)
    probed = _probe_scene(scene, s_vals)
    if isinstance(scene_or_solution, _Solution) and probed is scene and options is sol.options:
        # the solution's own structure: linearise its state, no solve
        prob = Problem(scene, options=options)
        prob._last = sol
        state = (sol.unknowns, max(1, sol.formulation.steps))
        try:
            return prob._jacobian(sol, s, design, load, method, False, state, side)
        except ConvergenceError as exc:
            return _failed(scene, s_vals, s, design, load, exc.solution, str(exc), strict)
    prob = Problem(probed, options=options)
    psol = Solution(prob._run(guess), prob.scene, prob.options)
    if not psol.success:
        msg = f"tendonrod.jacobian: the scene did not solve: {psol.message}{_in_rod_units(psol)}"
        return _failed(scene, s_vals, s, design, load, psol, msg, strict)
    prob._last = psol
    try:
        return prob.jacobian(s, design=design, load=load, method=method, side=side)
    except ConvergenceError as exc:
        return _failed(scene, s_vals, s, design, load, psol, str(exc), strict)


def _failed(scene, s_vals, s, design, load, sol, message, strict) -> Jacobian[Any]:
    """The Jacobian of a linearisation that could not be taken: NaN derivatives of the
    documented shapes, ``success`` False; reported by the failure rule."""
    nt = scene.robot.n_tendons
    names = _design_names(scene, design)
    lead = () if s is None or np.ndim(s) == 0 else (len(s_vals),)
    jac: Jacobian[Any] = Jacobian(
        s=float(s_vals[0]) if not lead else s_vals,
        actuation=np.full(lead + (6, nt), np.nan),
        tension=np.full((nt, nt), np.nan),
        slack=np.full((nt, nt), np.nan),
        load=np.full(lead + (6, 6), np.nan) if load else None,
        design=np.full(lead + (6, len(names)), np.nan),
        design_tension=np.full((nt, len(names)), np.nan),
        design_names=tuple(n for n, _, _ in names),
        control=tuple("displacement" if c else "tension" for c in scene.displacement_controlled()),
        at_switch=np.zeros(nt, dtype=bool),
        switch_side=np.zeros(nt, dtype=int),
        solution=sol,
        success=False,
        status=-1 if sol is None else min(int(sol.status), -1),
        message=message,
        nit=0 if sol is None else int(sol.nit),
        nfev=0 if sol is None else int(sol.nfev),
    )
    report_failure(jac, strict, message)
    return jac
