#!/usr/bin/env bash
# The CPython interpreters to build wheels for: one per minor version 3.10-3.13 (the
# package's requires-python floor to the newest CPython NumPy and GSL are tested on),
# printed one path a line, oldest first.  Looked for under pyenv's versions
# ($PYENV_ROOT, default ~/.pyenv: the newest patch release of each minor), then on PATH
# (pythonX.Y); each candidate must run and report that version (pyenv's shims of a
# version not selected do not).  Minors found nowhere are named on stderr.
#   tools/pythons.sh [MINOR...]     e.g. tools/pythons.sh 3.11 3.13
set -uo pipefail
minors=("$@")
[ ${#minors[@]} -gt 0 ] || minors=(3.10 3.11 3.12 3.13)
root=${PYENV_ROOT:-$HOME/.pyenv}
for v in "${minors[@]}"; do
  found=
  cands=$(ls -d "$root"/versions/"$v".*/bin/python"$v" 2>/dev/null | sort -V -r)
  cands="$cands $(command -v -a "python$v" 2>/dev/null | tr '\n' ' ')"
  for c in $cands; do
    got=$("$c" -c 'import sys, platform; print("%d.%d" % sys.version_info[:2], platform.python_implementation())' 2>/dev/null) || continue
    if [ "$got" = "$v CPython" ]; then found=$c; break; fi
  done
  if [ -n "$found" ]; then echo "$found"; else echo "pythons.sh: no CPython $v found" >&2; fi
done
