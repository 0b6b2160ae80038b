"""Validation of scene fields: each helper returns the value as a float (or 3-vector)
or raises ValueError naming ``owner.name`` and the value given."""

from __future__ import annotations

import math
import numbers
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from . import _core

Vec3 = tuple[float, float, float]
# what a constructor takes for a 3-vector: a tuple, a list or an array (stored as a Vec3)
Vec3Like = Sequence[float] | NDArray[np.floating]


# --------------------------------------------------------------------------- helpers
def _real(owner: str, name: str, value, *, allow_inf: bool = False) -> float:
    """``value`` as a float, or ValueError naming ``owner.name`` and the value."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(
        value, (numbers.Real, np.floating, np.integer)
    ):
        try:
            arr = np.asarray(value)
        except Exception:  # pragma: no cover - exotic objects
            arr = None
        if arr is None or arr.shape != () or arr.dtype.kind not in "fiu":
            raise ValueError(f"{owner}.{name} must be a real number, got {value!r}")
        value = arr.item()
    try:
        x = float(value)
    except OverflowError:
        raise ValueError(f"{owner}.{name} must be finite, got {value!r}") from None
    if math.isnan(x):
        raise ValueError(f"{owner}.{name} must not be NaN, got {value!r}")
    if math.isinf(x) and not allow_inf:
        raise ValueError(f"{owner}.{name} must be finite, got {value!r}")
    return x


# Range of a finite tendon EA [N]: the core's (a subnormal EA would overflow tau/EA).
_TENDON_EA_MIN, _TENDON_EA_MAX = _core.LIMITS["EA"]
_EA_MIN, _EA_MAX = _TENDON_EA_MIN, _TENDON_EA_MAX


def _positive(owner: str, name: str, value, *, allow_inf: bool = False) -> float:
    x = _real(owner, name, value, allow_inf=allow_inf)
    if not x > 0.0:
        raise ValueError(f"{owner}.{name} must be > 0, got {value!r}")
    return x


# Range of a nonzero length [m] (and of the rod's rigidities): the core's; beyond it the
# scales EI/L^2, EI/(r L) of the solver leave the normal doubles.
_LENGTH_MIN, _LENGTH_MAX = _core.LIMITS["rod"]


def _length(owner: str, name: str, value, *, zero_ok: bool = False) -> float:
    """A length [m]: > 0 (or 0 if ``zero_ok``) and within the core's range."""
    x = _nonnegative(owner, name, value) if zero_ok else _positive(owner, name, value)
    if x != 0.0 and not (_LENGTH_MIN <= x <= _LENGTH_MAX):
        raise ValueError(
            f"{owner}.{name} must lie in [{_LENGTH_MIN:g}, {_LENGTH_MAX:g}] m"
            + (" (or be 0)" if zero_ok else "")
            + f": double precision cannot carry the model's scales beyond, got {value!r}"
        )
    return x


def _nonnegative(owner: str, name: str, value) -> float:
    x = _real(owner, name, value)
    if x < 0.0:
        raise ValueError(f"{owner}.{name} must be >= 0, got {value!r}")
    return x


def _vec3(owner: str, name: str, value) -> Vec3:
    try:
        raw = np.asarray(value)
        if raw.dtype.kind == "O" and raw.ndim == 1:
            # Python ints beyond int64 (2**70) are real numbers too
            if any(isinstance(v, bool) or not isinstance(v, numbers.Real) for v in raw):
                raise TypeError
            raw = np.array([float(v) for v in raw])
        if raw.dtype.kind not in "fiu":
            raise TypeError
        arr = raw.astype(float)
    except OverflowError:
        raise ValueError(f"{owner}.{name} must be finite, got {value!r}") from None
    except (TypeError, ValueError):
        raise ValueError(
            f"{owner}.{name} must be a 3-vector of real numbers, got {value!r}"
        ) from None
    if arr.shape != (3,):
        raise ValueError(f"{owner}.{name} must be a 3-vector (shape (3,)), got {value!r}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{owner}.{name} must be finite, got {value!r}")
    return (float(arr[0]), float(arr[1]), float(arr[2]))


# A base rotation must be orthonormal to this absolute tolerance on every entry of
# R^T R - I: the integrated rotations keep orthonormality to ~1e-12 with the reference
# integrator (DESIGN.md), so a base rotation no worse than that adds no error of its own
# beyond the solver's, while a hand-typed 0.7071 (error 1e-5) is refused.
ROTATION_ATOL = 1e-12


