"""C-level regression tests of the core, built straight from csrc/ (no Python glue)
with the same compiler and GSL flags the extension uses."""

import pathlib
import shlex
import shutil
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
CSRC = ROOT / "csrc"


def _gsl_flags():
    if shutil.which("pkg-config"):
        c = subprocess.run(["pkg-config", "--cflags", "gsl"], capture_output=True, text=True)
        l = subprocess.run(["pkg-config", "--libs", "gsl"], capture_output=True, text=True)
        if c.returncode == 0 and l.returncode == 0:
            return shlex.split(c.stdout), shlex.split(l.stdout)
    if shutil.which("gsl-config"):
        return (
            shlex.split(subprocess.check_output(["gsl-config", "--cflags"], text=True)),
            shlex.split(subprocess.check_output(["gsl-config", "--libs"], text=True)),
        )
    pytest.skip("GSL flags not found (pkg-config / gsl-config)")


@pytest.fixture(scope="module")
def build(tmp_path_factory):
    cc = shutil.which("cc") or shutil.which("gcc")
    if cc is None:
        pytest.skip("no C compiler")
    cflags, libs = _gsl_flags()
    out = tmp_path_factory.mktemp("cbuild")

    def _build(test_c, *extra):
        exe = out / pathlib.Path(test_c).stem
        srcs = [str(p) for p in sorted(CSRC.glob("*.c"))]
        cmd = [
            cc,
            "-std=c99",
            "-O1",
            "-g",
            "-Wall",
            *extra,
            "-I",
            str(CSRC),
            *cflags,
            str(test_c),
            *srcs,
            "-o",
            str(exe),
            *libs,
            "-lm",
        ]
        r = subprocess.run(cmd, capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        return exe

    return _build


def test_failed_record_keeps_output_nodes(build):
    exe = build(CSRC / "tests" / "record_reuse.c")
    r = subprocess.run([str(exe)], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr + r.stdout
    assert r.stdout.strip() == "ok"


def test_ctrl_c_reaches_a_loop_of_short_solves(build):
    """The poll hook's interval runs across solves: a loop of warm solves (each far
    shorter than TR_POLL_INTERVAL) and a batch of lean solves both reach a hook that says
    stop at its first call, bounded by counting (at most 20000 solves or points), and the
    batch's interrupt is not lost to its fallback from the lean to the full solve (the
    hook is called exactly once)."""
    exe = build(CSRC / "tests" / "poll_loop.c")
    r = subprocess.run([str(exe)], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr + r.stdout
    assert r.stdout.strip() == "ok"


def test_threads_share_one_compiled_model(build):
    """One compiled model, several threads at once, each with its own workspace: the
    same calls (values set in the workspace, warm solves, linearisations in the rod's EI
    and a tendon's EA, i.e. design perturbations) give bitwise the outputs of the same
    calls in series -- the model is only read (tr_data_set_values, tr_linearize vary the
    workspace's inputs, never the model).  Every solve and linearisation of the 4 families
    x 5 steps must succeed, so that the comparison covers them all."""
    exe = build(CSRC / "tests" / "threads_one_model.c", "-pthread")
    r = subprocess.run([str(exe)], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr + r.stdout
    assert r.stdout.strip() == "ok 20 solves 20 linearisations of 20"


def test_solves_allocate_nothing(build):
    """Nothing the core allocates between tr_data_alloc_ext(TR_ALLOC_ALL) and tr_data_free:
    a scene of each stress family (plain, large load, tendons planar and spatial, slack,
    off the load path and confirmed, buckled column, friction, multiple shooting, Cosserat
    with a tension), solved cold, then warm and cold again in the same workspace, while
    csrc/tests/alloc_count.c counts every malloc/calloc/realloc by caller.  The core's count
    is 0 in every family (the stability grids with room for the finest and the
    confirmation's workspace come with the workspace), and so is GSL's: the LU factorisations
    are the core's own (tru_lu_factor), GSL's steppers come with the workspace.  Then the
    calls over the driver on such workspaces: a path in a tendon's value (planar, spatial)
    and an actuation toward each target kind (angle, direction, position, pose): 0 by the
    core and by GSL too (their buffers come from the workspace's TR_ALLOC_CALLS reserve)."""
    import sys

    if not sys.platform.startswith("linux"):
        pytest.skip("interposes glibc's allocator")
    exe = build(CSRC / "tests" / "alloc_count.c", "-std=gnu99", "-ldl")
    r = subprocess.run([str(exe)], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr + r.stdout
    solves, calls = r.stdout.split("\n\n")
    rows = [line.split() for line in solves.splitlines()[1:] if line.strip()]
    assert len(rows) == 10, r.stdout
    for name, core0, gsl0, core1, gsl1, status in rows:
        assert (int(core0), int(core1)) == (0, 0), f"{name}: {core0} + {core1} allocations"
        assert (int(gsl0), int(gsl1)) == (0, 0), f"{name}: {gsl0} + {gsl1} GSL allocations"
        assert int(status) >= 0, f"{name}: the first solve failed ({status})"
    rows = [line.split() for line in calls.splitlines()[1:] if line.strip()]
    assert [row[0] for row in rows] == [
        "path_planar",
        "path_spatial",
        "actuate_angle",
        "actuate_direction",
        "actuate_position",
        "actuate_pose",
    ], r.stdout
    for name, core, gsl, status in rows:
        assert int(core) == 0, f"{name}: {core} allocations"
        assert int(gsl) == 0, f"{name}: {gsl} GSL allocations"
        assert int(status) >= 0, f"{name}: the call failed ({status})"


def test_the_extension_exports_only_its_init():
    """tendonrod._core is built with hidden visibility: of the names its dynamic symbol
    table defines, PyInit__core is the only one of ours (the core's tr_* and the glue's
    names stay inside)."""
    import sys

    import tendonrod._core as core

    nm = shutil.which("nm")
    if nm is None or not sys.platform.startswith("linux"):
        pytest.skip("needs nm and an ELF shared object")
    r = subprocess.run([nm, "-D", "--defined-only", core.__file__], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    names = sorted(line.split()[-1] for line in r.stdout.splitlines() if line.strip())
    # names the toolchain itself may add (an instrumented build's __asan_* globals, _init,
    # _fini) aside: ours never start with an underscore
    ours = [n for n in names if not n.startswith("_")]
    assert ours == ["PyInit__core"], ours


def test_the_house_check_fails_on_an_upward_call_a_cycle_and_a_missing_file(tmp_path):
    """tools/check_house.py (make lint) reads the calls between csrc files from their
    objects: on a copy of csrc/ where the residual (shooting layer) calls the driver, and
    the README's table leaves a file out, it fails and names each (and on csrc/ as it is,
    it passes)."""
    import importlib.util
    import io
    from contextlib import redirect_stdout

    if shutil.which("nm") is None or (shutil.which("cc") or shutil.which("gcc")) is None:
        pytest.skip("needs a C compiler and nm")
    spec = importlib.util.spec_from_file_location("check_house", ROOT / "tools" / "check_house.py")
    house = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(house)
    with redirect_stdout(io.StringIO()) as out:
        assert house.check_c_layers(ROOT), out.getvalue()
    if "not checked" in out.getvalue():
        pytest.skip("the call graph could not be read here")
    shutil.copytree(CSRC, tmp_path / "csrc", ignore=shutil.ignore_patterns("tests"))
    readme = tmp_path / "csrc" / "README.md"
    readme.write_text(readme.read_text().replace("| | `tr_watch.c` |", "| | watch |"))
    with open(tmp_path / "csrc" / "tr_residual.c", "a") as fh:
        fh.write("int tr_up(const tr_model *m, tr_data *d) { return tr_solve_warm(m, d); }\n")
    with redirect_stdout(io.StringIO()) as out:
        assert not house.check_c_layers(tmp_path)
    report = out.getvalue()
    assert "csrc/tr_watch.c: not in the layer table" in report
    assert "upward call: tr_residual.c (shooting) -> tr_solve.c (driver): tr_solve_warm" in report
    assert "call cycle among" in report and "tr_residual.c" in report


def test_element_hessian_reduced_matches_all_coordinates(build):
    """The element Hessian and gradient in the reduced variables (a Cosserat element's
    positions only through its chord: 45 hyper-dual passes instead of 78) equal those of
    one pass per pair of all its coordinates on 400 random Cosserat and Kirchhoff elements
    with three tendons: to 1e-12 of the largest entry (the reduction is exact; the
    program's comment says why this bound)."""
    exe = build(CSRC / "tests" / "element_hessian.c")
    r = subprocess.run([str(exe)], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr + r.stdout
    assert r.stdout.startswith("ok")


def test_condition_from_the_last_newton_jacobian_matches_a_fresh_one(build):
    """Where a cold solve returns its last Newton Jacobian instead of a fresh one at the
    solution, it agrees with a fresh finite-difference Jacobian there to 1e-3 and its
    condition to a factor 2 (the program's comment says why these bounds)."""
    exe = build(CSRC / "tests" / "condition_reuse.c")
    r = subprocess.run([str(exe)], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr + r.stdout
    assert r.stdout.strip() == "ok"
