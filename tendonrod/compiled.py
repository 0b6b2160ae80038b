"""A scene compiled for the core: the flat arrays of the raw contract, the output nodes,
the structure that fixes a compiled model, and the compiled ``_core.Problem`` itself.

The first step of the one-way flow (dataclasses -> compiled model -> workspace ->
arrays -> result objects): everything here reads a frozen :class:`~tendonrod.Scene`
and its :class:`~tendonrod.Options`, caches what it derives on the scene, and knows
nothing of solutions.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from . import _core
from .backbone import pack_sections
from .loads import DistributedLoad, PointLoad
from .model import Scene
from .mounting import base_pose, vectors_in
from .options import Options
from .routing import route_rows

__all__ = ["pack_scene", "is_planar", "structure_difference", "compliance_point"]


# Column indices of the flat arrays of the raw contract (the core's layouts).
_ROD = {name: i for i, name in enumerate(_core.ROD_COLUMNS)}
_TD = {name: i for i, name in enumerate(_core.TENDON_COLUMNS)}
_LD = {name: i for i, name in enumerate(_core.LOAD_COLUMNS)}
assert _core.LOAD_COLUMNS == ("s", "Fx", "Fy", "Fz", "Mx", "My", "Mz")  # (pack_scene's rows)


def pack_scene(scene: Scene):
    """Flat float64 arrays ``(rod (6,), tendons (nt, 8), loads (nl, 7), dist (3,))`` of the
    raw glue contract (csrc/README.md) for ``scene``: forces and moments in the base frame
    (the world frame unless the robot is mounted)."""
    if not isinstance(scene, Scene):
        raise ValueError(f"scene must be a tendonrod.Scene, got {scene!r}")
    cached = scene.__dict__.get("_packed")
    if cached is not None:
        return cached
    robot = scene.robot
    r = robot.rod
    rod, template = _robot_rows(robot)
    tendons = template.copy()  # the robot's columns; the scene's control and value below
    assert scene.displacement is not None and scene.tension is not None  # (Scene fills them)
    disp = scene.displacement
    tendons[:, _TD["control"]] = [0.0 if d is not None else 1.0 for d in disp]
    tendons[:, _TD["value"]] = [d if d is not None else t for d, t in zip(disp, scene.tension)]
    L = r.length
    # one row per point load, in the core's column order [s, F (3), M (3)]
    loads = np.array(
        [(min(p.s, L), *p.force, *p.moment) for p in scene.point_loads], dtype=float
    ).reshape(-1, len(_core.LOAD_COLUMNS))
    dist = scene.distributed_force
    pose = base_pose(robot)
    if pose is not None:
        for c in (_LD["Fx"], _LD["Mx"]):
            loads[:, c : c + 3] = vectors_in(pose, loads[:, c : c + 3])
        dist = vectors_in(pose, dist)
    for a in (rod, tendons, loads, dist):
        a.setflags(write=False)
    # a Scene is frozen: pack it once (sweeps and warm starts call solve() in loops)
    object.__setattr__(scene, "_packed", (rod, tendons, loads, dist))
    return rod, tendons, loads, dist


def _robot_rows(robot):
    """``(rod (6,), tendons (nt, 8))`` of ``robot``: the rod row (read-only) and the
    tendon rows with every column the robot fixes (control and value left 0), cached on
    the frozen robot, which the scenes of a loop share."""
    cached = robot.__dict__.get("_packed_rows")
    if cached is not None:
        return cached
    r = robot.rod
    rod = np.empty(len(_core.ROD_COLUMNS))
    rod[_ROD["length"]], rod[_ROD["EI"]], rod[_ROD["GJ"]] = (
        r.length,
        r.bending_stiffness,
        r.torsional_stiffness,
    )
    rod[_ROD["EA"]], rod[_ROD["GA"]] = r.axial_stiffness, r.shear_stiffness
    rod[_ROD["kirchhoff"]] = 1.0 if r.kirchhoff else 0.0
    rod.setflags(write=False)
    tendons = np.zeros((robot.n_tendons, len(_core.TENDON_COLUMNS)))
    for i, t in enumerate(robot.tendons):
        row = tendons[i]
        row[_TD["offset"]], row[_TD["angle"]], row[_TD["slope"]] = t.offset, t.angle, t.slope
        row[_TD["EA"]], row[_TD["end"]], row[_TD["pretension"]] = (
            t.EA,
            robot.tendon_end(i),
            t.pretension,
        )
    tendons.setflags(write=False)
    object.__setattr__(robot, "_packed_rows", (rod, tendons))
    return rod, tendons


_NO_DLOADS = np.empty((0, 5))
_NO_DLOADS.setflags(write=False)


def pack_dloads(scene: Scene) -> np.ndarray:
    """The partial distributed loads of ``scene`` as the core's rows (nd, 5)
    ``[start, end, f (3)]`` [m, m, N/m], forces in the base frame (cached)."""
    cached = scene.__dict__.get("_packed_dloads")
    if cached is not None:
        return cached
    parts = scene.partial_loads
    if not parts:  # (the common case: one shared empty table)
        object.__setattr__(scene, "_packed_dloads", _NO_DLOADS)
        return _NO_DLOADS
    L = scene.robot.rod.length
    rows = np.empty((len(parts), 5))
    for k, ld in enumerate(parts):
        rows[k, 0], rows[k, 1] = ld.start, L if ld.end is None else min(ld.end, L)
        rows[k, 2:5] = ld.force
    pose = base_pose(scene.robot)
    if pose is not None:
        rows[:, 2:5] = vectors_in(pose, rows[:, 2:5])
    rows.setflags(write=False)
    object.__setattr__(scene, "_packed_dloads", rows)
    return rows


def _with_dloads(kw: dict, scene: Scene) -> dict:
    """``kw`` with the scene's partial distributed loads and backbone sections (none:
    ``kw`` itself)."""
    rows = pack_dloads(scene)
    secs = pack_sections(scene.robot.rod)
    routes = pack_routes(scene.robot)
    if rows.shape[0]:
        kw = dict(kw, dloads=rows)
    if routes is not None:
        kw = dict(kw, routes=routes)
    fric = pack_friction(scene)
    if fric is not None:
        kw = dict(kw, friction=fric)
    return kw if secs is None else dict(kw, sections=secs)


def pack_friction(scene: Scene):
    """The core's friction rows (ntendon, 2) ``[mu, +1 in / -1 out]``, or None when every
    tendon is frictionless (the problem is then compiled without friction states)."""
    tendons = scene.robot.tendons
    if not any(t.friction > 0.0 for t in tendons):
        return None
    return np.array(
        [[t.friction, 1.0 if d == "in" else -1.0] for t, d in zip(tendons, scene.sliding)]
    )


def pack_routes(robot):
    """The core's routing rows (nroute, 12) of the robot's helical and path tendons, or
    None when every tendon is linear (cached on the frozen robot)."""
    if "_packed_routes" not in robot.__dict__:
        ends = [robot.tendon_end(i) for i in range(robot.n_tendons)]
        object.__setattr__(robot, "_packed_routes", route_rows(robot.tendons, ends))
    return robot.__dict__["_packed_routes"]


def _nodes_for(scene: Scene, options: Options):
    nodes = options.nodes
    if isinstance(nodes, np.ndarray):
        L = scene.robot.rod.length
        if nodes[-1] > L * (1.0 + 1e-12):
            raise ValueError(f"Options.nodes must lie in [0, L={L!r}], got max {nodes[-1]!r}")
        return np.minimum(nodes, L)
    return nodes


def _structure_key(scene: Scene, options: Options):
    """What fixes the shape of the shooting problem (so a Jacobian can be reused)."""
    key = scene.__dict__.get("_structure")
    if key is None:
        rob = scene.robot
        key = (
            rob.n_tendons,
            scene.displacement_controlled(),
            rob.rod.kirchhoff,
            tuple(math.isinf(t.EA) for t in rob.tendons),
            tuple(t.friction > 0.0 for t in rob.tendons),
            is_planar(scene),
        )
        object.__setattr__(scene, "_structure", key)
    # solved spatially, planar and spatial scenes share one shape
    planar = key[-1] and not options.force_spatial
    return key[:-1] + (planar, options.force_spatial, options.slack_model)


def is_planar(scene: Scene) -> bool:
    """True when ``scene`` is solved with the planar (x-z) formulation unless
    ``Options.force_spatial``: every tendon at angle 0 or pi (``|sin angle| <= 1e-12``) and
    every load in the x-z plane.  The core's rule (``_core.is_planar``), so the answer
    is the ``formulation.planar`` a solve reports."""
    key = scene.__dict__.get("_planar")
    if key is None:
        _, tendons, loads, dist = pack_scene(scene)
        secs = pack_sections(scene.robot.rod)
        routes = pack_routes(scene.robot)
        key = bool(_core.is_planar(tendons, loads, dist, pack_dloads(scene), secs, routes))
        object.__setattr__(scene, "_planar", key)
    return key


_NO_LOADS = np.empty((0, len(_core.LOAD_COLUMNS)))


def fixed_planar(scene: Scene) -> bool:
    """:func:`is_planar` of ``scene`` with neither point loads nor a distributed force: the
    verdict of what its structure fixes (the tendons, the partial distributed loads, the
    sections and the routes)."""
    _, tendons, _, _ = pack_scene(scene)
    secs = pack_sections(scene.robot.rod)
    routes = pack_routes(scene.robot)
    dl = pack_dloads(scene)
    return bool(_core.is_planar(tendons, _NO_LOADS, np.zeros(3), dl, secs, routes))


def _robot_structure(robot) -> tuple:
    """(field path, value) pairs of the robot that fix a compiled structure (cached on the
    frozen robot, which scenes of a sweep share)."""
    key = robot.__dict__.get("_problem_structure")
    if key is None:
        rod = robot.rod
        # the density only sets a value (the weight), not the structure
        items = [
            (f"robot.rod.{name}", getattr(rod, name))
            for name in rod.__dataclass_fields__
            if name != "density"
        ]
        items.append(("robot.tendons (count)", robot.n_tendons))
        for i, t in enumerate(robot.tendons):
            for name in ("offset", "angle", "slope", "EA", "twist", "path", "friction"):
                items.append((f"robot.tendons[{i}].{name}", getattr(t, name)))
            items.append((f"robot.tendons[{i}].end", robot.tendon_end(i)))
        key = tuple(items)
        object.__setattr__(robot, "_problem_structure", key)
    return key


def _structure(scene: Scene) -> tuple:
    """(field path, value) pairs of the scene itself that fix a compiled structure, the
    robot's aside (cached on the frozen scene)."""
    key = scene.__dict__.get("_problem_structure")
    if key is None:
        L = scene.robot.rod.length
        items: list[tuple[str, object]] = [
            (f"displacement[{i}] (control kind)", "displacement" if c else "tension")
            for i, c in enumerate(scene.displacement_controlled())
        ]
        pls = scene.point_loads
        items.append(("loads (number of point loads)", len(pls)))
        for j, p in enumerate(pls):
            items.append((f"point load {j} position s", min(p.s, L)))
        for j, row in enumerate(pack_dloads(scene).tolist()):
            items.append((f"partial distributed load {j} [start, end, force]", tuple(row)))
        items.append(("sliding", scene.sliding))
        items.append(("planar formulation", is_planar(scene)))
        key = tuple(items)
        object.__setattr__(scene, "_problem_structure", key)
    return key


