"""A scene's structure compiled once: :class:`Problem`.

>>> prob = tr.Problem(scene)                       # doctest: +SKIP
>>> sol = prob.solve()                             # cold the first time
>>> sol = prob.solve(scene_with_other_loads)       # warm, no recompilation

The *structure* of a scene is what its compiled model depends on: the rod, the tendons'
routing, axial rigidity and anchors, which tendons are displacement- and which
tension-controlled, the positions of the point loads, the formulation (planar or
spatial) and the options.  Everything else is a per-call value: tendon displacements and
tensions, pretensions, point-load forces and moments, the distributed force.  A scene of
the same structure re-solves without recompiling, warm from the problem's last
successful solution, whose unknowns, Jacobian and verified step count stay in C between
calls; a scene of another structure raises ``ValueError`` naming the field that differs.

One thread at a time: a Problem holds one workspace (a call from a second thread while
one runs raises ``RuntimeError``); sweeps make one per worker.  Pickling keeps the scene
and the options and drops the warm state.  Ctrl-C during a solve raises
``KeyboardInterrupt`` within a few milliseconds; the problem stays usable.
"""

from __future__ import annotations

import numpy as np

from ._interrupt import current_token
from ._plausible import Checker
from ._secant import load_steps, secant_compliance
from .compiled import (
    _TD,
    _compile,
    compliance_point,
    pack_scene,
    structure_difference,
    value_vector,
)
from .model import PointLoad, Scene
from .options import Options, _check_options, _replace
from .results import ConvergenceError
from .solution import Solution, _guess_vector, _report

__all__ = ["Problem", "compliance"]


