"""The 3D-printed prototypes of the paper's Section V: calibrated parameters
(:class:`Prototype`), the closed-form curves and shapes of Figs. 20-23, and the
actuation trade-off of Fig. 8 (Cosserat model)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import analytic
from ..model import PointLoad, Robot, Rod, Scene, Tendon
from ..results import ConvergenceError
from ..solver import solve
from .robots import G_ACCEL, actuate

__all__ = [
    "Prototype",
    "PROTOTYPE",
    "prototype_curves",
    "prototype_shapes",
    "actuation_tradeoff",
]


@dataclass(frozen=True)
class Prototype:
    """The 3D-printed members of the paper's Section V (calibrated values).

    EI [N m^2] and k [N/m] are the paper's least-squares calibrations; L [m]
    the member length (201 mm); r [m] the base offset; r_tip the converging
    tendon's tip offset (it ends 1.875 mm off the centre line); the loads sit
    at the 8 most distal of 10 evenly spaced guides, z = j L / 10, j = 3..10
    (the guides' "inner corners" are ignored: a 1-2 mm shift).
    """

    L: float = 0.201
    r: float = 8e-3
    r_tip: float = 1.875e-3
    EI_parallel: float = 11.2e-3
    k_parallel: float = 4.5e3
    EI_converging: float = 11.3e-3
    k_converging: float = 8.55e3
    masses: tuple = (0.020, 0.050)

    @property
    def slope_converging(self) -> float:
        """a = (r_tip - r) / L [-] of the converging member."""
        return (self.r_tip - self.r) / self.L

    @property
    def z_loads(self) -> np.ndarray:
        """The 8 load locations [m]."""
        return self.L * np.arange(3, 11) / 10.0

    def design(self, routing: str) -> dict:
        """``dict(EI, k, a, b, L)`` of the parallel or converging member."""
        if routing == "parallel":
            return dict(EI=self.EI_parallel, k=self.k_parallel, a=0.0, b=self.r, L=self.L)
        if routing == "converging":
            return dict(
                EI=self.EI_converging,
                k=self.k_converging,
                a=self.slope_converging,
                b=self.r,
                L=self.L,
            )
        raise ValueError(f"routing must be 'parallel' or 'converging', got {routing!r}")


PROTOTYPE = Prototype()


def prototype_curves(routing: str, proto: Prototype = PROTOTYPE, n: int = 101) -> dict:
    """Figs. 20-22: the closed-form curves of the Section V experiments.

    Returns z [m] (fine grid), z_loads [m] (the 8 load points) and, for each
    weight m (20 g, 50 g; F = m g), the deflection at the loaded point with the
    tendon (eq. 8 / 27) and without it (F z^3 / 3EI, the EI calibration), and
    the tendon tension (eq. 6 / 25).  Keys: ('delta', m), ('delta_free', m),
    ('tension', m), each with a '_loads' twin at z_loads.  The measured points
    are not public, so they are not drawn.
    """
    d = proto.design(routing)
    z = np.linspace(0.0, d["L"], n)
    out = {"z": z, "z_loads": proto.z_loads, "routing": routing, **d}
    for m in proto.masses:
        F = m * G_ACCEL
        for tag, zz in (("", z), ("_loads", proto.z_loads)):
            out[("delta" + tag, m)] = analytic.deflection(
                zz, F, zz, d["L"], d["EI"], d["a"], d["b"], d["k"]
            )
            out[("delta_free" + tag, m)] = analytic.deflection(
                zz, F, zz, d["L"], d["EI"], 0.0, d["b"], 0.0
            )
            out[("tension" + tag, m)] = analytic.tension(
                F, zz, d["L"], d["EI"], d["a"], d["b"], d["k"]
            )
    out["alpha"] = d["b"] ** 2 * d["k"] * d["L"] / d["EI"]
    return out


def prototype_shapes(
    routing: str, proto: Prototype = PROTOTYPE, forces=(0.2, 0.5), n: int = 61
) -> dict:
    """Fig. 23: loaded shapes (integrated closed-form tangent angle, eq. 22) for the last
    four load locations and forces 0.2 N and 0.5 N.  Keys (F, z) -> (n, 2) array of
    (axial, lateral) [m], lateral positive along F (downwards in the experiment)."""
    d = proto.design(routing)
    s = np.linspace(0.0, d["L"], n)
    out: dict[Any, Any] = {
        "s": s,
        "routing": routing,
        "z": proto.z_loads[-4:],
        "forces": tuple(forces),
    }
    for F in forces:
        for z in proto.z_loads[-4:]:
            out[(F, z)] = analytic.planar_shape(s, F, z, d["L"], d["EI"], d["a"], d["b"], d["k"])
            out[("point", F, z)] = analytic.planar_shape(
                z, F, z, d["L"], d["EI"], d["a"], d["b"], d["k"]
            )
    return out


def _prototype_robot(routing: str, proto: Prototype = PROTOTYPE):
    """The Section V member as a Kirchhoff rod with the calibrated EI and tendon k
    (EA = k L; GJ is irrelevant for these planar scenes and set to EI/1.3, a
    square polymer section's ratio)."""
    d = proto.design(routing)
    rod = Rod(length=d["L"], EI=d["EI"], GJ=d["EI"] / 1.3, EA=1e9, GA=1e9, kirchhoff=True)
    t = Tendon(offset=d["b"], slope=d["a"], EA=d["k"] * d["L"])
    return Robot(rod, [t])


def actuation_tradeoff(
    proto: Prototype = PROTOTYPE, theta: float = math.pi / 2, load: float = 0.9, options=None
) -> dict:
    """Fig. 8: parallel vs converging prototypes actuated to ``theta`` (top) and, under a
    ``load`` [N] tip load pushing away from the tendon, actuated back until the tip is on
    the base axis again (bottom).

    Returns per routing: 'shape' (N, 3) at theta, 'tension' [N] and 'q_over_L' needed,
    the closed-form tension (eqs. 37-38), and 'shape_loaded' / 'q_loaded' for the bottom
    panel (None where the root find did not converge).
    """
    out: dict[Any, Any] = {"theta": theta, "load": load}
    for routing in ("parallel", "converging"):
        robot = _prototype_robot(routing, proto)
        act = actuate(robot, theta, options=options)
        d = proto.design(routing)
        rec: dict[Any, Any] = {
            "shape": np.asarray(act.solution.position),
            "tension": float(act.tensions[0]),
            "q_over_L": float(act.displacements[0] / d["L"]),
            "tension_closed_form": float(
                analytic.actuation_tension_for_angle(theta, d["L"], d["EI"], d["a"], d["b"])
            ),
            "shape_loaded": None,
            "q_loaded": None,
        }
        # bottom panel: tip load -load e_x; find q with tip x = 0 (secant from q = 0)
        load_ = PointLoad(s=d["L"], force=(-load, 0.0, 0.0))
        guess = None

        def tip_x(q):
            nonlocal guess
            sc = Scene(robot, displacement=[q], loads=[load_])
            sol = solve(sc, guess=guess, options=options, strict=True)
            guess = sol
            return sol.tip_position[0], sol

        try:
            # the first solve (q = 0, full load, cold) leans on the solver's own continuation
            q0, q1 = 0.0, 0.25 * float(act.displacements[0])
            f0, _ = tip_x(q0)
            f1, s1 = tip_x(q1)
            for _ in range(40):
                if abs(f1) < 1e-9 * d["L"]:
                    break
                q0, q1, f0 = q1, q1 - f1 * (q1 - q0) / (f1 - f0), f1
                f1, s1 = tip_x(q1)
            if abs(f1) < 1e-9 * d["L"]:
                rec["shape_loaded"] = np.asarray(s1.position)
                rec["q_loaded"] = q1
        except (RuntimeError, ConvergenceError):
            pass
        out[routing] = rec
    return out
