"""Public API of the Cosserat-rod/tendon solver: :func:`solve`, :class:`Solution`,
:func:`compliance`.

A :class:`~tendonrod.model.Scene` is packed into the flat float64 arrays of the raw
entry point ``tendonrod._core.solve`` (see ``csrc/README.md``), solved in C with the
GIL released, and wrapped in a :class:`Solution`. Bad input raises ``ValueError``
before any C runs; a solve that does not converge is never silent (``success`` is
False and a :class:`ConvergenceWarning` is issued, or :class:`ConvergenceError` is
raised with ``strict=True``). The pieces live in their own modules and are importable
from here: the packing of a scene in :mod:`tendonrod.compiled`, :class:`Solution` in
:mod:`tendonrod.solution`, the compiled :class:`~tendonrod.Problem` and
:func:`compliance` in :mod:`tendonrod.problem`, the options in :mod:`tendonrod.options`,
the records a solution carries in :mod:`tendonrod.results`.

Frames and units: SI, radians; the base at ``Robot.base_position`` with the base frame's
axes the columns of ``Robot.base_rotation`` (default: the origin and the world frame), the
undeformed rod along the base frame's +z; all vectors in the world frame unless said
otherwise (the core solves in the base frame, :mod:`tendonrod.mounting`).
"""

from __future__ import annotations

from ._deprecation import keyword_only
from .compiled import is_planar, pack_scene
from .model import Scene
from .options import Options
from .problem import Problem, compliance
from .results import ConvergenceError, ConvergenceWarning, Formulation, RodState
from .solution import Solution, _report

__all__ = [
    "Options",
    "Formulation",
    "Solution",
    "RodState",
    "solve",
    "compliance",
    "ConvergenceWarning",
    "ConvergenceError",
    "pack_scene",
    "is_planar",
]


@keyword_only("tendonrod.solve", 2, ("options", "strict"))
def solve(
    scene: Scene, guess=None, *, options: Options | None = None, strict: bool = False
) -> Solution:
    """Solve ``scene``: the static equilibrium of the robot under its actuation and loads.

    A one-shot :class:`~tendonrod.Problem`: the scene is compiled, solved and the compiled
    problem dropped.  To solve many scenes of one structure, keep a ``tr.Problem``.

    Parameters
    ----------
    scene : Scene
        Robot, actuation (displacements/tensions) and loads.
    guess : None, "cold", Solution or array (6 + 2 ntendon,), optional
        Warm start: a previous :class:`Solution` (its base state, and its Jacobian when
        the problem has the same formulation), or a raw ``[n(0), m(0), tension, slack]``
        vector (world frame, SI).  None or ``"cold"``: the core's cold guess.
    options : Options, optional
        Numerical options (default ``Options()``).
    strict : bool
        Raise :class:`ConvergenceError` instead of warning when the solve fails.

    Returns
    -------
    Solution

    A solution that looks like a slip (backbone strain over 2 %, a curl beyond 360 deg,
    a backbone through itself, a tension near EI/r^2) gives a
    :class:`~tendonrod.PlausibilityWarning`; ``sol.plausibility`` lists the findings
    (:mod:`tendonrod.plausibility`).

    Examples
    --------
    >>> rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    >>> robot = tr.Robot(rod, [tr.Tendon(offset=0.01, angle=0.0)])
    >>> scene = tr.Scene(robot, displacement=[0.0157],
    ...                  loads=[tr.PointLoad(s=0.2, force=(0.0, 0.0, -0.2))])
    >>> sol = tr.solve(scene)
    >>> sol.success, sol.nit, sol.tension.round(3)
    (True, 7, array([1.525]))
    >>> tr.solve(scene, guess=sol).nit  # warm: from a solution
    0
    """
    prob = Problem(scene, options=options)
    sol = Solution(prob._run(guess), scene, prob.options)
    _report(sol, strict, "tendonrod.solve")
    prob._plausible.check(sol, "tendonrod.solve", once=False)
    return sol
