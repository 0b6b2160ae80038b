"""Command line: --help and --version, exit codes 0 / 1 / 2 / 3, messages naming the key
of a malformed scene file (left untouched) or the extra a missing optional dependency
comes with, solve outputs, figures, bench dispatch."""

import dataclasses
import json
import math
import os
import pathlib
import subprocess
import sys
import types

import numpy as np
import pytest

import tendonrod as tr
from tendonrod.__main__ import (
    EXIT_BAD_INPUT,
    EXIT_MISSING_DEPENDENCY,
    EXIT_NOT_CONVERGED,
    EXIT_OK,
    main,
)

EXAMPLES = pathlib.Path(__file__).resolve().parent.parent / "examples"


def run_main(argv, capsys):
    try:
        rc = main(argv)
    except SystemExit as exc:  # argparse: --help (0) and usage errors (2)
        rc = exc.code
    out = capsys.readouterr()
    return rc, out.out, out.err


@pytest.mark.parametrize("argv", [["--help"], ["solve", "--help"], ["figures", "--help"]])
def test_help(argv, capsys):
    rc, out, _ = run_main(argv, capsys)
    assert rc == 0 and "usage" in out.lower()


def test_module_entry_point_help():
    # the real `python -m tendonrod` (one subprocess; the rest run in-process)
    p = subprocess.run(
        [sys.executable, "-m", "tendonrod", "--help"], capture_output=True, text=True
    )
    assert (
        p.returncode == 0 and "solve" in p.stdout and "figures" in p.stdout and "bench" in p.stdout
    )


def test_usage_errors_exit_2(capsys):
    assert run_main([], capsys)[0] == 2
    assert run_main(["nonsense"], capsys)[0] == 2
    assert run_main(["solve", "x.toml"], capsys)[0] == 2  # --out missing


@pytest.mark.parametrize(
    "edit, key",
    [
        (("length = 0.2          # [m]\n", ""), "rod.length"),  # missing key
        (("offset = 0.01 ", 'offset = "1cm" '), "tendon[0].offset"),  # wrong type
        (("s = 0.2 ", "s = 0.5 "), "load[0].s"),  # bad value
        (("EA = inf ", "EA = -1.0 "), "tendon[0]"),  # bad value (library)
        (("EA = inf ", 'friction = "high"\nEA = inf '), "tendon[0].friction"),  # wrong type
        (("EA = inf ", "friction = -0.2\nEA = inf "), "tendon[0]"),  # bad value (library)
        (("title = ", 'sliding = "sideways"\ntitle = '), "sliding"),  # not in / out
        (("title = ", 'sliding = ["in", "out"]\ntitle = '), "sliding"),  # one tendon, two
    ],
)
def test_solve_malformed_scene(tmp_path, capsys, edit, key):
    text = (EXAMPLES / "slack_robot.toml").read_text()
    assert edit[0] in text
    scene = tmp_path / "bad.toml"
    scene.write_text(text.replace(edit[0], edit[1], 1))
    before = (scene.read_bytes(), os.stat(scene).st_mtime_ns)
    rc, out, err = run_main(["solve", str(scene), "--out", str(tmp_path / "out")], capsys)
    assert rc == EXIT_BAD_INPUT
    assert key in err and "bad.toml" in err
    assert (scene.read_bytes(), os.stat(scene).st_mtime_ns) == before
    assert not (tmp_path / "out").exists()  # nothing written for bad input


def test_solve_missing_file(tmp_path, capsys):
    rc, _, err = run_main(["solve", str(tmp_path / "nope.toml"), "--out", str(tmp_path)], capsys)
    assert rc == EXIT_BAD_INPUT and "nope.toml" in err


