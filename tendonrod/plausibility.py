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
``|m(s)|`` bounded from the loads and tensions alone (:func:`screen`), so a solve
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
import operator
import os
import sys
import warnings
from dataclasses import asdict, dataclass
from types import FrameType

import numpy as np

from ._segments import segment_distance as _segment_distance

__all__ = [
    "PlausibilityWarning",
    "Finding",
    "MAX_STRAIN",
    "MIN_SLENDERNESS",
    "MAX_OFFSET",
    "MAX_CURL",
    "MAX_ANGLE",
    "MAX_FRICTION",
    "TENSION_FRACTION",
    "section_diameter",
]

# --------------------------------------------------------------------------- thresholds
#: Backbone axial or shear strain [-] beyond which linear elasticity (and, for a
#: Kirchhoff rod, the inextensible model) is out of its range: metals yield below
#: 1 %, superelastic NiTi's plateau ends near 6-8 %; 2 % is the issue's limit.
MAX_STRAIN = 0.02
#: L/d below which a rod is too stubby for rod theory (shear, warping and the
#: section's own deformation are no longer small).
MIN_SLENDERNESS = 10.0
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
#: largest r kappa toward the tendon (see :func:`tension_findings`).
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


# --------------------------------------------------------------------------- solution rules
def load_levers(z, forces, moments, dist, L):
    """What the loads contribute to :func:`screen`, from the point loads' arc
    lengths ``z`` [m], force and moment magnitudes [N, N m] and the distributed force's
    magnitude ``dist`` [N/m] (per load: scalars, or arrays over points):
    ``(n_ext, m_int, f_int, m_max, f_max)`` with ``n_ext = sum |F| + |f| L`` [N],
    ``m_int = sum |M| z`` and ``f_int = sum |F| z^2 / 2 + |f| L^3 / 6`` [N m^2] (the
    integral of the moment bound), ``m_max = sum |M|`` and ``f_max = sum |F| z + |f| L^2 / 2``
    [N m] (its largest value)."""
    n_ext, m_int, f_int = dist * L, 0.0, dist * (L * L * L) / 6.0
    m_max, f_max = 0.0, 0.5 * dist * (L * L)
    for zk, F, M in zip(z, forces, moments):
        n_ext = n_ext + F
        m_int = m_int + M * zk
        f_int = f_int + 0.5 * F * zk * zk
        m_max = m_max + M
        f_max = f_max + F * zk
    return n_ext, m_int, f_int, m_max, f_max


def screen(levers, robot_consts) -> tuple:
    """The bounds that decide whether a solution's states must be read, as linear tests
    on its tensions (:func:`screen_clear`), from its loads (``levers``:
    :func:`load_levers`; scalars, or arrays over points) and its robot (``robot_consts``:
    :func:`robot_constants`).

    Cut the robot at s: the distal part's backbone force is balanced by the distal loads
    and the tendon tensions crossing the cut, so ``|n(s)| <= N = n_ext + sum tau`` and the
    strain ``|v - e3| <= N / min(EA, GA)``.  About p(s), a point load at z acts at most
    ``(z - s)(1 + eps)`` away (the backbone stretches by at most ``eps = N / EA_model``),
    a tendon's tension at its radius r(s), so ``|m(s)| <= m_max + f_max (1 + eps) + sum
    tau_i r_i,max`` and ``int_0^L |m| ds <= m_int + f_int (1 + eps) + sum tau_i int r_i
    ds``; and ``|kappa| <= |m| / EI``.  The states need not be read when the strain bound
    is within the strain limit, the bending bound below a half turn (less cannot bring
    the backbone back to itself, nor curl it a full turn) and no tendon's ``r kappa`` can
    reach :data:`TENSION_FRACTION`.  Each test is ``sum_i w_i tau_i < c`` (``<=`` for the
    strain), linear in the tensions: returns ``(c_strain, w_turn, c_turn, w_reach,
    c_reach)``, the strain's weights being 1.
    """
    n_ext, m_int, f_int, m_max, f_max = levers
    ea_strain, ea_model, EI, radii, areas = robot_consts
    rmax = max(radii, default=0.0)
    stretch = 1.0 + n_ext / ea_model
    w_turn, w_reach = [], []
    for a, r in zip(areas, radii):
        w_turn.append(a + f_int / ea_model)
        w_reach.append(r + f_max / ea_model)
    c_turn = _SELF_TURN * EI - m_int - f_int * stretch
    c_reach = TENSION_FRACTION * EI / rmax - m_max - f_max * stretch if rmax > 0.0 else math.inf
    return MAX_STRAIN * ea_strain - n_ext, w_turn, c_turn, w_reach, c_reach


