#!/usr/bin/env python3
"""House rules of the tendonrod tree: every file a room with one job.

Fails (exit status 1, listing the offenders) when

- a C file (``csrc/*.c``, ``csrc/*.h``, ``tendonrod/**/*.c``) has more than 800 lines,
- a Python module (``tendonrod/**/*.py``) has more than 600 lines,
- the import graph inside the ``tendonrod`` package has a cycle,
- a file of ``csrc/`` is missing from the layer table of ``csrc/README.md`` (or the table
  names a file that does not exist), a function that ``solve()`` in ``csrc/tr_solve.c``
  calls (a driver stage) is not named in the README's list of stages, or a C file calls
  a function of a file in a higher layer or the files call each other in a circle,
- a ``csrc/*.c`` file defines a numeric constant of its own (``#define NAME 1e-6``): the
  policy constants live in the headers (``tr_internal.h`` by layer, ``tr_stab.h``,
  ``tr_qp.h``).

Lines are counted as ``wc -l`` counts them (newline characters).  The import graph is
read with :mod:`ast` from every module of the package: imports at module level and
inside functions alike, relative imports resolved, ``from pkg import name`` an edge to
the submodule ``pkg.name`` when there is one (a compiled extension such as
``tendonrod._core`` counts as one; else the edge goes to ``pkg``), and the names a
package's ``__init__`` lists in ``_LAZY_SUBMODULES`` (attributes imported on first
use) edges from that package.  Importing a submodule also runs its parent packages'
``__init__``; those implicit edges are not counted (every module would otherwise
depend on the package root).

The calls between C files are read from symbol tables: each ``csrc/*.c`` is compiled to
an object (the compiler ``$CC`` or ``cc``, ``csrc/CFLAGS`` at ``-O0``, GSL's flags from
pkg-config or gsl-config) and ``nm`` lists what it defines and what it needs; a needed
name defined in another file is an edge to that file (a call, or a function's address
taken).  Static inline functions of the headers are no edges (a header is in the bottom
layer).  Without a compiler or ``nm`` the call graph is reported as not checked.

The C and the Python checks are reported separately; ``--python-only`` or
``--c-only`` runs one of them.  On success the largest files and the size of the
import graph are printed; functions longer than 120 lines are listed as a note (the
house rule asks for a reason in a comment there), never as a failure.

Standard library only.  Usage::

    python tools/check_house.py [--python-only | --c-only] [--root DIR] [--top N]
"""

from __future__ import annotations

import argparse
import ast
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

C_MAX_LINES = 800
PY_MAX_LINES = 600
FUNCTION_NOTE_LINES = 120
PACKAGE = "tendonrod"


def count_lines(path: Path) -> int:
    """Newline characters in ``path``, as ``wc -l`` counts them."""
    return path.read_bytes().count(b"\n")


# --------------------------------------------------------------------------- files
def c_files(root: Path) -> list[Path]:
    files = sorted((root / "csrc").glob("*.c")) + sorted((root / "csrc").glob("*.h"))
    files += sorted((root / PACKAGE).rglob("*.c"))
    return files


def py_files(root: Path) -> list[Path]:
    return sorted((root / PACKAGE).rglob("*.py"))


def oversized(root: Path, files: list[Path], limit: int) -> tuple[list, list]:
    """(every file as (lines, relative path) largest first, those over ``limit``)."""
    sizes = sorted(((count_lines(f), f.relative_to(root).as_posix()) for f in files), reverse=True)
    return sizes, [(n, f) for n, f in sizes if n > limit]


# --------------------------------------------------------------------------- import graph
def module_name(root: Path, path: Path) -> str:
    """Dotted name of a module file (``tendonrod/paper/__init__.py`` -> ``tendonrod.paper``)."""
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _package_of(name: str, is_package: bool) -> str:
    """The package relative imports in module ``name`` start from."""
    return name if is_package else name.rpartition(".")[0]


def _resolve_relative(package: str, level: int, module: str | None) -> str | None:
    base = package.split(".")
    if level - 1 > len(base) - 1:
        return None  # beyond the top-level package
    if level > 1:
        base = base[: len(base) - (level - 1)]
    return ".".join(base + ([module] if module else []))


def _lazy_submodules(tree: ast.Module) -> list[str]:
    """String entries of a module-level ``_LAZY_SUBMODULES = (...)``."""
    out = []
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(
            isinstance(t, ast.Name) and t.id == "_LAZY_SUBMODULES" for t in node.targets
        ):
            if isinstance(node.value, (ast.Tuple, ast.List)):
                out += [
                    e.value
                    for e in node.value.elts
                    if isinstance(e, ast.Constant) and isinstance(e.value, str)
                ]
    return out