def test_solve_writes_outputs(tmp_path, capsys):
    out = tmp_path / "out"
    rc, stdout, _ = run_main(
        ["solve", str(EXAMPLES / "slack_robot.toml"), "--out", str(out), "--plot"], capsys
    )
    assert rc == EXIT_OK, stdout
    summary = json.loads((out / "solution.json").read_text())
    arrays = np.load(out / "solution.npz")
    assert summary["success"] is True
    n = arrays["s"].shape[0]
    assert arrays["position"].shape == (n, 3) and arrays["rotation"].shape == (n, 3, 3)
    assert arrays["tension"].shape == (1,)
    # the summary is the solution: same tip as a direct solve of the same scene
    from tendonrod.scenefile import load_scene

    sol = tr.solve(load_scene(EXAMPLES / "slack_robot.toml").scene)
    assert summary["tip_position_m"] == sol.tip_position.tolist()  # bitwise: same solve
    assert np.array_equal(arrays["position"], sol.position)
    # a locked inextensible parallel tendon keeps the tip at 90 degrees while it is taut
    # (exact); 1e-8 rad is the solver/integrator accuracy, far above round-off
    R = arrays["rotation"][-1]
    assert abs(math.atan2(R[0, 2], R[2, 2]) - math.pi / 2) < 1e-8
    assert summary["tension_N"][0] > 0
    assert (out / "solution.png").stat().st_size > 1000


def test_solve_spatial_example(tmp_path, capsys):
    rc, stdout, _ = run_main(
        [
            "solve",
            str(EXAMPLES / "converging_three_tendons.toml"),
            "--out",
            str(tmp_path),
            "--plot",
        ],
        capsys,
    )
    assert rc == EXIT_OK, stdout
    summary = json.loads((tmp_path / "solution.json").read_text())
    assert summary["tension_N"][0] == pytest.approx(
        10.0, rel=1e-12
    )  # tension-controlled: returned as given
    # the tendon paid out by 2 mm goes slack, the locked one carries tension (never both)
    assert summary["tension_N"][1] == 0.0 and summary["slack_m"][1] > 0
    assert summary["tension_N"][2] > 0 and summary["slack_m"][2] == 0.0
    assert np.load(tmp_path / "solution.npz")["s"].shape == (51,)  # [options] nodes = 51 honoured


@pytest.mark.parametrize("sliding", [None, "in", "out"])
def test_solve_friction_example(tmp_path, capsys, sliding):
    """The friction example is the exact planar solution of docs/model.md, Section 3:
    tau(s) = tau0 / (1 + sigma mu r tau0 s/EI), theta(L) = ln(1 + sigma mu r tau0 L/EI) /
    (sigma mu); --sliding overrides the file's "in"."""
    args = ["solve", str(EXAMPLES / "friction_robot.toml"), "--out", str(tmp_path)]
    rc, stdout, _ = run_main(args + (["--sliding", sliding] if sliding else []), capsys)
    assert rc == EXIT_OK, stdout
    summary = json.loads((tmp_path / "solution.json").read_text())
    arrays = np.load(tmp_path / "solution.npz")
    mu, r, tau0, L = 0.3, 0.01, 2.0, 0.2
    EI = 207e9 * math.pi * 0.8e-3**4 / 64
    sigma = -1.0 if sliding == "out" else 1.0
    c = sigma * mu * r * tau0 / EI
    assert summary["friction"] == [mu] and summary["sliding"] == [sliding or "in"]
    assert summary["tension_N"] == [tau0]  # tension-controlled: the actuator's, as given
    # the default tolerance (1e-10, scaled) and the verified step count: 1e-9 relative
    # leaves a margin over the ~1e-11 the solver reaches (tests/test_friction.py: 1e-10
    # at tol 1e-12)
    assert summary["anchor_tension_N"][0] == pytest.approx(tau0 / (1 + c * L), rel=1e-9)
    tau_s = arrays["tendon_tension"][:, 0]
    np.testing.assert_allclose(tau_s, tau0 / (1 + c * arrays["s"]), rtol=1e-9, atol=0)
    theta = _tip_angle(arrays["rotation"][-1])
    assert abs(theta - math.log1p(c * L) / (sigma * mu)) <= 1e-9
    # friction is not conservative: no stability verdict, and the reason is given
    assert summary["stable"] is None and "friction" in summary["stability_reason"]
    assert "at the anchor" in stdout and "not tested" in stdout
    assert f"({sliding or 'in'})" in stdout


def test_solve_frictionless_records_stability(tmp_path, capsys):
    rc, stdout, _ = run_main(
        ["solve", str(EXAMPLES / "slack_robot.toml"), "--out", str(tmp_path)], capsys
    )
    assert rc == EXIT_OK, stdout
    summary = json.loads((tmp_path / "solution.json").read_text())
    # without friction the tension is uniform: the anchor's is the actuator's, exactly
    assert summary["anchor_tension_N"] == summary["tension_N"]
    assert summary["friction"] == [0.0] and summary["stable"] is True
    assert "at the anchor" not in stdout  # nothing about friction on a frictionless scene


