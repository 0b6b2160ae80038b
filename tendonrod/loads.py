"""External loads of a scene: point loads, distributed loads and point masses.

Frozen, validated dataclasses (ValueError naming the field and its value). Forces and
moments are in the world frame; arc lengths are checked against the rod in
:class:`~tendonrod.Scene`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._fields import Vec3Like, _nonnegative, _vec3

__all__ = ["PointLoad", "DistributedLoad", "PointMass"]


@dataclass(frozen=True)
class PointLoad:
    """A point force and moment at arc length ``s`` [m] (0 <= s <= L, checked in :class:`Scene`).

    ``force`` [N] and ``moment`` [N m] are 3-vectors in the world frame; the force acts on
    the backbone centre line at ``s``.
    """

    s: float
    force: Vec3Like = (0.0, 0.0, 0.0)  # stored as a tuple
    moment: Vec3Like = (0.0, 0.0, 0.0)  # stored as a tuple

    def __post_init__(self):
        object.__setattr__(self, "s", _nonnegative("PointLoad", "s", self.s))
        object.__setattr__(self, "force", _vec3("PointLoad", "force", self.force))
        object.__setattr__(self, "moment", _vec3("PointLoad", "moment", self.moment))


@dataclass(frozen=True)
class DistributedLoad:
    """A uniform distributed force ``force`` [N/m] (world frame) on the arc lengths
    ``start <= s <= end`` [m] (defaults: the whole rod; ``end`` None is the tip;
    ``end <= L`` is checked in :class:`Scene`).  A load over part of the rod makes
    ``start`` and ``end`` breakpoints of the integration, and its force is part of a
    compiled problem's structure; one over the whole rod is a per-solve value."""

    force: Vec3Like = (0.0, 0.0, 0.0)  # stored as a tuple
    start: float = 0.0
    end: float | None = None

    def __post_init__(self):
        object.__setattr__(self, "force", _vec3("DistributedLoad", "force", self.force))
        object.__setattr__(self, "start", _nonnegative("DistributedLoad", "start", self.start))
        if self.end is not None:
            end = _nonnegative("DistributedLoad", "end", self.end)
            if not end > self.start:
                raise ValueError(
                    f"DistributedLoad.end must be > start = {self.start!r}, got {self.end!r}"
                )
            object.__setattr__(self, "end", end)


@dataclass(frozen=True)
class PointMass:
    """A mass ``mass`` [kg] on the centre line at arc length ``s`` [m] (0 <= s <= L, checked
    in :class:`Scene`), e.g. a spacer disk.  It weighs only under the scene's gravity,
    which turns it into the point force ``mass * gravity`` [N] (world frame) at ``s``."""

    s: float
    mass: float

    def __post_init__(self):
        object.__setattr__(self, "s", _nonnegative("PointMass", "s", self.s))
        object.__setattr__(self, "mass", _nonnegative("PointMass", "mass", self.mass))

    @classmethod
    def disks(cls, s, mass) -> tuple[PointMass, ...]:
        """The masses of spacer disks: one :class:`PointMass` per disk, as a tuple to put
        in :attr:`Scene.loads <tendonrod.Scene>`.

        ``s``: the disks' arc lengths [m] (a sequence, each 0 <= s <= L, checked in
        :class:`Scene`), or a :class:`tendonrod.routing.Path` made by ``Path.disks``,
        whose disk positions are used (its knots after the base hole at s = 0).
        ``mass`` [kg]: one number (every disk weighs the same) or one per disk.
        Like every point mass they weigh only under the scene's gravity; a disk's mass
        sits on the centre line (its rotary inertia plays no part in statics)."""
        knots = getattr(s, "knots", None)
        if knots is not None:
            s = np.asarray(knots, dtype=float)[1:]
        try:
            arc = np.asarray(s, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"PointMass.disks: s must be arc lengths [m], got {s!r}") from None
        if arc.ndim != 1 or arc.size == 0:
            raise ValueError(f"PointMass.disks: s must be a 1-D sequence of arc lengths, got {s!r}")
        if np.ndim(mass) == 0:
            masses = [mass] * arc.size
        else:
            masses = list(mass)
            if len(masses) != arc.size:
                raise ValueError(
                    f"PointMass.disks: mass must be one number or one per disk ({arc.size}), "
                    f"got {len(masses)} values: {mass!r}"
                )
        out = []
        for k, (sk, mk) in enumerate(zip(arc, masses)):
            try:
                out.append(cls(s=float(sk), mass=mk))
            except ValueError as exc:
                raise ValueError(f"PointMass.disks: disk {k}: {exc}") from None
        return tuple(out)
