"""Texture nodes on the device (opencl/textures/image.h, textures/nodes.h, textures/point.h): image lookups against a
numpy reference (Linear, Closest; Repeat, Extend, Clip), the mip level of a footprint, Blender's checker and Mix
blend definitions, and, through renders of a UV-mapped square, sRGB decoding, mip selection, texture coordinates,
normal maps and smooth shading."""

import math

import numpy as np
import pyopencl as cl
import pytest
from restircl import CheckerTexture, ImageTexture, Material, MixColor, NormalMap, Renderer, Settings
from restircl.core.program import build_program
from restircl.io.image_load import mip_chain, srgb_to_linear, to_linear_rgba
from restircl.materials.textures import EXTENSIONS, INTERPOLATIONS, MIX_BLENDS
from restircl.render.features import general_flags

from ..texture_scenes import facing_square, pixel_uv

SRC = """
#include "types.h"
#include "numerics.h"
#include "textures/point.h"
#include "textures/image.h"
#include "textures/nodes.h"

__kernel void lookup(const __global TexImage* images, const __global float4* texels, const __global float4* st,
                     int interp, int ext, __global float4* out)
{
    int i = get_global_id(0);
    out[i] = texture_image(images, texels, 0, st[i].xy, st[i].z, interp, ext);
}

__kernel void mip_level(const __global TexImage* images, const __global float* lod, __global float* out)
{
    int i = get_global_id(0);
    out[i] = tex_mip_level(images[0], lod[i]);
}

__kernel void checker(const __global float4* p, __global float* out)
{
    int i = get_global_id(0);
    out[i] = tex_checker(p[i].xyz);
}

__kernel void mix_blend(int blend, const __global float4* abt, __global float4* out)
{
    int i = get_global_id(0);
    float4 a = abt[3 * i], b = abt[3 * i + 1];
    out[i] = (float4)(tex_mix(blend, abt[3 * i + 2].x, a.xyz, b.xyz), 0.0f);
}
"""


def _run(device, name: str, n: int, out_shape: tuple, *args) -> np.ndarray:
    prog = build_program(device, general_flags(), source=SRC)
    mf = cl.mem_flags
    bufs = [cl.Buffer(device.context, mf.READ_ONLY | mf.COPY_HOST_PTR, hostbuf=np.ascontiguousarray(a))
            if isinstance(a, np.ndarray) else a for a in args]
    out = np.empty(out_shape, np.float32)
    ob = cl.Buffer(device.context, mf.WRITE_ONLY, out.nbytes)
    cl.Kernel(prog, name)(device.queue, (n,), None, *bufs, ob)
    cl.enqueue_copy(device.queue, out, ob)
    return out


