"""Public API of the Cosserat-rod/tendon solver: :func:`solve`, :class:`Solution`,
:func:`compliance`.

A :class:`~tendonrod.model.Scene` is packed into the flat float64 arrays of the raw
entry point ``tendonrod._core.solve`` (see ``csrc/README.md``), solved in C with the
GIL released, and wrapped in a :class:`Solution`. Bad input raises ``ValueError``
before any C runs; a solve that does not converge is never silent (``success`` is
False and a :class:`ConvergenceWarning` is issued, or :class:`ConvergenceError` is
raised with ``strict=True``). The options live in :mod:`tendonrod.options`, the
records a solution carries in :mod:`tendonrod.results`; both are importable from here.

Frames and units: SI, radians; base at the origin, base frame = world frame, the
undeformed rod along +z; all vectors in the world frame unless said otherwise.
"""

from __future__ import annotations

import math
import numbers
import warnings

import numpy as np

from . import _core
from .model import Scene
from .options import Options, _check_options, _replace
from .results import ConvergenceError, ConvergenceWarning, Formulation, RodState

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
]


# --------------------------------------------------------------------------- packing
# Column indices of the flat arrays of the raw contract (the core's layouts).
_ROD = {name: i for i, name in enumerate(_core.ROD_COLUMNS)}
_TD = {name: i for i, name in enumerate(_core.TENDON_COLUMNS)}
_LD = {name: i for i, name in enumerate(_core.LOAD_COLUMNS)}


def pack_scene(scene: Scene):
    """Flat float64 arrays ``(rod (6,), tendons (nt, 8), loads (nl, 7), dist (3,))`` of the
    raw glue contract (csrc/README.md) for ``scene``."""
    if not isinstance(scene, Scene):
        raise ValueError(f"scene must be a tendonrod.Scene, got {scene!r}")
    cached = scene.__dict__.get("_packed")
    if cached is not None:
        return cached
    robot = scene.robot
    r = robot.rod
    rod = np.empty(len(_core.ROD_COLUMNS))
    rod[_ROD["length"]], rod[_ROD["EI"]], rod[_ROD["GJ"]] = (
        r.length,
        r.bending_stiffness,
        r.torsional_stiffness,
    )
    rod[_ROD["EA"]], rod[_ROD["GA"]] = r.axial_stiffness, r.shear_stiffness
    rod[_ROD["kirchhoff"]] = 1.0 if r.kirchhoff else 0.0
    nt = robot.n_tendons
    tendons = np.empty((nt, len(_core.TENDON_COLUMNS)))
    for i, t in enumerate(robot.tendons):
        disp = scene.displacement[i]
        row = tendons[i]
        row[_TD["offset"]], row[_TD["angle"]], row[_TD["slope"]] = t.offset, t.angle, t.slope
        row[_TD["EA"]], row[_TD["end"]], row[_TD["pretension"]] = (
            t.EA,
            robot.tendon_end(i),
            t.pretension,
        )
        row[_TD["control"]] = 0.0 if disp is not None else 1.0
        row[_TD["value"]] = disp if disp is not None else scene.tension[i]
    pls = scene.point_loads
    loads = np.empty((len(pls), len(_core.LOAD_COLUMNS)))
    for k, p in enumerate(pls):
        loads[k, _LD["s"]] = min(p.s, r.length)
        loads[k, _LD["Fx"] : _LD["Fz"] + 1] = p.force
        loads[k, _LD["Mx"] : _LD["Mz"] + 1] = p.moment
    dist = scene.distributed_force
    for a in (rod, tendons, loads, dist):
        a.setflags(write=False)
    # a Scene is frozen: pack it once (sweeps and warm starts call solve() in loops)
    object.__setattr__(scene, "_packed", (rod, tendons, loads, dist))
    return rod, tendons, loads, dist


def _nodes_for(scene: Scene, options: Options):
    nodes = options.nodes
    if isinstance(nodes, np.ndarray):
        L = scene.robot.rod.length
        if nodes[-1] > L * (1.0 + 1e-12):
            raise ValueError(f"Options.nodes must lie in [0, L={L!r}], got max {nodes[-1]!r}")
        return np.minimum(nodes, L)
    return nodes


def _structure_key(scene: Scene, options: Options):
    """What fixes the shape of the shooting problem (so a Jacobian can be reused)."""
    key = scene.__dict__.get("_structure")
    if key is None:
        rob = scene.robot
        key = (
            rob.n_tendons,
            scene.displacement_controlled(),
            rob.rod.kirchhoff,
            tuple(math.isinf(t.EA) for t in rob.tendons),
            _is_planar(scene),
        )
        object.__setattr__(scene, "_structure", key)
    return key + (options.force_spatial, options.slack_model)


