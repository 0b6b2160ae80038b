"""The base pose: the core solves every scene in its base frame (base at the origin, rod
along +z); these maps carry world-frame inputs into that frame and results back out.

For a robot clamped at ``p0`` with base rotation ``R0`` (columns: the base axes in the
world), a world vector ``w`` is ``R0^T w`` in the base frame, and a base-frame position
``p``, rotation ``R`` or vector ``v`` is ``p0 + R0 p``, ``R0 R`` and ``R0 v`` in the world.
An unmounted robot (``Robot.mounted`` False) passes through untouched, so its results
are bitwise those of a solve without a base pose.  Arrays hold 3-vectors in their last
axis (rotations in their last two).
"""

from __future__ import annotations

import numpy as np

__all__ = ["base_pose", "vectors_in", "vectors_out", "points_out", "rotations_out", "pairs_out"]


def base_pose(robot):
    """``(p0 (3,), R0 (3, 3))`` of a mounted robot, None for an unmounted one."""
    if not robot.mounted:
        return None
    pose = robot.__dict__.get("_base_pose")
    if pose is None:
        pose = (np.array(robot.base_position), np.array(robot.base_rotation))
        for a in pose:
            a.setflags(write=False)
        object.__setattr__(robot, "_base_pose", pose)
    return pose


def vectors_in(pose, w: np.ndarray) -> np.ndarray:
    """World vectors ``w`` (..., 3) in the base frame."""
    return w if pose is None else w @ pose[1]


def vectors_out(pose, v: np.ndarray) -> np.ndarray:
    """Base-frame vectors ``v`` (..., 3) in the world frame."""
    return v if pose is None else v @ pose[1].T


def points_out(pose, p: np.ndarray) -> np.ndarray:
    """Base-frame positions ``p`` (..., 3) in the world frame."""
    return p if pose is None else pose[0] + p @ pose[1].T


def rotations_out(pose, R: np.ndarray) -> np.ndarray:
    """Body-to-base rotations ``R`` (..., 3, 3) as body-to-world rotations."""
    return R if pose is None else pose[1] @ R


def pairs_out(pose, x: np.ndarray, axis: int = -1) -> np.ndarray:
    """Stacked pairs of base-frame 3-vectors (force and moment, displacement and rotation)
    along ``axis`` (length 6) in the world frame."""
    if pose is None:
        return x
    x = np.moveaxis(np.asarray(x), axis, -1)
    R = pose[1]
    out = np.concatenate([x[..., :3] @ R.T, x[..., 3:] @ R.T], axis=-1)
    return np.moveaxis(out, -1, axis)
