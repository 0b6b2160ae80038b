"""The file of a resumable :func:`tendonrod.sweep`: JSON lines, a header holding the
sweep's fingerprint, then one line per finished chunk, each flushed to disk
(``os.fsync``) before the next is recorded.  Reading it back drops a half-written last
line (a killed process) and refuses a file written by a different sweep, or in another
format version.

Format versions: 1 stored one ``"status"`` per point, the sweep's own code (0 ok,
1 not converged, 2 error).  2 (this one) stores ``"outcome"`` (that code) and
``"status"`` (the solver core's status, or -1000 where no solve returned) separately; a
version-1 file would be misread (its codes as core statuses), so it is refused.

The header also records the tendonrod version that wrote the file, and the fingerprint
includes it: points computed by another version are not mixed with this one's.  A file
of another version (or of none: written before the header recorded it) is moved aside to
``<path>.tendonrod-<version>`` with a warning saying so, and the sweep starts afresh."""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import warnings
from typing import Any

import numpy as np

from .._version import __version__

_FORMAT_VERSION = 2


def _jsonable(value: Any) -> Any:
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, (np.floating, np.integer, np.bool_)):
        return value.item()
    return value


def fingerprint_of(
    base, names, point_values, chunksize, measure, build, options, warm_start
) -> str:
    """SHA-256 of everything that fixes a sweep's results (the file header holds it)."""

    def ident(f):
        # functions by module + qualified name; callable objects by their class (and, for
        # dataclasses, their fields) -- never by a repr holding a memory address, which
        # would change from one process to the next and make every file look foreign
        if f is None:
            return None
        if hasattr(f, "__qualname__"):
            return (getattr(f, "__module__", ""), f.__qualname__)
        cls = type(f)
        return (cls.__module__, cls.__qualname__, repr(f) if dataclasses.is_dataclass(f) else "")

    payload = repr(
        (
            _FORMAT_VERSION,
            __version__,
            repr(base),
            list(names),
            [[repr(_jsonable(np.asarray(v))) for v in row] for row in point_values],
            chunksize,
            ident(measure),
            ident(build),
            repr(options),
            bool(warm_start),
        )
    )
    return hashlib.sha256(payload.encode()).hexdigest()


def _read_progress(path: str, fingerprint: str, npoints: int) -> dict:
    """Chunks already recorded in ``path`` -> their records; drops a torn last line."""
    done: dict = {}
    with open(path, "rb+") as fh:
        raw = fh.read()
        good_end = 0
        lines = raw.split(b"\n")
        complete = lines[:-1]  # the last element follows the last newline
        for n, line in enumerate(complete):
            try:
                obj = json.loads(line)
            except (json.JSONDecodeError, UnicodeDecodeError, RecursionError):
                break  # torn write (killed mid-line): drop it and the rest
            if n == 0:
                _check_version(path, obj)
                found = obj.get("fingerprint") if isinstance(obj, dict) else None
                if found != fingerprint:
                    raise ValueError(
                        f"path {path!r} holds results of a different sweep (fingerprint "
                        f"{found!r}); choose another path or delete the file"
                    )
            else:
                try:
                    done[int(obj["chunk"])] = obj["records"]
                except (TypeError, KeyError, ValueError, OverflowError):
                    raise ValueError(
                        f"path {path!r}: line {n + 1} is not a chunk of sweep results "
                        f"({line[:80]!r}); choose another path or delete the file"
                    ) from None
            good_end += len(line) + 1
        if good_end == 0:
            raise ValueError(f"path {path!r} exists but has no sweep header; not overwriting it")
        if good_end != len(raw):  # cut the torn tail so appends start on a clean line
            fh.truncate(good_end)
    return done


def _check_version(path: str, header: Any) -> None:
    """Refuse a sweep file of another format version, naming both versions."""
    version = header.get("tendonrod_sweep") if isinstance(header, dict) else None
    if version is None or version == _FORMAT_VERSION:
        return  # no version: not a sweep header at all (the fingerprint check says so)
    why = (
        " (version 1 stored the sweep's own codes as 'status'; they are now 'outcome', "
        "and 'status' is the solver core's)"
        if version == 1
        else ""
    )
    raise ValueError(
        f"path {path!r} is a sweep file of format version {version!r}; this tendonrod "
        f"reads and writes format version {_FORMAT_VERSION} only{why}; rerun the sweep "
        "with another path or delete the file"
    )


def append_line(fh, obj: dict) -> None:
    """Append ``obj`` as one JSON line and force it to disk."""
    fh.write(json.dumps(obj, allow_nan=True, separators=(",", ":")) + "\n")
    fh.flush()
    os.fsync(fh.fileno())


def _written_by(path: str) -> str | None:
    """The tendonrod version in the header of the sweep file ``path``: the version string,
    ``"unknown"`` for a sweep header without one, None when the first line is no sweep
    header (the fingerprint check reports that)."""
    with open(path, "rb") as fh:
        first = fh.readline()
    try:
        header = json.loads(first)
    except (json.JSONDecodeError, UnicodeDecodeError, RecursionError):
        return None
    if not isinstance(header, dict) or "tendonrod_sweep" not in header:
        return None
    return str(header.get("tendonrod", "unknown"))


def _set_aside(path: str, version: str) -> None:
    """Move a sweep file written by tendonrod ``version`` out of the way, with a warning
    (its points are computed again by this version)."""
    kept = f"{path}.tendonrod-{version}"
    n = 1
    while os.path.exists(kept):
        n += 1
        kept = f"{path}.tendonrod-{version}.{n}"
    os.replace(path, kept)
    warnings.warn(
        f"sweep file {path!r} was written by tendonrod {version}, this is tendonrod "
        f"{__version__}: not resuming from it; every point is computed again (the old "
        f"file is kept as {kept!r})",
        UserWarning,
        stacklevel=4,  # the caller of sweep()
    )


def open_progress(path, fingerprint: str, npoints: int, chunksize: int, names, shape):
    """``(done, fh)``: the chunks already recorded in ``path`` (chunk -> records) and the
    file open for appending; a new file gets the sweep's header first.  A file written by
    another tendonrod version is set aside (:func:`_set_aside`) and a new one begun."""
    done: dict = {}
    path = os.fspath(path)
    if os.path.isdir(path):
        raise ValueError(f"path {path!r} is a directory; give the name of a sweep file")
    if os.path.exists(path) and os.path.getsize(path) > 0:
        version = _written_by(path)
        if version is not None and version != __version__:
            _set_aside(path, version)
    if os.path.exists(path) and os.path.getsize(path) > 0:
        done = _read_progress(path, fingerprint, npoints)
        fh = open(path, "a", encoding="utf-8")
    else:
        fh = open(path, "w", encoding="utf-8")
        append_line(
            fh,
            {
                "tendonrod_sweep": _FORMAT_VERSION,
                "fingerprint": fingerprint,
                "tendonrod": __version__,
                "npoints": npoints,
                "chunksize": chunksize,
                "names": list(names),
                "shape": list(shape),
            },
        )
    return done, fh