def test_actuate_with_sliding(tmp_path, capsys):
    # the friction example's tension is the control: 45 degrees sliding out takes less
    # tension than sliding in (friction adds tension toward the anchor)
    tensions = {}
    for sliding in ("in", "out"):
        out = tmp_path / sliding
        rc, stdout, _ = run_main(
            ["actuate", str(EXAMPLES / "friction_robot.toml"), "--out", str(out)]
            + ["--tip-angle", "45deg", "--sliding", sliding],
            capsys,
        )
        assert rc == EXIT_OK, stdout
        summary = json.loads((out / "solution.json").read_text())
        assert summary["sliding"] == [sliding]
        tensions[sliding] = summary["tension_N"][0]
        # the exact solution inverted: theta = ln(1 + c L)/(sigma mu) = pi/4 gives
        # tau0 = EI (exp(sigma mu pi/4) - 1) / (sigma mu r L); 1e-8 relative is the
        # target tolerance 1e-10 rad over d(theta)/d(ln tau0) ~ 1 with a margin
        sigma = 1.0 if sliding == "in" else -1.0
        EI = 207e9 * math.pi * 0.8e-3**4 / 64
        exact = EI * math.expm1(sigma * 0.3 * math.pi / 4) / (sigma * 0.3 * 0.01 * 0.2)
        assert tensions[sliding] == pytest.approx(exact, rel=1e-8)
    assert tensions["out"] < tensions["in"]


def test_solve_not_converged_exit_1(tmp_path, capsys):
    # one iteration and no continuation cannot solve a 90-degree bend from a cold start
    text = (
        EXAMPLES / "slack_robot.toml"
    ).read_text() + "\n[options]\nmax_iter = 1\ncontinuation = false\n"
    scene = tmp_path / "hard.toml"
    scene.write_text(text)
    rc, stdout, _ = run_main(["solve", str(scene), "--out", str(tmp_path / "o")], capsys)
    assert rc == EXIT_NOT_CONVERGED
    assert "DID NOT CONVERGE" in stdout
    assert json.loads((tmp_path / "o" / "solution.json").read_text())["success"] is False


def _tip_angle(R) -> float:
    return math.atan2(R[0, 2], R[2, 2])


@pytest.mark.parametrize("extra, degrees", [([], 45.0), (["--tip-angle", "30deg"], 30.0)])
def test_actuate_reaches_the_target(tmp_path, capsys, extra, degrees):
    scene_file = EXAMPLES / "actuate_under_load.toml"
    rc, stdout, _ = run_main(["actuate", str(scene_file), "--out", str(tmp_path)] + extra, capsys)
    assert rc == EXIT_OK, stdout
    summary = json.loads((tmp_path / "solution.json").read_text())
    assert summary["actuation"]["reached"] is True
    # the displacement written, given to a forward solve of the file's scene, gives the
    # angle (1e-9 rad: the target tolerance 1e-10 plus the two solves' accuracy)
    from tendonrod.scenefile import load_scene

    scene = load_scene(scene_file).scene
    q = summary["displacement_m"]
    fwd = tr.solve(dataclasses.replace(scene, displacement=q), strict=True)
    assert abs(_tip_angle(fwd.tip_rotation) - math.radians(degrees)) <= 1e-9


def test_actuate_unreachable_exit_1(tmp_path, capsys):
    # one tendon at +x cannot hold the tip at -80 deg against a load toward -x... it
    # can only go slack: the closest state is written, with its distance
    rc, stdout, _ = run_main(
        ["actuate", str(EXAMPLES / "actuate_under_load.toml"), "--out", str(tmp_path)]
        + ["--tip-angle=-80deg"],
        capsys,
    )
    assert rc == EXIT_NOT_CONVERGED and "TARGET NOT REACHED" in stdout
    summary = json.loads((tmp_path / "solution.json").read_text())
    assert summary["success"] is False and summary["actuation"]["distance"] > 0.1


