"""The rod/tendon dynamics in time: :func:`simulate` and its result :class:`Trajectory`.

Each implicit time step (BDF-alpha: BDF2, ``alpha=0``, by default; the trapezoidal rule
with ``alpha=-0.5``) is a boundary-value problem in the arc length s, solved by the shooting core
warm from the step before; the C side is ``csrc/tr_dyn.c`` (the time steps) and
``csrc/tr_dyn_rhs.c`` (the inertia, damping and drag in the spatial right-hand side).
The design, its scope and its accuracy are in ``docs/guide/dynamics.md``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from . import _core
from ._dynstart import held_values, paired, start_inputs, start_solution, statics_options
from ._fields import _int_option, _option_dict
from .compiled import _compile, pack_scene
from .loads import PointLoad, PointMass
from .mounting import base_pose, points_out, rotations_out
from .results import report_failure

__all__ = ["simulate", "Trajectory", "simulation_options"]

_FORMAT = "tendonrod.Trajectory 1"
# the core's per-step outputs whose last row a resumed run starts from
_ROW = ("tip", "tension", "slack", "energy", "residual", "iters")
_ARRAYS = (
    "t",
    "tip_position",
    "tip_rotation",
    "tension",
    "slack",
    "energy",
    "residual",
    "iterations",
    "time_error",
)
# the keys of ``options``: RK4 steps over the rod, BDF-alpha, Newton iterations per step
# before a fresh Jacobian, air drag, record the backbone, estimate the time error,
# extrapolate in dt, shooting segments per step (None: from the step's growth)
_DEFAULTS: dict[str, Any] = {
    "steps": 40,
    "alpha": 0.0,
    "max_iter": 8,
    "drag": 0.0,
    "backbone": False,
    "estimate": False,
    "extrapolate": False,
    "segments": None,
}


@dataclass(frozen=True, eq=False)
class Trajectory:
    """The motion computed by :func:`simulate`; row ``i`` is the time ``t[i]``.

    Attributes
    ----------
    t : ndarray (n,)
        Times [s], ``t[0] = 0`` the initial state.
    tip_position : ndarray (n, 3)
        Tip position, world frame [m].
    tip_rotation : ndarray (n, 3, 3)
        Tip rotation (body to world).
    tension, slack : ndarray (n, ntendon)
        Tendon tensions [N] and slacks [m] (slack: displacement-held tendons only).
    energy : ndarray (n, 6)
        Kinetic, elastic (rod strain), potential of the distributed loads (gravity),
        dissipated energy since the start, the displacement-held tendons' strain energy
        (``tau^2 rest / (2 EA)``) and their motors' work since the start (the trapezoidal
        sum of ``tau dq``) [J]: kinetic + strain + potential + dissipated + tendon strain
        - work is constant to the scheme's accuracy.  Not in it: the work of point loads
        and of tension-held tendons (their path lengths are not integrated).
    residual : ndarray (n,)
        Each step's scaled shooting residual (max-norm).
    iterations : ndarray (n,)
        Newton iterations of each step.
    time_error : ndarray (n,) or None
        With ``options={"estimate": True}``: the tip position's error estimate [m] from a
        second run at dt/2 (Richardson, second order: ``4/3 |x_dt - x_dt/2|``); with
        ``options={"extrapolate": True}`` the error estimate [m] of the extrapolated tip
        (:func:`simulate`); else None.
    backbone : ndarray (n, nb, 3) or None
        Centre-line positions at the grid's nodes [m] (``options={"backbone": True}``).
    s : ndarray (nb,) or None
        Their arc lengths [m]: the starts of the RK4 steps of each segment between
        breakpoints (point loads, tendon ends), and L; the steps are unequal where the
        breakpoints are uneven.
    segments : int
        Shooting segments of the run's steps (-1: not known, a file of an older version):
        with ``segments`` not fixed in ``options``, a run whose step fails is redone from
        the start with twice the segments while the growth allows (``tr_dyn_retry_segments``,
        ``csrc/tr_dyn.h``); the message then lists the counts tried.
    final : dict or None
        The last step's state (time history on the grid, unknowns): ``initial=`` of a
        next :func:`simulate` goes on from it.  Not saved by :meth:`save`.
    success, status, message, nit, nfev
        As every result; a failed step leaves ``success=False``, the message naming its
        time and why, and the trajectory up to the last good step.

    Examples
    --------
    A rod at rest stays at rest: ten steps, nothing moves, no energy changes.

    >>> rod = tr.Rod(0.2, 2e-3, 207e9, 79.6e9, density=7800.0)
    >>> traj = tr.simulate(tr.Scene(tr.Robot(rod, [])), 1e-3, 1e-4)
    >>> traj.t.shape, traj.energy.shape, float(np.abs(traj.tip_position[:, :2]).max())
    ((11,), (11, 6), 0.0)
    """

    t: NDArray[np.float64]
    tip_position: NDArray[np.float64]
    tip_rotation: NDArray[np.float64]
    tension: NDArray[np.float64]
    slack: NDArray[np.float64]
    energy: NDArray[np.float64]
    residual: NDArray[np.float64]
    iterations: NDArray[np.int64]
    time_error: NDArray[np.float64] | None = None
    backbone: NDArray[np.float64] | None = None
    s: NDArray[np.float64] | None = None
    success: bool = False
    status: int = 0
    message: str = ""
    nit: int = -1
    nfev: int = -1
    segments: int = -1
    final: Any = field(default=None, repr=False)

    def save(self, path) -> None:
        """Write the trajectory to ``path`` (``.npz``); read back with :meth:`load`."""
        arrays = {k: getattr(self, k) for k in _ARRAYS if getattr(self, k) is not None}
        if self.backbone is not None:
            arrays["backbone"], arrays["s"] = self.backbone, self.s
        meta = np.array(
            [self.success, self.status, self.nit, self.nfev, self.segments], dtype=np.int64
        )
        np.savez(
            path, format=np.array(_FORMAT), meta=meta, message=np.array(self.message), **arrays
        )

    @classmethod
    def load(cls, path) -> Trajectory:
        """The trajectory written by :meth:`save` (:func:`tendonrod.load` reads it too).
        ValueError naming the file for a file of another kind or a malformed one."""
        from ._io import _CONTENT_ERRORS, _PATH_ERRORS

        try:
            with open(path, "rb") as fh, np.load(fh, allow_pickle=False) as f:
                if "format" not in f or str(f["format"]) != _FORMAT:
                    raise ValueError(
                        f"Trajectory.load: {str(path)!r} is not a file written by "
                        f"Trajectory.save (format {_FORMAT!r})"
                    )
                kw: dict[str, Any] = {
                    k: (f[k] if k in f else None) for k in (*_ARRAYS, "backbone", "s")
                }
                meta = f["meta"]
                return cls(
                    **kw,
                    success=bool(meta[0]),
                    status=int(meta[1]),
                    message=str(f["message"]),
                    nit=int(meta[2]),
                    nfev=int(meta[3]),
                    segments=int(meta[4]) if len(meta) > 4 else -1,
                )
        except _PATH_ERRORS:
            raise
        except _CONTENT_ERRORS as e:
            if isinstance(e, ValueError) and str(e).startswith("Trajectory.load:"):
                raise
            raise ValueError(
                f"Trajectory.load: {str(path)!r} is not a valid Trajectory file: "
                f"{type(e).__name__}: {e}"
            ) from None

    def __repr__(self) -> str:
        return (
            f"Trajectory(n={len(self.t)}, t_end={self.t[-1]:.6g} s, success={self.success}, "
            f"message={self.message!r})"
        )


def _options(options) -> dict:
    opt = _option_dict("simulate", options, _DEFAULTS)
    _int_option("simulate", opt, "steps", 2, 100000)
    a = opt["alpha"]
    if not (isinstance(a, (int, float)) and -0.5 <= a <= 0.0):
        raise ValueError(f"simulate: options['alpha'] must be in [-0.5, 0], got {a!r}")
    if not (
        isinstance(opt["drag"], (int, float)) and opt["drag"] >= 0 and math.isfinite(opt["drag"])
    ):
        raise ValueError(f"simulate: options['drag'] must be finite and >= 0, got {opt['drag']!r}")
    _int_option("simulate", opt, "max_iter", 1, 100)
    if opt["segments"] is not None:
        _int_option("simulate", opt, "segments", 1, 64)
    if opt["extrapolate"] and (opt["estimate"] or opt["backbone"]):
        raise ValueError(
            "simulate: options['extrapolate'] brings its own error estimate and no backbone: "
            "give it without 'estimate' and 'backbone'"
        )
    return opt


def _values(scene, actuation, times) -> np.ndarray:
    nt = scene.robot.n_tendons
    if actuation is None:
        return np.tile(held_values(scene).reshape(1, nt), (len(times), 1))
    if not callable(actuation):
        raise TypeError(
            f"simulate: actuation must be a callable actuation(t) or None, got {actuation!r}"
        )
    out = np.empty((len(times), nt))
    for i, t in enumerate(times):
        v = np.asarray(actuation(float(t)), dtype=float).reshape(-1)
        if v.shape != (nt,) or not np.all(np.isfinite(v)):
            raise ValueError(
                f"simulate: actuation({t!r}) must give {nt} finite values "
                f"(displacement [m] or tension [N] per tendon), got {v!r}"
            )
        out[i] = v
    return out


def _loads(scene, loads, times, extra=()):
    """The point loads per time (len(times), nl, 6) of ``loads(t)`` (None: None), with the
    zero loads ``extra`` after the scene's (:func:`paired`)."""
    if loads is None:
        return None
    if not callable(loads):
        raise TypeError(f"simulate: loads must be a callable loads(t) or None, got {loads!r}")
    base = [ld for ld in scene.loads if isinstance(ld, PointLoad)]
    rows = []
    for t in times:
        got = list(loads(float(t)))
        ok = len(got) == len(base) and all(
            isinstance(g, PointLoad) and g.s == b.s for g, b in zip(got, base)
        )
        if not ok:
            raise ValueError(
                f"simulate: loads({t!r}) must be {len(base)} PointLoads at the "
                f"scene's positions {[b.s for b in base]}, got {got!r}"
            )
        sc = replace(
            scene,
            loads=(*got, *extra, *(ld for ld in scene.loads if not isinstance(ld, PointLoad))),
        )
        rows.append(pack_scene(sc)[2][:, 1:7])
    return np.array(rows, dtype=float)


