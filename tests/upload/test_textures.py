"""Textures on the host: the texture programs (upload/textures.py), image files (io/image_load.py), material validation
(materials/check.py), bad input (warnings naming the material and the image, never NaN pixels), and the scene file's
round trip of textured, mixed materials (scene/file.py, materials/file.py)."""

import math
import os
import warnings

import numpy as np
import pytest
from restircl import CheckerTexture, ImageTexture, Material, MixColor, NormalMap, Renderer, Scene, SceneError, Settings
from restircl.io.image_load import ImageReadError, mip_chain, read_image_file, to_linear_rgba
from restircl.upload.textures import MAGENTA, MAX_TEX_PROGRAM, TexturePacker

from ..texture_scenes import facing_square


def render_albedo(material: Material, size: int = 8) -> np.ndarray:
    scene = facing_square(material, size)
    return Renderer(scene, Settings(method="light_array", jitter=False)).render_frame(0)


# ---- programs ---------------------------------------------------------------------------------------------

def test_a_program_is_its_graph_in_post_order_and_shared_nodes_are_packed_once():
    img = ImageTexture(np.zeros((2, 2, 3), np.float32))
    checker = CheckerTexture(img, (0.1, 0.2, 0.3))
    mix = MixColor(img, checker, factor=0.25, blend="ADD")
    m = Material("m", albedo=mix, roughness=img)
    packer = TexturePacker([m])
    nodes = packer.packed().nodes
    root = packer.index(mix)
    assert root == 2 and packer.index(img) == 3  # img's own program comes after mix's, whose first node it is
    assert list(nodes["op"][:3, 0]) == [0, 1, 2] and np.all(nodes["blk"][:3, 0] == 0)
    assert tuple(nodes["in"][2, :3]) == (0, 1, -1) and nodes["p"][2, 0] == np.float32(0.25)
    assert tuple(nodes["in"][1, :2]) == (0, -1) and tuple(nodes["b"][1, :3]) == pytest.approx((0.1, 0.2, 0.3))
    assert len(packer.packed().images) == 1  # one image, used twice


def test_a_packing_takes_the_images_an_earlier_one_loaded(tmp_path, monkeypatch):
    """An interactive edit packs the materials again: an image whose content (an array) or file (path, size, time)
    is unchanged is taken from the earlier packing, not read again, and its key says so; another image is read."""
    from PIL import Image
    from restircl.upload import textures as texture_pack

    pixels = np.full((2, 2, 3), 0.25, np.float32)
    path = tmp_path / "t.png"
    Image.fromarray(np.full((2, 2, 3), 64, np.uint8)).save(path)
    first = TexturePacker([Material("a", albedo=ImageTexture(pixels), roughness=ImageTexture(str(path)))])
    reads = []
    monkeypatch.setattr(texture_pack, "read_image_file", lambda p: reads.append(p) or read_image_file(p))
    same = TexturePacker([Material("a", albedo=ImageTexture(pixels.copy()), roughness=ImageTexture(str(path)))],
                         first.images)
    assert same.image_keys == first.image_keys and not reads
    assert all(same.images[k] is first.images[k] for k in first.image_keys)
    np.testing.assert_array_equal(same.packed(texels=False).images, first.packed().images)
    assert len(same.packed(texels=False).texels) == 0
    pixels[0, 0, 0] = 0.5  # painted
    os.utime(path, ns=(1, 1))  # the file saved again
    other = TexturePacker([Material("a", albedo=ImageTexture(pixels), roughness=ImageTexture(str(path)))],
                          first.images)
    assert [a != b for a, b in zip(other.image_keys, first.image_keys, strict=True)] == [True, True]
    assert reads == [str(path)]


def test_a_node_loop_is_refused_naming_the_material():
    a = MixColor()
    b = MixColor(a=a)
    a.b = b
    scene = facing_square(Material("looped", albedo=a))
    with pytest.raises(SceneError, match="material 0 'looped'.*loop"):
        scene.validate()
    with pytest.raises(SceneError, match="material 0 'looped'.*loop"):  # packing refuses it too
        TexturePacker(scene.materials)