def _first_difference(ka: tuple, kb: tuple) -> str | None:
    if ka == kb:
        return None
    for (name, va), (_, vb) in zip(ka, kb):
        same = va == vb or (isinstance(va, float) and math.isnan(va) and math.isnan(vb))
        if not same:
            return f"{name} = {vb!r} (the problem's is {va!r})"
    return f"{ka[len(kb)][0] if len(ka) > len(kb) else kb[len(ka)][0]} differs"


def same_fields(a: Scene, b: Scene) -> bool:
    """True when scene ``b`` has the structure-defining fields of ``a`` (one robot, the
    same gravity, sliding and control kinds, point loads and point masses at the same
    arc lengths, equal partial distributed loads and point masses), so that
    ``_structure(b) == _structure(a)`` exactly when both get the same planar formulation;
    False may still be one structure (the caller then compares in full).  Only values
    differ: actuation, point-load forces and moments, whole-rod distributed forces."""
    if a.robot is not b.robot or a.gravity != b.gravity or a.sliding != b.sliding:
        return False
    da, db = a.displacement, b.displacement
    assert da is not None and db is not None  # (Scene fills them)
    if [d is None for d in da] != [d is None for d in db]:
        return False
    la, lb = a.loads, b.loads
    if len(la) != len(lb):
        return False
    for x, y in zip(la, lb):
        if x is y:
            continue
        if type(x) is not type(y):
            return False
        if isinstance(x, PointLoad) and isinstance(y, PointLoad):
            if x.s != y.s:
                return False
        elif (
            isinstance(x, DistributedLoad)
            and isinstance(y, DistributedLoad)
            and a._whole(x)
            and b._whole(y)
        ):
            continue
        elif x != y:
            return False
    return True


