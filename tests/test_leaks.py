"""No leaks in the glue: long loops of ufunc calls and solves leave resident
memory and Python's object count flat.

Method: run a warm-up loop (so that NumPy's caches, the allocator's arenas and
any lazily created objects exist), then measure
  - RSS, the resident set size from /proc/self/statm (what the OS sees: C
    allocations in the core and GSL included), and
  - sys.getallocatedblocks(), the number of memory blocks CPython's object
    allocator has handed out (any Python object that is never released --
    a missing Py_DECREF on a result, an exception or an argument -- counts
    here one by one),
  - sys.getrefcount of the argument objects (a missing Py_DECREF on an
    argument in the glue raises it by one per call),
run the loop of N calls, and measure again.

Tolerances (why they are that size):
  - RSS: 4 MiB.  The smallest realistic leak per call (one 8-byte malloc,
    which costs 32 bytes with glibc's header and alignment) over 10^5 calls is
    3.2 MB, so 4 MiB still catches it at 10^5 calls (the ufunc loops) and
    catches anything of >= 420 bytes per call at 10^4 calls.  Below 4 MiB the
    test would trip on glibc's heap fragmentation and NumPy's small-array
    cache, which move RSS by a few hundred KiB between identical loops.
  - allocated blocks: 200 over >= 10^4 calls, i.e. less than one leaked
    object per 50 calls; a leak of one object per call shows up as >= 10^4.
    The 200 absorbs objects created once on first use (interned strings,
    warning registries, the cache of NumPy scalars).
  - refcounts of arguments: exactly unchanged.
"""
import gc
import os
import sys
import time
import warnings

import numpy as np
import pytest

import tendonrod as tr

RSS_TOL = 4 * 1024 * 1024      # bytes, see the module docstring
BLOCKS_TOL = 200               # objects, see the module docstring

PAGE = os.sysconf("SC_PAGE_SIZE") if hasattr(os, "sysconf") else 4096


def rss():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * PAGE


pytestmark = pytest.mark.skipif(not os.path.exists("/proc/self/statm"),
                                reason="RSS is read from /proc/self/statm (Linux)")


def measure(loop, n, warm):
    """Run loop(warm), then loop(n); return (RSS growth [bytes], block growth, seconds)."""
    loop(warm)
    gc.collect()
    r0, b0 = rss(), sys.getallocatedblocks()
    t0 = time.perf_counter()
    loop(n)
    dt = time.perf_counter() - t0
    gc.collect()
    return rss() - r0, sys.getallocatedblocks() - b0, dt


def assert_flat(what, n, drss, dblocks, dt):
    print(f"{what}: {n} calls in {dt:.2f} s, RSS {drss / 1024:+.0f} KiB, "
          f"allocated blocks {dblocks:+d}")
    assert drss < RSS_TOL, f"{what}: RSS grew by {drss / 1024:.0f} KiB over {n} calls"
    assert dblocks < BLOCKS_TOL, f"{what}: {dblocks} Python objects leaked over {n} calls"


# ------------------------------------------------------------------ ufuncs
UFUNC_ARGS = {
    "tension": (0.3, 0.12, 0.2, 4e-3, -0.02, 0.01, 5e4),
    "angle": (0.15, 0.3, 0.12, 0.2, 4e-3, -0.02, 0.01, np.inf),
    "deflection": (0.15, 0.3, 0.12, 0.2, 4e-3, -0.02, 0.01, 5e4),
    "equivalent_stiffness": (5e4, 2e5),
    "pattern_factor": (4.0,),
    "actuation_tension_for_angle": (0.5, 0.2, 4e-3, -0.02, 0.01),
    "actuation_tension_for_deflection": (0.03, 0.2, 4e-3, -0.02, 0.01),
}


def test_ufunc_loops_do_not_leak():
    """10^5 calls of every closed-form ufunc: scalars, arrays with out=, and
    out-of-domain input (the NaN/invalid-flag path), plus 10^4 calls that
    raise TypeError (the error path of NumPy's type resolution)."""
    s = np.linspace(0.0, 0.2, 16)
    out = np.empty(16)
    bad_s = np.linspace(-0.1, 0.3, 16)          # partly outside [0, L]: NaN + invalid flag
    fs = [(getattr(tr.analytic, n), a) for n, a in UFUNC_ARGS.items()]
    angle, deflection = tr.analytic.angle, tr.analytic.deflection
    args8 = UFUNC_ARGS["deflection"][1:]
    before = [sys.getrefcount(x) for x in (s, out, bad_s)]

    def loop(n):
        with np.errstate(invalid="ignore"):
            for _ in range(n):
                for f, a in fs:
                    f(*a)
                deflection(s, *args8, out=out)
                angle(bad_s, *args8)

    n = 100_000
    drss, dblocks, dt = measure(loop, n, warm=2_000)
    assert_flat("ufuncs", n * (len(fs) + 2), drss, dblocks, dt)
    assert [sys.getrefcount(x) for x in (s, out, bad_s)] == before

    def bad_loop(n):
        for _ in range(n):
            try:
                deflection("abc", *args8)
            except TypeError:
                pass

    drss, dblocks, dt = measure(bad_loop, 10_000, warm=500)
    assert_flat("ufunc TypeError path", 10_000, drss, dblocks, dt)


def test_planar_shape_loop_does_not_leak():
    """planar_shape is Python over the angle ufunc (about 0.4 ms a call, most of
    it in NumPy's leggauss); 3000 calls stay flat (a leak of one object per
    call would show as +3000 blocks)."""
    s = np.linspace(0.0, 0.2, 8)

    def loop(n):
        for _ in range(n):
            tr.analytic.planar_shape(s, 0.3, 0.12, 0.2, 4e-3, -0.02, 0.01, np.inf)

    drss, dblocks, dt = measure(loop, 3_000, warm=100)
    assert_flat("planar_shape", 3_000, drss, dblocks, dt)
