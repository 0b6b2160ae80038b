#!/usr/bin/env python3
"""House rules of the tendonrod tree: every file a room with one job.

Fails (exit status 1, listing the offenders) when

- a C file (``csrc/*.c``, ``csrc/*.h``, ``tendonrod/**/*.c``) has more than 800 lines,
- a Python module (``tendonrod/**/*.py``) has more than 600 lines,
- the import graph inside the ``tendonrod`` package has a cycle.

Lines are counted as ``wc -l`` counts them (newline characters).  The import graph is
read with :mod:`ast` from every module of the package: imports at module level and
inside functions alike, relative imports resolved, ``from pkg import name`` an edge to
the submodule ``pkg.name`` when there is one (a compiled extension such as
``tendonrod._core`` counts as one; else the edge goes to ``pkg``), and the names a
package's ``__init__`` lists in ``_LAZY_SUBMODULES`` (attributes imported on first
use) edges from that package.  Importing a submodule also runs its parent packages'
``__init__``; those implicit edges are not counted (every module would otherwise
depend on the package root).

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
import sys
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
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
