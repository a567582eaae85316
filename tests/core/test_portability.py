"""The kernels are OpenCL C 1.2 for every vendor, not only for PoCL: clang's OpenCL front end (libclang) parses the
whole program for NVIDIA's, AMD's and the SPIR target, with every feature flag on and with none, and must report no
error and no warning. No GPU is needed; the headers of the OpenCL builtins come from PoCL's pip package."""

from pathlib import Path

import pytest
from restircl.core.program import MAIN_SOURCE, format_options, opencl_dir
from restircl.render.features import ALL_FLAGS

cindex = pytest.importorskip("clang.cindex", reason="libclang not installed (pip install libclang)")

TARGETS = ("nvptx64-nvidia-nvcl", "amdgcn-amd-amdhsa", "spir64-unknown-unknown")


def _builtin_headers() -> Path:
    pocl = pytest.importorskip("pocl_binary_distribution", reason="PoCL's pip package carries opencl-c-base.h")
    for path in Path(pocl.__file__).parent.rglob("opencl-c-base.h"):
        return path.parent
    pytest.skip("opencl-c-base.h not found in pocl_binary_distribution")


def _clang_args(target: str) -> list[str]:
    return ["-x", "cl", "-cl-std=CL1.2", f"--target={target}", "-Xclang", "-fdeclare-opencl-builtins",
            "-Xclang", "-finclude-default-header", "-isystem", str(_builtin_headers())]


@pytest.mark.parametrize("target", TARGETS)
@pytest.mark.parametrize("features", ["all", "none"])
def test_program_parses_cleanly_for_other_vendors(target, features):
    flags = dict.fromkeys(ALL_FLAGS, features == "all")
    src = opencl_dir() / MAIN_SOURCE
    args = [*_clang_args(target), "-nogpulib", f"-I{opencl_dir()}", *format_options(flags)]
    tu = cindex.Index.create().parse(str(src), args=args)
    diags = [f"{d.location.file}:{d.location.line}: {d.spelling}" for d in tu.diagnostics
             if d.severity >= cindex.Diagnostic.Warning]
    assert not diags, "\n".join(diags)


def test_the_check_sees_errors():
    """The same parse of a broken kernel reports it (so a clean result above means something)."""
    src = "__kernel void k(__global float* a) { a[0] = undefined_name; int2 v = (int2)(1.5f, 2); }"
    tu = cindex.Index.create().parse("broken.cl", args=_clang_args(TARGETS[0]), unsaved_files=[("broken.cl", src)])
    messages = " ".join(d.spelling for d in tu.diagnostics)
    assert "undefined_name" in messages and "changes value" in messages


def _diagnostics(tu) -> list[str]:
    return [f"{d.location.file}:{d.location.line}: {d.spelling}" for d in tu.diagnostics
            if d.severity >= cindex.Diagnostic.Warning]


# ReSTIR GI reuses the paths' vertices (render/features.py sets both); a refracting closure is a lobe
# (upload/device_scene.py sets HAS_GLOSSY with HAS_TRANSMISSION), and so is a thin film (materials/closures:
# a closure with one has a lobe); shadow rays through thin walls take the transparent ones' loop
# (upload/device_scene.py sets HAS_TRANSPARENCY with HAS_THIN_SHADOW)
REQUIRES = {"HAS_GI_REUSE": "HAS_PATHS", "HAS_TRANSMISSION": "HAS_GLOSSY", "HAS_THIN_FILM": "HAS_GLOSSY",
            "HAS_THIN_SHADOW": "HAS_TRANSPARENCY"}


@pytest.mark.parametrize("flag", sorted(ALL_FLAGS))
def test_each_feature_alone_parses_without_optional_extensions(flag):
    """One feature on (with the one it needs), the others off, as scenes of one kind compile it, for a device
    that has none of OpenCL's optional extensions: no cl_khr_fp64 (Apple's GPUs and Intel's Arc have no doubles,
    so a double literal or type would be an error or a silent float there), no byte-addressable stores, no 3D
    image writes."""
    flags = {name: name in (flag, REQUIRES.get(flag)) for name in ALL_FLAGS}
    args = [*_clang_args(TARGETS[2]), "-Xclang", "-cl-ext=-all", "-nogpulib", f"-I{opencl_dir()}",
            *format_options(flags)]
    tu = cindex.Index.create().parse(str(opencl_dir() / MAIN_SOURCE), args=args)
    diags = _diagnostics(tu)
    assert not diags, "\n".join(diags)


