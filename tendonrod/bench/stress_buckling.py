"""The stress suite's buckling group: the Euler cantilever below and above its load,
perfect and imperfect, Kirchhoff and Cosserat; a four-tendon robot far above it; and
warm ramps of a Problem across the bifurcation.  A well-posed case must return the
stable equilibrium (checked against the exact elastica, elliptic integrals); the
four-tendon robot whose only stable states lie behind unilateral (slack) tendon
constraints must fail honestly."""

from __future__ import annotations

import math
import time

import numpy as np

from ..model import PointLoad, Robot, Rod, Scene, Tendon
from ..options import Options
from ..problem import Problem
from . import references as refs
from .common import FIG17, rod_of

# the NiTi wire of the strain rule: L = 0.25 m, d = 1.2 mm, E = 60 GPa, G = 23 GPa (P_E = 0.241 N)
WIRE = dict(L=0.25, d=1.2e-3, E=60e9, G=23e9)


def _rod(kirchhoff=True):
    return Rod(WIRE["L"], WIRE["d"], WIRE["E"], WIRE["G"], kirchhoff=kirchhoff)


def _euler(rod):
    return math.pi**2 * rod.bending_stiffness / (4 * rod.length**2)


def _column(rod, P, side=0.0):
    return Scene(Robot(rod, []), loads=[PointLoad(s=rod.length, force=(side, 0.0, -P))])


def _check_straight(sol):
    """Below the Euler load: straight, and judged stable."""
    e = float(np.hypot(*sol.tip_position[:2]) / sol.scene.robot.rod.length)
    return e, e < 1e-12 and sol.stable is True, "straight and stable below P_E"


def _tol(rod, P):
    """Tip tolerance against the Kirchhoff elastica [L]: 1e-8 (a verified solve against
    elliptic integrals), plus on a Cosserat rod 3 P (1/EA + 1/GA), the tip's shift by the
    backbone's extension and shear strains (measured 1.3e-5 to 1.7e-4 L here)."""
    return 1e-8 + (
        0.0 if rod.kirchhoff else 3 * P * (1 / rod.axial_stiffness + 1 / rod.shear_stiffness)
    )


def _check_elastica(imperfect=False):
    """Above the Euler load: the first-mode elastica (exact, elliptic integrals) in any
    vertical plane, judged stable.  An imperfect column (1 mN side force, 0.4 % of the
    load) lies within 0.01 L of it."""

    def chk(sol):
        rod = sol.scene.robot.rod
        P = -sol.scene.point_loads[0].force[2]
        x, z, _ = refs.elastica_compressive(rod.length, rod.bending_stiffness, P)
        e = float(
            math.hypot(math.hypot(*sol.tip_position[:2]) - abs(x), sol.tip_position[2] - z)
            / rod.length
        )
        lim = 1e-2 if imperfect else _tol(rod, P)
        return e, e < lim and sol.stable is True, "stable, on the elastica"

    return chk


def _ramp_across(kirchhoff=True, n=11):
    """A Problem ramped warm from 0.5 to 1.5 P_E (the perfect column): straight and
    stable below, buckled (on the elastica) and stable above; never an unstable
    success.  The crossing is a double zero of the second variation (two planes)."""
    rod = _rod(kirchhoff)
    Pe = _euler(rod)
    prob = Problem(_column(rod, 0.5 * Pe))
    t0 = time.perf_counter()
    recs, notes, errs = [], [], []
    for f in np.linspace(0.5, 1.5, n):
        sol = prob.solve(_column(rod, f * Pe), strict=False)
        recs.append(sol)
        if not sol.success or sol.stable is False:
            notes.append(f"f={f:.2f}: success {sol.success}, stable {sol.stable}")
        elif f > 1.05:
            err, good, _ = _check_elastica()(sol)
            errs.append(err)
            if not good:
                notes.append(f"f={f:.2f}: {err:.2e} L off the elastica")
        elif f < 0.95 and np.hypot(*sol.tip_position[:2]) > 1e-12:
            notes.append(f"f={f:.2f}: not straight")
    secs = time.perf_counter() - t0
    worst = max(errs, default=math.nan)
    ok = all(s.success for s in recs)
    return dict(
        converged=ok,
        verified=ok and not notes,
        iterations=int(sum(s.nit for s in recs)),
        nfev=int(sum(s.nfev for s in recs)),
        residual=float(max(s.residual_norm for s in recs)),
        jacobian_cond=math.nan,
        seconds=secs,
        balance=math.nan,
        refine=math.nan,
        check_error=worst,
        message="; ".join(notes) or f"{n} warm steps 0.5 -> 1.5 P_E; worst {worst:.2e} L",
        continuation_steps=int(sum(s.continuation_steps for s in recs)),
    )


def buckling_cases(StressCase) -> list:
    """The group's cases (``StressCase`` passed in: the suite's record type)."""
    g = "buckling"
    cases = []
    for kirchhoff in (True, False):
        model = "kirchhoff" if kirchhoff else "cosserat"
        rod = _rod(kirchhoff)
        Pe = _euler(rod)
        for f in (0.5, 0.95):
            cases.append(
                StressCase(
                    f"buckling/{model}/perfect/P={f:g}PE",
                    g,
                    (lambda rod=rod, P=f * Pe: (_column(rod, P), Options())),
                    check=_check_straight,
                )
            )
        for f in (1.05, 1.5, 3.0, 41.0):
            cases.append(
                StressCase(
                    f"buckling/{model}/perfect/P={f:g}PE",
                    g,
                    (lambda rod=rod, P=f * Pe: (_column(rod, P), Options())),
                    check=_check_elastica(),
                    quick=(f == 3.0 and kirchhoff),
                )
            )
        for P in (0.3, 3 * Pe):
            cases.append(
                StressCase(
                    f"buckling/{model}/side-1mN/P={P / Pe:.3g}PE",
                    g,
                    (lambda rod=rod, P=P: (_column(rod, P, side=1e-3), Options())),
                    check=_check_elastica(imperfect=True),
                )
            )
        cases.append(
            StressCase(
                f"buckling/{model}/warm-ramp-across-PE",
                g,
                None,
                ramp=(lambda k=kirchhoff: _ramp_across(k)),
                quick=kirchhoff,
            )
        )
    # four locked tendons at q = 0 under 10 N axial (39 P_E): its stable states lie behind
    # unilateral constraints (each tendon is slack by ~5e-7 m, taut after the slightest
    # bend); the linear test on the slack side says unstable and no continuation gets past
    # P_E: an honest failure that names the unstable modes
    four = Robot(
        rod_of(FIG17, kirchhoff=False),
        [Tendon(offset=0.01, angle=i * math.pi / 2, EA=2e4) for i in range(4)],
    )
    cases.append(
        StressCase(
            "buckling/four-tendons/10N-axial",
            g,
            (
                lambda: (
                    Scene(
                        four, displacement=[0.0] * 4, loads=[PointLoad(s=0.2, force=(0, 0, -10.0))]
                    ),
                    Options(),
                )
            ),
            well_posed=False,
            expect_words=("unstable",),
        )
    )
    return cases
