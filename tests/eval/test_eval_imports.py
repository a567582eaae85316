"""The evaluation tools (restircl.eval) stay out of the library core: no core module imports them, and they import
one another without a circle. Read from the sources (every import statement, those inside functions too), and
checked once in a fresh interpreter. The command line (restircl.cli) is the one core package that reaches the
tools: its `stress`, `report`, `bench` and `compare` commands import them inside their `run` functions, never at
module level, so that `import restircl.cli.main` does not load them."""

from __future__ import annotations

import ast
import importlib.util
import subprocess
import sys
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2] / "python" / "restircl"


def _modules() -> dict[str, Path]:
    out = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = ("restircl", *path.relative_to(PACKAGE).with_suffix("").parts)
        out[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return out


MODULES = _modules()
FRONT_END = {m for m in MODULES if m.startswith("restircl.cli.")}
EVAL = sorted(m for m in MODULES if m.startswith("restircl.eval"))
CORE = sorted(m for m in MODULES if m not in EVAL)


def _imports(name: str) -> list[tuple[str, bool]]:
    """(imported restircl module, at module level) for every import statement of module `name`."""
    path = MODULES[name]
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    tree = ast.parse(path.read_text(), str(path))
    top = set(map(id, tree.body))
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join([*anchor, base] if base else anchor)
            # `from pkg import x` imports the module pkg.x when there is one, else a name of pkg
            targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in MODULES else base for a in node.names]
        else:
            continue
        out += [(t, id(node) in top) for t in targets if t in MODULES]
    return out


def test_the_core_never_imports_the_evaluation_tools():
    assert len(EVAL) > 10 and "restircl.render.pipeline" in CORE
    bad = [(m, t) for m in CORE for t, level in _imports(m) if t in EVAL and (level or m not in FRONT_END)]
    assert bad == [], f"core modules importing restircl.eval: {bad}"


def test_the_evaluation_tools_import_one_another_without_a_circle():
    graph = {m: sorted({t for t, _ in _imports(m) if t in EVAL and t != m}) for m in EVAL}
    state: dict[str, int] = {}  # 1: on the current path, 2: done

    def visit(m: str, path: list[str]) -> None:
        state[m] = 1
        for t in graph[m]:
            assert state.get(t) != 1, f"import circle: {' -> '.join([*path[path.index(t):], t])}"
            if t not in state:
                visit(t, [*path, t])
        state[m] = 2

    for m in EVAL:
        if m not in state:
            visit(m, [m])


def _needs_bpy(name: str) -> bool:
    """Whether module `name` imports bpy at module level (the Blender scene builders): it imports only with bpy."""
    tree = ast.parse(MODULES[name].read_text())
    return any((isinstance(n, ast.Import) and any(a.name == "bpy" for a in n.names))
               or (isinstance(n, ast.ImportFrom) and n.module == "bpy") for n in tree.body)


def test_importing_the_core_loads_no_evaluation_tool():
    # a fresh interpreter: every core module (the command line included; not __main__, which runs it), then every
    # tool, each from its own import (those that build Blender scenes where bpy is installed)
    assert _needs_bpy("restircl.eval.blender_scenes") and not _needs_bpy("restircl.eval.cycles.bridge")
    assert not [m for m in CORE if _needs_bpy(m)], "a core module needs bpy"
    core = [m for m in CORE if not m.endswith("__main__")]
    tools = [m for m in EVAL if importlib.util.find_spec("bpy") is not None or not _needs_bpy(m)]
    code = (
        "import importlib, sys\n"
        f"for m in {core!r}:\n"
        "    importlib.import_module(m)\n"
        "print(sorted(m for m in sys.modules if m.startswith('restircl.eval')))\n"
        f"for m in {tools!r}:\n"
        "    importlib.import_module(m)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=_env(), check=True)
    assert out.stdout.strip() == "[]"


def _env() -> dict[str, str]:
    import os

    return dict(os.environ, PYTHONPATH=os.pathsep.join([str(PACKAGE.parent), os.environ.get("PYTHONPATH", "")]))