def test_a_program_longer_than_the_registers_is_refused():
    node: object = (0.5, 0.5, 0.5)
    for _ in range(MAX_TEX_PROGRAM + 1):
        node = MixColor(node, (0.1, 0.1, 0.1))
    with pytest.raises(SceneError, match="material 0 'deep'.*at most"):
        TexturePacker([Material("deep", albedo=node)])


def test_mip_chain_halves_rounding_up_and_keeps_the_mean():
    img = np.random.default_rng(0).random((5, 8, 4)).astype(np.float32)
    levels = mip_chain(img)
    assert [lv.shape[:2] for lv in levels] == [(5, 8), (3, 4), (2, 2), (1, 1)]
    even = np.random.default_rng(1).random((4, 4, 4)).astype(np.float32)
    np.testing.assert_allclose(mip_chain(even)[-1][0, 0], even.mean(axis=(0, 1)), rtol=1e-5)


def test_an_encoded_mip_level_decodes_to_the_mean_light_of_its_texels():
    """A 2x2 sRGB-encoded block, one texel white (1.0) and three black: its 1x1 level must decode to the mean light
    0.25 (encoded 0.5371), not to the decoded mean encoding 0.25 (0.0508); alpha and level 0 stay as they are."""
    img = np.zeros((2, 2, 4), np.float32)
    img[0, 0, :3] = 1.0
    img[..., 3] = (0.2, 0.4), (0.6, 0.8)
    levels = mip_chain(img, encoded=True)
    assert levels[0] is img
    np.testing.assert_allclose(levels[1][0, 0], (0.53709, 0.53709, 0.53709, 0.5), atol=1e-4)


# ---- image files --------------------------------------------------------------------------------------------

def test_png_and_exr_files_are_read(tmp_path):
    from PIL import Image
    from restircl import write_exr

    rgb8 = np.random.default_rng(4).integers(0, 256, (3, 5, 3), dtype=np.uint8)
    Image.fromarray(rgb8, "RGB").save(tmp_path / "a.png")
    np.testing.assert_array_equal(read_image_file(tmp_path / "a.png"), rgb8)
    grey16 = np.random.default_rng(6).integers(0, 65536, (4, 3), dtype=np.uint16)
    Image.fromarray(grey16).save(tmp_path / "g.png")
    np.testing.assert_array_equal(read_image_file(tmp_path / "g.png"), grey16)
    np.testing.assert_allclose(to_linear_rgba(grey16, "Non-Color")[0, :, 1], grey16[-1] / 65535.0, rtol=1e-6)
    hdr = np.random.default_rng(5).random((3, 5, 4)).astype(np.float32) * 10
    write_exr(tmp_path / "b.exr", hdr)
    np.testing.assert_array_equal(read_image_file(tmp_path / "b.exr"), hdr)
    np.testing.assert_allclose(to_linear_rgba(hdr, "Non-Color"), hdr[::-1])  # bottom row first, as stored
    (tmp_path / "c.hdr").write_bytes(b"#?RADIANCE\n")
    with pytest.raises(ImageReadError, match="not readable"):
        read_image_file(tmp_path / "c.hdr")


# ---- bad input: warnings naming the material and the image, magenta, never NaN ---------------------------------

@pytest.mark.parametrize("case", ["missing", "empty", "colorspace", "format", "corrupt"])
def test_unusable_images_warn_and_render_magenta(tmp_path, case):
    (tmp_path / "broken.png").write_bytes(b"not a png")
    tex = {"missing": ImageTexture(str(tmp_path / "nowhere.png"), name="wood"),
           "empty": ImageTexture(np.zeros((0, 0, 3), np.float32), name="wood"),
           "colorspace": ImageTexture(np.ones((2, 2, 3), np.float32), colorspace="ACEScg", name="wood"),
           "format": ImageTexture(str(tmp_path / "wood.xyz"), name="wood"),
           "corrupt": ImageTexture(str(tmp_path / "broken.png"), name="wood")}[case]
    if case == "format":
        (tmp_path / "wood.xyz").write_bytes(b"?")
    with pytest.warns(UserWarning, match="material 0 'floor': image 'wood'.*magenta"):
        f = render_albedo(Material("floor", albedo=tex))
    np.testing.assert_array_equal(f.albedo, np.broadcast_to(np.float32(MAGENTA[:3]), f.albedo.shape))
    assert np.all(np.isfinite(f.color))