_HELICAL_SIX = """
[rod]
length = 0.24
diameter = 1.2e-3
E = 60e9
G = 23e9

[[load]]
s = 0.24
force = [0.0, 0.02, -0.03]
"""


def _helical_six(q):
    """Two sections of three helical displacement-controlled tendons (opposite hands; the
    first three end at mid-length) as a scene file text, and as a Scene."""
    text, tendons = _HELICAL_SIX, []
    for k in range(6):
        half = k < 3
        angle = 2 * math.pi * (k % 3) / 3 + (0.0 if half else math.pi / 3)
        text += (
            f'\n[[tendon]]\noffset = 0.008\nangle = {angle!r}\nrouting = "helical"\n'
            f"turns = {0.5 if half else -0.5}\nEA = 5e3\ndisplacement = {q[k]!r}\n"
            + ("end = 0.12\n" if half else "")
        )
        tendons.append(
            tr.Tendon.helical(
                0.008,
                angle,
                turns=0.5 if half else -0.5,
                length=0.12 if half else 0.24,
                end=0.12 if half else None,
                EA=5e3,
            )
        )
    rod = tr.Rod(length=0.24, diameter=1.2e-3, E=60e9, G=23e9)
    scene = tr.Scene(
        tr.Robot(rod, tendons),
        displacement=list(q),
        loads=[tr.PointLoad(s=0.24, force=(0.0, 0.02, -0.03))],
    )
    return text, scene


def _rotvec(R):
    """Rotation vector of R (independent of the package: SciPy)."""
    from scipy.spatial.transform import Rotation

    return Rotation.from_matrix(R).as_rotvec()


@pytest.mark.parametrize("where", ["command line", "scene file"])
def test_actuate_tip_pose(tmp_path, capsys, where):
    """--tip-pose X Y Z RX RY RZ (position [m], rotation vector [rad]) or a [target]
    tip_pose table: the six displacements of a forward solve come back."""
    q_goal = [1.5e-3, 5e-4, 0.0, 0.0, 1.2e-3, 4e-4]
    _, goal_scene = _helical_six(q_goal)
    goal = tr.solve(goal_scene, strict=True)
    p, rv = goal.tip_position.tolist(), _rotvec(goal.tip_rotation).tolist()
    text, _ = _helical_six([5e-4] * 6)
    args = []
    if where == "command line":
        args = ["--tip-pose"] + [repr(v) for v in p + rv]
    else:
        text += f"\n[target]\ntip_pose = {{position = {p!r}, rotation_vector = {rv!r}}}\n"
    scene_file = tmp_path / "six.toml"
    scene_file.write_text(text)
    rc, stdout, _ = run_main(
        ["actuate", str(scene_file), "--out", str(tmp_path / "o")] + args, capsys
    )
    assert rc == EXIT_OK, stdout
    summary = json.loads((tmp_path / "o" / "solution.json").read_text())
    # the pose fixes the six controls to ~1e-12 m (tests/test_actuate.py)
    np.testing.assert_allclose(summary["displacement_m"], q_goal, rtol=0, atol=1e-10)


@pytest.mark.parametrize(
    "edit, args, key",
    [
        (None, ["--tip-angle", "60dg"], "--tip-angle"),
        (
            ('tip_angle = "45deg"', "tip_pose = {position = [0, 0, 0.2]}"),
            [],
            "target.tip_pose",
        ),
        (
            ('tip_angle = "45deg"', "tip_pose = {position = [0, 0], rotation_vector = [0, 0, 0]}"),
            [],
            "target.tip_pose.position",
        ),
        (None, ["--tip-angle", "1", "--tip-position", "0", "0", "0.2"], "one of"),
        (None, ["--tendons", "a"], "--tendons"),
        (('tip_angle = "45deg"', 'tip_anlge = "45deg"'), [], "target.tip_anlge"),
        (('tip_angle = "45deg"', 'tip_angle = "45deg"\ntip_position = [0, 0, 0.2]'), [], "target"),
        (('tip_angle = "45deg"', 'tip_angle = "45deg"\ntendons = [3]'), [], "target.tendons[0]"),
        (('tip_angle = "45deg"', "tip_angle = true"), [], "target.tip_angle"),
        (('[target]\ntip_angle = "45deg"', ""), [], "no target"),
    ],
)
def test_actuate_bad_input_exit_2(tmp_path, capsys, edit, args, key):
    text = (EXAMPLES / "actuate_under_load.toml").read_text()
    if edit is not None:
        assert edit[0] in text
        text = text.replace(edit[0], edit[1], 1)
    scene = tmp_path / "bad.toml"
    scene.write_text(text)
    rc, _, err = run_main(["actuate", str(scene), "--out", str(tmp_path / "out")] + args, capsys)
    assert rc == EXIT_BAD_INPUT
    assert key in err and "bad.toml" in err
    assert not (tmp_path / "out").exists()  # nothing written for bad input


