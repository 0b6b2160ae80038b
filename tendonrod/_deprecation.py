"""Old spellings of the API, kept working for one release with a ``DeprecationWarning``.

The policy (CONTRIBUTING.md, docs/guide/deprecations.md): a renamed or moved name keeps
working for the next minor release after the one that renamed it (deprecated in 0.2,
removed in 0.3), warning the first time each old spelling is used in a process, the
warning naming the new spelling and the release that removes the old one.
"""

from __future__ import annotations

import functools
import inspect
import sys
import types
import warnings
from collections.abc import Callable
from typing import Any, ParamSpec, TypeVar

__all__ = ["deprecated", "renamed_keywords", "keyword_only", "old_module"]

SINCE = "0.2"
REMOVED_IN = "0.3"

_warned: set[str] = set()
"""The old spellings already warned about in this process (each warns once)."""

_P = ParamSpec("_P")
_R = TypeVar("_R")


def deprecated(old: str, new: str) -> None:
    """Warn, once per process, that ``old`` is deprecated in favour of ``new`` (the
    warning attributed to the user's line)."""
    if old in _warned:
        return
    _warned.add(old)
    from .plausibility import _user_stacklevel

    warnings.warn(
        f"{old} is deprecated since tendonrod {SINCE} and will be removed in {REMOVED_IN}: "
        f"use {new}",
        DeprecationWarning,
        stacklevel=_user_stacklevel(),
    )


def renamed_keywords(who: str, **old_to_new: str) -> Callable[[Callable[_P, _R]], Callable[_P, _R]]:
    """A decorator: the keyword ``old`` of ``who`` is accepted as ``new`` (with the warning);
    both given raise ``TypeError`` naming them."""

    def wrap(func: Callable[_P, _R]) -> Callable[_P, _R]:
        @functools.wraps(func)
        def inner(*args: Any, **kwargs: Any) -> Any:
            for old, new in old_to_new.items():
                if old in kwargs:
                    if new in kwargs:
                        raise TypeError(f"{who}: give {new}= only ({old}= is its old name)")
                    deprecated(f"{who}({old}=)", f"{new}=")
                    kwargs[new] = kwargs.pop(old)
            return func(*args, **kwargs)

        return inner

    return wrap


def keyword_only(
    who: str, n_positional: int, names: tuple[str, ...]
) -> Callable[[Callable[_P, _R]], Callable[_P, _R]]:
    """A decorator: arguments past the first ``n_positional`` given by position (the old
    signature, where ``names`` followed them positionally) are passed as those keywords,
    with the warning."""

    def wrap(func: Callable[_P, _R]) -> Callable[_P, _R]:
        @functools.wraps(func)
        def inner(*args: Any, **kwargs: Any) -> Any:
            if len(args) > n_positional:
                extra = args[n_positional:]
                if len(extra) > len(names):
                    raise TypeError(
                        f"{who} takes at most {n_positional + len(names)} positional "
                        f"arguments ({n_positional} now), got {len(args)}"
                    )
                for name, value in zip(names, extra):
                    if name in kwargs:
                        raise TypeError(f"{who}: {name} given by position and by keyword")
                    kwargs[name] = value
                given = ", ".join(f"{n}=" for n in names[: len(extra)])
                deprecated(f"{who} with {given} by position", f"{given} as keyword(s)")
                args = args[:n_positional]
            return func(*args, **kwargs)

        return inner

    return wrap


class _CallableModule(types.ModuleType):
    """An old module that was also the function of its name (``tr.sweep``, ``tr.path``):
    importing it rebinds the package's attribute to the module, so the module stays
    callable for as long as it lives."""

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        return self.__dict__["_function"](*args, **kwargs)


def old_module(name: str, new: str, function: Callable[..., Any]) -> None:
    """Turn the module ``name`` (being imported) into the deprecated alias of ``new``: warn
    (once), and make it callable as ``function``."""
    deprecated(f"the module {name}", f"{new} (tendonrod.{function.__name__} is the function)")
    module = sys.modules[name]
    module.__class__ = _CallableModule
    module.__dict__["_function"] = function
    module.__dict__["__signature__"] = inspect.signature(function)
