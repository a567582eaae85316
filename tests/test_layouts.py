"""Every struct in opencl/types.h has the size and field offsets of its numpy mirror in layouts.py."""

import numpy as np
import pyopencl as cl
from restircl import layouts
from restircl.program import build_program


def _layout_kernel() -> tuple[str, list[tuple[str, str, int]]]:
    lines = ['#include "types.h"', "__kernel void layout(__global int* out, __global char* base) {"]
    expected = []
    k = 0
    for struct, dtype in layouts.STRUCTS.items():
        lines.append(f"  {{ __global {struct}* s = (__global {struct}*)base;")
        lines.append(f"    out[{k}] = (int)sizeof({struct});")
        expected.append((struct, "sizeof", dtype.itemsize))
        k += 1
        for name in dtype.names:
            lines.append(f"    out[{k}] = (int)((__global char*)&s->{name} - base);")
            expected.append((struct, name, dtype.fields[name][1]))
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
    from restircl.program import opencl_dir

    text = (opencl_dir() / "types.h").read_text()
    assert "float3" not in text.replace("no float3", "")


def test_struct_sizes_are_multiples_of_16():
    for name, dtype in layouts.STRUCTS.items():
        assert dtype.itemsize % 16 == 0, name