def test_figures_closed_form_subset(tmp_path, capsys):
    rc, out, err = run_main(
        ["figures", "--out", str(tmp_path), "--fast", "--only", "fig03,fig07,fig22"], capsys
    )
    assert rc == EXIT_OK, err
    for k in ("fig03", "fig07", "fig22"):
        assert (tmp_path / f"{k}.png").stat().st_size > 1000
    index = (tmp_path / "index.md").read_text()
    assert "fig07.png" in index and "Fig. 7" in index


def test_figures_formats(tmp_path, capsys):
    # --format writes each figure once per format; the files are what their suffix says
    rc, out, err = run_main(
        ["figures", "--out", str(tmp_path), "--fast", "--only", "fig07", "--format", "pdf,svg"],
        capsys,
    )
    assert rc == EXIT_OK, err
    assert (tmp_path / "fig07.pdf").read_bytes()[:5] == b"%PDF-"
    assert b"<svg" in (tmp_path / "fig07.svg").read_bytes()[:2000]
    assert not (tmp_path / "fig07.png").exists()
    index = (tmp_path / "index.md").read_text()
    assert "![fig07](fig07.svg)" in index and "[fig07.pdf](fig07.pdf)" in index
    rc, _, err = run_main(["figures", "--out", str(tmp_path), "--format", "png,jpeg"], capsys)
    assert rc == EXIT_BAD_INPUT and "jpeg" in err


def test_figures_all(tmp_path, capsys):
    # what `make demo` runs (here with the fast setting): every figure, no failure
    rc, out, err = run_main(["figures", "--out", str(tmp_path), "--fast"], capsys)
    assert rc == EXIT_OK, err
    pngs = sorted(p.name for p in tmp_path.glob("*.png"))
    assert len(pngs) == 20 and "FAILED" not in (tmp_path / "index.md").read_text()


def test_figures_list_and_unknown(tmp_path, capsys):
    rc, out, _ = run_main(["figures", "--out", str(tmp_path), "--list"], capsys)
    keys = [line.split(":")[0] for line in out.splitlines()]
    expected = [
        "fig01",
        "fig03",
        "fig06",
        "fig07",
        "fig08",
        "fig10",
        "fig11",
        "fig12",
        "fig13",
        "fig14",
        "fig15",
        "fig16",
        "fig17",
        "fig18",
        "fig20",
        "fig21",
        "fig22",
        "fig23",
        "fig25",
        "fig25_hysteresis",
    ]
    assert rc == EXIT_OK and keys == expected
    rc, _, err = run_main(["figures", "--out", str(tmp_path), "--only", "fig99"], capsys)
    assert rc == EXIT_BAD_INPUT and "fig99" in err


def test_bench_dispatches_to_bench_main(monkeypatch, capsys):
    calls = []
    mod = types.ModuleType("tendonrod.bench")
    mod.main = lambda argv: calls.append(argv) or 0
    monkeypatch.setitem(sys.modules, "tendonrod.bench", mod)
    monkeypatch.setattr(tr, "bench", mod, raising=False)
    rc, _, _ = run_main(["bench", "work-precision", "--out", "d", "--quick"], capsys)
    assert rc == 0 and calls == [["work-precision", "--out", "d", "--quick"]]
    rc, _, _ = run_main(["bench", "--help"], capsys)  # --help goes to bench.main
    assert rc == 0 and calls[-1] == ["--help"]


def test_version(capsys):
    rc, out, _ = run_main(["--version"], capsys)
    assert rc == EXIT_OK and out.strip() == f"tendonrod {tr.__version__}"


