"""The paper's studies: the data behind each figure, computed by the library.

One function per study returns plain arrays (a dict); :mod:`tendonrod.plot`
draws them and :func:`figure_registry` pairs the two for
``python -m tendonrod figures``.  Notebooks call the same functions.  The
physics lives in :mod:`tendonrod.analytic` (closed forms) and
:func:`tendonrod.solve` / :func:`tendonrod.compliance` (Cosserat model); here
are only the paper's parameter sets, the actuation to a target tip angle, and
the loops.

Conventions used throughout
---------------------------
- Nondimensional compliance (the paper's): sigma = 12 EI delta / (F L^3),
  with delta the displacement of the loaded point in the direction of the
  force F.  From the Cosserat model, delta/F is the diagonal entry
  d^T C d of the translational block of :func:`tendonrod.compliance` for the
  unit direction d (a linearisation: "small loads", as the paper's charts).
- Nondimensional tendon stiffness alpha = r^2 k L / EI with r the base offset
  and k = EA / L the tendon's spring constant (so EA = alpha EI / r^2).
  For a converging tendon the real spring constant is EA/(c L) with
  c = sqrt(1 + a^2) -- c - 1 < 1e-2 for every design here.
- Geometry of the actuated robot (Figs. 11, 13-18): the base is clamped with
  the rod along +z (vertical), the tendon at +x pulls the tip over towards +x,
  so "actuated to 90 degrees" means the tip tangent points along +x.  The
  paper's load directions are then: *transverse* = world x (horizontal, in the
  bending plane), *axial* = world z (vertical, in the bending plane),
  *out-of-plane* = world y.
- Closed-form sign convention (as :mod:`tendonrod.analytic`): F > 0 points
  away from the tendon side; delta > 0 along F.
"""

from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

__all__ = [
    "G_ACCEL",
    "ALPHA_PAPER",
    "PROTOTYPE",
    "paper_rod_ivb",
    "paper_rod_slack",
    "tendon_EA",
    "single_tendon_robot",
    "tip_angle",
    "Actuation",
    "actuate",
    "sigma_from_compliance",
    "closed_form_sigma_vs_zeta",
    "closed_form_tip_sigma_vs_alpha",
    "prototype_curves",
    "prototype_shapes",
    "actuation_tradeoff",
    "straight_load_sweep",
    "prescribed_comparison",
    "out_of_plane_comparison",
    "torsion_paradox",
    "compliance_map",
    "tip_compliance_vs_alpha",
    "slack_study",
    "critical_slack_load",
    "design_study",
    "figure_registry",
    "fast_mode",
]

G_ACCEL = 9.81
"""Standard gravity [m/s^2], to turn the paper's 20 g / 50 g weights into forces."""
ALPHA_PAPER = 8.29e6
"""The dimensionless tendon stiffness r^2 k L / EI the paper used for Figs. 13-15."""
DIRECTIONS = {
    "transverse": np.array([1.0, 0.0, 0.0]),
    "axial": np.array([0.0, 0.0, 1.0]),
    "out-of-plane": np.array([0.0, 1.0, 0.0]),
}
"""World directions of the paper's load cases for the robot actuated in the x-z plane."""


def fast_mode(fast: bool | None = None) -> bool:
    """``fast`` if given, else the environment variable ``TENDONROD_FAST`` (1/true/yes)."""
    if fast is not None:
        return bool(fast)
    return os.environ.get("TENDONROD_FAST", "").strip().lower() in ("1", "true", "yes", "on")


# --------------------------------------------------------------------------- paper parameters
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


def paper_rod_ivb(**overrides):
    """The robot of the paper's Sec. IV-B (Figs. 11-16): Kirchhoff rod, L = 0.1 m,
    d = 1.04 mm, E = 210 GPa, G = 80 GPa."""
    import tendonrod as tr

    kw = dict(length=0.1, diameter=1.04e-3, E=210e9, G=80e9, kirchhoff=True)
    kw.update(overrides)
    return tr.Rod(**kw)


