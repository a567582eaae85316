"""The layout shows the design (issue 35): no import circle, no module over 400 lines, no function over 80 lines.

Scope: the host package (python/restircl), the Blender add-on (addon/restircl_blender) and, for the line count of a
module, the OpenCL sources (opencl/**/*.h, *.cl): a header is a module on the device side of the same house, one
concept per file, so the same bound applies. Functions are counted in Python only: the OpenCL kernels have no
parser here, and are short by construction (one stage per file).

Imports count wherever they are written: at module level, inside a function and under ``if TYPE_CHECKING:``. A cycle
that a function-level import defers still ties the modules together (neither can be understood, tested or moved
without the other), so it is a cycle. An import names one module: ``import a.b`` and ``from a.b import c`` give the
edge to ``a.b``, or to ``a.b.c`` when that is a module itself. The packages above it, which Python executes on the
way, are not counted: they are docstring-only, but for the public API ``restircl/__init__.py`` (imported by the
add-on, never from inside the package) and ``restircl/scenes/__init__.py``, whose imports are edges of their own.

Exceptions are declarative tables only, each named below with the reason; there are none today.
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: (source root, top-level package): module names are paths under the root
PACKAGES = ((ROOT / "python", "restircl"), (ROOT / "addon", "restircl_blender"))
OPENCL = ROOT / "opencl"

MAX_MODULE_LINES = 400
MAX_FUNCTION_LINES = 80

#: modules (path relative to the repository root) over MAX_MODULE_LINES that are declarative tables: reason
MODULE_TABLES: dict[str, str] = {
    "opencl/bsdf/thin_film_table.h": "generated data, 3072 numbers (upload/thin_film_table.py, checked by --check)",
}
#: functions ("path:qualified name") over MAX_FUNCTION_LINES that are declarative tables: reason
FUNCTION_TABLES: dict[str, str] = {}


def module_files(source_root: Path, package: str) -> dict[str, Path]:
    """Module name -> file, for every .py file of the package under source_root."""
    files = {}
    for path in sorted((source_root / package).rglob("*.py")):
        parts = list(path.relative_to(source_root).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        files[".".join(parts)] = path
    return files


def _resolve(module: str, is_package: bool, level: int, name: str | None) -> str:
    """The absolute name of a relative import `from <level dots><name> import ...` written in `module`."""
    if level == 0:
        return name or ""
    base = module.split(".")
    if not is_package:
        base = base[:-1]
    if level > 1:
        base = base[: len(base) - (level - 1)]
    return ".".join(base + ([name] if name else []))


def imported_modules(module: str, path: Path, known: set[str]) -> set[str]:
    """The modules of `known` that `module` (file `path`) imports anywhere in its body."""
    is_package = path.name == "__init__.py"
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names if alias.name in known)
        elif isinstance(node, ast.ImportFrom):
            target = _resolve(module, is_package, node.level, node.module)
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                if sub in known:
                    found.add(sub)
                elif target in known:
                    found.add(target)
    found.discard(module)
    return found


def import_graph(packages: tuple[tuple[Path, str], ...] = PACKAGES) -> dict[str, set[str]]:
    """Module -> the modules it imports, among the modules of all `packages` together."""
    files: dict[str, Path] = {}
    for source_root, package in packages:
        files.update(module_files(source_root, package))
    known = set(files)
    return {module: imported_modules(module, path, known) for module, path in files.items()}


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The import circles of `graph`: each strongly connected component of more than one module, as one shortest
    closed path through its first module (sorted), so the message reads as the chain of imports to break."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    components: list[set[str]] = []

    def visit(root: str) -> None:
        # iterative Tarjan: a frame is (module, iterator over its imports)
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(graph[child]))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = set()
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.add(member)
                    if member == node:
                        break
                components.append(component)

    for module in sorted(graph):
        if module not in index:
            visit(module)
    return [_shortest_circle(graph, component) for component in components if len(component) > 1]


def _shortest_circle(graph: dict[str, set[str]], component: set[str]) -> list[str]:
    """A shortest path start -> ... -> start inside `component` (breadth first), start its first module."""
    start = min(component)
    parent: dict[str, str] = {}
    frontier = [start]
    while frontier:
        following = []
        for node in frontier:
            for child in sorted(graph[node] & component):
                if child == start:
                    path = [node]
                    while path[-1] != start:
                        path.append(parent[path[-1]])
                    return [start, *reversed(path[:-1]), start] if node != start else [start, start]
                if child not in parent:
                    parent[child] = node
                    following.append(child)
        frontier = following
    raise AssertionError(f"{sorted(component)} is not strongly connected")


def long_modules() -> list[tuple[str, int]]:
    """(path, lines) of every Python module and OpenCL source over MAX_MODULE_LINES."""
    paths = [path for source_root, package in PACKAGES for path in (source_root / package).rglob("*.py")]
    paths += [path for path in OPENCL.rglob("*") if path.suffix in (".h", ".cl")]
    found = []
    for path in sorted(paths):
        name = str(path.relative_to(ROOT))
        lines = len(path.read_text().splitlines())
        if lines > MAX_MODULE_LINES:
            found.append((name, lines))
    return found


def long_functions(path: Path, name: str) -> list[tuple[str, int]]:
    """("name:qualified function", lines) of every function or method of the file over MAX_FUNCTION_LINES; a nested
    function counts on its own and inside its parent."""
    found = []

    def walk(node: ast.AST, prefix: str) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
                qualified = f"{prefix}{child.name}"
                if not isinstance(child, ast.ClassDef):
                    assert child.end_lineno is not None
                    lines = child.end_lineno - child.lineno + 1
                    if lines > MAX_FUNCTION_LINES:
                        found.append((f"{name}:{qualified}", lines))
                walk(child, qualified + ".")
            else:
                walk(child, prefix)

    walk(ast.parse(path.read_text(), str(path)), "")
    return found


def all_long_functions() -> list[tuple[str, int]]:
    found = []
    for source_root, package in PACKAGES:
        for path in sorted((source_root / package).rglob("*.py")):
            found += long_functions(path, str(path.relative_to(ROOT)))
    return found


def _circles_message(found: list[list[str]]) -> str:
    return "import circles:\n" + "\n".join(" -> ".join(circle) for circle in found)


def test_no_import_cycle():
    found = cycles(import_graph())
    assert not found, _circles_message(found)


def test_no_long_module():
    found = [(name, lines) for name, lines in long_modules() if name not in MODULE_TABLES]
    assert not found, f"modules over {MAX_MODULE_LINES} lines: {found}"


def test_no_long_function():
    found = [(key, lines) for key, lines in all_long_functions() if key not in FUNCTION_TABLES]
    assert not found, f"functions over {MAX_FUNCTION_LINES} lines: {found}"


def test_table_exceptions_are_needed():
    """A named exception that is no longer over its bound (or no longer exists) is stale: remove it."""
    assert set(MODULE_TABLES) <= {name for name, _ in long_modules()}
    assert set(FUNCTION_TABLES) <= {key for key, _ in all_long_functions()}


# The checker's power: synthetic packages with a known answer.


def _write(root: Path, files: dict[str, str]) -> None:
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)


def test_checker_finds_a_function_level_cycle(tmp_path):
    _write(tmp_path, {
        "pkg/__init__.py": '"""docstring only"""\n',
        "pkg/a.py": "from .b import g\n\n\ndef f():\n    return g()\n",
        "pkg/b.py": "def g():\n    from .a import f\n\n    return f\n",
        "pkg/c.py": "from . import a\n",
    })
    assert import_graph(((tmp_path, "pkg"),)) == {"pkg": set(), "pkg.a": {"pkg.b"}, "pkg.b": {"pkg.a"},
                                                  "pkg.c": {"pkg.a"}}
    assert cycles(import_graph(((tmp_path, "pkg"),))) == [["pkg.a", "pkg.b", "pkg.a"]]


def test_checker_finds_a_type_checking_cycle_across_packages(tmp_path):
    _write(tmp_path, {
        "one/__init__.py": "",
        "one/sub/__init__.py": "",
        "one/sub/x.py": "from typing import TYPE_CHECKING\n\nif TYPE_CHECKING:\n    from ...two.y import Y\n",
        "two/__init__.py": "",
        "two/y.py": "import one.sub.z\n",
        "one/sub/z.py": "from .. import sub\nfrom .x import X\n",
    })
    graph = import_graph(((tmp_path, "one"), (tmp_path, "two")))
    assert graph["one.sub.z"] == {"one.sub", "one.sub.x"}
    assert cycles(graph) == [["one.sub.x", "two.y", "one.sub.z", "one.sub.x"]]


def test_checker_passes_a_tree(tmp_path):
    _write(tmp_path, {"pkg/__init__.py": "", "pkg/a.py": "from .b import g\n", "pkg/b.py": "import os\n"})
    assert cycles(import_graph(((tmp_path, "pkg"),))) == []


def test_checker_counts_function_lines(tmp_path):
    body = "".join(f"        x{i} = {i}\n" for i in range(MAX_FUNCTION_LINES - 1))
    _write(tmp_path, {"m.py": f"def ok():\n{body}\n\nclass C:\n    def long(self):\n{body}        y = 0\n"})
    assert long_functions(tmp_path / "m.py", "m.py") == [("m.py:C.long", MAX_FUNCTION_LINES + 1)]
