"""tr.load of files that are not what sol.save wrote: truncated, foreign, edited by
hand or by an attacker.  The contract: a ValueError that names the file and what is
wrong (never BadZipFile, KeyError, AttributeError, TokenError, OverflowError, EOFError
or RecursionError), never a Solution that says success with numbers no solve gave (a
NaN tension), and nothing in a file is ever executed or imported.

Each probe starts from a real saved solution and changes one thing, so that what is
refused is that one thing."""

import io
import json
import math
import os
import pathlib
import subprocess
import sys
import warnings
import zipfile

import numpy as np
import pytest
from cpu_guard import limited

import tendonrod as tr

META = "__tendonrod__"


def _solution(spatial=False):
    rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    robot = tr.Robot(rod, [tr.Tendon(offset=0.01), tr.Tendon(offset=0.01, angle=2.0)])
    force = (0.05, 0.02, 0.0) if spatial else (0.05, 0.0, 0.0)
    scene = tr.Scene(robot, displacement=[0.004, 0.0], loads=[tr.PointLoad(s=0.2, force=force)])
    sol = tr.solve(scene)
    assert sol.success, sol.message
    return sol


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    """(tree, arrays) of a real saved solution, its lazy outputs filled."""
    sol = _solution()
    _ = sol.position  # the recorded arrays are saved too
    path = tmp_path_factory.mktemp("load") / "sol.npz"
    sol.save(path)
    with np.load(path) as z:
        return json.loads(str(z[META][()])), {k: z[k] for k in z.files if k != META}


def _write(path, tree, arrays):
    np.savez(path, **{META: np.array(json.dumps(tree, allow_nan=True))}, **arrays)
    return path


def _raw_key(tree, key):
    """The archive key of the raw result's array ``key``."""
    return tree["raw"]["__dict__"][key]["__array__"]


def _deep(n):
    return "[" * n + "]" * n


def _edits():
    """name -> f(tree, arrays) -> (tree, arrays): one change each to a saved file."""

    def raw_set(key, value):
        def f(t, a):
            t["raw"]["__dict__"][key] = value
            return t, a

        return f

    def arr(key, fn):
        def f(t, a):
            k = _raw_key(t, key)
            a = dict(a, **{k: fn(a[k].copy())})
            return t, a

        return f

    def nan_at(x):
        x.flat[0] = math.nan
        return x

    def tree_set(path, value):
        def f(t, a):
            node = t
            for p in path[:-1]:
                node = node[p]
            node[path[-1]] = value
            return t, a

        return f

    def drop(key):
        def f(t, a):
            del t["raw"]["__dict__"][key]
            return t, a

        return f

    rod_fields = ("scene", "fields", "robot", "fields", "rod", "fields")
    return {
        "NaN tension": arr("tension", nan_at),
        "inf tip position": arr("tip_position", lambda x: x * math.inf),
        "NaN base state": arr("base_state", nan_at),
        "NaN in the recorded positions": arr("position", nan_at),
        "negative tension": arr("tension", lambda x: x - 1.0),
        "tension of the wrong shape": arr("tension", lambda x: np.zeros(5)),
        "complex tip rotation": arr("tip_rotation", lambda x: x.astype(complex)),
        "string array": arr("slack", lambda x: np.array(["a", "b"])),
        "success a string": raw_set("success", "yes"),
        "status a float": raw_set("status", 0.5),
        "nit beyond a float": raw_set("nit", 1e400),  # JSON's 1e400 is inf
        "nfev negative": raw_set("nfev", -1),
        "message a number": raw_set("message", 3),
        "no tension": drop("tension"),
        "no formulation": drop("formulation"),
        "formulation steps a string": raw_set("formulation", {"__dict__": {"steps": "x"}}),
        "array reference missing": raw_set("tension", {"__array__": "a999"}),
        "array reference a number": raw_set("tension", {"__array__": 3}),
        "scalar of an array": raw_set("nit", {"__scalar__": _raw_key_fixed("tension")}),
        "unknown record": raw_set("tension", {"__what__": 1}),
        "tuple of a dict": raw_set("stability_carry", {"__tuple__": {"a": 1}}),
        "raw a list": tree_set(("raw",), [1, 2]),
        "no raw": lambda t, a: ({k: v for k, v in t.items() if k != "raw"}, a),
        "no scene": lambda t, a: ({k: v for k, v in t.items() if k != "scene"}, a),
        "scene a Rod": tree_set(("scene",), _rod_record()),
        "options a string": tree_set(("options",), "fast"),
        "foreign class": tree_set(("scene", "__dataclass__"), "os:system"),
        "tendonrod non-class": tree_set(("scene", "__dataclass__"), "tendonrod.model:np"),
        "class reached through another": tree_set(
            ("scene", "__dataclass__"), "tendonrod.model:dataclasses.Field"
        ),
        "module never imported": tree_set(("scene", "__dataclass__"), "tendonrod.plot:Figure"),
        "class name a number": tree_set(("scene", "__dataclass__"), 7),
        "unknown field": tree_set(rod_fields + ("colour",), "red"),
        "negative rod length": tree_set(rod_fields + ("length",), -1.0),
        "NaN rod length": tree_set(rod_fields + ("length",), math.nan),
        "huge integer rod length": tree_set(rod_fields + ("length",), 10**400),
        "fields a list": tree_set(("scene", "fields"), [1]),
        "deeply nested raw": lambda t, a: (dict(t, raw=json.loads(_deep(50))), a),
        "other format": tree_set(("format",), 99),
        "header a list": lambda t, a: ([t], a),
    }


