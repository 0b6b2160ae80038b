"""Scene files: a robot, its tendons, their actuation, loads and solver options in TOML.

A scene file is read (never written to) and checked key by key before any
object is built, so a malformed file gets a message naming the key and the
problem, e.g. ``robot.toml: tendon[2].displacement: expected a number, got
'abc' (string)``.  The format, with every key, is documented in
``examples/README.md``; ``examples/*.toml`` are working examples.  In short::

    title = "free text, optional"
    gravity = [0.0, 0.0, -9.81]   # [m/s^2] world frame, optional: weighs rod.density
                                  # [kg/m^3] and the [[mass]] point masses
    sliding = "in"        # tendons with friction: "in" (toward the actuator, default) or
                          # "out"; or one per tendon, e.g. ["in", "out"]

    [rod]                 # tr.Rod: length [m], diameter [m], E [Pa], G [Pa],
    length = 0.2          # optional overrides EI, GJ [N m^2], EA, GA [N];
    diameter = 0.8e-3     # kirchhoff = true for an unshearable, inextensible rod
    E = 207e9
    G = 79.6e9
    kirchhoff = true
    precurvature = [0.0, 5.0, 0.0]  # [1/m] body frame, optional: the unstressed curvature

    [[segment]]           # optional: the backbone in segments along s, base first; each a
    length = 0.05         # [rod] table of its own (length required), keys it omits taken
    diameter = 1.2e-3     # from [rod] (whose length, if given, must be their sum)

    [[tendon]]            # one table per tendon; messages count them from 0: tendon[0], ...
    offset = 0.01         # [m] radial offset at the base
    angle = 0.0           # [rad] angular position in the cross-section
    routing = "parallel"  # "parallel" (default) | "converging" | "helical" (with turns [-]
                          # over end, or pitch [m]) | "spline" / "disks" (with path);
                          # or give slope = a
    # path = [[0.0, 0.01, 0.0], [0.1, 0.0, 0.01], [0.2, -0.01, 0.0]]  # [s, x, y] [m] body
    EA = inf              # [N] axial rigidity; TOML's inf = inextensible (default)
    end = 0.2             # [m] anchor arc length (default: the tip)
    pretension = 0.0      # [N]
    friction = 0.0        # [-] Coulomb coefficient between tendon and channel (>= 0)
    displacement = 0.005  # [m] (> 0 retracts)  -- exactly one of
    # tension = 1.0       # [N]                 -- displacement / tension

    [[load]]              # point load at arc length s, world frame
    s = 0.2               # [m]
    force = [0.0, 0.0, -1.0]    # [N]
    moment = [0.0, 0.0, 0.0]    # [N m] (optional)

    [distributed]         # uniform distributed force, world frame
    force = [0.0, 0.0, -0.25]   # [N/m]
    start = 0.0           # [m] optional: over [start, end] (default: the whole rod)
    end = 0.2             # [m]

    [[mass]]              # point mass at arc length s (weighs only under gravity)
    s = 0.1               # [m]
    mass = 0.002          # [kg]

    [disks]               # spacer disks with equal (or listed) masses, weighed by gravity
    count = 10            # equally spaced at s = L/count, 2 L/count, ..., L; or
    # s = [0.02, 0.04]    # [m] their arc lengths
    mass = 0.002          # [kg] each (or an array, one per disk)

    [base]                # the base pose (default: the origin, base frame = world)
    position = [0.0, 0.0, 0.0]                         # [m] world frame
    rotation = [[0, 0, 1], [0, 1, 0], [-1, 0, 0]]      # columns: base axes in the world

    [options]             # any field of tr.Options, passed through by name

    [target]              # optional: what ``python -m tendonrod actuate`` reaches
    tip_angle = "45deg"   # [rad] a number, or a string "45deg" / "0.8rad" (planar scenes)
    # tip_direction = [1.0, 0.0, 1.0]   # or the tip tangent, world frame
    # tip_position = [0.1, 0.0, 0.15]   # or the tip position [m], world frame
    # tip_pose = {position = [0.1, 0.0, 0.15], rotation_vector = [0.0, 1.2, 0.0]}
    #                     # or the tip pose: position [m] and rotation (world), as a
    #                     # rotation vector [rad] or rotation = [[...], [...], [...]]
    tendons = [0]         # the actuated tendons (default: all)
    min_tension = 0.0     # [N] (more controls than target components)

Functions: :func:`load_scene` (path -> :class:`SceneSpec`), :func:`parse_scene`
(dict -> :class:`SceneSpec`).  Errors are :class:`SceneFileError` (a
``ValueError``) with ``.key`` and ``.problem``.
"""

from __future__ import annotations

