"""The value checks of scene files (:mod:`tendonrod.scenefile`): each parses one TOML
value or table and raises :class:`SceneFileError` naming the key and the problem."""

from __future__ import annotations

import math
import os
from collections.abc import Mapping
from typing import Any

__all__ = ["SceneFileError"]


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
