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
