"""tr.Problem with a new Scene per call: a scene of the robot of the scene set last whose
structure-defining fields are that scene's sends only its values; every verdict (another
structure refused naming its field, the planar formulation, the plausibility screen) is
the one the full comparison gives."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

import tendonrod as tr
from tendonrod import _core
from tendonrod import _plausible as PL
from tendonrod import _plausible_rules as PR
from tendonrod.compiled import _structure, is_planar, pack_scene, structure_difference, value_vector

pytestmark = pytest.mark.filterwarnings("ignore::tendonrod.PlausibilityWarning")

L = 0.1
ROD = tr.Rod(length=L, diameter=1.04e-3, E=210e9, G=80e9, density=7800.0)
PLANAR = tr.Robot(ROD, [tr.Tendon(offset=0.01, angle=0.0), tr.Tendon(offset=0.01, angle=math.pi)])
SPATIAL = tr.Robot(ROD, [tr.Tendon(offset=0.01, angle=2 * math.pi * i / 3) for i in range(3)])


def variants(rob):
    """Scenes of ``rob``: values-only changes of one another and structural ones (point
    load moved or added, control kind, sliding, gravity, a point mass, a partial
    distributed load), in-plane and out-of-plane loads."""
    nt = rob.n_tendons
    q = [0.001] + [0.0] * (nt - 1)

    def sc(force=(0.1, 0.0, 0.0), s=L, moment=(0.0, 0.0, 0.0), extra=(), **kw):
        kw.setdefault("displacement", q)
        return tr.Scene(rob, loads=[tr.PointLoad(s=s, force=force, moment=moment), *extra], **kw)

    whole = tr.DistributedLoad(force=(0.0, 0.0, -1.0))
    part = tr.DistributedLoad(force=(0.0, 0.0, -1.0), start=0.02, end=0.05)
    return [
        sc(),
        sc(force=(0.2, 0.0, 0.05)),  # in-plane values
        sc(force=(0.2, 0.0, 0.05), moment=(0.0, 0.01, 0.0)),
        sc(displacement=[0.002] + [0.0] * (nt - 1)),
        sc(force=(0.0, 0.1, 0.0)),  # out of the x-z plane
        sc(moment=(0.01, 0.0, 0.0)),
        sc(moment=(0.0, 0.0, 0.01)),
        sc(extra=[whole]),
        sc(extra=[tr.DistributedLoad(force=(0.0, 0.0, -2.0))]),  # whole rod: a value
        sc(extra=[tr.DistributedLoad(force=(0.0, 1.0, 0.0))]),  # ... leaving the plane
        sc(extra=[part]),
        sc(extra=[dataclasses.replace(part, force=(0.0, 0.0, -2.0))]),  # partial: structure
        sc(s=0.05),  # the point load moved
        sc(extra=[tr.PointLoad(s=0.03)]),  # one more
        sc(displacement=[None] + [0.0] * (nt - 1), tension=[1.0] + [None] * (nt - 1)),
        sc(sliding="out"),
        sc(gravity=(0.0, 0.0, -9.81)),
        sc(gravity=(0.0, 0.0, -9.81), extra=[tr.PointMass(s=0.05, mass=0.001)]),
        sc(gravity=(0.0, 0.0, -9.81), extra=[tr.PointMass(s=0.05, mass=0.002)]),
        sc(gravity=(0.0, -9.81, 0.0)),
    ]


@pytest.mark.parametrize("rob", [PLANAR, SPATIAL], ids=["planar robot", "spatial robot"])
@pytest.mark.parametrize("spatial", [False, True], ids=["", "force_spatial"])
def test_every_pair_gets_the_full_comparisons_verdict(rob, spatial):
    """For every scene compiled and every pair (the scene set last, the next one) of
    fresh scene objects: the next is refused exactly when the full comparison with the
    compiled scene finds a difference, naming that field; an accepted one is set, with
    the planar formulation the core's rule gives it."""
    opts = tr.Options(force_spatial=spatial)
    n = len(variants(rob))
    for i in range(n):
        prob = tr.Problem(variants(rob)[i], options=opts)
        for j in range(n):
            a = variants(rob)[j]
            if structure_difference(prob.scene, a, spatial) is not None:
                continue
            fresh = variants(rob)  # new objects: nothing cached on them
            for k in range(n):
                check_pair(prob, a, fresh[k], spatial, (i, j, k))