def test_nan_texels_are_counted_zeroed_and_warned():
    img = np.full((4, 4, 3), 0.5, np.float32)
    img[1, 2] = np.nan
    img[3, 0, 1] = np.inf
    with pytest.warns(UserWarning, match=r"material 0 'm': image 'spots': 2 texels hold NaN or Inf"):
        tex = ImageTexture(img, colorspace="Non-Color", name="spots", interpolation="Closest")
        f = render_albedo(Material("m", albedo=tex), 16)
    assert np.all(np.isfinite(f.color)) and np.all(np.isfinite(f.albedo))
    assert (f.albedo == 0).any() and np.isclose(f.albedo, 0.5).any()


def test_good_textures_do_not_warn():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        render_albedo(Material("m", albedo=CheckerTexture(), roughness=ImageTexture(np.ones((2, 2)))))


# ---- validation ---------------------------------------------------------------------------------------------

BAD_MATERIALS = {
    "kind": (dict(kind="plastic"), "kind must be one of"),
    "distribution": (dict(distribution="beckmann"), "distribution"),
    "roughness": (dict(roughness=1.5), r"roughness must be in \[0, 1\]"),
    "metallic": (dict(metallic=-0.1), "metallic must not be negative"),
    "specular": (dict(specular=float("nan")), "specular must be finite"),
    "ior": (dict(ior=0.0), "ior must be finite and > 0"),
    "albedo": (dict(albedo=(1.0, 0.5)), "albedo must be 3 numbers"),
    "tint": (dict(specular_tint=(1.0, math.inf, 0.0)), "specular_tint must be finite"),
    "normal": (dict(normal=CheckerTexture()), "normal must be a NormalMap"),
    "normal_in_colour": (dict(albedo=NormalMap()), "a NormalMap gives a normal"),
    "coords": (dict(albedo=ImageTexture(np.ones((2, 2)), coords="camera")), "coords must be one of"),
    "interp": (dict(albedo=ImageTexture(np.ones((2, 2)), interpolation="Cubic")), "interpolation must be one of"),
    "ext": (dict(albedo=ImageTexture(np.ones((2, 2)), extension="MIRROR")), "extension must be one of"),
    "mapping": (dict(albedo=CheckerTexture(mapping=np.eye(3))), "mapping must be a finite 4x4"),
    "blend": (dict(albedo=MixColor(blend="PIN_LIGHT")), "blend must be one of"),
    "nested": (dict(albedo=MixColor(a=CheckerTexture(color1=(2.0, -1.0, 0.0)))), "color1 must not be negative"),
    "strength": (dict(normal=NormalMap(strength=-1.0)), "strength must be finite and >= 0"),
    "image": (dict(albedo=ImageTexture(42)), "image must be an array or a file path"),
    "emission": (dict(emission_strength=-1.0), "emission_strength"),
}


@pytest.mark.parametrize("case", sorted(BAD_MATERIALS))
def test_bad_material_fields_raise_naming_the_material(case):
    fields, message = BAD_MATERIALS[case]
    scene = facing_square(Material("bad", **fields))
    with pytest.raises(SceneError, match=f"material 0 'bad': .*{message}"):
        scene.validate()