def _rotation(owner: str, name: str, value) -> tuple:
    """A proper rotation matrix (3x3, orthonormal to ROTATION_ATOL, det +1) as a tuple of
    row tuples, or ValueError naming ``owner.name`` and the value."""
    try:
        arr = np.asarray(value)
        if arr.dtype.kind not in "fiu":
            raise TypeError
        arr = arr.astype(float)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"{owner}.{name} must be a 3x3 rotation matrix, got {value!r}") from None
    if arr.shape != (3, 3):
        raise ValueError(
            f"{owner}.{name} must be a 3x3 rotation matrix (shape (3, 3)), got {value!r}"
        )
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{owner}.{name} must be finite, got {value!r}")
    err = float(np.max(np.abs(arr.T @ arr - np.eye(3))))
    if not err <= ROTATION_ATOL:
        raise ValueError(
            f"{owner}.{name} must be orthonormal (max |R^T R - I| <= {ROTATION_ATOL:g}), "
            f"got {value!r} (max |R^T R - I| = {err:.3g})"
        )
    if np.linalg.det(arr) < 0.0:
        raise ValueError(
            f"{owner}.{name} must be a proper rotation (det +1), got {value!r} (a reflection)"
        )
    return tuple(tuple(float(x) for x in row) for row in arr)


# --------------------------------------------------------------------------- per tendon
def _actuation(name: str, values, n: int) -> tuple[float | None, ...]:
    if values is None:
        return (None,) * n
    if isinstance(values, (str, bytes)):
        raise ValueError(f"Scene.{name} must be a sequence of length {n}, got {values!r}")
    try:
        vals = list(values)
    except TypeError:
        raise ValueError(
            f"Scene.{name} must be a sequence of length {n} (one entry per "
            f"tendon, None where not prescribed), got {values!r}"
        ) from None
    if len(vals) != n:
        raise ValueError(
            f"Scene.{name} must have one entry per tendon ({n}), got {len(vals)}: {values!r}"
        )
    out: list[float | None] = []
    for i, v in enumerate(vals):
        if v is None:
            out.append(None)
            continue
        x = _real("Scene", f"{name}[{i}]", v)
        if name == "tension" and x < 0.0:
            raise ValueError(f"Scene.tension[{i}] must be >= 0 (a tendon cannot push), got {v!r}")
        out.append(x)
    return tuple(out)


def _sliding(values, n: int) -> tuple[str, ...]:
    """Scene.sliding as one "in" / "out" per tendon (ValueError naming the entry)."""
    vals = [values] * n if isinstance(values, str) else values
    try:
        vals = list(vals)
    except TypeError:
        raise ValueError(
            f'Scene.sliding must be "in", "out" or one per tendon, got {values!r}'
        ) from None
    if len(vals) != n:
        raise ValueError(
            f"Scene.sliding must have one entry per tendon ({n}), got {len(vals)}: {values!r}"
        )
    for i, v in enumerate(vals):
        if v not in ("in", "out"):
            raise ValueError(f'Scene.sliding[{i}] must be "in" or "out", got {v!r}')
    return tuple(vals)


def _option_dict(who: str, options, defaults: dict) -> dict:
    """``defaults`` updated by ``options`` (None or a dict with only their keys): the
    options dict of a study function (``tr.modes``, ``tr.simulate``); TypeError for
    another type, ValueError for an unknown key, each naming ``who``."""
    opt = dict(defaults)
    if options is None:
        return opt
    if not isinstance(options, dict):
        raise TypeError(
            f"{who}: options must be a dict with keys {sorted(defaults)}, got {options!r}"
        )
    for k, v in options.items():
        if k not in defaults:
            raise ValueError(f"{who}: options has no key {k!r} (keys: {sorted(defaults)})")
        opt[k] = v
    return opt


def _int_option(who: str, options: dict, key: str, lo: int, hi: int) -> int:
    """``options[key]`` checked to be an int (not a bool) in [lo, hi]: ValueError naming
    ``who`` and the key otherwise."""
    v = options[key]
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not lo <= v <= hi:
        raise ValueError(f"{who}: options[{key!r}] must be an int in [{lo}, {hi}], got {v!r}")
    return int(v)
