"""The deprecated setters of a compiled model (``tr_model_set_values``, ``_pretension``,
``_target``, kept for one release of the C library) against what replaced them: a
model compiled with the new values, and a workspace given them by ``tr_data_set_*``.
Built straight from csrc/ like the other C-level tests (``csrc/tests/deprecated_setters.c``)."""

import subprocess

from test_c_core import CSRC, build  # noqa: F401  (the module's compiler fixture)


def test_deprecated_setters_match_their_replacements(build):  # noqa: F811
    exe = build(CSRC / "tests" / "deprecated_setters.c")
    r = subprocess.run([str(exe)], capture_output=True, text=True, timeout=300)
    # bitwise the same status, counts, tip state, tensions, slacks and displacements
    # three ways, for values and a load, pretensions and a tip target; a refused value
    # leaves the model and the workspace as they were
    assert r.returncode == 0 and r.stdout.strip().endswith("ok"), r.stdout + r.stderr