def test_bad_layers_raise():
    d = Material("d")
    too_many = Material("three", layers=[d, d, d])
    nested = Material("nest", layers=[Material.mixed(d, d), d])
    bad_mix = Material.mixed(d, d, factor=1.5)
    bad_layer = Material.added(d, Material("rough", roughness=2.0))
    for m, message in ((too_many, "at most 2"), (nested, "layers of its own"), (bad_mix, r"mix must be in \[0, 1\]"),
                       (bad_layer, "layer 1 'rough': roughness")):
        with pytest.raises(SceneError, match=message):
            facing_square(m).validate()


def test_mesh_attribute_shapes_are_checked():
    scene = facing_square(Material("m"))
    scene.meshes[0].uvs = np.zeros((2, 3, 3))
    with pytest.raises(SceneError, match="mesh 'square': uvs must be finite, shape"):
        scene.validate()
    scene.meshes[0].uvs = None
    scene.meshes[0].normals = np.full((2, 3, 3), np.nan)
    with pytest.raises(SceneError, match="mesh 'square': normals"):
        scene.validate()


# ---- the scene file --------------------------------------------------------------------------------------------

def test_scene_file_round_trip_of_textured_mixed_materials(tmp_path):
    img = np.random.default_rng(8).random((3, 4, 3)).astype(np.float32)
    image = ImageTexture(img, colorspace="Non-Color", interpolation="Closest", extension="CLIP", coords="generated",
                         mapping=np.diag([2.0, 1.0, 1.0, 1.0]), name="grain")
    checker = CheckerTexture(image, (0.1, 0.2, 0.3), scale=3.0, coords="object")
    gloss = Material("gloss", kind="glossy", albedo=checker, roughness=image, distribution="ggx")
    base = Material("base", metallic=0.3, specular=0.5, specular_tint=(1.0, 0.9, 0.8), ior=1.45,
                    normal=NormalMap(image, strength=0.7))
    mixed = Material.mixed(base, gloss, factor=MixColor(image, (0.5, 0.5, 0.5), factor=0.2, blend="OVERLAY",
                                                        clamp_factor=False), name="mixed")
    mixed.emission, mixed.emission_strength = CheckerTexture(), 2.0
    scene = facing_square(mixed, 16)
    scene.materials.append(Material.added(Material("a"), Material("b", albedo=str(tmp_path / "x.png"))))
    scene.materials[1].layers[1].albedo = ImageTexture(str(tmp_path / "x.png"))
    scene.meshes[0].normals = np.broadcast_to((0.0, 0.0, 1.0), (2, 3, 3)).copy()
    scene.save(tmp_path / "s.npz")
    back = Scene.load(tmp_path / "s.npz")
    m = back.materials[0]
    assert m.mix.blend == "OVERLAY" and m.mix.clamp_factor is False and m.emission_strength == 2.0
    b, g = m.layers
    assert (b.metallic, b.specular, b.ior, b.specular_tint) == (0.3, 0.5, 1.45, (1.0, 0.9, 0.8))
    assert g.kind == "glossy" and g.distribution == "ggx" and g.albedo.scale == 3.0 and g.albedo.coords == "object"
    # the image node is shared by five inputs, and stays one node
    assert g.roughness is g.albedo.color1 is b.normal.color is m.mix.a
    np.testing.assert_array_equal(g.roughness.image, img)
    np.testing.assert_array_equal(g.roughness.mapping, np.diag([2.0, 1.0, 1.0, 1.0]))
    assert (g.roughness.interpolation, g.roughness.extension, g.roughness.name) == ("Closest", "CLIP", "grain")
    assert back.materials[1].layers[1].albedo.image == str(tmp_path / "x.png")
    np.testing.assert_array_equal(back.meshes[0].uvs, scene.meshes[0].uvs)
    np.testing.assert_array_equal(back.meshes[0].normals, scene.meshes[0].normals)
    # the scene renders the same from the file
    with pytest.warns(UserWarning, match="x.png"):  # a missing file: magenta in both
        a = Renderer(scene.validate(), Settings(method="light_array", jitter=False)).render_frame(0).albedo
    with pytest.warns(UserWarning, match="x.png"):
        c = Renderer(back.validate(), Settings(method="light_array", jitter=False)).render_frame(0).albedo
    np.testing.assert_array_equal(a, c)


