"""A scene's structure compiled once: :class:`Problem`.

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

from typing import Any

import numpy as np

from ._deprecation import keyword_only
from ._interrupt import current_token
from ._plausible import Checker
from ._secant import load_steps, secant_compliance
from ._warmstart import _guess_vector
from .compiled import (
    _TD,
    _compile,
    _structure,
    compliance_point,
    fixed_planar,
    is_planar,
    pack_scene,
    same_fields,
    structure_difference,
    value_vector,
)
from .linearization import PARAM_KIND, Jacobian, _design_names, _forward, _rows, _sides
from .model import PointLoad, Scene
from .mounting import base_pose, pairs_out
from .options import Options, _check_options, _replace
from .results import ConvergenceError
from .solution import Solution, _in_rod_units, _report

__all__ = ["Problem", "compliance"]


class Problem:
    """A scene's structure compiled once into a C model and workspace.

    Parameters
    ----------
    scene : Scene
        The scene whose structure is compiled (and the default scene of :meth:`solve`).
    options : Options, optional
        Numerical options (default ``Options()``); fixed for the problem's life.

    Examples
    --------
    >>> robot = tr.Robot(tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True), [tr.Tendon(0.01)])
    >>> prob = tr.Problem(tr.Scene(robot, displacement=[0.0]))  # compiled once
    >>> sol = prob.solve(tr.Scene(robot, displacement=[0.01]))  # new values, solved warm
    >>> sol.success, sol.tension.round(3)
    (True, array([2.081]))
    """

    @keyword_only("tendonrod.Problem", 2, ("options",))
    def __init__(self, scene: Scene, *, options: Options | None = None):
        if not isinstance(scene, Scene):
            raise ValueError(f"scene must be a tendonrod.Scene, got {scene!r}")
        self._options = _check_options(options)
        self._scene = scene
        self._c = _compile(scene, self._options)
        self._current = scene  # the scene whose values are set in C
        self._last: Solution | None = None  # the last successful Solution
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

        form = self._c.formulation
        if self._current.robot.mounted:
            form = dict(form, mounted=True)
        return Formulation.from_dict(form)

    @property
    def last_solution(self):
        """The last successful :class:`~tendonrod.Solution`, or None."""
        return self._last

    def __getstate__(self):
        return {"scene": self._scene, "options": self._options}

    def __setstate__(self, state):
        self.__init__(state["scene"], options=state["options"])

    def __repr__(self):
        warm = "warm" if self._c.has_solution else "no solution yet"
        return f"Problem({self.formulation!r}, {warm})"

    # ------------------------------------------------------------------ values
    def _set(self, scene: Scene) -> None:
        """Make ``scene`` (same structure) the one whose values are set in C."""
        if not isinstance(scene, Scene):
            raise ValueError(f"scene must be a tendonrod.Scene, got {scene!r}")
        key = scene.__dict__.get("_problem_structure")
        if key is None and self._values_only(scene):
            return
        # the same robot and the same scene structure (both cached on the frozen objects):
        # nothing to compare field by field
        same = scene.robot is self._scene.robot and (key or _structure(scene)) == (
            self.__dict__.get("_structure") or self._cache_structure()
        )
        diff = (
            None if same else structure_difference(self._scene, scene, self._options.force_spatial)
        )
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

    def _values_only(self, scene: Scene) -> bool:
        """Set ``scene`` when only values differ from the scene set last (whose structure
        is this one's): the same robot and structure-defining fields, and the same planar
        formulation, which follows the loads' values (the rest of the core's rule is the
        structure's).  False: compare in full."""
        cur = self._current
        if not same_fields(cur, scene):
            return False
        v = value_vector(scene)
        if not self._options.force_spatial:
            fixed = self.__dict__.get("_fixed_planar")
            if fixed is None:
                fixed = self.__dict__["_fixed_planar"] = fixed_planar(cur)
            planar = fixed and self._c.values_planar(v)
            if planar != is_planar(cur):
                return False
            # the core's rule (the conjunction of the two), cached as is_planar does; the
            # scene's structure is then this problem's, cached as _structure does
            object.__setattr__(scene, "_planar", planar)
            key = self.__dict__.get("_structure") or self._cache_structure()
            object.__setattr__(scene, "_problem_structure", key)
        self._c.set_value_vector(v)
        self._current = scene
        return True

    def _cache_structure(self) -> tuple:
        key = self.__dict__["_structure"] = _structure(self._scene)
        return key

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
        sol = self._solve_quiet(scene, guess)
        _report(sol, strict, "tendonrod.Problem.solve")
        self._plausible.check(sol, "tendonrod.Problem.solve", once=True)
        return sol

    def _solve_quiet(self, scene: Scene | None, guess) -> Solution:
        """The Solution of one solve, neither reported nor checked for plausibility: for
        iterations whose intermediate states the caller judges only at the end."""
        scene = self._scene if scene is None else scene
        if scene is not self._current:
            self._set(scene)
        if guess is None:  # warm from the last solution (the loop's path)
            token = current_token()
            if token is None:  # (one keyword fewer to parse)
                raw = self._c.solve(record=False)
            else:
                raw = self._c.solve(cancel=token, record=False)
        else:
            raw = self._run(guess)
        sol = Solution(raw, scene, self._options)
        if sol.success:
            self._last = sol
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

    def jacobian(
        self, s=None, *, design=(), load: bool = True, method: str = "forward", side=None
    ) -> Jacobian[Any]:
        """The linearisation (:class:`~tendonrod.Jacobian`) of the last successful
        solution at arc length(s) ``s`` [m] (default: the tip), with respect to every
        tendon's control value, the probe loads at ``s`` (``load``) and the design
        parameters ``design`` (names as in :mod:`tendonrod.linearization`); see
        :func:`tendonrod.jacobian`.

        When that solution is the workspace's state and every ``s`` is a breakpoint (the
        tip, an anchor, a point load), this reuses the workspace: no solve, k + 1 shooting
        evaluations (k unknowns; 2 k + 1 with ``method="central"``) plus two per design
        parameter or tension-controlled tendon and twelve per interior ``s`` for the
        loads.  Otherwise, and for the loads of a planar problem (whose out-of-plane
        compliance needs the spatial formulation), one more warm solve of the scene with
        zero point loads at ``s``.  ``side`` (ntendon,) of +1 / -1 / 0 asks for the taut or
        the slack side's derivatives of a displacement-controlled tendon at its taut/slack
        switch (0: the side it is on; see :attr:`Jacobian.switch_side`).
        """
        if self._last is None:
            raise RuntimeError("Problem.jacobian needs a successful solve first")
        sol = self._last
        here = self._c.last_success and self._current is sol.scene
        return self._jacobian(sol, s, design, load, method, here, side=side)

    def _jacobian(self, sol, s, design, load, method, here, state=None, side=None) -> Jacobian:
        """The linearisation of ``sol``: the workspace's state (``here``), or the state
        (unknowns, steps) of ``sol`` set without solving, or a probe problem's."""
        forward = _forward(method)
        side = _sides(side, sol.scene.robot.n_tendons)
        s_vals, scalar, names, rows, params = self._jacobian_plan(s, design, load)
        if rows is None or not (here or state is not None):
            prob = _solved_probe(sol, s_vals, self._options, spatial=False)
            jac = prob.jacobian(s, design=design, load=load, method=method, side=side)
            return _with_solution(jac, sol)
        kw = {} if state is None else {"unknowns": state[0], "steps": state[1]}
        raw = self._linearize_raw(sol, params, rows, forward, side, kw)
        nt, nd, nr = sol.scene.robot.n_tendons, len(names), len(rows)
        pose = raw["pose"]  # (np, nrow, 6)
        act = pose[:nt].transpose(1, 2, 0)  # (nrow, 6, nt)
        des = pose[nt : nt + nd].transpose(1, 2, 0)
        C = None
        if load and len(params) > nt + nd:
            C = np.stack([pose[nt + nd + 6 * r : nt + nd + 6 * r + 6, r, :].T for r in range(nr)])
        elif load:
            C = _load_block(sol, s_vals, self._options, forward)
        ten = raw["tension"]
        mount = base_pose(sol.scene.robot)
        if mount is not None:  # base-frame [dx, dtheta] rows (and [F, M] columns) to world
            act, des = pairs_out(mount, act, axis=1), pairs_out(mount, des, axis=1)
            if C is not None:
                C = pairs_out(mount, pairs_out(mount, C, axis=1), axis=2)
        return Jacobian(
            s=float(s_vals[0]) if scalar else s_vals,
            actuation=act[0] if scalar else act,
            tension=ten[:nt].T.copy(),
            slack=raw["slack"][:nt].T.copy(),
            load=None if C is None else (C[0] if scalar else C),
            design=des[0] if scalar else des,
            design_tension=ten[nt : nt + nd].T.copy(),
            design_names=tuple(n for n, _, _ in names),
            control=tuple(
                "displacement" if c else "tension" for c in sol.scene.displacement_controlled()
            ),
            at_switch=np.array(raw["at_switch"]) != 0,
            switch_side=np.array(raw["at_switch"], dtype=int),
            solution=sol,
        )

    def _linearize_raw(self, sol, params, rows, forward, side, kw):
        """The core's linearisation (a dict of raw arrays; ``kw``: the state to set)."""
        if side is not None:
            kw["side"] = side
        try:
            return self._c.linearize(params, rows, forward=forward, cancel=current_token(), **kw)
        except RuntimeError as exc:  # the linearisation itself failed (e.g. its budget)
            raise ConvergenceError(f"tendonrod.jacobian: {exc}", sol) from None

    def _jacobian_plan(self, s, design, load: bool):
        """(arc lengths, scalar?, design names, breakpoint rows or None, raw parameter
        array) of a linearisation, cached per request (a control loop asks the same)."""
        key = (
            s if s is None or isinstance(s, float) else None,
            design if isinstance(design, (str, tuple)) else None,
            load,
        )
        plans = self.__dict__.setdefault("_plans", {})
        if key[0] is s and key[1] is design and key in plans:
            return plans[key]
        scene = self._scene
        L = scene.robot.rod.length
        s_vals, scalar = _arc_lengths(s, L)
        names = _design_names(scene, design)
        rows = _rows(self._c.breakpoints, s_vals, L)
        nt = scene.robot.n_tendons
        params = [(PARAM_KIND["value"], i) for i in range(nt)]
        params += [(kind, index) for _, kind, index in names]
        if load and rows is not None and not self._c.formulation["planar"]:
            params += [(PARAM_KIND["load"], 6 * r + c) for r in rows for c in range(6)]
        plan = (
            s_vals,
            scalar,
            names,
            None if rows is None else np.array(rows, dtype=float),
            np.array(params, dtype=float).reshape(-1, 2),
        )
        if key[0] is s and key[1] is design:
            plans[key] = plan
        return plan

    def _compliance_here(self, s: float):
        """The compliance at breakpoint ``s`` of the workspace's solved state."""
        assert self._last is not None  # (the callers' precondition)
        try:
            C = self._c.compliance(s, cancel=current_token())
        except RuntimeError as exc:  # the linearisation itself failed (e.g. its budget)
            raise ConvergenceError(f"tendonrod.compliance: {exc}", self._last) from None
        C = np.asarray(C, dtype=float).reshape(6, 6)
        pose = base_pose(self._last.scene.robot)
        if pose is None:
            return C
        # base-frame [dx, dtheta] per base-frame [F, M]: T C T^T, T = diag(R0, R0)
        return pairs_out(pose, pairs_out(pose, C, axis=0), axis=1)


def _probe_scene(scene: Scene, s, always: bool = False) -> Scene:
    """``scene`` with a zero point load at each arc length of ``s`` (a float or an array):
    breakpoints for the probes of a linearisation or a compliance (the tip is one already,
    so a point load there only with ``always``)."""
    import dataclasses

    L = scene.robot.rod.length
    extra = [
        PointLoad(s=float(x), force=(0, 0, 0))
        for x in np.atleast_1d(s)
        if always or x < L * (1 - 1e-12)
    ]
    if not extra:
        return scene
    return dataclasses.replace(scene, loads=[*scene.loads, *extra])


def _arc_lengths(s, L: float):
    """(the arc lengths of ``s`` as a float array (N,), whether ``s`` was a scalar):
    None is the tip; each one checked as a probe point (ValueError naming ``s``)."""
    if s is None or np.ndim(s) == 0:
        return np.array([compliance_point(s, L)]), True
    arr = np.asarray(s)
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(f"s must be an arc length or a 1-D array of them, got {s!r}")
    return np.array([compliance_point(x, L) for x in arr]), False


def _solved_probe(sol, s_vals, options: Options, spatial: bool) -> Problem:
    """A Problem of ``sol``'s scene with breakpoints at ``s_vals`` (spatial if asked),
    solved warm from ``sol``; ConvergenceError if that solve fails."""
    opts = _replace(options, force_spatial=True) if spatial else options
    prob = Problem(_probe_scene(sol.scene, s_vals), options=opts)
    psol = Solution(prob._run(sol), prob.scene, prob.options)
    if not psol.success:
        raise ConvergenceError(
            f"tendonrod.jacobian: the scene did not solve again with probes at s: {psol.message}"
            f"{_in_rod_units(psol)}",
            psol,
        )
    prob._last = psol
    return prob


def _load_block(sol, s_vals, options: Options, forward: bool) -> np.ndarray:
    """The compliance (N, 6, 6) at each arc length of ``s_vals`` of a planar solution,
    from its spatial formulation (out-of-plane probes leave the plane)."""
    prob = _solved_probe(sol, s_vals, _replace(options, tip_only=True), spatial=True)
    rows = _rows(prob._c.breakpoints, s_vals, sol.scene.robot.rod.length)
    params = [(PARAM_KIND["load"], 6 * r + c) for r in rows for c in range(6)]
    try:
        raw = prob._c.linearize(
            np.array(params, dtype=float).reshape(-1, 2),
            np.array(rows, dtype=float),
            cancel=current_token(),
        )
    except RuntimeError as exc:
        raise ConvergenceError(f"tendonrod.jacobian: {exc}", sol) from None
    return np.stack([raw["pose"][6 * r : 6 * r + 6, r, :].T for r in range(len(rows))])


def _with_solution(jac: Jacobian, sol) -> Jacobian:
    import dataclasses

    return dataclasses.replace(jac, solution=sol)


def compliance_problem(scene: Scene, s: float, options: Options) -> Problem:
    """The spatial, tip-only problem of ``scene`` with a breakpoint at ``s``."""
    return Problem(
        _probe_scene(scene, s), options=_replace(options, force_spatial=True, tip_only=True)
    )


@keyword_only("tendonrod.compliance", 3, ("options",))
def compliance(
    scene: Scene,
    s: float | None = None,
    guess=None,
    *,
    options: Options | None = None,
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

    If a solve fails, :class:`ConvergenceError` is raised, always: a linearisation about
    an unconverged state means nothing, nor does a secant to one, and a bare matrix has
    no ``success`` to carry the verdict (the one exception to the failure rule of
    :class:`~tendonrod.ConvergenceWarning`; :func:`tendonrod.jacobian` gives the same
    numbers in a result that does carry it).

    Examples
    --------
    >>> robot = tr.Robot(tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True), [tr.Tendon(0.01)])
    >>> tr.compliance(tr.Scene(robot, displacement=[0.01])).shape
    (6, 6)
    """
    options = _check_options(options)
    if not isinstance(scene, Scene):
        raise ValueError(f"scene must be a tendonrod.Scene, got {scene!r}")
    s_val = compliance_point(s, scene.robot.rod.length)
    if step is not None:
        steps = load_steps(step)
        # an output node at s (a recording reads the pose there; the solves record nothing)
        opts = _replace(options, force_spatial=True, tip_only=False, nodes=np.array([s_val]))
        prob = Problem(_probe_scene(scene, s_val, always=True), options=opts)
        return secant_compliance(prob, guess, s_val, steps)
    prob = compliance_problem(scene, s_val, options)
    sol = Solution(prob._run(guess), scene, prob.options)
    if not sol.success:
        raise ConvergenceError(
            f"tendonrod.compliance: the scene did not solve: {sol.message}{_in_rod_units(sol)}",
            sol,
        )
    prob._last = sol
    return prob._compliance_here(s_val)
