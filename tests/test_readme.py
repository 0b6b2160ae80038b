"""The README's Python examples run as written (in a scratch directory, since the
sweep example writes its results file there)."""

import pathlib
import re
import warnings

import pytest

README = pathlib.Path(__file__).resolve().parents[1] / "README.md"
BLOCKS = re.findall(r"```python\n(.*?)```", README.read_text(), re.S)


def test_readme_has_examples():
    assert len(BLOCKS) >= 3


def test_readme_examples_run(tmp_path, monkeypatch):
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    monkeypatch.chdir(tmp_path)
    ns = {}
    with warnings.catch_warnings():
        # a non-converged solve in an example would be a README bug: make it fail
        import tendonrod as tr

        warnings.simplefilter("error", tr.ConvergenceWarning)
        for i, block in enumerate(BLOCKS):
            exec(compile(block, f"README.md python block {i}", "exec"), ns)
    # the solver example's solution converged and is taut at 0.2 N (below 0.358 N)
    assert ns["sol"].success and ns["sol"].tension[0] > 0
