"""The work-precision scenes of robots as built: a helical tendon, a precurved backbone
and a horizontally mounted robot under its own weight and its disks' masses.  Each
function takes the benchmark's ``WPScene`` class (no import cycle with
:mod:`tendonrod.bench.work_precision`); the references are independent
(:mod:`tendonrod.bench.references`: an exact helix, SciPy shooting)."""

from __future__ import annotations

import math

import numpy as np

from ..model import PointLoad, PointMass, Robot, Rod, Scene, Tendon
from . import references as refs
from .common import FIG11, FIG17, EI_of, rod_of

__all__ = ["asbuilt_scenes", "MOUNT_P0", "MOUNT_R"]

#: The mounted scene's base: at (0.1, 0, 0.3) m, its z axis along world +x and its x
#: axis straight down (gravity -z), so the robot sticks out horizontally.
MOUNT_P0 = (0.1, 0.0, 0.3)
MOUNT_R = ((0.0, 0.0, 1.0), (0.0, 1.0, 0.0), (-1.0, 0.0, 0.0))
#: Five spacer disks of 2 g on the Fig. 17 robot, equally spaced to its tip [kg].
DISK_MASS = 2e-3
#: Gravity [m/s^2], world frame.
G = 9.81


def _tip_scale(ref):
    return float(np.linalg.norm(ref))


def helical_scene() -> tuple[Scene, dict]:
    """A Kirchhoff rod (L = 0.2 m, EI = 0.05, GJ = 0.035 N m^2) with one helical tendon
    of 0.75 turns (offset 4 mm) pulled with 2.5 N, and a tip force (0.05, -0.08, 0) N."""
    L, EI, GJ, b, phi, turns, tau = 0.2, 0.05, 0.035, 0.004, 0.3, 0.75, 2.5
    F = (0.05, -0.08, 0.0)
    rod = Rod(L, EI=EI, GJ=GJ, kirchhoff=True)
    t = Tendon.helical(b, phi, turns=turns, length=L)
    sc = Scene(Robot(rod, [t]), tension=[tau], loads=[PointLoad(s=L, force=F)])
    args = dict(
        L=L, EI=EI, GJ=GJ, b=b, phi=phi, twist=2 * math.pi * turns / L, tip_force=F, tension=tau
    )
    return sc, args


def precurved_scene() -> tuple[Scene, tuple]:
    """The Fig. 11 backbone as a Cosserat rod precurved u* = (5, 15, 10) 1/m under the
    world tip moment c u with c = 0.3 EI (exact: a helix)."""
    p = FIG11
    L, EI = p["L"], EI_of(p)
    us = (5.0, 15.0, 10.0)
    rod = rod_of(p, kirchhoff=False, precurvature=us)
    GJ = rod.torsional_stiffness
    c = 0.3 * EI
    u, _, _ = refs.precurved_helix_end_moment(L, EI, GJ, us, c)
    sc = Scene(Robot(rod, []), loads=[PointLoad(s=L, moment=tuple(c * u))])
    return sc, (L, EI, GJ, us, c)


def mounted_scene() -> Scene:
    """The Fig. 17 steel backbone (density 7800 kg/m^3, no tendon) mounted
    horizontally (:data:`MOUNT_P0`, :data:`MOUNT_R`) under gravity, with five 2 g disks
    equally spaced to the tip: w L^3/EI = 0.07 and the disks' weight sum P L^2/EI = 0.9."""
    p = FIG17
    L = p["L"]
    rod = rod_of(p, density=7800.0)
    robot = Robot(rod, [], base_position=MOUNT_P0, base_rotation=MOUNT_R)
    disks = PointMass.disks(L * np.arange(1, 6) / 5, DISK_MASS)
    return Scene(robot, loads=disks, gravity=(0.0, 0.0, -G))


def _mounted_reference(sc):
    def f():
        rod = sc.robot.rod
        L = rod.length
        s = [ld.s for ld in sc.loads]
        P = [ld.mass * G for ld in sc.loads]
        h, v = refs.cantilever_dead_loads(L, rod.bending_stiffness, rod.mass_per_length * G, s, P)
        return np.asarray(MOUNT_P0) + np.array([h, 0.0, -v])

    return f


def asbuilt_scenes(WPScene) -> list:
    """The three scenes as ``WPScene`` objects."""
    out = []
    sc, a = helical_scene()
    out.append(
        WPScene(
            "helical",
            "helical tendon 0.75 turns, 2.5 N, tip force (SciPy)",
            sc,
            lambda a=a: refs.helical_tendon_tip(**a),
            "independent ODE",
            _tip_scale,
        )
    )
    sc, args = precurved_scene()
    out.append(
        WPScene(
            "precurved",
            "precurved u*=(5,15,10)/m, end moment (exact helix)",
            sc,
            lambda a=args: refs.precurved_helix_end_moment(*a)[1],
            "exact",
            _tip_scale,
        )
    )
    sc = mounted_scene()
    out.append(
        WPScene(
            "mounted",
            "horizontal, own weight + 5 disks of 2 g (SciPy)",
            sc,
            _mounted_reference(sc),
            "independent ODE",
            _tip_scale,
        )
    )
    return out
