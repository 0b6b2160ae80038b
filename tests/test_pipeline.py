"""One verdict for every entry point.

Every way of solving a scene runs the same C pipeline (tr_solve: direct solve,
continuation, the confirmation of an equilibrium found off the load path, step
verification, diagnosis), so for one scene, one Options and the same history (here:
cold) they must report the same ``success``, the same core ``status`` and message, and
the same answer: ``tr.solve``, ``tr.Problem.solve``, ``tr.solve_batch``, ``tr.sweep``
over a load or actuation value (its batch path) and ``tr.sweep`` over a design field
(its per-point path).  The table: the reproducer that once got three verdicts (a plain
rod under a tip force (1, 0, 196) EI/L^2 with four shooting segments) and one case of
every family of the stress suite (``tendonrod.bench.stress_cases``).
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest

import tendonrod as tr
from tendonrod.bench.stress_cases import stress_cases

# one case per stress family (the ramps are sequences, not scenes)
FAMILY_CASES = [
    "stiffness/alpha=1e+06/outofplane",
    "actuation/90deg/cosserat/loaded-outofplane",
    "load/90deg/transverse-x/FL2EI=30",
    "tension/plain/Lsqrt(T/EI)=10",
    "opposing/kirchhoff-inextensible/q1=q2=0",
    "fig12/twist/alpha=1e+06",
    "slenderness/L/d=1000/outofplane",
    "offset/r=0.3L/cosserat",
    "tiny/90deg/axial/1e-6N",
]


def _reproducer():
    rod = tr.Rod(length=0.1, diameter=1.04e-3, E=210e9, G=80e9, kirchhoff=True)
    fs = rod.bending_stiffness / rod.length**2
    scene = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=0.1, force=(fs, 0, 196 * fs))])
    return scene, tr.Options(tip_only=True, shooting_segments=4)


def _cases():
    out = {"reproducer": _reproducer()}
    by_name = {c.name: c for c in stress_cases()}
    for name in FAMILY_CASES:
        scene, opts = by_name[name].build()
        out[name] = (scene, dataclasses.replace(opts, tip_only=True))
    return out


CASES = _cases()


def _batch_kwargs(scene):
    """Per-point arrays of one point that reproduce ``scene`` itself."""
    pls = scene.point_loads
    if pls:
        return {"forces": np.array([[p.force for p in pls]]), "path": "loads[0].force"}
    ctl = scene.displacement_controlled()
    if any(ctl):
        vals = [scene.displacement[i] for i, c in enumerate(ctl) if c]
        return {"displacement": np.array([vals]), "path": f"displacement[{ctl.index(True)}]"}
    vals = [scene.tension[i] for i, c in enumerate(ctl) if not c]
    return {"tension": np.array([vals]), "path": "tension[0]"}


def _value_at(scene, path):
    from tendonrod.sweeps import get_path

    return get_path(scene, path)


@pytest.mark.parametrize("name", list(CASES))
def test_every_entry_point_gives_one_verdict(name):
    """tr.solve, Problem.solve, solve_batch and both sweep paths: same success, status,
    message and answer (bitwise: one pipeline, the same cold history)."""
    scene, opts = CASES[name]
    kw = _batch_kwargs(scene)
    path = kw.pop("path")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", tr.ConvergenceWarning)
        ref = tr.solve(scene, options=opts)
        prob = tr.Problem(scene, options=opts).solve()
        batch = tr.solve_batch(scene, options=opts, **kw)
        sw_batch = tr.sweep(scene, {path: [_value_at(scene, path)]}, options=opts, progress=False)
        L = scene.robot.rod.length
        sw_point = tr.sweep(scene, {"robot.rod.length": [L]}, options=opts, progress=False)
    verdicts = {
        "Problem.solve": (prob.success, prob.status, prob.message, prob.tip_position),
        "solve_batch": (
            bool(batch.success[0]),
            int(batch.status[0]),
            str(batch.message[0]),
            batch.tip_position[0],
        ),
        "sweep (batch path)": (
            bool(sw_batch.success[0]),
            int(sw_batch.status[0]),
            str(sw_batch.message[0]),
            sw_batch["tip_position"][0],
        ),
        "sweep (per-point path)": (
            bool(sw_point.success[0]),
            int(sw_point.status[0]),
            str(sw_point.message[0]),
            sw_point["tip_position"][0],
        ),
    }
    for who, (success, status, message, tip) in verdicts.items():
        assert success == ref.success, (who, success, ref.success, message, ref.message)
        assert status == ref.status, (who, status, ref.status)
        assert message == ref.message, (who, message, ref.message)
        # the same computation: bitwise (NaN where the scene has no solution at all)
        assert np.array_equal(tip, ref.tip_position, equal_nan=True), (who, tip, ref.tip_position)


def test_the_reproducer_is_confirmed_everywhere():
    """The scene that once got three verdicts: an equilibrium found off the load path,
    which the core now confirms itself with a second formulation (status 4, success)."""
    scene, opts = CASES["reproducer"]
    sol = tr.solve(scene, options=opts)
    assert sol.success and sol.status == tr._core.STATUS_CONFIRMED
    assert "confirmed" in sol.message