def is_planar(scene: Scene) -> bool:
    """True when ``scene`` is solved with the planar (x-z) formulation unless
    ``Options.force_spatial``: every tendon at angle 0 or pi (|sin angle| <= 1e-12) and
    every load in the x-z plane.  The core's rule (``_core.is_planar``), so the answer
    is the ``formulation.planar`` a solve reports."""
    key = scene.__dict__.get("_planar")
    if key is None:
        _, tendons, loads, dist = pack_scene(scene)
        key = bool(_core.is_planar(tendons, loads, dist))
        object.__setattr__(scene, "_planar", key)
    return key


_is_planar = is_planar


def _guess_vector(guess, scene: Scene, options: Options):
    """(guess array (6+2nt,) or None, jacobian or None) from a Solution or an array."""
    nt = scene.robot.n_tendons
    if guess is None:
        return None, None
    if isinstance(guess, Solution):
        if guess.tension.shape != (nt,):
            raise ValueError(
                f"guess: a Solution with {guess.tension.shape[0]} tendons cannot "
                f"start a scene with {nt} tendons"
            )
        vec = guess.base_state
        jac = None
        if (
            guess.jacobian is not None
            and guess.scene is not None
            and _structure_key(guess.scene, guess.options) == _structure_key(scene, options)
        ):
            jac = guess.jacobian
        if not np.all(np.isfinite(vec)):
            return None, None
        return vec, jac
    try:
        vec = np.array(guess, dtype=float).ravel()
    except (TypeError, ValueError, OverflowError):
        raise ValueError(
            f"guess must be None, a Solution or an array of shape ({6 + 2 * nt},), got {guess!r}"
        ) from None
    if vec.shape != (6 + 2 * nt,) or not np.all(np.isfinite(vec)):
        raise ValueError(
            f"guess must be a finite array of shape ({6 + 2 * nt},) "
            f"[n(0), m(0), tension, slack], got {guess!r}"
        )
    return vec, None


