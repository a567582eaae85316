"""Export of texture nodes (Image, Checker, Mix Color, Normal Map, Mapping, Color Ramp, Hue/Saturation/Value),
images packed and on disk, the Cycles bake of other graphs, and the meshes' UV maps and corner normals."""

from __future__ import annotations

import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
restircl = pytest.importorskip("restircl")

from restircl import (  # noqa: E402
    CheckerTexture,
    ColorRamp,
    HueSaturationValue,
    ImageTexture,
    MixColor,
    NormalMap,
)

from .test_blender_materials import (  # noqa: E402
    add_node,
    export,
    fresh_scene,
    principled,
    socket,
    warnings_of,
)
from .test_blender_support import ensure_registered  # noqa: E402

pytestmark = pytest.mark.blender


@pytest.fixture(autouse=True)
def _addon():
    ensure_registered()


def plane(mat, name: str = "Plane", z: float = 0.0, uv: bool = True):
    """A 2x2 plane whose UV map covers [0, 1]^2 (as Blender's own primitive)."""
    bpy.ops.mesh.primitive_plane_add(size=2.0, location=(0, 0, z))
    ob = bpy.context.object
    ob.name = name
    if not uv:
        ob.data.uv_layers.remove(ob.data.uv_layers[0])
    ob.data.materials.append(mat)
    return ob


def image(name: str, w: int = 4, h: int = 2, float_buffer: bool = False):
    img = bpy.data.images.new(name, w, h, alpha=True, float_buffer=float_buffer)
    px = np.zeros((h, w, 4), np.float32)
    px[..., 0] = np.arange(w)[None, :] / (w - 1)  # red rises to the right
    px[..., 1] = np.arange(h)[:, None] / (h - 1)  # green rises upwards (Blender's row 0 is the bottom)
    px[..., 3] = 1.0
    img.pixels.foreach_set(px.reshape(-1))
    return img


def textured(name: str, img=None):
    mat, tree, p = principled(name)
    tex = tree.nodes.new("ShaderNodeTexImage")
    tex.image = img
    tree.links.new(tex.outputs["Color"], p.inputs["Base Color"])
    return mat, tree, p, tex


def material_of(name: str, **kw):
    exp = export()
    mats = [m for m in exp.scene.materials if m.name == name]
    assert mats, [m.name for m in exp.scene.materials]
    return mats[0], exp


def test_packed_image_on_base_color():
    fresh_scene()
    img = image("Ramp")
    img.pack()
    mat, _tree, _p, tex = textured("Img", img)
    tex.interpolation, tex.extension = "Closest", "EXTEND"
    plane(mat)
    m, exp = material_of("Img")
    t = m.albedo
    assert isinstance(t, ImageTexture)
    assert (t.interpolation, t.extension, t.coords, t.colorspace) == ("Closest", "EXTEND", "uv", "sRGB")
    arr = np.asarray(t.image)
    assert arr.dtype == np.uint8 and arr.shape == (2, 4, 4)
    assert list(arr[0, :, 0]) == [0, 85, 170, 255]  # columns left to right
    assert list(arr[:, 0, 1]) == [255, 0]  # row 0 is the top (an image file's order)
    assert not warnings_of(exp.warnings, "Img")
    mesh = next(x for x in exp.scene.meshes if x.name == "Plane")
    assert mesh.uvs is not None and mesh.uvs.shape == (len(mesh.triangles), 3, 2)


def test_image_on_disk_is_passed_by_path(tmp_path):
    fresh_scene()
    img = image("Disk", float_buffer=False)
    path = tmp_path / "ramp.png"
    img.filepath_raw = str(path)
    img.file_format = "PNG"
    img.save()
    loaded = bpy.data.images.load(str(path))
    loaded.colorspace_settings.name = "Non-Color"
    mat, *_ = textured("OnDisk", loaded)
    plane(mat)
    m, exp = material_of("OnDisk")
    assert isinstance(m.albedo, ImageTexture) and m.albedo.image == str(path)
    assert m.albedo.colorspace == "Non-Color"
    assert not warnings_of(exp.warnings, "OnDisk")


def test_float_image_is_linear_array():
    fresh_scene()
    img = image("HDR", float_buffer=True)
    img.pack()
    mat, *_ = textured("Flt", img)
    plane(mat)
    m, _exp = material_of("Flt")
    arr = np.asarray(m.albedo.image)
    assert arr.dtype == np.float32 and m.albedo.colorspace == "Non-Color"
    assert arr[0, -1, 0] == pytest.approx(1.0) and arr[-1, 0, 1] == pytest.approx(0.0)


