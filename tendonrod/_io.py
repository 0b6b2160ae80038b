"""A :class:`~tendonrod.Solution` to an ``.npz`` file and back, bit for bit.

``sol.save(path)`` writes, and ``tr.load(path)`` reads back, everything the solution
holds: the core's raw result (every array as an array of the archive, so bitwise; the
scalars, strings and nested records as JSON, whose floats round-trip exactly, NaN and
infinities included), the scene and the options.  The scene and options are written as
their dataclass fields and rebuilt by calling the classes -- only tendonrod's own
dataclasses of modules already imported are rebuilt, and nothing is unpickled, so
loading a file runs no code from it.  What is loaded is re-validated (the constructors
check the scene and options; the raw result's types and shapes are checked against the
scene, and a success's numbers must be finite): a malformed or edited file raises a
ValueError naming the file and what is wrong.  The archive's ``__tendonrod__`` entry holds the JSON: the format version, the
tendonrod version that wrote it and the encoded values; arrays are the entries ``a0``,
``a1``, ... it refers to."""

from __future__ import annotations

import dataclasses
import json
import math
import os
import struct
import sys
import tokenize
import zipfile
import zlib
from typing import Any, cast

import numpy as np

from . import _core
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


# What may be rebuilt from a file: tendonrod's own dataclasses of modules tendonrod has
# already imported (no module is imported, so nothing of a file's naming is executed).
def _class(name: str) -> type:
    """A tendonrod dataclass by ``module:qualname`` (no other class is rebuilt)."""
    if not isinstance(name, str):
        raise _Malformed(f"a dataclass name must be a string, got {name!r}")
    module, _, qualname = name.partition(":")
    if module != "tendonrod" and not module.startswith("tendonrod."):
        raise _Malformed(f"refusing to rebuild {name!r}: not a tendonrod class")
    obj: Any = sys.modules.get(module)
    for part in qualname.split(".") if obj is not None else ():
        obj = getattr(obj, part, None)
    if not (
        isinstance(obj, type)
        and dataclasses.is_dataclass(obj)
        and obj.__module__ == module
        and obj.__qualname__ == qualname
    ):
        raise _Malformed(f"{name!r} is not a tendonrod dataclass")
    return obj


def _array(arrays: Any, key: Any) -> np.ndarray:
    if not isinstance(key, str) or key not in arrays:
        raise _Malformed(f"it refers to an array {key!r} the archive does not hold")
    return arrays[key]


def _decode(tree: Any, arrays: Any) -> Any:
    if isinstance(tree, list):
        return [_decode(v, arrays) for v in tree]
    if not isinstance(tree, dict):
        return tree
    if "__array__" in tree:
        return _array(arrays, tree["__array__"])
    if "__scalar__" in tree:
        a = _array(arrays, tree["__scalar__"])
        if a.shape != ():
            raise _Malformed(f"the scalar {tree['__scalar__']!r} has shape {a.shape}")
        return a[()]
    if "__tuple__" in tree:
        return tuple(_decode(v, arrays) for v in _typed(tree["__tuple__"], list, "__tuple__"))
    if "__dict__" in tree:
        d = _typed(tree["__dict__"], dict, "__dict__")
        return {k: _decode(v, arrays) for k, v in d.items()}
    if "__dataclass__" in tree:
        cls = _class(tree["__dataclass__"])
        fields = {
            k: _decode(v, arrays) for k, v in _typed(tree.get("fields"), dict, "fields").items()
        }
        try:
            return cls(**fields)
        except TypeError as e:  # unknown or missing fields
            raise _Malformed(f"{cls.__name__}: {e}") from None
    raise _Malformed(f"unknown record in a tendonrod file: {sorted(tree)!r}")


class _Malformed(ValueError):
    """What is wrong with a file's content (read_solution adds the file's name)."""


def _typed(value: Any, kind: type, what: str) -> Any:
    if not isinstance(value, kind):
        raise _Malformed(f"{what} must be of type {kind.__name__}, got {type(value).__name__}")
    return value


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


# Malformed content shows up as one of these, from the zip reader, NumPy's .npy header
# parser, JSON, the decoding and the constructors: each becomes a ValueError naming the
# file and the part that is wrong.
_CONTENT_ERRORS = (
    ValueError,
    TypeError,
    LookupError,  # KeyError, IndexError, an unknown text encoding
    AttributeError,
    NotImplementedError,  # the zip reader: an unknown zip version or compression
    zlib.error,
    struct.error,
    OverflowError,
    EOFError,
    RecursionError,
    SyntaxError,
    tokenize.TokenError,
    zipfile.BadZipFile,
    zipfile.LargeZipFile,
    MemoryError,
    OSError,
)
# (an OSError about the path itself -- missing, a directory, not permitted -- stays one)
_PATH_ERRORS = (FileNotFoundError, IsADirectoryError, NotADirectoryError, PermissionError)


