"""The converter nodes on the device (opencl/textures/converters.h): Separate / Combine Color in RGB, HSV and HSL
against Python's colorsys, Math and Vector Math against numpy, and the Mix blend modes beyond the first nine, each
against a numpy reference written from Blender's manual; then through the renderer, that a Separate Color of an
image feeding Roughness is that channel of the texel exactly."""

import colorsys

import numpy as np
import pyopencl as cl
import pytest
from restircl import ImageTexture, Material, Math, MixColor, SeparateColor
from restircl.core.program import build_program
from restircl.materials.textures import COLOR_MODES, MATH_OPS, MIX_BLENDS, VECTOR_OPS
from restircl.render.features import general_flags
from restircl.upload.textures import TexturePacker

SRC = """
#include "types.h"
#include "numerics.h"
#include "textures/point.h"
#include "textures/image.h"
#include "textures/nodes.h"

__kernel void convert(int what, int code, int k, const __global float4* abc, __global float4* out)
{
    int i = get_global_id(0);
    float4 a = abc[3 * i], b = abc[3 * i + 1], c = abc[3 * i + 2];
    float3 r = (float3)(0.0f);
    if (what == 0) r = (float3)(tex_separate(code, k, a.xyz));
    if (what == 1) r = tex_combine(code, a.xyz);
    if (what == 2) r = (float3)(tex_math(code, a.x, b.x, c.x));
    if (what == 3) r = tex_vector_math(code, a.xyz, b.xyz, c.x);
    if (what == 4) r = tex_mix(code, c.x, a.xyz, b.xyz);
    out[i] = (float4)(r, 0.0f);
}
"""
N = 256


def _run(device, what: int, code: int, abc: np.ndarray, k: int = 0) -> np.ndarray:
    prog = build_program(device, general_flags(), source=SRC)
    mf = cl.mem_flags
    inp = cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=np.ascontiguousarray(abc, np.float32))
    out = np.empty((len(abc), 4), np.float32)
    ob = cl.Buffer(device.context, mf.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, "convert")(device.queue, (len(abc),), None, np.int32(what), np.int32(code), np.int32(k), inp, ob)
    cl.enqueue_copy(device.queue, out, ob)
    return out[:, :3].astype(np.float64)


def _inputs(lo: float = 0.0, hi: float = 1.0, seed: int = 3) -> np.ndarray:
    abc = np.zeros((N, 3, 4), np.float32)
    abc[..., :3] = np.random.default_rng(seed).uniform(lo, hi, (N, 3, 3))
    return abc


HSX = {"HSV": (colorsys.rgb_to_hsv, colorsys.hsv_to_rgb),
       "HSL": (lambda r, g, b: _hls(r, g, b), lambda h, s, l_: colorsys.hls_to_rgb(h, l_, s))}


def _hls(r, g, b):
    h, l_, s = colorsys.rgb_to_hls(r, g, b)
    return h, s, l_


@pytest.mark.parametrize("mode", COLOR_MODES)
def test_separate_and_combine_color(device, mode):
    abc = _inputs()
    for k in range(3):
        got = _run(device, 0, COLOR_MODES.index(mode), abc, k)[:, 0]
        want = [c[k] if mode == "RGB" else HSX[mode][0](*c)[k] for c in abc[:, 0, :3].astype(np.float64)]
        np.testing.assert_allclose(got, want, atol=2e-6)
    got = _run(device, 1, COLOR_MODES.index(mode), abc)
    want = [c if mode == "RGB" else HSX[mode][1](*c) for c in abc[:, 0, :3].astype(np.float64)]
    np.testing.assert_allclose(got, np.array(want), atol=2e-6)


def _safe_div(a, b):
    return np.where(b != 0, a / np.where(b != 0, b, 1), 0.0)


