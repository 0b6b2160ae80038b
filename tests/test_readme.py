"""The README's Python examples run as written (in a scratch directory, so that nothing
they might write lands in the checkout), and its links into the repository resolve."""

import pathlib
import re
import warnings

import pytest

README = pathlib.Path(__file__).resolve().parents[1] / "README.md"
BLOCKS = re.findall(r"```python\n(.*?)```", README.read_text(), re.S)


def test_readme_has_examples():
    assert len(BLOCKS) >= 2  # the quick start (the solver) and the closed forms


def test_readme_links_resolve():
    """Every relative link of the front page (into docs/, CONTRIBUTING, ...) names a file."""
    links = re.findall(r"\]\(([^)#]+)\)", README.read_text())
    local = [ln for ln in links if "://" not in ln]
    assert any(ln.startswith("docs/") for ln in local)
    missing = [ln for ln in local if not (README.parent / ln).is_file()]
    assert not missing, f"README links to missing files: {missing}"


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
    # the solver example's solution converged, is taut at 0.2 N (below 0.358 N) and stable
    assert ns["sol"].success and ns["sol"].tension[0] > 0 and ns["sol"].stable
