"""Hue/Saturation/Value on the device (opencl/textures/converters.h) against Python's colorsys, with the node's
rules written out from Blender's manual (hue turned by Hue - 0.5, saturation scaled then clamped, value scaled,
blended by Fac, clamped at 0); then the node packed with a linked input and evaluated through its texture program.
Color Ramp (opencl/textures/nodes.h) against a numpy evaluation of its stops and against values Blender 5.0's
ColorRamp.evaluate gave for one ramp."""

import colorsys

import numpy as np
import pyopencl as cl
import pytest
from restircl import ColorRamp, HueSaturationValue, Material, Math
from restircl.core.program import build_program
from restircl.materials.textures import RAMP_INTERPOLATIONS
from restircl.render.features import general_flags
from restircl.upload.textures import TexturePacker

SRC = """
#include "types.h"
#include "numerics.h"
#include "textures/point.h"
#include "textures/image.h"
#include "textures/nodes.h"

__kernel void hsv(const __global float4* inp, __global float4* out)
{
    int i = get_global_id(0);
    float4 c = inp[2 * i], h = inp[2 * i + 1];
    out[i] = (float4)(tex_hsv_adjust(c.xyz, h.xyz, h.w), 0.0f);
}

__kernel void ramp(const __global TexImage* images, const __global float4* texels, int img, int interp,
                   const __global float* t, __global float4* out)
{
    int i = get_global_id(0);
    out[i] = tex_color_ramp(images, texels, img, interp, t[i]);
}

__kernel void program(const __global TexNode* nodes, const __global TexImage* images, const __global float4* texels,
                      int root, __global float4* out)
{
    TexPoint tp;
    tp.uv = (float3)(0.0f);
    tp.lod_uv = -100.0f;
    out[0] = texture_eval(nodes, images, texels, root, &tp);
}
"""
N = 512


def _buf(device, a):
    mf = cl.mem_flags
    return cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=np.ascontiguousarray(a))


def _hsv_reference(c, hue, sat, val, fac):
    h, s, v = colorsys.rgb_to_hsv(*c)
    h = (h + hue + 0.5) % 1.0
    s = min(max(s * sat, 0.0), 1.0)
    rgb = np.array(colorsys.hsv_to_rgb(h, s, v * val))
    return np.maximum(fac * rgb + (1 - fac) * np.asarray(c), 0.0)


def test_hue_saturation_value_against_colorsys(device):
    rng = np.random.default_rng(7)
    inp = np.zeros((N, 2, 4), np.float32)
    inp[:, 0, :3] = rng.uniform(0.0, 1.5, (N, 3))
    inp[:, 1, 0] = rng.uniform(-1.0, 2.0, N)  # hue, turning past either end
    inp[:, 1, 1] = rng.uniform(0.0, 3.0, N)  # saturation, oversaturating
    inp[:, 1, 2] = rng.uniform(0.0, 2.0, N)
    inp[:, 1, 3] = rng.uniform(-0.5, 1.5, N)  # factor, unclamped as in Blender
    inp[:8, 0, :3] = 0.4  # greys: no hue
    prog = build_program(device, general_flags(), source=SRC)
    out = np.empty((N, 4), np.float32)
    ob = cl.Buffer(device.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, "hsv")(device.queue, (N,), None, _buf(device, inp), ob)
    cl.enqueue_copy(device.queue, out, ob)
    x = inp.astype(np.float64)
    want = [_hsv_reference(x[i, 0, :3], *x[i, 1]) for i in range(N)]
    np.testing.assert_allclose(out[:, :3], np.array(want), rtol=1e-5, atol=2e-5)


def _program(device, node, material: Material) -> np.ndarray:
    packer = TexturePacker([material])
    packed = packer.packed()
    prog = build_program(device, general_flags(), source=SRC)
    out = np.empty((1, 4), np.float32)
    ob = cl.Buffer(device.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, "program")(device.queue, (1,), None, _buf(device, packed.nodes), _buf(device, packed.images),
                               _buf(device, packed.texels), np.int32(packer.index(node)), ob)
    cl.enqueue_copy(device.queue, out, ob)
    return out[0, :3].astype(np.float64)


