"""Scenes whose solver outputs are pinned bit for bit by ``test_golden.py``.

The table covers every formulation the core compiles a scene into and every public
entry point that solves: planar and spatial, Kirchhoff and Cosserat, displacement and
tension control, slack, stiff tendons, pretension, mid-length anchors and loads,
distributed loads, multiple shooting, continuation (forced and after a failure), warm
starts, every integrator, Jacobian method and slack model, failures, the compliance,
``Solution.at``, ``solve_batch`` (exact and lean) and ``sweep`` (batched and point by
point), and beyond the single solve: friction, the stability verdicts and margins,
``tr.path`` (points and special points), ``tr.actuate`` (every target kind and route),
``tr.jacobian`` (every block), ``tr.fit`` and warm ``Problem`` sequences.  Only the
public API is used, so the table outlives any refactoring of the code behind it.

Regenerate (only when a change of the numbers is intended and explained)::

    .venv/bin/python tests/golden_cases.py --write
"""

from __future__ import annotations

import dataclasses
import importlib.util
import math
import os
import platform
import sys
import warnings

import numpy as np

import tendonrod as tr

HERE = os.path.dirname(os.path.abspath(__file__))
GOLDEN = os.path.join(HERE, "data", "golden.npz")

# fields of a Solution that the contract defines (the Solution docstring)
SOLUTION_ARRAYS = (
    "s",
    "position",
    "rotation",
    "force",
    "moment",
    "tension",
    "slack",
    "displacement",
)
SOLUTION_SCALARS = ("success", "status", "nit", "nfev", "residual_norm", "message")
# the stability verdict of every solve (the margin is computed where a verdict skipped it)
STABILITY = ("stable", "stability", "stability_index", "stability_reason")
# outputs that may differ off the writing platform while the floats agree to round-off:
# iteration and evaluation counts, and texts that print numbers (see test_golden.py)
LOOSE = (
    "nit",
    "nfev",
    "njev",
    "iterations",
    "solves",
    "jacobians",
    "message",
    "stability_reason",
)
BATCH_ARRAYS = (
    "tip_position",
    "tip_rotation",
    "tension",
    "slack",
    "displacement",
    "status",
    "nit",
    "nfev",
    "residual_norm",
    "success",
)


def fig11_rod():
    return tr.Rod(length=0.1, diameter=1.04e-3, E=210e9, G=80e9, kirchhoff=True)


def fig17_rod(kirchhoff=True):
    return tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=kirchhoff)


def three_tendon(alpha, kirchhoff=True, pretension=0.0):
    """Fig. 11c robot: three tendons at 10 mm, r^2 k L / (3 EI) = alpha (k = EA/L)."""
    rod = fig11_rod() if kirchhoff else tr.Rod(length=0.1, diameter=1.04e-3, E=210e9, G=80e9)
    EI, r = rod.bending_stiffness, 0.01
    EA = alpha * 3 * EI / r**2
    return tr.Robot(
        rod,
        [
            tr.Tendon(offset=r, angle=2 * math.pi * i / 3, EA=EA, pretension=pretension)
            for i in range(3)
        ],
    )


