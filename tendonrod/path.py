"""Deprecated since 0.2 (removed in 0.3): the module is :mod:`tendonrod.continuation`;
``tendonrod.path`` is the function :func:`tendonrod.continuation.path`."""

from ._deprecation import old_module
from .continuation import *  # noqa: F403
from .continuation import Branch, path

Path = Branch  # the result's name before 0.2

old_module(__name__, "tendonrod.continuation", path)
