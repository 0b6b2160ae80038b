"""Plausibility warnings: legal input that is probably a slip.

A scene can be legal and still describe something the model was not made for, or
something nobody meant: an angle in degrees, an offset in millimetres given as metres,
a load a thousand times too large.  tendonrod solves such scenes as given (legal input
stays legal) and says so with a :class:`PlausibilityWarning` that names the quantity,
its value, the limit and the likely slip.  A warning is never an error and never a
verdict: ``success`` stays the core's.

The rules, each written once in this module (thresholds below, with their reasons):

=====================  ===============================================  ===============
rule                   what is measured                                 checked
=====================  ===============================================  ===============
``angle``              ``|Tendon.angle| > 2 pi`` (likely degrees)       Tendon built
``friction``           ``Tendon.friction > 2`` (likely a percentage)    Tendon built
``slenderness``        ``L/d < 10`` (d: the diameter, or the round       Rod built
                       section's ``4 sqrt(EI/EA)``)
``modulus``            ``Rod.E`` or ``Rod.G`` ``< 1e3 Pa`` (likely GPa   Rod built
                       or MPa given as Pa) or ``> 1.5e12 Pa``
``offset``             a tendon's largest radius over [0, end]          Robot built
                       ``> 0.5 L``
``tension``            a tendon bent ``>= 0.9`` of the way to the        after a solve
                       backbone's centre of curvature (``r kappa >=
                       0.9``: the bending a tension of ``0.9 EI/r^2``
                       gives a lone tendon at a free tip)
``strain``             backbone axial ``|n3|/EA`` or shear              after a solve
                       ``|n12|/GA`` strain ``> 2 %`` (a Kirchhoff rod:
                       the strain its section would take)
``curl``               total bending angle ``int |kappa| ds > 360 deg``  after a solve
``self-intersection``  two parts of the backbone whose tangent turned   after a solve
                       by ``>= 180 deg`` between them closer than the
                       diameter (a loop through itself; the model has
                       no contact)
=====================  ===============================================  ===============

The checks of a solution read the backbone's states only when a bound says they
could fire: ``|n(s)| <= sum |F| + |f| L + sum tau`` and ``|kappa| <= |m(s)| / EI`` with
``|m(s)|`` bounded from the loads and tensions alone
(:func:`tendonrod._plausible_rules.screen`, with the rules on solved states), so a solve
whose bounds stay below the limits (almost every design scene) pays a few
microseconds; otherwise the states at the default output nodes are recorded once from
the solution's unknowns (no solve), some 0.1-0.3 ms
(``bench/results/plausibility_cost.md``).

Who warns, and how often (every entry point judges with the same rules; the
per-point findings are data, so nothing is lost when a warning is not repeated):

- a ``Tendon``, ``Rod`` or ``Robot`` warns when it is built;
- ``tr.solve`` warns for the findings of its solution;
- ``tr.Problem.solve`` warns once per rule and subject (a tendon, axial/shear) for the
  life of the problem: a load ramp through implausible states warns once;
- ``tr.solve_batch`` and ``tr.sweep`` issue one warning per rule and subject for the
  whole call, with the number of points, the worst one and its index;
- :attr:`tendonrod.Solution.plausibility`, ``BatchResult.plausibility`` and
  ``SweepResult.plausibility`` list every point's findings (:class:`Finding`).

Silence them as any warning: ``warnings.filterwarnings("ignore",
category=tr.PlausibilityWarning)``, or some of them by a regular expression that matches
the start of their message (``"Tendon.angle"``; a solution's findings start with the
entry point, ``"tendonrod.solve: "``); the findings are still computed and listed.
"""

from __future__ import annotations

import math
import os
import sys
import warnings
from dataclasses import asdict, dataclass
from types import FrameType

__all__ = [
    "PlausibilityWarning",
    "Finding",
    "MAX_STRAIN",
    "MIN_SLENDERNESS",
    "MAX_OFFSET",
    "MAX_CURL",
    "MAX_ANGLE",
    "MAX_FRICTION",
    "MIN_MODULUS",
    "MAX_MODULUS",
    "TENSION_FRACTION",
    "section_diameter",
]

