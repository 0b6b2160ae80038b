#!/usr/bin/env bash
# GSL from source into PREFIX (default /usr/local): cibuildwheel's before-all step in the
# manylinux_2_28 containers (pyproject.toml [tool.cibuildwheel]), where no libgsl package
# is old-glibc enough to ship in a wheel.  The tarball's SHA-256 is checked against the
# value GNU's 2.8 release carries in independent packaging recipes (Termux, MXE, MSYS2).
#   tools/build_gsl.sh [PREFIX]
# Without network access to GNU, GSL_TARBALL=FILE GSL_SHA256=HEX builds a local tarball
# instead (e.g. Debian's orig tarball of another release).  JOBS: make's parallel jobs
# (default: every core).
set -euo pipefail
PREFIX=${1:-/usr/local}
VERSION=2.8
SHA256=${GSL_SHA256:-6a99eeed15632c6354895b1dd542ed5a855c0f15d9ad1326c6fe2b2c9e423190}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
cd "$WORK"
if [ -n "${GSL_TARBALL:-}" ]; then
  cp "$GSL_TARBALL" gsl.tar.gz
else
  for url in "https://ftpmirror.gnu.org/gsl/gsl-$VERSION.tar.gz" \
             "https://mirrors.kernel.org/gnu/gsl/gsl-$VERSION.tar.gz" \
             "https://ftp.gnu.org/gnu/gsl/gsl-$VERSION.tar.gz"; do
    curl -fsSL --retry 3 -o gsl.tar.gz "$url" && break
    rm -f gsl.tar.gz
  done
  [ -f gsl.tar.gz ] || { echo "build_gsl.sh: no mirror gave GSL $VERSION" >&2; exit 1; }
fi
echo "$SHA256  gsl.tar.gz" | sha256sum -c -
mkdir src
tar xzf gsl.tar.gz -C src --strip-components=1
cd src
./configure --prefix="$PREFIX" --disable-static CFLAGS="-O2 -fPIC" > configure.log
make -j"${JOBS:-$(nproc)}" > make.log
make install > install.log
grep -m1 "define GSL_VERSION " "$PREFIX/include/gsl/gsl_version.h"
echo "GSL installed into $PREFIX"
