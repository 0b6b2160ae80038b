"""Where a tendon with channel friction slid: the check of the assumed sliding direction.

A scene with ``Tendon(friction=mu)`` is solved with every frictional tendon sliding along
its whole length in the direction ``Scene.sliding`` gives (docs/model.md, Section 3).
Whether the tendon really moved that way follows from the solution and the state it came
from: :func:`slip` compares the tendon material's position in its channel in the two
states and reports where it moved against the assumed direction, so that such a solution
is not taken for what static friction would give.  The recording pass integrates each
frictional tendon's rest length from the base, ``rho(s) = int |w| / (1 + tau/EA) ds``: the
material coordinate of the tendon at ``s``, measured from the base, and ``rho(t) - rho(s)``
the material between ``s`` and the anchor, which does not move.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

__all__ = ["Slip", "slip"]


@dataclass(frozen=True)
class Slip:
    """The slip of each frictional tendon between two states (see :func:`slip`).

    Attributes
    ----------
    s : ndarray (N,)
        Arc length of the solution's nodes [m].
    slip : ndarray (N, ntendon)
        How far the tendon material at each node moved along the rod relative to its
        channel since the reference state [m, reference arc length]: positive toward the
        actuator ("in"), negative toward the anchor ("out"); 0 at the anchor; NaN for a
        frictionless tendon and distal of the anchor.
    sliding : tuple of str
        The direction each tendon was assumed to slide (``Scene.sliding``).
    conflicts : tuple of (int, float, float, float)
        Per contradiction: tendon, the arc lengths [m] of the first and last node where
        the material moved against the assumed direction by more than ``tol``, and the
        largest such slip [m].
    tol : tuple of float
        Per tendon, the slip below which a sign is not counted [m] (NaN: frictionless).

    Examples
    --------
    >>> rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    >>> robot = tr.Robot(rod, [tr.Tendon(offset=0.01, friction=0.2)])
    >>> check = tr.slip(tr.solve(tr.Scene(robot, displacement=[0.01], sliding="out")))
    >>> check.consistent  # pulled from rest, the tendon slid in, not out
    False
    >>> check.conflicts[0][0], check.message.startswith("tendon 0 slid in")
    (0, True)
    """

    s: np.ndarray
    slip: np.ndarray
    sliding: tuple
    conflicts: tuple
    tol: tuple

    @property
    def consistent(self) -> bool:
        """True when every frictional tendon moved the way it was assumed to slide."""
        return not self.conflicts

    @property
    def message(self) -> str:
        """What the check found, in words."""
        if not self.conflicts:
            return "every frictional tendon slid the way its scene assumes"
        parts = [
            f"tendon {i} slid {'out' if self.sliding[i] == 'in' else 'in'} (by up to "
            f"{w:.3g} m) on s in [{a:.6g}, {b:.6g}] m, against the assumed "
            f'"{self.sliding[i]}": its friction there acts the other way'
            for i, a, b, w in self.conflicts
        ]
        return "; ".join(parts)


def _reference_scene(scene):
    """The scene unloaded and unactuated: every displacement and tension 0."""
    disp = tuple(None if d is None else 0.0 for d in scene.displacement)
    ten = tuple(None if t is None else 0.0 for t in scene.tension)
    return dataclasses.replace(scene, displacement=disp, tension=ten, loads=())


def slip(solution, reference=None, *, tol: float | None = None) -> Slip:
    """The slip of each frictional tendon of ``solution`` since ``reference`` (a solved
    state of the same robot; default: the robot unloaded and unactuated, every
    displacement and tension 0, which is where a tendon pulled from rest slid from).

    A tendon assumed to slide ``"in"`` must have moved toward the actuator wherever it is
    taut (a slack tendon presses on nothing), ``"out"`` toward the anchor; where its
    material moved the other way by more than ``tol`` [m] (finite, >= 0; default: 1e-9 L
    or 1e-6 of the largest slip, whichever is larger) the friction there would act the
    other way, and the solution is not the one the assumed direction stands for:
    ``Slip.conflicts`` says where, ``Slip.message`` in words.

    Examples
    --------
    >>> rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    >>> robot = tr.Robot(rod, [tr.Tendon(offset=0.01, friction=0.2)])
    >>> sol = tr.solve(tr.Scene(robot, displacement=[0.01], sliding="in"))
    >>> check = tr.slip(sol)
    >>> check.consistent, bool(check.slip[0, 0] > 0)  # pulled: it slid in
    (True, True)
    """
    from ._fields import _nonnegative
    from .solution import Solution
    from .solver import solve

    for name, sol in (("solution", solution), ("reference", reference)):
        if not (isinstance(sol, Solution) or (sol is None and name == "reference")):
            raise TypeError(f"slip: {name} must be a tendonrod.Solution, got {sol!r}")
        if sol is not None and sol.scene is None:
            raise ValueError(f"slip: the {name} carries no scene")
    if tol is not None:
        # finite and >= 0: NaN or inf would let every conflict through
        tol = _nonnegative("slip", "tol", tol)
    scene = solution.scene
    if reference is None:
        reference = solve(_reference_scene(scene), options=solution.options)
    if reference.scene.robot != scene.robot:
        raise ValueError("slip: the reference must be a solution of the same robot")
    for name, sol in (("solution", solution), ("reference", reference)):
        if not sol.success:
            raise ValueError(f"slip: the {name} did not succeed ({sol.message})")
    robot = scene.robot
    s, sa = solution.s, reference.s
    rb, ra = solution._recorded()["tendon_rest"], reference._recorded()["tendon_rest"]
    out = np.full(rb.shape, np.nan)
    conflicts = []
    L = robot.rod.length
    for i, t in enumerate(robot.tendons):
        if t.friction == 0.0:
            continue
        end = robot.tendon_end(i)
        inb, ina = s <= end * (1 + 1e-12), sa <= end * (1 + 1e-12)
        # material between each node and the anchor (rest length), in this state ...
        D = rb[inb, i][-1] - rb[inb, i]
        # ... and where that material sat in the reference (linear beyond the base: the
        # material that was outside the channel)
        rho, ss = ra[ina, i], sa[ina]
        target = rho[-1] - D
        s_ref = np.interp(target, rho, ss)
        below = target < rho[0]
        slope = (rho[1] - rho[0]) / (ss[1] - ss[0])
        s_ref[below] = ss[0] + (target[below] - rho[0]) / slope
        out[inb, i] = s_ref - s[inb]
    lims = [float("nan")] * robot.n_tendons
    for i, t in enumerate(robot.tendons):
        if t.friction == 0.0:
            continue
        col = out[:, i]
        big = np.nanmax(np.abs(col)) if np.any(np.isfinite(col)) else 0.0
        lim = lims[i] = tol if tol is not None else max(1e-9 * L, 1e-6 * big)
        sign = 1.0 if scene.sliding[i] == "in" else -1.0
        taut = solution.tendon_tension[:, i] > 0.0
        bad = np.flatnonzero((sign * col < -lim) & taut)
        if bad.size:
            worst = float(np.max(-sign * col[bad]))
            conflicts.append((i, float(s[bad[0]]), float(s[bad[-1]]), worst))
    return Slip(s, out, tuple(scene.sliding), tuple(conflicts), tuple(lims))
