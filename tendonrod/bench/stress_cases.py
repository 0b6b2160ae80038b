"""The stress suite's cases: each a scene and options (or a load ramp), whether it is
well posed (it must converge to a verified answer) or not (it must fail honestly,
with a message naming the problem), and an independent check where one is known."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .. import analytic
from ..model import PointLoad, Robot, Scene, Tendon
from ..options import Options
from ..solver import compliance
from . import references as refs
from .common import FIG11, EI_of, rod_of, solve_quiet
from .stress_buckling import buckling_cases
from .stress_hard import ladder_cases, tensile_cases
from .stress_paths import path_cases
from .stress_plausible import plausibility_cases
from .stress_ramps import ramp_fig17, ramp_large_load

__all__ = ["StressCase", "stress_cases", "one_tendon_scene", "KAPPA_R_LIMIT", "KAPPA_R_WORDS"]


@dataclass
class StressCase:
    """One stress case. ``build()`` -> (Scene, Options). ``well_posed``: must converge
    to a verified answer; otherwise it must fail honestly (success False, a message
    containing one of ``expect_words`` if given). ``check(sol)`` -> (error, ok, note)
    compares with an independent answer where one is known."""

    name: str
    group: str
    build: Callable | None  # None for a ramp
    well_posed: bool = True
    expect_words: tuple = ()
    check: Callable | None = None
    quick: bool = False
    ramp: Callable | None = None  # custom runner (load ramps): sol-less, returns dict


def _stress_opts(**kw):
    return Options(**kw)


def one_tendon_scene(
    p, theta, alpha=math.inf, F=(0.0, 0.0, 0.0), kirchhoff=True, r=None, EI_override=None, slope=0.0
):
    """One parallel tendon at +x on robot ``p`` displaced to bend an (unloaded)
    backbone to ``theta``: q = r theta (1 + 1/alpha) (exact for a Kirchhoff rod),
    with tip force F (world)."""
    L = p["L"]
    r = p["r"] if r is None else r
    EI = EI_of(p)
    EA = math.inf if math.isinf(alpha) else alpha * EI / (r * r)
    q = r * theta * (1.0 + (0.0 if math.isinf(alpha) else 1.0 / alpha))
    robot = Robot(rod_of(p, kirchhoff=kirchhoff), [Tendon(offset=r, EA=EA, slope=slope)])
    return Scene(robot, displacement=[q], loads=[PointLoad(s=L, force=tuple(F))])


#: Scenes beyond the model's validity. For a Kirchhoff rod with one parallel tendon
#: anchored at a moment-free tip, moment balance there gives the tip curvature
#: kappa(L) = tau r / EI, so the tendon's path-length rate |w| = 1 - kappa r reaches
#: zero when the tension reaches EI / r^2 (120.6 N for the Fig. 11 robot): the tendon
#: would pass through the centre of curvature. These loads need more tension than
#: that on their loading path (measured: the continuation stalls at tau = 116-120 N),
#: so no valid equilibrium is reachable; the solver must say so.
KAPPA_R_LIMIT = {("90deg", "transverse-x"), ("90deg", "axial+z"), ("straight", "transverse-x")}
KAPPA_R_WORDS = ("curvature", "1/r", "centre of curvature", "center of curvature", "ei/r")
#: In-plane loads whose planar equilibrium buckles laterally (one negative mode; the
#: spatial solve with a 1e-3 lateral load finds a stable state 25-49 mm out of plane).
LATERAL = {
    ("90deg", "transverse-x", 10.0),
    ("straight", "transverse-x", 10.0),
    ("straight", "transverse-x", 30.0),
}


def stress_cases() -> list[StressCase]:
    """Every stress case, each dimension swept, in the order of the report."""
    return [case for group in _GROUPS for case in group()]


def _fig11():
    """The Fig. 11 robot ``p`` and its scales: L, EI, r, and the force scale EI/L^2 [N]."""
    p = FIG11
    L, EI, r = p["L"], EI_of(p), p["r"]
    fs = EI / L**2  # force scale [N]
    return p, L, EI, r, fs


def _stiffness_cases() -> list[StressCase]:
    """Tendon stiffness from 1e-2 to 1e12 and inextensible."""
    p, _, _, _, fs = _fig11()
    cases: list[StressCase] = []
    # 1. tendon stiffness r^2 k L / EI from 1e-2 to 1e12, and inextensible; bent to 90 deg,
    #    with an in-plane and an out-of-plane tip load F L^2/EI = 1.
    for a in [1e-2, 1e-1, 1.0, 1e1, 1e2, 1e3, 1e4, 1e6, 1e8, 1e10, 1e12, math.inf]:
        for lab, F in (("inplane", (-fs, 0.0, 0.0)), ("outofplane", (0.0, fs, 0.0))):
            nm = f"stiffness/alpha={a:g}/{lab}"
            cases.append(
                StressCase(
                    nm,
                    "tendon stiffness",
                    (lambda a=a, F=F: (one_tendon_scene(p, math.pi / 2, a, F), _stress_opts())),
                    quick=(a in (1e-2, 1e12, math.inf) and lab == "inplane"),
                )
            )
    return cases


def _actuation_cases() -> list[StressCase]:
    """Actuation from straight to a 270 deg curl."""
    p, L, EI, _, fs = _fig11()
    cases: list[StressCase] = []
    # 2. actuation from straight to a 270 deg curl, unloaded (exact: a circle) and loaded.
    for deg in [0, 45, 90, 180, 270]:
        th = math.radians(deg)
        for kirch in (True, False):
            nm = f"actuation/{deg}deg/{'kirchhoff' if kirch else 'cosserat'}"

            def chk(sol, th=th, kirch=kirch):
                # Kirchhoff: theta_L = q/r exactly, the shape is a circle of curvature theta/L.
                if not kirch:
                    return math.nan, True, "no closed form (backbone compression)"
                pos, _ = refs.circle_end_moment(L, EI, (0.0, max(th, 1e-300) * EI / L, 0.0))
                e = float(np.linalg.norm(sol.tip_position - pos[0]) / L)
                return e, e < 1e-6, "vs exact circle"

            cases.append(
                StressCase(
                    nm,
                    "actuation",
                    (
                        lambda th=th, kirch=kirch: (
                            one_tendon_scene(p, th, kirchhoff=kirch),
                            _stress_opts(),
                        )
                    ),
                    check=chk,
                    quick=(deg == 270 and kirch),
                )
            )
            nm = f"actuation/{deg}deg/{'kirchhoff' if kirch else 'cosserat'}/loaded-outofplane"
            cases.append(
                StressCase(
                    nm,
                    "actuation",
                    (
                        lambda th=th, kirch=kirch: (
                            one_tendon_scene(p, th, F=(0.0, fs, 0.0), kirchhoff=kirch),
                            _stress_opts(),
                        )
                    ),
                )
            )
    return cases


def _load_cases() -> list[StressCase]:
    """Loads up to F L^2/EI = 100 on the actuated and the straight robot."""
    p, L, EI, _, fs = _fig11()
    cases: list[StressCase] = []
    # 3. loads up to F L^2/EI = 100, in-plane transverse, axial (both signs), out-of-plane,
    #    on the 90 deg actuated robot and on the straight robot.
    for mag in [1.0, 10.0, 30.0, 100.0]:
        for lab, d in (
            ("transverse-x", (-1, 0, 0)),
            ("transverse+x", (1, 0, 0)),
            ("axial-z", (0, 0, -1)),
            ("axial+z", (0, 0, 1)),
            ("outofplane", (0, 1, 0)),
        ):
            F = tuple(mag * fs * c for c in d)
            for th, tl in ((math.pi / 2, "90deg"), (0.0, "straight")):
                nm = f"load/{tl}/{lab}/FL2EI={mag:g}"
                chk = None
                if tl == "straight" and lab in ("outofplane", "transverse+x"):
                    # the tendon at +x stays at its length (out of plane: on the neutral axis)
                    # or shortens (slack), so the robot is the plain elastica: exact
                    ax = 1 if lab == "outofplane" else 0

                    def chk(sol, mag=mag, ax=ax):
                        x, z, _ = refs.elastica_tip_force(L, EI, mag * fs)
                        ref = np.zeros(3)
                        ref[ax] = x
                        ref[2] = z
                        e = float(np.linalg.norm(sol.tip_position - ref) / L)
                        return e, e < 1e-6, "vs exact elastica"

                wp = True
                words: tuple[str, ...] = ()
                if (mag == 100.0 and (tl, lab) in KAPPA_R_LIMIT) or (
                    mag == 30.0 and (tl, lab) == ("90deg", "transverse-x")
                ):
                    # (the 90 deg robot under -x reaches tau = EI/r^2 at F L^2/EI ~ 26 on its path)
                    wp, words = False, KAPPA_R_WORDS
                elif (tl, lab, mag) in LATERAL:
                    # in-plane transverse loads that the taut tendon resists: the planar
                    # equilibrium is unstable out of its plane (lateral buckling; the
                    # spatial solve with a small lateral load reaches a stable, laterally
                    # buckled state): a planar solve must say so
                    wp, words = False, ("force_spatial",)
                elif mag == 100.0 and (tl, lab) == ("90deg", "transverse+x"):
                    # the tendon goes nearly slack and the bending gathers at the base until
                    # r kappa(0) = 1 at F L^2/EI = 50 (tr.path: no limit point on the way):
                    # the tendon would pass the centre of curvature at a tension far below
                    # EI/r^2; no valid loading path reaches 100.  The failure must name it.
                    wp, words = False, ("would pass the centre of curvature",)
                cases.append(
                    StressCase(
                        nm,
                        "loads",
                        (lambda th=th, F=F: (one_tendon_scene(p, th, F=F), _stress_opts())),
                        check=chk,
                        well_posed=wp,
                        expect_words=words,
                        quick=(
                            mag == 100.0 and tl == "90deg" and lab in ("transverse-x", "outofplane")
                        ),
                    )
                )
    return cases


def _plain_rod_cases() -> list[StressCase]:
    """The plain cantilever under a transverse tip force."""
    p, L, EI, _, fs = _fig11()
    cases: list[StressCase] = []
    # 3b. the plain cantilever (no tendon) under a transverse tip force: exact elastica.
    for mag in [5.0, 10.0, 12.0, 30.0, 100.0]:

        def chk_ela(sol, mag=mag):
            x, z, _ = refs.elastica_tip_force(L, EI, mag * fs)
            e = float(np.linalg.norm(sol.tip_position - np.array([x, 0.0, z])) / L)
            return e, e < 1e-6, "vs exact elastica"

        cases.append(
            StressCase(
                f"load/plain-rod/transverse/FL2EI={mag:g}",
                "loads",
                (
                    lambda mag=mag: (
                        Scene(
                            Robot(rod_of(p), []),
                            loads=[PointLoad(s=L, force=(mag * fs, 0.0, 0.0))],
                        ),
                        _stress_opts(),
                    )
                ),
                check=chk_ela,
                quick=(mag == 30.0),
            )
        )
    return cases


def _ramp_cases() -> list[StressCase]:
    """Load ramps (slack switch, large loads)."""
    cases: list[StressCase] = []
    # 5. load ramps across the taut/slack switch and back (Fig. 17 robot), warm started.
    cases.append(
        StressCase("ramp/fig17/taut-slack-taut", "slack switch", None, ramp=ramp_fig17, quick=True)
    )
    cases.append(
        StressCase(
            "ramp/fig17/taut-slack-taut/squared",
            "slack switch",
            None,
            ramp=lambda: ramp_fig17(slack_model="squared"),
        )
    )
    cases.append(
        StressCase(
            "ramp/fig17/cold-each", "slack switch", None, ramp=lambda: ramp_fig17(warm=False)
        )
    )
    # 5b. a warm-started sweep of a large transverse load on the plain rod (exact elastica)
    cases.append(
        StressCase(
            "ramp/plain-rod/FL2EI=31.6->100/warm-10%",
            "loads",
            None,
            ramp=ramp_large_load,
            quick=True,
        )
    )
    return cases


def _opposing_cases() -> list[StressCase]:
    """Opposing tendons."""
    p, _, EI, r, fs = _fig11()
    cases: list[StressCase] = []
    # 6. opposing inextensible tendons on a Kirchhoff backbone (statically indeterminate or
    #    without equilibrium) and the well-posed neighbours.
    for q, wp, words in (
        (0.0, False, ("indetermin",)),
        (1e-3, False, ("equilibrium", "indetermin")),
        (-1e-3, True, ()),
    ):
        nm = f"opposing/kirchhoff-inextensible/q1=q2={q:g}"
        cases.append(
            StressCase(
                nm,
                "opposing tendons",
                (lambda q=q: (_opposing(p, q, q), _stress_opts())),
                well_posed=wp,
                expect_words=words,
                quick=(q == 0.0),
            )
        )
    # loaded: one tendon tightens and locks the tip angle at 0, so the other keeps its
    # length exactly; the difference of the tensions is fixed, their common level is not
    cases.append(
        StressCase(
            "opposing/kirchhoff-inextensible/q1=q2=0/loaded",
            "opposing tendons",
            lambda: (_opposing(p, 0.0, 0.0, F=(fs, 0.0, 0.0)), _stress_opts()),
            well_posed=False,
            expect_words=("indetermin",),
            quick=True,
        )
    )
    cases.append(
        StressCase(
            "opposing/cosserat-inextensible/q1=q2=1mm",
            "opposing tendons",
            lambda: (_opposing(p, 1e-3, 1e-3, kirchhoff=False), _stress_opts()),
        )
    )
    cases.append(
        StressCase(
            "opposing/kirchhoff-EA-finite/q1=q2=1mm",
            "opposing tendons",
            lambda: (_opposing(p, 1e-3, 1e-3, EA=1e4 * EI / r**2), _stress_opts()),
        )
    )
    return cases


def _twist_cases() -> list[StressCase]:
    """Fig. 12's twist."""
    p, L, EI, r, _ = _fig11()
    cases: list[StressCase] = []
    # 7. Fig. 12: straight robot, three tendons at q = 0, pure twisting moment, tendon
    #    stiffness growing without bound (inextensible: no equilibrium with M != 0).
    for a in [1.0, 1e2, 1e4, 1e6, 1e8, 1e12, math.inf]:
        nm = f"fig12/twist/alpha={a:g}"
        chk12 = None
        if not math.isinf(a):

            def chk12(sol, a=a):
                rod = sol.scene.robot.rod
                EA = a * EI / r**2
                Mz = sol.scene.point_loads[0].moment[2]
                psi, T = refs.twist_with_tendons(L, rod.torsional_stiffness, EA, r, 3, Mz)
                Rt = sol.tip_rotation
                psi_sol = math.atan2(Rt[1, 0], Rt[0, 0])
                e = max(abs(psi_sol - psi) / psi, float(np.max(np.abs(sol.tension - T))) / T)
                # exact solution; 1e-6 relative is the verification threshold used throughout
                return e, e < 1e-6, "twist and tension vs the exact helix solution"

        cases.append(
            StressCase(
                nm,
                "Fig. 12 twist",
                (lambda a=a: (_fig12(p, a), _stress_opts())),
                well_posed=not math.isinf(a),
                check=chk12,
                expect_words=("equilibrium", "indetermin", "singular", "twist"),
                quick=(a in (1e12, math.inf)),
            )
        )
    return cases


