"""The progress bar of a :func:`tendonrod.sweep` (tqdm), and when it shows.

``progress=None`` (the default) shows a bar when the session is interactive -- standard
error is a terminal, or the code runs in a Jupyter kernel -- and not in CI (the
environment variable ``CI`` set, as CI services and ``.ci/run`` set it), and only on a
long sweep: the bar appears once the sweep has run for :data:`DELAY` seconds (a short
sweep prints nothing).  ``TENDONROD_PROGRESS=0`` in the environment turns the default
off.  ``progress=True`` always shows it (a warning when tqdm is not installed);
``progress=False`` never."""

from __future__ import annotations

import os
import sys
import warnings
from typing import Any

DELAY = 2.0
"""Seconds a sweep runs before its default bar appears [s]."""


def _truthy(value: str | None) -> bool:
    return value is not None and value.strip().lower() not in ("", "0", "false", "no", "off")


def in_notebook() -> bool:
    """True inside a Jupyter kernel (an IPython shell that talks ZMQ)."""
    ipython = sys.modules.get("IPython")
    if ipython is None or "ipykernel" not in sys.modules:
        return False
    shell = getattr(ipython, "get_ipython", lambda: None)()
    return shell is not None and type(shell).__name__ == "ZMQInteractiveShell"


def wanted(progress: bool | None) -> bool:
    """Whether a sweep shows a bar (see the module docstring)."""
    if progress is not None:
        return bool(progress)
    env = os.environ
    if "TENDONROD_PROGRESS" in env and not _truthy(env["TENDONROD_PROGRESS"]):
        return False
    if _truthy(env.get("CI")):
        return False
    if in_notebook():
        return True
    isatty = getattr(sys.stderr, "isatty", None)
    return bool(isatty and isatty())


def _tqdm_class(notebook: bool) -> Any:
    """tqdm's notebook widget in a notebook with ipywidgets, else the text bar (which a
    notebook shows too; tqdm.auto would warn that ipywidgets is missing)."""
    if notebook:
        try:
            import ipywidgets  # noqa: F401
            from tqdm.notebook import tqdm as nb_tqdm

            return nb_tqdm
        except ImportError:
            pass
    from tqdm import tqdm

    return tqdm


def progress_bar(progress: bool | None, npoints: int, done: dict) -> Any:
    """A tqdm bar for a sweep of ``npoints`` points of which the chunks ``done`` are
    finished, or None (not wanted, or tqdm missing: with ``progress=True`` that warns)."""
    if not wanted(progress):
        return None
    try:
        cls = _tqdm_class(in_notebook())
    except ImportError:
        if progress:
            # stacklevel 4: the warning points at the caller of sweep()
            warnings.warn(
                "progress=True but tqdm is not installed (pip install 'tendonrod[progress]'); "
                "running quietly",
                stacklevel=4,
            )
        return None
    return cls(
        total=npoints,
        initial=sum(len(r) for r in done.values()),
        unit="pt",
        desc="sweep",
        delay=0.0 if progress else DELAY,
        file=None if cls.__module__ == "tqdm.notebook" else sys.stderr,
        disable=False,
    )