def scenes() -> dict:
    """name -> (scene, options, guess-scene or None)."""
    out = {}
    r = 0.01
    rod = fig11_rod()
    L = rod.length
    q90 = r * math.pi / 2
    one = tr.Robot(rod, [tr.Tendon(offset=r)])
    tip = lambda f, m=(0.0, 0.0, 0.0): [tr.PointLoad(s=L, force=f, moment=m)]  # noqa: E731
    O = tr.Options  # noqa: E741,N806
    out["planar_transverse"] = (
        tr.Scene(one, displacement=[q90], loads=tip((-1.0, 0, 0))),
        O(),
        None,
    )
    out["planar_axial"] = (tr.Scene(one, displacement=[q90], loads=tip((0, 0, -1.0))), O(), None)
    out["planar_tip_only_fixed"] = (
        tr.Scene(one, displacement=[q90], loads=tip((-1.0, 0, 0))),
        O(steps=3, tip_only=True),
        None,
    )
    out["planar_warm"] = (
        tr.Scene(one, displacement=[q90], loads=tip((-1.0, 0, 0))),
        O(),
        tr.Scene(one, displacement=[q90], loads=tip((-0.99, 0, 0))),
    )
    out["planar_warm_tip_only"] = (
        tr.Scene(one, displacement=[q90], loads=tip((-1.0, 0, 0))),
        O(tip_only=True),
        tr.Scene(one, displacement=[q90], loads=tip((-0.99, 0, 0))),
    )
    out["planar_rk4"] = (
        tr.Scene(one, displacement=[q90], loads=tip((-1.0, 0, 0))),
        O(integrator="rk4"),
        None,
    )
    out["planar_adaptive"] = (
        tr.Scene(one, displacement=[q90], loads=tip((-1.0, 0, 0))),
        O(integrator="adaptive", rtol=1e-11, nodes=21),
        None,
    )
    out["planar_newton"] = (
        tr.Scene(one, displacement=[q90], loads=tip((0, 0, -1.0))),
        O(jacobian_method="newton"),
        None,
    )
    out["planar_hybrid"] = (
        tr.Scene(one, displacement=[q90], loads=tip((0, 0, -1.0))),
        O(jacobian_method="hybrid"),
        None,
    )
    out["planar_force_spatial"] = (
        tr.Scene(one, displacement=[q90], loads=tip((-1.0, 0, 0))),
        O(force_spatial=True),
        None,
    )
    out["planar_nodes_array"] = (
        tr.Scene(one, displacement=[q90], loads=tip((-1.0, 0, 0))),
        O(nodes=np.array([0.0, 0.013, 0.05, 0.05, 0.0999, 0.1])),
        None,
    )
    for alpha in (50.0, 5e4):
        rob = three_tendon(alpha)
        EI = rob.rod.bending_stiffness
        tau90 = EI * (math.pi / 2) / (r * L)
        free = tr.Scene(rob, tension=[tau90, 0.0, 0.0])
        out[f"spatial_tension_a{alpha:g}"] = (free, O(), None)
        out[f"spatial_disp_a{alpha:g}"] = (
            tr.Scene(rob, displacement=[q90 * 0.98, -0.001, -0.001], loads=tip((0, 0.5, 0))),
            O(),
            None,
        )
    out["spatial_disp_warm"] = (
        tr.Scene(
            three_tendon(50.0), displacement=[q90 * 0.98, -0.001, -0.001], loads=tip((0, 0.5, 0))
        ),
        O(),
        tr.Scene(
            three_tendon(50.0), displacement=[q90 * 0.98, -0.001, -0.001], loads=tip((0, 0.495, 0))
        ),
    )
    out["spatial_cosserat_pretension"] = (
        tr.Scene(
            three_tendon(50.0, kirchhoff=False, pretension=2.0),
            displacement=[0.002, 0.0, 0.0],
            loads=tip((0.1, 0.2, -0.3), (0, 0, 0.001)),
        ),
        O(),
        None,
    )
    k17 = fig17_rod()
    t17 = tr.Robot(k17, [tr.Tendon(offset=r)])
    out["fig17_taut"] = (
        tr.Scene(t17, displacement=[q90], loads=[tr.PointLoad(s=0.2, force=(0, 0, -0.2))]),
        O(),
        None,
    )
    out["fig17_slack"] = (
        tr.Scene(t17, displacement=[q90], loads=[tr.PointLoad(s=0.2, force=(0, 0, -0.5))]),
        O(),
        None,
    )
    out["fig17_slack_squared"] = (
        tr.Scene(t17, displacement=[q90], loads=[tr.PointLoad(s=0.2, force=(0, 0, -0.5))]),
        O(slack_model="squared"),
        None,
    )
    four = tr.Robot(
        fig17_rod(False), [tr.Tendon(offset=r, angle=i * math.pi / 2) for i in range(4)]
    )
    out["four_gravity"] = (
        tr.Scene(
            four,
            displacement=[4e-3, 2e-3, -5e-3, -3e-3],
            loads=[tr.DistributedLoad(force=(0, 0, -0.5))],
        ),
        O(),
        None,
    )
    # Till's displacement-control scene T0 (peers.md): gravity along +x
    till_rod = tr.Rod(length=0.5, diameter=2e-3, E=200e9, G=80e9)
    till = tr.Robot(
        till_rod, [tr.Tendon(offset=0.01506, angle=i * math.pi / 2, EA=1e4) for i in range(4)]
    )
    w = 8000 * 9.81 * math.pi * 1e-6
    out["till_T0"] = (
        tr.Scene(
            till, displacement=[5e-3, 0.0, -5e-3, 0.0], loads=[tr.DistributedLoad(force=(w, 0, 0))]
        ),
        O(),
        None,
    )
    # Rao's scene R: one tension-controlled tendon at +y, tip force
    rao_rod = tr.Rod(length=0.4, diameter=1.4e-3, E=54e9, G=54e9 / 2.6)
    rao = tr.Robot(rao_rod, [tr.Tendon(offset=0.01, angle=math.pi / 2)])
    out["rao_R"] = (
        tr.Scene(rao, tension=[2.0], loads=[tr.PointLoad(s=0.4, force=(0.1, 0, 0))]),
        O(),
        None,
    )
    # mixed control, a tendon anchored mid-length, a mid-length load, a converging tendon
    mixed = tr.Robot(
        fig17_rod(False),
        [
            tr.Tendon(offset=r),
            tr.Tendon(offset=r, angle=math.pi, end=0.12),
            tr.Tendon.converging(offset=r, angle=math.pi / 2, length=0.2),
        ],
    )
    out["mixed_midlength"] = (
        tr.Scene(
            mixed,
            displacement=[0.004, None, 0.001],
            tension=[None, 1.5, None],
            loads=[
                tr.PointLoad(s=0.07, force=(0.05, -0.02, 0.0)),
                tr.PointLoad(s=0.2, force=(0, 0, -0.1), moment=(0, 0.001, 0)),
            ],
        ),
        O(),
        None,
    )
    # plain rods: large load (forced continuation), tensile load (multiple shooting), failure
    plain = tr.Robot(fig11_rod(), [])
    EI = plain.rod.bending_stiffness
    out["plain_large_load"] = (tr.Scene(plain, loads=tip((30 * EI / L**2, 0, 0))), O(), None)
    out["plain_tensile_ms"] = (
        tr.Scene(plain, loads=tip((EI / L**2, 0, 100 * EI / L**2))),
        O(shooting_segments=4),
        None,
    )
    out["plain_tip_moment"] = (
        tr.Scene(plain, loads=tip((0, 0, 0), (0, 0.3 * EI / L, 0.1 * EI / L))),
        O(),
        None,
    )
    out["fail_maxnfev"] = (
        tr.Scene(plain, loads=tip((1e6, 0, 0))),
        O(max_nfev=200, continuation=False),
        None,
    )
    # the off-path pipeline of single shooting under tension L sqrt(T/EI) = 20 (by
    # default such scenes are compiled with multiple shooting: tests/test_hard_cases.py)
    out["offpath_confirmed"] = (
        tr.Scene(plain, loads=tip((0, 0, 400 * EI / L**2))),
        O(auto_shooting=False),
        None,
    )
    out["offpath_refused"] = (
        tr.Scene(plain, loads=tip((EI / L**2, 0, 400 * EI / L**2))),
        O(auto_shooting=False),
        None,
    )
    # stability: tendons locked at their switch hold a column beyond its Euler load, or
    # not (accepted unstable, and the default's stable branch); a buckled column
    frod = fig17_rod()
    four_locked = tr.Robot(
        frod, [tr.Tendon(offset=r, angle=k * math.pi / 2, EA=3e3) for k in range(4)]
    )
    p_e = math.pi**2 * frod.bending_stiffness / (4 * 0.2**2)
    for tag, f, opts in (
        ("held", 2.0, O()),
        ("unstable_accepted", 4.1, O(accept_unstable=True)),
        ("stable_branch", 4.1, O()),
    ):
        out[f"locked_{tag}"] = (
            tr.Scene(
                four_locked,
                displacement=[0.0] * 4,
                loads=[tr.PointLoad(0.2, force=(0, 0, -f * p_e))],
            ),
            opts,
            None,
        )
    out["column_buckled"] = (
        tr.Scene(tr.Robot(frod, []), loads=[tr.PointLoad(0.2, force=(1e-3 * p_e, 0, -2 * p_e))]),
        O(),
        None,
    )
    out["column_perfect_buckles"] = (
        tr.Scene(tr.Robot(frod, []), loads=[tr.PointLoad(0.2, force=(0, 0, -1.5 * p_e))]),
        O(),
        None,
    )
    # stiff tendon sets sharing a tension level: Fig. 12's twist at r^2 EA/EI = 1e9 solved
    # along that level's own direction; Fig. 18's pair locked at 90 deg at 1e10, where the
    # residuals fix the level only to their rounding (refused, TR_EINDETERMINATE)
    EI11, GJ11 = rod.bending_stiffness, rod.torsional_stiffness
    twist = tr.Robot(
        rod,
        [tr.Tendon(offset=r, angle=2 * math.pi * i / 3, EA=1e9 * EI11 / r**2) for i in range(3)],
    )
    out["stiff_twist"] = (
        tr.Scene(twist, displacement=[0.0] * 3, loads=tip((0, 0, 0), (0, 0, 0.5 * GJ11 / L))),
        O(),
        None,
    )
    k17 = fig17_rod()
    pair = tr.Robot(
        k17,
        [
            tr.Tendon(offset=r, angle=a, EA=1e10 * k17.bending_stiffness / r**2)
            for a in (0.0, math.pi)
        ],
    )
    out["stiff_pair_refused"] = (
        tr.Scene(
            pair,
            displacement=[0.01570796327192245, -0.01570796326554625],
            loads=[tr.PointLoad(s=0.2, force=(0, 0, -0.2))],
        ),
        O(),
        None,
    )
    # statically indeterminate at compile time
    opp = tr.Robot(fig11_rod(), [tr.Tendon(offset=r), tr.Tendon(offset=r, angle=math.pi)])
    out["indeterminate"] = (tr.Scene(opp, displacement=[0.0, 0.0]), O(), None)
    return out


