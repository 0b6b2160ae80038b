"""Paths into frozen dataclasses, the names of what a :func:`tendonrod.sweep` varies:
``"robot.rod.length"``, ``"robot.tendons[0].EA"``, ``"displacement[0]"``,
``"loads[0].force[2]"``.  A value is replaced with :func:`dataclasses.replace`, so every
dataclass on the way validates it again."""

from __future__ import annotations

import dataclasses
import re
from typing import Any, cast

import numpy as np

__all__ = ["get_path", "set_path"]

_TOKEN = re.compile(r"\.?([A-Za-z_][A-Za-z_0-9]*)|\[(-?\d+)\]")


def _parse_path(path: str) -> list:
    tokens, pos = [], 0
    while pos < len(path):
        m = _TOKEN.match(path, pos)
        if m is None or (pos == 0 and path.startswith(".")):
            raise ValueError(
                f"path {path!r}: cannot parse at position {pos} ({path[pos:]!r}); "
                "use names and [index], e.g. 'robot.tendons[0].EA'"
            )
        tokens.append(m.group(1) if m.group(1) is not None else int(m.group(2)))
        pos = m.end()
    if not tokens:
        raise ValueError(f"path {path!r}: empty")
    return tokens


def get_path(obj: Any, path: str) -> Any:
    """The value at ``path`` (e.g. ``"robot.tendons[0].offset"``) inside ``obj``."""
    for tok in _parse_path(path):
        if (
            isinstance(tok, str)
            and dataclasses.is_dataclass(obj)
            and tok not in {f.name for f in dataclasses.fields(obj)}
        ):
            raise ValueError(f"path {path!r}: {type(obj).__name__} has no field {tok!r}")
        try:
            obj = obj[tok] if isinstance(tok, int) else getattr(obj, tok)
        except (IndexError, AttributeError, TypeError) as exc:
            raise ValueError(
                f"path {path!r}: {tok!r} does not exist in {type(obj).__name__}"
            ) from exc
    return obj


def _set(obj: Any, tokens: list, value: Any, path: str) -> Any:
    if not tokens:
        return value
    tok, rest = tokens[0], tokens[1:]
    if isinstance(tok, int):
        if isinstance(obj, np.ndarray):
            new = np.array(obj, copy=True)
            new[tok] = _set(new[tok], rest, value, path)
            return new
        if not isinstance(obj, (list, tuple)):
            raise ValueError(
                f"path {path!r}: [{tok}] indexes a {type(obj).__name__}, not a sequence"
            )
        if not -len(obj) <= tok < len(obj):
            raise ValueError(f"path {path!r}: index {tok} out of range (length {len(obj)})")
        items = list(obj)
        items[tok] = _set(items[tok], rest, value, path)
        return type(obj)(items) if isinstance(obj, tuple) else items
    if not dataclasses.is_dataclass(obj):
        raise ValueError(
            f"path {path!r}: .{tok} on a {type(obj).__name__}, which is not a dataclass"
        )
    names = {f.name for f in dataclasses.fields(obj)}
    if tok not in names:
        raise ValueError(
            f"path {path!r}: {type(obj).__name__} has no field {tok!r} "
            f"(fields: {', '.join(sorted(names))})"
        )
    new = _set(getattr(obj, tok), rest, value, path)
    return dataclasses.replace(cast(Any, obj), **{tok: new})  # an instance, checked above


def set_path(obj: Any, path: str, value: Any) -> Any:
    """A copy of the dataclass ``obj`` with the value at ``path`` replaced.

    Every dataclass on the way is rebuilt with :func:`dataclasses.replace`,
    so its ``__post_init__`` validation runs on the new value.
    """
    return _set(obj, _parse_path(path), value, path)