def _slenderness_cases() -> list[StressCase]:
    """Slenderness L/d from 10 to 1e4."""
    p, L, _, _, _ = _fig11()
    cases: list[StressCase] = []
    # 8. slenderness L/d from 10 to 1e4 (Cosserat backbone: shear and extension matter at 10).
    for sl in [10, 30, 100, 1e3, 1e4]:
        pp = dict(p)
        pp["d"] = p["L"] / sl
        pp["r"] = max(p["r"], 0.6 * pp["d"])  # channel outside the section
        fsl = EI_of(pp) / L**2
        for lab, F in (("inplane", (-fsl, 0.0, 0.0)), ("outofplane", (0.0, fsl, 0.0))):
            nm = f"slenderness/L/d={sl:g}/{lab}"
            cases.append(
                StressCase(
                    nm,
                    "slenderness",
                    (
                        lambda pp=pp, F=F: (
                            one_tendon_scene(pp, math.pi / 2, F=F, kirchhoff=False),
                            _stress_opts(),
                        )
                    ),
                    quick=(sl in (10, 1e4) and lab == "outofplane"),
                )
            )
    return cases


def _offset_cases() -> list[StressCase]:
    """Tendon offsets from 1e-4 L to 0.3 L."""
    p, L, _, _, fs = _fig11()
    cases: list[StressCase] = []
    # 9. tendon offsets from 1e-4 L to 0.3 L (90 deg, F L^2/EI = 1 in-plane), Kirchhoff and Cosserat.
    for rr in [1e-4, 1e-3, 1e-2, 0.1, 0.3]:
        for kirch in (True, False):
            nm = f"offset/r={rr:g}L/{'kirchhoff' if kirch else 'cosserat'}"
            cases.append(
                StressCase(
                    nm,
                    "tendon offset",
                    (
                        lambda rr=rr, kirch=kirch: (
                            one_tendon_scene(
                                p, math.pi / 2, F=(-fs, 0.0, 0.0), r=rr * L, kirchhoff=kirch
                            ),
                            _stress_opts(),
                        )
                    ),
                    quick=(rr in (1e-4, 0.3) and kirch),
                )
            )
    return cases


