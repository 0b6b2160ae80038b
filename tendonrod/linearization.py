"""What a linearisation reports (:class:`Jacobian`) and the names of the design parameters
it can differentiate with respect to.

Design parameters are named by their path into the scene's dataclasses, as a
:func:`tendonrod.sweep` names what it varies: ``"robot.rod.EI"``, ``"robot.rod.GJ"``,
``"robot.rod.EA"``, ``"robot.rod.GA"`` (rigidities [N m^2, N m^2, N, N]; EA and GA of a
Cosserat rod only), ``"robot.tendons[i].EA"`` [N] (finite), ``"robot.tendons[i].offset"``
[m] and ``"robot.tendons[i].slope"`` [-] (not for a pretensioned tendon set, whose balance
one tendon's routing cannot change alone), ``"robot.tendons[i].friction"`` [-] (a tendon
with friction > 0: the problem's structure has its friction state).  Short forms are accepted: ``"EI"``,
``"rod.EI"``, ``"tendons[0].EA"``.  A derivative with respect to one of them holds every
other field of the scene fixed: a converging tendon's slope stays when its offset moves;
``robot.rod.EI`` moves the bending rigidity alone (not GJ, whatever the section).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from typing import Generic, TypeVar

import numpy as np
from numpy.typing import NDArray

from . import _core
from ._scene_paths import get_path, set_path
from .model import Scene

__all__ = ["Jacobian", "design_parameter", "design_value", "with_design"]

# The core's parameter kinds (tr_param_kind), by name.
PARAM_KIND = {name: i for i, name in enumerate(_core.PARAM_KINDS)}

_ROD = {"EI": "bending_stiffness", "GJ": "torsional_stiffness", "EA": "axial_stiffness"}
_ROD["GA"] = "shear_stiffness"
_TENDON_FIELDS = {"EA": "tendon_EA", "offset": "offset", "slope": "slope", "friction": "friction"}
_NAME = re.compile(r"^(?:robot\.)?(?:rod\.)?(EI|GJ|EA|GA)$|^(?:robot\.)?tendons\[(\d+)\]\.(\w+)$")


def design_parameter(scene: Scene, name) -> tuple[str, int, int]:
    """``(canonical path, core kind, index)`` of the design parameter ``name`` of
    ``scene``; ValueError naming it when the scene has no such parameter."""
    m = _NAME.match(name) if isinstance(name, str) else None
    robot = scene.robot
    if m is None:
        raise ValueError(
            f"design parameter {name!r}: expected one of 'robot.rod.EI', 'robot.rod.GJ', "
            f"'robot.rod.EA', 'robot.rod.GA', 'robot.tendons[i].EA', 'robot.tendons[i].offset', "
            f"'robot.tendons[i].slope', 'robot.tendons[i].friction' (or the short forms 'EI', "
            f"'tendons[i].EA')"
        )
    if m.group(1):
        field = m.group(1)
        if robot.rod.segments:
            raise ValueError(
                f"design parameter {name!r}: a segmented rod has one {field} per segment, "
                f"not one for the rod"
            )
        if field in ("EA", "GA") and robot.rod.kirchhoff:
            raise ValueError(
                f"design parameter {name!r}: a Kirchhoff rod (kirchhoff=True) has no "
                f"{field} in its model"
            )
        return f"robot.rod.{field}", PARAM_KIND[field], 0
    i, field = int(m.group(2)), m.group(3)
    if field not in _TENDON_FIELDS:
        raise ValueError(
            f"design parameter {name!r}: a tendon's design parameters are EA, offset, slope and "
            f"friction"
        )
    if i >= robot.n_tendons:
        raise ValueError(f"design parameter {name!r}: the robot has {robot.n_tendons} tendon(s)")
    if field == "EA" and math.isinf(robot.tendons[i].EA):
        raise ValueError(
            f"design parameter {name!r}: tendon {i} is inextensible (EA = inf); give it a "
            f"finite EA to differentiate or fit it"
        )
    if field == "friction" and robot.tendons[i].friction == 0.0:
        raise ValueError(
            f"design parameter {name!r}: tendon {i} is frictionless (friction = 0), so its "
            f"problem has no friction state; give it friction > 0 to differentiate or fit it"
        )
    if field in ("offset", "slope") and robot.tendons[i].path is not None:
        raise ValueError(
            f"design parameter {name!r}: tendon {i} follows a Path; its offset and slope are "
            f"derived from it, not parameters"
        )
    if field in ("offset", "slope") and any(t.pretension != 0.0 for t in robot.tendons):
        raise ValueError(
            f"design parameter {name!r}: the routing of one tendon of a pretensioned set "
            f"cannot vary alone (the set would lose the balance its pretension needs)"
        )
    return f"robot.tendons[{i}].{field}", PARAM_KIND[_TENDON_FIELDS[field]], i


def design_value(scene: Scene, path: str) -> float:
    """The value of the design parameter at canonical ``path`` in ``scene`` (the rod's
    effective rigidity where the field is derived from the section)."""
    if path.startswith("robot.rod."):
        return float(getattr(scene.robot.rod, _ROD[path[len("robot.rod.") :]]))
    return float(get_path(scene, path))


def with_design(scene: Scene, values: dict) -> Scene:
    """``scene`` with the design parameters ``{canonical path: value}`` replaced (every
    dataclass on the way validates its new value)."""
    for path, value in values.items():
        scene = set_path(scene, path, float(value))
    return scene


# the type of Jacobian.load: an array when the load block was asked for (load=True, the
# default of tendonrod.jacobian and Problem.jacobian), None when not (load=False)
_LoadT = TypeVar("_LoadT", bound="NDArray[np.float64] | None")


@dataclass(frozen=True, eq=False)
class Jacobian(Generic[_LoadT]):
    """The linearisation of a solved scene at arc length ``s`` (:func:`tendonrod.jacobian`).

    A :class:`~tendonrod.Result`: ``success``, ``status``, ``message``, ``nit``, ``nfev``
    mean the same on every result type.

    Every derivative is taken at the solved state by the implicit function theorem on the
    converged shooting system, the other inputs held: the other tendons' prescribed
    displacements and tensions, the loads, the design.  Rows ``[dx (3) [m], dtheta (3)
    [rad]]`` are the position and the rotation-vector increment (``dR = [dtheta]x R``) of
    the backbone point at ``s``, world frame, as in :func:`tendonrod.compliance`.  With an
    array ``s`` of N arc lengths, ``actuation``, ``load`` and ``design`` gain a leading
    axis of length N.

    Attributes
    ----------
    s : float or ndarray (N,)
        Arc length(s) [m].
    actuation : ndarray (6, ntendon)
        Column j: per unit change of tendon j's control value, q [m] for a
        displacement-controlled tendon, tau [N] for a tension-controlled one (units m/m,
        rad/m or m/N, rad/N).
    tension : ndarray (ntendon, ntendon)
        ``tension[i, j]``: change of tendon i's tension [N] per unit change of tendon j's
        control value.
    slack : ndarray (ntendon, ntendon)
        ``slack[i, j]``: change of tendon i's slack [m] per unit change of tendon j's
        control value (nonzero only for a slack tendon, or one given its slack side).
    load : ndarray (6, 6) or None
        The compliance at ``s``: per unit force (3) [N] and moment (3) [N m] applied at
        ``s``, world frame (the numbers of :func:`tendonrod.compliance`); None when not
        asked for.
    design : ndarray (6, ndesign)
        Per unit change of each parameter of ``design_names`` (its SI unit).
    design_tension : ndarray (ntendon, ndesign)
        Tension changes [N] per unit change of each design parameter.
    design_names : tuple of str
        Canonical paths of the design parameters (see :mod:`tendonrod.linearization`).
    control : tuple of str
        ``"displacement"`` or ``"tension"``: the control value of each tendon.
    at_switch : ndarray (ntendon,) bool
        True where a tendon sits at its taut/slack switch (within the difference stencil,
        ~1e-5 of the solver's tension scale EI/(r L); a tension-controlled tendon: at
        tension 0).  Its derivatives are one-sided, from the side ``switch_side`` says.
    switch_side : ndarray (ntendon,) int
        +1: the taut side's derivatives (valid for changes that tighten the tendon); -1:
        the slack side's (valid for changes that slacken it: its tension stays 0); 0: not
        at the switch.  A tendon at the switch is given the side it is on, the taut one
        when it is exactly at it, unless the taut side leaves the shooting Jacobian
        singular (a tension that cannot change the shape, e.g. of two inextensible
        tendons sharing one path, is indeterminate): then the slack one.
    solution : Solution
        The solved state linearised (the unconverged one when ``success`` is False).
    success, status, message, nit, nfev
        The common fields (:class:`~tendonrod.results.Outcome`): True, 0, ``""``, 0 (a
        linearisation does not iterate) and -1 (its shooting evaluations are not counted)
        when the linearisation was taken; False, < 0 and why not (the derivatives then NaN;
        ``nit``, ``nfev`` the failed solve's) when the scene did not solve or the
        linearisation failed.

    Examples
    --------
    >>> rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    >>> robot = tr.Robot(rod, [tr.Tendon(offset=0.01, angle=0.0)])
    >>> J = tr.jacobian(tr.Scene(robot, displacement=[0.0157]))
    >>> J.actuation.shape, J.tension.shape, J.load.shape
    ((6, 1), (1, 1), (6, 6))
    """

    s: object
    actuation: NDArray[np.float64]
    tension: NDArray[np.float64]
    slack: NDArray[np.float64]
    load: _LoadT
    design: NDArray[np.float64]
    design_tension: NDArray[np.float64]
    design_names: tuple
    control: tuple
    at_switch: np.ndarray
    switch_side: np.ndarray
    solution: object
    success: bool = True
    status: int = 0
    message: str = ""
    nit: int = 0
    nfev: int = -1

    def __repr__(self):
        shape = "" if np.ndim(self.s) == 0 else f" at {np.size(self.s)} arc lengths"
        switch = (
            f", at switch: {np.flatnonzero(self.at_switch).tolist()}" if any(self.at_switch) else ""
        )
        return (
            f"Jacobian(s={self.s!r}{shape}, {len(self.control)} tendon(s) "
            f"{list(self.control)}, design {list(self.design_names)}, "
            f"load {'yes' if self.load is not None else 'no'}{switch})"
        )


# argument checks of the linearisations (tr.jacobian, Problem.jacobian)
def _rows(bp: np.ndarray, s_vals: np.ndarray, L: float):
    """The breakpoint index of each arc length, or None when one is not a breakpoint."""
    rows = []
    for x in s_vals:
        hit = np.flatnonzero(np.abs(bp[1:] - x) <= 1e-12 * L)
        if hit.size == 0:
            return None
        rows.append(int(hit[-1]) + 1)
    return rows


def _design_names(scene: Scene, design, what: str = "design") -> list:
    """(canonical path, kind, index) of each design parameter name (ValueError naming a
    bad one, and the argument ``what`` they came in); a single name may be a string."""
    if isinstance(design, str):
        design = [design]
    try:
        names = list(design)
    except TypeError:
        raise ValueError(f"{what} must be a sequence of parameter names, got {design!r}") from None
    out = [design_parameter(scene, n) for n in names]
    paths = [p for p, _, _ in out]
    if len(set(paths)) != len(paths):
        raise ValueError(f"{what} names a parameter twice: {names!r}")
    return out


def _sides(side, nt: int):
    """``side`` as a float array (nt,) of +1 / -1 / 0, or None; ValueError naming it."""
    if side is None:
        return None
    try:
        arr = np.array(side, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        arr = None
    if arr is None or arr.shape != (nt,) or not np.all((arr == 1.0) | (arr == -1.0) | (arr == 0.0)):
        raise ValueError(f"side must hold +1, -1 or 0 for each of the {nt} tendon(s), got {side!r}")
    return arr


def _forward(method) -> bool:
    """True for method "forward", False for "central"; ValueError naming ``method``."""
    if method not in ("central", "forward"):
        raise ValueError(f"method must be 'central' or 'forward', got {method!r}")
    return method == "forward"
