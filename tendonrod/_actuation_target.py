"""The targets of :func:`tendonrod.actuate`: checked, put in the base frame, and handed to
the core (``csrc/tr_act_run.c``), which computes each one's residual at a solution and its
derivative with respect to the tip's [dx, dtheta].

Residuals are dimensionless: positions divided by the rod length L, angles and direction
components in radians.  No arccos: a tip angle is the planar formulation's unwrapped
angle, a direction its log map on the unit sphere about the target (the great-circle angle
by atan2, along an orthonormal basis B of the plane normal to it), a rotation the rotation
vector of R R_target^T (from its skew part and trace through atan2).

A mounted robot's targets are given in the world frame and compared in its base frame
(where the planar formulation's plane and tip angle are defined): positions ``R0^T (p -
p0)``, directions and rotations ``R0^T t``, ``R0^T R``, against the base-frame tip the
core reports.
"""

from __future__ import annotations

import math

import numpy as np

from .mounting import base_pose

__all__ = ["Target"]


def _skew(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def _unit(v, name):
    try:
        a = np.array(v, dtype=float).reshape(3)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"{name} must be a 3-vector of real numbers, got {v!r}") from None
    n = np.linalg.norm(a)
    if not (np.all(np.isfinite(a)) and n > 0.0):
        raise ValueError(f"{name} must be a finite nonzero 3-vector, got {v!r}")
    return a / n


class Target:
    """A tip target with m residual components, in the base frame; ``planar`` keeps the
    in-plane components."""

    def __init__(self, scene, planar, tip_angle, tip_direction, tip_position, tip_pose):
        given = {
            k: v
            for k, v in (
                ("tip_angle", tip_angle),
                ("tip_direction", tip_direction),
                ("tip_position", tip_position),
                ("tip_pose", tip_pose),
            )
            if v is not None
        }
        if len(given) != 1:
            raise ValueError(
                "give exactly one target: tip_angle, tip_direction, tip_position or tip_pose "
                f"(got {', '.join(given) or 'none'})"
            )
        ((self.name, value),) = given.items()
        self.given = dict(given)
        pose = base_pose(scene.robot)
        self.pose = pose
        self._R0t = None if pose is None else pose[1].T
        self.L = scene.robot.rod.length
        self.planar = planar
        if self.name == "tip_angle":
            if not planar:
                raise ValueError(
                    f"tip_angle={value!r} is for planar scenes (tendons at angle 0 or pi, loads "
                    f"in the x-z plane, no force_spatial); give tip_direction=(sin a, 0, cos a)"
                )
            try:
                self.theta = float(value)
            except (TypeError, ValueError, OverflowError):
                raise ValueError(f"tip_angle must be a finite angle [rad], got {value!r}") from None
            if not math.isfinite(self.theta):
                raise ValueError(f"tip_angle must be a finite angle [rad], got {value!r}")
            self.m = 1
        elif self.name == "tip_direction":
            self.t = _unit(value, "tip_direction")
            if pose is not None:
                self.t = self._R0t @ self.t
            e = np.eye(3)[int(np.argmin(np.abs(self.t)))]
            b1 = _skew(self.t) @ e  # t x e
            b1 /= np.linalg.norm(b1)
            if planar and abs(self.t[1]) == 0.0:
                b1 = np.array([self.t[2], 0.0, -self.t[0]])  # the in-plane normal only
                self.B = b1[:, None]
            else:
                self.B = np.column_stack([b1, _skew(self.t) @ b1])
            self.m = self.B.shape[1]
            self._BT = np.ascontiguousarray(self.B.T)  # (m, 3) rows b_k^T
        else:
            if self.name == "tip_position":
                p, R = value, None
            else:
                try:
                    p, R = value
                except (TypeError, ValueError):
                    raise ValueError(
                        f"tip_pose must be (position (3,), rotation (3, 3)), got {value!r}"
                    ) from None
            try:
                self.p = np.array(p, dtype=float).reshape(3)
            except (TypeError, ValueError, OverflowError):
                raise ValueError(f"{self.name}: position must be a 3-vector, got {p!r}") from None
            if not np.all(np.isfinite(self.p)):
                raise ValueError(f"{self.name}: position must be finite, got {p!r}")
            self.R = None
            if R is not None:
                try:
                    Ra = np.array(R, dtype=float).reshape(3, 3)
                except (TypeError, ValueError, OverflowError):
                    raise ValueError(f"tip_pose: rotation must be 3x3, got {R!r}") from None
                if not (
                    np.all(np.isfinite(Ra))
                    and np.abs(Ra.T @ Ra - np.eye(3)).max() <= 1e-9
                    and np.linalg.det(Ra) > 0
                ):
                    raise ValueError(f"tip_pose: rotation must be a rotation matrix, got {R!r}")
                self.R = Ra if pose is None else self._R0t @ Ra
            if pose is not None:
                self.p = self._R0t @ (self.p - pose[0])
            rows = [0, 1, 2]
            if planar and self.p[1] == 0.0:
                rows = [0, 2]
            if self.R is not None:
                about_y = abs(self.R[1, 1] - 1.0) <= 1e-12
                rows += [4] if planar and about_y and rows == [0, 2] else [3, 4, 5]
            self.rows = rows
            self.m = len(rows)

    def spec(self) -> dict:
        """The target as ``_core.Problem.actuate`` takes it (base frame): ``goal`` (1 angle,
        2 direction, 3 position or pose) and its values."""
        if self.name == "tip_angle":
            return {"goal": 1, "theta": self.theta}
        if self.name == "tip_direction":
            return {"goal": 2, "direction": self.t, "basis": self._BT}
        return {
            "goal": 3,
            "position": self.p,
            "rotation": self.R,
            "rows": np.array(self.rows, dtype=float),
        }