def _run(scene, sol, duration, dt, actuation, loads, opt, t0=0.0, resume=None) -> dict:
    """The core's run of ``scene`` from ``sol`` (on the grid, of the start's scene): row 0
    of the values the start's (unless resumed), the run's from the first step on."""
    n = int(round(duration / dt))
    times = t0 + dt * np.arange(n + 1)
    rod = scene.robot.rod
    d = rod.diameter
    rI = rod.density * math.pi * d**4 / 64.0
    run, start, extra = paired(scene, sol.scene)
    values = _values(scene, actuation, times)
    ld = _loads(scene, loads, times, extra)
    dist0 = None
    if resume is None:
        values[0], load0, dist0 = start_inputs(run, start)
        if load0 is not None:
            if ld is None:
                ld = np.tile(pack_scene(run)[2][:, 1:7], (len(times), 1, 1))
            ld[0] = load0
    return _core.simulate(
        _compile(run, sol.options),
        sol.unknowns,
        values,
        ld,
        dt,
        alpha=float(opt["alpha"]),
        rho_a=rod.mass_per_length,
        rho_j=np.array([rI, rI, 2.0 * rI]),
        eta=float(rod.damping or 0.0),
        drag=float(opt["drag"]),
        max_iter=int(opt["max_iter"]),
        backbone=bool(opt["backbone"]),
        resume=resume,
        dist0=dist0,
    )