def test_missing_image_file_is_one_warning_and_the_constant(tmp_path):
    fresh_scene()
    img = bpy.data.images.new("Gone", 4, 4)
    img.source = "FILE"
    img.filepath = str(tmp_path / "does_not_exist.png")
    mat, _tree, p, _tex = textured("Missing", img)
    plane(mat)
    m, exp = material_of("Missing")
    mine = warnings_of(exp.warnings, "Missing")
    assert len(mine) == 1 and "missing" in mine[0] and "does_not_exist.png" in mine[0], mine
    assert m.albedo == pytest.approx(tuple(p.inputs["Base Color"].default_value[:3]))


def test_unsupported_colour_space_warns_and_takes_the_nearest():
    fresh_scene()
    img = image("Aces")
    img.pack()
    img.colorspace_settings.name = "ACEScg"
    mat, *_ = textured("AcesMat", img)
    plane(mat)
    m, exp = material_of("AcesMat")
    mine = warnings_of(exp.warnings, "AcesMat")
    assert len(mine) == 1 and "ACEScg" in mine[0]
    assert m.albedo.colorspace == "Non-Color"


def test_mapping_and_texture_coordinates():
    fresh_scene()
    img = image("Mapped")
    img.pack()
    mat, tree, _p, tex = textured("MapMat", img)
    coord, mapping = tree.nodes.new("ShaderNodeTexCoord"), tree.nodes.new("ShaderNodeMapping")
    mapping.inputs["Location"].default_value = (0.5, 0.0, 0.0)
    mapping.inputs["Rotation"].default_value = (0.0, 0.0, math.pi / 2)
    mapping.inputs["Scale"].default_value = (2.0, 3.0, 1.0)
    tree.links.new(coord.outputs["Generated"], mapping.inputs["Vector"])
    tree.links.new(mapping.outputs["Vector"], tex.inputs["Vector"])
    plane(mat)
    m, _exp = material_of("MapMat")
    t = m.albedo
    assert t.coords == "generated"
    p = np.array([0.3, 0.2, 0.0, 1.0])
    expect = np.array([0.5 - 3.0 * 0.2, 2.0 * 0.3, 0.0])  # rotate (2x, 3y) by 90 degrees about z, then move
    assert (t.mapping @ p)[:3] == pytest.approx(expect)


def test_checker_and_mix_color_nodes():
    fresh_scene()
    mat, tree, p = principled("Chk")
    chk = add_node(tree, "ShaderNodeTexChecker", {"Color1": (1, 0, 0, 1), "Scale": 7.0})
    mix = add_node(tree, "ShaderNodeMix", data_type="RGBA", blend_type="MULTIPLY")
    socket(mix.inputs, "Factor_Float").default_value = 0.25
    socket(mix.inputs, "B_Color").default_value = (0.5, 0.5, 0.5, 1)
    tree.links.new(chk.outputs["Color"], socket(mix.inputs, "A_Color"))
    tree.links.new(socket(mix.outputs, "Result_Color"), p.inputs["Base Color"])
    legacy = tree.nodes.new("ShaderNodeMixRGB")
    legacy.blend_type = "SCREEN"
    tree.links.new(chk.outputs["Fac"], legacy.inputs["Fac"])
    tree.links.new(legacy.outputs[0], p.inputs["Roughness"])
    plane(mat)
    m, exp = material_of("Chk")
    assert isinstance(m.albedo, MixColor) and m.albedo.blend == "MULTIPLY" and m.albedo.factor == 0.25
    assert m.albedo.b == pytest.approx((0.5, 0.5, 0.5))
    c = m.albedo.a
    assert isinstance(c, CheckerTexture) and c.scale == 7.0 and c.coords == "generated"
    assert c.color1 == pytest.approx((1, 0, 0))
    assert isinstance(m.roughness, MixColor) and m.roughness.blend == "SCREEN"
    assert isinstance(m.roughness.factor, CheckerTexture)
    assert not warnings_of(exp.warnings, "Chk")