MATH = {
    "ADD": lambda a, b, c: a + b, "SUBTRACT": lambda a, b, c: a - b, "MULTIPLY": lambda a, b, c: a * b,
    "DIVIDE": lambda a, b, c: _safe_div(a, b), "MULTIPLY_ADD": lambda a, b, c: a * b + c,
    "POWER": lambda a, b, c: np.where((a < 0) & (b != np.floor(b)), 0.0, np.abs(a) ** b * np.where(
        (a < 0) & (np.floor(b) % 2 == 1), -1.0, 1.0)),
    "LOGARITHM": lambda a, b, c: np.where((a > 0) & (b > 0), _safe_div(np.log(np.abs(a) + (a <= 0)),
                                                                     np.log(np.abs(b) + (b <= 0))), 0.0),
    "SQRT": lambda a, b, c: np.sqrt(np.maximum(a, 0)), "INVERSE_SQRT": lambda a, b, c: np.where(
        a > 0, 1 / np.sqrt(np.maximum(a, 1e-30)), 0.0),
    "ABSOLUTE": lambda a, b, c: np.abs(a), "EXPONENT": lambda a, b, c: np.exp(a),
    "MINIMUM": lambda a, b, c: np.minimum(a, b), "MAXIMUM": lambda a, b, c: np.maximum(a, b),
    "LESS_THAN": lambda a, b, c: (a < b) * 1.0, "GREATER_THAN": lambda a, b, c: (a > b) * 1.0,
    "SIGN": lambda a, b, c: np.sign(a), "COMPARE": lambda a, b, c: (np.abs(a - b) <= np.maximum(c, 1e-5)) * 1.0,
    "ROUND": lambda a, b, c: np.floor(a + 0.5), "FLOOR": lambda a, b, c: np.floor(a),
    "CEIL": lambda a, b, c: np.ceil(a), "TRUNC": lambda a, b, c: np.trunc(a), "FRACT": lambda a, b, c: a - np.floor(a),
    "MODULO": lambda a, b, c: np.where(b != 0, np.fmod(a, np.where(b != 0, b, 1)), 0.0),
    "FLOORED_MODULO": lambda a, b, c: np.where(b != 0, a - np.floor(_safe_div(a, b)) * b, 0.0),
    "SNAP": lambda a, b, c: np.where(b != 0, np.floor(_safe_div(a, b)) * b, 0.0),
    "SINE": lambda a, b, c: np.sin(a), "COSINE": lambda a, b, c: np.cos(a), "TANGENT": lambda a, b, c: np.tan(a),
    "ARCTAN2": lambda a, b, c: np.arctan2(a, b), "RADIANS": lambda a, b, c: np.radians(a),
    "DEGREES": lambda a, b, c: np.degrees(a),
}


@pytest.mark.parametrize("op", MATH_OPS)
def test_math(device, op):
    abc = _inputs(-2.0, 2.0)
    abc[:8, 1, 0] = 0.0  # division by zero and friends
    abc[8:16, 1, 0] = np.round(abc[8:16, 1, 0])  # integer powers of negative numbers
    a, b, c = (abc[:, j, 0].astype(np.float64) for j in range(3))
    with np.errstate(all="ignore"):
        want = MATH[op](a, b, c)
    got = _run(device, 2, MATH_OPS.index(op), abc)[:, 0]
    np.testing.assert_allclose(got, want, rtol=2e-5, atol=2e-5)


def _vec(op, a, b, s):
    table = {"ADD": a + b, "SUBTRACT": a - b, "MULTIPLY": a * b, "DIVIDE": _safe_div(a, b), "SCALE": a * s[:, None],
             "ABSOLUTE": np.abs(a), "MINIMUM": np.minimum(a, b), "MAXIMUM": np.maximum(a, b), "FLOOR": np.floor(a),
             "CEIL": np.ceil(a), "FRACTION": a - np.floor(a), "CROSS_PRODUCT": np.cross(a, b),
             "NORMALIZE": a / np.linalg.norm(a, axis=1, keepdims=True)}
    one = {"DOT_PRODUCT": (a * b).sum(1), "LENGTH": np.linalg.norm(a, axis=1),
           "DISTANCE": np.linalg.norm(a - b, axis=1)}
    return table[op] if op in table else np.repeat(one[op][:, None], 3, axis=1)