import dataclasses
import math
import os
import sys
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from ._scene_fields import (
    SceneFileError,
    _build,
    _kind,
    _number,
    _parse_pose,
    _parse_sliding,
    _table,
    _unknown,
    _vector3,
)
from ._scene_tables import (
    _parse_base,
    _parse_disks,
    _parse_distributed,
    _parse_load,
    _parse_mass,
    _parse_rod,
    _parse_tendon,
)
from .model import Robot, Scene
from .options import Options

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib

__all__ = [
    "SceneFileError",
    "SceneSpec",
    "load_scene",
    "parse_scene",
    "parse_angle",
    "TOP_LEVEL_KEYS",
]


@dataclass(frozen=True)
class SceneSpec:
    """What a scene file describes.

    Attributes
    ----------
    scene : tendonrod.Scene
        The robot, actuation and loads.
    options : tendonrod.Options or None
        Solver options from the ``[options]`` table (None: the defaults).
    title : str
        The file's ``title`` (empty if absent).
    source : str or None
        The path the scene was read from.
    target : dict or None
        The ``[target]`` table as keyword arguments of :func:`tendonrod.actuate`
        (angles in radians), or None.

    Examples
    --------
    >>> data = {"rod": {"length": 0.2, "diameter": 8e-4, "E": 207e9, "G": 79.6e9},
    ...         "tendon": [{"offset": 0.01, "tension": 1.0}]}
    >>> spec = tr.scenefile.parse_scene(data)
    >>> spec.scene.robot.n_tendons, spec.options, spec.title
    (1, None, '')
    """

    scene: Any
    options: Any = None
    title: str = ""
    source: str | None = None
    target: Any = None


TOP_LEVEL_KEYS = (
    "title",
    "rod",
    "segment",
    "tendon",
    "load",
    "distributed",
    "gravity",
    "sliding",
    "mass",
    "disks",
    "base",
    "options",
    "target",
)
TARGET_KINDS = ("tip_angle", "tip_direction", "tip_position", "tip_pose")


def _parse_options(raw: Any):
    table = _table(raw, "options")
    fields = {f.name for f in dataclasses.fields(Options)}
    _unknown(table, fields, "options")
    return _build(Options, dict(table), "options")


def parse_angle(value: Any, key: str) -> float:
    """An angle [rad] from a number (radians) or a string with a unit, ``"45deg"``,
    ``"45 deg"``, ``"0.8rad"`` (a bare number in a string: radians); SceneFileError
    naming ``key`` otherwise.

    Examples
    --------
    >>> from tendonrod.scenefile import parse_angle
    >>> round(parse_angle("45deg", "target.tip_angle"), 6), parse_angle(0.5, "x")
    (0.785398, 0.5)
    """
    if isinstance(value, str):
        text = value.strip().lower()
        for unit, factor in (("deg", math.pi / 180.0), ("rad", 1.0), ("", 1.0)):
            if text.endswith(unit):
                try:
                    number = float(text[: len(text) - len(unit)])
                except ValueError:
                    break
                if math.isfinite(number):
                    return number * factor
                break
        raise SceneFileError(
            key, f"expected an angle such as 45deg or 0.8rad (or a number in rad), got {value!r}"
        )
    number = _number(value, key)
    if not math.isfinite(number):
        raise SceneFileError(key, f"expected a finite angle, got {value!r}")
    return number


def _parse_target(raw: Any, n_tendons: int) -> dict:
    """The [target] table as keyword arguments of tendonrod.actuate."""
    table = _table(raw, "target")
    _unknown(table, TARGET_KINDS + ("tendons", "min_tension", "tol"), "target")
    kinds = [k for k in TARGET_KINDS if k in table]
    if len(kinds) != 1:
        raise SceneFileError(
            "target", f"give exactly one of {', '.join(TARGET_KINDS)}; got {kinds or 'none'}"
        )
    kind = kinds[0]
    key = f"target.{kind}"
    out: dict = {}
    if kind == "tip_angle":
        out[kind] = parse_angle(table[kind], key)
    elif kind == "tip_pose":
        out[kind] = _parse_pose(table[kind], key)
    else:
        out[kind] = _vector3(table[kind], key)
    if "tendons" in table:
        idx = table["tendons"]
        if not isinstance(idx, list) or not idx:
            raise SceneFileError(
                "target.tendons", f"expected an array of tendon indices, got {idx!r}"
            )
        for j, i in enumerate(idx):
            if isinstance(i, bool) or not isinstance(i, int) or not 0 <= i < n_tendons:
                raise SceneFileError(
                    f"target.tendons[{j}]",
                    f"expected a tendon index in 0..{n_tendons - 1}, got {i!r}",
                )
        out["tendons"] = list(idx)
    for name in ("min_tension", "tol"):
        if name in table:
            out[name] = _number(table[name], f"target.{name}")
    return out