class Problem:
    """A scene's structure compiled once into a C model and workspace.

    Parameters
    ----------
    scene : Scene
        The scene whose structure is compiled (and the default scene of :meth:`solve`).
    options : Options, optional
        Numerical options (default ``Options()``); fixed for the problem's life.
    """

    def __init__(self, scene: Scene, options: Options | None = None):
        if not isinstance(scene, Scene):
            raise ValueError(f"scene must be a tendonrod.Scene, got {scene!r}")
        self._options = _check_options(options)
        self._scene = scene
        self._c = _compile(scene, self._options)
        self._current = scene  # the scene whose values are set in C
        self._last = None  # the last successful Solution
        self._plausible = Checker()  # plausibility warnings: once per rule and subject

    # ------------------------------------------------------------------ state
    @property
    def scene(self) -> Scene:
        """The scene the problem was compiled from."""
        return self._scene

    @property
    def options(self) -> Options:
        """The problem's options."""
        return self._options

    @property
    def formulation(self):
        """What the scene compiled to (:class:`~tendonrod.Formulation`)."""
        from .results import Formulation

        return Formulation.from_dict(self._c.formulation)

    @property
    def last_solution(self):
        """The last successful :class:`~tendonrod.Solution`, or None."""
        return self._last

    def __getstate__(self):
        return {"scene": self._scene, "options": self._options}

    def __setstate__(self, state):
        self.__init__(state["scene"], state["options"])

    def __repr__(self):
        warm = "warm" if self._c.has_solution else "no solution yet"
        return f"Problem({self.formulation!r}, {warm})"

    # ------------------------------------------------------------------ values
    def _set(self, scene: Scene) -> None:
        """Make ``scene`` (same structure) the one whose values are set in C."""
        if not isinstance(scene, Scene):
            raise ValueError(f"scene must be a tendonrod.Scene, got {scene!r}")
        diff = structure_difference(self._scene, scene, self._options.force_spatial)
        if diff is not None:
            raise ValueError(
                f"scene has another structure than this Problem: {diff}; a Problem keeps "
                f"its structure (make a new tr.Problem for this scene)"
            )
        if scene.robot is not self._current.robot:
            # pretensions are values too (the rest lengths follow); sent only when changed
            old = pack_scene(self._current)[1][:, _TD["pretension"]]
            new = pack_scene(scene)[1][:, _TD["pretension"]]
            if new.tolist() != old.tolist():
                self._c.set_values(pretension=new)
        self._c.set_value_vector(value_vector(scene))
        self._current = scene

    # ------------------------------------------------------------------ solve
    def _run(self, guess):
        """The raw result dict of one solve from ``guess`` (see :meth:`solve`)."""
        cancel = current_token()
        if guess is None:
            return self._c.solve(warm=True, cancel=cancel, record=False)
        if isinstance(guess, str):
            if guess != "cold":
                raise ValueError(
                    f"guess must be None, 'cold', a Solution or an array, got {guess!r}"
                )
            return self._c.solve(warm=False, cancel=cancel, record=False)
        vec, jac, verified, carry = _guess_vector(guess, self._current, self._options)
        if vec is None:
            return self._c.solve(warm=False, cancel=cancel, record=False)
        return self._c.solve(
            guess=vec, jacobian=jac, verified=verified, carry=carry, cancel=cancel, record=False
        )

    def solve(self, scene: Scene | None = None, *, guess=None, strict: bool = False):
        """Solve ``scene`` (default: the problem's scene), a scene of the same structure.

        Parameters
        ----------
        scene : Scene, optional
            Same structure as the problem's scene; its values (actuation, loads,
            pretensions) are set without recompiling.  Another structure raises
            ``ValueError`` naming the field that differs.
        guess : None, "cold", Solution or array (6 + 2 ntendon,)
            None (default): warm from the problem's last successful solution (cold if
            there is none).  ``"cold"``: from the core's cold guess.  A Solution (of any
            problem) or a raw ``[n(0), m(0), tension, slack]`` vector: from it.
        strict : bool
            Raise :class:`~tendonrod.ConvergenceError` instead of warning on failure.

        Returns
        -------
        Solution

        A solution that looks like a slip (:mod:`tendonrod.plausibility`) gives a
        :class:`~tendonrod.PlausibilityWarning` the first time its rule fires for this
        problem; every solution lists its own findings in ``plausibility``.
        """
        scene = self._scene if scene is None else scene
        if scene is not self._current:
            self._set(scene)
        raw = self._run(guess)
        sol = Solution(raw, scene, self._options)
        if sol.success:
            self._last = sol
        _report(sol, strict, "tendonrod.Problem.solve", stacklevel=3)
        self._plausible.check(sol, "tendonrod.Problem.solve", once=True)
        return sol

    def compliance(self, s: float | None = None, *, step=None):
        """Compliance (6, 6) at arc length ``s`` [m] (default: the tip) of the last
        successful solution (see :func:`tendonrod.compliance`).  The tangent
        (``step=None``): directly from the workspace when that solution is the
        workspace's current state, the problem is spatial and ``s`` is a breakpoint (the
        tip, an anchor or a point load); else by a warm solve of the probe problem from
        that solution.  The secant over the load step ``step``: its perturbed scenes
        solved warm from that solution."""
        if self._last is None:
            raise RuntimeError("Problem.compliance needs a successful solve first")
        L = self._last.scene.robot.rod.length
        s_val = compliance_point(s, L)
        if step is not None:
            return compliance(
                self._last.scene, s_val, guess=self._last, options=self._options, step=step
            )
        bp = self._c.breakpoints
        here = (
            self._c.last_success
            and self._current is self._last.scene
            and not self._c.formulation["planar"]
            and np.any(np.abs(bp - s_val) <= 1e-12 * L)
        )
        if here:
            return self._compliance_here(s_val)
        return compliance(self._last.scene, s_val, guess=self._last, options=self._options)

    def _compliance_here(self, s: float):
        """The compliance at breakpoint ``s`` of the workspace's solved state."""
        try:
            C = self._c.compliance(s, cancel=current_token())
        except RuntimeError as exc:  # the linearisation itself failed (e.g. its budget)
            raise ConvergenceError(f"tendonrod.compliance: {exc}", self._last) from None
        return np.asarray(C, dtype=float).reshape(6, 6)