# --------------------------------------------------------------------------- results
class Solution:
    """Result of :func:`solve`.

    Attributes
    ----------
    success : bool
        The residual fell below ``options.tol`` on an equilibrium the solver vouches for:
        status >= 0, except status 3 (found by a direct solve after load continuation
        stalled), which counts only when a cold solve with another shooting formulation
        reaches the same equilibrium (the message says which).
    status : int
        Core status: 0 ok, > 0 finished with a caveat, < 0 failure.
    message : str
        Human-readable status.
    nit, nfev, njev : int
        Iterations, shooting evaluations (integrations), Jacobian evaluations.
    residual_norm : float
        Norm of the scaled residual at the returned state [-].
    s : ndarray (N,)
        Arc length of the output nodes [m].  The node arrays (``s``, ``position``,
        ``rotation``, ``force``, ``moment``) are computed on first access by the recording
        pass from the converged unknowns (bitwise what an eager solve records): a caller
        who reads only the tip, the tensions and slacks pays for none of it.
    position : ndarray (N, 3)
        Backbone position, world frame [m].
    rotation : ndarray (N, 3, 3)
        Body-to-world rotation matrices.
    force : ndarray (N, 3)
        Internal backbone force n(s) (force of the distal part on the proximal part,
        tendons excluded), world frame [N].
    moment : ndarray (N, 3)
        Internal backbone moment m(s), world frame [N m].
    tension : ndarray (ntendon,)
        Tendon tensions [N] (>= 0).
    slack : ndarray (ntendon,)
        Tendon slack [m] (>= 0; > 0 only where the tension is 0).
    displacement : ndarray (ntendon,)
        Actuator displacement [m] consistent with the solution for every tendon (> 0
        retracts), so "actuate by tension, then lock the actuator" is two calls.
    tip_position : ndarray (3,)
        Tip position (s = L), world frame [m]; ``position[-1]`` when the output nodes end
        at L.
    tip_rotation : ndarray (3, 3)
        Tip body-to-world rotation.
    jacobian_cond : float
        Condition number of the scaled shooting Jacobian at the solution.
    continuation_steps : int
        Continuation stages used (0: solved directly).
    truncation_estimate : float
        Estimate of the integrator's truncation error (scaled, relative) [-].
    unknowns : ndarray
        Raw converged shooting unknowns (as the core defines them).
    jacobian : ndarray or None
        Raw shooting Jacobian (reused by warm starts of the same formulation).
    formulation : Formulation
        What was solved.
    scene : Scene
        The scene solved.
    options : Options
        The options used.
    raw : dict
        Everything ``_core.solve`` returned.
    """

    def __init__(self, raw: dict, scene: Scene, options: Options):
        # Kept light: solve() runs in tight loops. The glue returns float64 arrays of the
        # documented shapes; they are used as they are.
        self.raw = raw
        self.scene = scene
        self.options = options
        self.success = bool(raw["success"])
        self.status = int(raw["status"])
        msg = raw.get("message", "")
        self.message = msg.decode() if isinstance(msg, bytes) else str(msg)
        self.nit = int(raw.get("nit", 0))
        self.nfev = int(raw.get("nfev", 0))
        self.njev = int(raw.get("njev", 0))
        self.residual_norm = float(raw.get("residual_norm", math.nan))
        self.tension = raw["tension"]
        self.slack = raw["slack"]
        self.unknowns = raw.get("unknowns")
        self.jacobian = raw.get("jacobian")
        self.jacobian_cond = float(raw.get("jacobian_cond", math.nan))
        self.continuation_steps = int(raw.get("continuation_steps", 0))
        self.truncation_estimate = float(raw.get("truncation_estimate", math.nan))
        self._formulation = None

    # ------------------------------------------------------------ lazy outputs
    # A solve computes the tip state, the tensions and slacks; the states at the output
    # nodes (and the actuator displacement of tension-controlled tendons, which only the
    # recording pass integrates) are computed on first access, by the recording pass
    # from the solution's unknowns at its verified step count: bitwise what an eager
    # solve records.  A caller who reads only tip quantities pays for none of it.
    def _recorded(self) -> dict:
        raw = self.raw
        if "position" not in raw:
            from .problem import _compile

            steps = max(1, int(raw["formulation"]["steps"]))
            rec = _compile(self.scene, self.options).record_from(self.unknowns, steps)
            for key in ("s", "position", "rotation", "force", "moment", "displacement"):
                raw[key] = rec[key]
        return raw

    @property
    def s(self) -> np.ndarray:
        """Arc length of the output nodes [m], shape (N,) (computed on first access)."""
        return self._recorded()["s"]

    @property
    def position(self) -> np.ndarray:
        """Backbone position at the nodes, world frame [m], shape (N, 3)."""
        return self._recorded()["position"]

    @property
    def rotation(self) -> np.ndarray:
        """Body-to-world rotation at the nodes, shape (N, 3, 3)."""
        return self._recorded()["rotation"]

    @property
    def force(self) -> np.ndarray:
        """Internal backbone force at the nodes, world frame [N], shape (N, 3)."""
        return self._recorded()["force"]

    @property
    def moment(self) -> np.ndarray:
        """Internal backbone moment at the nodes, world frame [N m], shape (N, 3)."""
        return self._recorded()["moment"]

    @property
    def displacement(self) -> np.ndarray:
        """Actuator displacement [m] of every tendon, shape (ntendon,): the prescribed one,
        or for a tension-controlled tendon the one consistent with the solution (computed
        on first access)."""
        d = self.raw["displacement"]
        if "position" not in self.raw and np.isnan(d).any():
            d = self._recorded()["displacement"]
        return d

    @property
    def formulation(self) -> Formulation:
        """What was solved (:class:`Formulation`)."""
        if self._formulation is None:
            self._formulation = Formulation.from_dict(self.raw.get("formulation", {}))
        return self._formulation

    @property
    def tip_position(self) -> np.ndarray:
        """Tip position (s = L), world frame [m], shape (3,): the end state of the shooting
        integration that the residual and the tolerance refer to, whatever the output
        nodes (it is ``position[-1]`` when the nodes end at L)."""
        return self.raw["tip_position"]

    @property
    def tip_rotation(self) -> np.ndarray:
        """Tip body-to-world rotation (s = L), shape (3, 3) (see :attr:`tip_position`)."""
        return self.raw["tip_rotation"]

    @property
    def base_state(self) -> np.ndarray:
        """``[n(0), m(0), tension, slack]`` (6 + 2 ntendon,), world frame, SI: the raw guess
        format, from the core's map of the converged unknowns (so a warm start from it
        starts exactly at this solution)."""
        return self.raw["base_state"]

    def at(self, s) -> RodState:
        """The state at arc length(s) ``s`` [m] (scalar or 1-D array in [0, L]).

        Exact to solver accuracy: the core integrates again from this solution's
        converged unknowns at its step count, with output nodes at ``s`` (no solve, no
        interpolation).
        """
        L = self.scene.robot.rod.length
        scalar = np.ndim(s) == 0
        ss = np.atleast_1d(np.asarray(s, dtype=float)).ravel()
        if (
            ss.size == 0
            or not np.all(np.isfinite(ss))
            or np.any(ss < 0)
            or np.any(ss > L * (1 + 1e-12))
        ):
            raise ValueError(f"s must be arc lengths in [0, L={L!r}], got {s!r}")
        order = np.argsort(ss, kind="stable")
        # the states of this solution at the nodes s: a recording pass from its unknowns
        # at its verified step count (no solve)
        from .problem import _compile

        opts = _replace(self.options, nodes=np.minimum(ss[order], L), tip_only=False)
        sol = Solution(
            _compile(self.scene, opts).record_from(self.unknowns, max(1, self.formulation.steps)),
            self.scene,
            opts,
        )
        inv = np.empty_like(order)
        inv[order] = np.arange(order.size)
        pos, rot = sol.position[inv], sol.rotation[inv]
        frc, mom = sol.force[inv], sol.moment[inv]
        if scalar:
            return RodState(float(ss[0]), pos[0], rot[0], frc[0], mom[0])
        return RodState(ss, pos, rot, frc, mom)

    def __repr__(self):
        head = "converged" if self.success else "NOT converged"
        tip = np.array2string(np.asarray(self.tip_position), precision=6, separator=", ")
        lines = [
            f"Solution({head}: {self.message!r}, status {self.status}, nit {self.nit}, "
            f"nfev {self.nfev}, residual {self.residual_norm:.2e}",
            f"  tip_position {tip} m",
        ]
        if self.tension.size:
            lines.append(
                "  tension "
                + np.array2string(self.tension, precision=6, separator=", ")
                + " N, slack "
                + np.array2string(self.slack, precision=3, separator=", ")
                + " m"
            )
        lines.append(f"  {self.formulation!r}, {self.s.size} nodes)")
        return "\n".join(lines)