def screen_clear(scr, tensions):
    """True (elementwise over points) where the solution with these ``tensions`` (per
    tendon: scalars, or arrays over points) needs no state read (:func:`screen`).  A NaN
    (an overflow) is never clear."""
    c_strain, w_turn, c_turn, w_reach, c_reach = scr
    turn = sum(map(operator.mul, w_turn, tensions))
    reach = sum(map(operator.mul, w_reach, tensions))
    return (sum(tensions) <= c_strain) & (turn < c_turn) & (reach < c_reach)


def rod_constants(rod) -> tuple:
    """``(EA_strain, EA_model, EI)``: the smaller of EA and GA for the strain rule (a
    Kirchhoff rod's section values; inf when unknown), the model's (inf for a Kirchhoff
    rod), and EI."""
    ea, ga = rod._effective("EA"), rod._effective("GA")
    ea = math.inf if ea is None else ea
    ga = math.inf if ga is None else ga
    model = math.inf if rod.kirchhoff else min(ea, ga)
    return min(ea, ga), model, rod.bending_stiffness


def robot_constants(robot) -> tuple:
    """``(EA_strain, EA_model, EI, radii, areas)`` of :func:`screen`: the rod's
    (:func:`rod_constants`) and per tendon its largest radius [m] and ``int_0^end r ds``
    [m^2] (the radius is linear in s and >= 0)."""
    radii, areas = [], []
    for i, t in enumerate(robot.tendons):
        e = robot.tendon_end(i)
        radii.append(tendon_radius(t, e))
        areas.append(t.offset * e + 0.5 * t.slope * e * e)
    return rod_constants(robot.rod) + (radii, areas)


def tension_findings(robot, s, m_body, tensions) -> list:
    """The ``tension`` rule on recorded states: for tendon i, ``r_i(s) kappa_i(s)``, its
    radius times the curvature that bends the backbone toward it (``kappa_i = (u2 cos phi
    - u1 sin phi)``, ``u = m_b / EI``), reaching 0.9 somewhere on [0, end]: its path is
    then within 10 % of the backbone's centre of curvature (where ``|w_i| = 1 - r kappa``
    vanishes).  A tendon alone at a moment-free tip bends the backbone to ``kappa = tau
    r / EI``, so this is the issue's ``tau >= 0.9 EI/r^2`` measured where it matters:
    tensions that other tendons balance (high antagonistic tension) do not count.
    ``s`` (N,) [m], ``m_body`` (N, 3) [N m], ``tensions`` (nt,) [N]."""
    EI = robot.rod.bending_stiffness
    u1, u2 = m_body[:, 0] / EI, m_body[:, 1] / EI
    out = []
    for i, t in enumerate(robot.tendons):
        on = s <= robot.tendon_end(i)
        rho = t.offset + t.slope * s[on]
        reach = rho * (u2[on] * math.cos(t.angle) - u1[on] * math.sin(t.angle))
        if reach.size == 0:
            continue
        k = int(np.argmax(reach))
        c, r = float(reach[k]), float(rho[k])
        if not c >= TENSION_FRACTION:
            continue
        out.append(
            _finding(
                "tension",
                f"tendon {i}",
                c,
                TENSION_FRACTION,
                c / TENSION_FRACTION,
                f"tendon {i} is {c:.3g} of the way to the backbone's centre of curvature: "
                f"r kappa = {c:.3g} at s = {s[on][k]:.4g} m (r = {r:.4g} m), the bending a lone "
                f"tendon gets from {c:.3g} EI/r^2 = {c * EI / (r * r):.4g} N (it carries "
                f"{tensions[i]:.4g} N), beyond {TENSION_FRACTION:g} EI/r^2",
            )
        )
    return out


def strain_findings(rod, s, n_body) -> list:
    """The ``strain`` rule on recorded states: ``s`` (N,) [m], ``n_body`` (N, 3) the
    internal force in the body frame [N]."""
    ea, ga = rod._effective("EA"), rod._effective("GA")
    out = []
    for subject, col, stiff in (
        ("axial", np.abs(n_body[:, 2]), ea),
        ("shear", np.hypot(n_body[:, 0], n_body[:, 1]), ga),
    ):
        if stiff is None or not math.isfinite(stiff):
            continue
        eps = col / stiff
        k = int(np.argmax(eps))
        e = float(eps[k])
        if e > MAX_STRAIN:
            kind = " (the strain the Kirchhoff model neglects)" if rod.kirchhoff else ""
            out.append(
                _finding(
                    "strain",
                    subject,
                    e,
                    MAX_STRAIN,
                    e / MAX_STRAIN,
                    f"backbone {subject} strain {100 * e:.3g} %{kind} at s = {s[k]:.4g} m "
                    f"(force {col[k]:.4g} N, {'EA' if subject == 'axial' else 'GA'} = {stiff:.4g} N) "
                    f"is beyond {100 * MAX_STRAIN:g} %",
                )
            )
    return out