@pytest.mark.parametrize("op", VECTOR_OPS)
def test_vector_math(device, op):
    abc = _inputs(-2.0, 2.0, seed=5)
    abc[:4, 1, 1] = 0.0
    a, b = abc[:, 0, :3].astype(np.float64), abc[:, 1, :3].astype(np.float64)
    with np.errstate(all="ignore"):
        want = _vec(op, a, b, abc[:, 2, 0].astype(np.float64))
    np.testing.assert_allclose(_run(device, 3, VECTOR_OPS.index(op), abc), want, rtol=2e-5, atol=2e-5)


def _hsv(c):
    return np.array([colorsys.rgb_to_hsv(*x) for x in c])


def _rgb(h):
    return np.array([colorsys.hsv_to_rgb(*x) for x in h])


def more_blend(blend: str, t: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The blend modes after the first nine, from Blender's manual (HSV through colorsys)."""
    t1, tm = t[:, None], 1 - t[:, None]
    if blend == "BURN":
        d = tm + t1 * b
        return np.where(d <= 0, 0.0, np.clip(1 - (1 - a) / np.where(d <= 0, 1, d), 0, 1))
    if blend == "DODGE":
        d = 1 - t1 * b
        return np.where(a == 0, 0.0, np.where(d <= 0, 1.0, np.minimum(a / np.where(d <= 0, 1, d), 1)))
    if blend == "DIVIDE":
        return np.where(b != 0, tm * a + t1 * _safe_div(a, b), a)
    if blend == "SOFT_LIGHT":
        return tm * a + t1 * ((1 - a) * b * a + a * (1 - (1 - b) * (1 - a)))
    if blend == "LINEAR_LIGHT":
        return a + t1 * (2 * b - 1)
    if blend == "EXCLUSION":
        return np.maximum(a + t1 * (b - 2 * a * b), 0)
    ha, hb = _hsv(a), _hsv(b)
    out = a.copy()
    if blend == "VALUE":
        return _rgb(np.stack([ha[:, 0], ha[:, 1], tm[:, 0] * ha[:, 2] + t * hb[:, 2]], 1))
    if blend == "SATURATION":
        new = _rgb(np.stack([ha[:, 0], tm[:, 0] * ha[:, 1] + t * hb[:, 1], ha[:, 2]], 1))
        return np.where(ha[:, 1:2] != 0, new, a)
    hue = np.stack([hb[:, 0], ha[:, 1] if blend == "HUE" else hb[:, 1], ha[:, 2]], 1)
    out = a + t1 * (_rgb(hue) - a)
    return np.where(hb[:, 1:2] != 0, out, a)


@pytest.mark.parametrize("blend", MIX_BLENDS[9:])
def test_more_mix_blends(device, blend):
    abc = _inputs(0.0, 1.2, seed=7)
    abc[:, 2, 0] = np.random.default_rng(8).uniform(0, 1, N)
    abc[:6, 1, :3] = 0.0  # divisions by zero, grey b
    a, b, t = abc[:, 0, :3].astype(np.float64), abc[:, 1, :3].astype(np.float64), abc[:, 2, 0].astype(np.float64)
    with np.errstate(all="ignore"):
        want = more_blend(blend, t, a, b)
    np.testing.assert_allclose(_run(device, 4, MIX_BLENDS.index(blend), abc), want, rtol=2e-5, atol=2e-5)


def test_converter_records_say_which_give_numbers():
    img = ImageTexture(np.zeros((2, 2, 3), np.float32), colorspace="Non-Color")
    sep = SeparateColor(img, channel=2)
    mix = MixColor(img, sep, factor=Math("MULTIPLY", sep, 0.5), blend="BURN", clamp_result=True)
    packer = TexturePacker([Material("m", albedo=mix, roughness=sep)])
    nodes = packer.packed().nodes
    k = packer.index(mix)
    assert nodes["blk"][k, 3] == 0 and nodes["blk"][k, 2] == 1 and nodes["op"][k, 1] == MIX_BLENDS.index("BURN")
    assert nodes["blk"][packer.index(sep), 3] == 1 and nodes["op"][packer.index(sep), 2] == 2


NUMBER_SRC = SRC + """
#include "textures/closure_inputs.h"

__kernel void number(const __global TexNode* nodes, const __global TexImage* images, const __global float4* texels,
                     int root, const __global float2* uv, __global float* out)
{
    int i = get_global_id(0);
    TexPoint tp;
    tp.uv = (float3)(uv[i], 0.0f);
    tp.lod_uv = -100.0f;  /* level 0 */
    out[i] = tex_input_number(nodes, images, texels, root, &tp);
}
"""


def _numbers(device, node, uv: np.ndarray) -> np.ndarray:
    packer = TexturePacker([Material("m", kind="principled", roughness=node)])
    packed = packer.packed()
    prog = build_program(device, general_flags(), source=NUMBER_SRC)
    mf = cl.mem_flags

    def buf(a):
        return cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=np.ascontiguousarray(a))

    out = np.empty(len(uv), np.float32)
    ob = cl.Buffer(device.context, mf.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, "number")(device.queue, (len(uv),), None, buf(packed.nodes), buf(packed.images),
                              buf(packed.texels), np.int32(packer.index(node)), buf(uv.astype(np.float32)), ob)
    cl.enqueue_copy(device.queue, out, ob)
    return out


