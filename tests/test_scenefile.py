"""Scene files: the examples parse to the scenes they describe; every malformed file
gets a SceneFileError naming the key and the problem; the file is never modified."""

import math
import os
import pathlib

import pytest

import tendonrod as tr
from tendonrod.scenefile import SceneFileError, load_scene, parse_scene

EXAMPLES = pathlib.Path(__file__).resolve().parent.parent / "examples"

GOOD = """
title = "t"
[rod]
length = 0.2
diameter = 0.8e-3
E = 207e9
G = 79.6e9
kirchhoff = true

[[tendon]]
offset = 0.01
displacement = 0.002

[[tendon]]
offset = 0.01
angle = 3.141592653589793
routing = "converging"
EA = 1e5
tension = 0.5

[[load]]
s = 0.2
force = [0.0, 0.0, -0.1]

[distributed]
force = [0.0, 0.0, -0.05]

[options]
nodes = 21
"""


def write(tmp_path, text, name="scene.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def test_examples_parse():
    spec = load_scene(EXAMPLES / "slack_robot.toml")
    sc = spec.scene
    assert sc.robot.rod.length == 0.2 and sc.robot.rod.kirchhoff
    assert sc.robot.tendons[0].EA == math.inf
    assert sc.displacement == (0.01 * math.pi / 2,) and sc.tension == (None,)
    assert spec.options is None and spec.title
    spec = load_scene(EXAMPLES / "converging_three_tendons.toml")
    sc = spec.scene
    assert len(sc.robot.tendons) == 3
    for t in (
        sc.robot.tendons
    ):  # routing = "converging" -> slope = -offset / L, exactly as Tendon.converging
        assert t.slope == tr.Tendon.converging(offset=t.offset, length=0.1).slope
    assert sc.tension == (10.0, None, None) and sc.displacement == (None, -0.002, 0.0)
    assert spec.options == tr.Options(nodes=51)
    assert len(sc.loads) == 2  # one point load + the distributed load


def test_full_scene_maps_every_key(tmp_path):
    spec = load_scene(write(tmp_path, GOOD))
    sc = spec.scene
    t0, t1 = sc.robot.tendons
    assert (t0.offset, t0.angle, t0.slope, t0.EA) == (0.01, 0.0, 0.0, math.inf)
    assert t1.slope == -0.01 / 0.2 and t1.EA == 1e5 and t1.angle == math.pi
    assert sc.displacement == (0.002, None) and sc.tension == (None, 0.5)
    assert sc.point_loads[0].force == (0.0, 0.0, -0.1)
    assert tuple(sc.distributed_force) == (0.0, 0.0, -0.05)
    assert spec.options.nodes == 21 and spec.title == "t"


def test_friction_and_sliding(tmp_path):
    text = _replace(GOOD, 'title = "t"', 'title = "t"\nsliding = ["out", "in"]')
    text = _replace(text, "displacement = 0.002", "displacement = 0.002\nfriction = 0.4")
    sc = load_scene(write(tmp_path, text)).scene
    assert [t.friction for t in sc.robot.tendons] == [0.4, 0.0]  # default: frictionless
    assert sc.sliding == ("out", "in")
    # one string sets every tendon; no key: the default "in"
    text = _replace(GOOD, 'title = "t"', 'title = "t"\nsliding = "out"')
    assert load_scene(write(tmp_path, text, "one.toml")).scene.sliding == ("out", "out")
    assert load_scene(write(tmp_path, GOOD, "none.toml")).scene.sliding == ("in", "in")
    spec = load_scene(EXAMPLES / "friction_robot.toml")
    assert spec.scene.robot.tendons[0].friction == 0.3 and spec.scene.sliding == ("in",)
    assert spec.scene.tension == (2.0,)


def _replace(text, old, new):
    assert old in text, old
    return text.replace(old, new, 1)


BAD = [
    # (description, edit, expected key, expected words in the problem)
    ("missing rod length", ("length = 0.2\n", ""), "rod.length", "missing"),
    ("missing rod table", ("[rod]", "[rodd]"), "rodd", "unknown key"),
    (
        "wrong type offset",
        ("offset = 0.01\ndisplacement", 'offset = "abc"\ndisplacement'),
        "tendon[0].offset",
        "expected a number",
    ),
    ("boolean for a number", ("E = 207e9", "E = true"), "rod.E", "expected a number"),
    (
        "number for a boolean",
        ("kirchhoff = true", "kirchhoff = 1"),
        "rod.kirchhoff",
        "true or false",
    ),
    (
        "negative offset (library check)",
        ("offset = 0.01\ndisplacement", "offset = -0.01\ndisplacement"),
        "tendon[0]",
        "offset",
    ),
    (
        "both actuations",
        ("displacement = 0.002", "displacement = 0.002\ntension = 1.0"),
        "tendon[0]",
        "exactly one",
    ),
    ("no actuation", ("displacement = 0.002\n", ""), "tendon[0]", "exactly one"),
    (
        "unknown tendon key",
        ("displacement = 0.002", "displacement = 0.002\nofset = 1.0"),
        "tendon[0].ofset",
        "unknown key",
    ),
    (
        "bad routing",
        ('routing = "converging"', 'routing = "spiral"'),
        "tendon[1].routing",
        "spiral",
    ),
    (
        "routing and slope",
        ('routing = "converging"', 'routing = "converging"\nslope = -0.01'),
        "tendon[1].routing",
        "not both",
    ),
    (
        "short force vector",
        ("force = [0.0, 0.0, -0.1]", "force = [0.0, -0.1]"),
        "load[0].force",
        "3 numbers",
    ),
    (
        "string in vector",
        ("force = [0.0, 0.0, -0.1]", 'force = [0.0, "x", -0.1]'),
        "load[0].force[1]",
        "expected a number",
    ),
    ("load beyond the tip", ("s = 0.2\n", "s = 0.3\n"), "load[0].s", "on the rod"),
    ("load without s", ("s = 0.2\n", ""), "load[0].s", "missing"),
    ("unknown option", ("nodes = 21", "nodez = 21"), "options.nodez", "unknown key"),
    ("bad option value", ("nodes = 21", 'integrator = "euler"'), "options", "integrator"),
    ("negative tension (library check)", ("tension = 0.5", "tension = -0.5"), "scene", "tension"),
    (
        "key lands in the table above",
        ("[[load]]", "tendon = 3\n[[load]]"),
        "tendon[1].tendon",
        "unknown key",
    ),
    ("syntax error", ("length = 0.2", "length = = 0.2"), "(syntax)", "not valid TOML"),
    (
        "friction not a number",
        ("displacement = 0.002", 'displacement = 0.002\nfriction = "high"'),
        "tendon[0].friction",
        "expected a number",
    ),
    (
        "negative friction (library check)",
        ("displacement = 0.002", "displacement = 0.002\nfriction = -0.1"),
        "tendon[0]",
        "friction",
    ),
    ("unknown sliding", ('title = "t"', 'title = "t"\nsliding = "up"'), "sliding", '"in" or "out"'),
    ("sliding a number", ('title = "t"', 'title = "t"\nsliding = 1'), "sliding", "array"),
    (
        "sliding one short",
        ('title = "t"', 'title = "t"\nsliding = ["in"]'),
        "sliding",
        "one entry per tendon (2)",
    ),
    (
        "sliding entry",
        ('title = "t"', 'title = "t"\nsliding = ["in", "outward"]'),
        "sliding[1]",
        "outward",
    ),
]


@pytest.mark.parametrize("desc, edit, key, words", BAD, ids=[b[0] for b in BAD])
def test_malformed_names_key_and_leaves_file(tmp_path, desc, edit, key, words):
    p = write(tmp_path, _replace(GOOD, *edit))
    before = (p.read_bytes(), os.stat(p).st_mtime_ns)
    with pytest.raises(SceneFileError) as info:
        load_scene(p)
    err = info.value
    assert err.key == key, str(err)
    assert words.lower() in err.problem.lower(), str(err)
    assert str(p) in str(err) and key in str(err)
    assert isinstance(err, ValueError)
    assert (p.read_bytes(), os.stat(p).st_mtime_ns) == before


def test_parse_scene_from_dict_and_not_utf8(tmp_path):
    spec = parse_scene({"rod": {"length": 0.1, "EI": 1e-2, "GJ": 1e-2, "EA": 1e6, "GA": 1e6}})
    assert spec.scene.robot.n_tendons == 0
    with pytest.raises(SceneFileError) as info:
        parse_scene(
            {
                "rod": {"length": 0.1, "EI": 1e-2, "GJ": 1e-2, "EA": 1e6, "GA": 1e6},
                "tendon": {"offset": 1},
            }
        )
    assert info.value.key == "tendon"
    p = tmp_path / "latin1.toml"
    p.write_bytes(b'title = "\xe9"\n')
    with pytest.raises(SceneFileError) as info:
        load_scene(p)
    assert info.value.key == "(file)"