def file_kind(path: str | os.PathLike) -> str:
    """``"Trajectory"`` when ``path`` is an ``.npz`` archive whose ``format`` entry is a
    :meth:`Trajectory.save <tendonrod.Trajectory.save>` marker (a string starting with
    ``"tendonrod.Trajectory"``), else ``"Solution"``: :func:`read_solution` then reads the
    file or says what is wrong with it.  Only the archive's directory and that one entry are
    read; an OSError about the path itself (missing, a directory) is raised as open() says."""
    try:
        with open(path, "rb") as fh:
            npz = np.load(fh, allow_pickle=False)
            if not isinstance(npz, np.lib.npyio.NpzFile):
                return "Solution"
            with npz:
                if _META in npz.files or "format" not in npz.files:
                    return "Solution"
                mark = npz["format"]
                if mark.shape == () and mark.dtype.kind == "U":
                    if str(mark[()]).startswith("tendonrod.Trajectory"):
                        return "Trajectory"
    except _PATH_ERRORS:
        raise
    except _CONTENT_ERRORS:
        pass
    return "Solution"


def read_solution(path: str | os.PathLike) -> tuple[dict, Any, Any]:
    """``(raw, scene, options)`` of a solution written by :func:`save_solution`
    (:func:`tendonrod.load` makes the :class:`~tendonrod.Solution`), re-validated: the
    scene and options through their constructors, the raw result's types and shapes
    against the scene, and a success's numbers finite.  ValueError naming the file and
    what is wrong otherwise."""
    name = os.fspath(path)
    part = "the archive"
    try:
        # (opened here: NumPy leaves its own handle open when it fails on some files)
        with open(path, "rb") as fh:
            npz = np.load(fh, allow_pickle=False)
            if not isinstance(npz, np.lib.npyio.NpzFile):
                raise _Malformed("it is a single .npy array, not an .npz archive")
            with npz:
                if _META not in npz.files:
                    raise ValueError(f"{name!r} is not a file written by tendonrod")
                part = f"its {_META} entry"
                meta = npz[_META]
                if meta.shape != () or meta.dtype.kind != "U":
                    raise _Malformed(f"it is not a string (dtype {meta.dtype}, shape {meta.shape})")
                tree = _typed(json.loads(str(meta[()])), dict, "the header")
                if tree.get("format") != FORMAT or tree.get("kind") != "Solution":
                    raise ValueError(
                        f"{name!r} holds a tendonrod file of format {tree.get('format')!r} "
                        f"({tree.get('kind')!r}, written by tendonrod {tree.get('tendonrod')}); this "
                        f"tendonrod {__version__} reads Solution files of format {FORMAT}"
                    )
                part = "its arrays"
                arrays = {k: npz[k] for k in npz.files if k != _META}
        part = "its scene"
        scene = _decode(tree.get("scene"), arrays)
        part = "its options"
        options = _decode(tree.get("options"), arrays)
        part = "its result"
        raw = _typed(_decode(tree.get("raw"), arrays), dict, "the result")
        check_solution(raw, scene, options)
    except _PATH_ERRORS:
        raise
    except _CONTENT_ERRORS as e:
        if isinstance(e, ValueError) and str(e).startswith(repr(name)):
            raise
        what = str(e) if isinstance(e, _Malformed) else f"{type(e).__name__}: {e}"
        raise ValueError(
            f"{name!r} is not a valid tendonrod Solution file: {part}: {what}"
        ) from None
    return raw, scene, options


# The result's entries a Solution reads: (name, type) of scalars; arrays with shapes in
# terms of the tendon count; the entries that must be finite in a success.
_SCALARS = {
    "success": (bool,),
    "status": (int,),
    "message": (str,),
    "nit": (int,),
    "nfev": (int,),
    "njev": (int,),
    "continuation_steps": (int,),
    "residual_norm": (int, float),
    "jacobian_cond": (int, float),
    "truncation_estimate": (int, float),
    "truncation_carried": (bool,),
}
_FINITE_IN_A_SUCCESS = (
    "tension",
    "slack",
    "displacement",
    "tip_position",
    "tip_force",
    "tip_moment",
    "tip_rotation",
    "base_state",
    "unknowns",
    "s",
    "position",
    "rotation",
    "force",
    "moment",
)


