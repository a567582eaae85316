"""Export of Blender's World: a colour, an Environment Texture (packed or on disk, with a Mapping rotation), a
graph baked through Cycles (Sky Texture), and the cases that must warn rather than fail."""

from __future__ import annotations

import math

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")
restircl = pytest.importorskip("restircl")

from restircl.eval import blender_scenes as scenes  # noqa: E402

from .test_blender_support import ensure_registered  # noqa: E402

pytestmark = [pytest.mark.blender,
              pytest.mark.skipif(not hasattr(restircl, "Environment"), reason="restircl has no Environment")]


@pytest.fixture(autouse=True)
def _addon():
    ensure_registered()


def export(bake_resolution=None):
    from restircl_blender import export as ex

    return ex.export_scene(bpy.context.evaluated_depsgraph_get(), bake_resolution=bake_resolution)


def world_scene():
    sc = scenes.new_scene(16, 12)
    scenes.quad("Floor", 4.0, 4.0, scenes.diffuse_material("Floor"))
    scenes.camera((0, -6, 4), (0, 0, 0))
    return sc, sc.world.node_tree


def sky_world():
    """world_scene with a Sky Texture (a node the native reader does not take) on the Background's Color."""
    sc, tree = world_scene()
    sky = tree.nodes.new("ShaderNodeTexSky")
    tree.links.new(sky.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    tree.nodes["Background"].inputs["Strength"].default_value = 1.0
    return sc, tree


def test_background_colour_and_strength():
    sc, tree = world_scene()
    bg = tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.2, 0.4, 0.6, 1.0)
    bg.inputs["Strength"].default_value = 2.5
    sc.world.cycles_visibility.camera = False
    env = export().scene.environment
    assert env is not None and env.image is None and env.path is None
    assert env.color == pytest.approx((0.2, 0.4, 0.6)) and env.strength == pytest.approx(2.5)
    assert env.visible_camera is False
    env.validate()


def test_emission_on_the_world_output_and_a_black_world():
    sc, tree = world_scene()
    em = tree.nodes.new("ShaderNodeEmission")
    em.inputs["Color"].default_value = (1.0, 0.5, 0.25, 1.0)
    em.inputs["Strength"].default_value = 3.0
    tree.links.new(em.outputs[0], tree.nodes["World Output"].inputs["Surface"])
    env = export().scene.environment
    assert env.color == pytest.approx((1.0, 0.5, 0.25)) and env.strength == pytest.approx(3.0)
    tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    tree.links.new(tree.nodes["Background"].outputs[0], tree.nodes["World Output"].inputs["Surface"])
    assert export().scene.environment is None  # new_scene's world emits nothing: no world light at all


def test_world_without_nodes_uses_its_colour():
    sc, _tree = world_scene()
    if not getattr(sc.world.bl_rna.properties["use_nodes"], "is_deprecated", False):
        sc.world.use_nodes = False
    else:
        sc.world.node_tree.nodes.clear()  # Blender 5: a world with an empty tree shows nothing
        assert export().scene.environment is None
        return
    sc.world.color = (0.3, 0.2, 0.1)
    env = export().scene.environment
    assert env.color == pytest.approx((0.3, 0.2, 0.1)) and env.strength == 1.0


