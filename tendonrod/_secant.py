"""The secant (finite-load) compliance: column j is ``(x(F0 + h_j e_j) - x(F0)) / h_j``,
each perturbed scene solved warm from the base solution through one compiled
:class:`~tendonrod.Problem` (see :func:`tendonrod.compliance`, ``step=``).

``x = [dx (3) [m], dtheta (3) [rad]]`` is the pose of the backbone at arc length s in
the world frame: the position change, and the rotation vector of ``R(F0 + h e_j)
R(F0)^T`` (the rotation that carries the base pose's frame to the perturbed one), as
the tangent compliance defines its small rotation.
"""

from __future__ import annotations

import dataclasses
import math
import numbers

import numpy as np

from .model import PointLoad
from .mounting import base_pose, points_out, rotations_out
from .results import ConvergenceError
from .solution import Solution, _in_rod_units

__all__ = ["load_steps", "secant_compliance", "rotation_vector"]

_COMPONENTS = ("Fx [N]", "Fy [N]", "Fz [N]", "Mx [N m]", "My [N m]", "Mz [N m]")


def load_steps(step) -> np.ndarray:
    """The six signed load steps ``[Fx, Fy, Fz [N], Mx, My, Mz [N m]]`` of ``step`` (a real
    number for all six, or a sequence of six), each finite and nonzero; ValueError
    naming ``step`` otherwise."""
    scalar = isinstance(step, (numbers.Real, np.floating, np.integer)) and not isinstance(
        step, (bool, np.bool_)
    )
    try:
        h = np.full(6, float(step)) if scalar else np.array(step, dtype=float).ravel()
    except (TypeError, ValueError, OverflowError):
        h = None
    if scalar or (h is not None and isinstance(step, (list, tuple, np.ndarray))):
        ok = h is not None and h.shape == (6,) and np.all(np.isfinite(h)) and np.all(h != 0.0)
    else:
        ok = False
    if not ok:
        raise ValueError(
            "step must be a finite, nonzero load step (a real number for all six columns, "
            f"or six: {', '.join(_COMPONENTS)}), got {step!r}"
        )
    assert h is not None  # (ok says so)
    return h


def rotation_vector(R) -> np.ndarray:
    """The rotation vector (axis times angle in [0, pi], rad) of the rotation matrix ``R``
    (3, 3): ``atan2`` of the skew and symmetric parts, accurate for small angles; near pi
    the axis comes from ``(R + I) / 2``."""
    R = np.asarray(R, dtype=float)
    w = 0.5 * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    sin = float(np.linalg.norm(w))
    cos = 0.5 * (float(np.trace(R)) - 1.0)
    theta = math.atan2(sin, cos)
    if cos > -0.9:  # theta < 154 deg: theta / sin theta is well conditioned
        return w * (theta / sin) if sin > 0.0 else w
    # R = cos I + sin [a]x + (1 - cos) a a^T: its symmetric part gives a a^T exactly
    B = (0.5 * (R + R.T) - cos * np.eye(3)) / (1.0 - cos)
    k = int(np.argmax(np.diag(B)))
    a = B[:, k] / math.sqrt(B[k, k])
    a /= np.linalg.norm(a)
    if a @ w < 0.0:
        a = -a
    return a * theta


def _pose(prob, sol, s: float, L: float):
    """(position (3,) [m], rotation (3, 3)) of solution ``sol`` of ``prob`` at ``s``."""
    if s >= L:
        return np.asarray(sol.tip_position), np.asarray(sol.tip_rotation)
    rec = prob._c.record_from(sol.unknowns, max(1, sol.formulation.steps))
    k = int(np.argmin(np.abs(rec["s"] - s)))
    pose = base_pose(prob.scene.robot)
    return points_out(pose, rec["position"][k]), rotations_out(pose, rec["rotation"][k])


def secant_compliance(prob, guess, s: float, steps: np.ndarray) -> np.ndarray:
    """The secant compliance (6, 6) at ``s`` of the problem ``prob`` (compiled spatial from a
    scene whose last load is a zero point load at ``s``, with an output node at ``s``),
    solved first from ``guess``, then once per column with that load's component j at
    ``steps[j]``, warm from the first solution."""
    scene0 = prob.scene
    L = scene0.robot.rod.length
    base = Solution(prob._run(guess), scene0, prob.options)
    if not base.success:
        raise ConvergenceError(
            f"tendonrod.compliance: the scene did not solve: {base.message}{_in_rod_units(base)}",
            base,
        )
    p0, R0 = _pose(prob, base, s, L)
    C = np.empty((6, 6))
    head = tuple(scene0.loads[:-1])
    for j, h in enumerate(steps.tolist()):
        load = [0.0] * 6
        load[j] = h
        sc = dataclasses.replace(scene0, loads=head + (PointLoad(s, load[:3], load[3:]),))
        prob._set(sc)
        sol = Solution(prob._run(base), sc, prob.options)
        if not sol.success:
            raise ConvergenceError(
                f"tendonrod.compliance: the scene with the load step {_COMPONENTS[j]} = {h!r} "
                f"at s = {s!r} m did not solve: {sol.message}{_in_rod_units(sol)}",
                sol,
            )
        p, R = _pose(prob, sol, s, L)
        C[:3, j] = (p - p0) / h
        C[3:, j] = rotation_vector(R @ R0.T) / h
    return C