def test_help_documents_every_exit_code(capsys):
    rc, out, _ = run_main(["--help"], capsys)
    text = " ".join(out.split())  # argparse wraps the epilog
    assert rc == EXIT_OK
    for code in ("0 ok", "1 did not converge", "2 bad input", "3 an optional dependency"):
        assert code in text


# A Python in which the given top-level modules cannot be imported (as if not installed:
# a meta-path finder ahead of every other refuses them), running the command line or a
# snippet; the modules are installed here, so blocking is the only way to miss them.
BLOCKED = """
import sys
BLOCK = set(sys.argv[1].split(","))

class Block:
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in BLOCK:
            raise ModuleNotFoundError(f"No module named {name!r}", name=name)
        return None

sys.meta_path.insert(0, Block())
del sys.argv[1]
"""


def run_blocked(blocked, argv, cwd):
    code = BLOCKED + "from tendonrod.__main__ import main\nsys.exit(main(sys.argv[1:]))\n"
    return subprocess.run(
        [sys.executable, "-c", code, blocked, *argv],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=120,
    )


@pytest.mark.parametrize(
    "argv",
    [
        ["solve", str(EXAMPLES / "slack_robot.toml"), "--plot"],
        ["actuate", str(EXAMPLES / "slack_robot.toml"), "--tip-angle", "10deg", "--plot"],
        ["figures", "--only", "fig03"],
    ],
)
def test_missing_matplotlib_exit_3(tmp_path, argv):
    out = tmp_path / "out"
    p = run_blocked("matplotlib", [*argv, "--out", str(out)], tmp_path)
    assert p.returncode == EXIT_MISSING_DEPENDENCY, p.stderr
    # one line, naming the extra; nothing solved or written before the check
    assert p.stderr.count("\n") == 1, p.stderr
    assert "matplotlib" in p.stderr and "pip install 'tendonrod[plot]'" in p.stderr
    assert not out.exists()


def test_figures_list_needs_no_matplotlib(tmp_path):
    p = run_blocked("matplotlib", ["figures", "--list", "--out", str(tmp_path)], tmp_path)
    assert p.returncode == EXIT_OK, p.stderr
    assert p.stdout.startswith("fig01:")


def test_plot_without_matplotlib_names_the_extra(tmp_path):
    # the library: tr.plot's functions raise ModuleNotFoundError with the pip command
    code = BLOCKED + (
        "import tendonrod as tr\n"
        "rod = tr.Rod(length=0.2, diameter=0.8e-3, E=207e9, G=79.6e9, kirchhoff=True)\n"
        "robot = tr.Robot(rod, [tr.Tendon(offset=0.008, angle=0.0)])\n"
        "scene = tr.Scene(robot, tension=[1.0])\n"
        "try:\n"
        "    tr.plot.robot(tr.solve(scene), scene)\n"
        "except ModuleNotFoundError as exc:\n"
        "    print(type(exc).__name__, exc.name, exc)\n"
    )
    p = subprocess.run(
        [sys.executable, "-c", code, "matplotlib"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=120,
    )
    assert p.returncode == 0, p.stderr
    assert p.stdout.startswith("MissingExtraError matplotlib tendonrod.plot needs matplotlib")
    assert "pip install 'tendonrod[plot]'" in p.stdout


@pytest.mark.parametrize("module, extra", [("tqdm", "progress"), ("distributed", "dask")])
def test_missing_optional_module_exit_3(monkeypatch, capsys, module, extra):
    # any command that meets an optional dependency missing (here a stand-in for the
    # figures command) exits 3 with the extra named
    def needs(args):
        raise ModuleNotFoundError(f"No module named {module!r}", name=module)

    monkeypatch.setattr("tendonrod.__main__._cmd_figures", needs)
    rc, _, err = run_main(["figures", "--out", "x"], capsys)
    assert rc == EXIT_MISSING_DEPENDENCY
    assert err.count("\n") == 1 and f"pip install 'tendonrod[{extra}]'" in err


def test_missing_other_module_is_not_exit_3(monkeypatch, capsys):
    # a module no extra brings is a broken installation: the error propagates
    def needs(args):
        raise ModuleNotFoundError("No module named 'tendonrod._core'", name="tendonrod._core")

    monkeypatch.setattr("tendonrod.__main__._cmd_figures", needs)
    with pytest.raises(ModuleNotFoundError, match="_core"):
        main(["figures", "--out", "x"])
