#!/usr/bin/env bash
# Build tendonrod._core with AddressSanitizer + UndefinedBehaviorSanitizer in a
# separate copy of the work tree and run the test suite against that build.
#
#   bench/sanitize.sh                 # whole tests/ directory
#   bench/sanitize.sh tests/test_hostile.py -k raw   # any pytest arguments
#
# Why a copy: other processes (and the editable install) use the in-tree
# tendonrod/_core*.so; an instrumented .so there would need LD_PRELOAD of the
# ASan runtime in every Python that imports it.  The copy lives in
# $TR_SANITIZE_DIR (default /tmp/tendonrod-sanitize) and is put first on
# PYTHONPATH, so its tendonrod shadows the editable install; the script checks
# that it really is the instrumented module that gets imported.
#
# Environment of the run:
#   LD_PRELOAD=<libasan.so of the compiler> <libstdc++.so>   CPython itself is
#       not built with ASan, so the runtime must be loaded before anything
#       else; libstdc++ next, for C++ extensions that throw (see below).
#   ASAN_OPTIONS=detect_leaks=0               CPython keeps many allocations
#       alive until exit on purpose (interned strings, type caches); LeakSanitizer
#       would report them all.  Leaks of our code are checked by tests/test_leaks.py
#       and by the valgrind run (bench/valgrind.sh), which looks for definite
#       leaks with a frame in our code.
#   UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1  the first undefined
#       behaviour stops the process with a stack trace (the build also uses
#       -fno-sanitize-recover=undefined so that this holds for every check).
# Exit status: that of pytest (non-zero on any failure or sanitizer report).
set -euo pipefail

ROOT="$(cd "$(dirname "$0")/.." && pwd)"
VPY="${VPY:-$ROOT/.venv/bin/python}"
CC="${CC:-gcc}"
DEST="${TR_SANITIZE_DIR:-/tmp/tendonrod-sanitize}"

# The optimisation flags of the normal build (csrc/CFLAGS, which setup.py reads) stay,
# so floating-point results match it and the suite's tolerances apply unchanged; -g
# for file:line in reports.
# float-cast-overflow: GCC's -fsanitize=undefined leaves it out (clang's does
# not); a double outside the int range cast to int is undefined behaviour.
SAN_CFLAGS="-fsanitize=address,undefined,float-cast-overflow -fno-sanitize-recover=undefined,float-cast-overflow -fno-omit-frame-pointer -g"
SAN_LDFLAGS="-fsanitize=address,undefined,float-cast-overflow"

ASAN_RT="$($CC -print-file-name=libasan.so)"
if [ ! -e "$ASAN_RT" ] || [ "$ASAN_RT" = "libasan.so" ]; then
    echo "sanitize: $CC does not know libasan.so (install the compiler's ASan runtime, e.g. libasan8)" >&2
    exit 2
fi

echo "sanitize: copying the work tree to $DEST"
rm -rf "$DEST"
mkdir -p "$DEST"
# tracked files plus untracked, not-ignored ones (what the test suite would see)
(cd "$ROOT" && git ls-files -z --cached --others --exclude-standard) |
    (cd "$ROOT" && xargs -0 cp --parents -t "$DEST" 2>/dev/null || true)

echo "sanitize: building the instrumented extension ($SAN_CFLAGS)"
(cd "$DEST" && CC="$CC" TR_EXTRA_CFLAGS="$SAN_CFLAGS" TR_EXTRA_LDFLAGS="$SAN_LDFLAGS" \
    "$VPY" setup.py -q build_ext --inplace >"$DEST/build.log" 2>&1) || {
    cat "$DEST/build.log" >&2; echo "sanitize: build failed" >&2; exit 2; }

# libstdc++ is preloaded right after the ASan runtime: C++ extensions loaded
# later (matplotlib's ft2font, SciPy) throw exceptions, and ASan's __cxa_throw
# interceptor must find the real one at start-up ("CHECK failed:
# asan_interceptors.cpp ... real___cxa_throw" otherwise).
STDCXX="$($CC -print-file-name=libstdc++.so)"
export LD_PRELOAD="$ASAN_RT${STDCXX:+ $STDCXX}"
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1:allocator_may_return_null=1:strict_init_order=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export PYTHONPATH="$DEST${PYTHONPATH:+:$PYTHONPATH}"
export MPLBACKEND=Agg
# the hang guards of tests/test_hostile.py and tests/test_bounded.py: ASan and
# UBSan make the core several times slower
export TR_HANG_GUARD_SCALE="${TR_HANG_GUARD_SCALE:-5}"
export PYTHONDONTWRITEBYTECODE=1

cd "$DEST"
# The module that gets imported must be the instrumented one.
"$VPY" - "$DEST" <<'EOF'
import os, sys, subprocess
import tendonrod._core as c
dest = os.path.realpath(sys.argv[1])
so = os.path.realpath(c.__file__)
if not so.startswith(dest + os.sep):
    sys.exit(f"sanitize: imported {so}, not the instrumented copy under {dest}")
deps = subprocess.run(["ldd", so], capture_output=True, text=True).stdout
if "libasan" not in deps:
    sys.exit(f"sanitize: {so} is not linked against libasan")
print(f"sanitize: using {so}")
EOF

if [ "$#" -eq 0 ]; then set -- tests; fi
echo "sanitize: pytest $*"
"$VPY" -m pytest -q -p no:cacheprovider "$@"
