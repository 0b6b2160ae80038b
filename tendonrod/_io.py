"""A :class:`~tendonrod.Solution` to an ``.npz`` file and back, bit for bit.

``sol.save(path)`` writes, and ``tr.load(path)`` reads back, everything the solution
holds: the core's raw result (every array as an array of the archive, so bitwise; the
scalars, strings and nested records as JSON, whose floats round-trip exactly, NaN and
infinities included), the scene and the options.  The scene and options are written as
their dataclass fields and rebuilt by calling the classes -- only tendonrod's own
dataclasses are rebuilt, and nothing is unpickled, so loading a file runs no code from
it.  The archive's ``__tendonrod__`` entry holds the JSON: the format version, the
tendonrod version that wrote it and the encoded values; arrays are the entries ``a0``,
``a1``, ... it refers to."""

from __future__ import annotations

import dataclasses
import importlib
import json
import os
from typing import Any, cast

import numpy as np

from ._version import __version__

FORMAT = 1
_META = "__tendonrod__"


class _Encoder:
    """Values to JSON-able trees; arrays and NumPy scalars go to ``arrays``."""

    def __init__(self) -> None:
        self.arrays: dict[str, np.ndarray] = {}

    def array(self, value: np.ndarray) -> dict:
        key = f"a{len(self.arrays)}"
        self.arrays[key] = value
        return {"__array__": key}

    def __call__(self, value: Any) -> Any:
        if isinstance(value, np.ndarray):
            if value.dtype == object:
                raise TypeError("object arrays cannot be saved")
            return self.array(value)
        if isinstance(value, np.generic):  # before float: np.float64 is a float
            return {"__scalar__": self.array(np.asarray(value))["__array__"]}
        if value is None or isinstance(value, (bool, int, float, str)):
            return value
        if isinstance(value, tuple):
            return {"__tuple__": [self(v) for v in value]}
        if isinstance(value, list):
            return [self(v) for v in value]
        if isinstance(value, dict):
            if not all(isinstance(k, str) for k in value):
                raise TypeError(f"dict keys must be str to be saved: {list(value)!r}")
            return {"__dict__": {k: self(v) for k, v in value.items()}}
        if dataclasses.is_dataclass(value) and not isinstance(value, type):
            cls = type(value)
            return {
                "__dataclass__": f"{cls.__module__}:{cls.__qualname__}",
                "fields": {
                    f.name: self(getattr(value, f.name))
                    for f in dataclasses.fields(value)
                    if f.init
                },
            }
        raise TypeError(f"cannot save a value of type {type(value).__name__}: {value!r}")


def _class(name: str) -> type:
    """A tendonrod dataclass by ``module:qualname`` (no other class is rebuilt)."""
    module, _, qualname = name.partition(":")
    if module != "tendonrod" and not module.startswith("tendonrod."):
        raise ValueError(f"refusing to rebuild {name!r}: not a tendonrod class")
    obj: Any = importlib.import_module(module)
    for part in qualname.split("."):
        obj = getattr(obj, part)
    if not (isinstance(obj, type) and dataclasses.is_dataclass(obj)):
        raise ValueError(f"{name!r} is not a tendonrod dataclass")
    return obj


def _decode(tree: Any, arrays: Any) -> Any:
    if isinstance(tree, list):
        return [_decode(v, arrays) for v in tree]
    if not isinstance(tree, dict):
        return tree
    if "__array__" in tree:
        return arrays[tree["__array__"]]
    if "__scalar__" in tree:
        return arrays[tree["__scalar__"]][()]
    if "__tuple__" in tree:
        return tuple(_decode(v, arrays) for v in tree["__tuple__"])
    if "__dict__" in tree:
        return {k: _decode(v, arrays) for k, v in tree["__dict__"].items()}
    if "__dataclass__" in tree:
        fields = {k: _decode(v, arrays) for k, v in tree["fields"].items()}
        return _class(tree["__dataclass__"])(**fields)
    raise ValueError(f"unknown record in a tendonrod file: {sorted(tree)!r}")


def save_solution(sol: Any, path: str | os.PathLike) -> None:
    """Write ``sol`` (a :class:`~tendonrod.Solution`) to ``path`` (``.npz``; NumPy adds
    the suffix when it is missing)."""
    enc = _Encoder()
    tree = {
        "format": FORMAT,
        "tendonrod": __version__,
        "kind": "Solution",
        "raw": enc(dict(sol.raw)),
        "scene": enc(sol.scene),
        "options": enc(sol.options),
    }
    meta = np.array(json.dumps(tree, allow_nan=True))
    # (cast: NumPy's stub reads ** entries as its keyword arguments, e.g. allow_pickle)
    cast(Any, np.savez)(path, **{_META: meta}, **enc.arrays)


def read_solution(path: str | os.PathLike) -> tuple[dict, Any, Any]:
    """``(raw, scene, options)`` of a solution written by :func:`save_solution`
    (:func:`tendonrod.load` makes the :class:`~tendonrod.Solution`)."""
    with np.load(path, allow_pickle=False) as npz:
        if _META not in npz.files:
            raise ValueError(f"{os.fspath(path)!r} is not a file written by tendonrod")
        tree = json.loads(str(npz[_META][()]))
        if tree.get("format") != FORMAT or tree.get("kind") != "Solution":
            raise ValueError(
                f"{os.fspath(path)!r} holds a tendonrod file of format {tree.get('format')!r} "
                f"({tree.get('kind')!r}, written by tendonrod {tree.get('tendonrod')}); this "
                f"tendonrod {__version__} reads Solution files of format {FORMAT}"
            )
        arrays = {k: npz[k] for k in npz.files if k != _META}
    raw = _decode(tree["raw"], arrays)
    return raw, _decode(tree["scene"], arrays), _decode(tree["options"], arrays)
