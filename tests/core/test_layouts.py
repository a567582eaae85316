"""Every struct in opencl/types.h has the size and field offsets of its numpy mirror in core/layouts.py."""

import numpy as np
import pyopencl as cl
import pytest
from restircl.core import layouts
from restircl.core.program import build_program


def _fields(dtype: np.dtype, prefix: str = "", base: int = 0) -> list[tuple[str, int]]:
    """(C member path, offset) of every field, nested structs' fields included ("sampler.light_count")."""
    out = []
    for name in dtype.names:
        sub, offset = dtype.fields[name][:2]
        out.append((prefix + name, base + offset))
        if sub.names is not None:
            out += _fields(sub, f"{prefix}{name}.", base + offset)
    return out


def _layout_kernel() -> tuple[str, list[tuple[str, str, int]]]:
    lines = ['#include "types.h"', "__kernel void layout(__global int* out, __global char* base) {"]
    expected = []
    k = 0
    for struct, dtype in layouts.STRUCTS.items():
        lines.append(f"  {{ __global {struct}* s = (__global {struct}*)base;")
        lines.append(f"    out[{k}] = (int)sizeof({struct});")
        expected.append((struct, "sizeof", dtype.itemsize))
        k += 1
        for path, offset in _fields(dtype):
            lines.append(f"    out[{k}] = (int)((__global char*)&s->{path} - base);")
            expected.append((struct, path, offset))
            k += 1
        lines.append("  }")
    lines.append("}")
    return "\n".join(lines), expected


def test_struct_layouts_match_numpy(device):
    src, expected = _layout_kernel()
    prog = build_program(device, {}, source=src)
    out = np.zeros(len(expected), np.int32)
    out_buf = cl.Buffer(device.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
    base = cl.Buffer(device.context, cl.mem_flags.READ_WRITE, 1024)
    prog.layout(device.queue, (1,), None, out_buf, base)
    cl.enqueue_copy(device.queue, out, out_buf)
    got = {(s, f): int(v) for (s, f, _), v in zip(expected, out, strict=True)}
    want = {(s, f): v for s, f, v in expected}
    assert got == want


def test_no_float3_in_shared_structs():
    from restircl.core.program import opencl_dir

    text = (opencl_dir() / "types.h").read_text()
    assert "float3" not in text.replace("no float3", "")


def test_struct_sizes_are_multiples_of_16():
    for name, dtype in layouts.STRUCTS.items():
        assert dtype.itemsize % 16 == 0, name


def test_nested_parameter_structs_are_checked():
    """The per-stage structs nest SamplerParams: the layout kernel reaches the nested fields too."""
    _, expected = _layout_kernel()
    assert ("InitialParams", "sampler.tile_size", 12) in expected
    assert ("ShadeParams", "sampler.light_count", 0) in expected


def test_pack_names_fields():
    p = layouts.pack(layouts.INITIAL_PARAMS, candidates=8, sampler={"light_count": 3})
    assert p["candidates"] == 8 and p["sampler"]["light_count"] == 3 and p["visibility_reuse"] == 0
    with pytest.raises(KeyError, match="candidate"):
        layouts.pack(layouts.INITIAL_PARAMS, candidate=8)
