#!/usr/bin/env bash
# A wheel in a bare virtual environment of its own Python, run against the quick tests.
#   tools/wheel_test.sh PYTHON WHEEL [PIP_REQUIREMENT...]
# PYTHON makes the venv (its minor version must match the wheel's tag); the wheel is
# installed with its dependencies from PyPI, plus pytest and any PIP_REQUIREMENT given
# (e.g. 'numpy==1.26.*': the oldest NumPy the package supports, instead of the newest).
# The tests run from a scratch directory, so `import tendonrod` can only find the
# installed wheel (checked first), never the source tree.  The quick tests need NumPy
# and pytest only (no SciPy, matplotlib, Dask): the package's metadata and GSL, the
# golden outputs, the model's validation, scene files, the batch API, Problem, the
# lazy imports and the one-verdict pipeline -- about 20 s.  (pyproject.toml's
# [tool.cibuildwheel] test-command runs the same files: change both together.)
set -euo pipefail
cd "$(dirname "$0")/.."
REPO=$PWD
PY=$1
WHEEL=$(readlink -f "$2")
shift 2
QUICK_TESTS=${QUICK_TESTS:-"test_package test_golden test_model test_scenefile test_batch test_problem test_lazy test_pipeline"}
WORK=$(mktemp -d /tmp/tendonrod-wheel-test.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
"$PY" -m venv "$WORK/venv"
VPY="$WORK/venv/bin/python"
# pip's own upgrade notice is noise here
export PIP_DISABLE_PIP_VERSION_CHECK=1
"$VPY" -m pip install -q "$WHEEL" pytest "$@"
cd "$WORK"
"$VPY" - "$WHEEL" <<'PYEOF'
import sys, sysconfig
import numpy, tendonrod
site = sysconfig.get_paths()["purelib"]
assert tendonrod.__file__.startswith(site), (tendonrod.__file__, site)
print(f"{sys.argv[1].rsplit('/', 1)[-1]}: Python {sys.version.split()[0]}, "
      f"NumPy {numpy.__version__}, tendonrod {tendonrod.__version__}, GSL {tendonrod.gsl_version}")
PYEOF
tests=()
for t in $QUICK_TESTS; do tests+=("$REPO/tests/$t.py"); done
# the repository's pytest configuration (warnings are errors, strict markers)
"$VPY" -m pytest -q -p no:cacheprovider -c "$REPO/pyproject.toml" --rootdir "$REPO" "${tests[@]}"