def friction_scenes() -> dict:
    """name -> (scene, options, None): friction between the tendons and their channels
    (docs/model.md, Section 3), kept apart from :func:`scenes` (whose table other tests
    solve through the raw core, which takes the friction separately)."""
    out = {}
    r, L = 0.01, 0.2
    frod = fig17_rod()
    O = tr.Options  # noqa: E741,N806
    tip = lambda f, m=(0.0, 0.0, 0.0): [tr.PointLoad(s=L, force=f, moment=m)]  # noqa: E731
    # tension and displacement control, both sliding directions, a curvature that changes
    # sign (a kink of the friction law), an anchor at mid-length beside a frictionless
    # tendon, spatial and with multiple shooting

    def frict(mu, **kw):
        return tr.Robot(frod, [tr.Tendon(offset=r, friction=mu, **kw)])

    tight = O(tol=1e-12)
    out["friction_tension_in"] = (tr.Scene(frict(0.3), tension=[2.0]), tight, None)
    out["friction_tension_out_spatial"] = (
        tr.Scene(frict(0.3), tension=[2.0], sliding="out"),
        O(tol=1e-12, force_spatial=True),
        None,
    )
    out["friction_reversal"] = (
        tr.Scene(frict(0.4), tension=[3.0], sliding="out", loads=tip((-0.3, 0, 0))),
        O(),
        None,
    )
    out["friction_disp_stretch"] = (
        tr.Scene(frict(0.3, EA=2e3), displacement=[0.01], loads=tip((0.1, 0, -0.1))),
        tight,
        None,
    )
    fmixed = tr.Robot(
        frod,
        [
            tr.Tendon(offset=r, angle=0.0, friction=0.5),
            tr.Tendon(offset=r, angle=2.0, friction=0.3, end=0.12),
            tr.Tendon(offset=r, angle=4.0),
        ],
    )
    fscene = tr.Scene(
        fmixed,
        tension=[2.0, 3.0, None],
        displacement=[None, None, 0.002],
        sliding=["in", "out", "in"],
        loads=[
            tr.PointLoad(0.08, force=(0.05, -0.1, -0.2)),
            tr.PointLoad(0.2, force=(-0.1, 0.2, 0.05)),
        ],
    )
    out["friction_spatial_anchor"] = (fscene, tight, None)
    out["friction_spatial_anchor_ms"] = (fscene, O(tol=1e-12, shooting_segments=3), None)
    return out


