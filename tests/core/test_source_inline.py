"""The program's headers are written into its source, so that the build needs no include path: it builds from a
folder whose path has spaces (as Blender's extensions folder on Windows and macOS), and the compiler's messages
still name the header and line."""

from __future__ import annotations

import shutil
import warnings
from pathlib import Path

import numpy as np
import pyopencl as cl
import pytest
from restircl.core import program as program_mod
from restircl.core.program import build_program, opencl_dir
from restircl.core.source_inline import inline_includes


def _tree(root: Path, files: dict[str, str]) -> Path:
    for rel, text in files.items():
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        (root / rel).write_text(text)
    return root


def test_includes_are_found_beside_the_file_then_under_the_root(tmp_path):
    root = _tree(tmp_path, {
        "a.h": "#ifndef A_H\n#define A_H\nint a;\n#endif",
        "sub/b.h": '#include "c.h"\n#include "a.h"  /* from the root,\n   over two lines */\nint b;',
        "sub/c.h": "int c_sub;",
        "c.h": "int c_root;",
    })
    text = inline_includes('#include "sub/b.h"\n#include "missing.h"\nint main_line;', "main.cl", root)
    assert text.split("\n") == [
        '#line 1 "sub/b.h"',
        '#line 1 "sub/c.h"', "int c_sub;", '#line 2 "sub/b.h"',
        '#line 1 "a.h"', "#ifndef A_H", "#define A_H", "int a;", "#endif", '#line 2 "sub/b.h"',
        "/* from the root,", "   over two lines */",
        "int b;",
        '#line 2 "main.cl"',
        '#include "missing.h"',  # left for the compiler to report
        "int main_line;",
    ]


def test_an_include_cycle_without_a_guard_is_an_error(tmp_path):
    root = _tree(tmp_path, {"x.h": '#include "y.h"', "y.h": '#include "x.h"'})
    with pytest.raises(RecursionError, match="cycle"):
        inline_includes('#include "x.h"', "main.cl", root)


def test_the_program_builds_from_a_folder_with_spaces(device, tmp_path, monkeypatch):
    """The kernels' own headers, copied under "Blender Foundation/Application Support", build and run."""
    spaced = tmp_path / "Blender Foundation" / "Application Support" / "opencl"
    shutil.copytree(opencl_dir(), spaced)
    monkeypatch.setattr(program_mod, "opencl_dir", lambda: spaced)
    src = ('#include "types.h"\n#include "sampling/warps.h"\n'
           "__kernel void k(__global float* out) { out[get_global_id(0)] = 2.5f * (float)get_global_id(0); }\n")
    prog = build_program(device, {"RESTIRCL_TEST_SPACED": 1}, source=src)
    assert not any(o.startswith("-I") for o in program_mod.BASE_OPTIONS)
    out = np.zeros(4, np.float32)
    buf = cl.Buffer(device.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
    prog.k(device.queue, (4,), None, buf)
    cl.enqueue_copy(device.queue, out, buf)
    assert out.tolist() == [0.0, 2.5, 5.0, 7.5]


def test_a_compiler_message_names_the_header_and_its_line(device, tmp_path):
    root = _tree(tmp_path, {"lights/broken.h": "// a comment\n\nfloat broken(void) { return undefined_name; }\n"})
    text = inline_includes('#include "lights/broken.h"\n__kernel void k() {}\n', "program.cl", root)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(cl.RuntimeError) as err:
            cl.Program(device.context, text).build(options=["-cl-std=CL1.2"])
    assert "lights/broken.h:3:" in str(err.value) and "undefined_name" in str(err.value)
