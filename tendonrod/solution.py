"""The result of a solve: :class:`Solution` (how a failure is reported: results.py; how a
warm start maps to the core's guess: _warmstart.py).

Frames and units: SI, radians; the undeformed rod along the base frame's +z; all
vectors in the world frame unless said otherwise.  The core solves in the base frame
(``raw`` holds its base-frame arrays); the properties carry them into the world frame
(:mod:`tendonrod.mounting`; the identity for an unmounted robot).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from . import _core
from .compiled import _compile
from .model import Scene
from .mounting import base_pose, pairs_out, points_out, rotations_out, vectors_out
from .options import Options, _replace
from .results import Formulation, RodState, _in_rod_units, _report  # noqa: F401 (re-exported)

__all__ = ["Solution"]

# The fields a Solution of a core Result builds from it on first access.
_FIELDS = frozenset(
    (
        "success",
        "status",
        "message",
        "nit",
        "nfev",
        "njev",
        "residual_norm",
        "tension",
        "slack",
        "unknowns",
        "jacobian",
        "jacobian_cond",
        "continuation_steps",
        "truncation_estimate",
        "truncation_carried",
    )
)


class _Lazy:
    """A field of a Solution built on first access and kept in its __dict__ (which then
    shadows this non-data descriptor): from its core Result (``name`` an attribute of
    it), ``raw`` (the Result's dict) or ``_pose`` (the scene's base pose)."""

    __slots__ = ("name",)

    def __init__(self, name: str):
        self.name = name

    def __get__(self, sol, owner=None):
        if sol is None:
            return self
        d, name = sol.__dict__, self.name
        if name == "_pose":
            scene = d.get("scene")
            value = None if scene is None else base_pose(scene.robot)
        elif name == "raw":
            value = d["_res"].as_dict()
        else:
            value = getattr(d["_res"], name)
        d[name] = value
        return value


class Solution:
    """Result of :func:`solve`.

    A :class:`~tendonrod.Result`: ``success``, ``status``, ``message``, ``nit``, ``nfev``
    mean the same on every result type.

    Attributes
    ----------
    success : bool
        The core's verdict: the residual fell below ``options.tol`` on an equilibrium the
        solver vouches for, status >= 0 except 3 (found by a direct solve after load
        continuation stalled, and not confirmed by a cold solve with another shooting
        formulation; a confirmed one is status 4, the message says which) and 5 (an
        unstable equilibrium, and no stable one was reached: see :attr:`stable` and
        ``Options.accept_unstable``).
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
        Tendon tensions [N] (>= 0), at the actuator.
    tendon_tension : ndarray (N, ntendon)
        Each tendon's tension at the output nodes [N]: ``tension`` along its whole
        length in a frictionless channel; with ``Tendon.friction`` the tension changed
        by friction along s; 0 distal of its anchor (computed on first access).
    slack : ndarray (ntendon,)
        Tendon slack [m] (>= 0; > 0 only where the tension is 0).
    taut : ndarray (ntendon,) of bool
        The tendons that carry tension (``tension > 0``).
    displacement : ndarray (ntendon,)
        Actuator displacement [m] consistent with the solution for every tendon (> 0
        retracts), so "actuate by tension, then lock the actuator" is two calls.
    tip_position : ndarray (3,)
        Tip position (s = L), world frame [m]; ``position[-1]`` when the output nodes end
        at L.
    tip_rotation : ndarray (3, 3)
        Tip body-to-world rotation.
    tip_angle : float
        Planar solves: the signed tip angle [rad], unwrapped along s (NaN if spatial).
    bending_angle : float
        Every solve: the angle [rad] in [0, pi] between the base and tip tangents.
    jacobian_cond : float
        Condition number (1-norm estimate) of the scaled shooting Jacobian at the
        solution: of a finite-difference Jacobian there, or of the last Newton Jacobian
        (Broyden-updated) when that was differenced within 1e-3 (scaled) of the solution
        and its condition is <= 1e6 (where it was measured within a factor 2 of a fresh
        one's), or for warm solves the updated one they kept.
    continuation_steps : int
        Continuation stages used (0: solved directly).
    truncation_estimate : float
        Estimate of the integrator's truncation error (scaled, relative) [-] (NaN for
        the adaptive integrator): measured by step doubling, or -- for a warm solve at
        the automatic step count that ended close to a solution whose step count was
        verified (``truncation_carried``) -- the bound ``2 e_v (1 + delta)^(p+1)``
        carried from that verification, where ``delta`` is how far the scaled unknowns
        and the prescribed tensions moved (relative) and ``p`` the integrator's order.
        At the automatic step count it is <= ``options.tol`` on success; with
        ``Options.steps`` it is what those steps give, and above 1e4 ``tol`` the solve
        warns (``status`` 1).
    truncation_carried : bool
        True when the step count was not verified again (see ``truncation_estimate``);
        a sweep re-verifies once its unknowns drift more than that bound allows.
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
        Everything ``_core.solve`` returned (built on first access from the core's
        result object when the solve returned one).

    Examples
    --------
    >>> rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    >>> robot = tr.Robot(rod, [tr.Tendon(offset=0.01, angle=0.0)])
    >>> scene = tr.Scene(robot, displacement=[0.0157])
    >>> sol = tr.solve(scene)
    >>> sol.success, sol.stable, sol.tip_position.round(4), sol.tension.round(3)
    (True, True, array([0.1273, 0.    , 0.1274]), array([3.267]))
    """

    raw: dict
    scene: Scene
    options: Options
    success: bool
    status: int
    message: str
    nit: int
    nfev: int
    njev: int
    residual_norm: float
    tension: NDArray[np.float64]
    slack: NDArray[np.float64]
    unknowns: NDArray[np.float64] | None
    jacobian: NDArray[np.float64] | None
    jacobian_cond: float
    continuation_steps: int
    truncation_estimate: float
    truncation_carried: bool
    _formulation: Formulation | None
    _pose: Any

    def __init__(self, raw, scene: Scene, options: Options):
        # Kept light: solve() runs in tight loops.  ``raw`` is the core's dict, or its
        # ``_core.Result`` (a lazy solve of a Problem): then every field is built on first
        # access (_Lazy), ``raw`` too.  Written into __dict__ directly: a Solution
        # is read-only after the solve (__setattr__).
        d = self.__dict__
        d["scene"] = scene
        d["options"] = options
        d["_formulation"] = None
        if type(raw) is _core.Result:
            d["_res"] = raw
            # what every solve reads (the failure rule, the plausibility screen)
            d["success"] = raw.success
            d["status"] = raw.status
            d["tension"] = raw.tension
            return
        d["_res"] = None
        d["raw"] = raw
        d["success"] = bool(raw["success"])
        d["status"] = int(raw["status"])
        msg = raw.get("message", "")
        d["message"] = msg.decode() if isinstance(msg, bytes) else str(msg)
        d["nit"] = int(raw.get("nit", 0))
        d["nfev"] = int(raw.get("nfev", 0))
        d["njev"] = int(raw.get("njev", 0))
        d["residual_norm"] = float(raw.get("residual_norm", math.nan))
        d["tension"] = raw["tension"]
        d["slack"] = raw["slack"]
        d["unknowns"] = raw.get("unknowns")
        d["jacobian"] = raw.get("jacobian")
        d["jacobian_cond"] = float(raw.get("jacobian_cond", math.nan))
        d["continuation_steps"] = int(raw.get("continuation_steps", 0))
        d["truncation_estimate"] = float(raw.get("truncation_estimate", math.nan))
        d["truncation_carried"] = bool(raw.get("truncation_carried", False))

    def _get(self, key: str, default=None):
        """The raw result's ``key`` (``default`` when a dict lacks it), without building
        ``raw`` from a core Result."""
        d = self.__dict__
        raw = d.get("raw")
        if raw is not None:
            return raw.get(key, default)
        return getattr(d["_res"], key)

    def __getstate__(self):
        # pickled with its fields and raw dict (a core Result does not travel)
        state = dict(self.__dict__)
        if state.get("_res") is not None:
            state["raw"] = self.raw
            for name in _FIELDS:
                state[name] = getattr(self, name)
        state["_res"] = None
        return state

    def __setstate__(self, state) -> None:
        self.__dict__.update(state)

    def __setattr__(self, name: str, value) -> None:
        # the lazy outputs cache themselves under private names; the results are the solve's
        if not name.startswith("_"):
            raise AttributeError(
                f"Solution.{name} is read-only: a Solution is what the solve returned "
                "(solve again, or copy what you need)"
            )
        object.__setattr__(self, name, value)

    def __delattr__(self, name: str) -> None:
        raise AttributeError(f"Solution.{name} is read-only: a Solution is what the solve returned")

    # ------------------------------------------------------------ lazy outputs
    # A solve computes the tip state, the tensions and slacks; the states at the output
    # nodes (and the actuator displacement of tension-controlled tendons, which only the
    # recording pass integrates) are computed on first access, by the recording pass
    # from the solution's unknowns at its verified step count: bitwise what an eager
    # solve records.  A caller who reads only tip quantities pays for none of it.
    def _recorded(self) -> dict:
        raw = self.raw
        if "position" not in raw:
            steps = max(1, int(raw["formulation"]["steps"]))
            rec = _compile(self.scene, self.options).record_from(self.unknowns, steps)
            for key in (
                "s",
                "position",
                "rotation",
                "force",
                "moment",
                "displacement",
                "tendon_tension",
                "tendon_rest",
            ):
                raw[key] = rec[key]
        return raw

    @property
    def s(self) -> NDArray[np.float64]:
        """Arc length of the output nodes [m], shape (N,) (computed on first access)."""
        return self._recorded()["s"]

    @property
    def position(self) -> NDArray[np.float64]:
        """Backbone position at the nodes, world frame [m], shape (N, 3)."""
        return points_out(self._pose, self._recorded()["position"])

    @property
    def rotation(self) -> NDArray[np.float64]:
        """Body-to-world rotation at the nodes, shape (N, 3, 3)."""
        return rotations_out(self._pose, self._recorded()["rotation"])

    @property
    def force(self) -> NDArray[np.float64]:
        """Internal backbone force at the nodes, world frame [N], shape (N, 3)."""
        return vectors_out(self._pose, self._recorded()["force"])

    @property
    def moment(self) -> NDArray[np.float64]:
        """Internal backbone moment at the nodes, world frame [N m], shape (N, 3)."""
        return vectors_out(self._pose, self._recorded()["moment"])

    @property
    def tendon_tension(self) -> NDArray[np.float64]:
        """Each tendon's tension at the nodes [N], shape (N, ntendon): its tension at the
        actuator less what friction took along s (more, sliding out); 0 distal of its
        anchor."""
        return self._recorded()["tendon_tension"]

    @property
    def taut(self) -> NDArray[np.bool_]:
        """(ntendon,) bool: the tendons that carry tension (``tension > 0``); the others are
        slack (their ``slack`` [m] says by how much) or exactly at the switch."""
        return np.asarray(self.tension) > 0.0

    @property
    def displacement(self) -> NDArray[np.float64]:
        """Actuator displacement [m] of every tendon, shape (ntendon,): the prescribed one,
        or for a tension-controlled tendon the one consistent with the solution (computed
        on first access)."""
        d = self._get("displacement")
        raw = self.__dict__.get("raw")
        if (raw is None or "position" not in raw) and np.isnan(d).any():
            d = self._recorded()["displacement"]
        return d

    # ------------------------------------------------------------ stability
    # Whether the solution is a strict local minimum of the total potential energy among
    # the configurations that hold the base and the prescribed displacements: the
    # constrained Hessian of a discretised energy (bench/results/stability_design.md).
    # Every converged solve judges it in C (its verdict is in raw["stability_verdict"],
    # the margin NaN where a quick test decided); with Options(accept_unstable=True) it
    # is computed on first access; the margin, where the verdict lacks it, too.
    def _stability(self, margin: bool = False) -> dict:
        st = self._get("stability_verdict")
        if st is None or (margin and math.isnan(st["stability"]) and st["stable"] is not None):
            if self.unknowns is None or self.status < 0:
                full = {
                    "stable": None,
                    "stability": math.nan,
                    "index": -1,
                    "reason": "not tested: no solution",
                }
            else:
                steps = max(1, int(self._get("formulation")["steps"]))
                full = _compile(self.scene, self.options).stability(self.unknowns, steps)
            if st is None:
                st = self.raw["stability_verdict"] = full
            else:
                st["stability"] = full["stability"]
        return st

    @property
    def stable(self) -> bool | None:
        """True when the solution is a strict (or, along a symmetry, neutral) local minimum
        of the total potential energy -- rod strain energy, the work of prescribed tensions,
        the stretch energy of displacement-controlled tendons, dead loads -- among the
        configurations that hold the clamped base and the prescribed displacements; False
        when some admissible perturbation lowers it; None when the test does not apply or
        cannot decide (a point moment fixed in the world, which is not conservative for
        spatial perturbations; a margin within the test's discretisation error of zero;
        no solution): :attr:`stability_reason` says which.  A displacement-controlled
        tendon exactly at its taut/slack switch is tested on its slack side."""
        return self._stability()["stable"]

    @property
    def stability(self) -> float:
        """The margin [-]: the smallest eigenvalue of the constrained second variation in
        the norm ``(1/L) int |dtheta|^2 ds``, scaled by EI/L (positive: stable; ~0 at a
        critical point or along a symmetry; NaN where not tested).  For a straight
        cantilever under a compressive dead load P it is (pi^2/4)(1 - P/P_E), P_E the
        Euler load pi^2 EI / (4 L^2)."""
        return self._stability(margin=True)["stability"]

    @property
    def stability_index(self) -> int:
        """The number of independent perturbations that lower the energy (0 when stable;
        -1 where not tested)."""
        return self._stability()["index"]

    @property
    def stability_reason(self) -> str:
        """What the stability test concluded, in words."""
        return self._stability()["reason"]

    @property
    def formulation(self) -> Formulation:
        """What was solved (:class:`Formulation`)."""
        if self._formulation is None:
            form = self._get("formulation", {})
            if self._pose is not None:
                form = dict(form, mounted=True)
            self._formulation = Formulation.from_dict(form)
        return self._formulation

    @property
    def tip_position(self) -> NDArray[np.float64]:
        """Tip position (s = L), world frame [m], shape (3,): the end state of the shooting
        integration that the residual and the tolerance refer to, whatever the output
        nodes (it is ``position[-1]`` when the nodes end at L)."""
        return points_out(self._pose, self._get("tip_position"))

    @property
    def tip_angle(self) -> float:
        """Tip angle [rad] of a planar solve: the signed angle of the tip tangent from the
        base axis (base +z) toward base +x, unwrapped along s (a curl past 180 degrees reads past
        pi); NaN for the spatial formulation (see :attr:`tip_rotation`)."""
        return float(self._get("tip_angle", math.nan))

    @property
    def bending_angle(self) -> float:
        """Bending angle [rad] in [0, pi]: the angle between the tangent at the base (the
        base frame's +z) and the tip tangent, for every formulation (planar or spatial,
        mounted or not).  Not the total turning along s: a planar curl by ``tip_angle`` =
        4 rad has a bending angle of ``2 pi - 4`` rad.  NaN where the tip is not finite."""
        R = self._get("tip_rotation")  # base frame: the base tangent is e3
        return float(math.atan2(math.hypot(R[0, 2], R[1, 2]), R[2, 2]))

    @property
    def tip_rotation(self) -> NDArray[np.float64]:
        """Tip body-to-world rotation (s = L), shape (3, 3) (see :attr:`tip_position`)."""
        return rotations_out(self._pose, self._get("tip_rotation"))

    @property
    def base_state(self) -> NDArray[np.float64]:
        """``[n(0), m(0), tension, slack]`` (6 + 2 ntendon,), world frame, SI: the raw guess
        format, from the core's map of the converged unknowns (so a warm start from it
        starts exactly at this solution)."""
        b = self._get("base_state")
        if self._pose is None:
            return b
        return np.concatenate([pairs_out(self._pose, b[:6]), b[6:]])

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
        opts = _replace(self.options, nodes=np.minimum(ss[order], L), tip_only=False)
        sol = Solution(
            _compile(self.scene, opts).record_from(self.unknowns, max(1, self.formulation.steps)),
            self.scene,
            opts,
        )
        inv = np.empty_like(order)
        inv[order] = np.arange(order.size)
        pos, rot = sol.position[inv], sol.rotation[inv]
        frc, mom, ten = sol.force[inv], sol.moment[inv], sol.tendon_tension[inv]
        if scalar:
            return RodState(float(ss[0]), pos[0], rot[0], frc[0], mom[0], ten[0])
        return RodState(ss, pos, rot, frc, mom, ten)

    @property
    def plausibility(self) -> tuple:
        """The :class:`~tendonrod.plausibility.Finding` s of this solution: its scene's input
        findings (angle, slenderness, offset) and, for a successful solve, those of the
        solution (tension vs EI/r^2, backbone strain, curl, self-intersection); ``()``
        when all is plausible.  Computed on first access (``tr.solve`` and
        ``Problem.solve`` compute it to warn); see :mod:`tendonrod.plausibility`."""
        found = self.__dict__.get("_plausibility")
        if found is None:
            from ._plausible import solution_findings

            found = solution_findings(self)
        return found

    def save(self, path) -> None:
        """Write this solution to ``path`` (``.npz``); :func:`tendonrod.load` reads it
        back bit for bit (see :mod:`tendonrod._io`)."""
        from ._io import save_solution

        save_solution(self, path)

    def export(self, path, **kwargs) -> None:
        """Write this solution for other tools, the format by ``path``'s suffix: ``.csv``
        (node arrays with a units header), ``.obj`` / ``.stl`` (the backbone as a closed
        tube at its diameter; ``tendons=True`` adds each tendon as a thin tube of
        ``tendon_diameter`` [m]; ``sides`` per ring, default 32) or ``.json``.  Another
        suffix raises ``ValueError`` naming it (see :mod:`tendonrod._export`)."""
        from ._export import export

        export(self, path, **kwargs)

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


for _name in (*_FIELDS, "raw", "_pose"):
    setattr(Solution, _name, _Lazy(_name))
del _name