def _quiet(fn, *a, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*a, **kw)


def _bits(value) -> np.ndarray:
    return np.ascontiguousarray(np.asarray(value))


def _put(out: dict, key: str, value) -> None:
    """``value`` under ``key``: arrays and numbers as they are; None, texts and object
    arrays (a path's verdicts and kinds) as text; a record (dataclass), dict, or a
    sequence of records one entry per field / item.  Scenes and solutions inside a
    record are left out (they are the inputs, or pinned on their own)."""
    if value is None:
        out[key] = np.array("None")
    elif isinstance(value, (tr.Scene, tr.Solution)):
        return
    elif dataclasses.is_dataclass(value):
        for f in dataclasses.fields(value):
            _put(out, f"{key}/{f.name}", getattr(value, f.name))
    elif isinstance(value, dict):
        for k, v in value.items():
            _put(out, f"{key}/{k}", v)
    elif isinstance(value, (list, tuple)) and any(
        dataclasses.is_dataclass(v) or isinstance(v, (tr.Scene, tr.Solution)) for v in value
    ):
        out[f"{key}/len"] = np.array(len(value))
        for i, v in enumerate(value):
            _put(out, f"{key}/{i}", v)
    else:
        try:
            arr = np.asarray(value)
        except ValueError:  # a ragged tuple: a pose's (position, rotation)
            for i, v in enumerate(value):
                _put(out, f"{key}/{i}", v)
            return
        if arr.dtype == object:
            arr = np.array([str(v) for v in arr.ravel()]).reshape(arr.shape)
        out[key] = np.ascontiguousarray(arr)


