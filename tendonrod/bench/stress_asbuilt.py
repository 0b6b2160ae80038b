"""The stress suite's group of robots as built: precurved backbones up to a full curl,
helical tendons up to three turns, horizontally mounted robots under their own weight
and their disks' masses up to w L^3/EI = 100, and a stepped, precurved, mounted robot
with helical and converging tendons.  Each case is checked against an independent
answer where one is known (:mod:`tendonrod.bench.references`: the exact helix, SciPy
shooting); all are verified (balance, refinement).  :func:`asbuilt_cases` takes the
suite's ``StressCase`` class (no import cycle with stress_cases.py)."""

from __future__ import annotations

import math

import numpy as np

from ..model import PointLoad, PointMass, Robot, Rod, Scene, Tendon
from ..options import Options
from . import references as refs
from .common import FIG11, FIG17, EI_of, rod_of
from .wp_asbuilt import MOUNT_P0, MOUNT_R

__all__ = ["asbuilt_cases", "GROUP", "stepped_robot"]

GROUP = "robots as built"
G = 9.81
#: Independent checks must agree to this fraction of L: the references run at rtol
#: 1e-12 and the suite verifies to 1e-6 (BALANCE_TOL, REFINE_TOL).
CHECK_TOL = 1e-6


def _precurved(us, c_frac, kirchhoff):
    p = FIG11
    L, EI = p["L"], EI_of(p)
    rod = rod_of(p, kirchhoff=kirchhoff, precurvature=us)
    GJ = rod.torsional_stiffness
    c = c_frac * EI
    u, pt, _ = refs.precurved_helix_end_moment(L, EI, GJ, us, c)
    sc = Scene(Robot(rod, []), loads=[PointLoad(s=L, moment=tuple(c * u))])

    def chk(sol):
        e = float(np.linalg.norm(sol.tip_position - pt) / L)
        return e, e < CHECK_TOL, "vs the exact helix"

    return sc, chk


def _helical(turns, tau):
    L, EI, GJ, b, phi = 0.2, 0.05, 0.035, 0.004, 0.3
    F = (0.05, -0.08, 0.0)
    t = Tendon.helical(b, phi, turns=turns, length=L)
    sc = Scene(
        Robot(Rod(L, EI=EI, GJ=GJ, kirchhoff=True), [t]),
        tension=[tau],
        loads=[PointLoad(s=L, force=F)],
    )

    def chk(sol):
        pt = refs.helical_tendon_tip(L, EI, GJ, b, phi, 2 * math.pi * turns / L, F, tau)
        e = float(np.linalg.norm(sol.tip_position - pt) / L)
        return e, e < CHECK_TOL, "vs SciPy shooting (helical tendon)"

    return sc, chk


def _mounted(wl3, n_disks, disk_frac):
    """The Fig. 17 backbone with Kirchhoff rigidity scaled so that w L^3/EI = ``wl3``,
    mounted horizontally, with ``n_disks`` equal disks weighing ``disk_frac`` of the rod."""
    p = FIG17
    L = p["L"]
    rho = 7800.0
    base = rod_of(p, density=rho)
    w = base.mass_per_length * G
    rod = rod_of(p, density=rho, EI=w * L**3 / wl3)
    robot = Robot(rod, [], base_position=MOUNT_P0, base_rotation=MOUNT_R)
    m = disk_frac * base.mass_per_length * L / max(n_disks, 1)
    s = L * np.arange(1, n_disks + 1) / n_disks
    masses = PointMass.disks(s, m) if n_disks else ()
    sc = Scene(robot, loads=masses, gravity=(0.0, 0.0, -G))

    def chk(sol):
        h, v = refs.cantilever_dead_loads(
            L, rod.bending_stiffness, w, s, [m * G] * n_disks if n_disks else ()
        )
        pt = np.asarray(MOUNT_P0) + np.array([h, 0.0, -v])
        e = float(np.linalg.norm(sol.tip_position - pt) / L)
        return e, e < CHECK_TOL, "vs SciPy shooting (dead-load cantilever)"

    return sc, chk


