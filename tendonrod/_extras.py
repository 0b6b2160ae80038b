"""Optional dependencies: the extra of the package that installs each, and the error a
missing one raises (a ``ModuleNotFoundError`` whose message is the pip command that
fixes it).  The extras themselves are declared in pyproject.toml."""

from __future__ import annotations

import importlib
from types import ModuleType

#: top-level module -> the extra that installs it (``pip install 'tendonrod[extra]'``)
EXTRAS: dict[str, str] = {
    "matplotlib": "plot",
    "tqdm": "progress",
    "scipy": "fit",
    "dask": "dask",
    "distributed": "dask",
    "plotly": "view",
}


class MissingExtraError(ModuleNotFoundError):
    """An optional dependency is not installed; the message names the extra to install."""


def install_hint(module: str) -> str | None:
    """``pip install 'tendonrod[extra]'`` for the extra that brings ``module`` (a dotted
    name; its top-level package decides), or None for a module no extra brings."""
    extra = EXTRAS.get(module.split(".")[0])
    return None if extra is None else f"pip install 'tendonrod[{extra}]'"


def missing(module: str, feature: str) -> MissingExtraError:
    """The error for ``feature`` (what the user asked for) needing ``module``."""
    top = module.split(".")[0]
    return MissingExtraError(
        f"{feature} needs {top}, which is not installed: {install_hint(top)}", name=top
    )


def optional_import(module: str, feature: str) -> ModuleType:
    """Import ``module`` (one that an extra installs), or raise :class:`MissingExtraError`
    naming the extra when it (its top-level package) is not installed."""
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as exc:
        top = module.split(".")[0]
        if exc.name is None or exc.name.split(".")[0] != top:
            raise  # something the module itself needs: not ours to name
        raise missing(module, feature) from exc