def _retried(scene, given, duration, dt, actuation, loads, opt, strict):
    """``(start, raw)``: the run at dt from ``given`` (a Solution or None: the scene's
    equilibrium), redone from the start with the segments ``tr_dyn_retry_segments`` gives
    while a step fails and ``segments`` is not fixed; ``raw["segments"]`` the last count,
    the message the counts tried (when redone)."""
    sol = start_solution(scene, given, dt, opt, strict)
    raw = _run(scene, sol, duration, dt, actuation, loads, opt)
    tried = []
    while opt["segments"] is None and raw["status"] != 0:
        seg = sol.options.shooting_segments
        nxt = _core.dyn_segments(
            _compile(scene, sol.options),
            scene.robot.rod.mass_per_length,
            float(dt),
            float(opt["alpha"]),
            failed=int(raw["status"]),
        )[0]
        tried.append(f"{seg} (step {raw['done'] + 1} failed)")
        if not nxt:
            break
        sol = start_solution(scene, given, dt, {**opt, "segments": nxt}, strict)
        work = raw["nit"], raw["nfev"]
        raw = _run(scene, sol, duration, dt, actuation, loads, opt)
        raw["nit"], raw["nfev"] = raw["nit"] + work[0], raw["nfev"] + work[1]
    raw["segments"] = sol.options.shooting_segments
    if len(tried) > 1 or (tried and raw["status"] == 0):  # redone at least once
        last = "" if raw["status"] != 0 else f", {raw['segments']}"
        raw["message"] += f"; shooting segments tried: {', '.join(tried)}{last}"
    return sol, raw