def check_solution(raw: dict, scene: Any, options: Any) -> None:
    """Raise :class:`_Malformed` unless ``raw`` is the result of a solve of ``scene`` with
    ``options`` as the core writes it: types, shapes, and finite numbers in a success."""
    from .model import Scene
    from .options import Options
    from .results import Formulation

    if not isinstance(scene, Scene):
        raise _Malformed(f"the scene is a {type(scene).__name__}, not a tendonrod.Scene")
    if not isinstance(options, Options):
        raise _Malformed(f"the options are a {type(options).__name__}, not tendonrod.Options")
    nt = scene.robot.n_tendons
    for key in ("success", "status", "tension", "slack", "base_state", "formulation"):
        if key not in raw:
            raise _Malformed(f"the result has no {key!r}")
    for key, kinds in _SCALARS.items():
        v = raw.get(key)
        ok = isinstance(v, kinds) and (bool in kinds or not isinstance(v, bool))
        if key in raw and not ok:
            want = " or ".join(k.__name__ for k in kinds)
            raise _Malformed(f"the result's {key} must be of type {want}, got {v!r}")
    for key in ("nit", "nfev", "njev", "continuation_steps"):
        if raw.get(key, 0) < 0:
            raise _Malformed(f"the result's {key} is negative: {raw[key]!r}")
    form = _typed(raw["formulation"], dict, "the result's formulation")
    steps = form.get("steps")
    # (the core's range of a step count; a warm start passes it back to the core)
    top = _core.LIMITS["steps"][1]
    if not (isinstance(steps, int) and not isinstance(steps, bool) and 0 <= steps <= top):
        raise _Malformed(f"the result's formulation has no step count in [0, {top}]: {steps!r}")
    Formulation.from_dict(form)  # its fields convert (a TypeError/ValueError names one)
    _check_records(raw, nt)
    shapes = {
        "tension": (nt,),
        "slack": (nt,),
        "displacement": (nt,),
        "tip_position": (3,),
        "tip_force": (3,),
        "tip_moment": (3,),
        "tip_rotation": (3, 3),
        "base_state": (6 + 2 * nt,),
    }
    for key, v in raw.items():
        if isinstance(v, np.ndarray) and v.dtype.kind not in "fiub":
            raise _Malformed(f"the result's {key} is not a real array (dtype {v.dtype})")
    for key, shape in shapes.items():
        v = raw.get(key)
        if key in raw and not (isinstance(v, np.ndarray) and v.shape == shape):
            got = v.shape if isinstance(v, np.ndarray) else type(v).__name__
            raise _Malformed(f"the result's {key} must be an array of shape {shape}, got {got}")
    if raw["success"]:
        for key in _FINITE_IN_A_SUCCESS:
            v = raw.get(key)
            if isinstance(v, np.ndarray) and not np.all(np.isfinite(v)):
                bad = tuple(int(i) for i in np.argwhere(~np.isfinite(v))[0])
                raise _Malformed(
                    f"it says success, but its {key}{list(bad)} is {float(v[bad])} "
                    f"(a corrupt or edited file)"
                )
        for key in ("tension", "slack"):
            if np.any(raw[key] < 0):
                raise _Malformed(f"it says success, but a {key} is negative: {raw[key]!r}")
        if not math.isfinite(raw.get("residual_norm", 0.0)):
            raise _Malformed(f"it says success, but its residual_norm is {raw['residual_norm']}")


def _real_array(v: Any, ndim: int) -> bool:
    return isinstance(v, np.ndarray) and v.ndim == ndim and v.dtype.kind in "fiu"


def _check_records(raw: dict, nt: int) -> None:
    """The optional records a Solution reads later (a warm start, its stability): their
    types and shapes, so that a file that loads can be used."""
    u = raw.get("unknowns")
    if u is not None and not _real_array(u, 1):
        raise _Malformed("the result's unknowns must be a real 1-D array")
    k = 0 if u is None else u.shape[0]
    shapes = {"jacobian": (k, k), "verified_unknowns": (k,), "verified_values": (nt,)}
    for key, shape in shapes.items():
        v = raw.get(key)
        if v is not None and not (_real_array(v, len(shape)) and v.shape == shape):
            raise _Malformed(f"the result's {key} must be None or a real array of shape {shape}")
    for key in ("tip_angle", "verified_estimate", "work"):
        v = raw.get(key, 0.0)
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            raise _Malformed(f"the result's {key} must be a number, got {v!r}")
    # a step verification vouches with a finite estimate >= 0 (what a warm start passes on)
    v = raw.get("verified_estimate", 0.0)
    if raw.get("verified_unknowns") is not None and not (math.isfinite(v) and v >= 0.0):
        raise _Malformed(f"the result's verified_estimate must be finite and >= 0, got {v!r}")
    carry = raw.get("stability_carry")
    if carry is not None and not (
        isinstance(carry, tuple)
        and len(carry) == 2
        and _real_array(carry[0], 1)
        and isinstance(carry[1], str)
    ):
        raise _Malformed("the result's stability_carry must be None or (array, reason)")
    st = raw.get("stability_verdict")
    if st is None:
        return
    ok = (
        isinstance(st, dict)
        and (st.get("stable") is None or isinstance(st.get("stable"), bool))
        and isinstance(st.get("stability"), (int, float))
        and not isinstance(st.get("stability"), bool)
        and isinstance(st.get("index"), int)
        and not isinstance(st.get("index"), bool)
        and isinstance(st.get("reason"), str)
    )
    if not ok:
        raise _Malformed(f"the result's stability_verdict is not a verdict record: {st!r}")
