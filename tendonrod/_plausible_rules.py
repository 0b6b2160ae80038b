"""The plausibility rules of a solved state (the thresholds, :class:`Finding` and the
message texts are :mod:`tendonrod.plausibility`'s; the rules of the input are there too):
the screen that decides whether a solution's states must be read at all, and the
``tension``, ``strain``, ``curl`` and ``self-intersection`` rules on those states.
:mod:`tendonrod._plausible` applies them to solutions and batches."""

from __future__ import annotations

import math
import operator

import numpy as np

from ._segments import segment_distance as _segment_distance
from .plausibility import (
    _CROSSING_RTOL,
    _SELF_TURN,
    MAX_CURL,
    MAX_STRAIN,
    TENSION_FRACTION,
    Finding,
    _finding,
    tendon_radius,
)


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
    r / EI``, so this is the rule's ``tau >= 0.9 EI/r^2`` measured where it matters:
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