def _solution(out: dict, key: str, sol) -> None:
    for f in SOLUTION_ARRAYS + SOLUTION_SCALARS + STABILITY:
        _put(out, f"{key}/{f}", getattr(sol, f))


#: SciPy is there (tr.fit's least squares): the wheels' quick tests run without it
HAVE_SCIPY = importlib.util.find_spec("scipy") is not None


def capture() -> dict:
    """Every pinned output, as name -> array."""
    out = {}
    for name, (scene, opts, guess_scene) in (scenes() | friction_scenes()).items():
        guess = _quiet(tr.solve, guess_scene, options=opts) if guess_scene is not None else None
        sol = _quiet(tr.solve, scene, guess=guess, options=opts)
        _solution(out, f"solve/{name}", sol)
        if name.startswith("friction"):
            out[f"solve/{name}/tendon_tension"] = _bits(sol.tendon_tension)
    scs = scenes()
    # compliance and Solution.at on a spatial and a planar scene
    for name in ("spatial_disp_a50", "planar_transverse", "mixed_midlength"):
        scene, opts, _ = scs[name]
        out[f"compliance/{name}"] = _bits(tr.compliance(scene, options=opts))
        sol = _quiet(tr.solve, scene, options=opts)
        st = sol.at(np.array([0.0, 0.031, 0.06]))
        for f in ("position", "rotation", "force", "moment"):
            out[f"at/{name}/{f}"] = _bits(getattr(st, f))
    out["compliance/mixed_midlength_s0.07"] = _bits(
        tr.compliance(scs["mixed_midlength"][0], s=0.07)
    )
    # solve_batch: a load line on a planar and a spatial scene, exact and lean
    for name, comp in (("planar_transverse", 0), ("spatial_disp_a50", 1)):
        scene = scs[name][0]
        n = 40
        F = np.zeros((n, 1, 3))
        F[:, 0, comp] = np.linspace(-1.0, 1.0, n) if comp == 0 else np.linspace(0.0, 1.0, n)
        for tag, kw in (
            ("auto_exact", dict(exact=True)),
            ("auto", dict()),
            ("fixed_lean", dict(options=tr.Options(steps=4))),
            ("fixed_exact", dict(options=tr.Options(steps=4), exact=True)),
            ("chunked", dict(options=tr.Options(steps=4), chunksize=7)),
        ):
            res = _quiet(tr.solve_batch, scene, forces=F, **kw)
            for f in BATCH_ARRAYS:
                out[f"batch/{name}/{tag}/{f}"] = _bits(getattr(res, f))
    # displacement sweep through the batch, mixed control
    res = _quiet(
        tr.solve_batch,
        scs["mixed_midlength"][0],
        displacement=np.stack([np.linspace(0.0, 0.006, 12), np.full(12, 0.001)], axis=1),
        tension=np.linspace(0.5, 2.0, 12)[:, None],
    )
    for f in BATCH_ARRAYS:
        out[f"batch/mixed/{f}"] = _bits(getattr(res, f))
    # sweep: batched path (a load component), per-point path (a design parameter)
    base = scs["planar_transverse"][0]
    for tag, vary, opts in (
        (
            "load_batched",
            {"loads[0].force[0]": np.linspace(-1.0, 1.0, 9)},
            tr.Options(tip_only=True),
        ),
        ("offset_pointwise", {"robot.tendons[0].offset": np.linspace(0.008, 0.012, 5)}, None),
        (
            "grid",
            {"displacement[0]": [0.0, 0.01], "loads[0].force[2]": [-0.5, 0.0, 0.5]},
            tr.Options(tip_only=True, steps=4),
        ),
    ):
        res = _quiet(tr.sweep, base, vary, options=opts, max_workers=1, progress=False)
        out[f"sweep/{tag}/status"] = _bits(res.status)
        for f in ("tip_position", "tension"):
            out[f"sweep/{tag}/{f}"] = _bits(res[f])
    capture_path(out)
    capture_actuate(out)
    capture_jacobian(out, scs)
    capture_problem(out)
    if HAVE_SCIPY:  # tr.fit needs it (the fit extra); a bare install checks the rest
        capture_fit(out)
    return out


