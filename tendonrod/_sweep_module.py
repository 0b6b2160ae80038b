"""``tendonrod.sweep`` is a module that can be called.

``import tendonrod.sweep as m`` gives the module (its result type, measures and outcome
codes), and ``tr.sweep(scene, vary, ...)`` -- the call every example makes -- runs the
function :func:`tendonrod.sweep.sweep`.  The package's ``__init__`` gives the module
this class once it is imported."""

from __future__ import annotations

import inspect
import types
from typing import Any


class CallableModule(types.ModuleType):
    """A module whose call is its function of the same name as the module's last part."""

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        return getattr(self, self.__name__.rpartition(".")[2])(*args, **kwargs)


def make_callable(module: types.ModuleType) -> None:
    """Make ``module`` callable (its function of the same name) and give it that
    function's signature, so ``inspect.signature(tr.sweep)`` and ``help`` show it."""
    func = getattr(module, module.__name__.rpartition(".")[2])
    module.__class__ = CallableModule
    module.__signature__ = inspect.signature(func)  # type: ignore[attr-defined]
