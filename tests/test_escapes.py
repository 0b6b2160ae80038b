"""Escapes found by outside probes: each call below once raised AttributeError,
TypeError, RecursionError, IsADirectoryError, UnicodeDecodeError or OverflowError (or
answered a NaN tolerance with a verdict); each must be a ValueError/TypeError naming the
parameter, or the documented behaviour."""

import math
import subprocess
import sys

import numpy as np
import pytest

import tendonrod as tr

HUGE = 10**400  # an int beyond every double

ROD = dict(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)


def _scene(friction=0.0):
    robot = tr.Robot(tr.Rod(**ROD), [tr.Tendon(offset=0.01, friction=friction)])
    return tr.Scene(
        robot, displacement=[0.004], loads=[tr.PointLoad(s=0.2, force=(-0.1, 0.0, 0.0))]
    )


@pytest.fixture(scope="module")
def frictional():
    sol = tr.solve(
        tr.Scene(
            tr.Robot(tr.Rod(**ROD), [tr.Tendon(offset=0.01, friction=0.2)]),
            displacement=[0.01],
            sliding="in",
        )
    )
    assert sol.success, sol.message
    return sol


@pytest.mark.parametrize("bad", [5, None, "sol", _scene()])
def test_slip_refuses_what_is_no_solution(bad):
    with pytest.raises(TypeError, match="solution must be a tendonrod.Solution"):
        tr.slip(bad)


def test_slip_refuses_a_reference_that_is_no_solution(frictional):
    with pytest.raises(TypeError, match="reference"):
        tr.slip(frictional, reference=3.0)


@pytest.mark.parametrize("tol", ["abc", math.nan, math.inf, -1e-9, HUGE, [1e-9]])
def test_slip_tol_must_be_a_finite_nonnegative_length(frictional, tol):
    with pytest.raises(ValueError, match="tol"):
        tr.slip(frictional, tol=tol)


def test_slip_with_a_legal_tol_still_answers(frictional):
    # pulled from rest it slid in everywhere: consistent at any tolerance >= 0
    assert tr.slip(frictional, tol=0.0).consistent and tr.slip(frictional, tol=1e-6).consistent


def _deep_scene_file(tmp_path, depth):
    path = tmp_path / f"deep{depth}.toml"
    path.write_text(
        "[rod]\nlength = 0.2\ndiameter = 0.8e-3\nE = 207e9\nG = 79.6e9\nkirchhoff = true\n\n"
        "[[tendon]]\noffset = 0.01\ndisplacement = " + "[" * depth + "0.001" + "]" * depth + "\n"
    )
    return path


@pytest.mark.parametrize("depth", [5, 300, 500, 5000])
def test_deeply_nested_scene_file_is_a_scene_file_error(tmp_path, depth):
    with pytest.raises(tr.scenefile.SceneFileError, match="displacement|nested too deep"):
        tr.scenefile.load_scene(_deep_scene_file(tmp_path, depth))


def test_cli_exits_2_on_a_deeply_nested_scene_file(tmp_path):
    """Exit status 2 is a bad input file; 1 would say the solve did not converge."""
    p = subprocess.run(
        [
            sys.executable,
            "-m",
            "tendonrod",
            "solve",
            str(_deep_scene_file(tmp_path, 500)),
            "--out",
            str(tmp_path / "out"),
        ],
        capture_output=True,
        text=True,
    )
    assert p.returncode == 2, (p.returncode, p.stderr[-2000:])
    assert "nested too deep" in p.stderr, p.stderr[-2000:]


def test_sweep_path_a_directory_is_refused(tmp_path):
    with pytest.raises(ValueError, match="is a directory"):
        tr.sweep(_scene(), {"loads[0].force[0]": [0.1]}, file=tmp_path, progress=False)


@pytest.mark.parametrize(
    "content", [b"\xff\xfe\x00bad\n", b"\x80\x81\x82\n", b'{"chunk": 0}\n', b"[" * 100000 + b"\n"]
)
def test_sweep_path_an_undecodable_file_is_refused_not_overwritten(tmp_path, content):
    path = tmp_path / "sweep.jsonl"
    path.write_bytes(content)
    with pytest.raises(ValueError, match="sweep"):
        tr.sweep(_scene(), {"loads[0].force[0]": [0.1]}, file=path, progress=False)
    assert path.read_bytes() == content  # never overwritten


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(tip_position=(HUGE, 0.0, 0.0)), "tip_position"),
        (dict(tip_angle=HUGE), "tip_angle"),
        (dict(tip_direction=(HUGE, 0.0, 1.0)), "tip_direction"),
        (dict(tip_pose=((0.0, 0.0, 0.2), [[HUGE, 0, 0], [0, 1, 0], [0, 0, 1]])), "tip_pose"),
        (dict(tip_angle=0.5, min_tension=HUGE), "min_tension"),
        (dict(tip_angle=0.5, tol=HUGE), "tol"),
        (dict(tip_angle=0.5, max_iter=HUGE), "max_iter"),
        (dict(tip_angle=0.5, tendons=[HUGE]), "tendons"),
    ],
)
def test_actuate_huge_integers_name_the_parameter(kwargs, name):
    with pytest.raises(ValueError, match=name):
        tr.actuate(_scene(), **kwargs)


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(span=(0.0, HUGE)), r"span\[1\]"),
        (dict(span=(HUGE, 0.0)), r"span\[0\]"),
        (dict(span=(0.0, 0.1), step=HUGE), "step"),
        (dict(span=(0.0, 0.1), max_step=HUGE), "max_step"),
        (dict(span=(0.0, 0.1), max_points=HUGE), "max_points"),
        (dict(span=(0.0, 0.1), max_points=-HUGE), "max_points"),
    ],
)
def test_path_huge_integers_name_the_parameter(kwargs, name):
    with pytest.raises(ValueError, match=name):
        tr.path(_scene(), "loads[0].force[0]", **kwargs)