def _extrapolated(scene, initial, duration, dt, actuation, loads, opt, strict, raw):
    """Richardson in dt: the runs at dt, dt/2 and dt/4 give two second-order extrapolations
    R(dt, dt/2), R(dt/2, dt/4) at the times of dt; the rows are the second, the error
    estimate of its tip position is |R(dt, dt/2) - R(dt/2, dt/4)| / 3 (the extrapolation's
    error taken as falling by 4 per halving: the actuation's corners leave a second-order
    part, docs/validation/dynamics.md).  A failed run ends it: its rows and message."""
    runs = [raw]
    for f in (2, 4):
        if runs[-1]["status"] != 0:
            break
        runs.append(_retried(scene, initial, duration, dt / f, actuation, loads, opt, strict)[1])
    out = dict(runs[-1])
    out["nit"] = sum(r["nit"] for r in runs)
    out["nfev"] = sum(r["nfev"] for r in runs)
    if out["status"] != 0:
        return out, None
    out = dict(raw, nit=out["nit"], nfev=out["nfev"])
    a, b, c = raw, runs[1], runs[2]
    for key in ("tip", "tension", "slack", "energy"):
        rb, rc = b[key][::2], c[key][::4]
        out[key] = (4.0 * rc - rb) / 3.0
        if key == "tip":
            r1 = (4.0 * rb - a[key]) / 3.0
            err = np.linalg.norm(r1[:, :3] - out[key][:, :3], axis=1) / 3.0
    # the extrapolated rotations back onto SO(3): the nearest rotation (polar factor)
    u, _, vt = np.linalg.svd(out["tip"][:, 3:].reshape(-1, 3, 3))
    out["tip"][:, 3:] = (u @ vt).reshape(-1, 9)
    return out, err


def _resumed(initial, dt, opt):
    """The previous run's final state (Trajectory.final) checked against this run."""
    fin = initial.final
    if fin is None or not initial.success:
        raise ValueError(
            "simulate: initial is a Trajectory without a final state to go on from "
            f"(success={initial.success}, loaded from a file: the state is not saved)"
        )
    seg = fin["solution"].options.shooting_segments
    if opt["segments"] is not None and opt["segments"] != seg:
        raise ValueError(
            f"simulate: a run goes on with its shooting segments: segments={seg!r}, "
            f"got {opt['segments']!r}"
        )
    if abs(fin["dt"] - dt) > 1e-12 * dt or fin["steps"] != int(opt["steps"]):
        raise ValueError(
            f"simulate: a run goes on with its dt and grid: dt={fin['dt']!r} s and "
            f"steps={fin['steps']!r}, got dt={dt!r}, steps={opt['steps']!r}"
        )
    if opt["estimate"] or opt["extrapolate"]:
        raise ValueError(
            "simulate: options['estimate'] and ['extrapolate'] need a start at rest, "
            "not a resumed run"
        )
    return fin