def test_hue_saturation_value_program_with_linked_inputs(device):
    """Constant hue/saturation/value and linked ones (a Math node each) both reach the device."""
    c = (0.7, 0.3, 0.1)
    const = HueSaturationValue(color=c, hue=0.3, saturation=0.5, value=1.2, factor=0.8)
    np.testing.assert_allclose(_program(device, const, Material("m", albedo=const)),
                               _hsv_reference(c, 0.3, 0.5, 1.2, 0.8), atol=2e-6)
    linked = HueSaturationValue(color=c, hue=Math("ADD", 0.1, 0.2), saturation=Math("MULTIPLY", 0.25, 2.0),
                                value=1.2, factor=Math("SUBTRACT", 1.0, 0.2))
    m = Material("m", albedo=linked, roughness=linked)  # the same node twice: one program
    np.testing.assert_allclose(_program(device, linked, m), _hsv_reference(c, 0.3, 0.5, 1.2, 0.8), atol=2e-6)


def _ramp_reference(t: float, pos: np.ndarray, cols: np.ndarray, interp: str) -> np.ndarray:
    """The ramp at t, written from Blender's manual: the first / last stop's colour outside them; else the stops
    i, i + 1 around t (the last i with pos[i] <= t), blended linearly, by smoothstep, or not at all (Constant)."""
    order = np.argsort(pos, kind="stable")
    pos, cols = pos[order], cols[order]
    if t <= pos[0]:
        return cols[0]
    if t >= pos[-1]:
        return cols[-1]
    i = int(np.nonzero(pos <= t)[0].max())
    if interp == "CONSTANT":
        return cols[i]
    u = (t - pos[i]) / (pos[i + 1] - pos[i])
    if interp == "EASE":
        u = 3 * u * u - 2 * u ** 3
    return (1 - u) * cols[i] + u * cols[i + 1]


def _ramp_on_device(device, ramp: ColorRamp, t: np.ndarray) -> np.ndarray:
    packer = TexturePacker([Material("m", albedo=ramp)])
    packed = packer.packed()
    k = packer.index(ramp)
    prog = build_program(device, general_flags(), source=SRC)
    out = np.empty((len(t), 4), np.float32)
    ob = cl.Buffer(device.context, cl.mem_flags.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, "ramp")(device.queue, (len(t),), None, _buf(device, packed.images), _buf(device, packed.texels),
                            np.int32(packed.nodes["in"][k, 3]), np.int32(packed.nodes["op"][k, 1]),
                            _buf(device, t.astype(np.float32)), ob)
    cl.enqueue_copy(device.queue, out, ob)
    return out.astype(np.float64)


@pytest.mark.parametrize("interp", RAMP_INTERPOLATIONS)
def test_color_ramp_against_numpy(device, interp):
    rng = np.random.default_rng(11)
    pos = np.array([0.8, 0.1, 0.45, 0.3, 0.45, 0.95], np.float32)  # unsorted, one position twice
    cols = rng.uniform(0.0, 2.0, (len(pos), 4)).astype(np.float32)
    t = np.concatenate([rng.uniform(-0.5, 1.5, 400), pos, [0.0, 1.0]]).astype(np.float32)
    ramp = ColorRamp(positions=tuple(pos), colors=tuple(map(tuple, cols)), interpolation=interp)
    want = [_ramp_reference(float(x), pos.astype(np.float64), cols.astype(np.float64), interp) for x in t]
    np.testing.assert_allclose(_ramp_on_device(device, ramp, t), np.array(want), rtol=1e-5, atol=1e-6)


