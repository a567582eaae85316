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


# UVs per corner of the plane's one quad: all on one point (Blender 4.2 and 5.0 bake zeros there, 5.3 one texel's value
# spread by the bake's margin over most of the image), all on one line (5.3 bakes an image that varies), and a good map
# of little area: two corners on one UV, the quad a triangle of area 1/4 (the plane's own map is the whole square)
UV_MAPS = {"zero-area UV map": [(0.25, 0.25)] * 4, "UV map on a line": [(0.1, 0.5), (0.9, 0.5), (0.7, 0.5), (0.2, 0.5)],
           "folded UV map": [(0.0, 0.0), (1.0, 0.0), (0.5, 0.5), (0.0, 0.0)]}


def _noisy_plane(case: str):
    """A plane of a material that bakes (a Noise Texture on Roughness), with the UV map of `case` (or none)."""
    from .test_blender_export_textures import plane

    ob = plane(_noise_material("Noisy"), uv=case != "no UV map")
    if case in UV_MAPS:
        for loop, uv in zip(ob.data.uv_layers[0].data, UV_MAPS[case], strict=True):
            loop.uv = uv
    return ob


def _failure(case: str) -> str:
    return "needs a UV map" if case == "no UV map" else \
        "failed: the UV map 'UVMap' of object 'Plane' has zero area on the faces of material 'Noisy'"


@pytest.mark.parametrize("case", ["no UV map", "zero-area UV map", "UV map on a line"])
def test_a_failed_bake_is_reported_and_the_value_used(case):
    """A bake that cannot write a texel is said in the export's warnings (Blender's report), never a silent zero:
    a zero-area UV map is told from the mesh before the bake, the same on every Blender."""
    from .test_blender_materials import export, warnings_of

    fresh_scene()
    _noisy_plane(case)
    exp = export(bake_resolution=16)
    m = next(m for m in exp.scene.materials if m.name == "Noisy")
    assert m.roughness == pytest.approx(0.5)  # the Principled BSDF's own Roughness, as the warning says
    mine = warnings_of(exp.warnings, "Noisy")
    assert any(_failure(case) in w and "Noise Texture" in w and "the input's value is used" in w for w in mine), mine


@pytest.mark.parametrize("case", ["folded UV map", "plane's own UV map"])
def test_a_bake_on_a_good_uv_map_is_not_reported(case):
    """The control of the test above: a UV map of some area (a quarter of the square, or all of it) bakes the noise,
    and nothing says it failed."""
    from restircl import ImageTexture

    from .test_blender_materials import export, warnings_of

    fresh_scene()
    _noisy_plane(case)
    exp = export(bake_resolution=16)
    m = next(m for m in exp.scene.materials if m.name == "Noisy")
    assert isinstance(m.roughness, ImageTexture), m.roughness
    baked = np.asarray(m.roughness.image)
    assert np.ptp(baked) > 0.05, "the noise baked to one value"
    mine = warnings_of(exp.warnings, "Noisy")
    assert not any("fail" in w or "zero" in w or "input's value" in w for w in mine), mine
    assert any("baked to images" in w and "Noise Texture" in w for w in mine), mine


def test_the_check_of_a_baked_image():
    """All zero, one value, or one value and zeros (Blender 5.3's bake of a zero-area UV map: one texel spread by
    the margin) while a texture feeds the graph are failures; an image that varies, also beside zeros, is not, nor
    is one value that no texture feeds."""
    from restircl_blender.export.bake import bake_failure

    fresh_scene()
    tree = _noise_material("Noisy").node_tree
    noise = tree.nodes["Noise Texture"]
    value = tree.nodes.new("ShaderNodeMath")
    zeros = np.zeros((4, 4), np.float32)
    spread = zeros.copy()
    spread[:, :3] = 0.43
    ramp = np.linspace(0.0, 1.0, 16, dtype=np.float32).reshape(4, 4)
    assert "is all zero" in bake_failure(zeros, noise)
    assert "one value (0.5) while" in bake_failure(zeros + 0.5, noise)
    assert "one value (0.43) on the 12 texels not zero" in bake_failure(spread, noise)
    assert "one value (0.43) on the 12 texels not zero" in bake_failure(np.dstack([spread, spread, zeros]), noise)
    assert "NaN" in bake_failure(np.where(spread > 0, np.nan, 0.0), noise)
    assert bake_failure(ramp, noise) == "" and bake_failure(np.where(spread > 0, ramp, 0.0), noise) == ""
    assert bake_failure(np.dstack([spread, ramp, zeros]), noise) == ""
    assert bake_failure(zeros + 0.5, value) == "" and bake_failure(spread, value) == ""


@pytest.mark.parametrize(("case", "area"), [("plane's own UV map", 1.0), ("folded UV map", 0.25),
                                            ("zero-area UV map", 0.0), ("UV map on a line", 0.0)])
def test_the_uv_area_of_a_material(case, area):
    """The UV area the bake check measures, against the areas of the maps above worked out by hand; faces of another
    material slot do not count."""
    from restircl_blender.export.bake_uv import uv_area

    fresh_scene()
    ob = _noisy_plane(case)
    mesh = ob.data
    assert uv_area(mesh, mesh.uv_layers[0], [0], 1) == pytest.approx(area, abs=1e-6)
    ob.data.materials.append(_noise_material("Other"))
    mesh.polygons[0].material_index = 1
    assert uv_area(mesh, mesh.uv_layers[0], [0], 2) is None
    assert uv_area(mesh, mesh.uv_layers[0], [1], 2) == pytest.approx(area, abs=1e-6)


@pytest.mark.parametrize("case", ["zero-area UV map", "plane's own UV map"])
def test_the_report_of_a_failed_bake_reaches_blender(tmp_path, monkeypatch, case):
    """F12 of a scene whose bake fails: the engine reports the failure (RenderEngine.report) and renders; with a
    good UV map it reports the bake and no failure."""
    from .test_blender_support import record_engine, render_to

    sc = fresh_scene()
    _noisy_plane(case)
    sc.render.engine = "RESTIRCL"
    sc.restircl.bake_resolution = 16
    sc.restircl.samples = 1
    reports, _stats = record_engine(monkeypatch)
    render_to(sc, tmp_path / "out.exr")
    assert (tmp_path / "out.exr").stat().st_size > 0
    failed = [r for r in reports if "Noise Texture" in r and "failed" in r]
    if case == "zero-area UV map":
        assert any(_failure(case) in r for r in failed), reports
    else:
        assert not failed and any("baked to images" in r and "Noise Texture" in r for r in reports), reports


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
