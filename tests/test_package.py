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
    # triggers a GSL domain error through ctypes must survive.  The library called is the
    # one the extension loaded (a wheel carries its own copy, tendonrod.libs/libgsl-*.so,
    # beside which the system's libgsl is another library with another handler).
    code = (
        "import ctypes, tendonrod\n"
        "maps = open('/proc/self/maps').read().split()\n"
        "path = next(w for w in maps if '/libgsl' in w and 'cblas' not in w)\n"
        "gsl = ctypes.CDLL(path)\n"
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


def test_citation_names_this_version():
    # CITATION.cff (the software and the paper to cite) repeats the version that
    # tendonrod/_version.py defines; a release that forgets it fails here
    import pathlib

    cff = pathlib.Path(__file__).resolve().parent.parent / "CITATION.cff"
    versions = re.findall(r"^version: (\S+)$", cff.read_text(encoding="utf-8"), re.M)
    assert versions == [tendonrod.__version__]


def test_progress_without_tqdm_names_the_extra():
    # progress=True asks for tqdm's bar; without tqdm (refused by a meta-path finder, as if
    # not installed) the sweep runs and its one warning names the extra that brings it
    code = (
        "import sys, warnings\n"
        "class Block:\n"
        "    def find_spec(self, name, path=None, target=None):\n"
        "        if name.split('.')[0] == 'tqdm':\n"
        "            raise ModuleNotFoundError(name, name=name)\n"
        "sys.meta_path.insert(0, Block())\n"
        "import tendonrod as tr\n"
        "rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)\n"
        "scene = tr.Scene(tr.Robot(rod, [tr.Tendon(offset=0.01)]), tension=[1.0])\n"
        "with warnings.catch_warnings(record=True) as w:\n"
        "    warnings.simplefilter('always')\n"
        "    res = tr.sweep(scene, {'tension': [[1.0], [2.0]]}, progress=True)\n"
        "print(bool(res.success.all()), [str(x.message) for x in w])\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.startswith("True [") and "pip install 'tendonrod[progress]'" in out.stdout
    assert out.stdout.count("tqdm is not installed") == 1
