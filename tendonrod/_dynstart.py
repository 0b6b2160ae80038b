"""The start of a :func:`~tendonrod.simulate` run: the static state it starts from, on the
dynamics' grid, and the inputs that state holds under (its own scene's), checked against
the run's scene: what may differ between the two (actuation values, point-load values,
gravity and whole-rod distributed loads) acts from the first step on; what may not (the
robot, the tendons' control kinds, partial distributed loads, point masses) is refused."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from . import _core
from .compiled import _compile, pack_scene
from .loads import PointLoad, PointMass


def statics_options(steps: int, segments: int = 1):
    """The static solve's options on the dynamics' grid: spatial, fixed RK4, ``segments``
    shooting segments."""
    from .options import Options

    return Options(
        integrator="rk4",
        steps=steps,
        force_spatial=True,
        shooting_segments=segments,
        auto_shooting=False,
    )


def held_values(scene) -> np.ndarray:
    """Per tendon the value its control holds: displacement [m] or tension [N]."""
    return np.array(
        [d if d is not None else tau for d, tau in zip(scene.displacement, scene.tension)],
        dtype=float,
    )


def paired(scene, start_scene):
    """``(run, start, extra)``: the two scenes with point loads at the same positions in the
    same order (a zero load where one scene has none: it changes neither's physics), and
    the zero loads added to the run's (appended after its own).  ValueError naming
    ``initial`` for a start of another structure."""

    def refuse(what):
        raise ValueError(
            f"simulate: initial is a solution of a scene whose {what} differs from the "
            "scene's: a run starts from a state of the same structure (its actuation values, "
            "point-load values, gravity and whole-rod distributed loads may differ, and act "
            "from the first step on)"
        )

    if start_scene is scene:
        return scene, scene, ()
    if start_scene.robot != scene.robot:
        refuse("robot (rod, tendons or mounting)")
    if start_scene.displacement_controlled() != scene.displacement_controlled():
        refuse("tendons' control kinds (displacement- or tension-held)")
    if start_scene.partial_loads != scene.partial_loads:
        refuse("partial distributed loads")
    if any(isinstance(ld, PointMass) for ld in start_scene.loads):
        refuse("point masses")
    run_pl = [ld for ld in scene.loads if isinstance(ld, PointLoad)]
    rest = [ld for ld in start_scene.loads if isinstance(ld, PointLoad)]
    start_pl = []
    for p in run_pl:
        k = next((i for i, q in enumerate(rest) if q.s == p.s), None)
        start_pl.append(rest.pop(k) if k is not None else PointLoad(p.s))
    extra = tuple(PointLoad(q.s) for q in rest)
    start_pl += rest
    if extra:
        others = tuple(ld for ld in scene.loads if not isinstance(ld, PointLoad))
        scene = replace(scene, loads=(*run_pl, *extra, *others))
    if len(start_pl) != sum(isinstance(ld, PointLoad) for ld in start_scene.loads) or any(
        a is not b
        for a, b in zip(start_pl, (ld for ld in start_scene.loads if isinstance(ld, PointLoad)))
    ):
        others = tuple(ld for ld in start_scene.loads if not isinstance(ld, PointLoad))
        start_scene = replace(start_scene, loads=(*start_pl, *others))
    return scene, start_scene, extra


def start_inputs(run, start):
    """The start's inputs where they differ from the run's (of two :func:`paired`
    scenes): ``(values (nt,), point loads (nl, 6) or None, dist (3,) or None)``."""
    _, _, lr, dr = pack_scene(run)
    _, _, ls, ds = pack_scene(start)
    loads = None if np.array_equal(lr[:, 1:7], ls[:, 1:7]) else np.array(ls[:, 1:7])
    dist = None if np.array_equal(dr, ds) else np.array(ds, dtype=float)
    return held_values(start), loads, dist


def start_solution(scene, initial, dt, opt, strict):
    """The solution the run at dt starts from, on its grid and shooting segments (the
    given ``initial`` solved again there, in its own scene, if it is not): the scene's
    equilibrium for None."""
    from .solver import solve

    steps = int(opt["steps"])
    seg = opt["segments"]
    if seg is None:
        prob = _compile(scene, statics_options(steps))
        seg = _core.dyn_segments(
            prob, scene.robot.rod.mass_per_length, float(dt), float(opt["alpha"])
        )[0]
    stat = statics_options(steps, int(seg))
    if initial is None:
        initial = solve(scene, options=stat, strict=strict)
    else:
        _, start, _ = paired(scene, initial.scene)
        if initial.options != stat or start is not initial.scene:
            initial = solve(start, initial, options=stat, strict=strict)
    if not initial.success or initial.unknowns is None:
        raise ValueError(f"simulate: the initial state is not an equilibrium: {initial.message}")
    return initial