def simulate(
    scene, duration, dt, *, actuation=None, loads=None, initial=None, options=None, strict=False
) -> Trajectory:
    """The robot's motion over ``duration`` [s] in implicit steps of ``dt`` [s].

    Parameters
    ----------
    scene : Scene
        The robot, its actuation and loads; ``Rod(density=, diameter=)`` gives the mass
        (rotary inertia of the round section), ``Rod(damping=eta)`` the Kelvin-Voigt
        retardation time [s] on every strain rate, ``Scene(gravity=)`` the weight.
    duration, dt : float
        Simulated time and time step [s] (``round(duration / dt)`` steps).
    actuation : callable or None
        ``actuation(t)`` -> per tendon its displacement [m] or tension [N] (its control
        kind in the scene) at time t; None: the scene's constant values.
    loads : callable or None
        ``loads(t)`` -> the scene's point loads at t (PointLoads at the same positions);
        None: the scene's.
    initial : Solution, Trajectory or None
        The static state the motion starts from, at rest (None: the scene's equilibrium).
        It must be a solution on the dynamics' grid (spatial, ``integrator="rk4"``,
        ``steps=options["steps"]``), else it is solved again there, in its own scene.
        The run starts from its pose, under its own scene's actuation values, point
        loads and gravity; the run's act from the first step on (a rod released into
        gravity, a load suddenly removed).  A solution of another structure (rod,
        tendons, mounting, control kinds, partial distributed loads) is refused
        (ValueError).  A :class:`Trajectory` (of a scene of the same structure, the same dt and
        ``steps``): the motion goes on from its last step, its times continuing.
    options : dict, optional
        ``steps`` (40): RK4 steps over the rod; ``alpha`` (0): BDF-alpha, 0 BDF2 (the
        default, as Till et al.: damps the fast axial and shear modes a kink of the
        actuation excites), -0.5 the trapezoidal rule (no numerical damping: the energy
        of an undamped smooth motion); ``max_iter`` (8); ``drag`` (0):
        air drag per body-frame velocity component [N s^2/m^3]; ``backbone`` (False);
        ``estimate`` (False): a second run at dt/2 for the time error;
        ``extrapolate`` (False): runs at dt, dt/2 and dt/4, the rows (tip, tensions,
        slacks, energies at the times of dt) Richardson-extrapolated from the last two,
        ``time_error`` the tip's error estimate from the first two's extrapolation (the
        converged motion at a fraction of the cost of a fine dt; ``residual`` and
        ``iterations`` are the dt run's, ``nit`` and ``nfev`` the three runs'; no
        ``final`` state, no backbone); ``segments`` (None): shooting segments of each
        step's boundary-value problem, None to choose them from the step's growth
        (short steps make the inertia a stiff foundation for the bending: single shooting
        fails below dt ~ 2 ms on Till's robot; a large swing can need them sooner than
        the growth says: a run whose step fails is then redone with twice the segments,
        ``Trajectory.segments``; a given count is kept, its failure reported).
    strict : bool
        Raise :class:`~tendonrod.ConvergenceError` instead of warning on failure.

    Notes
    -----
    Cosserat rods, spatial formulation, single or multiple shooting.  Refused (ValueError): Kirchhoff
    rods, channel friction, point masses (their inertia at a breakpoint is not modelled
    yet).  With damping, the tendon's direction at its anchor is taken from the elastic
    part of the internal force (docs/guide/dynamics.md).

    Examples
    --------
    A cantilever released from a small tip load rings at its first frequency:

    >>> rod = tr.Rod(0.2, 2e-3, 207e9, 79.6e9, density=7800.0)
    >>> held = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(0.2, (1e-3, 0, 0))])
    >>> start = tr.solve(held, options=tr.simulation_options())
    >>> traj = tr.simulate(tr.Scene(tr.Robot(rod, [])), 0.01, 2e-4, initial=start)
    >>> traj.success, traj.tip_position.shape
    (True, (51, 3))
    """
    from .model import Scene
    from .solution import Solution

    if not isinstance(scene, Scene):
        raise TypeError(f"simulate: scene must be a Scene, got {type(scene).__name__}")
    for name, x in (("duration", duration), ("dt", dt)):
        if not (isinstance(x, (int, float)) and math.isfinite(x) and x > 0):
            raise ValueError(f"simulate: {name} must be finite and > 0 [s], got {x!r}")
    if not 1 <= round(duration / dt) <= 10_000_000:
        raise ValueError(f"simulate: duration / dt = {duration / dt!r} steps out of [1, 1e7]")
    opt = _options(options)
    duration = round(duration / dt) * dt  # whole steps (the dt/2 run: twice as many)
    rod = scene.robot.rod
    if rod.kirchhoff:
        raise ValueError(
            "simulate: Kirchhoff rods are not supported by the dynamics yet "
            "(give a Cosserat rod: Rod(..., kirchhoff=False))"
        )
    if rod.density is None or rod.diameter is None or not rod.mass_per_length > 0:
        raise ValueError(
            f"simulate: the rod needs a mass: Rod(density=..., diameter=...) "
            f"(density={rod.density!r}, diameter={rod.diameter!r})"
        )
    if any(t.friction > 0.0 for t in scene.robot.tendons):
        raise ValueError("simulate: channel friction is not supported by the dynamics")
    if any(isinstance(ld, PointMass) for ld in scene.loads):
        raise ValueError(
            "simulate: point masses (PointMass) are not supported by the "
            "dynamics yet: spread their mass into Rod(density=...)"
        )
    fin = None
    if isinstance(initial, Trajectory):
        fin = _resumed(initial, dt, opt)
        initial = fin["solution"]
    elif initial is not None and not isinstance(initial, Solution):
        raise TypeError(
            f"simulate: initial must be a Solution, a Trajectory or None, got {initial!r}"
        )
    t0 = 0.0 if fin is None else fin["t"]
    if fin is None:
        initial, raw = _retried(scene, initial, duration, dt, actuation, loads, opt, strict)
    else:  # a resumed run keeps its segments (its state is on them)
        initial = start_solution(scene, initial, dt, opt, strict)
        raw = _run(scene, initial, duration, dt, actuation, loads, opt, t0, fin["state"])
        raw["segments"] = initial.options.shooting_segments
        for key in ("tip", "tension", "slack", "energy", "residual", "iters"):
            raw[key][0] = fin["row"][key]  # row 0: the previous run's last
    err = None
    if opt["estimate"] and raw["status"] == 0:
        half = _retried(scene, initial, duration, dt / 2, actuation, loads, opt, strict)[1]
        if half["status"] == 0:
            err = 4.0 / 3.0 * np.linalg.norm(raw["tip"][:, :3] - half["tip"][::2, :3], axis=1)
    if opt["extrapolate"]:
        raw, err = _extrapolated(scene, initial, duration, dt, actuation, loads, opt, strict, raw)
    pose = base_pose(scene.robot)
    k = raw["done"] + 1
    tip = raw["tip"]
    bb = raw["backbone"]
    s = None
    if bb is not None:
        s = raw["s"]
        bb = points_out(pose, bb)
    res = Trajectory(
        t=t0 + dt * np.arange(k),
        tip_position=points_out(pose, tip[:, :3]),
        tip_rotation=rotations_out(pose, tip[:, 3:].reshape(-1, 3, 3)),
        tension=raw["tension"],
        slack=raw["slack"],
        energy=raw["energy"],
        residual=raw["residual"],
        iterations=raw["iters"].astype(np.int64),
        time_error=err,
        backbone=bb,
        s=s,
        success=raw["status"] == 0,
        status=int(raw["status"]),
        message=raw["message"],
        nit=int(raw["nit"]),
        nfev=int(raw["nfev"]),
        segments=int(raw["segments"]),
        final=None
        if raw["done"] == 0 or opt["extrapolate"]
        else {
            "state": raw["state"],
            "dt": dt,
            "steps": int(opt["steps"]),
            "t": t0 + dt * (k - 1),
            "solution": initial,
            "row": {key: np.copy(raw[key][k - 1]) for key in _ROW},
        },
    )
    if not res.success:
        report_failure(res, strict, f"simulate: {res.message}")
    return res


def simulation_options(steps: int = int(_DEFAULTS["steps"]), segments: int = 1):
    """The static solve's :class:`~tendonrod.Options` on the grid of :func:`simulate`
    (``steps`` RK4 steps, spatial, ``segments`` shooting segments): solve a start state
    with them (:func:`simulate` solves it again on its segments where they differ).

    Examples
    --------
    >>> opts = tr.simulation_options(40)
    >>> opts.integrator, opts.steps, opts.force_spatial
    ('rk4', 40, True)
    """
    return statics_options(steps, segments)