# ColorRamp.evaluate of Blender 5.0.1 for stops 0.2 red, 0.5 green, 0.7 blue with alpha 0.5
BLENDER_RAMP = {
    "LINEAR": {0.0: (1, 0, 0, 1), 0.3: (0.66667, 0.33333, 0, 1), 0.45: (0.16667, 0.83333, 0, 1),
               0.55: (0, 0.75, 0.25, 0.875), 0.6: (0, 0.5, 0.5, 0.75), 0.9: (0, 0, 1, 0.5)},
    "CONSTANT": {0.0: (1, 0, 0, 1), 0.2: (1, 0, 0, 1), 0.45: (1, 0, 0, 1), 0.5: (0, 1, 0, 1), 0.6: (0, 1, 0, 1),
                 0.7: (0, 0, 1, 0.5), 0.9: (0, 0, 1, 0.5)},
    "EASE": {0.3: (0.74074, 0.25926, 0, 1), 0.45: (0.07407, 0.92593, 0, 1), 0.55: (0, 0.84375, 0.15625, 0.92188),
             0.6: (0, 0.5, 0.5, 0.75)},
}


@pytest.mark.parametrize("interp", RAMP_INTERPOLATIONS)
def test_color_ramp_as_blender_evaluates_it(device, interp):
    ramp = ColorRamp(positions=(0.2, 0.7, 0.5), colors=((1, 0, 0, 1), (0, 0, 1, 0.5), (0, 1, 0, 1)),
                     interpolation=interp)
    t = np.array(list(BLENDER_RAMP[interp]), np.float32)
    want = np.array(list(BLENDER_RAMP[interp].values()), np.float64)
    np.testing.assert_allclose(_ramp_on_device(device, ramp, t), want, atol=1e-5)


def test_color_ramp_alpha_output_and_linked_factor(device):
    """The Alpha output is a number (every component); a linked Fac reaches the lookup."""
    stops = {"positions": (0.0, 1.0), "colors": ((0.0, 0.2, 0.4, 1.0), (1.0, 0.6, 0.0, 0.0))}
    alpha = ColorRamp(factor=Math("ADD", 0.1, 0.15), alpha=True, **stops)
    np.testing.assert_allclose(_program(device, alpha, Material("m", roughness=alpha)), [0.75] * 3, atol=1e-6)
    color = ColorRamp(factor=Math("ADD", 0.1, 0.15), **stops)
    np.testing.assert_allclose(_program(device, color, Material("m", albedo=color)), [0.25, 0.3, 0.3], atol=1e-6)


def test_ramp_and_hsv_survive_the_scene_file_tables():
    from restircl.materials.file import MaterialReader, MaterialWriter

    ramp = ColorRamp(factor=Math("ADD", 0.1, 0.2), positions=(0.0, 0.4, 1.0),
                     colors=((1.0, 0.0, 0.0, 1.0), (0.0, 1.0, 0.0, 0.5), (0.0, 0.0, 1.0, 1.0)), interpolation="EASE",
                     alpha=True)
    hsv = HueSaturationValue(color=(0.5, 0.2, 0.1), hue=ramp, saturation=1.5, value=0.8, factor=0.9)
    arrays: dict = {}
    writer = MaterialWriter(arrays)
    d = writer.material(Material("m", albedo=hsv))
    back = MaterialReader(writer.nodes, arrays).material(d)
    h = back.albedo
    assert isinstance(h, HueSaturationValue) and (h.saturation, h.value, h.factor) == (1.5, 0.8, 0.9)
    r = h.hue
    assert isinstance(r, ColorRamp) and r.positions == (0.0, 0.4, 1.0) and r.colors == ramp.colors
    assert r.interpolation == "EASE" and r.alpha is True and r.factor.op == "ADD"


def test_ramp_checks():
    from restircl.materials.check import MaterialError, check_material

    with pytest.raises(MaterialError, match="as many positions"):
        check_material(Material("m", albedo=ColorRamp(positions=(0.0,), colors=())))
    with pytest.raises(MaterialError, match="interpolation"):
        check_material(Material("m", albedo=ColorRamp(interpolation="B_SPLINE")))
