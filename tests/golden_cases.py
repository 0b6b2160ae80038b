"""Scenes whose solver outputs are pinned bit for bit by ``test_golden.py``.

The table covers every formulation the core compiles a scene into and every public
entry point that solves: planar and spatial, Kirchhoff and Cosserat, displacement and
tension control, slack, stiff tendons, pretension, mid-length anchors and loads,
distributed loads, multiple shooting, continuation (forced and after a failure), warm
starts, every integrator, Jacobian method and slack model, failures, the compliance,
``Solution.at``, ``solve_batch`` (exact and lean) and ``sweep`` (batched and point by
point).  Only the public API is used, so the table outlives any refactoring of the
code behind it.

Regenerate (only when a change of the numbers is intended and explained)::

    .venv/bin/python tests/golden_cases.py --write
"""

from __future__ import annotations

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
SOLUTION_SCALARS = ("success", "status", "nit", "nfev", "residual_norm")
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
    # statically indeterminate at compile time
    opp = tr.Robot(fig11_rod(), [tr.Tendon(offset=r), tr.Tendon(offset=r, angle=math.pi)])
    out["indeterminate"] = (tr.Scene(opp, displacement=[0.0, 0.0]), O(), None)
    return out


def _quiet(fn, *a, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fn(*a, **kw)


def _bits(value) -> np.ndarray:
    return np.ascontiguousarray(np.asarray(value))


def capture() -> dict:
    """Every pinned output, as name -> array."""
    out = {}
    for name, (scene, opts, guess_scene) in scenes().items():
        guess = _quiet(tr.solve, guess_scene, options=opts) if guess_scene is not None else None
        sol = _quiet(tr.solve, scene, guess=guess, options=opts)
        for f in SOLUTION_ARRAYS:
            out[f"solve/{name}/{f}"] = _bits(getattr(sol, f))
        for f in SOLUTION_SCALARS:
            out[f"solve/{name}/{f}"] = _bits(getattr(sol, f))
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
    return out


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
    return {
        "machine": platform.machine(),
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