def test_color_ramp_and_hue_saturation_value_nodes():
    """A Color Ramp (Ease, its Alpha into Hue/Saturation/Value's Hue, its Color into Roughness) is read natively;
    a B-Spline ramp is baked."""
    sc = fresh_scene()
    sc.restircl.bake_resolution = 8
    mat, tree, p = principled("Ramp")
    chk = add_node(tree, "ShaderNodeTexChecker", {"Scale": 3.0})
    ramp = tree.nodes.new("ShaderNodeValToRGB")
    ramp.color_ramp.interpolation = "EASE"
    ramp.color_ramp.elements[1].position = 0.6
    ramp.color_ramp.elements[1].color = (1.0, 0.5, 0.25, 0.4)
    hsv = add_node(tree, "ShaderNodeHueSaturation", {"Saturation": 1.5, "Value": 0.7, "Fac": 0.9})
    tree.links.new(chk.outputs["Fac"], ramp.inputs["Fac"])
    tree.links.new(ramp.outputs["Alpha"], hsv.inputs["Hue"])
    tree.links.new(hsv.outputs["Color"], p.inputs["Base Color"])
    tree.links.new(ramp.outputs["Color"], p.inputs["Roughness"])
    plane(mat)
    m, exp = material_of("Ramp")
    h, r = m.albedo, m.roughness
    assert isinstance(h, HueSaturationValue) and (h.saturation, h.value) == pytest.approx((1.5, 0.7))
    assert h.factor == pytest.approx(0.9) and h.color == pytest.approx((0.8, 0.8, 0.8))
    assert isinstance(h.hue, ColorRamp) and h.hue.alpha and isinstance(h.hue.factor, CheckerTexture)
    assert isinstance(r, ColorRamp) and not r.alpha and r.interpolation == "EASE"
    assert r.positions == pytest.approx((0.0, 0.6)) and r.colors[1] == pytest.approx((1.0, 0.5, 0.25, 0.4))
    assert not warnings_of(exp.warnings, "Ramp")
    ramp.color_ramp.interpolation = "B_SPLINE"
    m, exp = material_of("Ramp")
    assert isinstance(m.roughness, ImageTexture)
    assert any("Color Ramp" in w for w in warnings_of(exp.warnings, "Ramp"))


def test_normal_map_node():
    fresh_scene()
    img = image("Bumps")
    img.pack()
    img.colorspace_settings.name = "Non-Color"
    mat, tree, p = principled("Nrm")
    tex, nmap = tree.nodes.new("ShaderNodeTexImage"), tree.nodes.new("ShaderNodeNormalMap")
    tex.image = img
    nmap.inputs["Strength"].default_value = 0.7
    tree.links.new(tex.outputs["Color"], nmap.inputs["Color"])
    tree.links.new(nmap.outputs["Normal"], p.inputs["Normal"])
    plane(mat)
    m, exp = material_of("Nrm")
    assert isinstance(m.normal, NormalMap) and m.normal.strength == pytest.approx(0.7)
    assert isinstance(m.normal.color, ImageTexture) and m.normal.color.colorspace == "Non-Color"
    assert not warnings_of(exp.warnings, "Nrm")


def test_object_without_uv_map_gets_the_constant():
    fresh_scene()
    img = image("NoUV")
    img.pack()
    mat, _tree, p, _tex = textured("NeedsUV", img)
    plane(mat, "WithUV", 0.0)
    plane(mat, "Bare", 1.0, uv=False)
    exp = export()
    by_mesh = {x.name: exp.scene.materials[x.material_ids[0]] for x in exp.scene.meshes}
    assert isinstance(by_mesh["WithUV"].albedo, ImageTexture)
    assert by_mesh["Bare"].albedo == pytest.approx(tuple(p.inputs["Base Color"].default_value[:3]))
    mine = warnings_of(exp.warnings, "NeedsUV")
    assert len(mine) == 1 and "UV map" in mine[0]
    bare = next(x for x in exp.scene.meshes if x.name == "Bare")
    assert bare.uvs is None


def test_uvs_and_smooth_normals_of_a_uv_sphere_match_blender():
    fresh_scene()
    bpy.ops.mesh.primitive_uv_sphere_add(segments=12, ring_count=6, radius=1.5)
    ob = bpy.context.object
    bpy.ops.object.shade_smooth()
    img = image("SphereImg")
    img.pack()
    mat, *_ = textured("SphereMat", img)
    ob.data.materials.append(mat)
    mesh = next(x for x in export().scene.meshes if x.name == ob.name)
    me = ob.data
    me.calc_loop_triangles()
    loops = np.array([list(t.loops) for t in me.loop_triangles])
    uv = np.array([tuple(d.uv) for d in me.uv_layers.active.data])
    nrm = np.array([tuple(n.vector) for n in me.corner_normals])
    assert mesh.uvs == pytest.approx(uv[loops], abs=1e-6)
    assert mesh.normals == pytest.approx(nrm[loops], abs=1e-6)
    # smooth: every corner at a vertex has the same normal, near the sphere's normal there
    flat_n = mesh.normals.reshape(-1, 3)
    for v in range(len(mesh.vertices)):
        at = flat_n[mesh.triangles.reshape(-1) == v]
        assert at == pytest.approx(np.repeat(at[:1], len(at), axis=0), abs=1e-6)
    pos = mesh.vertices[mesh.triangles]
    assert mesh.normals == pytest.approx(pos / np.linalg.norm(pos, axis=-1, keepdims=True), abs=0.05)