# --------------------------------------------------------------------------- solve
def solve(
    scene: Scene, guess=None, options: Options | None = None, strict: bool = False
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
    """
    from .problem import Problem

    prob = Problem(scene, options)
    sol = Solution(prob._run(guess), scene, prob.options)
    _report(sol, strict, "tendonrod.solve", stacklevel=3)
    return sol


def _report(sol: Solution, strict: bool, who: str, stacklevel: int) -> None:
    """A failed solve is never silent: ConvergenceError (strict) or ConvergenceWarning."""
    if sol.success:
        return
    msg = (
        f"{who} did not converge: {sol.message} (status {sol.status}, "
        f"nit {sol.nit}, nfev {sol.nfev}, residual {sol.residual_norm:.3g})"
    )
    if strict:
        raise ConvergenceError(msg, sol)
    warnings.warn(msg, ConvergenceWarning, stacklevel=stacklevel)


def compliance(
    scene: Scene, s: float | None = None, guess=None, options: Options | None = None
) -> np.ndarray:
    """Compliance matrix (6, 6) at arc length ``s`` [m] (default: the tip).

    Column j is the derivative of ``[dx (3) [m], dtheta (3) [rad]]`` (position and small
    rotation of the backbone at ``s``, world frame) with respect to component j of
    ``[force (3) [N], moment (3) [N m]]`` applied at ``s`` in the world frame, linearised
    at the solved state of ``scene`` with the prescribed tendon displacements and tensions
    held fixed. Units per block: m/N, m/(N m), rad/N, rad/(N m).

    One solve of the spatial formulation of ``scene`` (``guess`` and ``options`` as in
    :func:`solve`; with a breakpoint at ``s``), then the implicit function theorem on
    its converged shooting system.  If that solve fails, :class:`ConvergenceError` is
    raised (a linearisation about an unconverged state means nothing).
    """
    from .problem import compliance_problem

    options = _check_options(options)
    if not isinstance(scene, Scene):
        raise ValueError(f"scene must be a tendonrod.Scene, got {scene!r}")
    s_val = compliance_point(s, scene.robot.rod.length)
    prob = compliance_problem(scene, s_val, options)
    sol = Solution(prob._run(guess), scene, prob.options)
    if not sol.success:
        raise ConvergenceError(f"tendonrod.compliance: the scene did not solve: {sol.message}", sol)
    prob._last = sol
    return prob._compliance_here(s_val)


# Arc lengths within this fraction of L of the base merge with it (TR_BP_MERGE): the
# clamp takes a load there, so the compliance is not defined.
_BASE_MERGE = 1e-12


def compliance_point(s, L: float) -> float:
    """The arc length [m] of a compliance probe: ``s`` (None: the tip ``L``) as a float in
    (0, L]; ValueError naming ``s`` otherwise."""
    if s is None:
        return L
    ok = not isinstance(s, (bool, np.bool_)) and (
        isinstance(s, (numbers.Real, np.floating, np.integer))
        or (isinstance(s, np.ndarray) and s.ndim == 0 and s.dtype.kind in "fiu")
    )
    try:
        x = float(s) if ok else math.nan
    except OverflowError:
        x = math.inf
    if not (math.isfinite(x) and _BASE_MERGE * L < x <= L * (1 + 1e-12)):
        raise ValueError(
            f"s must be an arc length in (0, L={L!r}] m (farther than {_BASE_MERGE:g} L from "
            f"the clamped base), got {s!r}"
        )
    return min(x, L)