# --------------------------------------------------------------------------- thresholds
#: Backbone axial or shear strain [-] beyond which linear elasticity (and, for a
#: Kirchhoff rod, the inextensible model) is out of its range: metals yield below
#: 1 %, superelastic NiTi's plateau ends near 6-8 %; 2 % is the rule's limit.
MAX_STRAIN = 0.02
#: L/d below which a rod is too stubby for rod theory (shear, warping and the
#: section's own deformation are no longer small).
MIN_SLENDERNESS = 10.0
#: Young's or shear modulus [Pa] below which it is likely in GPa or MPa given as Pa:
#: the softest materials continuum robots are made of lie above it (hydrogels
#: 1e3-1e5 Pa, silicone elastomers 1e5-1e7 Pa).
MIN_MODULUS = 1e3
#: ... and above which it is stiffer than any solid (diamond: E = 1.2e12 Pa).
MAX_MODULUS = 1.5e12
#: A tendon radius beyond this fraction of L is a robot wider than half its length:
#: almost always an offset in millimetres given as metres.
MAX_OFFSET = 0.5
#: Total bending angle [rad] beyond which the backbone has curled more than a full
#: turn: a displacement or load off by a unit factor.
MAX_CURL = 2.0 * math.pi
#: |Tendon.angle| [rad] beyond which the angle is likely in degrees.
MAX_ANGLE = 2.0 * math.pi
#: Coulomb coefficient beyond which Tendon.friction is likely a percentage: tendons in
#: polymer or steel channels slide at 0.05-0.5, rubber on rough surfaces reaches ~1.
MAX_FRICTION = 2.0
#: Fraction of EI/r^2 a tension may reach: at EI/r^2 a tendon anchored at a free tip
#: bends the backbone to curvature 1/r, its path reaches the centre of curvature
#: (|w| = 1 - kappa r -> 0) and the model's tendon path breaks down.  Measured as the
#: largest r kappa toward the tendon (see :func:`tendonrod._plausible_rules.tension_findings`).
TENSION_FRACTION = 0.9
#: Tangent turning [rad] two parts of the backbone need between them before their
#: distance counts as the backbone passing through itself: an arc that turns less than
#: a half turn cannot come back to itself (its chord is >= its length cos(turn/2)).
_SELF_TURN = math.pi
#: Distance [m, relative to L] that counts as contact when the rod's diameter is not
#: known (a rod given by EI alone): the centre line crossing itself.
_CROSSING_RTOL = 1e-9

_SLIPS = {
    "angle": "angles are in radians; a value in degrees (angle=90 meant as 90 deg) is the "
    "usual slip: use math.radians",
    "friction": "friction is the Coulomb coefficient mu (dimensionless); a percentage "
    "(friction=30 meant as 0.3) is the usual slip",
    "slenderness": "rod theory assumes a slender rod; check the units of length and "
    "diameter (a diameter in mm given as m?)",
    "modulus": "moduli are in Pa; a modulus in GPa given as Pa (E=60 meant as 60 GPa) is "
    "the usual slip",
    "offset": "the robot would be wider than half its length; an offset in mm given as m "
    "is the usual slip",
    "tension": "near EI/r^2 the tendon's path reaches the backbone's centre of curvature and "
    "the model breaks down; check the load or tension units (N vs mN) and EI",
    "strain": "the rod is loaded far beyond its elastic range (the model assumes small "
    "strains); check the load units (N vs mN) and the rod's moduli and diameter",
    "curl": "the backbone curls more than a full turn; check the tendon displacement or "
    "load units (mm given as m?)",
    "self-intersection": "a real rod would touch itself there (the model has no contact); "
    "check the displacement or load units",
}


class PlausibilityWarning(UserWarning):
    """Legal input (or its solution) that is probably a slip; never an error.

    The message names the quantity, its value, the limit and the likely slip;
    ``finding`` holds the :class:`Finding` (None for a summary of many points).

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings(record=True) as w:
    ...     warnings.simplefilter("always")
    ...     t = tr.Tendon(offset=0.01, angle=90.0)  # degrees by mistake
    >>> w[0].category.__name__
    'PlausibilityWarning'
    """

    def __init__(self, message: str, finding: Finding | None = None):
        super().__init__(message)
        self.finding = finding


