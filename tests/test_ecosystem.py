"""Small things with big effects: a solution saved to .npz and loaded
back bit for bit; ``tr.sweep`` and ``tr.path`` plain functions (their old modules warn
and still work); the ImportError
of an unbuilt source tree saying what to do."""

import inspect
import math
import os
import pathlib
import shutil
import subprocess
import sys

import numpy as np
import pytest
from cpu_guard import limited

import tendonrod as tr

ROOT = pathlib.Path(__file__).resolve().parents[1]


def _scene(spatial=False):
    rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=not spatial)
    tendons = [tr.Tendon(offset=0.01, angle=0.0)]
    if spatial:
        tendons.append(tr.Tendon(offset=0.01, angle=2.0, EA=1e4))
    robot = tr.Robot(rod, tendons)
    return tr.Scene(
        robot,
        displacement=[0.0157] + ([0.001] if spatial else []),
        loads=[
            tr.PointLoad(s=0.2, force=(0.0, 0.01 if spatial else 0.0, -0.2)),
            tr.DistributedLoad(force=(0.0, 0.0, -0.1), start=0.05, end=0.1),
        ],
    )


def _same(a, b):
    """Bitwise equality of two values of a raw result (arrays by their bytes, so that NaN
    compares equal to the same NaN)."""
    if isinstance(a, np.ndarray):
        return (
            isinstance(b, np.ndarray)
            and a.dtype == b.dtype
            and a.shape == b.shape
            and a.tobytes() == b.tobytes()
        )
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, (tuple, list)):
        return type(a) is type(b) and len(a) == len(b) and all(map(_same, a, b))
    if isinstance(a, float) and math.isnan(a):
        return isinstance(b, float) and math.isnan(b)
    return type(a) is type(b) and a == b


@pytest.mark.parametrize("spatial", [False, True])
def test_save_load_round_trip_bitwise(tmp_path, spatial):
    sol = tr.solve(_scene(spatial), options=tr.Options(nodes=17))
    _ = sol.position, sol.stability  # fill the lazy outputs too: they are saved as well
    path = tmp_path / "sol.npz"
    sol.save(path)
    back = tr.load(path)
    assert _same(sol.raw, back.raw)
    assert back.scene == sol.scene and repr(back.scene) == repr(sol.scene)
    assert back.options == sol.options
    for name in ("tip_position", "tip_rotation", "tension", "slack", "position", "rotation"):
        assert getattr(back, name).tobytes() == getattr(sol, name).tobytes(), name
    assert (back.success, back.status, back.message) == (sol.success, sol.status, sol.message)
    # a loaded solution starts a warm solve exactly as the original does
    again = tr.solve(sol.scene, options=sol.options, guess=back)
    ref = tr.solve(sol.scene, options=sol.options, guess=sol)
    assert again.tip_position.tobytes() == ref.tip_position.tobytes()


def test_load_refuses_foreign_file(tmp_path):
    path = tmp_path / "other.npz"
    np.savez(path, x=np.arange(3))
    with pytest.raises(ValueError, match="not a file written by tendonrod"):
        tr.load(path)


def test_sweep_and_path_are_functions_their_modules_renamed(rod):
    assert inspect.isfunction(tr.sweep) and inspect.isfunction(tr.path)
    assert tr.sweep is tr.sweeps.sweep and tr.path is tr.continuation.path
    for name in ("tip_measure", "ComplianceMeasure", "SweepResult", "load", "Branch"):
        assert name in tr.__all__ and hasattr(tr, name)
    assert tr.tip_measure is tr.sweeps.tip_measure and tr.Branch is tr.continuation.Branch
    res = tr.sweep(
        _scene(),
        {"loads[0].force": [(0.0, 0.0, -0.1), (0.0, 0.0, -0.2)]},
        grid=False,
        progress=False,
    )
    assert res.success.all()
    scene = tr.Scene(tr.Robot(rod, []), loads=[tr.PointLoad(s=0.2, force=(0.0, 0.0, 0.0))])
    p = tr.path(scene, "loads[0].force[0]", (0.0, 0.01), max_points=20)
    assert p.success and isinstance(p, tr.Branch), p.message


# importing an old module rebinds the package's attribute to it: in a child process
OLD_MODULES = """
import inspect, warnings
import tendonrod as tr
with warnings.catch_warnings(record=True) as w:
    warnings.simplefilter("always")
    import tendonrod.sweep as ms
    from tendonrod.path import Path, SpecialPoint
    import tendonrod.path as mp
texts = [str(x.message) for x in w if x.category is DeprecationWarning]
assert len(texts) == 2, texts
assert "the module tendonrod.sweep is deprecated" in texts[0] and "tendonrod.sweeps" in texts[0]
assert "the module tendonrod.path is deprecated" in texts[1]
assert Path is tr.Branch and ms.OUTCOME_OK == tr.sweeps.OUTCOME_OK
# the old modules stay callable as the functions they were
assert callable(tr.sweep) and tr.sweep is ms and ms.sweep is tr.sweeps.sweep
assert str(inspect.signature(ms)) == str(inspect.signature(tr.sweeps.sweep))
print("ok")
"""


def test_old_modules_warn_and_still_work():
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    out = subprocess.run(
        [sys.executable, "-W", "error", "-c", OLD_MODULES],
        capture_output=True,
        text=True,
        env=env,
        timeout=120,
    )
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr


def test_version_defined_once():
    from tendonrod._version import __version__

    assert tr.__version__ is __version__
    try:
        import tomllib
    except ImportError:  # Python 3.10
        import tomli as tomllib
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text())
    assert "version" not in meta["project"] and "version" in meta["project"]["dynamic"]
    attr = meta["tool"]["setuptools"]["dynamic"]["version"]["attr"]
    assert attr == "tendonrod._version.__version__"


@pytest.mark.skipif(shutil.which("cp") is None, reason="needs cp")
def test_unbuilt_source_tree_says_what_to_do(tmp_path):
    """A copy of the package without its extension, imported as from a checkout: one
    ImportError naming the source tree and the command that builds it."""
    tree = tmp_path / "checkout"
    shutil.copytree(
        ROOT / "tendonrod",
        tree / "tendonrod",
        ignore=shutil.ignore_patterns("_core*.so", "_core*.pyd", "__pycache__"),
    )
    (tree / "setup.py").write_text("")
    (tree / "csrc").mkdir()
    env = dict(os.environ, PYTHONPATH=str(tree))
    # an editable install's finder would map tendonrod._core to its own tree: drop it
    code = (
        "import sys; sys.meta_path[:] = [f for f in sys.meta_path "
        "if 'editable' not in repr(f).lower()]; import tendonrod"
    )
    r = subprocess.run(
        [sys.executable, "-c", code],
        cwd=tree,
        env=env,
        capture_output=True,
        text=True,
        **limited(60),  # a hang guard of 60 s of CPU; the import takes ~0.3 s
    )
    assert r.returncode != 0
    last = r.stderr.strip().splitlines()[-1]
    assert last.startswith("ImportError: You are importing tendonrod from its source tree")
    assert "pip install -e ." in last and "circular" not in r.stderr
