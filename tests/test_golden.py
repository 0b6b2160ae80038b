"""Golden outputs: the solver's results on the scenes of ``golden_cases.py``, bit for bit.

The stored file pins what ``tr.solve`` (with its stability verdict), ``tr.compliance``,
``Solution.at``, ``tr.solve_batch``, ``tr.sweep``, ``tr.path``, ``tr.actuate``,
``tr.jacobian``, ``tr.fit`` and warm ``Problem`` sequences return, so that refactoring
the code behind them cannot change a result unnoticed.  Bits depend on the code and on
the floating-point environment (libm's vectorised variants, NumPy's SIMD dispatch): on a platform whose
fingerprint matches the one that wrote the file the comparison is bitwise; elsewhere
the floats must agree to 1e-9 relative (round-off of a converged solve, amplified by
at most the shooting problem's condition number ~1e6 in these scenes), and the
iteration counts and the texts that print numbers (``golden_cases.LOOSE``) may differ.
"""

from __future__ import annotations

import golden_cases as G
import numpy as np
import pytest


@pytest.fixture(scope="module")
def stored():
    with np.load(G.GOLDEN) as f:
        return {k: f[k] for k in f.files}


@pytest.fixture(scope="module")
def current():
    return G.capture()


def _same_platform(stored) -> bool:
    fp = G.fingerprint()
    return all(str(stored[f"__fingerprint__/{k}"]) == str(v) for k, v in fp.items())


def _loose(key: str) -> bool:
    return key.rsplit("/", 1)[-1] in G.LOOSE


def test_same_keys(stored, current):
    want = {k for k in stored if not k.startswith("__fingerprint__")}
    if not G.HAVE_SCIPY:  # tr.fit's keys need SciPy (a bare install without the fit extra)
        want = {k for k in want if not k.startswith("fit/")}
    assert set(current) == want


def test_golden(stored, current):
    bitwise = _same_platform(stored)
    bad = []
    for key, new in current.items():
        old = stored[key]
        if old.shape != new.shape or old.dtype != new.dtype:
            bad.append(f"{key}: shape/dtype {old.shape} {old.dtype} -> {new.shape} {new.dtype}")
            continue
        if old.dtype.kind == "f":
            same_nan = np.array_equal(np.isnan(old), np.isnan(new))
            if bitwise:
                ok = same_nan and np.array_equal(old.view(np.uint64), new.view(np.uint64))
            else:
                fin = np.isfinite(old)
                scale = np.max(np.abs(old[fin]), initial=1e-300)
                # 1e-9 relative: see the module docstring
                ok = same_nan and np.allclose(new[fin], old[fin], rtol=1e-9, atol=1e-9 * scale)
            if not ok:
                d = np.abs(new - old)
                bad.append(
                    f"{key}: max |diff| {np.nanmax(d):.3g} (max |value| "
                    f"{np.nanmax(np.abs(old)):.3g})"
                )
        elif not bitwise and _loose(key):
            continue
        elif not np.array_equal(old, new):
            bad.append(f"{key}: {old.ravel()[:6]} -> {new.ravel()[:6]}")
    assert not bad, f"{len(bad)} golden outputs changed:\n" + "\n".join(bad[:60])
