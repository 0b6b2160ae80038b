"""Deprecated since 0.2 (removed in 0.3): the module is :mod:`tendonrod.sweeps`;
``tendonrod.sweep`` is the function :func:`tendonrod.sweeps.sweep`."""

from ._deprecation import old_module
from .sweeps import *  # noqa: F403
from .sweeps import sweep

old_module(__name__, "tendonrod.sweeps", sweep)
