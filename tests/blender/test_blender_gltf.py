"""Real assets as Blender's glTF importer makes them (tests/blender/gltf_scenes.py): the importer's node setup, the
bake of a packed occlusion-roughness-metallic channel, the native export of the helmet material, failed bakes in the
report, and the helmet scene against Cycles (slow: about a minute)."""

from __future__ import annotations

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
restircl = pytest.importorskip("restircl")

from .gltf_scenes import SIZE, import_helmet, orm_texels  # noqa: E402
from .test_blender_materials import fresh_scene  # noqa: E402
from .test_blender_support import ensure_registered, needs_renderer  # noqa: E402

pytestmark = pytest.mark.blender


@pytest.fixture(autouse=True)
def _addon():
    ensure_registered()


def _helmet(tmp_path):
    fresh_scene()
    ob = import_helmet(tmp_path)
    return ob, ob.data.materials[0]


def test_the_importer_gives_the_packed_orm_setup(tmp_path):
    ob, mat = _helmet(tmp_path)
    kinds = sorted(n.bl_idname for n in mat.node_tree.nodes)
    assert kinds.count("ShaderNodeTexImage") >= 4 and "ShaderNodeSeparateColor" in kinds
    assert "ShaderNodeGroup" in kinds and ob.data.uv_layers.keys() == ["UVMap"]
    p = mat.node_tree.nodes["Principled BSDF"]
    for name, channel in (("Roughness", "Green"), ("Metallic", "Blue")):
        link = p.inputs[name].links[0]
        assert link.from_node.bl_idname == "ShaderNodeSeparateColor" and link.from_socket.name == channel


@pytest.mark.parametrize("channel", ["Green", "Blue"])
def test_bake_of_a_packed_channel_is_the_image_channel(tmp_path, channel):
    """Cycles' Emit bake of a Separate Color output on the imported mesh gives the ORM image's channel (the texels
    of the UV map's interior: the sphere's poles squeeze whole rows into a point)."""
    from restircl_blender.export.bake import bake_socket

    ob, mat = _helmet(tmp_path)
    sock = mat.node_tree.nodes["Principled BSDF"].inputs["Roughness" if channel == "Green" else "Metallic"]
    baked = bake_socket(mat, ob, sock.links[0].from_socket, SIZE)[::-1, :, 0]  # rows bottom first, as the image
    want = orm_texels()[..., 1 if channel == "Green" else 2]
    inner = (slice(2, SIZE - 2), slice(1, SIZE - 1))
    assert baked.max() > 0.5, "the bake wrote zeros"
    # texel centres, antialiased over the texel (the ramp's kinks blur by a texel)
    tol = 0.02 if channel == "Green" else 0.15
    np.testing.assert_allclose(baked[inner], want[inner], atol=tol)


def test_the_helmet_material_is_read_natively(tmp_path):
    """Roughness and Metallic are one channel each of the ORM image (no bake), the occlusion group changes nothing
    (as in Cycles), and nothing is said about the emission image (it lights by its texels)."""
    from restircl import ImageTexture, NormalMap, SeparateColor

    from .test_blender_materials import export

    _helmet(tmp_path)
    exp = export(bake_resolution=16)
    m = next(m for m in exp.scene.materials if m.name == "HelmetSource")
    for field, channel in (("roughness", 1), ("metallic", 2)):
        node = getattr(m, field)
        assert isinstance(node, SeparateColor) and node.channel == channel and node.mode == "RGB"
        assert isinstance(node.color, ImageTexture) and node.color.colorspace == "Non-Color"
        np.testing.assert_array_equal(np.asarray(node.color.image)[::-1, :, channel],
                                      np.round(orm_texels()[..., channel] * 255).astype(np.uint8))
    assert isinstance(m.albedo, ImageTexture) and isinstance(m.normal, NormalMap)
    assert isinstance(m.emission, ImageTexture) and m.emission_strength == 1.0
    assert not any("baked" in w or "Group" in w or "glTF" in w for w in exp.warnings), exp.warnings


def _noise_material(name: str):
    from .test_blender_materials import principled

    mat, tree, p = principled(name)
    noise = tree.nodes.new("ShaderNodeTexNoise")  # a graph the renderer bakes
    tree.links.new(noise.outputs["Fac"], p.inputs["Roughness"])
    return mat


@pytest.mark.parametrize("case", ["no UV map", "zero-area UV map"])
def test_a_failed_bake_is_reported_and_the_value_used(case):
    """A bake that cannot write a texel is said in the export's warnings (Blender's report), never a silent zero."""
    from .test_blender_export_textures import plane
    from .test_blender_materials import export, warnings_of

    fresh_scene()
    ob = plane(_noise_material("Noisy"), uv=case != "no UV map")
    if case == "zero-area UV map":
        uv = ob.data.uv_layers[0].data
        for loop in uv:
            loop.uv = (0.5, 0.5)
    exp = export(bake_resolution=16)
    m = next(m for m in exp.scene.materials if m.name == "Noisy")
    assert m.roughness == pytest.approx(0.5)  # the Principled BSDF's own Roughness, as the warning says
    mine = warnings_of(exp.warnings, "Noisy")
    # a zero-area UV map bakes to zeros in Blender 5.0 and to the one value at that UV point in 5.3: both are failures
    wants = ("needs a UV map",) if case == "no UV map" else ("failed: the baked 16x16 image is all zero",
                                                            "failed: the baked image is one value")
    assert any(any(x in w for x in wants) and "Noise Texture" in w and "the input's value is used" in w
               for w in mine), mine


@pytest.mark.xfail(bpy.app.version >= (5, 1, 0), strict=False,
                   reason="Blender 5.3 bakes this zero-area UV map (at a texel corner) to an image that passes the "
                          "check; the export's own check of a zero-area map (above) reports it")
def test_the_report_of_a_failed_bake_reaches_blender(tmp_path, monkeypatch):
    """F12 of a scene whose bake fails: the engine reports the failure (RenderEngine.report) and renders."""
    from .test_blender_export_textures import plane
    from .test_blender_support import record_engine, render_to

    sc = fresh_scene()
    ob = plane(_noise_material("Noisy"))
    for loop in ob.data.uv_layers[0].data:
        loop.uv = (0.25, 0.25)
    sc.render.engine = "RESTIRCL"
    sc.restircl.bake_resolution = 16
    sc.restircl.samples = 1
    reports, _stats = record_engine(monkeypatch)
    render_to(sc, tmp_path / "out.exr")
    assert any("Noise Texture" in r and "failed" in r and "all zero" in r for r in reports), reports


@pytest.mark.slow
@needs_renderer
def test_the_helmet_agrees_with_cycles(tmp_path, record_property):
    """The issue's scene at 64x48 (tests/blender/gltf_scenes.py), direct light: F12 against Cycles, relMSE < 1e-2,
    the helmet's emissive band lighting the scene by its texels (lights/textured_emission.py)."""
    from .gltf_scenes import helmet_scene
    from .test_blender_support import cycles_and_ours

    sc = helmet_scene(tmp_path, 64, 48)
    err, ratio = cycles_and_ours(tmp_path, sc, 256, 64, "glTF helmet", bake_resolution=64)
    record_property("relmse", err)
    assert err < 1e-2, f"glTF helmet: relMSE {100 * err:.3f} % against Cycles"
    assert ratio == pytest.approx(1.0, abs=0.02)
