"""make typecheck, the user's side: mypy over the code a user copies -- the README's
Python blocks, every documentation page's examples (its testsetup and testcode blocks, and
the user guide's plain ``python`` blocks) and the notebooks' code cells -- each page or notebook extracted
to one module, checked as a user's script would be: mypy's defaults, tendonrod's own types
(py.typed, _core.pyi) from this tree, errors reported only in the extracted code.

    python tools/typecheck_examples.py [--keep DIR]

Exits with mypy's status; a finding names the extracted file and line and the page it
came from (the extracted files keep a comment with the source line of every block).
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import re
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parent.parent
# the fences whose code runs: MyST's doctest directives and plain Python blocks
FENCE = re.compile(r"^(`{3,})\s*(\{testsetup\}|\{testcode\}|python)\s*(.*)$")
# what conf.py's doctest_global_setup gives every page
DOC_SETUP = "ROOT = ''\nimport numpy as np\nimport tendonrod as tr\n"
# A user's configuration: mypy's defaults, except that a name may be rebound to a value of
# another type (notebooks do: x = 0.5, later x = np.linspace(...)); errors only in the
# extracted code (follow_imports = silent); third-party modules without type information
# ignored, as a user's mypy would be told to.
CONFIG = """[mypy]
python_version = 3.10
follow_imports = silent
allow_redefinition = true

[mypy-scipy.*,tqdm.*,ipywidgets.*,IPython.*]
ignore_missing_imports = true
"""


def markdown_blocks(path: pathlib.Path, plain: bool) -> list[tuple[int, str]]:
    """(first line, code) of every runnable fenced block of a Markdown page, in order:
    the doctest directives' blocks, and with ``plain`` the ``python`` blocks too."""
    blocks, lines, i = [], path.read_text(encoding="utf-8").splitlines(), 0
    while i < len(lines):
        m = FENCE.match(lines[i].strip())
        if not m or (m.group(2) == "python" and not plain):
            i += 1
            continue
        fence, start, body = m.group(1), i + 2, []
        i += 1
        while i < len(lines) and not lines[i].strip().startswith(fence):
            if not lines[i].lstrip().startswith(":"):  # a directive's options
                body.append(lines[i])
            i += 1
        blocks.append((start, "\n".join(body)))
        i += 1
    return blocks


def notebook_cells(path: pathlib.Path) -> list[tuple[int, str]]:
    """(cell number, code) of every code cell; IPython magics and shell lines dropped."""
    nb = json.loads(path.read_text(encoding="utf-8"))
    cells = []
    for k, cell in enumerate(nb["cells"], 1):
        if cell["cell_type"] != "code":
            continue
        src = "".join(cell["source"])
        src = "\n".join(
            "pass  # " + ln if ln.lstrip().startswith(("%", "!")) else ln for ln in src.splitlines()
        )
        cells.append((k, src))
    return cells


def module_text(source: pathlib.Path, blocks, prefix: str, unit: str) -> str:
    rel = source.relative_to(ROOT)
    parts = [f"# extracted from {rel}\n{prefix}"]
    for where, code in blocks:
        parts.append(f"# ---- {rel}, {unit} {where}\n{code}\n")
    return "\n".join(parts)


def extract(out: pathlib.Path) -> list[pathlib.Path]:
    files = []
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
    for page in pages:
        # plain python blocks: the README's and the user guide's are examples; elsewhere
        # (docs/design.md) they sketch an API with names the text defines
        rel = page.relative_to(ROOT).parts
        blocks = markdown_blocks(page, plain=rel[0] == "README.md" or rel[:2] == ("docs", "guide"))
        if not blocks:
            continue
        prefix = "" if page.name == "README.md" else DOC_SETUP
        name = "_".join(page.relative_to(ROOT).with_suffix("").parts).replace("-", "_")
        target = out / f"{name}.py"
        target.write_text(module_text(page, blocks, prefix, "line"), encoding="utf-8")
        files.append(target)
    for nb in sorted((ROOT / "notebooks").glob("*.ipynb")):
        target = out / f"notebook_{nb.stem}.py"
        target.write_text(module_text(nb, notebook_cells(nb), "", "cell"), encoding="utf-8")
        files.append(target)
    return files


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--keep", help="write the extracted modules here (kept)")
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="tendonrod-user-types.") as tmp:
        out = pathlib.Path(args.keep or tmp)
        out.mkdir(parents=True, exist_ok=True)
        files = extract(out)
        (out / "mypy.ini").write_text(CONFIG, encoding="utf-8")
        env = dict(os.environ, MYPYPATH=str(ROOT))  # tendonrod from this tree
        cmd = [sys.executable, "-m", "mypy", "--config-file", str(out / "mypy.ini")]
        cmd += ["--cache-dir", str(ROOT / ".mypy_cache" / "user"), *map(str, files)]
        print(f"mypy over {len(files)} extracted modules (README, docs pages, notebooks)")
        return subprocess.run(cmd, cwd=out, env=env).returncode


if __name__ == "__main__":
    sys.exit(main())
