"""Build of tendonrod._core: the Extension and GSL discovery, nothing else.

Metadata lives in pyproject.toml.  GSL is found, in this order:
  1. override variables GSL_CFLAGS and GSL_LIBS (or GSL_PREFIX),
  2. pkg-config gsl,
  3. gsl-config.
If none works the build stops with one message naming what was tried.
"""

import os
import shlex
import shutil
import subprocess
import sys

import numpy
from setuptools import Extension, setup

INSTALL_HINT = (
    "  Debian/Ubuntu: sudo apt-get install -y libgsl-dev\n"
    "  macOS:         brew install gsl\n"
    "  conda:         conda install -c conda-forge gsl\n"
)


def _run(cmd):
    try:
        out = subprocess.run(cmd, check=True, capture_output=True, text=True)
    except (OSError, subprocess.CalledProcessError):
        return None
    return out.stdout.strip()


def find_gsl():
    """Return (cflags, libs, how) for GSL, or exit with one clear message."""
    tried = []
    cflags, libs = os.environ.get("GSL_CFLAGS"), os.environ.get("GSL_LIBS")
    prefix = os.environ.get("GSL_PREFIX")
    if cflags is not None or libs is not None:
        return (
            shlex.split(cflags or ""),
            shlex.split(libs or "-lgsl -lgslcblas -lm"),
            "GSL_CFLAGS/GSL_LIBS",
        )
    tried.append("GSL_CFLAGS/GSL_LIBS (unset)")
    if prefix:
        return (
            [f"-I{prefix}/include"],
            [f"-L{prefix}/lib", f"-Wl,-rpath,{prefix}/lib", "-lgsl", "-lgslcblas", "-lm"],
            "GSL_PREFIX",
        )
    tried.append("GSL_PREFIX (unset)")
    if shutil.which("pkg-config"):
        c, l = _run(["pkg-config", "--cflags", "gsl"]), _run(["pkg-config", "--libs", "gsl"])
        if c is not None and l is not None:
            return shlex.split(c), shlex.split(l), "pkg-config"
        tried.append("pkg-config gsl (package not found)")
    else:
        tried.append("pkg-config (not installed)")
    if shutil.which("gsl-config"):
        c, l = _run(["gsl-config", "--cflags"]), _run(["gsl-config", "--libs"])
        if c is not None and l is not None:
            return shlex.split(c), shlex.split(l), "gsl-config"
        tried.append("gsl-config (failed)")
    else:
        tried.append("gsl-config (not installed)")
    sys.exit(
        "tendonrod needs the GNU Scientific Library (GSL >= 2.5) to build.\n"
        "Tried: "
        + "; ".join(tried)
        + ".\nInstall it with one of:\n"
        + INSTALL_HINT
        + "or point GSL_PREFIX (or GSL_CFLAGS and GSL_LIBS) at an existing installation."
    )


def split_flags(cflags, libs):
    inc = [f[2:] for f in cflags if f.startswith("-I")]
    extra_c = [f for f in cflags if not f.startswith("-I")]
    libdirs = [f[2:] for f in libs if f.startswith("-L")]
    libnames = [f[2:] for f in libs if f.startswith("-l")]
    extra_l = [f for f in libs if not (f.startswith("-L") or f.startswith("-l"))]
    return inc, extra_c, libdirs, libnames, extra_l


# the core's C flags, one place for the extension and the benchmarks' C builds
with open(os.path.join("csrc", "CFLAGS")) as fh:
    CFLAGS = [ln.strip() for ln in fh if ln.strip() and not ln.startswith("#")]

cflags, libs, how = find_gsl()
inc, extra_c, libdirs, libnames, extra_l = split_flags(cflags, libs)
csrc = sorted(os.path.join("csrc", f) for f in os.listdir("csrc") if f.endswith(".c"))
# the glue: tendonrod/_*.c (only these files speak the CPython / NumPy C-API)
glue = sorted(os.path.join("tendonrod", f) for f in os.listdir("tendonrod") if f.endswith(".c"))
# a changed header rebuilds every source (the structs it defines are shared)
headers = sorted(os.path.join("csrc", f) for f in os.listdir("csrc") if f.endswith(".h"))
headers += [os.path.join("tendonrod", "_glue.h")]
# Extra compile/link flags for instrumented builds (make sanitize) come from the
# environment: TR_EXTRA_CFLAGS / TR_EXTRA_LDFLAGS.
extra_c += shlex.split(os.environ.get("TR_EXTRA_CFLAGS", ""))
extra_l += shlex.split(os.environ.get("TR_EXTRA_LDFLAGS", ""))

ext = Extension(
    "tendonrod._core",
    sources=glue + csrc,
    depends=headers,
    include_dirs=["csrc", "tendonrod", numpy.get_include()] + inc,
    library_dirs=libdirs,
    libraries=libnames,
    # Built against NumPy 2 headers (pyproject's build requirement), the extension targets
    # the C-API of NumPy 1.25/1.26 (the same API version), the runtime floor numpy>=1.26:
    # it then imports under NumPy 1.26 (ROS 2 Jazzy's) as well as 2.x.  The deprecated
    # API stays hidden as of 2.0, so nothing removed in 2.x can creep in.
    define_macros=[
        ("NPY_NO_DEPRECATED_API", "NPY_2_0_API_VERSION"),
        ("NPY_TARGET_VERSION", "NPY_1_25_API_VERSION"),
    ],
    # hidden visibility: the module exports PyInit__core alone (PyMODINIT_FUNC marks it)
    extra_compile_args=CFLAGS + ["-fvisibility=hidden"] + extra_c,
    extra_link_args=extra_l,
)

setup(ext_modules=[ext])