def capture_path(out: dict) -> None:
    """tr.path: a bifurcation followed straight on and switched onto the buckled branch,
    a limit point (the branch folds back to the start), a tendon displacement."""
    rod = tr.Rod(length=0.25, diameter=1.2e-3, E=60e9, G=23e9, kirchhoff=True)
    p_e = math.pi**2 * rod.bending_stiffness / (4 * rod.length**2)
    column = tr.Robot(rod, [])
    straight = tr.Scene(column, loads=[tr.PointLoad(s=0.25, force=(0.0, 0.0, 0.0))])
    buckled = tr.Scene(column, loads=[tr.PointLoad(s=0.25, force=(0.0, 0.0, -1.5 * p_e))])
    x0 = _quiet(tr.solve, buckled).tip_position[0]
    robot = tr.Robot(fig17_rod(), [tr.Tendon(offset=0.01)])
    pulled = tr.Scene(robot, displacement=[0.0], loads=[tr.PointLoad(s=0.2, force=(0.3, 0, 0))])
    free = tr.Scene(robot, displacement=[0.0])
    stretchy = tr.Scene(
        tr.Robot(fig17_rod(), [tr.Tendon(offset=0.01, EA=1e5)]),
        displacement=[0.01],
        loads=[tr.PointLoad(s=0.2, force=(0.0, 0.2, 0.0))],
    )
    for tag, scene, parameter, span, kw in (
        ("bifurcation", straight, "loads[0].force[2]", (0.0, -3.0 * p_e), {}),
        ("switched", straight, "loads[0].force[2]", (0.0, -3.0 * p_e), dict(switch=1)),
        ("limit", buckled, "loads[0].force[0]", (0.0, -math.copysign(0.5 * p_e, x0)), {}),
        ("displacement", free, "displacement[0]", (0.0, 0.0157), {}),
        # stalls where the tendon meets its slack switch (status -12, the points kept)
        ("displacement_stall", pulled, "displacement[0]", (0.0, 0.01 * math.pi / 2), {}),
        ("design", stretchy, "robot.tendons[0].EA", (1e5, 1e3), {}),
    ):
        _put(out, f"path/{tag}", _quiet(tr.path, scene, parameter, span, **kw))


def capture_actuate(out: dict) -> None:
    """tr.actuate: every target kind (tip angle, direction, position, pose), every kind of
    problem (square, least change with and without an active tension floor, least
    squares) and both routes (inside the shooting system, steps on the linearisation)."""
    rod = fig17_rod()
    two = tr.Robot(rod, [tr.Tendon(offset=0.01, angle=a, EA=3e3) for a in (0.0, math.pi)])
    loaded = tr.Scene(
        two, displacement=[0.0, 0.0], loads=[tr.PointLoad(0.2, force=(-0.1, 0, -0.05))]
    )
    rod4 = tr.Rod(length=0.25, diameter=1.2e-3, E=60e9, G=23e9)
    four = tr.Robot(
        rod4, [tr.Tendon(offset=0.008, angle=k * math.pi / 2, EA=4e3) for k in range(4)]
    )
    weight = tr.DistributedLoad(force=(0.0, 0.0, -0.6))
    heavy = tr.Scene(four, displacement=[0.0] * 4, loads=[weight])
    t_goal = _quiet(tr.solve, dataclasses.replace(heavy, displacement=[4e-3, 3e-3, -2e-3, -1e-3]))
    pushed = tr.Scene(four, tension=[0.0] * 4, loads=[tr.PointLoad(0.25, force=(0, 0.05, 0))])
    p_goal = _quiet(tr.solve, dataclasses.replace(pushed, tension=[2.0, 1.0, 0.0, 0.5]))
    rod6 = tr.Rod(length=0.24, diameter=1.2e-3, E=60e9, G=23e9)
    six = tr.Robot(
        rod6,
        [tr.Tendon(offset=0.008, angle=2 * math.pi * k / 3, EA=5e3, end=0.12) for k in range(3)]
        + [tr.Tendon(offset=0.008, angle=(2 * k + 1) * math.pi / 3, EA=5e3) for k in range(3)],
    )
    pose = _quiet(tr.solve, tr.Scene(six, tension=[1.5, 0.2, 0.0, 0.0, 1.0, 0.3]))
    f11 = three_tendon(150.0 / 3)
    locked = tr.Scene(f11, displacement=[0.0] * 3, loads=[tr.PointLoad(0.1, force=(0, 0.5, 0))])
    rod_p = tr.Rod(length=0.2, diameter=1e-3, E=60e9, G=23e9)
    pre = tr.Robot(
        rod_p, [tr.Tendon(offset=0.01, angle=a, EA=2e3, pretension=3.0) for a in (0.0, math.pi)]
    )
    pre = tr.Scene(pre, displacement=[0.0, 0.0])
    one = tr.Robot(rod, [tr.Tendon(offset=0.01)])
    cases = {
        "angle_augmented": (loaded, dict(tip_angle=math.pi / 2, tendons=[0])),
        "angle_linearisation": (
            loaded,
            dict(tip_angle=math.pi / 2, tendons=[0], method="linearisation"),
        ),
        "angle_curl": (loaded, dict(tip_angle=math.radians(200.0), tendons=[0])),
        "angle_tension": (tr.Scene(one, tension=[0.0]), dict(tip_angle=1.2)),
        "direction_square": (heavy, dict(tip_direction=t_goal.tip_rotation[:, 2], tendons=[0, 1])),
        "position_square": (pushed, dict(tip_position=p_goal.tip_position, tendons=[0, 1, 3])),
        "pose_square": (
            tr.Scene(six, tension=[0.5] * 6),
            dict(tip_pose=(pose.tip_position, pose.tip_rotation)),
        ),
        "least_change": (locked, dict(tip_direction=(0.3, 0.5, 1.0))),
        "least_change_floor": (pre, dict(tip_angle=0.8, min_tension=1.0)),
        "least_squares": (
            tr.Scene(one, displacement=[0.0]),
            dict(tip_position=(0.12, 0.0, 0.12)),
        ),
        "unreachable": (tr.Scene(one, tension=[0.0]), dict(tip_angle=-math.pi / 4)),
    }
    for name, (scene, kw) in cases.items():
        sol = _quiet(tr.actuate, scene, **kw)
        _solution(out, f"actuate/{name}", sol)
        _put(out, f"actuate/{name}/actuation", sol.actuation)