def _raw_key_fixed(key):
    """A placeholder for the archive key of the raw result's ``key`` array (the probe
    replaces it: the key is known only once the file is read)."""
    return f"@{key}"


def _rod_record():
    return {
        "__dataclass__": "tendonrod.model:Rod",
        "fields": {"length": 0.2, "EI": 1e-3, "GJ": 1e-3, "EA": 1e4, "GA": 1e4},
    }


EDITS = _edits()


@pytest.mark.parametrize("name", list(EDITS))
def test_an_edited_file_is_refused_by_what_is_wrong(saved, tmp_path, name):
    tree, arrays = json.loads(json.dumps(saved[0])), dict(saved[1])
    tree, arrays = EDITS[name](tree, arrays)
    text = json.dumps(tree, allow_nan=True)
    if '"@tension"' in text:  # _raw_key_fixed's placeholder: the tension array's key
        text = text.replace('"@tension"', json.dumps(_raw_key(saved[0], "tension")))
    path = tmp_path / "edited.npz"
    np.savez(path, **{META: np.array(text)}, **arrays)
    with pytest.raises(ValueError) as e:
        tr.load(path)
    assert repr(str(path)) in str(e.value), e.value
    assert len(str(e.value)) > len(repr(str(path))) + 20, e.value  # says what is wrong


def _zip_of(entries):
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w") as z:
        for k, v in entries.items():
            z.writestr(k, v)
    return buf.getvalue()


def _npy(arr):
    buf = io.BytesIO()
    np.save(buf, arr)
    return buf.getvalue()


