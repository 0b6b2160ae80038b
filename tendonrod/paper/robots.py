"""The paper's robots and how they are actuated: parameter sets, rods, one-tendon
robots, the tip angle, sigma from a compliance matrix, and :func:`actuate` (pull a
tendon until the unloaded tip reaches a target angle, by :func:`tendonrod.actuate`, then
lock it)."""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..actuation import actuate as actuate_tip
from ..compiled import is_planar
from ..model import Robot, Rod, Scene, Tendon
from ..results import ConvergenceWarning
from ..solution import Solution

__all__ = [
    "G_ACCEL",
    "ALPHA_PAPER",
    "DIRECTIONS",
    "paper_rod_ivb",
    "paper_rod_slack",
    "tendon_EA",
    "single_tendon_robot",
    "tip_angle",
    "sigma_from_compliance",
    "Actuation",
    "actuate",
]

G_ACCEL = 9.81
"""Standard gravity [m/s^2], to turn the paper's 20 g / 50 g weights into forces."""
ALPHA_PAPER = 8.29e6
"""The dimensionless tendon stiffness r^2 k L / EI the paper used for Figs. 13-15."""
DIRECTIONS = {
    "transverse": np.array([1.0, 0.0, 0.0]),
    "axial": np.array([0.0, 0.0, 1.0]),
    "out-of-plane": np.array([0.0, 1.0, 0.0]),
}
"""World directions of the paper's load cases for the robot actuated in the x-z plane."""


def paper_rod_ivb(**overrides):
    """The robot of the paper's Sec. IV-B (Figs. 11-16): Kirchhoff rod, L = 0.1 m,
    d = 1.04 mm, E = 210 GPa, G = 80 GPa."""
    kw = dict(length=0.1, diameter=1.04e-3, E=210e9, G=80e9, kirchhoff=True)
    kw.update(overrides)
    return Rod(**kw)


def paper_rod_slack(**overrides):
    """The robot of the paper's Figs. 17-18: Kirchhoff rod, L = 0.2 m, d = 0.8 mm,
    E = 207 GPa, G = 79.6 GPa."""
    kw = dict(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    kw.update(overrides)
    return Rod(**kw)


def tendon_EA(alpha: float, EI: float, r: float) -> float:
    """Tendon axial rigidity EA [N] for a dimensionless stiffness alpha = r^2 k L / EI,
    k = EA / L (np.inf stays np.inf)."""
    return math.inf if math.isinf(alpha) else alpha * EI / r**2


def single_tendon_robot(
    rod,
    routing: str = "parallel",
    offset: float = 0.01,
    alpha: float = math.inf,
    angle: float = 0.0,
):
    """A robot with one tendon at ``offset`` [m], parallel or converging to the tip,
    stiffness alpha = r^2 k L / EI (np.inf: inextensible)."""
    EA = tendon_EA(alpha, rod.bending_stiffness, offset)
    if routing == "parallel":
        t = Tendon(offset=offset, angle=angle, EA=EA)
    elif routing == "converging":
        t = Tendon.converging(offset=offset, angle=angle, length=rod.length, EA=EA)
    else:
        raise ValueError(f"routing must be 'parallel' or 'converging', got {routing!r}")
    return Robot(rod, [t])


def tip_angle(sol) -> float:
    """Tip angle [rad] in the x-z plane: the tip tangent's inclination from +z towards +x."""
    R = np.asarray(sol.tip_rotation)
    return math.atan2(R[0, 2], R[2, 2])


def sigma_from_compliance(C, direction, EI: float, L: float) -> float:
    """sigma = 12 EI/L^3 * d^T C_ff d for the unit world direction d (C: (6, 6) compliance)."""
    d = np.asarray(direction, dtype=float)
    d = d / np.linalg.norm(d)
    return 12.0 * EI / L**3 * float(d @ np.asarray(C)[:3, :3] @ d)


# --------------------------------------------------------------------------- actuation
@dataclass(frozen=True)
class Actuation:
    """A robot brought to a target tip angle by tension, and the same state with the
    actuators locked.

    tension_scene : Scene  -- every tendon tension-controlled (``tensions``)
    locked_scene  : Scene  -- every tendon displacement-controlled at ``displacements``
    solution      : Solution of ``tension_scene`` (= of ``locked_scene``, unloaded)
    tensions      : (nt,) [N];  displacements : (nt,) [m];  theta : tip angle reached [rad]
    """

    tension_scene: Scene
    locked_scene: Scene
    solution: Solution
    tensions: np.ndarray
    displacements: np.ndarray
    theta: float

    def with_loads(self, loads, locked: bool = True) -> Scene:
        """The locked (or tension-held) scene with ``loads`` applied."""
        base = self.locked_scene if locked else self.tension_scene
        return dataclasses.replace(base, loads=tuple(loads))


def actuate(
    robot,
    theta: float,
    tendon: int = 0,
    tensions: Sequence[float] | None = None,
    options=None,
    tol: float = 1e-11,
    max_iter: int = 60,
) -> Actuation:
    """Pull ``tendon`` until the unloaded tip angle (x-z plane, towards +x) is ``theta``,
    by :func:`tendonrod.actuate` on the tension of that tendon.

    The other tendons keep ``tensions`` (default 0 N).  ``tol`` [rad] on the tip angle
    (1e-11: far below anything plotted, above the solver's 1e-10 scaled tolerance times a
    curvature of order 1).  A planar robot is driven by the unwrapped tip angle; any other
    by the tip direction (sin theta, 0, cos theta).  RuntimeError with
    :func:`tendonrod.actuate`'s message when the tendon cannot reach ``theta`` (e.g. it
    has no moment arm in the x-z plane).
    """
    nt = robot.n_tendons
    base = np.zeros(nt) if tensions is None else np.array(tensions, dtype=float)
    if base.shape != (nt,):
        raise ValueError(f"tensions must have one entry per tendon ({nt}), got {tensions!r}")
    if not (isinstance(tendon, (int, np.integer)) and 0 <= tendon < nt):
        raise ValueError(f"tendon must be a tendon index in 0..{nt - 1}, got {tendon!r}")
    scene = Scene(robot, tension=list(base))
    target: dict[str, Any]
    if is_planar(scene):
        target = {"tip_angle": float(theta)}
    else:
        target = {"tip_direction": (math.sin(theta), 0.0, math.cos(theta))}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        sol = actuate_tip(
            scene, tendons=[tendon], tol=tol, max_iter=max_iter, options=options, **target
        )
    if not (sol.success and sol.actuation.reached):
        why = sol.message if not sol.success else sol.actuation.message
        raise RuntimeError(f"actuate: tendon {tendon} cannot reach theta={theta!r} rad: {why}")
    taus = np.array(sol.tension, dtype=float)
    q = np.array(sol.displacement, dtype=float)
    return Actuation(
        tension_scene=Scene(robot, tension=list(taus)),
        locked_scene=Scene(robot, displacement=list(q)),
        solution=sol,
        tensions=taus,
        displacements=q,
        theta=tip_angle(sol),
    )