def stepped_robot(q_helical=0.0, tau_converging=0.0, disk_mass=0.5e-3):
    """A stepped, precurved two-segment robot mounted horizontally under gravity: a
    straight 60 mm base section (NiTi, d = 1.2 mm) and a 90 mm distal section (d = 0.8
    mm) precurved upward (u* = (0, -8, 0) 1/m, against gravity); a helical tendon (offset
    3 mm, half a turn) displaced ``q_helical`` [m] and a converging tendon on the other
    side (3 mm at the base to the centre line at the tip) pulled with ``tau_converging``
    [N]; ten disks of ``disk_mass`` [kg] equally spaced to the tip (the design of
    notebooks/10_robot_as_built.ipynb)."""
    E, Gm, rho = 60e9, 23e9, 6450.0  # NiTi [Pa], [Pa], [kg/m^3]
    base = Rod(0.06, 1.2e-3, E, Gm, density=rho)
    tip = Rod(0.09, 0.8e-3, E, Gm, density=rho, precurvature=(0.0, -8.0, 0.0))
    rod = Rod.segmented([base, tip])
    L = rod.length
    tendons = [
        Tendon.helical(3e-3, 0.0, turns=0.5, length=L),
        Tendon.converging(offset=3e-3, angle=math.pi, length=L),
    ]
    robot = Robot(rod, tendons, base_position=MOUNT_P0, base_rotation=MOUNT_R)
    disks = PointMass.disks(L * np.arange(1, 11) / 10, disk_mass)
    return Scene(
        robot,
        displacement=[q_helical, None],
        tension=[None, tau_converging],
        loads=disks,
        gravity=(0.0, 0.0, -G),
    )


def asbuilt_cases(StressCase) -> list:
    """The group's cases, in the order of the report."""
    cases = []
    for us, cf, kirch in (
        ((5.0, 15.0, 10.0), 0.3, True),
        ((5.0, 15.0, 10.0), 0.3, False),
        ((0.0, 60.0, 0.0), 0.5, True),  # a full curl (u L = 6 rad unloaded)
        ((20.0, 40.0, 60.0), -0.5, False),  # a moment against the curvature
    ):
        name = f"asbuilt/precurved/u*={us}/c={cf}EI/{'kirchhoff' if kirch else 'cosserat'}"
        cases.append(
            StressCase(
                name,
                GROUP,
                (lambda us=us, cf=cf, k=kirch: (_precurved(us, cf, k)[0], Options())),
                check=_precurved(us, cf, kirch)[1],
            )
        )
    for turns in (0.25, 1.0, 3.0):
        for tau in (0.5, 5.0):
            cases.append(
                StressCase(
                    f"asbuilt/helical/turns={turns}/tension={tau}N",
                    GROUP,
                    (lambda tn=turns, t=tau: (_helical(tn, t)[0], Options())),
                    check=_helical(turns, tau)[1],
                )
            )
    for wl3, nd, frac in ((0.1, 5, 1.0), (3.0, 5, 1.0), (30.0, 10, 0.5), (100.0, 0, 0.0)):
        cases.append(
            StressCase(
                f"asbuilt/mounted/wL3/EI={wl3:g}/disks={nd}",
                GROUP,
                (lambda a=wl3, n=nd, f=frac: (_mounted(a, n, f)[0], Options())),
                check=_mounted(wl3, nd, frac)[1],
            )
        )
    for q, tau in ((0.0, 0.0), (1e-3, 0.0), (2e-3, 1.0), (-1e-3, 2.0)):
        cases.append(
            StressCase(
                f"asbuilt/stepped-precurved-mounted/q={q * 1e3:g}mm/tau={tau:g}N",
                GROUP,
                (lambda q=q, t=tau: (stepped_robot(q, t), Options())),
            )
        )
    return cases
