"""The targets of :func:`tendonrod.actuate`: each one's residual at a solution and its
derivative with respect to the tip's [dx, dtheta] (base frame), which the linearisation's
actuation rows (base frame too) turn into the derivative by the controls.

Residuals are dimensionless: positions divided by the rod length L, angles and direction
components in radians.  No arccos: a tip angle is the planar formulation's unwrapped
angle, a direction its log map on the unit sphere about the target (the great-circle angle
by atan2), a rotation the rotation vector of R R_target^T (from its skew part and trace
through atan2).

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


# (t x v)_i = t_{i+1} v_{i+2} - t_{i+2} v_{i+1}
_CYC1, _CYC2 = np.array([1, 2, 0]), np.array([2, 0, 1])


def _skew(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def _rotvec(R):
    """Rotation vector phi of the rotation matrix R (R = exp([phi]x)), without arccos."""
    v = 0.5 * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    s, c = np.linalg.norm(v), 0.5 * (np.trace(R) - 1.0)
    th = math.atan2(s, c)
    if s > 1e-6:
        return v * (th / s)
    if c > 0.0:  # near the identity: th = s (1 + s^2 / 6 + ...)
        return v * (1.0 + s * s / 6.0)
    # near a half turn: the axis from the symmetric part, its sign from v
    B = 0.5 * (R + R.T) - c * np.eye(3)
    axis = B[:, int(np.argmax(np.diag(B)))]
    axis = axis / np.linalg.norm(axis)
    if axis @ v < 0.0:
        axis = -axis
    return th * axis


def _inv_left_jacobian(phi):
    """J_l^-1(phi): d log(R) = J_l^-1 dtheta for a world increment dR = [dtheta]x R."""
    th = np.linalg.norm(phi)
    K = _skew(phi)
    if th < 1e-6:
        return np.eye(3) - 0.5 * K + K @ K / 12.0
    coef = 1.0 / th**2 - (1.0 + math.cos(th)) / (2.0 * th * math.sin(th))
    return np.eye(3) - 0.5 * K + coef * (K @ K)


def _unit(v, name):
    try:
        a = np.array(v, dtype=float).reshape(3)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a 3-vector, got {v!r}") from None
    n = np.linalg.norm(a)
    if not (np.all(np.isfinite(a)) and n > 0.0):
        raise ValueError(f"{name} must be a finite nonzero 3-vector, got {v!r}")
    return a / n


class Target:
    """The target's residual r (m,) at a solution and its rows of derivatives (m, 6)
    with respect to the tip's [dx, dtheta]; ``planar`` keeps the in-plane components."""

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
            self.theta = float(value)
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
            # the rows b_k^T and t_target^T, and their cyclic shifts for t x v
            self._BT = np.ascontiguousarray(self.B.T)
            rows = np.vstack([self._BT, self.t])
            self._V1, self._V2 = rows[:, _CYC1], rows[:, _CYC2]
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
            except (TypeError, ValueError):
                raise ValueError(f"{self.name}: position must be a 3-vector, got {p!r}") from None
            if not np.all(np.isfinite(self.p)):
                raise ValueError(f"{self.name}: position must be finite, got {p!r}")
            self.R = None
            if R is not None:
                try:
                    Ra = np.array(R, dtype=float).reshape(3, 3)
                except (TypeError, ValueError):
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

    def residual(self, sol):
        """(r (m,), D (m, 6)): the residual and its derivative by the tip's [dx, dtheta]
        in the base frame (where the core reports the tip, ``sol.raw``, and linearises)."""
        if self.name == "tip_angle":
            D = np.zeros((1, 6))
            D[0, 4] = 1.0
            return np.array([sol.tip_angle - self.theta]), D
        R = sol.raw["tip_rotation"]
        if self.name == "tip_direction":
            # the tip direction's coordinates on the unit sphere about the target (its log
            # map): the angle alpha between them along the great circle, in the direction
            # B^T t, alpha = atan2(|B^T t|, t . t_target); linear in the bend of a
            # constant-curvature arc, zero only at the target
            t = R[:, 2]
            Bt = self._BT @ t
            c = float(self.t @ t)
            s = math.sqrt(float(Bt @ Bt))
            # d t = dtheta x t, so d(v . t) = (t x v) . dtheta: the rows of B^T dt and
            # t_target . dt, the cross products by cyclic index shifts of [B t_target]^T
            V = t[_CYC1] * self._V2 - t[_CYC2] * self._V1
            Bdt, cdt = V[:-1], V[-1]
            D = np.zeros((self.m, 6))
            if s < 1e-8 * max(abs(c), 1.0):  # at (or opposite) the target: alpha / s -> 1
                f = 1.0 if c > 0.0 else math.pi / max(s, 1e-300)
                D[:, 3:] = f * Bdt
                return f * Bt, D
            alpha = math.atan2(s, c)
            f = alpha / s
            ds = (Bt @ Bdt) / s  # (3,) row: d|B^T t| by dtheta
            dalpha = (c * ds - s * cdt) / (s * s + c * c)
            df = (dalpha * s - alpha * ds) / (s * s)
            D[:, 3:] = f * Bdt + Bt[:, None] * df
            return f * Bt, D
        r6 = np.zeros(6)
        D6 = np.zeros((6, 6))
        r6[:3] = (sol.raw["tip_position"] - self.p) / self.L
        D6[:3, :3] = np.eye(3) / self.L
        if self.R is not None:
            phi = _rotvec(R @ self.R.T)
            r6[3:] = phi
            D6[3:, 3:] = _inv_left_jacobian(phi)
        return r6[self.rows], D6[self.rows]