def test_flat_and_sharp_edges():
    fresh_scene()
    bpy.ops.mesh.primitive_cube_add(size=1.0)
    flat = bpy.context.object
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(3, 0, 0))
    sharp = bpy.context.object
    bpy.ops.object.shade_smooth()
    me = sharp.data
    top = next(f for f in me.polygons if f.normal.z > 0.9)
    for e in me.edges:  # the edges around the top face are sharp, the others smooth
        e.use_edge_sharp = set(e.vertices) <= set(top.vertices)
    meshes = {x.name: x for x in export().scene.meshes}
    assert meshes[flat.name].normals is None  # all faces flat: the geometric normal
    geo = meshes[sharp.name]
    p = geo.vertices[geo.triangles]
    face_n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    face_n /= np.linalg.norm(face_n, axis=-1, keepdims=True)
    up = face_n[:, 2] > 0.9
    assert geo.normals[up] == pytest.approx(np.broadcast_to([0.0, 0.0, 1.0], geo.normals[up].shape), abs=1e-6)
    side_bottom = (np.abs(face_n[:, 2]) < 0.1)[:, None] & (p[..., 2] < 0)
    # at the bottom corners of the sides the smooth normal leans away from the face's
    assert np.all(np.abs(geo.normals[side_bottom][:, 2]) > 0.3)


def test_other_graphs_are_baked():
    sc = fresh_scene()
    sc.restircl.bake_resolution = 16
    mat, tree, p = principled("Baked")
    coord, grad = tree.nodes.new("ShaderNodeTexCoord"), tree.nodes.new("ShaderNodeTexGradient")
    grad.gradient_type = "LINEAR"
    tree.links.new(coord.outputs["Generated"], grad.inputs["Vector"])
    tree.links.new(grad.outputs["Fac"], p.inputs["Roughness"])
    ob = plane(mat)
    m, exp = material_of("Baked")
    t = m.roughness
    assert isinstance(t, ImageTexture) and t.coords == "uv" and t.colorspace == "Non-Color"
    arr = np.asarray(t.image)
    assert arr.shape == (16, 16)
    # the plane's UV map and its generated coordinates agree: the gradient's x is the texel's u; the bake's
    # samples lie inside their texel, so they stay within half a texel (1/32) of its centre
    u = (np.arange(16) + 0.5) / 16
    assert arr[8] == pytest.approx(u, abs=0.04)
    mine = warnings_of(exp.warnings, "Baked")
    assert len(mine) == 1 and "Gradient Texture" in mine[0] and "Texture Coordinate" in mine[0], mine
    # the node tree is as it was
    assert p.inputs["Roughness"].links[0].from_node == grad
    assert not any(n.bl_idname == "ShaderNodeEmission" for n in tree.nodes)
    assert not any(i.name.startswith("restircl-bake") for i in bpy.data.images)
    assert ob.name in {x.name for x in exp.scene.meshes}


def test_unreadable_image_and_nan_pixels_warn(tmp_path):
    fresh_scene()
    bad = tmp_path / "broken.tga"
    bad.write_bytes(b"not an image at all")
    broken = bpy.data.images.load(str(bad))
    mat, _tree, p, _tex = textured("Broken", broken)
    plane(mat, "A")
    img = image("NaNs", float_buffer=True)
    px = np.zeros(4 * 2 * 4, np.float32)
    img.pixels.foreach_get(px)
    px[0] = np.nan
    img.pixels.foreach_set(px)
    img.pack()
    nan_mat, *_ = textured("NaNMat", img)
    plane(nan_mat, "B", 1.0)
    exp = export()
    mats = {m.name: m for m in exp.scene.materials}
    mine = warnings_of(exp.warnings, "Broken")
    assert len(mine) == 1 and "no pixels" in mine[0], mine
    assert mats["Broken"].albedo == pytest.approx(tuple(p.inputs["Base Color"].default_value[:3]))
    mine = warnings_of(exp.warnings, "NaNMat")
    assert len(mine) == 1 and "NaN" in mine[0], mine
    assert np.all(np.isfinite(mats["NaNMat"].albedo.image))
