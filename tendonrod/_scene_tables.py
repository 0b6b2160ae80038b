"""The robot's tables of a scene file (:mod:`tendonrod.scenefile`): ``[rod]`` and its
``[[rod.segment]]``, ``[[tendon]]`` with its routing, ``[[load]]``, ``[distributed]``,
``[[mass]]`` and ``[disks]``, ``[base]`` -- each read into the keyword arguments of its
class, every error a :class:`~tendonrod._scene_fields.SceneFileError` naming the key."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from typing import Any

from ._scene_fields import (
    SceneFileError,
    _boolean,
    _build,
    _kind,
    _number,
    _table,
    _unknown,
    _vector3,
)
from .model import DistributedLoad, PointLoad, PointMass, Rod, Tendon

_ROD_NUMBERS = ("length", "diameter", "E", "G", "EI", "GJ", "EA", "GA", "density")
_ROD_BOOLS = ("kirchhoff",)
_TENDON_NUMBERS = (
    "offset",
    "angle",
    "slope",
    "EA",
    "end",
    "pretension",
    "displacement",
    "tension",
    "turns",
    "pitch",
    "friction",
)
_TENDON_STRINGS = ("routing",)
_ROUTINGS = ("parallel", "converging", "helical", "spline", "disks")


def _rod_kwargs(rod: Mapping, key: str) -> dict:
    fields = {f.name for f in dataclasses.fields(Rod)} - {"segments"}
    _unknown(rod, fields, key)
    kwargs: dict = {}
    for name, value in rod.items():
        if name in _ROD_BOOLS:
            kwargs[name] = _boolean(value, f"{key}.{name}")
        elif name in _ROD_NUMBERS:
            kwargs[name] = _number(value, f"{key}.{name}")
        elif name == "precurvature":
            kwargs[name] = _vector3(value, f"{key}.{name}")
        else:  # a field added to tr.Rod after this reader: pass through, the class validates
            kwargs[name] = value
    return kwargs


def _parse_rod(raw: Any, raw_segments: Any = None) -> Any:
    kwargs = _rod_kwargs(_table(raw, "rod"), "rod")
    if raw_segments is None:
        if "length" not in kwargs:
            raise SceneFileError("rod.length", "missing (required)")
        return _build(Rod, kwargs, "rod")
    if not isinstance(raw_segments, list) or not raw_segments:
        raise SceneFileError("segment", "expected an array of tables ([[segment]] sections)")
    inherited = {k: v for k, v in kwargs.items() if k != "length"}
    parts = []
    for j, raw_seg in enumerate(raw_segments):
        key = f"segment[{j}]"
        seg = _rod_kwargs(_table(raw_seg, key), key)
        if "length" not in seg:
            raise SceneFileError(f"{key}.length", "missing (required)")
        parts.append(_build(Rod, {**inherited, **seg}, key))
    rod = _build(Rod.segmented, {"parts": parts}, "segment")
    if "length" in kwargs and abs(kwargs["length"] - rod.length) > 1e-12 * rod.length:
        raise SceneFileError(
            "rod.length", f"{kwargs['length']!r} m differs from the segments' sum {rod.length!r} m"
        )
    return rod


def _parse_tendon(raw: Any, j: int, length: float):
    key = f"tendon[{j}]"
    table = _table(raw, key)
    fields = {f.name for f in dataclasses.fields(Tendon)}
    allowed = (fields - {"twist"}) | {"displacement", "tension", "routing", "turns", "pitch"}
    _unknown(table, allowed, key)
    values: dict[str, Any] = {}
    for name, value in table.items():
        if name in _TENDON_NUMBERS:
            values[name] = _number(value, f"{key}.{name}")
        elif name in _TENDON_STRINGS:
            if not isinstance(value, str):
                raise SceneFileError(
                    f"{key}.{name}", f"expected a string, got {value!r} ({_kind(value)})"
                )
            values[name] = value
        else:
            values[name] = value
    routing = values.get("routing")
    if routing in ("spline", "disks"):
        values["path"] = _parse_path(values.get("path"), routing, f"{key}.path")
        values.setdefault("offset", 0.0)
    elif "path" in values:
        raise SceneFileError(f"{key}.path", 'needs routing = "spline" or "disks"')
    for name in ("turns", "pitch"):
        if name in values and routing != "helical":
            raise SceneFileError(f"{key}.{name}", 'needs routing = "helical"')
    if "offset" not in values:
        raise SceneFileError(f"{key}.offset", "missing (required)")
    has_q, has_tau = "displacement" in values, "tension" in values
    if has_q == has_tau:
        raise SceneFileError(
            key,
            "give exactly one of 'displacement' [m] or 'tension' [N]"
            + (" (both given)" if has_q else " (neither given)"),
        )
    routing = values.pop("routing", None)
    if routing is not None:
        if routing not in _ROUTINGS:
            raise SceneFileError(
                f"{key}.routing",
                f"expected one of {', '.join(map(repr, _ROUTINGS))}, got {routing!r}",
            )
        if "slope" in values and routing != "helical":
            raise SceneFileError(f"{key}.routing", "give either routing or slope, not both")
        if routing == "helical":
            turns, pitch = values.pop("turns", None), values.pop("pitch", None)
            if (turns is None) == (pitch is None):
                raise SceneFileError(key, 'routing = "helical" needs exactly one of turns, pitch')
            if turns is not None and turns != 0.0:
                values["twist"] = 2.0 * math.pi * turns / values.get("end", length)
            elif turns is not None:
                values["twist"] = 0.0
            elif pitch == 0.0:
                raise SceneFileError(f"{key}.pitch", "must be nonzero [m per turn]")
            else:
                values["twist"] = 2.0 * math.pi / pitch
        if routing == "converging":
            end = values.get("end", length)
            if not end > 0:
                raise SceneFileError(
                    f"{key}.end", f"must be > 0 for a converging tendon, got {end!r}"
                )
            values["slope"] = -values["offset"] / end
    q = values.pop("displacement", None)
    tau = values.pop("tension", None)
    tendon = _build(Tendon, values, key)
    return tendon, q, tau


def _parse_path(raw: Any, routing: str, key: str):
    """A tendon path from rows [s, x, y] [m] (body frame), as a spline or disk pieces."""
    from .routing import Path

    if not isinstance(raw, list) or len(raw) < 2:
        raise SceneFileError(key, f"expected an array of 2 or more [s, x, y] rows, got {raw!r}")
    rows = []
    for j, row in enumerate(raw):
        if not isinstance(row, list) or len(row) != 3:
            raise SceneFileError(f"{key}[{j}]", f"expected [s, x, y] (3 numbers), got {row!r}")
        rows.append([_number(v, f"{key}[{j}][{c}]") for c, v in enumerate(row)])
    s = [r[0] for r in rows]
    pts = [r[1:] for r in rows]
    make = Path.sampled if routing == "spline" else Path.disks
    return _build(make, {"s": s, "points": pts}, key)


def _parse_load(raw: Any, j: int, length: float):
    key = f"load[{j}]"
    table = _table(raw, key)
    fields = {f.name for f in dataclasses.fields(PointLoad)}
    _unknown(table, fields, key)
    if "s" not in table:
        raise SceneFileError(f"{key}.s", "missing (required)")
    kwargs: dict[str, Any] = {}
    for name, value in table.items():
        if name == "s":
            kwargs[name] = _number(value, f"{key}.s")
        elif name in ("force", "moment"):
            kwargs[name] = _vector3(value, f"{key}.{name}")
        else:
            kwargs[name] = value
    if "force" not in kwargs and "moment" not in kwargs:
        raise SceneFileError(key, "give a force and/or a moment")
    if not 0.0 <= kwargs["s"] <= length:
        raise SceneFileError(
            f"{key}.s",
            f"must lie on the rod, 0 <= s <= rod.length = {length!r}; got {kwargs['s']!r}",
        )
    return _build(PointLoad, kwargs, key)


def _parse_distributed(raw: Any):
    table = _table(raw, "distributed")
    fields = {f.name for f in dataclasses.fields(DistributedLoad)}
    _unknown(table, fields, "distributed")
    kwargs: dict[str, Any] = {}
    for name, value in table.items():
        if name in ("force", "moment"):
            kwargs[name] = _vector3(value, f"distributed.{name}")
        elif name in ("start", "end"):
            kwargs[name] = _number(value, f"distributed.{name}")
        else:
            kwargs[name] = value
    return _build(DistributedLoad, kwargs, "distributed")


def _parse_mass(raw: Any, j: int, length: float):
    key = f"mass[{j}]"
    table = _table(raw, key)
    _unknown(table, ("s", "mass"), key)
    kwargs: dict = {}
    for name in ("s", "mass"):
        if name not in table:
            raise SceneFileError(f"{key}.{name}", "missing (required)")
        kwargs[name] = _number(table[name], f"{key}.{name}")
    if not 0.0 <= kwargs["s"] <= length:
        raise SceneFileError(
            f"{key}.s",
            f"must lie on the rod, 0 <= s <= rod.length = {length!r}; got {kwargs['s']!r}",
        )
    return _build(PointMass, kwargs, key)


def _parse_disks(raw: Any, length: float):
    """The [disks] table as PointMass.disks: count or s, and mass (one or per disk)."""
    table = _table(raw, "disks")
    _unknown(table, ("count", "s", "mass"), "disks")
    if ("count" in table) == ("s" in table):
        raise SceneFileError("disks", "give exactly one of count (equally spaced) or s [m]")
    if "count" in table:
        n = table["count"]
        if isinstance(n, bool) or not isinstance(n, int) or n < 1:
            raise SceneFileError("disks.count", f"expected an integer >= 1, got {n!r}")
        s = [length * (k + 1) / n for k in range(n)]
    else:
        raw_s = table["s"]
        if not isinstance(raw_s, list) or not raw_s:
            raise SceneFileError("disks.s", f"expected an array of arc lengths [m], got {raw_s!r}")
        s = [_number(v, f"disks.s[{j}]") for j, v in enumerate(raw_s)]
        for j, sj in enumerate(s):
            if not 0.0 <= sj <= length:
                raise SceneFileError(
                    f"disks.s[{j}]", f"must lie on the rod, 0 <= s <= rod.length = {length!r}"
                )
    if "mass" not in table:
        raise SceneFileError("disks.mass", "missing (required) [kg]")
    m = table["mass"]
    if isinstance(m, list):
        if len(m) != len(s):
            raise SceneFileError("disks.mass", f"expected 1 or {len(s)} masses, got {len(m)}")
        mass: Any = [_number(v, f"disks.mass[{j}]") for j, v in enumerate(m)]
    else:
        mass = _number(m, "disks.mass")
    return _build(PointMass.disks, {"s": s, "mass": mass}, "disks")


def _parse_base(raw: Any) -> dict:
    table = _table(raw, "base")
    _unknown(table, ("position", "rotation"), "base")
    out: dict = {}
    if "position" in table:
        out["base_position"] = _vector3(table["position"], "base.position")
    if "rotation" in table:
        rot = table["rotation"]
        if not isinstance(rot, list) or len(rot) != 3:
            raise SceneFileError(
                "base.rotation", f"expected an array of 3 rows of 3 numbers, got {rot!r}"
            )
        rows = tuple(_vector3(row, f"base.rotation[{j}]") for j, row in enumerate(rot))
        out["base_rotation"] = rows
    return out