def capture_jacobian(out: dict, scs: dict) -> None:
    """tr.jacobian: every block (actuation, tension, slack, load, design, design tension,
    the switch flags), forward and central, at the tip and at several arc lengths, a
    tendon at its switch taken on either side, and a friction coefficient as a design
    parameter."""
    # a Cosserat rod with four stretchable tendons, two anchored at mid-length, mixed
    # control, a distributed load and an oblique tip force
    mixed = tr.Scene(
        tr.Robot(
            tr.Rod(length=0.2, diameter=1e-3, E=100e9, G=40e9),
            [
                tr.Tendon(offset=0.008, angle=0.0, EA=500.0),
                tr.Tendon(offset=0.008, angle=math.pi / 2, EA=500.0, end=0.12),
                tr.Tendon(offset=0.008, angle=math.pi, EA=500.0, end=0.12),
                tr.Tendon.converging(offset=0.008, angle=1.5 * math.pi, length=0.2, EA=800.0),
            ],
        ),
        displacement=[0.003, None, -0.001, None],
        tension=[None, 1.0, None, 0.3],
        loads=[
            tr.DistributedLoad(force=(0.0, 0.0, -0.5)),
            tr.PointLoad(s=0.2, force=(0.1, 0.05, 0.0)),
        ],
    )
    spatial = _quiet(tr.solve, scs["spatial_disp_a50"][0])
    locked = tr.Scene(
        tr.Robot(fig17_rod(), [tr.Tendon(offset=0.01, angle=a, EA=3e3) for a in (0.0, math.pi)]),
        displacement=[0.0, 0.0],
        loads=[tr.PointLoad(0.2, force=(0.0, 0.0, -0.1))],
    )
    lever = tr.Scene(
        tr.Robot(fig17_rod(), [tr.Tendon(offset=0.01, EA=3e3, friction=0.3)]),
        displacement=[0.01],
        loads=[tr.PointLoad(0.2, force=(0.1, 0.0, -0.1))],
    )
    design_mixed = ["EI", "EA", "GA", "tendons[1].EA", "tendons[0].slope"]
    for tag, subject, kw in (
        (
            "spatial_forward",
            spatial,
            dict(design=["EI", "GJ", "tendons[0].EA", "tendons[1].offset"]),
        ),
        ("spatial_central", spatial, dict(method="central", design=["tendons[2].EA"])),
        ("mixed_nodes", mixed, dict(s=[0.07, 0.12, 0.2], design=design_mixed)),
        ("mixed_central_noload", mixed, dict(method="central", load=False)),
        ("switch_taut", locked, dict(side=[1, 1])),
        ("switch_slack", locked, dict(side=[-1, 0])),
        ("friction", lever, dict(design=["tendons[0].friction"])),
    ):
        _put(out, f"jacobian/{tag}", _quiet(tr.jacobian, subject, **kw))