def _raw_files(saved_bytes):
    """name -> bytes of a file that is not an intact .npz of a solution."""
    npy = _npy(np.array("{}"))
    header_end = npy.index(b"\n") + 1
    bad_header = npy[:10] + npy[10:header_end].replace(b"'descr'", b"'descr") + npy[header_end:]
    huge_shape = npy[:10] + npy[10:header_end].replace(b"()", b"(2**4000,)") + npy[header_end:]
    return {
        "empty file": b"",
        "random bytes": bytes(range(256)) * 4,
        "a text file": b"hello, world\n",
        "truncated archive": saved_bytes[: len(saved_bytes) // 2],
        "archive without its end": saved_bytes[:-30],
        "a single .npy": _npy(np.arange(3.0)),
        "a pickle": b"\x80\x04\x95\x05\x00\x00\x00\x00\x00\x00\x00K\x01.",
        "header not JSON": _zip_of({META + ".npy": _npy(np.array("{not json"))}),
        "header a number array": _zip_of({META + ".npy": _npy(np.arange(3))}),
        "header deeply nested": _zip_of({META + ".npy": _npy(np.array(_deep(100000)))}),
        "header of an unparsable .npy": _zip_of({META + ".npy": bad_header}),
        "header of a huge .npy shape": _zip_of({META + ".npy": huge_shape}),
        "header truncated .npy": _zip_of({META + ".npy": npy[:20]}),
        "header of an object array": _zip_of(
            {META + ".npy": _npy(np.array([{"x": 1}], dtype=object))}
        ),
        "header with an integer of 5000 digits": _zip_of(
            {META + ".npy": _npy(np.array('{"format": ' + "9" * 5000 + "}"))}
        ),
        "header with a string of bad UTF-8": _zip_of({META + ".npy": b"\x93NUMPY\xff\xfe"}),
    }


def test_malformed_files_raise_value_error_naming_the_file(saved, tmp_path):
    good = _write(tmp_path / "good.npz", *saved)
    assert tr.load(good).success  # the probes below start from a loadable file
    escaped = {}
    for name, data in _raw_files(good.read_bytes()).items():
        path = tmp_path / "probe.npz"
        path.write_bytes(data)
        try:
            tr.load(path)
        except ValueError as e:
            if repr(str(path)) not in str(e):
                escaped[name] = f"ValueError not naming the file: {e}"
        except BaseException as e:  # noqa: BLE001 -- every other escape is the finding
            escaped[name] = f"{type(e).__name__}: {e}"
        else:
            escaped[name] = "loaded"
    assert not escaped, escaped


def test_a_missing_file_is_an_os_error(tmp_path):
    """A path that names no file is the caller's mistake about the path, not a malformed
    file: FileNotFoundError (IsADirectoryError for a directory) as open() says it."""
    with pytest.raises(FileNotFoundError):
        tr.load(tmp_path / "none.npz")
    with pytest.raises(IsADirectoryError):
        tr.load(tmp_path)


class _Payload:
    """Unpickling this would create the marker file."""

    def __init__(self, marker):
        self.marker = marker

    def __reduce__(self):
        return (open, (self.marker, "w"))


def test_nothing_in_a_file_is_executed(saved, tmp_path):
    """A pickled object in the archive is not unpickled, and a class the file names in a
    module tendonrod has not imported is not imported: the file is refused, nothing runs."""
    marker = tmp_path / "ran"
    tree, arrays = json.loads(json.dumps(saved[0])), dict(saved[1])
    payload = np.empty(1, dtype=object)
    payload[0] = _Payload(str(marker))
    key = _raw_key(tree, "tension")
    path = tmp_path / "pickled.npz"
    np.savez(path, **{META: np.array(json.dumps(tree))}, **dict(arrays, **{key: payload}))
    with pytest.raises(ValueError, match="pickle|[Oo]bject arrays"):
        tr.load(path)
    assert not marker.exists()

    # in a fresh interpreter: loading a file that names tendonrod.plot (lazily imported,
    # it reaches for matplotlib) and tendonrod.__main__ (the command line) imports neither
    for target in ("tendonrod.plot:Figure", "tendonrod.__main__:main"):
        tree["scene"]["__dataclass__"] = target
        p = _write(tmp_path / "names.npz", tree, arrays)
        code = (
            "import sys, tendonrod as tr\n"
            "try:\n    tr.load(sys.argv[1])\nexcept ValueError as e:\n    print('refused', e)\n"
            "print(sorted(m for m in sys.modules if m.startswith(('tendonrod.plot', "
            "'tendonrod.__main__', 'matplotlib'))))\n"
        )
        root = os.path.dirname(os.path.dirname(os.path.abspath(tr.__file__)))
        out = subprocess.run(
            [sys.executable, "-c", code, str(p)],
            capture_output=True,
            text=True,
            env=dict(os.environ, PYTHONPATH=root),
            check=True,
            **limited(60),  # a hang guard of 60 s of CPU; the child takes ~0.5 s
        ).stdout
        assert out.startswith("refused") and out.strip().endswith("[]"), out


def test_round_trip_still_bitwise_and_validated(tmp_path):
    """The validation accepts every file save writes: planar and spatial, lazy outputs
    filled or not (bitwise equality is test_ecosystem's)."""
    for spatial in (False, True):
        sol = _solution(spatial)
        for fill in (False, True):
            if fill:
                _ = sol.position, sol.stability
            path = tmp_path / f"s{spatial}{fill}.npz"
            sol.save(path)
            back = tr.load(path)
            assert back.success and back.tip_position.tobytes() == sol.tip_position.tobytes()


def test_random_corruption_loads_validated_or_is_refused(saved, tmp_path):
    """200 copies of a saved file, each with 1-8 random bytes changed (a fixed seed): each
    is refused with a ValueError naming the file, or loads a solution that passed the
    validation (a change the zip's CRC does not see, e.g. in its directory)."""
    good = _write(tmp_path / "good.npz", *saved).read_bytes()
    rng = np.random.default_rng(20261207)
    outcomes = {"refused": 0, "loaded": 0}
    path = tmp_path / "corrupt.npz"
    for _ in range(200):
        data = bytearray(good)
        for i in rng.integers(0, len(data), size=rng.integers(1, 9)):
            data[i] = int(rng.integers(0, 256))
        path.write_bytes(bytes(data))
        try:
            sol = tr.load(path)
        except ValueError as e:
            assert repr(str(path)) in str(e), e
            outcomes["refused"] += 1
        else:
            assert not sol.success or np.all(np.isfinite(sol.tension)), sol.tension
            outcomes["loaded"] += 1
    assert outcomes["refused"] > 0, outcomes  # the probe reached the checks


_POOL = [None, "x", -1, 0, 1e400, math.nan, [], {}, True, 2**70, 10**30, [1, 2], 0.5, ""]
_POOL += [{"__array__": "a0"}, {"__scalar__": "a1"}, {"__tuple__": [1]}, {"__dict__": {}}]


def _nodes(t, path=()):
    yield path
    if isinstance(t, dict):
        for k, v in t.items():
            yield from _nodes(v, path + (k,))
    elif isinstance(t, list):
        for i, v in enumerate(t):
            yield from _nodes(v, path + (i,))


def test_random_edits_of_the_header_load_usable_or_are_refused(tmp_path):
    """300 copies of a saved spatial solution, each with one or two values of its header
    replaced by a random one (a fixed seed): each is refused with a ValueError, or loads
    a solution that can be read and used as a warm start without any other exception."""
    sol = _solution(spatial=True)
    _ = sol.position, sol.stability
    sol.save(tmp_path / "s.npz")
    with np.load(tmp_path / "s.npz") as z:
        tree0 = json.loads(str(z[META][()]))
        arrays = {k: z[k] for k in z.files if k != META}
    paths = [p for p in _nodes(tree0) if p]
    rng = np.random.default_rng(7)
    path = tmp_path / "edited.npz"
    loaded = 0
    for _ in range(300):
        tree = json.loads(json.dumps(tree0))
        for _k in range(int(rng.integers(1, 3))):
            where = paths[int(rng.integers(len(paths)))]
            node = tree
            try:
                for q in where[:-1]:
                    node = node[q]
                node[where[-1]] = json.loads(json.dumps(_POOL[int(rng.integers(len(_POOL)))]))
            except (KeyError, IndexError, TypeError):
                pass  # an earlier edit removed the path
        _write(path, tree, arrays)
        try:
            with warnings.catch_warnings():
                # legal but odd values (a diameter of 0.5 m) warn as they would in code
                warnings.simplefilter("ignore", tr.PlausibilityWarning)
                back = tr.load(path)
        except ValueError:
            continue
        loaded += 1
        _ = back.position, back.stability, back.bending_angle, repr(back.scene)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            tr.solve(back.scene, guess=back, options=back.options)
    assert 0 < loaded < 300, loaded  # some edits are legal values, most are not


# Files written by tendonrod 0.1's Solution.save (tests/data/solution_0.1_*.npz, made with
# the 0.1 tree): a spatial three-tendon robot with two slack tendons, and a planar tip-only
# solve.  They must keep loading, with the common result fields and the taut mask.
_DATA_01 = pathlib.Path(__file__).resolve().parent / "data"


def _scenes_01():
    rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)
    angles = (0.0, 2.0943951023931953, 4.1887902047863905)
    robot = tr.Robot(rod, [tr.Tendon(offset=0.01, angle=a, EA=3e3) for a in angles])
    spatial = tr.Scene(
        robot,
        displacement=[0.004, -0.002, -0.006],
        loads=[tr.PointLoad(s=0.2, force=(0.0, 0.05, -0.1))],
    )
    planar = tr.Scene(
        tr.Robot(rod, [tr.Tendon(offset=0.01)]),
        displacement=[0.0157],
        loads=[tr.PointLoad(s=0.2, force=(0.0, 0.0, -0.2))],
    )
    # the options as 0.1 saved them: its default work budget was 2e7 units (3.5e7 since
    # the budget counts every formulation's work alike)
    return {
        "spatial": (spatial, tr.Options(max_work=2e7)),
        "planar_tip_only": (planar, tr.Options(tip_only=True, max_work=2e7)),
    }


@pytest.mark.parametrize("name", ["spatial", "planar_tip_only"])
def test_solutions_saved_by_0_1_still_load(name):
    scene, options = _scenes_01()[name]
    old = tr.load(_DATA_01 / f"solution_0.1_{name}.npz")
    assert old.scene == scene and old.options == options
    assert isinstance(old, tr.Result) and old.success and old.status >= 0
    fresh = tr.solve(scene, options=options)
    # the same scene solved today: equal to well within the solver's tolerance (1e-10 of
    # the scaled residual; positions ~0.2 m), whatever the core's last bits
    np.testing.assert_allclose(old.tip_position, fresh.tip_position, rtol=0, atol=1e-9)
    np.testing.assert_allclose(old.tension, fresh.tension, rtol=0, atol=1e-7)
    assert old.taut.tolist() == fresh.taut.tolist()
    if name == "spatial":
        assert old.taut.tolist() == [True, False, False] and old.position.shape[1] == 3