def structure_difference(a: Scene, b: Scene, spatial: bool = False) -> str | None:
    """None if scenes ``a`` and ``b`` share one structure, else the first field that
    differs, with both values.  ``spatial``: both are solved with the spatial
    formulation (``Options.force_spatial``), so whether each is planar does not matter."""
    if a is b:
        return None
    if a.robot is not b.robot:
        diff = _first_difference(_robot_structure(a.robot), _robot_structure(b.robot))
        if diff is not None:
            return diff
    sa, sb = _structure(a), _structure(b)
    if spatial:  # the last item is the planar formulation
        sa, sb = sa[:-1], sb[:-1]
    return _first_difference(sa, sb)


def value_vector(scene: Scene) -> np.ndarray:
    """The per-call values of ``scene`` in one float64 vector, [actuation values (nt),
    point loads (nl x 6: F [N], M [N m], world), distributed force (3) [N/m]] (cached on
    the frozen scene): what a compiled Problem takes per solve."""
    v = scene.__dict__.get("_value_vector")
    if v is None:
        if base_pose(scene.robot) is None:  # world frame: from the fields, as pack_scene
            disp = scene.displacement
            assert disp is not None and scene.tension is not None  # (Scene fills them)
            vals = [d if d is not None else t for d, t in zip(disp, scene.tension)]
            for p in scene.point_loads:
                vals += p.force
                vals += p.moment
            vals += scene.distributed_force.tolist()
            v = np.array(vals, dtype=float)
        else:
            _, tendons, loads, dist = pack_scene(scene)
            v = np.concatenate([tendons[:, _TD["value"]], loads[:, 1:7].ravel(), dist])
        v.setflags(write=False)
        object.__setattr__(scene, "_value_vector", v)
    return v