def capture_problem(out: dict) -> None:
    """Warm Problem sequences: a tendon pulled in steps (with a cold solve and a guess
    from another scene between), pretensions changed without recompiling, and a column
    ramped across its bifurcation (the verdict redone on the way)."""
    robot = three_tendon(50.0)
    L = robot.rod.length

    def pulled(q, f=0.5):
        return tr.Scene(
            robot, displacement=[q, -0.001, -0.001], loads=[tr.PointLoad(L, force=(0, f, 0))]
        )

    prob = tr.Problem(pulled(0.0))
    for i, q in enumerate(np.linspace(0.0, 0.016, 5)):
        _solution(out, f"problem/pull/{i}", _quiet(prob.solve, pulled(q)))
    _solution(out, "problem/pull/cold", _quiet(prob.solve, pulled(0.008), guess="cold"))
    other = _quiet(tr.solve, pulled(0.01, 0.3))
    _solution(out, "problem/pull/guess", _quiet(prob.solve, pulled(0.012), guess=other))
    _solution(out, "problem/pull/again", _quiet(prob.solve))
    pre = tr.Problem(tr.Scene(three_tendon(50.0, pretension=1.0), displacement=[0.0] * 3))
    for i, t in enumerate((1.0, 3.0, 0.5)):
        scene = tr.Scene(three_tendon(50.0, pretension=t), displacement=[0.002, 0.0, 0.0])
        _solution(out, f"problem/pretension/{i}", _quiet(pre.solve, scene))
    rod = tr.Rod(length=0.25, diameter=1.2e-3, E=60e9, G=23e9, kirchhoff=True)
    p_e = math.pi**2 * rod.bending_stiffness / (4 * rod.length**2)

    def column(f):
        return tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(0.25, force=(0, 0, -f * p_e))])

    ramp = tr.Problem(column(0.5))
    for i, f in enumerate(np.linspace(0.5, 1.5, 6)):
        _solution(out, f"problem/ramp/{i}", _quiet(ramp.solve, column(f)))
    out["problem/ramp/compliance"] = _bits(ramp.compliance())


def capture_fit(out: dict) -> None:
    """tr.fit: a rod's EI from tip positions under three loads, and a tendon's friction
    coefficient from a lever under five (synthetic data: forward solves at known values;
    the optimiser is SciPy's, whose version is part of the fingerprint)."""
    truth = tr.Robot(tr.Rod(0.2, 0.8e-3, 207e9, 79.6e9, kirchhoff=True, EI=4.6e-3), [])
    model = tr.Robot(fig17_rod(), [])
    loads = [[tr.PointLoad(s=0.2, force=(-f, 0, 0))] for f in (0.01, 0.02, 0.03)]
    measured = [_quiet(tr.solve, tr.Scene(truth, loads=ld)).tip_position for ld in loads]
    res = _quiet(tr.fit, [tr.Scene(model, loads=ld) for ld in loads], measured, ["EI"])
    _put(out, "fit/EI", res)

    def lever(mu, F):
        robot = tr.Robot(fig17_rod(), [tr.Tendon(offset=0.01, EA=3e3, friction=mu)])
        return tr.Scene(robot, displacement=[0.01], loads=[tr.PointLoad(0.2, force=(F, 0, -0.1))])

    forces = (-0.2, 0.0, 0.2)
    measured = [_quiet(tr.solve, lever(0.25, F)).tip_position for F in forces]
    res = _quiet(tr.fit, [lever(0.1, F) for F in forces], measured, ["tendons[0].friction"])
    _put(out, "fit/friction", res)


def fingerprint() -> dict:
    """What the bits of floating-point results depend on besides the code."""
    flags = ""
    try:
        with open("/proc/cpuinfo") as fh:
            for line in fh:
                if line.startswith("flags"):
                    have = set(line.split(":", 1)[1].split())
                    flags = ",".join(f for f in ("fma", "avx2", "avx512f") if f in have)
                    break
    except OSError:
        pass
    try:
        import scipy

        scipy_version = scipy.__version__
    except ImportError:  # tr.fit needs it; the fingerprint says it is missing
        scipy_version = "none"
    return {
        "machine": platform.machine(),
        "scipy": scipy_version,
        "libc": "-".join(platform.libc_ver()),
        "numpy": np.__version__,
        "gsl": tr.gsl_version,
        "cpu": flags,
    }


def write(path: str = GOLDEN) -> None:
    data = capture()
    fp = fingerprint()
    for k, v in fp.items():
        data[f"__fingerprint__/{k}"] = np.array(v)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    np.savez_compressed(path, **data)
    print(f"wrote {len(data)} arrays to {path}")


if __name__ == "__main__":
    if "--write" in sys.argv[1:]:
        write()
    else:
        print(__doc__)
