"""Package-level facts: the build links GSL and the module imports cleanly."""

import re
import subprocess
import sys

from cpu_guard import limited

import tendonrod


def test_gsl_version_is_linked_version():
    # tendonrod.gsl_version is the version string compiled into the library we
    # link (gsl_version from <gsl/gsl_version.h>), e.g. "2.7.1".
    assert re.fullmatch(r"\d+\.\d+(\.\d+)?", tendonrod.gsl_version)
    major, minor = (int(x) for x in tendonrod.gsl_version.split(".")[:2])
    assert (major, minor) >= (2, 5)


def test_gsl_error_handler_is_off():
    # GSL's default handler aborts the process on any error; the module must
    # switch it off at load.  A fresh interpreter that imports tendonrod and then
    # triggers a GSL domain error through ctypes must survive.
    code = (
        "import ctypes, ctypes.util, tendonrod\n"
        "gsl = ctypes.CDLL(ctypes.util.find_library('gsl'))\n"
        "res = (ctypes.c_double * 2)()\n"
        "gsl.gsl_sf_log_e.argtypes = [ctypes.c_double, ctypes.c_void_p]\n"
        "print(gsl.gsl_sf_log_e(-1.0, res))\n"  # log(-1): GSL_EDOM = 1
    )
    # a hang guard of 60 s of CPU; the import and the call take ~0.3 s
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, **limited(60)
    )
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "1"  # GSL_EDOM returned, not abort()


def test_version_string():
    assert re.fullmatch(r"\d+\.\d+\.\d+", tendonrod.__version__)
