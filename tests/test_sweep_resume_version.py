"""A sweep's progress bar (when it shows) and its file's tendonrod version (a resume
across versions says so and computes again)."""

import io
import json
import sys

import numpy as np
import pytest

import tendonrod as tr
from tendonrod.sweeps import _file as _sweep_file
from tendonrod.sweeps import _progress as _sweep_progress

FORCES = [(-f, 0.0, 0.0) for f in np.linspace(0.1, 1.2, 6)]


def base_scene():
    rod = tr.Rod(length=0.1, diameter=1.04e-3, E=210e9, G=80e9, kirchhoff=True)
    return tr.Scene(
        tr.Robot(rod, [tr.Tendon(offset=0.01)]),
        displacement=[0.0],
        loads=[tr.PointLoad(s=0.1, force=(0.0, 0.0, 0.0))],
    )


class _Tty(io.StringIO):
    def isatty(self):
        return True


@pytest.mark.parametrize(
    "env, tty, progress, shown",
    [
        ({}, True, None, True),  # a terminal
        ({}, False, None, False),  # a log file
        ({"CI": "true"}, True, None, False),  # CI, even on a terminal
        ({"CI": "0"}, True, None, True),  # CI=0 is no CI
        ({"TENDONROD_PROGRESS": "0"}, True, None, False),  # turned off
        ({"CI": "1"}, False, True, True),  # asked for
        ({}, True, False, False),  # refused
    ],
)
def test_progress_wanted(monkeypatch, env, tty, progress, shown):
    for k in ("CI", "TENDONROD_PROGRESS"):
        monkeypatch.delenv(k, raising=False)
    for k, v in env.items():
        monkeypatch.setenv(k, v)
    monkeypatch.setattr(sys, "stderr", _Tty() if tty else io.StringIO())
    assert _sweep_progress.wanted(progress) is shown


def test_progress_bar_in_a_terminal(monkeypatch):
    """On a terminal the default bar counts every point (shown after DELAY; a sweep that
    long is not needed to see that it is made and updated)."""
    monkeypatch.delenv("CI", raising=False)
    monkeypatch.delenv("TENDONROD_PROGRESS", raising=False)
    err = _Tty()
    monkeypatch.setattr(sys, "stderr", err)
    made = []
    real = _sweep_progress.progress_bar

    def spy(progress, npoints, done):
        bar = real(progress, npoints, done)
        made.append(bar)
        return bar

    monkeypatch.setattr(tr.sweeps.run, "progress_bar", spy)
    tr.sweep(base_scene(), {"loads[0].force": FORCES}, grid=False, chunksize=2)
    (bar,) = made
    assert bar is not None and bar.n == bar.total == len(FORCES) and bar.delay == 2.0
    made.clear()
    tr.sweep(base_scene(), {"loads[0].force": FORCES}, grid=False, chunksize=2, progress=True)
    assert made[0].delay == 0.0 and "6/6" in err.getvalue()  # asked for: shown at once


def test_resume_across_versions_recomputes(tmp_path, monkeypatch):
    sc, vary = base_scene(), {"loads[0].force": FORCES}
    kw = dict(grid=False, chunksize=2, progress=False)
    path = tmp_path / "s.jsonl"
    full = tr.sweep(sc, vary, file=path, **kw)
    header = json.loads(path.read_text().splitlines()[0])
    assert header["tendonrod"] == tr.__version__
    # the file as another version wrote it: its header names that version, and its
    # points are poisoned so that a resume reusing them would show
    lines = path.read_text().splitlines()
    header["tendonrod"] = "0.0.1"
    chunks = [json.loads(line) for line in lines[1:]]
    for c in chunks:
        for r in c["records"]:
            r["data"]["tip_position"] = [123.0, 0.0, 0.0]
    path.write_text("\n".join(json.dumps(o) for o in [header, *chunks]) + "\n")
    old = path.read_text()
    with pytest.warns(UserWarning, match=r"written by tendonrod 0\.0\.1, this is tendonrod"):
        res = tr.sweep(sc, vary, file=path, **kw)
    for k in full.data:
        assert np.array_equal(res[k], full[k]), k  # recomputed, nothing reused
    assert (tmp_path / "s.jsonl.tendonrod-0.0.1").read_text() == old  # kept aside
    assert json.loads(path.read_text().splitlines()[0])["tendonrod"] == tr.__version__
    # the same version resumes (nothing to do) silently
    again = tr.sweep(sc, vary, file=path, **kw)
    assert all(np.array_equal(again[k], full[k]) for k in full.data)


def test_fingerprint_includes_version(monkeypatch):
    args = (base_scene(), ["x"], [[1.0]], 1, None, None, None, True)
    a = _sweep_file.fingerprint_of(*args)
    monkeypatch.setattr(_sweep_file, "__version__", "9.9.9")
    assert _sweep_file.fingerprint_of(*args) != a
