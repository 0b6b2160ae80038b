#!/usr/bin/env bash
# valgrind memcheck run of a loop of solves and ufunc calls (bench/valgrind_loop.py)
# against the in-tree build of tendonrod._core.
#
#   bench/valgrind.sh            # default loop sizes (about 1-2 minutes)
#   bench/valgrind.sh --fast     # a shorter loop for CI
#   bench/valgrind.sh ARGS...    # any arguments of bench/valgrind_loop.py
#
# PYTHONMALLOC=malloc makes CPython use malloc for every object, so valgrind
# sees each allocation (pymalloc's arenas would hide use-after-free and leaks
# of small objects).  bench/valgrind.supp silences known reports in glibc's
# loader and CPython; bench/valgrind_check.py then fails on any error with a
# frame in our code (tendonrod/_core*.so, csrc/), on any definite leak with a
# frame in our code, and on any unsuppressed invalid access anywhere.
# Output: build/valgrind.xml (the raw report; VALGRIND_XML=... to move it) and
# a summary on stdout.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
VPY="${VPY:-$ROOT/.venv/bin/python}"
OUT="${VALGRIND_XML:-$ROOT/build/valgrind.xml}"
command -v valgrind >/dev/null || { echo "valgrind: not installed (apt-get install -y valgrind)" >&2; exit 2; }
mkdir -p "$(dirname "$OUT")"
cd "$ROOT"
start=$(date +%s)
PYTHONMALLOC=malloc MPLBACKEND=Agg valgrind --tool=memcheck \
    --suppressions="$ROOT/bench/valgrind.supp" \
    --leak-check=full --show-leak-kinds=definite --errors-for-leak-kinds=definite \
    --track-origins=no --num-callers=40 \
    --xml=yes --xml-file="$OUT" \
    "$VPY" "$ROOT/bench/valgrind_loop.py" "$@"
echo "valgrind: run took $(( $(date +%s) - start )) s"
"$VPY" "$ROOT/bench/valgrind_check.py" "$OUT"