def turning(s, m_body, EI: float) -> np.ndarray:
    """Cumulative bending angle ``int_0^s |kappa| ds`` [rad] at the nodes ``s`` (N,), from
    the body-frame moment ``m_body`` (N, 3) [N m] (trapezoidal rule; repeated nodes at a
    jump add nothing)."""
    kappa = np.hypot(m_body[:, 0], m_body[:, 1]) / EI
    return np.concatenate([[0.0], np.cumsum(0.5 * (kappa[1:] + kappa[:-1]) * np.diff(s))])


def curl_finding(T) -> Finding | None:
    """The ``curl`` rule on the cumulative bending angle ``T`` (N,) [rad]."""
    total = float(T[-1])
    if not total > MAX_CURL:
        return None
    return _finding(
        "curl",
        "",
        total,
        MAX_CURL,
        total / MAX_CURL,
        f"the backbone's total bending angle is {math.degrees(total):.4g} deg ({total:.4g} rad), "
        f"beyond {math.degrees(MAX_CURL):g} deg",
    )


def self_intersection_finding(s, position, T, thickness: float | None, L: float) -> Finding | None:
    """The ``self-intersection`` rule on recorded states: nodes ``s`` (N,) [m],
    ``position`` (N, 3) [m] and cumulative bending angle ``T`` (N,) [rad]: two segments
    of the polyline between which the backbone turned by >= 180 deg, closer than the
    diameter ``thickness`` (None: unknown, the centre line crossing itself)."""
    if not T[-1] >= _SELF_TURN:
        return None
    keep = np.concatenate([[True], np.diff(s) > 0.0])  # drop the repeated nodes at jumps
    s, P, T = s[keep], position[keep], T[keep]
    limit = thickness if thickness is not None else _CROSSING_RTOL * L
    # segments a < b far apart along the backbone: T[b] - T[a + 1] >= pi (T does not
    # decrease, so this leaves out b <= a + 1, and only the rows a with T[a + 1] <=
    # T[-2] - pi and the columns b with T[b] >= T[1] + pi can hold such pairs: that block,
    # taken a little wider than round-off could make it, and the exact test inside)
    tiny = 1e-12 * (1.0 + float(T[-1]))
    a1 = int(np.searchsorted(T[1:-1], T[-2] - _SELF_TURN + tiny, side="right"))
    b0 = int(np.searchsorted(T[:-1], T[1] + _SELF_TURN - tiny, side="left"))
    far = T[None, b0:-1] - T[1 : a1 + 1, None] >= _SELF_TURN
    # segments whose midpoints are farther apart than limit + both half lengths cannot be
    # closer than limit: the exact distance only for the others (squared distances by the
    # Gram matrix; the margin covers its round-off, so no candidate is lost)
    mid, half = 0.5 * (P[1:] + P[:-1]), 0.5 * np.linalg.norm(P[1:] - P[:-1], axis=1)
    ma, mb, ha, hb = mid[:a1], mid[b0:], half[:a1], half[b0:]
    gap2 = (
        np.einsum("ij,ij->i", ma, ma)[:, None]
        + np.einsum("ij,ij->i", mb, mb)[None, :]
        - 2.0 * (ma @ mb.T)
    )
    reach = limit + ha[:, None] + hb[None, :]
    ia, ib = np.nonzero(far & (gap2 < reach * reach + 1e-12 * (L * L)))
    ib = ib + b0
    if ia.size == 0:
        return None
    dist = _segment_distance(P[ia], P[ia + 1], P[ib], P[ib + 1])
    k = int(np.argmin(dist))
    if not dist[k] < limit:
        return None
    what = (
        f"the diameter {limit:.4g} m"
        if thickness is not None
        else "zero (its diameter is not known)"
    )
    return _finding(
        "self-intersection",
        "",
        dist[k],
        limit,
        limit / max(float(dist[k]), 1e-300 * limit),
        f"the backbone passes through itself: near s = {s[ia[k]]:.4g} m and s = {s[ib[k]]:.4g} m "
        f"its centre lines are {dist[k]:.3g} m apart, less than {what}",
    )