def extension_modules(root: Path) -> set[str]:
    """Dotted names of the package's compiled extension modules (built ``*.so``/``*.pyd``
    files, or a ``*.c`` file directly in a package directory, as ``tendonrod/_core.c``):
    leaves of the import graph."""
    out = set()
    for f in (root / PACKAGE).rglob("*"):
        if f.suffix in (".so", ".pyd") or (
            f.suffix == ".c" and (f.parent / "__init__.py").exists()
        ):
            rel = f.relative_to(root).parent.parts + (f.name.split(".")[0],)
            out.add(".".join(rel))
    return out


def import_graph(root: Path, files: list[Path]) -> dict[str, set[str]]:
    """Module -> the modules of the package it imports (see the module docstring);
    compiled extension modules are nodes without edges of their own."""
    sources = {module_name(root, f): f for f in files}
    modules = dict.fromkeys(extension_modules(root) - set(sources)) | sources
    graph: dict[str, set[str]] = {m: set() for m in modules}

    def target(name: str) -> str | None:
        # the longest prefix of ``name`` that is a module of the package
        while name:
            if name in modules:
                return name
            name = name.rpartition(".")[0]
        return None

    for name, path in sources.items():
        is_package = path.name == "__init__.py"
        package = _package_of(name, is_package)
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        found: set[str] = set()
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                for alias in node.names:
                    found.add(target(alias.name) or "")
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = _resolve_relative(package, node.level, node.module)
                else:
                    base = node.module
                if base is None:
                    continue
                for alias in node.names:
                    sub = f"{base}.{alias.name}"
                    found.add(sub if sub in modules else (target(base) or ""))
            elif (
                isinstance(node, ast.Call)
                and isinstance(node.func, ast.Attribute)
                and node.func.attr == "import_module"
                and node.args
                and isinstance(node.args[0], ast.Constant)
                and isinstance(node.args[0].value, str)
            ):
                lit = node.args[0].value
                level = len(lit) - len(lit.lstrip("."))
                full = _resolve_relative(package, level, lit.lstrip(".") or None) if level else lit
                found.add(target(full or "") or "")
        if is_package:
            found |= {
                f"{name}.{sub}" for sub in _lazy_submodules(tree) if f"{name}.{sub}" in modules
            }
        found.discard("")
        found.discard(name)
        graph[name] = found & set(modules)
    return graph


