"""The tendon of a scene: a frozen, validated dataclass (ValueError naming the field).

Its path in the body frame is linear (``r(s) = (slope s + offset)(cos angle, sin angle,
0)``, the fast special case), helical (``twist``: the angle turns along s) or a general
:class:`~tendonrod.routing.Path` (a spline of a function or of sampled points, or straight
pieces between disks).  Conventions as in :mod:`tendonrod.model`.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import KW_ONLY, dataclass

import numpy as np

from . import plausibility
from ._fields import (
    _LENGTH_MAX,
    _TENDON_EA_MAX,
    _TENDON_EA_MIN,
    _length,
    _nonnegative,
    _positive,
    _real,
)
from .routing import Path

__all__ = ["Tendon"]


class _Omitted(float):
    """The type of an offset the caller did not give (its value, 0.01 m, is the old
    default): told apart from any number or None given explicitly."""


_OMITTED_OFFSET = _Omitted(0.01)


@dataclass(frozen=True)
class Tendon:
    """One tendon in its channel.

    Path in the body frame: ``r(s) = (slope * s + offset) * (cos angle, sin angle, 0)``
    for ``0 <= s <= end``.

    Attributes
    ----------
    offset : float
        Radial offset b at the base [m], >= 0.  Required: a tendon without it takes
        0.01 m with a FutureWarning (an error from tendonrod 0.2).
    angle : float
        Angular position phi of the channel in the cross section [rad] (0: +x).
    slope : float
        Radial slope a = dr/ds [-] (0: parallel; ``-offset/L``: converging to the
        centre line at the tip). The radius ``slope*s + offset`` must stay >= 0 on
        ``[0, end]`` (a tendon cannot cross the centre line); :class:`Robot` checks.
    EA : float
        Axial rigidity of the tendon [N], > 0; ``np.inf`` (default): inextensible.
    end : float or None
        Arc length where the tendon is anchored [m], ``0 < end <= L``; ``None``: the tip.
    pretension : float
        Tension [N] the tendon holds at zero displacement in the straight, unloaded
        robot; its rest length is set so. Only meaningful for a balanced set
        (sum of pretension * r_i = 0) with some axial compliance (finite EA or a
        Cosserat backbone); :class:`Robot` checks.
    twist : float or None
        Helical routing (:meth:`helical`): the channel's angle turns at ``twist`` [rad/m],
        ``r(s) = (slope s + offset)(cos(angle + twist s), sin(angle + twist s), 0)``
        (``twist = 0`` is the helix of zero turns); ``None``: linear.
    path : Path or None
        A general path (:class:`tendonrod.routing.Path`), spanning [0, end]; then
        ``offset``, ``angle`` and ``slope`` are derived from it (its polar position at the
        base, its mean radial slope) and serve only the solver's guess and scales.
    friction : float
        Coulomb friction coefficient mu [-] between the tendon and its channel, >= 0
        (default 0: frictionless, the problem compiled exactly as without it).  The
        tendon slides along its whole length in the direction its scene gives
        (``Scene.sliding``), and its tension changes along s by
        ``d tau/ds = -/+ mu tau |t'|`` (docs/model.md, Section 3).

    Helical and general paths make the scene spatial.

    Examples
    --------
    >>> t = tr.Tendon(offset=0.01, angle=np.pi / 2, EA=4e3)  # extensible, at body +y
    >>> float(t.radius(0.1))
    0.01
    >>> round(tr.Tendon.converging(0.01, length=0.2).slope, 12)  # ends on the centre line
    -0.05
    """

    offset: float = _OMITTED_OFFSET
    angle: float = 0.0
    slope: float = 0.0
    EA: float = math.inf
    end: float | None = None
    pretension: float = 0.0
    _: KW_ONLY
    twist: float | None = None
    path: Path | None = None
    friction: float = 0.0

    def __post_init__(self):
        own = "Tendon"
        if type(self.offset) is _Omitted and self.path is None:
            warnings.warn(
                "Tendon() without offset= takes 0.01 m, a default that goes away in "
                "tendonrod 0.2 (then an error): give the radial offset at the base, "
                "e.g. Tendon(offset=0.01) [m]",
                FutureWarning,
                stacklevel=3,
            )
            object.__setattr__(self, "offset", float(self.offset))
        if self.path is not None:
            if not isinstance(self.path, Path):
                raise ValueError(f"Tendon.path must be a tendonrod.routing.Path, got {self.path!r}")
            if self.twist is not None:
                raise ValueError(f"Tendon: give a path or a twist, not both (twist={self.twist!r})")
            b, ang, a = self.path.polar()
            object.__setattr__(self, "offset", b)
            object.__setattr__(self, "angle", ang)
            object.__setattr__(self, "slope", a)
        if self.twist is not None:
            object.__setattr__(self, "twist", _real(own, "twist", self.twist))
        object.__setattr__(self, "offset", _length(own, "offset", self.offset, zero_ok=True))
        object.__setattr__(self, "angle", _real(own, "angle", self.angle))
        slope = _real(own, "slope", self.slope)
        if abs(slope) > _LENGTH_MAX:
            raise ValueError(
                f"{own}.slope must lie in [-{_LENGTH_MAX:g}, {_LENGTH_MAX:g}], got {self.slope!r}"
            )
        object.__setattr__(self, "slope", slope)
        EA = _positive(own, "EA", self.EA, allow_inf=True)
        if math.isfinite(EA) and not (_TENDON_EA_MIN <= EA <= _TENDON_EA_MAX):
            # a subnormal EA would make tau/EA overflow; the same range as the core
            raise ValueError(
                f"{own}.EA must lie in [{_TENDON_EA_MIN:g}, {_TENDON_EA_MAX:g}] N "
                f"or be inf (inextensible), got {self.EA!r}"
            )
        object.__setattr__(self, "EA", EA)
        if self.end is not None:
            object.__setattr__(self, "end", _length(own, "end", self.end))
        object.__setattr__(self, "pretension", _nonnegative(own, "pretension", self.pretension))
        object.__setattr__(self, "friction", _nonnegative(own, "friction", self.friction))
        plausibility.warn(
            filter(
                None,
                [
                    plausibility.angle_finding(self.angle),
                    plausibility.friction_finding(self.friction),
                ],
            )
        )

    @classmethod
    def converging(
        cls,
        offset: float,
        angle: float = 0.0,
        length: float | None = None,
        *,
        EA: float = math.inf,
        end: float | None = None,
        pretension: float = 0.0,
    ) -> Tendon:
        """A tendon converging from ``offset`` at the base to the centre line at
        arc length ``length`` [m] (normally the rod length): ``slope = -offset/length``.

        ``end`` [m] (where the tendon is anchored) defaults to ``length``: past the point
        where it reaches the centre line the tendon would cross it.  Give ``end`` to
        anchor it earlier (``end <= length``; and ``<=`` the rod length)."""
        if length is None:
            raise TypeError("Tendon.converging() missing required argument 'length'")
        length = _positive("Tendon.converging", "length", length)
        offset = _nonnegative("Tendon", "offset", offset)
        if end is None:
            end = length
        return cls(
            offset=offset,
            angle=angle,
            slope=-offset / length,
            EA=EA,
            end=end,
            pretension=pretension,
        )

    @classmethod
    def helical(
        cls,
        offset: float,
        angle: float = 0.0,
        *,
        turns: float | None = None,
        pitch: float | None = None,
        length: float | None = None,
        slope: float = 0.0,
        EA: float = math.inf,
        end: float | None = None,
        pretension: float = 0.0,
    ) -> Tendon:
        """A helical tendon starting at ``offset`` [m] and ``angle`` [rad] at the base:
        ``turns`` [-] turns over ``length`` [m] (normally the rod length or ``end``), or one
        turn per ``pitch`` [m] of arc length; positive turns its angle from body x toward y
        as s grows (a right-handed helix).  ``turns=0`` is the parallel tendon."""
        if (turns is None) == (pitch is None):
            raise ValueError(
                f"Tendon.helical needs exactly one of turns= or pitch= (got turns={turns!r}, "
                f"pitch={pitch!r})"
            )
        if turns is not None:
            if length is None:
                raise TypeError("Tendon.helical(turns=...) needs length= (the helix's length)")
            length = _positive("Tendon.helical", "length", length)
            twist = 2.0 * math.pi * _real("Tendon.helical", "turns", turns) / length
        else:
            p = _real("Tendon.helical", "pitch", pitch)
            if p == 0.0:
                raise ValueError("Tendon.helical: pitch must be nonzero [m per turn], got 0")
            twist = 2.0 * math.pi / p
        return cls(
            offset=offset,
            angle=angle,
            slope=slope,
            EA=EA,
            end=end,
            pretension=pretension,
            twist=twist,
        )

    @classmethod
    def ring(cls, n: int, offset: float, *, phase: float = 0.0, **kwargs) -> tuple[Tendon, ...]:
        """``n`` tendons equally spaced around the rod at radial offset ``offset`` [m]:
        tendon i at angle ``phase + 2 pi i / n`` [rad] from body x toward y; ``kwargs``
        (``EA``, ``pretension``, ``slope``, ``end``, ``friction``, ...) go to each.

        Examples
        --------
        >>> ring = tr.Tendon.ring(3, 0.01, EA=3e3)
        >>> [round(t.angle, 4) for t in ring], ring[2].EA
        ([0.0, 2.0944, 4.1888], 3000.0)
        """
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
            raise ValueError(f"Tendon.ring: n must be an int >= 1, got {n!r}")
        phase = _real("Tendon.ring", "phase", phase)
        return tuple(
            cls(offset=offset, angle=phase + 2.0 * math.pi * i / int(n), **kwargs)
            for i in range(int(n))
        )

    def radius(self, s) -> np.ndarray:
        """Channel radius ``slope*s + offset`` [m] at arc length(s) ``s``."""
        return self.slope * np.asarray(s, dtype=float) + self.offset
