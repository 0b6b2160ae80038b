"""The stress suite's hard groups: tensile axial loads up to L sqrt(T/EI) = 30 (the model
compiles them with multiple shooting by itself) and the tendon-stiffness ladder of
pretensioned tendon sets up to r^2 EA/EI = 1e12.  Each function takes the suite's
``StressCase`` class (no import cycle with stress_cases.py)."""

from __future__ import annotations

import math

import numpy as np

from ..model import PointLoad, Robot, Scene, Tendon
from ..options import Options
from . import references as refs
from .common import FIG11, EI_of, rod_of

__all__ = ["tensile_cases", "LAMBDAS"]

#: L sqrt(T/EI) of the tensile group.
LAMBDAS = (1.0, 3.0, 5.0, 7.0, 10.0, 15.0, 20.0, 25.0, 30.0)
#: the tendon tension of the 45 deg tension-controlled robot [N] (a tip moment tau r)
TAU45 = 5.0


def _fig11():
    p = FIG11
    L, EI = p["L"], EI_of(p)
    return p, L, EI, p["r"], EI / L**2


def _chk_plain(L, EI, fs, T):
    def chk(sol):
        x, z, _, _ = refs.planar_rod_bvp(L, EI, (fs, T), tol=1e-11, nodes=800)
        e = float(np.hypot(sol.tip_position[0] - x, sol.tip_position[2] - z) / L)
        # collocation to 1e-11; 1e-6 L is the suite's verification threshold
        return e, e < 1e-6, "vs collocation (solve_bvp)"

    return chk


def _chk_tendon45(L, EI, r, T):
    """A parallel tendon of tension tau stays parallel to the backbone when the robot bends
    in the tendon's plane (w = (1 - kappa r) t), so it adds the constant body-frame moment
    tau r: the planar rod under the tip force and tip moment tau r, turned to 45 deg."""

    def chk(sol):
        x, z, _, _ = refs.planar_rod_bvp(L, EI, (0.0, T), M=TAU45 * r, tol=1e-11, nodes=800)
        c = math.cos(math.pi / 4)
        ref = np.array([x * c, x * c, z])
        e = float(np.linalg.norm(sol.tip_position - ref) / L)
        # as above: collocation to 1e-11, the suite's 1e-6 L threshold
        return e, e < 1e-6, "vs collocation (solve_bvp) of the equivalent planar rod"

    return chk


def tensile_cases(StressCase, one_tendon_scene, kappa_words) -> list:
    """Tensile axial tip loads L sqrt(T/EI) up to 30: a plain rod with a transverse tip force
    EI/L^2, a tendon at 45 deg about the axis under a fixed tension, and the 45 deg
    actuated robot (displacement control), whose tendon would need more than EI/r^2 from
    L sqrt(T/EI) ~ 12 on (its curvature concentrates at the tip): an honest failure."""
    p, L, EI, r, fs = _fig11()
    cases = []
    for lam in LAMBDAS:
        T = lam**2 * fs
        cases.append(
            StressCase(
                f"tension/plain/Lsqrt(T/EI)={lam:g}",
                "tensile load",
                (
                    lambda T=T: (
                        Scene(Robot(rod_of(p), []), loads=[PointLoad(s=L, force=(fs, 0.0, T))]),
                        Options(),
                    )
                ),
                check=_chk_plain(L, EI, fs, T),
                quick=(lam in (7.0, 20.0, 30.0)),
            )
        )
        robot45 = Robot(rod_of(p), [Tendon(offset=r, angle=math.pi / 4)])
        cases.append(
            StressCase(
                f"tension/tendon45/Lsqrt(T/EI)={lam:g}",
                "tensile load",
                (
                    lambda T=T, robot45=robot45: (
                        Scene(robot45, tension=[TAU45], loads=[PointLoad(s=L, force=(0, 0, T))]),
                        Options(),
                    )
                ),
                check=_chk_tendon45(L, EI, r, T),
                quick=(lam == 30.0),
            )
        )
        cases.append(
            StressCase(
                f"tension/actuated45/Lsqrt(T/EI)={lam:g}",
                "tensile load",
                (lambda T=T: (one_tendon_scene(p, math.pi / 4, F=(0.0, 0.0, T)), Options())),
                quick=(lam == 20.0),
                well_posed=lam < 15.0,
                expect_words=kappa_words,
            )
        )
    return cases


#: r^2 k L / EI of the stiffness ladder
ALPHAS = (1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12)


def _twist_scene(alpha):
    """Fig. 12: three tendons at q = 0 on the straight Kirchhoff robot, tip twist 0.5 GJ/L."""
    p, L, EI, r, _ = _fig11()
    rod = rod_of(p)
    EA = alpha * EI / r**2
    tendons = [Tendon(offset=r, angle=2 * math.pi * i / 3, EA=EA) for i in range(3)]
    Mz = 0.5 * rod.torsional_stiffness / L
    return Scene(
        Robot(rod, tendons), displacement=[0.0] * 3, loads=[PointLoad(s=L, moment=(0, 0, Mz))]
    )


