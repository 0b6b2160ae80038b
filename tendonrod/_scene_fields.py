"""The value checks of scene files (:mod:`tendonrod.scenefile`): each parses one TOML
value or table and raises :class:`SceneFileError` naming the key and the problem."""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from typing import Any

__all__ = ["SceneFileError", "rotation_from_vector"]


class SceneFileError(ValueError):
    """A scene file that cannot be used: ``key`` names where, ``problem`` says what.

    Examples
    --------
    >>> try:
    ...     tr.scenefile.parse_scene({"rod": {"length": "abc"}}, "robot.toml")
    ... except tr.scenefile.SceneFileError as e:
    ...     print(e)
    robot.toml: rod.length: expected a number, got 'abc' (string)
    """

    def __init__(self, key: str, problem: str, path: str | os.PathLike | None = None):
        self.key = key
        self.problem = problem
        self.path = None if path is None else os.fspath(path)
        where = f"{self.path}: " if self.path else ""
        super().__init__(f"{where}{key}: {problem}")


def _kind(value: Any) -> str:
    """TOML's name for the type of a parsed value (for messages)."""
    if isinstance(value, bool):
        return "boolean"
    if isinstance(value, (int, float)):
        return "number"
    if isinstance(value, str):
        return "string"
    if isinstance(value, list):
        return "array"
    if isinstance(value, dict):
        return "table"
    return type(value).__name__  # dates and times


def _number(value: Any, key: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise SceneFileError(key, f"expected a number, got {value!r} ({_kind(value)})")
    if math.isnan(value):
        raise SceneFileError(key, "expected a number, got nan")
    return float(value)


def _boolean(value: Any, key: str) -> bool:
    if not isinstance(value, bool):
        raise SceneFileError(key, f"expected true or false, got {value!r} ({_kind(value)})")
    return value


def _vector3(value: Any, key: str) -> tuple[float, float, float]:
    if not isinstance(value, list):
        raise SceneFileError(key, f"expected an array of 3 numbers, got {value!r} ({_kind(value)})")
    if len(value) != 3:
        raise SceneFileError(key, f"expected an array of 3 numbers, got {len(value)} elements")
    return tuple(_number(v, f"{key}[{j}]") for j, v in enumerate(value))  # type: ignore[return-value]


def _table(value: Any, key: str) -> dict:
    if not isinstance(value, dict):
        raise SceneFileError(key, f"expected a table, got {value!r} ({_kind(value)})")
    return value


def _unknown(table: Mapping, allowed, key: str) -> None:
    for name in table:
        if name not in allowed:
            raise SceneFileError(
                f"{key}.{name}" if key else name,
                "unknown key; allowed keys are " + ", ".join(sorted(allowed)),
            )


def _build(cls, kwargs: dict, key: str):
    """Construct a library dataclass; its own ValueError/TypeError is re-raised naming `key`."""
    try:
        return cls(**kwargs)
    except (ValueError, TypeError) as exc:
        raise SceneFileError(key, str(exc)) from exc


#: The settings of ``sliding`` (``tendonrod.Scene.sliding``): the direction a frictional
#: tendon last slid in its channel.
SLIDINGS = ("in", "out")


def _parse_sliding(raw: Any, n_tendons: int, key: str = "sliding"):
    """``sliding``: one of :data:`SLIDINGS` for every tendon, or an array of them, one
    per tendon (in the order of the ``[[tendon]]`` tables)."""
    if isinstance(raw, str):
        if raw not in SLIDINGS:
            raise SceneFileError(key, f'expected "in" or "out", got {raw!r}')
        return raw
    if not isinstance(raw, list):
        raise SceneFileError(
            key, f'expected "in", "out" or an array of them, got {raw!r} ({_kind(raw)})'
        )
    if len(raw) != n_tendons:
        raise SceneFileError(
            key, f"expected one entry per tendon ({n_tendons}), got {len(raw)}: {raw!r}"
        )
    for j, v in enumerate(raw):
        if v not in SLIDINGS:
            raise SceneFileError(f"{key}[{j}]", f'expected "in" or "out", got {v!r} ({_kind(v)})')
    return list(raw)


def rotation_from_vector(phi, key: str) -> tuple:
    """The rotation matrix exp([phi]x) (3 rows) of a rotation vector ``phi`` [rad]
    (Rodrigues); SceneFileError naming ``key`` when it is not 3 finite numbers."""
    p = _vector3(phi, key)
    th = math.sqrt(sum(c * c for c in p))
    if th == 0.0:
        return ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    x, y, z = (c / th for c in p)
    c, s = math.cos(th), math.sin(th)
    C = 1.0 - c
    return (
        (c + x * x * C, x * y * C - z * s, x * z * C + y * s),
        (y * x * C + z * s, c + y * y * C, y * z * C - x * s),
        (z * x * C - y * s, z * y * C + x * s, c + z * z * C),
    )


def _parse_pose(raw: Any, key: str) -> tuple:
    """``{position = [...], rotation_vector = [...] | rotation = [[...] x 3]}`` as
    (position, rotation) for tendonrod.actuate's tip_pose."""
    table = _table(raw, key)
    _unknown(table, ("position", "rotation", "rotation_vector"), key)
    if "position" not in table:
        raise SceneFileError(f"{key}.position", "missing (required)")
    if ("rotation" in table) == ("rotation_vector" in table):
        raise SceneFileError(key, "give exactly one of rotation, rotation_vector")
    if "rotation_vector" in table:
        R = rotation_from_vector(table["rotation_vector"], f"{key}.rotation_vector")
    else:
        rot = table["rotation"]
        if not isinstance(rot, list) or len(rot) != 3:
            raise SceneFileError(
                f"{key}.rotation", f"expected an array of 3 rows of 3 numbers, got {rot!r}"
            )
        R = tuple(_vector3(row, f"{key}.rotation[{j}]") for j, row in enumerate(rot))
    return _vector3(table["position"], f"{key}.position"), R
