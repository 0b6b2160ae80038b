"""Scene description for the Cosserat-rod/tendon solver: frozen, validated dataclasses.

Everything here is pure Python and describes *what* is solved; :mod:`tendonrod.solver`
packs it into the flat arrays of the C core. Conventions (see ``docs/model.md``):

- SI units (m, N, N m, Pa, kg/m^3, m/s^2), angles in radians.
- The base sits at ``Robot.base_position`` with its frame's axes the columns of
  ``Robot.base_rotation`` (default: the origin and the world frame); the undeformed
  rod lies along the base frame's +z. Loads and gravity are given in the world frame.
- Tendon ``i`` runs at the body-frame offset
  ``r_i(s) = (slope * s + offset) * (cos angle, sin angle, 0)`` and is anchored at
  arc length ``end`` (``None``: the tip). A positive displacement retracts (pulls)
  the tendon; a tension is >= 0.

Every class validates itself on construction and raises :class:`ValueError` naming
the field and its value, so bad input never reaches the C core.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import KW_ONLY, dataclass
from typing import cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import backbone, plausibility
from ._fields import (
    _EA_MAX,
    _EA_MIN,
    _LENGTH_MAX,
    _LENGTH_MIN,
    Vec3Like,
    _actuation,
    _length,
    _nonnegative,
    _positive,
    _rotation,
    _sliding,
    _vec3,
)
from ._pretension import check_pretension
from .loads import DistributedLoad, PointLoad, PointMass
from .tendon import Tendon

__all__ = ["Rod", "Tendon", "Robot", "PointLoad", "DistributedLoad", "PointMass", "Scene"]

_IDENTITY = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


# --------------------------------------------------------------------------- rod
@dataclass(frozen=True)
class Rod:
    """The elastic backbone: a straight, uniform rod of length ``length``.

    Stiffness comes from a round section of ``diameter`` [m] with Young's modulus
    ``E`` [Pa] and shear modulus ``G`` [Pa]: ``A = pi d^2/4``, ``I = pi d^4/64``,
    ``J = 2 I``, hence ``EI = E I``, ``GJ = G J``, ``EA = E A`` and ``GA = G A``
    (shear coefficient 1, as the public codes use). Each of the keyword overrides
    ``EI``, ``GJ`` [N m^2], ``EA``, ``GA`` [N] replaces what the diameter gives;
    without a diameter, the rigidities the model needs must all be given.

    ``kirchhoff=True`` makes the backbone unshearable and inextensible (``EA`` and
    ``GA`` are then not used and may be omitted or ``np.inf``). A Cosserat rod's ``EA``
    and ``GA`` must be finite. The solver's ranges apply: length and diameter in
    [1e-100, 1e100] m, ``EI`` and ``GJ`` in [1e-100, 1e100] N m^2, ``EA`` and ``GA`` in
    [1e-100, 1e150] N.

    Attributes
    ----------
    length : float
        Rod length L [m], > 0.
    diameter, E, G : float or None
        Round section [m] and moduli [Pa] (each > 0 when given).
    EI, GJ, EA, GA : float or None
        Explicit rigidities [N m^2, N m^2, N, N]; ``None``: from the section.
    kirchhoff : bool
        Unshearable, inextensible backbone (``v = e3`` exactly).
    density : float or None
        Mass density rho [kg/m^3] (>= 0, needs ``diameter``): the rod's weight under the
        scene's gravity is the distributed force ``rho A g`` [N/m]; ``None``: weightless.
        With the diameter it is also the mass of :func:`tendonrod.modes`.
    damping : float or None
        Kelvin-Voigt material damping: the retardation time eta [s] (>= 0, finite) of the
        stress ``K (strain + eta d strain/dt)``; used only by :func:`tendonrod.modes`
        (the damping ratios); ``None``: undamped.
    precurvature, segments : 3 floats [1/m], tuple of Rod
        Body-frame curvature u* of the unstressed shape (``m_b = K_bt (u - u*)``), and the
        segments of :meth:`segmented`; see :mod:`tendonrod.backbone`.

    Notes
    -----
    The effective values are the properties :attr:`bending_stiffness` etc. (also
    spelled :attr:`EI_eff`...), used by the solver.

    Examples
    --------
    A 0.2 m spring-steel wire of 0.8 mm diameter, unshearable and inextensible:

    >>> rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    >>> round(rod.bending_stiffness, 6), rod.segments
    (0.004162, ())
    """

    length: float
    diameter: float | None = None
    E: float | None = None
    G: float | None = None
    _: KW_ONLY
    EI: float | None = None
    GJ: float | None = None
    EA: float | None = None
    GA: float | None = None
    kirchhoff: bool = False
    density: float | None = None
    damping: float | None = None
    precurvature: Vec3Like = (0.0, 0.0, 0.0)  # stored as a tuple
    segments: tuple = ()

    def __post_init__(self) -> None:
        own = "Rod"
        pc, segs = backbone.check_backbone(self)
        object.__setattr__(self, "precurvature", pc)
        object.__setattr__(self, "segments", segs)
        if self.density is not None:
            object.__setattr__(self, "density", _nonnegative(own, "density", self.density))
            if self.diameter is None:
                raise ValueError(
                    f"Rod.density={self.density!r} needs a diameter (the section area), "
                    f"got diameter=None"
                )
        if self.damping is not None:
            eta = _nonnegative(own, "damping", self.damping)
            if not math.isfinite(eta):
                raise ValueError(f"Rod.damping must be finite, got {self.damping!r}")
            object.__setattr__(self, "damping", eta)
        object.__setattr__(self, "length", _length(own, "length", self.length))
        if self.diameter is not None:
            object.__setattr__(self, "diameter", _length(own, "diameter", self.diameter))
        for name in ("E", "G"):
            v = getattr(self, name)
            if v is not None:
                object.__setattr__(self, name, _positive(own, name, v))
        for name in ("EI", "GJ"):
            v = getattr(self, name)
            if v is not None:
                object.__setattr__(self, name, _positive(own, name, v))
        for name in ("EA", "GA"):
            v = getattr(self, name)
            if v is not None:
                object.__setattr__(self, name, _positive(own, name, v, allow_inf=True))
        if not isinstance(self.kirchhoff, (bool, np.bool_)):
            raise ValueError(f"Rod.kirchhoff must be True or False, got {self.kirchhoff!r}")
        object.__setattr__(self, "kirchhoff", bool(self.kirchhoff))
        # every rigidity the model needs must be known, finite and > 0 (EA and GA may be
        # inf only when given so explicitly)
        needed = ("EI", "GJ") if self.kirchhoff else ("EI", "GJ", "EA", "GA")
        for name in needed:
            v = self._effective(name)
            src = "E" if name in ("EI", "EA") else "G"
            if v is None:
                raise ValueError(
                    f"Rod.{name} is missing: give {name}=... or both diameter and {src} "
                    f"(diameter={self.diameter!r}, {src}={getattr(self, src)!r})"
                )
            if getattr(self, name) is None and not (math.isfinite(v) and v > 0.0):
                raise ValueError(
                    f"Rod.{name} from diameter={self.diameter!r} and {src}={getattr(self, src)!r} "
                    f"is {v!r}: the section's rigidity must be finite and > 0"
                )
            # the core's ranges: EI, GJ like a length; a finite EA, GA like a tendon's EA; a
            # Cosserat rod's EA and GA finite (kirchhoff=True makes the backbone rigid)
            lo, hi = (_LENGTH_MIN, _LENGTH_MAX) if name in ("EI", "GJ") else (_EA_MIN, _EA_MAX)
            if math.isinf(v):
                raise ValueError(
                    f"Rod.{name} = inf: a Cosserat rod's {name} must be finite; "
                    f"kirchhoff=True makes the backbone unshearable and inextensible"
                )
            if not lo <= v <= hi:
                how = (
                    ""
                    if getattr(self, name) is not None
                    else f" (from diameter={self.diameter!r} and {src}={getattr(self, src)!r})"
                )
                raise ValueError(f"Rod.{name} = {v!r}{how} must lie in [{lo:g}, {hi:g}]")
        # a Kirchhoff rod does not use EA and GA, but a finite value given must be one a
        # Cosserat rod takes (the same rod with kirchhoff=False solves with it)
        for name in ("EA", "GA") if self.kirchhoff else ():
            v = getattr(self, name)
            if v is not None and math.isfinite(v) and not _EA_MIN <= v <= _EA_MAX:
                raise ValueError(
                    f"Rod.{name} = {v!r} must lie in [{_EA_MIN:g}, {_EA_MAX:g}] "
                    f"(or be inf or omitted: kirchhoff=True does not use it)"
                )
        plausibility.warn(
            [f for f in [plausibility.slenderness_finding(self)] if f is not None]
            + plausibility.modulus_findings(self)
        )

    def _effective(self, name: str) -> float | None:
        explicit = getattr(self, name)
        if explicit is not None:
            return explicit
        d = self.diameter
        if d is None:
            return None
        d2 = d * d  # floats: overflow gives inf, never OverflowError
        A = math.pi * d2 / 4.0
        I = math.pi * (d2 * d2) / 64.0
        if name == "EI":
            return None if self.E is None else self.E * I
        if name == "GJ":
            return None if self.G is None else self.G * 2.0 * I
        if name == "EA":
            return None if self.E is None else self.E * A
        if name == "GA":
            return None if self.G is None else self.G * A
        raise KeyError(name)  # pragma: no cover

    def _needed(self, name: str) -> float:
        """A rigidity the model uses: known, since ``__post_init__`` refuses a rod without it."""
        return cast(float, self._effective(name))

    @property
    def bending_stiffness(self) -> float:
        """Effective bending rigidity EI [N m^2]."""
        return self._needed("EI")

    @property
    def torsional_stiffness(self) -> float:
        """Effective torsional rigidity GJ [N m^2]."""
        return self._needed("GJ")

    @property
    def axial_stiffness(self) -> float:
        """Effective axial rigidity EA [N] (``inf`` for a Kirchhoff rod)."""
        return math.inf if self.kirchhoff else self._needed("EA")

    @property
    def shear_stiffness(self) -> float:
        """Effective shear rigidity GA [N] (``inf`` for a Kirchhoff rod)."""
        return math.inf if self.kirchhoff else self._needed("GA")

    @property
    def mass_per_length(self) -> float:
        """rho A [kg/m]: ``density * pi d^2 / 4`` (0 without a density)."""
        if self.density is None:
            return 0.0
        d = cast(float, self.diameter)  # __post_init__ refuses a density without a diameter
        return self.density * (math.pi * d * d / 4.0)

    @classmethod
    def segmented(cls, parts) -> Rod:
        """A backbone of the segments ``parts`` (Rods, base first; see
        :func:`tendonrod.backbone.segmented`)."""
        return backbone.segmented(cls, parts)

    EI_eff = bending_stiffness
    GJ_eff = torsional_stiffness
    EA_eff = axial_stiffness
    GA_eff = shear_stiffness


# --------------------------------------------------------------------------- robot
# Relative tolerance on "the routing radius stays >= 0" and "an anchor lies on the rod":
# exact geometric statements that round-off can miss by a few ulps (a converging
# tendon's radius at the tip is offset - offset/L*L).
_GEOM_RTOL = 1e-12


@dataclass(frozen=True)
class Robot:
    """A rod with tendons: ``Robot(rod, [Tendon(...), ...])``. ``Robot(rod, [])`` is a plain rod.

    Checks on construction: every tendon's ``end`` is <= the rod length; its routing
    radius ``slope*s + offset`` stays >= 0 over ``[0, end]`` (a tendon may reach the
    centre line, as a converging tendon does at its anchor, but not cross it: a
    negative radius would be the same channel at ``angle + pi``, so describe it
    that way); pretension is only accepted on sets that are balanced on every
    segment between anchors and have some axial compliance.

    The base is clamped at ``base_position`` [m] (world frame) with the base frame's
    axes the columns of ``base_rotation`` (3x3, orthonormal to 1e-12, det +1): the
    undeformed rod lies along its third column.  Results are in the world frame.

    Examples
    --------
    >>> rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    >>> robot = tr.Robot(rod, [tr.Tendon(offset=0.01, angle=a) for a in (0.0, np.pi)])
    >>> robot.n_tendons, robot.mounted
    (2, False)
    """

    rod: Rod
    tendons: Sequence[Tendon] = ()  # any sequence; stored as a tuple
    _: KW_ONLY
    base_position: Vec3Like = (0.0, 0.0, 0.0)  # stored as a tuple
    base_rotation: ArrayLike = _IDENTITY  # (3, 3); stored as a tuple of rows

    def __post_init__(self) -> None:
        object.__setattr__(
            self, "base_position", _vec3("Robot", "base_position", self.base_position)
        )
        object.__setattr__(
            self, "base_rotation", _rotation("Robot", "base_rotation", self.base_rotation)
        )
        if not isinstance(self.rod, Rod):
            raise ValueError(f"Robot.rod must be a tendonrod.Rod, got {self.rod!r}")
        try:
            tendons = tuple(self.tendons)
        except TypeError:
            raise ValueError(
                f"Robot.tendons must be a sequence of Tendon, got {self.tendons!r}"
            ) from None
        for i, t in enumerate(tendons):
            if not isinstance(t, Tendon):
                raise ValueError(f"Robot.tendons[{i}] must be a tendonrod.Tendon, got {t!r}")
        object.__setattr__(self, "tendons", tendons)
        L = self.rod.length
        for i, t in enumerate(tendons):
            if t.end is not None and t.end > L * (1.0 + _GEOM_RTOL):
                raise ValueError(
                    f"Robot.tendons[{i}].end must be <= rod length {L!r}, got {t.end!r}"
                )
            end = self.tendon_end(i)
            r_end = t.slope * end + t.offset
            scale = max(t.offset, abs(t.slope) * end)
            if r_end < -_GEOM_RTOL * scale:
                raise ValueError(
                    f"Robot.tendons[{i}]: routing radius slope*s + offset = {r_end!r} < 0 at "
                    f"s = end = {end!r} (slope={t.slope!r}, offset={t.offset!r}); a tendon "
                    f"cannot cross the centre line"
                )
        for i, t in enumerate(tendons):
            if t.path is not None and abs(t.path.knots[-1] - self.tendon_end(i)) > _GEOM_RTOL * L:
                raise ValueError(
                    f"Robot.tendons[{i}].path ends at s = {t.path.knots[-1]!r} m, but the tendon "
                    f"is anchored at {self.tendon_end(i)!r} m: the path must span [0, end]"
                )
        check_pretension(self.rod, tendons, [self.tendon_end(i) for i in range(len(tendons))])
        plausibility.warn(plausibility.offset_findings(self))

    @property
    def mounted(self) -> bool:
        """True when the base is not the world origin and frame."""
        return self.base_rotation != _IDENTITY or self.base_position != (0.0, 0.0, 0.0)

    @property
    def n_tendons(self) -> int:
        """Number of tendons."""
        return len(self.tendons)

    def tendon_end(self, i: int) -> float:
        """Anchor arc length of tendon ``i`` [m] (``end`` or the rod length)."""
        t = self.tendons[i]
        return self.rod.length if t.end is None else min(t.end, self.rod.length)


# --------------------------------------------------------------------------- scene
@dataclass(frozen=True)
class Scene:
    """A robot with its actuation and external loads.

    Each tendon gets exactly one of ``displacement[i]`` [m] (> 0 retracts the tendon;
    its tension is then unknown and it may go slack) or ``tension[i]`` [N] (>= 0);
    the other list holds ``None`` at that place. Both lists may be omitted for a robot
    without tendons. ``loads`` is a sequence of :class:`PointLoad` (world frame, at
    0 <= s <= L), :class:`DistributedLoad` (summed) and :class:`PointMass` objects.
    ``gravity`` [m/s^2] (world frame, default none) weighs the rod (``Rod.density``)
    as the distributed force ``rho A g`` and each point mass as the point force
    ``mass * g``.  ``sliding`` gives, per tendon with ``Tendon.friction``, the direction
    it last slid in its channel: ``"in"`` (toward the actuator: tension falls from the
    actuator toward the anchor; the default) or ``"out"`` (toward the anchor: tension
    rises toward it); one string sets every tendon.  The two bound the hysteresis band
    that static friction allows.

    Examples
    --------
    One tendon retracted by 15.7 mm (a 90 degree bend) and 0.2 N down at the tip:

    >>> rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    >>> robot = tr.Robot(rod, [tr.Tendon(offset=0.01, angle=0.0)])
    >>> scene = tr.Scene(robot, displacement=[0.0157],
    ...                  loads=[tr.PointLoad(s=0.2, force=(0.0, 0.0, -0.2))])
    >>> scene.displacement_controlled()
    (True,)
    """

    robot: Robot
    _: KW_ONLY
    displacement: Sequence[float | None] | NDArray[np.floating] | None = None
    tension: Sequence[float | None] | NDArray[np.floating] | None = None
    loads: Sequence[PointLoad | DistributedLoad | PointMass] = ()
    gravity: Vec3Like = (0.0, 0.0, 0.0)  # stored as a tuple
    sliding: str | Sequence[str] = "in"

    def __post_init__(self) -> None:
        if not isinstance(self.robot, Robot):
            raise ValueError(f"Scene.robot must be a tendonrod.Robot, got {self.robot!r}")
        n = self.robot.n_tendons
        object.__setattr__(self, "sliding", _sliding(self.sliding, n))
        disp = _actuation("displacement", self.displacement, n)
        tens = _actuation("tension", self.tension, n)
        for i in range(n):
            if disp[i] is None and tens[i] is None:
                raise ValueError(
                    f"Scene: tendon {i} has neither a displacement nor a tension "
                    f"(displacement[{i}] = tension[{i}] = None); give exactly one"
                )
            if disp[i] is not None and tens[i] is not None:
                raise ValueError(
                    f"Scene: tendon {i} has both displacement[{i}]={disp[i]!r} and "
                    f"tension[{i}]={tens[i]!r}; give exactly one, None in the other list"
                )
        rod = self.robot.rod
        for i, t in enumerate(self.robot.tendons):
            if (
                disp[i] is not None
                and t.offset == 0.0
                and t.slope == 0.0
                and rod.kirchhoff
                and math.isinf(t.EA)
            ):
                raise ValueError(
                    f"Scene.displacement[{i}]={disp[i]!r}: tendon {i} runs on the centre line "
                    f"(offset=0, slope=0) of an inextensible backbone and is inextensible, so its "
                    f"path length is always its rest length: a displacement cannot act (its tension "
                    f"is indeterminate at 0, impossible otherwise); prescribe its tension instead"
                )
        object.__setattr__(self, "displacement", disp)
        object.__setattr__(self, "tension", tens)
        object.__setattr__(self, "gravity", _vec3("Scene", "gravity", self.gravity))
        loads = self.loads
        if isinstance(loads, (PointLoad, DistributedLoad, PointMass)):
            loads = (loads,)
        try:
            loads = tuple(loads)
        except TypeError:
            raise ValueError(
                f"Scene.loads must be a sequence of PointLoad/DistributedLoad/PointMass, "
                f"got {self.loads!r}"
            ) from None
        L = self.robot.rod.length
        for k, ld in enumerate(loads):
            if isinstance(ld, (PointLoad, PointMass)):
                if ld.s > L * (1.0 + _GEOM_RTOL):
                    raise ValueError(f"Scene.loads[{k}].s must be in [0, L={L!r}], got {ld.s!r}")
            elif isinstance(ld, DistributedLoad) and ld.end is not None:
                if ld.end > L * (1.0 + _GEOM_RTOL):
                    raise ValueError(f"Scene.loads[{k}].end must be <= L={L!r}, got {ld.end!r}")
            elif isinstance(ld, DistributedLoad) and ld.start >= L:
                raise ValueError(
                    f"Scene.loads[{k}].start must be < L={L!r} (its end is the tip), "
                    f"got {ld.start!r}"
                )
            elif not isinstance(ld, DistributedLoad):
                raise ValueError(
                    f"Scene.loads[{k}] must be a PointLoad, DistributedLoad or PointMass, "
                    f"got {ld!r}"
                )
        object.__setattr__(self, "loads", loads)

    @property
    def point_loads(self) -> tuple[PointLoad, ...]:
        """The point loads, in the order given, then the weights ``mass * gravity`` of the
        point masses in theirs (none without gravity)."""
        pls = tuple(ld for ld in self.loads if isinstance(ld, PointLoad))
        g = self.gravity
        if g == (0.0, 0.0, 0.0):
            return pls
        masses = [ld for ld in self.loads if isinstance(ld, PointMass)]
        return pls + tuple(
            PointLoad(ld.s, force=(ld.mass * g[0], ld.mass * g[1], ld.mass * g[2])) for ld in masses
        )

    def _whole(self, ld: DistributedLoad) -> bool:
        L = self.robot.rod.length
        return ld.start == 0.0 and (ld.end is None or ld.end >= L)

    @property
    def partial_loads(self) -> tuple[DistributedLoad, ...]:
        """The distributed loads over part of the rod, in the order given, then the weights
        of a segmented rod's segments (:func:`tendonrod.backbone.segment_weights`)."""
        return tuple(
            ld for ld in self.loads if isinstance(ld, DistributedLoad) and not self._whole(ld)
        ) + backbone.segment_weights(self.robot.rod, self.gravity)

    @property
    def distributed_force(self) -> np.ndarray:
        """Sum of the distributed loads over the whole rod and the rod's weight
        ``rho A g`` [N/m], world frame, shape (3,) (:attr:`partial_loads` aside)."""
        f = np.zeros(3)
        for ld in self.loads:
            if isinstance(ld, DistributedLoad) and self._whole(ld):
                f += ld.force
        w = self.robot.rod.mass_per_length
        if w != 0.0 and self.gravity != (0.0, 0.0, 0.0):
            f += w * np.asarray(self.gravity)
        return f

    def displacement_controlled(self) -> tuple[bool, ...]:
        """Per tendon: True where the displacement is prescribed (tension unknown)."""
        disp = cast(tuple[float | None, ...], self.displacement)  # filled by __post_init__
        return tuple(d is not None for d in disp)
