#!/usr/bin/env bash
# make wheel-check: install the repaired wheel (dist/) into a bare virtual environment
# and solve a scene there with the system's libgsl masked -- in a private mount
# namespace (unshare -m) an empty file is bind-mounted over every libgsl*.so* of the
# system -- so the solve can only pass on the copy of GSL inside the wheel.  Proves the
# masking first: in the same namespace the system libgsl no longer loads.
#   tools/wheel_check.sh PYTHON   (the Python to make the venv with; root, or sudo)
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${1:-python3}
WHEEL=$(ls dist/tendonrod-*-manylinux_2_*.whl)
WORK=$(mktemp -d /tmp/tendonrod-wheel-check.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
"$PY" -m venv "$WORK/venv"
"$WORK/venv/bin/python" -m pip install -q "$WHEEL"
# the wheel carries GSL's licence (License-File entries of its metadata)
unzip -l "$WHEEL" | grep -E "licenses/LICENSES/GSL-COPYING|licenses/LICENSES/GSL-NOTICE"
unzip -l "$WHEEL" | grep -E "tendonrod.libs/libgsl"

LIBS=$(ls /usr/lib/*-linux-gnu/libgsl*.so* /usr/lib/libgsl*.so* /usr/local/lib/libgsl*.so* \
       2>/dev/null | tr "\n" " " || true)
[ -n "$LIBS" ] || { echo "no system libgsl found to mask" >&2; exit 1; }
cat > "$WORK/masked.sh" <<EOS
set -euo pipefail
: > "$WORK/empty"
for f in $LIBS; do mount --bind "$WORK/empty" "\$(readlink -f "\$f")"; done
# the mask works: the system's libgsl does not load in this namespace
if "$WORK/venv/bin/python" -c "import ctypes; ctypes.CDLL('libgsl.so.27')" 2>/dev/null; then
  echo "masking failed: the system libgsl still loads" >&2; exit 1
fi
echo "system libgsl masked: ctypes cannot load it"
cd "$WORK"   # away from the source tree: import the installed package
"$WORK/venv/bin/python" - <<'PYEOF'
import numpy as np
import tendonrod as tr
import tendonrod._core as core

maps = open("/proc/self/maps").read()
gsl = sorted({line.split()[-1] for line in maps.splitlines() if "libgsl" in line})
print("tendonrod", tr.__version__, "from", tr.__file__)
print("libgsl mapped from:", *gsl, sep="\n  ")
assert gsl and all("tendonrod.libs" in p for p in gsl), gsl
rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
robot = tr.Robot(rod, [tr.Tendon(offset=0.008, angle=0.0)])
sol = tr.solve(tr.Scene(robot, tension=[1.0]))
# a tension-driven parallel tendon bends the rod into an arc of curvature tau r / EI
k = 1.0 * 0.008 / (207e9 * np.pi * 0.8e-3**4 / 64)  # tau r / (E pi d^4 / 64)
arc = np.array([(1 - np.cos(k * 0.2)) / k, 0.0, np.sin(k * 0.2) / k])
err = np.abs(sol.tip_position - arc).max()
print("solve:", sol.message, "| tip", sol.tip_position, "| arc error", err)
assert sol.success and err < 1e-9 * 0.2  # the solver's tol 1e-10 (scaled), a factor 10 spare
PYEOF
EOS
if [ "$(id -u)" = 0 ]; then
  unshare -m bash "$WORK/masked.sh"
elif command -v sudo >/dev/null && sudo -n true 2>/dev/null; then
  sudo unshare -m bash "$WORK/masked.sh"
else
  unshare -r -m bash "$WORK/masked.sh"   # an unprivileged user namespace
fi
echo "wheel check passed: $(basename "$WHEEL") ($(du -h "$WHEEL" | cut -f1))"