def _chk_twist(alpha):
    def chk(sol):
        p, L, EI, r, _ = _fig11()
        rod = sol.scene.robot.rod
        Mz = sol.scene.point_loads[0].moment[2]
        psi, T = refs.twist_with_tendons(L, rod.torsional_stiffness, alpha * EI / r**2, r, 3, Mz)
        Rt = sol.tip_rotation
        e = max(
            abs(math.atan2(Rt[1, 0], Rt[0, 0]) - psi) / psi,
            float(np.max(np.abs(sol.tension - T))) / T,
        )
        # exact helix solution; 1e-6 relative is the suite's verification threshold
        return e, e < 1e-6, "twist and tension vs the exact helix solution"

    return chk


def _opposing_locked(alpha, F=0.2):
    """Fig. 18's pair (paper robot of Figs. 17-18, 5 N before locking) locked at 90 deg,
    tip force -F e_z (stable below ~0.3 N)."""
    from ..paper.robots import actuate, paper_rod_slack, tendon_EA

    rod = paper_rod_slack()
    EA = tendon_EA(alpha, rod.bending_stiffness, 0.01)
    robot = Robot(
        rod, [Tendon(offset=0.01, angle=0.0, EA=EA), Tendon(offset=0.01, angle=math.pi, EA=EA)]
    )
    act = actuate(robot, math.pi / 2, tensions=[5.0, 5.0])
    sc = act.locked_scene
    return Scene(
        robot, displacement=sc.displacement, loads=[PointLoad(s=rod.length, force=(0, 0, -F))]
    )


def _chk_opposing(F=0.2):
    """While both are taut the locked pair keeps the tip angle (to (tau_1 - tau_2) L /
    (2 r EA) ~ 1e-7 rad) and adds a constant body moment (tau_1 - tau_2) r: the planar rod
    under the tip force with the tip moment that keeps 90 deg, by collocation."""

    def chk(sol):
        from scipy.optimize import brentq

        rod = sol.scene.robot.rod
        L, EI = rod.length, rod.bending_stiffness

        def th(M):
            return refs.planar_rod_bvp(L, EI, (0.0, -F), M=M, tol=1e-11, nodes=400)[2] - math.pi / 2

        M = brentq(th, 0.05 * EI * math.pi / (2 * L), 1.0 * EI * math.pi / (2 * L), xtol=1e-14)
        x, z, _, _ = refs.planar_rod_bvp(L, EI, (0.0, -F), M=M, tol=1e-11, nodes=400)
        e = max(
            float(np.hypot(sol.tip_position[0] - x, sol.tip_position[2] - z) / L),
            abs((sol.tension[0] - sol.tension[1]) * 0.01 - M) / M,
        )
        # the tip-angle drift from tendon stretch bounds the difference by ~2e-6 at
        # alpha = 1e6 (less above): 1e-5
        return e, e < 1e-5, "vs collocation of the planar rod with the moment that holds 90 deg"

    return chk


def ladder_cases(StressCase) -> list:
    """Pretensioned tendon sets from r^2 k L / EI = 1e6 to 1e12: three tendons bent to
    90 deg under a 0.5 N out-of-plane load (the work-precision scene ``stiff3``), the Fig. 12
    twist (exact), and Fig. 18's locked opposing pair under 0.2 N (collocation)."""
    from .work_precision import _three_tendon_scene

    cases = []
    for a in ALPHAS:
        cases.append(
            StressCase(
                f"ladder/stiff3/alpha={a:g}",
                "stiffness ladder",
                (lambda a=a: (_three_tendon_scene("s", "", FIG11, a, 0.5).scene, Options())),
                quick=(a == 1e12),
            )
        )
        if a not in (1e6, 1e8, 1e12):  # those are in the Fig. 12 group
            cases.append(
                StressCase(
                    f"ladder/fig12-twist/alpha={a:g}",
                    "stiffness ladder",
                    (lambda a=a: (_twist_scene(a), Options())),
                    check=_chk_twist(a),
                )
            )
        if a in (1e6, 1e8, 1e10, 1e12):
            # from 1e8 the pair's shared level is fixed by its stretch below what the
            # residual resolves (measured +-4e-5 N of 7.4 N at 1e8): an honest refusal
            cases.append(
                StressCase(
                    f"ladder/opposing-locked/alpha={a:g}",
                    "stiffness ladder",
                    (lambda a=a: (_opposing_locked(a), Options())),
                    check=_chk_opposing(),
                    well_posed=a < 1e8,
                    expect_words=("not determined in double precision", "round-off"),
                )
            )
    cases.append(
        StressCase(
            "ladder/opposing-locked/alpha=8.29e6",
            "stiffness ladder",
            (lambda: (_opposing_locked(8.29e6), Options())),
            check=_chk_opposing(),
            quick=True,
        )
    )
    return cases