def test_version_1_scene_files_still_load(tmp_path):
    import json

    meta = {"magic": "restircl-scene", "version": 1, "name": "old", "frame_count": None,
            "materials": [{"name": "w", "albedo": [0.5, 0.6, 0.7], "emission": [0.0, 0.0, 0.0],
                           "emission_strength": 0.0}], "meshes": [], "lights": [], "camera": None}
    np.savez_compressed(tmp_path / "old.npz", meta=np.frombuffer(json.dumps(meta).encode(), np.uint8))
    m = Scene.load(tmp_path / "old.npz").materials[0]
    assert m.albedo == (0.5, 0.6, 0.7) and m.kind == "principled" and m.specular == 0.0 and m.normal is None


def test_builtin_textured_room_renders_and_survives_the_scene_file(tmp_path):
    from restircl import scenes

    scene = scenes.builtin("textured_room", width=40, height=30)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        a = Renderer(scene, Settings(method="light_array", jitter=False)).render_frame(0)
    assert "textures" in a.features and np.all(np.isfinite(a.color))
    assert a.albedo[..., 0].std() > 0.05  # textured: not one flat colour per object
    scene.save(tmp_path / "room.npz")
    b = Renderer(Scene.load(tmp_path / "room.npz"), Settings(method="light_array", jitter=False)).render_frame(0)
    np.testing.assert_array_equal(a.color, b.color)


def test_uv_textures_on_a_mesh_without_uvs_warn():
    scene = facing_square(Material("m", albedo=ImageTexture(np.ones((2, 2)))))
    scene.meshes[0].uvs = None
    with pytest.warns(UserWarning, match="mesh 'square' has no UV map but material 0 'm' reads one"):
        Renderer(scene, Settings(method="light_array"))
    scene.materials[0] = Material("m", albedo=CheckerTexture(coords="generated"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        Renderer(scene, Settings(method="light_array"))


def test_an_emission_image_lights_by_its_texels_and_other_graphs_say_so():
    """What docs/textures.md states: as a light, each triangle of an emission image shines with the image's mean
    over its UV footprint (decoded, then averaged) times Emission Strength; another texture graph keeps the white
    bound (its records are those of a constant white emission) and the upload warns, naming the material."""
    from restircl.lights.device_lights import scene_lights
    from restircl.upload.textures import warn_textured_emission

    def square(emission):
        return facing_square(Material("glow", albedo=(0.0, 0.0, 0.0), emission=emission, emission_strength=3.0), 8)

    # one row, left texel sRGB 64, right 200: decoded 0.05127 and 0.57758 (IEC 61966-2-1)
    image = ImageTexture(np.array([[64, 200]], np.uint8), interpolation="Closest")
    textured, white = square(image), square((1.0, 1.0, 1.0))
    checker = square(CheckerTexture((1.0, 1.0, 1.0), (0.0, 0.0, 0.0)))
    recs = scene_lights(textured, 0).records.view(np.float32).reshape(-1, 16)[1:]  # the sun first
    uvs = textured.meshes[0].uvs
    # the triangle below the diagonal u = v has 3/4 of its area at u > 1/2, the other 1/4
    right = np.where(uvs[:, :, 0].sum(1) > uvs[:, :, 1].sum(1), 0.75, 0.25)
    want = 3.0 * (right * 0.57758044 + (1 - right) * 0.05126946)
    np.testing.assert_allclose(recs[:, 12], want, rtol=1e-5)
    np.testing.assert_array_equal(scene_lights(checker, 0).records, scene_lights(white, 0).records)
    with pytest.warns(UserWarning, match="material 0 'glow' has a textured emission"):
        warn_textured_emission(checker.meshes, checker.materials)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        warn_textured_emission(white.meshes, white.materials)
        warn_textured_emission(textured.meshes, textured.materials)