@dataclass(frozen=True)
class Finding:
    """One implausible quantity.

    Attributes
    ----------
    rule : str
        ``"angle"``, ``"slenderness"``, ``"offset"``, ``"tension"``, ``"strain"``,
        ``"curl"`` or ``"self-intersection"`` (see the module docstring).
    subject : str
        What within the rule it is about (``"tendon 1"``, ``"axial"``, ``"shear"``;
        ``""`` for the rod as a whole); findings of one rule and subject are counted
        together in batch and sweep summaries.
    value, limit : float
        The measured value and the rule's limit, in the units the message states (SI;
        angles in rad; a distance in m for ``self-intersection``, a ratio for the rest).
    severity : float
        How far past the limit (>= 1 where the rule fires; the worst point of a summary
        is the most severe).
    message : str
        The full sentence: quantity, value, limit, likely slip.
    """

    rule: str
    subject: str
    value: float
    limit: float
    severity: float
    message: str

    def to_dict(self) -> dict:
        """Plain JSON types (a sweep's file stores them)."""
        return asdict(self)

    @classmethod
    def from_dict(cls, d: dict) -> Finding:
        return cls(
            **{k: d[k] for k in ("rule", "subject", "value", "limit", "severity", "message")}
        )


def _finding(rule, subject, value, limit, severity, text) -> Finding:
    return Finding(
        rule, subject, float(value), float(limit), float(severity), f"{text}: {_SLIPS[rule]}"
    )


# --------------------------------------------------------------------------- emitting
_PKG_DIR = os.path.dirname(os.path.abspath(__file__)) + os.sep


def _user_stacklevel() -> int:
    """The ``stacklevel`` that makes a ``warnings.warn`` in the calling function point at
    the first frame outside tendonrod (a dataclass's generated ``__init__`` counts as
    inside), so that the warning names the user's line."""
    level = 1
    f: FrameType | None = sys._getframe(1)
    while f is not None:
        code = f.f_code
        if code.co_filename.startswith("<frozen importlib"):
            # an import of ours: warnings.warn skips these frames when counting
            f = f.f_back
            continue
        inside = code.co_filename.startswith(_PKG_DIR) or (
            code.co_filename == "<string>" and code.co_name == "__init__"
        )
        if not inside:
            break
        f, level = f.f_back, level + 1
    return level


def warn(findings, who: str = "") -> None:
    """Issue one :class:`PlausibilityWarning` per finding, attributed to the user's line."""
    level = None
    for f in findings:
        if level is None:
            level = _user_stacklevel()
        text = f"{who}: {f.message}" if who else f.message
        warnings.warn(PlausibilityWarning(text, f), stacklevel=level)


def summarize(per_point, who: str, index=lambda i: i, where: str = "") -> list:
    """One :class:`PlausibilityWarning` text per rule and subject over many points.

    ``per_point``: a sequence of tuples of findings (one tuple per point, in order);
    ``index(i)`` names point i (a grid index for a sweep).  Returns the messages (also
    issued as warnings attributed to the user's line)."""
    groups: dict = {}
    for i, fs in enumerate(per_point):
        for f in fs or ():
            g = groups.setdefault((f.rule, f.subject), [0, None, None])
            g[0] += 1
            if g[1] is None or f.severity > g[1].severity:
                g[1], g[2] = f, i
    n = len(per_point)
    texts = []
    for count, worst, i in groups.values():
        texts.append(
            f"{who}: {count} of {n} point{'s' if n != 1 else ''}, the worst at {index(i)}: "
            f"{worst.message}" + (f" (every point's findings: {where})" if where else "")
        )
    level = _user_stacklevel()
    for t in texts:
        warnings.warn(PlausibilityWarning(t), stacklevel=level)
    return texts


# --------------------------------------------------------------------------- input rules
def section_diameter(rod) -> float | None:
    """The rod's diameter [m], or the round section's ``4 sqrt(EI/EA)`` when the
    rigidities are given instead (I/A = d^2/16), or None (a rod given by EI alone)."""
    if rod.diameter is not None:
        return rod.diameter
    ea = rod._effective("EA")
    if ea is None or not math.isfinite(ea):
        return None
    return 4.0 * math.sqrt(rod.bending_stiffness / ea)


def angle_finding(angle: float, who: str = "Tendon.angle") -> Finding | None:
    """The ``angle`` rule: ``|angle| > 2 pi`` [rad]."""
    if not abs(angle) > MAX_ANGLE:
        return None
    return _finding(
        "angle",
        "",
        angle,
        MAX_ANGLE,
        abs(angle) / MAX_ANGLE,
        f"{who} = {angle:.6g} rad is beyond 2 pi in magnitude (read as degrees it would be "
        f"{math.radians(angle):.6g} rad)",
    )