def _env_texture(tree, image, rotation=None, vector_type="POINT"):
    tex = tree.nodes.new("ShaderNodeTexEnvironment")
    tex.image = image
    tree.links.new(tex.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    tree.nodes["Background"].inputs["Strength"].default_value = 1.5
    if rotation is not None:
        mapping = tree.nodes.new("ShaderNodeMapping")
        mapping.vector_type = vector_type
        mapping.inputs["Rotation"].default_value = rotation
        coords = tree.nodes.new("ShaderNodeTexCoord")
        tree.links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
        tree.links.new(mapping.outputs["Vector"], tex.inputs["Vector"])
    return tex


def _float_image(name, w=8, h=4):
    img = bpy.data.images.new(name, w, h, alpha=True, float_buffer=True)
    px = np.zeros((h, w, 4), np.float32)
    px[..., 0] = np.arange(w)[None, :] / w
    px[..., 1] = np.arange(h)[:, None] / h
    px[..., 2] = 0.5
    px[..., 3] = 1.0
    img.pixels.foreach_set(px.reshape(-1))
    return img, px


def test_packed_float_image_is_passed_as_pixels_rows_top_first():
    sc, tree = world_scene()
    img, px = _float_image("Sky")
    img.pack()
    _env_texture(tree, img)
    env = export().scene.environment
    assert env.path is None and env.image.shape == (4, 8, 3)
    np.testing.assert_allclose(env.image, px[::-1, :, :3], atol=1e-6)  # Blender's rows start at the bottom
    assert env.strength == pytest.approx(1.5) and env.rotation is None
    env.validate()


def test_exr_on_disk_is_passed_by_path(tmp_path):
    sc, tree = world_scene()
    img, _px = _float_image("SkyFile")
    path = tmp_path / "sky.exr"
    img.filepath_raw = str(path)
    img.file_format = "OPEN_EXR"
    img.save()
    on_disk = bpy.data.images.load(str(path))
    _env_texture(tree, on_disk)
    env = export().scene.environment
    assert env.image is None and env.path == str(path)
    env.validate()


def test_srgb_png_becomes_linear(tmp_path):
    sc, tree = world_scene()
    img = bpy.data.images.new("Png", 2, 1, alpha=False)
    img.pixels.foreach_set(np.array([0.5, 0.5, 0.5, 1.0, 1.0, 0.0, 0.0, 1.0], np.float32))
    img.filepath_raw = str(tmp_path / "sky.png")
    img.file_format = "PNG"
    img.save()
    _env_texture(tree, bpy.data.images.load(str(tmp_path / "sky.png")))
    env = export().scene.environment
    assert env.image is not None and env.image.shape == (1, 2, 3)
    assert env.image[0, 0, 0] == pytest.approx(0.214, abs=0.003)  # sRGB 0.5 (stored as 128/255) in linear
    assert env.image[0, 1].tolist() == pytest.approx([1.0, 0.0, 0.0])


@pytest.mark.parametrize("vector_type", ["POINT", "TEXTURE"])
def test_mapping_rotation(vector_type):
    sc, tree = world_scene()
    img, _ = _float_image("Rot")
    img.pack()
    angles = (0.3, -0.2, 1.1)
    _env_texture(tree, img, rotation=angles, vector_type=vector_type)
    env = export().scene.environment
    from mathutils import Euler

    r = np.array(Euler(angles, "XYZ").to_matrix())
    np.testing.assert_allclose(env.rotation, r if vector_type == "POINT" else r.T, atol=1e-6)
    env.validate()


@pytest.mark.parametrize(("node", "ours"), [("Linear", "Linear"), ("Closest", "Closest"), ("Cubic", "Linear"),
                                             ("Smart", "Linear")])
def test_interpolation_is_exported(node, ours):
    sc, tree = world_scene()
    img, _ = _float_image("Interp")
    img.pack()
    _env_texture(tree, img).interpolation = node
    env = export().scene.environment
    assert env.interpolation == ours
    env.validate()


def test_missing_image_warns_and_leaves_the_world_out():
    sc, tree = world_scene()
    img = bpy.data.images.new("Gone", 4, 2)
    img.source = "FILE"
    img.filepath = "/nonexistent/sky.exr"
    _env_texture(tree, img)
    exp = export()
    assert exp.scene.environment is None
    assert any("missing" in w and "Gone" in w for w in exp.warnings)
    exp.scene.validate()


def test_negative_world_strength_warns():
    sc, tree = world_scene()
    tree.nodes["Background"].inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    tree.nodes["Background"].inputs["Strength"].default_value = -1.0
    exp = export()
    if tree.nodes["Background"].inputs["Strength"].default_value >= 0:
        pytest.skip("this Blender clamps the strength at 0")
    assert exp.scene.environment is None and any("negative" in w for w in exp.warnings)


def test_baking_off_warns():
    sc, tree = sky_world()
    exp = export(bake_resolution=0)
    assert exp.scene.environment is None and any("baking is off" in w for w in exp.warnings)


def _lookup(image: np.ndarray, dirs: np.ndarray) -> np.ndarray:
    """Nearest texel of an equirectangular image (rows top first) in world directions, Cycles' map."""
    h, w = image.shape[:2]
    u = 0.5 - np.arctan2(dirs[..., 1], dirs[..., 0]) / (2 * math.pi)
    v = 0.5 + np.arcsin(np.clip(dirs[..., 2], -1, 1)) / math.pi
    col = np.clip((u * w).astype(int), 0, w - 1)
    row = np.clip(((1.0 - v) * h).astype(int), 0, h - 1)
    return image[row, col]


def _texel_dirs(w: int, h: int) -> np.ndarray:
    u = (np.arange(w) + 0.5) / w
    v = 1.0 - (np.arange(h) + 0.5) / h
    phi = (0.5 - u)[None, :] * 2 * math.pi
    lat = (v[:, None] - 0.5) * math.pi
    return np.stack(np.broadcast_arrays(np.cos(lat) * np.cos(phi), np.cos(lat) * np.sin(phi), np.sin(lat)), -1)


def test_baked_environment_texture_matches_the_rotation_sense_of_cycles():
    """A rotated Environment Texture baked by Cycles equals the image looked up in R d (Environment.rotation's
    sense): the bake path and the native path agree, and the rotation is Cycles' own."""
    sc, tree = world_scene()
    w, h = 32, 16
    img = bpy.data.images.new("Checker", w, h, alpha=True, float_buffer=True)
    rng = np.random.default_rng(5)
    blocks = rng.random((4, 8, 3)).astype(np.float32)
    px = np.ones((h, w, 4), np.float32)
    px[..., :3] = np.kron(blocks, np.ones((4, 4, 1), np.float32))  # 4x4-texel blocks: nearest lookups are exact
    img.pixels.foreach_set(px.reshape(-1))
    img.pack()
    tex = _env_texture(tree, img, rotation=(0.0, 0.0, 0.5 * math.pi))  # a quarter turn: blocks stay whole
    tex.interpolation = "Closest"
    tree.nodes["Background"].inputs["Strength"].default_value = 1.0
    native = export().scene.environment
    tree.links.new(tree.nodes.new("ShaderNodeTexSky").outputs[0], tree.nodes["Background"].inputs["Color"])
    tree.links.new(tex.outputs["Color"], tree.nodes["Background"].inputs["Color"])  # the sky node is idle
    tree.links.new(tex.outputs["Color"], tree.nodes.new("ShaderNodeGamma").inputs["Color"])
    gamma = tree.nodes["Gamma"]
    gamma.inputs["Gamma"].default_value = 1.0
    tree.links.new(gamma.outputs[0], tree.nodes["Background"].inputs["Color"])  # a node we do not read: baked
    exp = export(bake_resolution=h)
    baked = exp.scene.environment
    assert baked is not None and baked.image.shape == (h, 2 * h, 3) and baked.rotation is None
    assert any("baked" in m and "Gamma" in m for m in exp.warnings)
    dirs = _texel_dirs(2 * h, h)
    expected = _lookup(px[::-1, :, :3], dirs @ native.rotation.T)
    inner = np.zeros((h, 2 * h), bool)  # texels away from block edges (the bake antialiases them)
    inner[1:-1, 1:-1] = True
    close = np.isclose(baked.image, expected, atol=2e-3).all(axis=-1)
    assert close[inner].mean() > 0.7, f"only {close[inner].mean():.2f} of the texels agree"
    unrotated = _lookup(px[::-1, :, :3], dirs)
    assert np.isclose(baked.image, unrotated, atol=2e-3).all(axis=-1)[inner].mean() < 0.5


def test_sky_texture_is_baked_with_a_warning():
    sc, tree = sky_world()
    exp = export(bake_resolution=16)
    env = exp.scene.environment
    assert env is not None and env.image.shape == (16, 32, 3)
    assert any("Sky Texture" in w and "baked" in w for w in exp.warnings)
    assert np.all(np.isfinite(env.image)) and env.image.max() > 0
    sky_half, ground_half = env.image[:8].mean(), env.image[8:].mean()
    assert sky_half > ground_half  # the zenith is row 0
    env.validate()


def test_sky_world_bakes_during_f12(tmp_path):
    """The bake runs inside the render in progress (a scratch scene of its own) and the render completes."""
    from .test_blender_support import needs_renderer, read_exr_passes, render_to

    if needs_renderer.args and needs_renderer.args[0]:
        pytest.skip("restircl.Renderer is not available")
    sc, tree = sky_world()
    scenes.light("SUN", "Sun", (0, 0, 5), energy=2.0)
    sc.render.engine = "RESTIRCL"
    sc.restircl.samples = 2
    sc.restircl.bake_resolution = 16
    render_to(sc, tmp_path / "sky.exr")
    rgba = read_exr_passes(tmp_path / "sky.exr")["Combined"]
    assert np.all(np.isfinite(rgba)) and rgba[..., :3].max() > 0
    assert not any(s.name.startswith("restircl-world-bake") for s in bpy.data.scenes)
    exp = ensure_registered().engine._SESSIONS[(sc.name, sc.view_layers[0].name)].export
    assert exp.scene.environment is not None and exp.scene.environment.image.shape == (16, 32, 3)
    assert any("baked" in w for w in exp.warnings) and not any("failed" in w for w in exp.warnings)
