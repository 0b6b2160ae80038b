"""The plausibility rules (:mod:`tendonrod.plausibility`) applied to solutions: one
solution (``tr.solve``, ``Problem.solve``, :attr:`Solution.plausibility`) or the points
of a batch (``tr.solve_batch``, the sweep's batch path), by one procedure:

1. the scene's input findings (cached on its robot);
2. for a successful solve, the bounds of :func:`~tendonrod._plausible_rules.screen` from its
   loads and tensions (:func:`~tendonrod._plausible_rules.screen_clear`);
3. where they are not clear, the states at the default output nodes, recorded once
   from the solution's unknowns at its step count (no solve), for the tension, strain,
   curl and self-intersection rules.

The recording uses its own compiled problem with the default node count, whatever the
caller's ``Options.nodes``, so that every entry point finds the same for the same
solution.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from . import _plausible_rules as PR
from . import plausibility as P
from .compiled import _compile, pack_scene, value_vector
from .options import _DEFAULTS, _replace

__all__ = ["Checker", "Recorder", "solution_findings", "batch_findings"]

# The node count of the recording behind the state rules: the default output nodes
# (uniform spacing L/100 plus every breakpoint), fine enough that a polyline of them
# stays within (L/100)^2 kappa / 8 of the curve.
_NODES = int(_DEFAULTS["nodes"])


def _robot_constants(robot) -> dict:
    """What the rules need of a robot, computed once (cached on the frozen robot)."""
    c = robot.__dict__.get("_plausibility_constants")
    if c is None:
        c = dict(bounds=PR.robot_constants(robot), thickness=P.section_diameter(robot.rod))
        object.__setattr__(robot, "_plausibility_constants", c)
    return c


def _scene_screen(scene) -> tuple:
    """:func:`~tendonrod._plausible_rules.screen` of the scene's loads and robot (cached on
    the frozen scene)."""
    v = scene.__dict__.get("_plausibility_screen")
    if v is None:
        # the point loads' [F, M] and the distributed force from the value vector (base
        # frame for a mounted robot: the norms are the same), arc lengths clipped to [0, L]
        L = scene.robot.rod.length
        pls = scene.point_loads
        v = value_vector(scene).tolist()
        k = scene.robot.n_tendons
        levers = PR.load_levers(
            [min(p.s, L) for p in pls],
            [math.hypot(*v[k + 6 * j : k + 6 * j + 3]) for j in range(len(pls))],
            [math.hypot(*v[k + 6 * j + 3 : k + 6 * j + 6]) for j in range(len(pls))],
            math.hypot(*v[-3:]),
            L,
        )
        v = PR.screen(levers, _robot_constants(scene.robot)["bounds"])
        object.__setattr__(scene, "_plausibility_screen", v)
    return v


class Recorder:
    """The states at the default nodes of solutions of one design (one robot, one
    formulation), compiled on first use and reused with new values."""

    def __init__(self, scene, options, force_spatial: bool | None = None):
        kw = dict(nodes=_NODES, tip_only=False)
        if force_spatial is not None:
            kw["force_spatial"] = force_spatial
        self.robot = scene.robot
        self.options = options  # the solutions' options (the recording's differ in nodes)
        self._scene = scene
        self._options = _replace(options, **kw)
        self._core: Any = None
        self._values: Any = None

    def record(self, unknowns, steps: int, values=None) -> dict:
        """The recorded states (``_core.Problem.record_from``'s dict) of the solution with
        these ``unknowns`` at ``steps``, with the per-call ``values`` (a value vector;
        None: the scene's)."""
        if self._core is None:
            self._core = _compile(self._scene, self._options)
            self._values = value_vector(self._scene)
        if values is not None and values is not self._values:
            self._core.set_value_vector(values)
            self._values = values
        return self._core.record_from(np.asarray(unknowns, dtype=float), max(1, int(steps)))


def _state_findings(robot, rec: dict, tensions) -> list:
    """The tension, strain, curl and self-intersection rules on recorded states."""
    c = _robot_constants(robot)
    s, R = rec["s"], rec["rotation"]
    n_body = np.einsum("kji,kj->ki", R, rec["force"])
    m_body = np.einsum("kji,kj->ki", R, rec["moment"])
    rod = robot.rod
    found = PR.tension_findings(robot, s, m_body, tensions)
    found += PR.strain_findings(rod, s, n_body)
    T = PR.turning(s, m_body, rod.bending_stiffness)
    for f in (
        PR.curl_finding(T),
        PR.self_intersection_finding(s, rec["position"], T, c["thickness"], rod.length),
    ):
        if f is not None:
            found.append(f)
    return found


def solution_findings(sol, recorders=None) -> tuple:
    """Every finding of ``sol`` (input findings of its scene first), stored on it as its
    :attr:`~tendonrod.Solution.plausibility`; a recording, when one is needed, from
    ``recorders.recorder(sol)`` (a :class:`Checker` keeps one per problem) or a new
    :class:`Recorder`."""
    found = sol.__dict__.get("_plausibility")
    if found is not None:
        return found
    scene = sol.scene
    found = P.input_findings(scene)
    if sol.success:
        tau = sol.tension.tolist()
        if not PR.screen_clear(_scene_screen(scene), tau):
            rec = recorders.recorder(sol) if recorders is not None else Recorder(scene, sol.options)
            raw = rec.record(sol.unknowns, sol.formulation.steps, value_vector(scene))
            found = found + tuple(_state_findings(scene.robot, raw, tau))
    sol.__dict__["_plausibility"] = found
    return found


class Checker:
    """A solver's warnings: the findings of each solution it returns, warned (with
    ``once``) only the first time a rule and subject fire; keeps a recorder."""

    def __init__(self):
        self._recorder = None
        self._warned: set = set()

    def recorder(self, sol) -> Recorder:
        """A recorder for ``sol``: the kept one when it fits its robot and options."""
        rec = self._recorder
        if rec is None or rec.robot is not sol.scene.robot or rec.options is not sol.options:
            rec = self._recorder = Recorder(sol.scene, sol.options)
        return rec

    def check(self, sol, who: str, once: bool) -> None:
        # the input findings warn when built; a failed solve has no others, nor does a
        # successful one whose screen is clear (its findings are then computed on access)
        if not sol.success:
            return
        scene = sol.scene
        screen = scene.__dict__.get("_plausibility_screen")
        if PR.screen_clear(
            _scene_screen(scene) if screen is None else screen, sol.tension.tolist()
        ):
            return
        found = solution_findings(sol, self)
        n_in = len(P.input_findings(sol.scene))  # input findings warn when built
        if len(found) == n_in:
            return
        new = list(found[n_in:])
        if once:
            new = [f for f in new if (f.rule, f.subject) not in self._warned]
            self._warned.update((f.rule, f.subject) for f in new)
        P.warn(new, who)


def batch_findings(scene, options, raw: dict, values, point_loads, distributed) -> np.ndarray:
    """Each point's findings (an object array (n,) of tuples) of a batch of ``scene``
    solved with ``options``: ``raw`` the batch's result dict, ``values`` (n, nt),
    ``point_loads`` (n, nl, 6), ``distributed`` (n, 3) the per-point values given (None:
    the scene's)."""
    robot = scene.robot
    c = _robot_constants(robot)
    L = robot.rod.length
    ok = np.asarray(raw["success"], dtype=bool)
    n = ok.shape[0]
    T = raw["tension"]
    _, tendons, loads, dist = pack_scene(scene)
    if point_loads is None:
        point_loads = loads[None, :, 1:7]
    d = dist[None, :] if distributed is None else distributed
    levers = PR.load_levers(
        loads[:, 0].tolist(),  # arc lengths, clipped to [0, L] by pack_scene
        [np.linalg.norm(point_loads[:, k, 0:3], axis=1) for k in range(loads.shape[0])],
        [np.linalg.norm(point_loads[:, k, 3:6], axis=1) for k in range(loads.shape[0])],
        np.linalg.norm(d, axis=1),
        L,
    )
    scr = PR.screen(levers, c["bounds"])
    clear = np.broadcast_to(PR.screen_clear(scr, [T[:, i] for i in range(T.shape[1])]), (n,))
    inputs = P.input_findings(scene)
    out = np.empty(n, dtype=object)
    out.fill(inputs)
    recorder = None
    base = value_vector(scene)
    nt, nl = tendons.shape[0], loads.shape[0]
    for k in np.flatnonzero(ok & ~clear).tolist():
        if recorder is None:
            # the batch's formulation (spatial when any point leaves the plane)
            recorder = Recorder(scene, options, not raw["formulation"]["planar"])
        v = base.copy()
        if values is not None:
            v[:nt] = values[k]
        if point_loads.shape[0] == n:
            v[nt : nt + 6 * nl] = point_loads[k].ravel()
        if distributed is not None:
            v[nt + 6 * nl :] = distributed[k]
        rec = recorder.record(raw["unknowns"][k], raw["steps"][k], v)
        out[k] = inputs + tuple(_state_findings(robot, rec, T[k].tolist()))
    return out