def _probe_scene(scene: Scene, s: float, always: bool = False) -> Scene:
    """``scene`` with a zero point load at ``s`` (a breakpoint for the compliance probe;
    the tip is one already, so there only with ``always``)."""
    import dataclasses

    L = scene.robot.rod.length
    if s >= L * (1 - 1e-12) and not always:
        return scene
    return dataclasses.replace(scene, loads=list(scene.loads) + [PointLoad(s=s, force=(0, 0, 0))])


def compliance_problem(scene: Scene, s: float, options: Options) -> Problem:
    """The spatial, tip-only problem of ``scene`` with a breakpoint at ``s``."""
    return Problem(_probe_scene(scene, s), _replace(options, force_spatial=True, tip_only=True))


def compliance(
    scene: Scene,
    s: float | None = None,
    guess=None,
    options: Options | None = None,
    *,
    step=None,
) -> np.ndarray:
    """Compliance matrix (6, 6) at arc length ``s`` [m] (default: the tip): the tangent
    (``step=None``) or the secant over a finite load step ``step``.

    Column j is the response of ``[dx (3) [m], dtheta (3) [rad]]`` (position and rotation
    of the backbone at ``s``, world frame) to component j of ``[force (3) [N], moment (3)
    [N m]]`` applied at ``s`` in the world frame, with the prescribed tendon displacements
    and tensions held fixed.  Units per block: m/N, m/(N m), rad/N, rad/(N m).

    - ``step=None``: the tangent, the derivative at the solved state of ``scene``: one
      solve of its spatial formulation (``guess`` and ``options`` as in :func:`solve`;
      with a breakpoint at ``s``), then the implicit function theorem on the converged
      shooting system.
    - ``step=h`` (a real number for all six columns, or six: ``[Fx, Fy, Fz]`` [N] and
      ``[Mx, My, Mz]`` [N m]; signed, nonzero): the secant ``(x(F0 + h_j e_j) - x(F0)) /
      h_j``, F0 the scene's loads, x(F) the pose at ``s`` under F, ``dtheta`` the rotation
      vector of ``R(F0 + h_j e_j) R(F0)^T``.  The scene is solved (as above), then each
      perturbed scene warm from that solution through the same compiled problem; seven
      solves in all.  Its difference from the tangent is ``h_j x''(F0) / 2 + O(h^2)``.

    When the tangent misleads: it is exact only for loads small enough that the state
    stays on one smooth branch.  A tendon within a hair of its taut/slack switch (slack by
    micrometres, or taut with almost no tension) responds one-sidedly: the tangent sees
    only the side the solution sits on.  A four-tendon robot whose side tendons are slack
    by 31 um under backbone compression gets the bare rod's out-of-plane tangent, 2.6x
    softer than the secant at 0.1 N (the tendon takes up its slack and stiffens the
    robot); the Fig. 17 robot just below its critical load gets the taut tangent, far
    stiffer than it is over any load step that crosses the switch.  Near a limit point
    or buckling the tangent is large or negative.  For a design figure at a given load,
    ask for the secant at that load step, with the sign the load has.

    If a solve fails, :class:`ConvergenceError` is raised (a linearisation about an
    unconverged state means nothing, nor does a secant to one).
    """
    options = _check_options(options)
    if not isinstance(scene, Scene):
        raise ValueError(f"scene must be a tendonrod.Scene, got {scene!r}")
    s_val = compliance_point(s, scene.robot.rod.length)
    if step is not None:
        steps = load_steps(step)
        # an output node at s (a recording reads the pose there; the solves record nothing)
        opts = _replace(options, force_spatial=True, tip_only=False, nodes=np.array([s_val]))
        prob = Problem(_probe_scene(scene, s_val, always=True), opts)
        return secant_compliance(prob, guess, s_val, steps)
    prob = compliance_problem(scene, s_val, options)
    sol = Solution(prob._run(guess), scene, prob.options)
    if not sol.success:
        raise ConvergenceError(f"tendonrod.compliance: the scene did not solve: {sol.message}", sol)
    prob._last = sol
    return prob._compliance_here(s_val)