def cycles(graph: dict[str, set[str]]) -> list[tuple[list[str], list[str]]]:
    """The strongly connected components with more than one module (Tarjan): each as
    ``(its modules, one cycle through the first of them)``, the cycle's first module
    repeated at its end."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    components: list[list[str]] = []
    counter = [0]

    def strongconnect(v: str) -> None:
        # iterative Tarjan: deep import chains must not hit the recursion limit
        work = [(v, iter(sorted(graph[v])))]
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        while work:
            node, it = work[-1]
            for w in it:
                if w not in index:
                    index[w] = low[w] = counter[0]
                    counter[0] += 1
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(graph[w]))))
                    break
                if w in on_stack:
                    low[node] = min(low[node], index[w])
            else:
                work.pop()
                if work:
                    parent = work[-1][0]
                    low[parent] = min(low[parent], low[node])
                if low[node] == index[node]:
                    comp = []
                    while True:
                        w = stack.pop()
                        on_stack.discard(w)
                        comp.append(w)
                        if w == node:
                            break
                    if len(comp) > 1:
                        components.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            strongconnect(v)
    return [(comp, _one_cycle(graph, comp)) for comp in components]


def _one_cycle(graph: dict[str, set[str]], comp: list[str]) -> list[str]:
    """A shortest cycle through the first module of a strongly connected component."""
    inside = set(comp)
    start = comp[0]
    prev: dict[str, str] = {}
    frontier = [start]
    while frontier:
        nxt = []
        for v in frontier:
            for w in sorted(graph[v] & inside):
                if w == start:
                    path = [v]
                    while path[-1] != start:
                        path.append(prev[path[-1]])
                    return [start] + path[::-1][1:] + [start] if len(path) > 1 else [start, start]
                if w not in prev:
                    prev[w] = v
                    nxt.append(w)
        frontier = nxt
    return comp + [comp[0]]


# --------------------------------------------------------------------------- long functions
def long_functions(root: Path, files: list[Path], limit: int) -> list[tuple[int, str]]:
    """``(lines, "path:line name")`` of every function longer than ``limit`` lines, its
    docstring not counted, longest first."""
    out = []
    for f in files:
        tree = ast.parse(f.read_text(encoding="utf-8"), filename=str(f))
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                first = node.lineno
                body = node.body
                if (
                    body
                    and isinstance(body[0], ast.Expr)
                    and isinstance(body[0].value, ast.Constant)
                    and isinstance(body[0].value.value, str)
                ):
                    first = body[0].end_lineno  # the docstring does not count
                n = node.end_lineno - first + 1
                if n > limit:
                    out.append((n, f"{f.relative_to(root).as_posix()}:{node.lineno} {node.name}"))
    return sorted(out, reverse=True)


def long_c_functions(root: Path, files: list[Path], limit: int) -> list[tuple[int, str]]:
    """``(lines, "path:line name")`` of every C function body longer than ``limit`` lines.
    The tree is clang-formatted: a function body opens with ``{`` and closes with ``}`` in
    column 0, its name on the line before the ``{`` (or the line that ends the
    parameter list)."""
    out = []
    for f in files:
        lines = f.read_text(encoding="utf-8").split("\n")
        start, name = None, ""
        for i, line in enumerate(lines):
            if line == "{" and i > 0:
                start, name = i, "?"
                for j in range(i - 1, max(-1, i - 6), -1):  # the line that opens the signature
                    if lines[j][:1] not in ("", " ", "/", "*") and "(" in lines[j]:
                        cut = lines[j].split("(")[0].split()
                        name = cut[-1].lstrip("*") if cut else "?"
                        break
            elif line == "}" and start is not None:
                n = i - start + 1
                if n > limit:
                    out.append((n, f"{f.relative_to(root).as_posix()}:{start} {name}"))
                start = None
    return sorted(out, reverse=True)


# --------------------------------------------------------------------------- C layers
README = "csrc/README.md"
DRIVER = "csrc/tr_solve.c"
# Calls between C files that may break the layers, each with its reason: none.  A new
# entry must say why the call cannot go down (or through the driver) instead.
ALLOWED_EDGES: dict[tuple[str, str], str] = {}


def _section(text: str, heading: str) -> str:
    """The body of the README section whose heading starts with ``heading``."""
    start = text.find("\n" + heading)
    if start < 0:
        return ""
    end = text.find("\n## ", start + 1)
    return text[start : end if end > 0 else len(text)]


def readme_layers(text: str) -> tuple[list[str], dict[str, int]]:
    """``(layer names bottom up, file -> layer index)`` from the README's layer table: its
    rows ``| layer | files | job |``, a blank layer cell continuing the row above."""
    layers: list[str] = []
    where: dict[str, int] = {}
    for line in _section(text, "## The house").splitlines():
        if not line.startswith("|") or line.startswith("|---"):
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 2 or cells[0] == "layer":
            continue
        if cells[0]:
            layers.append(cells[0])
        if layers:
            for name in re.findall(r"`([^`]+)`", cells[1]):
                where[name] = len(layers) - 1
    return layers, where


def driver_stages(source: str) -> list[str]:
    """The functions ``solve()`` calls, in order: the body of ``static int solve(`` up to
    the closing brace in column 0 (the tree is clang-formatted)."""
    m = re.search(r"^static int solve\([^{]*?\)\n\{\n(.*?)^\}", source, re.S | re.M)
    if not m:
        return []
    out: list[str] = []
    for name in re.findall(r"\b([A-Za-z_]\w*)\s*\(", m.group(1)):
        if name not in ("if", "for", "while", "switch", "return", "sizeof") and not name.isupper():
            if name not in out:
                out.append(name)
    return out


def _gsl_cflags() -> list[str]:
    for cmd in (["pkg-config", "--cflags", "gsl"], ["gsl-config", "--cflags"]):
        if shutil.which(cmd[0]):
            r = subprocess.run(cmd, capture_output=True, text=True)
            if r.returncode == 0:
                return shlex.split(r.stdout)
    return []


def call_graph(root: Path) -> tuple[dict[str, set[str]], dict[tuple[str, str], set[str]], str]:
    """``(file -> files it calls, (caller, callee) -> the names, error)`` for the
    ``csrc/*.c`` files, from their objects' symbol tables; ``error`` non-empty (and the
    graph empty) when they could not be built or read."""
    cc = os.environ.get("CC") or shutil.which("cc") or shutil.which("gcc")
    nm = shutil.which("nm")
    if not cc or not nm:
        return {}, {}, "not checked: no C compiler or nm"
    flags = [
        ln.strip()
        for ln in (root / "csrc" / "CFLAGS").read_text().splitlines()
        if ln.strip() and not ln.startswith("#") and not ln.strip().startswith("-O")
    ]
    flags += ["-O0", "-w", "-I", str(root / "csrc")] + _gsl_cflags()
    sources = sorted((root / "csrc").glob("*.c"))
    with tempfile.TemporaryDirectory(prefix="check_house_") as tmp:

        def build(src: Path) -> tuple[str, str, str]:
            obj = Path(tmp) / (src.stem + ".o")
            r = subprocess.run(
                shlex.split(cc) + flags + ["-c", str(src), "-o", str(obj)],
                capture_output=True,
                text=True,
            )
            if r.returncode != 0:
                return src.name, "", f"{src.name} does not compile: {r.stderr.strip()[:400]}"
            r = subprocess.run([nm, "-P", "-g", str(obj)], capture_output=True, text=True)
            return src.name, r.stdout, "" if r.returncode == 0 else f"nm {src.name}: {r.stderr}"

        with ThreadPoolExecutor(max_workers=os.cpu_count() or 2) as pool:
            results = list(pool.map(build, sources))
    errors = [e for _, _, e in results if e]
    if errors:
        return {}, {}, "; ".join(errors)
    defined: dict[str, str] = {}
    needed: dict[str, set[str]] = {}
    for name, table, _ in results:
        needed[name] = set()
        for line in table.splitlines():
            parts = line.split()
            if len(parts) >= 2:
                if parts[1] == "U":
                    needed[name].add(parts[0])
                elif parts[1] in "TDBRCGSV":
                    defined[parts[0]] = name
    graph: dict[str, set[str]] = {name: set() for name in needed}
    why: dict[tuple[str, str], set[str]] = {}
    for name, syms in needed.items():
        for sym in syms:
            other = defined.get(sym)
            if other and other != name:
                graph[name].add(other)
                why.setdefault((name, other), set()).add(sym)
    return graph, why, ""


NUMERIC_DEFINE = re.compile(r"^#define\s+([A-Za-z]\w*)\s+\(?[-+]?\.?[0-9]", re.M)


def numeric_defines(path: Path) -> list[str]:
    """The numeric constants ``path`` defines (names with a leading underscore, such as
    feature-test macros, aside)."""
    return NUMERIC_DEFINE.findall(path.read_text(encoding="utf-8"))


def check_c_layers(root: Path) -> bool:
    """The README's layer table and stage list against ``csrc/``, and the calls between
    the C files against the layers (see the module docstring)."""
    text = (root / README).read_text(encoding="utf-8")
    layers, where = readme_layers(text)
    files = sorted(p.name for p in (root / "csrc").iterdir() if p.suffix in (".c", ".h"))
    missing = [f for f in files if f not in where]
    stale = sorted(f for f in where if f.endswith((".c", ".h")) and f not in files)
    named = set(re.findall(r"`([^`]+)`", _section(text, "## What `tr_solve` does")))
    stages = driver_stages((root / DRIVER).read_text(encoding="utf-8"))
    unnamed = [s for s in stages if s not in named]
    graph, why, error = call_graph(root)
    upward = sorted(
        (a, b)
        for a, outs in graph.items()
        for b in outs
        if a in where and b in where and where[a] < where[b] and (a, b) not in ALLOWED_EDGES
    )
    pruned = {a: {b for b in outs if (a, b) not in ALLOWED_EDGES} for a, outs in graph.items()}
    loops = cycles(pruned)
    local = {
        p.name: numeric_defines(p)
        for p in sorted((root / "csrc").glob("*.c"))
        if numeric_defines(p)
    }
    shared = {
        p.name: len(numeric_defines(p))
        for p in sorted((root / "csrc").glob("*.h"))
        if numeric_defines(p)
    }
    ok = not (missing or stale or unnamed or upward or loops or local or not stages or not layers)
    print(
        f"C layers: {'ok' if ok else 'FAIL'} ({len(files)} files of csrc/ in {len(layers)} layers)"
    )
    for f in missing:
        print(f"  csrc/{f}: not in the layer table of {README}")
    for f in stale:
        print(f"  {README} lists {f}, which csrc/ does not have")
    if not stages:
        print(f"  {DRIVER}: no solve() found (the driver's list of stages)")
    for s in unnamed:
        print(f"  driver stage {s} (called by solve() in {DRIVER}) is not named in {README}")
    for a, b in upward:
        print(
            f"  upward call: {a} ({layers[where[a]]}) -> {b} ({layers[where[b]]}): "
            f"{', '.join(sorted(why[(a, b)]))}"
        )
    for comp, loop in loops:
        print(f"  call cycle among {len(comp)} files: {', '.join(comp)}")
        print(f"    e.g. {' -> '.join(loop)}")
    if error:
        print(f"  call graph: {error}")
        ok = ok and error.startswith("not checked")
    else:
        nedges = sum(len(v) for v in graph.values())
        print(
            f"  call graph: {len(graph)} files, {nedges} edges between files, "
            f"{len(upward)} upward, {len(loops)} cycle{'s' if len(loops) != 1 else ''}"
            f"{f', {len(ALLOWED_EDGES)} allowed exceptions' if ALLOWED_EDGES else ''}"
        )
    if stages and not unnamed:
        print(f"  driver stages: {len(stages)}, each named in {README}")
    for name, consts in local.items():
        print(
            f"  csrc/{name} defines constants of its own (to its layer's header): {', '.join(consts)}"
        )
    print(
        "  numeric constants: "
        + ", ".join(f"{n} in {h}" for h, n in sorted(shared.items(), key=lambda kv: -kv[1]))
        + ("; none in a .c file" if not local else "")
    )
    return ok


# --------------------------------------------------------------------------- report
def check_python(root: Path, top: int) -> bool:
    files = py_files(root)
    sizes, big = oversized(root, files, PY_MAX_LINES)
    graph = import_graph(root, files)
    loops = cycles(graph)
    ok = not big and not loops
    print(f"Python: {'ok' if ok else 'FAIL'} ({len(files)} modules under {PACKAGE}/)")
    for n, f in big:
        print(f"  {f}: {n} lines > {PY_MAX_LINES}")
    for comp, loop in loops:
        print(f"  import cycle among {len(comp)} modules: {', '.join(comp)}")
        print(f"    e.g. {' -> '.join(loop)}")
    print(f"  largest modules (limit {PY_MAX_LINES} lines):")
    for n, f in sizes[:top]:
        print(f"    {n:6d}  {f}")
    nedges = sum(len(v) for v in graph.values())
    print(
        f"  import graph: {len(graph)} modules, {nedges} edges, "
        f"{len(loops)} cycle{'s' if len(loops) != 1 else ''}"
    )
    longs = long_functions(root, files, FUNCTION_NOTE_LINES)
    if longs:
        print(f"  note: functions over {FUNCTION_NOTE_LINES} lines (give the reason in a comment):")
        for n, where in longs:
            print(f"    {n:6d}  {where}")
    return ok


def check_c(root: Path, top: int) -> bool:
    files = c_files(root)
    sizes, big = oversized(root, files, C_MAX_LINES)
    ok = not big
    print(f"C: {'ok' if ok else 'FAIL'} ({len(files)} files in csrc/ and {PACKAGE}/)")
    for n, f in big:
        print(f"  {f}: {n} lines > {C_MAX_LINES}")
    print(f"  largest files (limit {C_MAX_LINES} lines):")
    for n, f in sizes[:top]:
        print(f"    {n:6d}  {f}")
    longs = long_c_functions(root, files, FUNCTION_NOTE_LINES)
    if longs:
        print(f"  note: functions over {FUNCTION_NOTE_LINES} lines (give the reason in a comment):")
        for n, where in longs:
            print(f"    {n:6d}  {where}")
    return ok


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    which = ap.add_mutually_exclusive_group()
    which.add_argument("--python-only", action="store_true", help="only the Python checks")
    which.add_argument("--c-only", action="store_true", help="only the C checks")
    ap.add_argument(
        "--root",
        type=Path,
        default=Path(__file__).resolve().parent.parent,
        help="repository root (default: the parent of tools/)",
    )
    ap.add_argument("--top", type=int, default=8, help="largest files to list (default 8)")
    args = ap.parse_args(argv)
    ok = True
    if not args.c_only:
        ok &= check_python(args.root, args.top)
    if not args.python_only:
        ok &= check_c(args.root, args.top)
        ok &= check_c_layers(args.root)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