def test_without_fp64_a_double_is_reported():
    """The check above would see a double: the same parse of a kernel with one reports it."""
    src = "__kernel void k(__global float* a) { a[0] = a[0] * 1.5; }"
    args = [*_clang_args(TARGETS[2]), "-Xclang", "-cl-ext=-all"]
    tu = cindex.Index.create().parse("double.cl", args=args, unsaved_files=[("double.cl", src)])
    assert any("cl_khr_fp64" in d for d in _diagnostics(tu))


@pytest.mark.parametrize("target", TARGETS)
def test_the_source_as_built_parses_with_no_include_path(target):
    """What build_program hands the driver, the headers written in (core/source_inline.py), parses with no -I."""
    from restircl.core.source_inline import inline_includes

    text = inline_includes((opencl_dir() / MAIN_SOURCE).read_text(), MAIN_SOURCE, opencl_dir())
    args = [*_clang_args(target), "-nogpulib", *format_options(dict.fromkeys(ALL_FLAGS, True))]
    tu = cindex.Index.create().parse("inlined.cl", args=args, unsaved_files=[("inlined.cl", text)])
    diags = _diagnostics(tu)
    assert not diags, "\n".join(diags)
    included = {Path(str(inc.include)).resolve() for inc in tu.get_includes()}
    assert not [p for p in included if p.is_relative_to(opencl_dir().resolve())], "a header was left to include"


def _call_graph(tu) -> dict[str, set[str]]:
    """Function name -> the functions its body calls, for the functions defined in opencl/."""
    root = str(opencl_dir())
    graph: dict[str, set[str]] = {}

    def calls(node, into: set[str]) -> None:
        for child in node.get_children():
            if child.kind == cindex.CursorKind.CALL_EXPR and child.referenced is not None:
                into.add(child.referenced.spelling)
            calls(child, into)

    for node in tu.cursor.get_children():
        if node.kind == cindex.CursorKind.FUNCTION_DECL and node.is_definition() and node.location.file \
                and str(node.location.file.name).startswith(root):
            calls(node, graph.setdefault(node.spelling, set()))
    return graph


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The call cycles of `graph` (each once, from its first function in sorted order)."""
    found, state = [], {}

    def visit(name: str, path: list[str]) -> None:
        state[name] = "open"
        for callee in sorted(graph.get(name, ())):
            if state.get(callee) == "open":
                found.append(path[path.index(callee):] + [callee])
            elif callee not in state and callee in graph:
                visit(callee, path + [callee])
        state[name] = "done"

    for name in sorted(graph):
        if name not in state:
            visit(name, [name])
    return found


def test_no_function_calls_itself_directly_or_through_others():
    """OpenCL C has no recursion (1.2 spec, 6.9): PoCL on the CPU may build a recursive call, a GPU compiler
    refuses it or inlines without end. The call graph of the whole program with every feature on has no cycle."""
    args = [*_clang_args(TARGETS[2]), "-nogpulib", f"-I{opencl_dir()}",
            *format_options(dict.fromkeys(ALL_FLAGS, True))]
    tu = cindex.Index.create().parse(str(opencl_dir() / MAIN_SOURCE), args=args)
    graph = _call_graph(tu)
    assert len(graph) > 200 and "shade" in " ".join(graph)  # the walk saw the program
    cycles = _cycles(graph)
    assert not cycles, "\n".join(" -> ".join(c) for c in cycles)


def test_the_call_graph_check_sees_recursion():
    src = ("float f(float x);\nfloat g(float x) { return f(x) + 1.0f; }\nfloat f(float x) { return x > 1.0f ? "
           "g(x - 1.0f) : x; }\n__kernel void k(__global float* a) { a[0] = f(a[0]); }\n")
    path = opencl_dir() / "recursion_probe.cl"  # a name under opencl/, given as an unsaved file: nothing written
    tu = cindex.Index.create().parse(str(path), args=_clang_args(TARGETS[2]), unsaved_files=[(str(path), src)])
    assert _cycles(_call_graph(tu)) == [["f", "g", "f"]]
