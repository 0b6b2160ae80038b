"""External loads of a scene: point loads, distributed loads and point masses.

Frozen, validated dataclasses (ValueError naming the field and its value). Forces and
moments are in the world frame; arc lengths are checked against the rod in
:class:`~tendonrod.Scene`.
"""

from __future__ import annotations

from dataclasses import dataclass

from ._fields import Vec3, _nonnegative, _vec3

__all__ = ["PointLoad", "DistributedLoad", "PointMass"]


@dataclass(frozen=True)
class PointLoad:
    """A point force and moment at arc length ``s`` [m] (0 <= s <= L, checked in :class:`Scene`).

    ``force`` [N] and ``moment`` [N m] are 3-vectors in the world frame; the force acts on
    the backbone centre line at ``s``.
    """

    s: float
    force: Vec3 = (0.0, 0.0, 0.0)
    moment: Vec3 = (0.0, 0.0, 0.0)

    def __post_init__(self):
        object.__setattr__(self, "s", _nonnegative("PointLoad", "s", self.s))
        object.__setattr__(self, "force", _vec3("PointLoad", "force", self.force))
        object.__setattr__(self, "moment", _vec3("PointLoad", "moment", self.moment))


@dataclass(frozen=True)
class DistributedLoad:
    """A uniform distributed force ``force`` [N/m] (world frame) over the whole rod."""

    force: Vec3 = (0.0, 0.0, 0.0)

    def __post_init__(self):
        object.__setattr__(self, "force", _vec3("DistributedLoad", "force", self.force))


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