def test_a_channel_feeding_roughness_is_that_texel_channel_exactly(device):
    """A value input (Roughness) linked to a Separate Color of an image reads that channel of the texel bit for bit
    (not the grey of a colour), and a Math on it the float32 value; an image's colour is still read as its grey."""
    size = 8
    px = np.random.default_rng(1).uniform(0.05, 0.95, (size, size, 3)).astype(np.float32)
    img = ImageTexture(px, colorspace="Non-Color", interpolation="Closest")
    y, x = np.mgrid[0:size, 0:size]
    uv = np.stack([(x.reshape(-1) + 0.5) / size, (y.reshape(-1) + 0.5) / size], 1)
    flat = px[::-1].reshape(-1, 3)  # the array's rows are top first: its last row is v = 0.5 / size
    np.testing.assert_array_equal(_numbers(device, SeparateColor(img, channel=2), uv), flat[:, 2])
    got = _numbers(device, Math("MULTIPLY_ADD", SeparateColor(img, channel=1), 0.5, 0.25), uv)
    np.testing.assert_array_equal(got, flat[:, 1] * np.float32(0.5) + np.float32(0.25))
    grey = flat.astype(np.float64) @ np.array([0.2126, 0.7152, 0.0722])
    np.testing.assert_allclose(_numbers(device, img, uv), grey, rtol=1e-6)


def test_converters_survive_the_scene_file_tables():
    from restircl.materials.file import MaterialReader, MaterialWriter

    img = ImageTexture(np.zeros((2, 2, 3), np.float32), colorspace="Non-Color")
    sep = SeparateColor(img, channel=1, mode="HSV")
    m = Material("m", kind="principled", roughness=Math("POWER", sep, 2.0, 0.0, clamp=True),
                 albedo=MixColor(img, sep, factor=0.3, blend="SOFT_LIGHT", clamp_result=True))
    arrays: dict = {}
    writer = MaterialWriter(arrays)
    d = writer.material(m)
    back = MaterialReader(writer.nodes, arrays).material(d)
    s = back.roughness.a
    assert isinstance(s, SeparateColor) and s.channel == 1 and isinstance(s.channel, int) and s.mode == "HSV"
    assert back.roughness.op == "POWER" and back.roughness.clamp is True and back.roughness.b == 2.0
    assert back.albedo.blend == "SOFT_LIGHT" and back.albedo.clamp_result is True and back.albedo.b is s
    del writer.nodes[d["albedo"]["node"]]["clamp_result"]  # a file written before the field: its default
    assert MaterialReader(writer.nodes, arrays).material(d).albedo.clamp_result is False