@pytest.mark.parametrize("name", ["measured", "sigma", "x0", "s", "max_iter"])
def test_fit_huge_integers_name_the_parameter(name):
    sc = _scene()
    tip = tr.solve(sc).tip_position
    args = dict(scenes=[sc], measured=[tip], parameters=["EI"])
    args[name] = {
        "measured": [[HUGE, 0, 0]],
        "sigma": HUGE,
        "x0": [HUGE],
        "s": [HUGE],
        "max_iter": HUGE,
    }[name]
    with pytest.raises(ValueError, match=name):
        tr.fit(**args)


@pytest.mark.parametrize("field", ["EA", "GA"])
@pytest.mark.parametrize("value", [5e-324, 1e-101, 1e151])
def test_kirchhoff_rod_refuses_what_a_cosserat_rod_refuses(field, value):
    """The same range as a Cosserat rod's ([1e-100, 1e150] N); inf or omitted stays legal."""
    kw = dict(length=0.2, EI=1e-3, GJ=1e-3, EA=1e4, GA=1e4)
    kw[field] = value
    with pytest.raises(ValueError, match=f"Rod.{field}"):
        tr.Rod(**kw)
    with pytest.raises(ValueError, match=f"Rod.{field}"):
        tr.Rod(**kw, kirchhoff=True)
    kw[field] = math.inf
    assert tr.Rod(**kw, kirchhoff=True).kirchhoff


def test_kirchhoff_rod_at_the_range_ends_warns_without_overflow():
    """EI/EA at the range's extreme (1e100 / 1e-100) is 1e200: the slenderness rule's
    equivalent diameter stays finite (it was inf for EA = 5e-324)."""
    with pytest.warns(tr.PlausibilityWarning, match="slenderness") as rec:
        tr.Rod(length=0.2, EI=1e-3, GJ=1e-3, EA=1e-100, GA=1e4, kirchhoff=True)
    assert "inf" not in str(rec[0].message), rec[0].message


def test_converging_tendon_ends_at_its_length():
    """A tendon converging at length L/2 on a rod of length L: end defaults to L/2, where
    it reaches the centre line (it would have crossed it on the way to the tip)."""
    L = 0.2
    rod = tr.Rod(length=L, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    t = tr.Tendon.converging(0.01, 0.0, length=L / 2)
    assert t.end == L / 2 and t.slope == -0.01 / (L / 2)
    robot = tr.Robot(rod, [t])
    assert robot.tendon_end(0) == L / 2
    # explicit end still wins, and the full-length tendon ends at the tip as before
    assert tr.Tendon.converging(0.01, 0.0, length=L / 2, end=L / 4).end == L / 4
    full = tr.Robot(rod, [tr.Tendon.converging(0.01, 0.0, length=L)])
    assert full.tendon_end(0) == L
    # and it solves: a converging tendon anchored at L/2 bends only [0, L/2]; the tip
    # part stays straight (its tangent is the tangent at L/2, to round-off 1e-9)
    sol = tr.solve(tr.Scene(robot, tension=[1.0]), options=tr.Options(nodes=[L / 2, L]))
    assert sol.success, sol.message
    R = sol.rotation
    assert np.allclose(R[0][:, 2], R[1][:, 2], atol=1e-9)


def test_parse_scene_of_a_deeply_nested_dict_is_a_scene_file_error():
    """The same refusal for a document built in Python (100000 levels: beyond the
    recursion limit of every step that reads it)."""
    v = 0.001
    for _ in range(100000):
        v = [v]
    rod = {"length": 0.2, "EI": 4e-3, "GJ": 3e-3, "kirchhoff": True}
    data = {"rod": rod, "tendon": [{"offset": 0.01}]}
    data["tendon"][0]["displacement"] = v
    with pytest.raises(tr.scenefile.SceneFileError, match="nested too deep"):
        tr.scenefile.parse_scene(data, "robot.toml")