def _image_buffers(texels: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    levels = mip_chain(texels)
    table = np.array([[0, texels.shape[1], texels.shape[0], len(levels)]], np.int32)
    return table, np.concatenate([lv.reshape(-1, 4) for lv in levels]).astype(np.float32)


def _wrap(i: np.ndarray, n: int, ext: str) -> tuple[np.ndarray, np.ndarray]:
    if ext == "REPEAT":
        return np.mod(i, n), np.zeros(i.shape, bool)
    return np.clip(i, 0, n - 1), (i < 0) | (i >= n) if ext == "CLIP" else np.zeros(i.shape, bool)


def reference_lookup(img: np.ndarray, st: np.ndarray, interp: str, ext: str) -> np.ndarray:
    """Blender's image sampling at level 0: img (H, W, 4) bottom row first, st (N, 2) in image units."""
    h, w = img.shape[:2]

    def texel(x, y):
        (xi, ox), (yi, oy) = _wrap(x, w, ext), _wrap(y, h, ext)
        return np.where((ox | oy)[:, None], 0.0, img[yi, xi])

    if interp == "Closest":
        return texel(np.floor(st[:, 0] * w).astype(int), np.floor(st[:, 1] * h).astype(int))
    fx, fy = st[:, 0] * w - 0.5, st[:, 1] * h - 0.5
    x0, y0 = np.floor(fx).astype(int), np.floor(fy).astype(int)
    ax, ay = (fx - x0)[:, None], (fy - y0)[:, None]
    return ((1 - ay) * ((1 - ax) * texel(x0, y0) + ax * texel(x0 + 1, y0))
            + ay * ((1 - ax) * texel(x0, y0 + 1) + ax * texel(x0 + 1, y0 + 1)))


@pytest.mark.parametrize("interp", INTERPOLATIONS)
@pytest.mark.parametrize("ext", EXTENSIONS)
def test_image_lookup_matches_numpy_reference(device, interp, ext):
    rng = np.random.default_rng(7)
    img = rng.random((5, 7, 4)).astype(np.float32)
    n = 4096
    st = np.zeros((n, 4), np.float32)
    st[:, :2] = rng.uniform(-1.5, 2.5, (n, 2))
    st[:, 2] = -50.0  # a footprint far below a texel: level 0
    table, texels = _image_buffers(img)
    got = _run(device, "lookup", n, (n, 4), table, texels, st, np.int32(INTERPOLATIONS.index(interp)),
               np.int32(EXTENSIONS.index(ext)))
    want = reference_lookup(img.astype(np.float64), st[:, :2].astype(np.float64), interp, ext)
    # float32 coordinates on the device: a texel boundary can fall either way for Closest within 1e-5
    bad = np.abs(got - want).max(axis=1) > 1e-4
    assert bad.sum() <= (n // 500 if interp == "Closest" else 0), f"{bad.sum()} of {n} lookups differ"


def test_mip_level_of_a_footprint(device):
    table, _ = _image_buffers(np.zeros((64, 64, 4), np.float32))  # 7 levels
    lods = np.array([-6.0, -7.0, -5.5, -4.0, 0.0, 3.0, np.nan, -np.inf], np.float32)
    got = _run(device, "mip_level", len(lods), (len(lods),), table, lods)
    # a footprint of one texel (1/64 of the image: log2 = -6) is level 0; twice as wide level 1; clamped to 0..6
    np.testing.assert_allclose(got, [0.0, 0.0, 0.5, 2.0, 6.0, 6.0, 0.0, 0.0], atol=1e-6)


def blender_checker(p: np.ndarray) -> np.ndarray:
    """Blender's checker as its documentation and source define it: the coordinate nudged by (p + 1e-6) * 0.999999,
    then color1 where (|floor x| mod 2 == |floor y| mod 2) == |floor z| mod 2 (float32 arithmetic as on the GPU)."""
    q = (p.astype(np.float32) + np.float32(0.000001)) * np.float32(0.999999)
    xi, yi, zi = (np.abs(np.floor(q[:, k]).astype(np.int64)) for k in range(3))
    return (((xi % 2) == (yi % 2)) == (zi % 2).astype(bool)).astype(np.float32)


def test_checker_matches_blender_definition(device):
    rng = np.random.default_rng(3)
    known = np.array([[0.5, 0.5, 0.5], [1.5, 0.5, 0.5], [0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [-0.5, 0.5, 0.5],
                      [2.5, 2.5, 2.5], [-1.0, -1.0, 0.0], [0.999999, 0.0, 0.0]])
    p = np.concatenate([known, rng.uniform(-20, 20, (4000, 3)), np.round(rng.uniform(-5, 5, (500, 3)))])
    p4 = np.zeros((len(p), 4), np.float32)
    p4[:, :3] = p
    got = _run(device, "checker", len(p), (len(p),), p4)
    np.testing.assert_array_equal(got, blender_checker(p))
    # at the centre of the generated cube times Blender's default scale 5: (2.5, 2.5, 2.5) is color2; one cell over
    # in x is color1
    assert got[5] == 0.0 and blender_checker(np.array([[3.5, 2.5, 2.5]]))[0] == 1.0


def blender_mix(blend: str, t: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Blender's Mix (Color) blend modes (the Mix node's documented formulas)."""
    t = t[:, None]
    lerp = {"MIX": b, "MULTIPLY": a * b, "ADD": a + b, "SUBTRACT": a - b, "DIFFERENCE": np.abs(a - b),
            "DARKEN": np.minimum(a, b), "LIGHTEN": np.maximum(a, b)}
    if blend in lerp:
        return a + t * (lerp[blend] - a)
    if blend == "SCREEN":
        return 1 - ((1 - t) + t * (1 - b)) * (1 - a)
    low = a * ((1 - t) + 2 * t * b)
    high = 1 - ((1 - t) + 2 * t * (1 - b)) * (1 - a)
    return np.where(a < 0.5, low, high)  # OVERLAY


@pytest.mark.parametrize("blend", MIX_BLENDS[:9])  # the others: test_converters.py
def test_mix_blends_match_blender(device, blend):
    rng = np.random.default_rng(11)
    n = 512
    abt = np.zeros((n, 3, 4), np.float32)
    abt[:, 0, :3] = rng.uniform(0, 1.5, (n, 3))
    abt[:, 1, :3] = rng.uniform(0, 1.5, (n, 3))
    abt[:, 2, 0] = rng.uniform(0, 1, n)
    got = _run(device, "mix_blend", n, (n, 4), np.int32(MIX_BLENDS.index(blend)), abt)
    want = blender_mix(blend, abt[:, 2, 0].astype(np.float64), abt[:, 0, :3].astype(np.float64),
                       abt[:, 1, :3].astype(np.float64))
    np.testing.assert_allclose(got[:, :3], want, rtol=1e-5, atol=1e-6)


# ---- through the renderer: the UV-mapped square of texture_scenes.py --------------------------------------

def render(scene, **settings) -> object:
    settings = {"method": "light_array", "jitter": False, **settings}
    return Renderer(scene, Settings(**settings)).render_frame(0)


def test_srgb_images_are_decoded_and_non_color_is_not(device):
    assert srgb_to_linear(np.array([0.0, 1.0]))[1] == pytest.approx(1.0)
    assert srgb_to_linear(np.array([188 / 255]))[0] == pytest.approx(0.5029, abs=1e-4)
    assert srgb_to_linear(np.array([0.02]))[0] == pytest.approx(0.02 / 12.92)
    img = np.random.default_rng(5).integers(0, 256, (4, 4, 3), dtype=np.uint8)
    u, v = pixel_uv(16)
    ix, iy = (u * 4).astype(int), (v * 4).astype(int)
    for space, decode in (("sRGB", srgb_to_linear), ("Non-Color", lambda x: x)):
        tex = ImageTexture(img, colorspace=space, interpolation="Closest")
        f = render(facing_square(Material("m", albedo=tex), 16))
        want = decode(img[::-1].astype(np.float64) / 255.0)[iy, ix]
        np.testing.assert_allclose(f.albedo, want, atol=2e-6, rtol=1e-5)
    np.testing.assert_allclose(to_linear_rgba(img, "sRGB")[::-1, :, :3], srgb_to_linear(img / 255.0), atol=1e-6)


def test_head_on_texel_per_pixel_picks_level_0_and_two_texels_level_1(device):
    img = np.random.default_rng(2).random((64, 64, 3)).astype(np.float32)
    levels = mip_chain(to_linear_rgba(img, "Non-Color"))  # bottom row first
    for size, level in ((64, 0), (32, 1)):
        f = render(facing_square(Material("m", albedo=ImageTexture(img, colorspace="Non-Color")), size))
        np.testing.assert_allclose(f.albedo, levels[level][::-1, :, :3], atol=2e-3, err_msg=f"{size} px")


def _world_xy(size: int) -> tuple[np.ndarray, np.ndarray]:
    u, v = pixel_uv(size)
    return 2.0 * u - 1.0, 2.0 * v - 1.0  # the square of half size 1


@pytest.mark.parametrize("coords", ["object", "generated"])
def test_checker_on_object_and_generated_coordinates(device, coords):
    size = 48
    mapping = np.diag([2.0, 3.0, 1.0, 1.0])
    mapping[:3, 3] = (0.25, -0.5, 0.0)
    tex = CheckerTexture((0.9, 0.1, 0.1), (0.1, 0.1, 0.9), scale=1.5, coords=coords, mapping=mapping)
    f = render(facing_square(Material("m", albedo=tex), size))
    x, y = _world_xy(size)
    # Blender's Generated of this square: x, y over the box mapped to [0, 1]; a flat z is 0.5
    p = np.stack([x, y, np.zeros_like(x)], -1) if coords == "object" else np.stack([(x + 1) / 2, (y + 1) / 2,
                                                                                   np.full_like(x, 0.5)], -1)
    p = p.reshape(-1, 3) @ mapping[:3, :3].T + mapping[:3, 3]
    want = np.where(blender_checker(p * 1.5)[:, None] == 1.0, (0.9, 0.1, 0.1), (0.1, 0.1, 0.9))
    # a pixel whose centre lies within float32 rounding of a cell edge may go either way
    bad = np.abs(f.albedo.reshape(-1, 3) - want).max(axis=1) > 1e-5
    assert bad.sum() <= 2 and bad.sum() < len(bad) // 100


def test_mix_of_image_and_checker_on_the_square(device):
    size = 16
    img = np.full((2, 2, 3), 0.6, np.float32)
    checker = CheckerTexture((1.0, 1.0, 1.0), (0.0, 0.0, 0.0), scale=2.0, coords="uv")
    tex = MixColor(ImageTexture(img, colorspace="Non-Color"), (0.2, 0.4, 0.8), factor=checker, blend="MULTIPLY")
    f = render(facing_square(Material("m", albedo=tex), size))
    u, v = pixel_uv(size)
    t = blender_checker(np.stack([u, v, np.zeros_like(u)], -1).reshape(-1, 3) * 2.0).reshape(size, size)
    want = 0.6 * (1 - t[..., None]) + t[..., None] * 0.6 * np.array([0.2, 0.4, 0.8])
    np.testing.assert_allclose(f.albedo, want, atol=1e-5)


def _normal_colour(n) -> tuple:
    return tuple(0.5 * np.asarray(n, float) + 0.5)


@pytest.mark.parametrize("mirrored", [False, True])
@pytest.mark.parametrize("strength", [1.0, 0.5, 1.5])
def test_constant_normal_map_tilts_the_shading_normal(device, mirrored, strength):
    a = math.radians(25.0)
    nt = np.array([math.sin(a), 0.0, math.cos(a)])  # tangent space: tilted towards +tangent
    scene = facing_square(Material("m", normal=NormalMap(_normal_colour(nt), strength=strength)), 8)
    if mirrored:  # u runs along -x: the tangent is -x and the bitangent sign flips so that B stays +y
        scene.meshes[0].uvs[..., 0] = 1.0 - scene.meshes[0].uvs[..., 0]
    f = render(scene)
    c = 2 * (np.array(_normal_colour(nt), np.float32) - 0.5)
    c = np.array([c[0] * strength, c[1] * strength, 1.0 + min(max(strength, 0), 1) * (c[2] - 1.0)])
    tangent = np.array([-1.0 if mirrored else 1.0, 0.0, 0.0])
    want = c[0] * tangent + c[1] * np.array([0.0, 1.0, 0.0]) + c[2] * np.array([0.0, 0.0, 1.0])
    want /= np.linalg.norm(want)
    np.testing.assert_allclose(f.normal.reshape(-1, 3), np.broadcast_to(want, (64, 3)), atol=1e-5)


def test_smooth_normals_are_interpolated_faced_and_guarded(device):
    b = math.radians(20.0)
    tilted = np.array([math.sin(b), 0.0, math.cos(b)])
    scene = facing_square(Material("m"), 8)
    scene.meshes[0].normals = np.broadcast_to(tilted, (2, 3, 3)).copy()
    np.testing.assert_allclose(render(scene).normal.reshape(-1, 3), np.broadcast_to(tilted, (64, 3)), atol=1e-6)
    # rotated by 90 degrees about y, the square's object-space normal turns with it (inverse transpose)
    rot = np.array([[0, 0, 1, 0], [0, 1, 0, 0], [-1, 0, 0, 0], [0, 0, 0, 1]], float)
    scene.meshes[0].transforms = rot
    scene.camera.transforms = rot @ scene.camera.transforms
    np.testing.assert_allclose(render(scene).normal.reshape(-1, 3),
                               np.broadcast_to(rot[:3, :3] @ tilted, (64, 3)), atol=1e-6)
    # seen from behind, the shading normal flips with the geometric one
    scene = facing_square(Material("m"), 8)
    scene.meshes[0].normals = np.broadcast_to(tilted, (2, 3, 3)).copy()
    scene.meshes[0].triangles = scene.meshes[0].triangles[:, ::-1].copy()  # the back faces the camera now
    scene.meshes[0].normals = -scene.meshes[0].normals
    np.testing.assert_allclose(render(scene).normal.reshape(-1, 3), np.broadcast_to(tilted, (64, 3)), atol=1e-6)
    # a normal tilted beyond 45 degrees from the view would mirror the view into the surface: bent back until the
    # mirror direction leaves it
    steep = np.array([math.sin(math.radians(80)), 0.0, math.cos(math.radians(80))])
    scene.meshes[0].triangles = scene.meshes[0].triangles[:, ::-1].copy()
    scene.meshes[0].normals = np.broadcast_to(steep, (2, 3, 3)).copy()
    f = render(scene)
    n = f.normal.reshape(-1, 3).astype(np.float64)
    x, y = _world_xy(8)
    wi = np.stack([-x.ravel(), -y.ravel(), np.full(64, 4.0)], -1)
    wi /= np.linalg.norm(wi, axis=1, keepdims=True)
    cos_n = np.einsum("ij,ij->i", n, wi)
    refl_z = 2 * cos_n * n[:, 2] - wi[:, 2]  # the mirror direction's height above the square
    assert np.all(refl_z >= np.minimum(0.01, 0.5 * wi[:, 2]) - 1e-4)
    assert np.all(n[:, 0] < steep[0]) and np.all(n[:, 2] > steep[2])
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-5)


def test_textured_emission_is_seen_by_the_camera(device):
    img = np.random.default_rng(9).random((4, 4, 3)).astype(np.float32)
    tex = ImageTexture(img, colorspace="Non-Color", interpolation="Closest")
    scene = facing_square(Material("glow", albedo=(0.0, 0.0, 0.0), emission=tex, emission_strength=3.0), 16)
    scene.lights = []
    f = render(scene)
    u, v = pixel_uv(16)
    want = 3.0 * img[::-1][(v * 4).astype(int), (u * 4).astype(int)]
    np.testing.assert_allclose(f.noisy, want, rtol=1e-5)


@pytest.mark.parametrize("interp", INTERPOLATIONS)
def test_mips_remove_aliasing_on_a_grazing_plane(device, monkeypatch, interp):
    """A 1-texel checkerboard on a long floor seen at a grazing angle: without mips the far pixels alias (values
    jump between 0 and 1); with the ray-cone mip level they converge to the image mean 0.5."""
    from restircl import Camera, look_at
    from restircl.upload import textures as tp

    from ..texture_scenes import square_mesh

    board = (np.indices((256, 256)).sum(axis=0) % 2).astype(np.float32)
    tex = ImageTexture(board, colorspace="Non-Color", interpolation=interp, mapping=np.diag([8.0, 8.0, 1.0, 1.0]))

    def scene():
        mesh = square_mesh(20.0)
        cam = Camera(look_at((0, -20, 2.0), (0, 0, 0), (0, 0, 1)), 64, 48)
        cam.set_fov(math.radians(50))
        s = facing_square(Material("floor", albedo=tex), 8)
        s.meshes, s.camera = [mesh], cam
        return s

    f = render(scene())
    far = np.isfinite(f.depth) & (f.depth > 15.0)  # tens of texels per pixel
    with_mips = f.albedo[far][:, 0]
    monkeypatch.setattr(tp, "mip_chain", lambda level0, encoded=False: [level0])
    without = render(scene()).albedo[far][:, 0]
    assert far.sum() > 200
    var_with, var_without = with_mips.var(), without.var()
    # aliased: Closest reads 0 or 1 (variance 0.25), Linear a bilinear blend of a random texel quad (0.04)
    assert var_without > (0.1 if interp == "Closest" else 0.02)
    assert var_with < 0.1 * var_without
    assert abs(with_mips.mean() - 0.5) < 0.05


def test_specialised_and_general_builds_agree_on_a_textured_scene(device):
    img = np.random.default_rng(4).random((8, 8, 3)).astype(np.float32)
    m = Material("m", albedo=MixColor(ImageTexture(img), CheckerTexture(), factor=0.5),
                 normal=NormalMap((0.6, 0.5, 0.9)))
    scene = facing_square(m, 16)
    scene.meshes[0].normals = np.broadcast_to((0.1, 0.0, 1.0), (2, 3, 3)).copy()
    a, b = render(scene, method="ris"), render(scene, method="ris", specialise=False)
    np.testing.assert_array_equal(a.color, b.color)
    np.testing.assert_array_equal(a.normal, b.normal)


def test_object_coordinates_move_with_the_object(device):
    """A checker on Object coordinates is painted on the object: moved by (0.5, 0, 0) in frame 1, the pattern the
    camera sees moves by the same amount (a quarter of the 32-pixel view: 8 pixels)."""
    tex = CheckerTexture((1.0, 1.0, 1.0), (0.0, 0.0, 0.0), scale=2.0, coords="object")
    scene = facing_square(Material("m", albedo=tex), 32, half=1.0)
    scene.meshes[0].vertices *= 3.0  # larger than the view: it fills it in both frames
    moved = np.eye(4)
    moved[0, 3] = 0.5
    scene.meshes[0].transforms = np.stack([np.eye(4), moved])
    r = Renderer(scene, Settings(method="light_array", jitter=False))
    f0, f1 = r.render_frame(0).albedo, r.render_frame(1).albedo
    np.testing.assert_array_equal(f1[:, 8:], f0[:, :-8])
    assert f0[:, :, 0].std() > 0.3  # the pattern is there