def parse_scene(data: Mapping[str, Any], source: str | None = None) -> SceneSpec:
    """Build a :class:`SceneSpec` from an already parsed TOML document (a dict).

    Raises :class:`SceneFileError` naming the offending key.

    Examples
    --------
    >>> data = {"rod": {"length": 0.2, "diameter": 8e-4, "E": 207e9, "G": 79.6e9},
    ...         "tendon": [{"offset": 0.01, "tension": 1.0}]}
    >>> tr.solve(tr.scenefile.parse_scene(data).scene).success
    True
    """
    try:
        if not isinstance(data, Mapping):
            raise SceneFileError("(document)", f"expected a table, got {_kind(data)}")
        _unknown(data, TOP_LEVEL_KEYS, "")
        title = data.get("title", "")
        if not isinstance(title, str):
            raise SceneFileError("title", f"expected a string, got {title!r} ({_kind(title)})")
        if "rod" not in data:
            raise SceneFileError("rod", "missing (required): a [rod] table with at least length")
        rod = _parse_rod(data["rod"], data.get("segment"))
        raw_tendons = data.get("tendon", [])
        if not isinstance(raw_tendons, list):
            raise SceneFileError("tendon", "expected an array of tables ([[tendon]] sections)")
        tendons, qs, taus = [], [], []
        for j, raw in enumerate(raw_tendons):
            t, q, tau = _parse_tendon(raw, j, rod.length)
            tendons.append(t)
            qs.append(q)
            taus.append(tau)
        raw_loads = data.get("load", [])
        if not isinstance(raw_loads, list):
            raise SceneFileError("load", "expected an array of tables ([[load]] sections)")
        loads = [_parse_load(raw, j, rod.length) for j, raw in enumerate(raw_loads)]
        if "distributed" in data:
            loads.append(_parse_distributed(data["distributed"]))
        raw_masses = data.get("mass", [])
        if not isinstance(raw_masses, list):
            raise SceneFileError("mass", "expected an array of tables ([[mass]] sections)")
        loads += [_parse_mass(raw, j, rod.length) for j, raw in enumerate(raw_masses)]
        if "disks" in data:
            loads += _parse_disks(data["disks"], rod.length)
        base = _parse_base(data["base"]) if "base" in data else {}
        robot = _build(Robot, {"rod": rod, "tendons": tendons}, "tendon")
        if base:
            robot = _build(Robot, {"rod": rod, "tendons": tendons, **base}, "base")
        scene_kw = {"robot": robot, "displacement": qs, "tension": taus, "loads": loads}
        if "gravity" in data:
            scene_kw["gravity"] = _vector3(data["gravity"], "gravity")
        if "sliding" in data:
            scene_kw["sliding"] = _parse_sliding(data["sliding"], len(tendons))
        scene = _build(Scene, scene_kw, "scene")
        options = _parse_options(data["options"]) if "options" in data else None
        target = _parse_target(data["target"], len(tendons)) if "target" in data else None
    except SceneFileError as exc:
        if source is not None and exc.path is None:
            raise SceneFileError(exc.key, exc.problem, source) from exc.__cause__
        raise
    except RecursionError:  # a value nested deeper than Python recurses
        raise SceneFileError("(structure)", "arrays or tables nested too deep", source) from None
    return SceneSpec(scene=scene, options=options, title=title, source=source, target=target)


def load_scene(path: str | os.PathLike) -> SceneSpec:
    """Read a scene file (opened read-only; never modified).

    Raises :class:`SceneFileError` (a ``ValueError``) naming the key and the
    problem, or ``OSError`` if the file cannot be read.

    Examples
    --------
    >>> import os, tempfile
    >>> path = os.path.join(tempfile.mkdtemp(), "robot.toml")
    >>> with open(path, "w") as fh:
    ...     _ = fh.write('[rod]\\nlength = 0.2\\nEI = 4e-3\\nGJ = 3e-3\\nkirchhoff = true\\n')
    >>> tr.scenefile.load_scene(path).scene.robot.rod.length
    0.2
    """
    with open(path, "rb") as fh:
        raw = fh.read()
    try:
        data = tomllib.loads(raw.decode("utf-8"))
    except UnicodeDecodeError as exc:
        raise SceneFileError("(file)", f"not UTF-8 text: {exc}", path) from exc
    except tomllib.TOMLDecodeError as exc:
        raise SceneFileError("(syntax)", f"not valid TOML: {exc}", path) from exc
    except RecursionError:  # the parser recurses once per level of nesting
        raise SceneFileError(
            "(syntax)", "arrays or tables nested too deep for the TOML parser", path
        ) from None
    return parse_scene(data, source=os.fspath(path))