def _tiny_cases() -> list[StressCase]:
    """Loads of 1e-6 N."""
    p, L, EI, r, _ = _fig11()
    cases: list[StressCase] = []
    # 10. loads of 1e-6 N on the straight robot (closed form known) and on the 90 deg robot.
    for lab, F in (
        ("transverse", (-1e-6, 0.0, 0.0)),
        ("outofplane", (0.0, 1e-6, 0.0)),
        ("axial", (0.0, 0.0, -1e-6)),
    ):
        nm = f"tiny/straight/{lab}/1e-6N"
        if lab == "outofplane":

            def chk(sol):
                # bending about x leaves the tendon at +x on the neutral axis (its length does
                # not change to first order), so the tip moves F L^3/(3 EI) like a plain rod
                d = 1e-6 * L**3 / (3 * EI)
                e = abs(sol.tip_position[1] - d) / d
                return e, e < 1e-6, "deflection vs F L^3/(3 EI)"
        elif lab == "axial":

            def chk(sol):
                # a compressive load far below Euler's leaves the Kirchhoff rod straight
                e = float(
                    np.hypot(sol.tip_position[0], sol.tip_position[1]) / L
                    + abs(sol.tip_position[2] - L) / L
                )
                return e, e < 1e-12, "straight under axial load"

        if lab == "transverse":

            def chk(sol):
                d = float(analytic.deflection(L, 1e-6, L, L, EI, 0.0, r, np.inf))
                e = abs(-sol.tip_position[0] - d) / d
                # F L^2/EI = 8e-7: the closed form is exact to ~1e-12 of the deflection;
                # 1e-6 allows the solver's scaled stopping test, not an unscaled one.
                return e, e < 1e-6, "deflection vs closed form eq. 12"

        cases.append(
            StressCase(
                nm,
                "tiny loads",
                (
                    lambda F=F: (
                        Scene(
                            Robot(rod_of(p), [Tendon(offset=r)]),
                            displacement=[0.0],
                            loads=[PointLoad(s=L, force=F)],
                        ),
                        _stress_opts(),
                    )
                ),
                check=chk,
                quick=(lab == "transverse"),
            )
        )
        nm = f"tiny/90deg/{lab}/1e-6N"
        cases.append(
            StressCase(
                nm,
                "tiny loads",
                (lambda F=F: (one_tendon_scene(p, math.pi / 2, F=F), _stress_opts())),
                check=_tiny_vs_unloaded(F),
            )
        )
    return cases