def check_pair(prob, a, b, spatial, where):
    prob._set(a)
    # (on a copy: the full comparison caches the structure on the scene it reads)
    want = structure_difference(prob.scene, dataclasses.replace(b), spatial)
    if want is None:
        prob._set(b)
        assert prob._current is b
        # the planarity cached on b is the core's rule on b's packed tables
        ref = dataclasses.replace(b)
        assert is_planar(b) == is_planar(ref), where
        # and the structure cached on it is the one of its fields
        assert _structure(b) == _structure(ref), where
    else:
        with pytest.raises(ValueError, match=re_escape(want.split(" = ")[0])):
            prob._set(b)
        assert prob._current is a, where


def re_escape(text: str) -> str:
    import re

    return re.escape(text.split(" differs")[0])


def test_values_planar_is_the_cores_rule_on_the_loads():
    """_core.Problem.values_planar(v) equals _core.is_planar on the loads and distributed
    force of v (tendons none), over vectors with each component zero or not."""
    prob = tr.Problem(variants(SPATIAL)[13])  # two point loads
    nt, nl = 3, 2
    rng = np.random.default_rng(5)
    for _ in range(300):
        v = rng.normal(size=nt + 6 * nl + 3) * (rng.random(nt + 6 * nl + 3) < 0.3)
        loads = np.column_stack([np.full(nl, L), v[nt : nt + 6 * nl].reshape(nl, 6)])
        want = bool(_core.is_planar(np.empty((0, 8)), loads, v[-3:].copy()))
        assert prob._c.values_planar(v) is want


@pytest.mark.parametrize("rob", [PLANAR, SPATIAL], ids=["planar robot", "spatial robot"])
def test_value_vector_is_the_packed_tables_values(rob):
    """The value vector from the scene's fields is, bit for bit, [tendon values, point
    loads' F and M, distributed force] of its packed tables (point masses under gravity,
    whole-rod loads and the rod's weight included)."""
    for scene in variants(rob):
        _, tendons, loads, dist = pack_scene(dataclasses.replace(scene))
        want = np.concatenate([tendons[:, 6], loads[:, 1:7].ravel(), dist])
        assert np.array_equal(value_vector(scene), want)


def test_screen_is_the_packed_loads_screen():
    """The plausibility screen from the value vector equals the screen of the packed
    loads (arc lengths, |F|, |M|, |distributed force|), also for a mounted robot (base-
    frame values: the norms are the world's)."""
    c, s = math.cos(0.7), math.sin(0.7)
    mounted = dataclasses.replace(SPATIAL, base_rotation=((c, -s, 0.0), (s, c, 0.0), (0, 0, 1)))
    for rob in (PLANAR, SPATIAL, mounted):
        for scene in variants(rob):
            _, _, loads, dist = pack_scene(scene)
            rows = loads.tolist()
            levers = PR.load_levers(
                [r[0] for r in rows],
                [math.hypot(*r[1:4]) for r in rows],
                [math.hypot(*r[4:7]) for r in rows],
                math.hypot(*dist.tolist()),
                L,
            )
            want = PR.screen(levers, PL._robot_constants(rob)["bounds"])
            got = PL._scene_screen(dataclasses.replace(scene))
            assert got == want


def test_fresh_scenes_solve_as_reused_ones():
    """A sweep of fresh Scene objects through one Problem gives the solutions of the
    same sweep of reused objects bitwise (the same values set in C, the same warm
    path)."""
    vals = [0.1 * (1 + i / 100) for i in range(5)]

    def sweep(rob):
        return [
            tr.Scene(rob, displacement=[0.001, 0, 0], loads=[tr.PointLoad(L, (f, f, 0))])
            for f in vals
        ]

    reused = sweep(SPATIAL)
    p1, p2 = tr.Problem(reused[0]), tr.Problem(reused[0])
    for s in reused:
        p1.solve(s)
    a = [p1.solve(s).tip_position for s in reused]
    for s in sweep(SPATIAL):
        p2.solve(s)
    b = [p2.solve(s).tip_position for s in sweep(SPATIAL)]
    for x, y in zip(a, b):
        assert np.array_equal(x, y)