# Arc lengths within this fraction of L of the base merge with it (TR_BP_MERGE): the
# clamp takes a load there, so the compliance is not defined.
_BASE_MERGE = 1e-12


def compliance_point(s, L: float) -> float:
    """The arc length [m] of a compliance probe: ``s`` (None: the tip ``L``) as a float in
    (0, L]; ValueError naming ``s`` otherwise."""
    if s is None:
        return L
    ok = not isinstance(s, (bool, np.bool_)) and (
        isinstance(s, (numbers.Real, np.floating, np.integer))
        or (isinstance(s, np.ndarray) and s.ndim == 0 and s.dtype.kind in "fiu")
    )
    try:
        x = float(s) if ok else math.nan
    except OverflowError:
        x = math.inf
    if not (math.isfinite(x) and _BASE_MERGE * L < x <= L * (1 + 1e-12)):
        raise ValueError(
            f"s must be an arc length in (0, L={L!r}] m (farther than {_BASE_MERGE:g} L from "
            f"the clamped base), got {s!r}"
        )
    return min(x, L)


def _compile(scene: Scene, options: Options):
    """The ``_core.Problem`` (compiled model and workspace) of ``scene`` with ``options``."""
    rod, tendons, loads, dist = pack_scene(scene)
    cached = scene.__dict__.get("_compile_kw")
    if cached is not None and cached[0] is options:
        kw = cached[1]
    else:
        # the options the core's defaults lack, and the scene's tables (cached on the
        # frozen scene for the frozen options it was last compiled with)
        kw = options._core_kw
        nodes = _nodes_for(scene, options)
        if nodes is not options.nodes:
            kw = dict(kw, nodes=nodes)
        kw = _with_dloads(kw, scene)
        object.__setattr__(scene, "_compile_kw", (options, kw))
    return _core.Problem(rod, tendons, loads, dist, **kw)
