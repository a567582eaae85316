"""RGB Curves on the device (opencl/textures/nodes.h tex_rgb_curves) against a numpy reading of its table written
out here: rows evenly over [lo, hi], linear between rows, the end rows' slope continued past either end (or the end
row held), blended with the input by Fac; then through a texture program with linked inputs, and through the scene
file. The table's contents (Blender's curve evaluation) are the exporter's: tests/blender/test_blender_rgb_curves.py
checks them against Cycles."""

import numpy as np
import pyopencl as cl
import pytest
from restircl import Material, Math, RGBCurves
from restircl.core.program import build_program
from restircl.render.features import general_flags
from restircl.upload.textures import TexturePacker

from .test_ramp_hsv import _program

SRC = """
#include "types.h"
#include "numerics.h"
#include "textures/point.h"
#include "textures/image.h"
#include "textures/nodes.h"

__kernel void curves(const __global TexNode* nodes, const __global TexImage* images, const __global float4* texels,
                     int k, const __global float4* inp, __global float4* out)
{
    int i = get_global_id(0);
    TexNode n = nodes[k];
    out[i] = (float4)(tex_rgb_curves(images, texels, &n, inp[i].xyz, inp[i].w), 0.0f);
}
"""


def _buf(device, a):
    mf = cl.mem_flags
    return cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=np.ascontiguousarray(a))


def _reference(x: float, column: np.ndarray, lo: float, hi: float, extrapolate: bool) -> float:
    n = len(column)
    xs = lo + (hi - lo) * np.arange(n) / (n - 1)
    if x < lo and extrapolate:
        return float(column[0] + (x - xs[0]) * (column[1] - column[0]) / (xs[1] - xs[0]))
    if x > hi and extrapolate:
        return float(column[-1] + (x - xs[-1]) * (column[-1] - column[-2]) / (xs[-1] - xs[-2]))
    return float(np.interp(x, xs, column))


@pytest.mark.parametrize("extrapolate", [True, False])
def test_rgb_curves_against_numpy(device, extrapolate):
    rng = np.random.default_rng(5)
    rows, lo, hi = 17, -0.25, 1.5
    table = np.cumsum(rng.uniform(-0.1, 0.3, (rows, 3)), axis=0).astype(np.float32)  # three different columns
    node = RGBCurves(table=tuple(map(tuple, table)), lo=lo, hi=hi, extrapolate=extrapolate)
    packer = TexturePacker([Material("m", albedo=node)])
    packed = packer.packed()
    inp = np.zeros((300, 4), np.float32)
    inp[:, :3] = rng.uniform(-1.0, 2.5, (300, 3))  # inside and past both ends
    inp[:, 3] = rng.uniform(0.0, 1.0, 300)
    inp[:4, 3] = 1.0
    prog = build_program(device, general_flags(), source=SRC)
    out = np.empty((300, 4), np.float32)
    ob = cl.Buffer(device.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, "curves")(device.queue, (300,), None, _buf(device, packed.nodes), _buf(device, packed.images),
                              _buf(device, packed.texels), np.int32(packer.index(node)), _buf(device, inp), ob)
    cl.enqueue_copy(device.queue, out, ob)
    x = inp.astype(np.float64)
    t64 = table.astype(np.float64)
    want = np.array([[(1 - x[i, 3]) * x[i, c] + x[i, 3] * _reference(x[i, c], t64[:, c], lo, hi, extrapolate)
                      for c in range(3)] for i in range(300)])
    np.testing.assert_allclose(out[:, :3], want, rtol=1e-5, atol=1e-5)


def test_rgb_curves_in_a_program_with_linked_inputs(device):
    table = ((0.0, 1.0, 0.5), (1.0, 0.0, 0.5), (0.0, 1.0, 2.5))  # rows at 0, 0.5, 1
    node = RGBCurves(color=Math("ADD", 0.1, 0.15), factor=Math("MULTIPLY", 0.5, 1.5), table=table)
    # x = 0.25 in every channel: halfway between rows 0 and 1 -> (0.5, 0.5, 0.5); blended by 0.75 with 0.25
    np.testing.assert_allclose(_program(device, node, Material("m", albedo=node)), [0.4375] * 3, atol=1e-6)


def test_rgb_curves_survive_the_scene_file_and_are_checked():
    from restircl.materials.check import MaterialError, check_material
    from restircl.materials.file import MaterialReader, MaterialWriter

    node = RGBCurves(color=(0.2, 0.4, 0.6), factor=0.7, table=((0.0, 0.1, 0.2), (0.9, 1.0, 1.1)), lo=-0.5, hi=2.0,
                     extrapolate=False)
    arrays: dict = {}
    writer = MaterialWriter(arrays)
    d = writer.material(Material("m", albedo=node))
    back = MaterialReader(writer.nodes, arrays).material(d).albedo
    assert isinstance(back, RGBCurves) and (back.lo, back.hi, back.extrapolate, back.factor) == (-0.5, 2.0, False, 0.7)
    np.testing.assert_array_equal(np.asarray(back.table, np.float64), np.asarray(node.table, np.float64))
    for bad, match in (({"table": ((0.0, 0.0, 0.0),)}, "at least 2"), ({"lo": 1.0, "hi": 1.0}, "lo < hi")):
        with pytest.raises(MaterialError, match=match):
            check_material(Material("m", albedo=RGBCurves(**bad)))
