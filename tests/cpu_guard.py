"""Hang guards that count work, not seconds of a possibly busy machine: a child process
is stopped by the kernel (SIGXCPU) once it has used so many seconds of CPU time
(RLIMIT_CPU), and a wall-clock backstop far beyond that stops a child that blocks
without using CPU (a deadlock).  Instrumented runs (make sanitize) stretch both by
TR_HANG_GUARD_SCALE."""

import math
import os
import resource

# the wall-clock backstop, in multiples of the CPU-time limit: a machine loaded 10x
# does not reach it
WALL_BACKSTOP = 20
SCALE = float(os.environ.get("TR_HANG_GUARD_SCALE", "1"))


def limited(cpu_seconds: float) -> dict:
    """Keyword arguments of subprocess.run / Popen.communicate's caller: ``preexec_fn``
    setting the CPU-time limit and ``timeout``, the wall-clock backstop."""
    n = int(math.ceil(cpu_seconds * SCALE))

    def set_limit():
        resource.setrlimit(resource.RLIMIT_CPU, (n, n + 5))

    return dict(preexec_fn=set_limit, timeout=WALL_BACKSTOP * n)