def friction_finding(mu: float, who: str = "Tendon.friction") -> Finding | None:
    """The ``friction`` rule: ``Tendon.friction > MAX_FRICTION``."""
    if not mu > MAX_FRICTION:
        return None
    return _finding(
        "friction",
        "",
        mu,
        MAX_FRICTION,
        mu / MAX_FRICTION,
        f"{who} = {mu:.6g} is a Coulomb coefficient beyond {MAX_FRICTION:g}",
    )


def slenderness_finding(rod, who: str = "Rod") -> Finding | None:
    """The ``slenderness`` rule: ``L/d < 10``."""
    d = section_diameter(rod)
    if d is None:
        return None
    ratio = rod.length / d
    if not ratio < MIN_SLENDERNESS:
        return None
    what = "diameter" if rod.diameter is not None else "round-section diameter 4 sqrt(EI/EA)"
    return _finding(
        "slenderness",
        "",
        ratio,
        MIN_SLENDERNESS,
        MIN_SLENDERNESS / max(ratio, 1e-300),
        f"{who}: slenderness L/d = {ratio:.4g} is below {MIN_SLENDERNESS:g} (length "
        f"{rod.length:.4g} m, {what} {d:.4g} m)",
    )


def modulus_findings(rod, who: str = "Rod") -> list:
    """The ``modulus`` rule: ``Rod.E`` or ``Rod.G`` [Pa] outside [MIN_MODULUS,
    MAX_MODULUS] (rigidities given directly are not judged: their units mix)."""
    out = []
    for name in ("E", "G"):
        v = getattr(rod, name)
        if v is None or MIN_MODULUS <= v <= MAX_MODULUS:
            continue
        if v < MIN_MODULUS:
            text = (
                f"{who}.{name} = {v:.6g} Pa is below {MIN_MODULUS:g} Pa, softer than any "
                f"gel (read as GPa it would be {v * 1e9:.4g} Pa, as MPa {v * 1e6:.4g} Pa)"
            )
            severity = MIN_MODULUS / max(v, 1e-300)
        else:
            text = (
                f"{who}.{name} = {v:.6g} Pa is above {MAX_MODULUS:g} Pa, stiffer than any "
                f"solid (diamond: E = 1.2e12 Pa)"
            )
            severity = v / MAX_MODULUS
        limit = MIN_MODULUS if v < MIN_MODULUS else MAX_MODULUS
        out.append(_finding("modulus", name, v, limit, severity, text))
    return out


def tendon_radius(tendon, end: float) -> float:
    """A tendon's largest channel radius [m] over [0, end] (its radius is linear in s)."""
    return max(tendon.offset, tendon.offset + tendon.slope * end)


def offset_findings(robot, who: str = "Robot") -> list:
    """The ``offset`` rule: a tendon radius ``> 0.5 L`` anywhere on [0, end]."""
    L, out = robot.rod.length, []
    for i, t in enumerate(robot.tendons):
        r = tendon_radius(t, robot.tendon_end(i))
        if r > MAX_OFFSET * L:
            where = "at the base" if r == t.offset else f"at s = {robot.tendon_end(i):.4g} m"
            out.append(
                _finding(
                    "offset",
                    f"tendon {i}",
                    r / L,
                    MAX_OFFSET,
                    r / (MAX_OFFSET * L),
                    f"{who}: tendon {i}'s radius {r:.4g} m ({where}) is {r / L:.3g} L, beyond "
                    f"{MAX_OFFSET:g} L on a rod of length {L:.4g} m",
                )
            )
    return out


def input_findings(scene) -> tuple:
    """Every input rule's findings for ``scene`` (its rod, tendons and their routing;
    cached on the frozen robot)."""
    robot = scene.robot
    found = robot.__dict__.get("_plausibility")
    if found is None:
        fs = [slenderness_finding(robot.rod, "robot.rod")]
        fs += modulus_findings(robot.rod, "robot.rod")
        fs += [
            angle_finding(t.angle, f"robot.tendons[{i}].angle") for i, t in enumerate(robot.tendons)
        ]
        fs += [
            friction_finding(t.friction, f"robot.tendons[{i}].friction")
            for i, t in enumerate(robot.tendons)
        ]
        fs += offset_findings(robot, "robot")
        found = tuple(f for f in fs if f is not None)
        object.__setattr__(robot, "_plausibility", found)
    return found
