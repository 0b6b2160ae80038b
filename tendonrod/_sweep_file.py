"""The file of a resumable :func:`tendonrod.sweep`: JSON lines, a header holding the
sweep's fingerprint, then one line per finished chunk, each flushed to disk
(``os.fsync``) before the next is recorded.  Reading it back drops a half-written last
line (a killed process) and refuses a file written by a different sweep, or in another
format version.

Format versions: 1 stored one ``"status"`` per point, the sweep's own code (0 ok,
1 not converged, 2 error).  2 (this one) stores ``"outcome"`` (that code) and
``"status"`` (the solver core's status, or -1000 where no solve returned) separately; a
version-1 file would be misread (its codes as core statuses), so it is refused."""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
from typing import Any

import numpy as np

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
            except json.JSONDecodeError:
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
                done[int(obj["chunk"])] = obj["records"]
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


def open_progress(path, fingerprint: str, npoints: int, chunksize: int, names, shape):
    """``(done, fh)``: the chunks already recorded in ``path`` (chunk -> records) and the
    file open for appending; a new file gets the sweep's header first."""
    done: dict = {}
    path = os.fspath(path)
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
                "npoints": npoints,
                "chunksize": chunksize,
                "names": list(names),
                "shape": list(shape),
            },
        )
    return done, fh