def paper_rod_slack(**overrides):
    """The robot of the paper's Figs. 17-18: Kirchhoff rod, L = 0.2 m, d = 0.8 mm,
    E = 207 GPa, G = 79.6 GPa."""
    import tendonrod as tr

    kw = dict(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    kw.update(overrides)
    return tr.Rod(**kw)


def tendon_EA(alpha: float, EI: float, r: float) -> float:
    """Tendon axial rigidity EA [N] for a dimensionless stiffness alpha = r^2 k L / EI,
    k = EA / L (np.inf stays np.inf)."""
    return math.inf if math.isinf(alpha) else alpha * EI / r**2


def single_tendon_robot(
    rod,
    routing: str = "parallel",
    offset: float = 0.01,
    alpha: float = math.inf,
    angle: float = 0.0,
):
    """A robot with one tendon at ``offset`` [m], parallel or converging to the tip,
    stiffness alpha = r^2 k L / EI (np.inf: inextensible)."""
    import tendonrod as tr

    EA = tendon_EA(alpha, rod.bending_stiffness, offset)
    if routing == "parallel":
        t = tr.Tendon(offset=offset, angle=angle, EA=EA)
    elif routing == "converging":
        t = tr.Tendon.converging(offset=offset, angle=angle, length=rod.length, EA=EA)
    else:
        raise ValueError(f"routing must be 'parallel' or 'converging', got {routing!r}")
    return tr.Robot(rod, [t])


def tip_angle(sol) -> float:
    """Tip angle [rad] in the x-z plane: the tip tangent's inclination from +z towards +x."""
    R = np.asarray(sol.tip_rotation)
    return math.atan2(R[0, 2], R[2, 2])


def sigma_from_compliance(C, direction, EI: float, L: float) -> float:
    """sigma = 12 EI/L^3 * d^T C_ff d for the unit world direction d (C: (6, 6) compliance)."""
    d = np.asarray(direction, dtype=float)
    d = d / np.linalg.norm(d)
    return 12.0 * EI / L**3 * float(d @ np.asarray(C)[:3, :3] @ d)


# --------------------------------------------------------------------------- actuation
@dataclass(frozen=True)
class Actuation:
    """A robot brought to a target tip angle by tension, and the same state with the
    actuators locked.

    tension_scene : Scene  -- every tendon tension-controlled (``tensions``)
    locked_scene  : Scene  -- every tendon displacement-controlled at ``displacements``
    solution      : Solution of ``tension_scene`` (= of ``locked_scene``, unloaded)
    tensions      : (nt,) [N];  displacements : (nt,) [m];  theta : tip angle reached [rad]
    """

    tension_scene: object
    locked_scene: object
    solution: object
    tensions: np.ndarray
    displacements: np.ndarray
    theta: float

    def with_loads(self, loads, locked: bool = True):
        """The locked (or tension-held) scene with ``loads`` applied."""
        base = self.locked_scene if locked else self.tension_scene
        return dataclasses.replace(base, loads=tuple(loads))


def actuate(
    robot,
    theta: float,
    tendon: int = 0,
    tensions: Sequence[float] | None = None,
    options=None,
    tol: float = 1e-11,
    max_iter: int = 60,
) -> Actuation:
    """Pull ``tendon`` until the unloaded tip angle (x-z plane, towards +x) is ``theta``.

    The other tendons keep ``tensions`` (default 0 N).  Solves by the secant
    method on the tendon's tension, starting from the closed form (eqs. 37-38);
    ``tol`` [rad] on the tip angle (1e-11: far below anything plotted, above the
    solver's 1e-10 scaled tolerance times a curvature of order 1).
    """
    import tendonrod as tr

    nt = robot.n_tendons
    base = np.zeros(nt) if tensions is None else np.array(tensions, dtype=float)
    if base.shape != (nt,):
        raise ValueError(f"tensions must have one entry per tendon ({nt}), got {tensions!r}")
    t = robot.tendons[tendon]
    EI, L = robot.rod.bending_stiffness, robot.rod.length
    arm = t.offset * math.cos(t.angle)
    tau0 = float(
        tr.analytic.actuation_tension_for_angle(theta, L, EI, t.slope * math.cos(t.angle), arm)
    )
    if not math.isfinite(tau0):
        raise ValueError(
            f"tendon {tendon} has no moment arm in the x-z plane; cannot reach theta={theta!r}"
        )

    def scene_for(tau):
        taus = base.copy()
        taus[tendon] += tau
        return tr.Scene(robot, tension=list(taus))

    guess = None

    def f(tau):
        nonlocal guess
        sol = tr.solve(scene_for(tau), guess=guess, options=options, strict=True)
        guess = sol
        return tip_angle(sol) - theta, sol

    x0, (f0, s0) = tau0, f(tau0)
    if abs(f0) <= tol:
        x1, f1, s1 = x0, f0, s0
    else:
        x1 = tau0 * (1.0 + 1e-3) + 1e-9
        f1, s1 = f(x1)
        for _ in range(max_iter):
            if abs(f1) <= tol:
                break
            if f1 == f0:
                raise RuntimeError(
                    f"actuate: secant stalled at tension {x1!r} N (tip angle error {f1!r} rad)"
                )
            x0, x1, f0 = x1, x1 - f1 * (x1 - x0) / (f1 - f0), f1
            f1, s1 = f(x1)
        else:
            raise RuntimeError(
                f"actuate: no tension reaching theta={theta!r} rad in {max_iter} "
                f"iterations (last error {f1!r} rad)"
            )
    sol = s1
    taus = base.copy()
    taus[tendon] += x1
    q = np.array(sol.displacement, dtype=float)
    locked = tr.Scene(robot, displacement=list(q))
    return Actuation(
        tension_scene=scene_for(x1),
        locked_scene=locked,
        solution=sol,
        tensions=taus,
        displacements=q,
        theta=tip_angle(sol),
    )


def _load_path(scene, forces, s=None, moments=None, options=None):
    """Solve ``scene`` under a point load stepping through ``forces`` (K, 3) [N] (and
    ``moments``), in one warm-started chunk (a continuation path), via tr.sweep."""
    import tendonrod as tr

    from .sweep import sweep

    L = scene.robot.rod.length
    s = L if s is None else s
    forces = np.asarray(forces, dtype=float).reshape(-1, 3)
    moments = (
        np.zeros_like(forces)
        if moments is None
        else np.asarray(moments, dtype=float).reshape(-1, 3)
    )
    base = dataclasses.replace(scene, loads=(tr.PointLoad(s=s, force=(0.0, 0.0, 0.0)),))
    res = sweep(
        base,
        {"loads[0].force": list(forces), "loads[0].moment": list(moments)},
        grid=False,
        chunksize=len(forces),
        measure=_shape_measure,
        options=options,
        progress=False,
    )
    if not res.data:
        raise RuntimeError(
            f"load path: all {len(forces)} points failed; first: {res.message.flat[0]}"
        )
    return res


def _shape_measure(scene, sol):
    """Per-point record for load paths: tip pose, tensions, slack, and the backbone."""
    from .sweep import tip_measure

    out = tip_measure(scene, sol)
    out["position"] = np.asarray(sol.position, dtype=float)
    out["tip_angle"] = np.array(tip_angle(sol))
    return out


# --------------------------------------------------------------------------- closed forms
def closed_form_sigma_vs_zeta(zeta=None, slopes=(0.0,), alpha: float = math.inf) -> dict:
    """Figs. 3 and 6: sigma(zeta) at the loaded point (eqs. 10, 29, 33).

    ``slopes`` are a L / b (0: parallel, -1: converging); ``alpha`` = b^2 k L / EI.
    Returns zeta, 'no tendon' (4 zeta^3) and one curve per slope.
    """
    import tendonrod as tr

    zeta = np.linspace(0.0, 1.0, 101) if zeta is None else np.asarray(zeta, dtype=float)
    out = {
        "zeta": zeta,
        "no tendon": 12.0 * tr.analytic.deflection(zeta, 1.0, zeta, 1.0, 1.0, 0.0, 1.0, 0.0),
    }
    for a in slopes:
        out[a] = 12.0 * tr.analytic.deflection(zeta, 1.0, zeta, 1.0, 1.0, a, 1.0, alpha)
    return out


def closed_form_tip_sigma_vs_alpha(alpha=None) -> dict:
    """Fig. 7: tip sigma against alpha = r^2 k L / EI for parallel and converging routing
    (eqs. 9-10 and 32)."""
    import tendonrod as tr

    alpha = np.logspace(-2, 4, 121) if alpha is None else np.asarray(alpha, dtype=float)
    return {
        "alpha": alpha,
        "parallel": 12.0 * tr.analytic.deflection(1.0, 1.0, 1.0, 1.0, 1.0, 0.0, 1.0, alpha),
        "converging": 12.0 * tr.analytic.deflection(1.0, 1.0, 1.0, 1.0, 1.0, -1.0, 1.0, alpha),
    }


def prototype_curves(routing: str, proto: Prototype = PROTOTYPE, n: int = 101) -> dict:
    """Figs. 20-22: the closed-form curves of the Section V experiments.

    Returns z [m] (fine grid), z_loads [m] (the 8 load points) and, for each
    weight m (20 g, 50 g; F = m g), the deflection at the loaded point with the
    tendon (eq. 8 / 27) and without it (F z^3 / 3EI, the EI calibration), and
    the tendon tension (eq. 6 / 25).  Keys: ('delta', m), ('delta_free', m),
    ('tension', m), each with a '_loads' twin at z_loads.  The measured points
    are not public, so they are not drawn.
    """
    import tendonrod as tr

    d = proto.design(routing)
    z = np.linspace(0.0, d["L"], n)
    out = {"z": z, "z_loads": proto.z_loads, "routing": routing, **d}
    for m in proto.masses:
        F = m * G_ACCEL
        for tag, zz in (("", z), ("_loads", proto.z_loads)):
            out[("delta" + tag, m)] = tr.analytic.deflection(
                zz, F, zz, d["L"], d["EI"], d["a"], d["b"], d["k"]
            )
            out[("delta_free" + tag, m)] = tr.analytic.deflection(
                zz, F, zz, d["L"], d["EI"], 0.0, d["b"], 0.0
            )
            out[("tension" + tag, m)] = tr.analytic.tension(
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
    import tendonrod as tr

    d = proto.design(routing)
    s = np.linspace(0.0, d["L"], n)
    out = {"s": s, "routing": routing, "z": proto.z_loads[-4:], "forces": tuple(forces)}
    for F in forces:
        for z in proto.z_loads[-4:]:
            out[(F, z)] = tr.analytic.planar_shape(s, F, z, d["L"], d["EI"], d["a"], d["b"], d["k"])
            out[("point", F, z)] = tr.analytic.planar_shape(
                z, F, z, d["L"], d["EI"], d["a"], d["b"], d["k"]
            )
    return out


# --------------------------------------------------------------------------- Cosserat studies
def _prototype_robot(routing: str, proto: Prototype = PROTOTYPE):
    """The Section V member as a Kirchhoff rod with the calibrated EI and tendon k
    (EA = k L; GJ is irrelevant for these planar scenes and set to EI/1.3, a
    square polymer section's ratio)."""
    import tendonrod as tr

    d = proto.design(routing)
    rod = tr.Rod(length=d["L"], EI=d["EI"], GJ=d["EI"] / 1.3, EA=1e9, GA=1e9, kirchhoff=True)
    t = tr.Tendon(offset=d["b"], slope=d["a"], EA=d["k"] * d["L"])
    return tr.Robot(rod, [t])


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
    import tendonrod as tr

    out = {"theta": theta, "load": load}
    for routing in ("parallel", "converging"):
        robot = _prototype_robot(routing, proto)
        act = actuate(robot, theta, options=options)
        d = proto.design(routing)
        rec = {
            "shape": np.asarray(act.solution.position),
            "tension": float(act.tensions[0]),
            "q_over_L": float(act.displacements[0] / d["L"]),
            "tension_closed_form": float(
                tr.analytic.actuation_tension_for_angle(theta, d["L"], d["EI"], d["a"], d["b"])
            ),
            "shape_loaded": None,
            "q_loaded": None,
        }
        # bottom panel: tip load -load e_x; find q with tip x = 0 (secant from q = 0)
        load_ = tr.PointLoad(s=d["L"], force=(-load, 0.0, 0.0))
        guess = None

        def tip_x(q):
            nonlocal guess
            sc = tr.Scene(robot, displacement=[q], loads=[load_])
            sol = tr.solve(sc, guess=guess, options=options, strict=True)
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
        except (RuntimeError, tr.ConvergenceError):
            pass
        out[routing] = rec
    return out


def straight_load_sweep(rod=None, offset: float = 0.01, loads=None, options=None) -> dict:
    """Fig. 10: tip deflection of the initially straight robot (tendon locked at q = 0,
    inextensible) under a growing transverse tip load -F e_x, Cosserat against the
    closed forms, for no tendon, parallel and converging routing.

    Returns F_nd = F L^2 / EI, and per case 'cosserat' and 'closed' tip deflection
    delta / L along the load (+ 'success').
    """
    import tendonrod as tr

    rod = paper_rod_ivb() if rod is None else rod
    EI, L = rod.bending_stiffness, rod.length
    F_nd = np.linspace(0.0, 3.0, 31) if loads is None else np.asarray(loads, dtype=float)
    F = F_nd * EI / L**2
    out = {"F_nd": F_nd}
    cases = {
        "no tendon": (tr.Robot(rod, []), 0.0, 0.0),
        "parallel": (single_tendon_robot(rod, "parallel", offset), 0.0, math.inf),
        "converging": (single_tendon_robot(rod, "converging", offset), -offset / L, math.inf),
    }
    for name, (robot, a, k) in cases.items():
        scene = tr.Scene(robot, displacement=[0.0] * robot.n_tendons)
        res = _load_path(scene, np.outer(F, [-1.0, 0.0, 0.0]), options=options)
        out[name] = {
            "cosserat": -res["tip_position"][:, 0] / L,
            "success": res.success,
            "tension": res["tension"],
            "closed": tr.analytic.deflection(L, F, L, L, EI, a, offset, k) / L,
        }
    return out


def prescribed_comparison(
    rod=None, offset: float = 0.01, theta: float = math.pi / 2, force=(-0.5, 0.0, 0.0), options=None
) -> dict:
    """Figs. 1 and 11(a, b): the same robot and load with the tendon's displacement held
    (actuator locked) or its tension held.

    theta = 0 is Fig. 1 (straight robot, q = 0: the tendon starts exactly taut and
    unstressed); theta = pi/2 with a transverse or axial force is Fig. 11(a)/(b).
    Returns 'unloaded', 'displacement held', 'tension held' backbones (N, 3) [m], their
    tensions, and the closed-form tip deflections for theta = 0 (eqs. 9 and 12).
    """
    import tendonrod as tr

    rod = paper_rod_ivb() if rod is None else rod
    robot = single_tendon_robot(rod, "parallel", offset)
    L = rod.length
    if theta == 0.0:
        unloaded = tr.solve(tr.Scene(robot, displacement=[0.0]), options=options, strict=True)
        locked = tr.Scene(robot, displacement=[0.0])
        held = tr.Scene(robot, tension=[0.0])
    else:
        act = actuate(robot, theta, options=options)
        unloaded, locked, held = act.solution, act.locked_scene, act.tension_scene
    forces = np.outer(np.linspace(0.0, 1.0, 11)[1:], force)
    out = {
        "force": np.asarray(force, dtype=float),
        "theta": theta,
        "unloaded": np.asarray(unloaded.position),
    }
    for name, sc in (("displacement held", locked), ("tension held", held)):
        res = _load_path(sc, forces, options=options)
        out[name] = res["position"][-1]
        out[name + " tension"] = float(res["tension"][-1, 0])
        out[name + " success"] = bool(res.success[-1])
    if theta == 0.0:
        EI, F = rod.bending_stiffness, -float(force[0])
        out["closed displacement held"] = float(
            tr.analytic.deflection(L, F, L, L, EI, 0.0, offset, math.inf)
        )
        out["closed tension held"] = float(tr.analytic.deflection(L, F, L, L, EI, 0.0, offset, 0.0))
    return out


def out_of_plane_comparison(
    rod=None,
    offset: float = 0.01,
    theta: float = math.pi / 2,
    force=(0.0, 0.5, 0.0),
    alphas3=(50.0, 50e3),
    options=None,
) -> dict:
    """Fig. 11(c): three equally spaced stretchable tendons, actuated to ``theta`` by the
    tendon at +x, loaded out of plane at the tip; displacement held for each
    r^2 k L / (3 EI) in ``alphas3`` and tension held.  Returns backbones (N, 3) [m]."""
    import tendonrod as tr

    rod = paper_rod_ivb() if rod is None else rod
    EI = rod.bending_stiffness
    out = {"force": np.asarray(force, dtype=float), "alphas3": tuple(alphas3)}
    forces = np.outer(np.linspace(0.0, 1.0, 11)[1:], force)
    for a3 in alphas3:
        EA = tendon_EA(3.0 * a3, EI, offset)
        robot = tr.Robot(
            rod, [tr.Tendon(offset=offset, angle=2 * math.pi * i / 3, EA=EA) for i in range(3)]
        )
        act = actuate(robot, theta, options=options)
        out["unloaded"] = np.asarray(act.solution.position)
        res = _load_path(act.locked_scene, forces, options=options)
        out[("displacement held", a3)] = res["position"][-1]
        out[("success", a3)] = bool(res.success[-1])
        out[("tension", a3)] = res["tension"][-1]
        if a3 == alphas3[0]:
            res_t = _load_path(act.tension_scene, forces, options=options)
            out["tension held"] = res_t["position"][-1]
    return out


def torsion_paradox(
    rod=None,
    offset: float = 0.01,
    alphas=(10.0, 1e2, 1e3, 1e4),
    n: int = 21,
    twist_max: float = 0.5,
    options=None,
) -> dict:
    """Fig. 12: a straight robot with three parallel tendons locked at q = 0 under a pure
    twisting moment M_z at the tip, for growing tendon stiffness alpha = r^2 k L / EI.

    The moment is stepped up to twist_max * GJ / L (the rod alone would twist
    ``twist_max`` rad).  Returns M_nd = M L / GJ and the tip twist phi [rad] per alpha
    (and 'no tendon' = M_nd, the rod alone).  The slope d phi / d M_nd at 0 is 1 for
    every alpha: the tendons' length changes are second order in the twist.
    """
    import tendonrod as tr

    rod = paper_rod_ivb() if rod is None else rod
    EI, GJ, L = rod.bending_stiffness, rod.torsional_stiffness, rod.length
    M_nd = np.linspace(0.0, twist_max, n)
    out = {"M_nd": M_nd, "no tendon": M_nd.copy(), "alphas": tuple(alphas)}
    for alpha in alphas:
        EA = tendon_EA(alpha, EI, offset)
        robot = tr.Robot(
            rod, [tr.Tendon(offset=offset, angle=2 * math.pi * i / 3, EA=EA) for i in range(3)]
        )
        scene = tr.Scene(robot, displacement=[0.0] * 3)
        M = M_nd[1:] * GJ / L
        res = _load_path(
            scene, np.zeros((len(M), 3)), moments=np.outer(M, [0.0, 0.0, 1.0]), options=options
        )
        R = res["tip_rotation"]
        phi = np.arctan2(R[:, 1, 0], R[:, 0, 0])
        out[alpha] = np.concatenate([[0.0], np.where(res.success, phi, np.nan)])
        out[("tension", alpha)] = res["tension"]
    return out


def compliance_map(
    rod=None,
    offset: float = 0.01,
    routings=("parallel", "converging"),
    theta: float = math.pi / 2,
    alpha: float = ALPHA_PAPER,
    zeta=None,
    tension_held: bool = True,
    options=None,
) -> dict:
    """Figs. 13-15: sigma(zeta) at a loaded point z = zeta L of the robot actuated to
    ``theta``, for loads in the transverse, axial and out-of-plane directions.

    sigma = 12 EI/L^3 d^T C(z) d from tr.compliance at s = z (small loads).  For each
    routing: the tendon locked ('displacement held') and, if ``tension_held``, its
    tension held.  Returns zeta and out[(routing, held, direction)] arrays.
    """
    import tendonrod as tr

    rod = paper_rod_ivb() if rod is None else rod
    EI, L = rod.bending_stiffness, rod.length
    zeta = np.linspace(0.05, 1.0, 20) if zeta is None else np.asarray(zeta, dtype=float)
    out = {"zeta": zeta, "theta": theta, "alpha": alpha}
    for routing in routings:
        robot = single_tendon_robot(rod, routing, offset, alpha)
        act = actuate(robot, theta, options=options)
        scenes = {"displacement held": act.locked_scene}
        if tension_held:
            scenes["tension held"] = act.tension_scene
        for held, sc in scenes.items():
            sig = {d: np.empty(len(zeta)) for d in DIRECTIONS}
            for j, z in enumerate(zeta):
                C = tr.compliance(sc, s=z * L, guess=act.solution, options=options)
                for dname, dvec in DIRECTIONS.items():
                    sig[dname][j] = sigma_from_compliance(C, dvec, EI, L)
            for dname in DIRECTIONS:
                out[(routing, held, dname)] = sig[dname]
    return out


class _LockedTipCompliance:
    """Sweep measure: lock the solved tension-controlled scene's actuators at
    sol.displacement and record the tip compliance (6, 6) of the locked scene."""

    def __call__(self, scene, sol):
        import tendonrod as tr

        locked = dataclasses.replace(
            scene, displacement=list(sol.displacement), tension=[None] * scene.robot.n_tendons
        )
        return {
            "compliance": tr.compliance(locked, guess=sol),
            "tension": np.asarray(sol.tension),
            "displacement": np.asarray(sol.displacement),
        }


def tip_compliance_vs_alpha(
    rod=None,
    offset: float = 0.01,
    theta: float = math.pi / 2,
    alphas=None,
    options=None,
    executor=None,
) -> dict:
    """Fig. 16: tip sigma against alpha = r^2 k L / EI (b^2 k L / EI converging) for the
    robot actuated to ``theta``, parallel and converging, three load directions.

    A tension-controlled tendon's stiffness does not change the unloaded shape, so each
    routing is actuated once (tension found by :func:`actuate`), then tr.sweep varies
    the tendon's EA and records the locked-actuator tip compliance.  Also returns the
    closed-form straight-robot curves of Fig. 7 for comparison (as the paper writes
    them; the exact straight-robot limit of the converging tendon is eq. 32 at
    alpha / c^3, c = sqrt(1 + a^2) -- see MODEL.md and tests/test_studies.py).
    """
    from .sweep import sweep

    rod = paper_rod_ivb() if rod is None else rod
    EI, L = rod.bending_stiffness, rod.length
    alphas = np.logspace(-1, 4, 21) if alphas is None else np.asarray(alphas, dtype=float)
    out = {"alpha": alphas, "theta": theta, "closed": closed_form_tip_sigma_vs_alpha(alphas)}
    for routing in ("parallel", "converging"):
        act = actuate(single_tendon_robot(rod, routing, offset, math.inf), theta, options=options)
        EAs = [tendon_EA(a, EI, offset) for a in alphas]
        res = sweep(
            act.tension_scene,
            {"robot.tendons[0].EA": EAs},
            measure=_LockedTipCompliance(),
            options=options,
            executor=executor,
            chunksize=1,
            progress=False,
        )
        C = res["compliance"]
        for dname, dvec in DIRECTIONS.items():
            out[(routing, dname)] = np.array(
                [
                    sigma_from_compliance(c, dvec, EI, L) if ok else np.nan
                    for c, ok in zip(C, res.success)
                ]
            )
        out[(routing, "failures")] = res.failures()
    return out


def slack_study(
    rod=None,
    offset: float = 0.01,
    theta: float = math.pi / 2,
    F_max: float = 1.0,
    n: int = 41,
    opposing: bool = False,
    pretension: float = 5.0,
    alpha: float = 1e5,
    options=None,
) -> dict:
    """Figs. 17 (single tendon) and 18 (``opposing``: a second tendon at -x held at
    ``pretension`` [N] before locking; finite stiffness ``alpha`` so that the opposing pair
    has a defined tension level): the robot of Figs. 17-18 actuated to ``theta``, actuators
    locked, under a vertical tip force -F e_z stepped from 0 to F_max (one continuation
    path).  Also the tension-held response.

    On ``alpha``: an opposing pair of inextensible tendons on a Kirchhoff rod has no
    defined tension level, so the pair needs a finite stiffness.  The default 1e5
    (r^2 k L / EI) is inextensible for every practical purpose (the tensions agree with
    alpha = 1e3..1e6 to 3 digits; the tip angle stays within 1.3e-3 deg of 90 at 1 N);
    the paper's 8.29e6 makes the tension level depend on path lengths to ~1e-12 relative
    and the solver then fails (measured), so it is not the default here.

    Points that did not converge are NaN in the returned arrays ("success" says which).

    Returns F [N], tension (n, nt) [N], slack (n, nt) [m], tip displacement from the
    unloaded tip (n, 3) [m], tip angle [rad], success, and the tension-held tip
    displacement and angle.
    """
    import tendonrod as tr

    rod = paper_rod_slack() if rod is None else rod
    EI = rod.bending_stiffness
    if opposing:
        EA = tendon_EA(alpha, EI, offset)
        robot = tr.Robot(
            rod,
            [
                tr.Tendon(offset=offset, angle=0.0, EA=EA),
                tr.Tendon(offset=offset, angle=math.pi, EA=EA),
            ],
        )
        act = actuate(robot, theta, tensions=[pretension, pretension], options=options)
    else:
        robot = single_tendon_robot(rod, "parallel", offset, math.inf)
        act = actuate(robot, theta, options=options)
    F = np.linspace(0.0, F_max, n)
    tip0 = np.asarray(act.solution.tip_position)
    out = {
        "F": F,
        "theta": theta,
        "opposing": opposing,
        "unloaded": np.asarray(act.solution.position),
        "tension0": act.tensions,
    }
    for key, sc in (("locked", act.locked_scene), ("held", act.tension_scene)):
        res = _load_path(sc, np.outer(F[1:], [0.0, 0.0, -1.0]), options=options)
        ok = np.concatenate([[True], res.success])

        def masked(first, rest):
            arr = np.concatenate(
                [np.asarray(first, dtype=float)[None], np.asarray(rest, dtype=float)]
            )
            arr[~ok] = np.nan
            return arr

        out[key] = {
            "tension": masked(act.tensions, res["tension"]),
            "slack": masked(np.zeros_like(act.tensions), res["slack"]),
            "tip_displacement": masked(np.zeros(3), res["tip_position"] - tip0),
            "tip_angle": masked(act.theta, res["tip_angle"]),
            "position": masked(act.solution.position, res["position"]),
            "success": ok,
        }
    # critical load: bracketed by the first converged grid point where the (first)
    # tendon's tension reaches 0, then refined to solver accuracy (not a grid value)
    tau = out["locked"]["tension"][:, 0]
    crit = np.nonzero(out["locked"]["success"] & (tau <= 0.0))[0]
    out["F_slack"] = math.nan
    if crit.size and crit[0] > 0 and out["locked"]["success"][crit[0] - 1]:
        out["F_slack"] = critical_slack_load(
            act.locked_scene,
            F[crit[0] - 1],
            F[crit[0]],
            direction=(0.0, 0.0, -1.0),
            options=options,
        )
    return out


def critical_slack_load(
    scene,
    F_lo: float,
    F_hi: float,
    direction=(0.0, 0.0, -1.0),
    tendon: int = 0,
    xtol: float = 1e-12,
    options=None,
) -> float:
    """Load magnitude [N] at which ``tendon`` of ``scene`` goes slack under a tip force
    ``F * direction`` (world frame), bracketed by ``F_lo`` (taut) and ``F_hi`` (slack).

    Bisection on the signed taut/slack indicator g(F) = tension [N] when taut and
    -slack [m] when slack: both vanish at the switch, so g changes sign exactly there
    (the solver's semismooth tension/slack variable makes g continuous).  Each solve is
    warm-started from the nearer bracket end.  Stops when the bracket is below
    ``xtol`` relative.  Raises RuntimeError when a solve fails or the bracket does not
    straddle the switch."""
    import tendonrod as tr

    L = scene.robot.rod.length
    d = np.asarray(direction, dtype=float)

    def g(F, guess):
        sc = dataclasses.replace(scene, loads=(tr.PointLoad(s=L, force=tuple(F * d)),))
        sol = tr.solve(sc, guess=guess, options=options)
        if not sol.success:
            raise RuntimeError(f"critical_slack_load: solve at F = {F!r} N failed: {sol.message}")
        tau, beta = float(sol.tension[tendon]), float(sol.slack[tendon])
        return (tau if tau > 0.0 else -beta), sol

    lo, hi = float(F_lo), float(F_hi)
    g_lo, sol_lo = g(lo, None)
    g_hi, sol_hi = g(hi, sol_lo)
    if not (g_lo > 0.0 and g_hi <= 0.0):
        raise RuntimeError(
            f"critical_slack_load: [{lo}, {hi}] N does not bracket the switch "
            f"(tension/-slack {g_lo!r} and {g_hi!r})"
        )
    while hi - lo > xtol * hi:
        mid = 0.5 * (lo + hi)
        g_mid, sol_mid = g(mid, sol_lo)
        if g_mid > 0.0:
            lo, sol_lo = mid, sol_mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def design_study(
    target_sigma: float = 1.0, rod=None, offset: float = 0.01, alphas=None, theta: float = 0.0
) -> dict:
    """Notebook 07: which routing and tendon stiffness reach a target tip stiffness?

    Closed forms (theta = 0, straight robot): tip sigma(alpha) for parallel (eq. 10) and
    converging (eq. 32) routing, the smallest alpha reaching ``target_sigma`` for each
    (parallel cannot go below sigma = 1), the tendon EA [N] that alpha means for ``rod``
    and ``offset``, and the actuation tension per radian of tip angle (eqs. 37-38).
    """
    import tendonrod as tr

    rod = paper_rod_ivb() if rod is None else rod
    EI, L = rod.bending_stiffness, rod.length
    alphas = np.logspace(-1, 5, 241) if alphas is None else np.asarray(alphas, dtype=float)
    cf = closed_form_tip_sigma_vs_alpha(alphas)
    out = {
        "alpha": alphas,
        "target": target_sigma,
        "parallel": cf["parallel"],
        "converging": cf["converging"],
    }
    for routing, a in (("parallel", 0.0), ("converging", -offset / L)):
        # sigma is decreasing in alpha: invert the closed form exactly where possible
        if routing == "parallel":
            # 4 - 3 alpha/(1+alpha) = s  ->  alpha = (4 - s)/(s - 1)
            need = (
                (4.0 - target_sigma) / (target_sigma - 1.0)
                if 1.0 < target_sigma < 4.0
                else (0.0 if target_sigma >= 4.0 else math.inf)
            )
        else:
            # 12/(3+alpha) = s  ->  alpha = 12/s - 3
            need = max(12.0 / target_sigma - 3.0, 0.0) if target_sigma > 0 else math.inf
        out[(routing, "alpha_needed")] = need
        out[(routing, "EA_needed")] = (
            tendon_EA(need, EI, offset) if math.isfinite(need) else math.inf
        )
        out[(routing, "tension_per_rad")] = float(
            tr.analytic.actuation_tension_for_angle(1.0, L, EI, a, offset)
        )
    return out


# --------------------------------------------------------------------------- figures
@dataclass(frozen=True)
class FigureEntry:
    """A figure of ``python -m tendonrod figures``: ``make(fast) -> matplotlib Figure``."""

    caption: str
    make: Callable


def figure_registry() -> dict:
    """Every figure the ``figures`` command writes, key -> :class:`FigureEntry`."""
    from . import plot as P

    return {k: FigureEntry(c, m) for k, c, m in P.paper_figures()}
