"""Cancellation of solves running in worker threads.

Ctrl-C reaches only the main thread: a solve running there stops by itself (the C
core polls Python's signal handlers).  Solves in worker threads (a threaded
``solve_batch`` or ``sweep``) poll a :class:`tendonrod._core.Cancel` token instead; the
thread that waits for them sets it when interrupted.  Code running in a worker picks
its token up with :func:`current_token`, which the worker set with
:func:`cancel_scope`.
"""

from __future__ import annotations

import contextlib
import threading

from . import _core


class _Local(threading.local):
    token = None  # a class default: a thread without a scope reads None, no lookup miss


_local = _Local()


def current_token():
    """The Cancel token of this thread's current scope, or None."""
    return _local.token


@contextlib.contextmanager
def cancel_scope(token):
    """Make ``token`` (a :class:`tendonrod._core.Cancel` or None) this thread's token."""
    old = _local.token
    _local.token = token
    try:
        yield token
    finally:
        _local.token = old


def new_token():
    """A fresh, unset Cancel token."""
    return _core.Cancel()
