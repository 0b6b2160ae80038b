"""Import of the compiled core, with a message that says what to do when it is missing.

Run from a source checkout whose extension was never built (after a non-editable
``pip install .``, say, Python still finds the checkout's ``tendonrod/`` first when
started in the checkout), ``from . import _core`` fails with an error that names a
circular import.  :func:`import_core` replaces it with one that says what happened and
what to do, as NumPy does.  An extension that is there but cannot load (its libgsl
missing, say) keeps its own error, with the same advice added."""

from __future__ import annotations

import importlib
import importlib.machinery
import os
from types import ModuleType

_HERE = os.path.dirname(os.path.abspath(__file__))


def _built_here() -> list[str]:
    """The extension files ``tendonrod/_core*`` next to this module."""
    suffixes = tuple(importlib.machinery.EXTENSION_SUFFIXES)
    return sorted(f for f in os.listdir(_HERE) if f.startswith("_core") and f.endswith(suffixes))


def _in_source_tree() -> bool:
    """True when this package is a checkout (setup.py and csrc/ beside it)."""
    root = os.path.dirname(_HERE)
    return os.path.exists(os.path.join(root, "setup.py")) and os.path.isdir(
        os.path.join(root, "csrc")
    )


def advice() -> str:
    """What to do about a missing or unloadable extension."""
    root = os.path.dirname(_HERE)
    if _in_source_tree():
        return (
            f"You are importing tendonrod from its source tree ({root}), where the C "
            "extension tendonrod._core is not built.  Either build it in place "
            "(`python -m pip install -e .`, or `python setup.py build_ext --inplace`; "
            "`make test` does the former), or start Python outside the source tree to "
            "use an installed tendonrod."
        )
    return (
        f"The C extension tendonrod._core of the tendonrod installed in {_HERE} is "
        "missing; reinstall tendonrod (`python -m pip install --force-reinstall tendonrod`)."
    )


def import_core() -> ModuleType:
    """``tendonrod._core``, or an ImportError saying what to do."""
    try:
        return importlib.import_module("tendonrod._core")
    except ImportError as exc:
        built = _built_here()
        if built:  # the file is there but does not load: keep its reason
            raise ImportError(
                f"tendonrod._core ({built[0]}) failed to load: {exc}.  " + advice()
            ) from exc
        raise ImportError(advice()) from None