_GROUPS = (
    _stiffness_cases,
    _actuation_cases,
    _load_cases,
    _plain_rod_cases,
    lambda: tensile_cases(StressCase, one_tendon_scene, KAPPA_R_WORDS),
    lambda: ladder_cases(StressCase),
    _ramp_cases,
    _opposing_cases,
    _twist_cases,
    _slenderness_cases,
    _offset_cases,
    _tiny_cases,
    lambda: plausibility_cases(StressCase),
    lambda: buckling_cases(StressCase),
    lambda: path_cases(StressCase),
)


def _tiny_vs_unloaded(F):
    """A 1e-6 N load on the 90 deg robot: compare the tip displacement with the one
    the compliance predicts (dx = C F). Catches solvers that stop before a tiny load
    has moved the tip."""

    def chk(sol):
        sc0 = Scene(sol.scene.robot, displacement=sol.scene.displacement)
        s0 = solve_quiet(sc0, Options(tol=1e-13))
        C = compliance(sc0, options=Options(tol=1e-13))
        dx_pred = C[:3, :3] @ np.asarray(F)
        dx = sol.tip_position - s0.tip_position
        n = np.linalg.norm(dx_pred)
        e = float(np.linalg.norm(dx - dx_pred) / n)
        # the load is 1e-6 of EI/L^2, so the linearisation error is ~1e-6 relative;
        # 1e-3 catches a solver that leaves the tip where the unloaded robot had it.
        return e, e < 1e-3, "tip displacement vs compliance x load"

    return chk


def _opposing(p, q1, q2, F=(0.0, 0.0, 0.0), kirchhoff=True, EA=math.inf):
    L, r = p["L"], p["r"]
    robot = Robot(
        rod_of(p, kirchhoff=kirchhoff),
        [Tendon(offset=r, angle=0.0, EA=EA), Tendon(offset=r, angle=math.pi, EA=EA)],
    )
    return Scene(robot, displacement=[q1, q2], loads=[PointLoad(s=L, force=F)])


def _fig12(p, alpha, Mz_scale=0.5):
    """Paper Fig. 12: straight Kirchhoff robot, three tendons at q = 0, tip moment M_z =
    0.5 GJ/L (a half-radian twist without tendons)."""
    L, r, EI = p["L"], p["r"], EI_of(p)
    rod = rod_of(p)
    EA = math.inf if math.isinf(alpha) else alpha * EI / r**2
    tendons = [Tendon(offset=r, angle=2 * math.pi * i / 3, EA=EA) for i in range(3)]
    Mz = Mz_scale * rod.torsional_stiffness / L
    return Scene(
        Robot(rod, tendons),
        displacement=[0.0, 0.0, 0.0],
        loads=[PointLoad(s=L, moment=(0.0, 0.0, Mz))],
    )
