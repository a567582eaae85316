"""Colour attributes (Mesh.attributes) read by the Attribute texture node (materials/textures.py Attribute,
upload/attributes.py, opencl/textures/nodes.h): the camera's albedo over a square whose four corners hold different
colours is their barycentric blend over each triangle, written out here; Alpha and Fac outputs are numbers; a mesh
without the attribute reads 0; the attribute survives the scene file."""

from __future__ import annotations

import numpy as np
import pytest
from restircl import Attribute, Material, MixColor, Scene

from ..texture_scenes import facing_square, pixel_uv
from .test_textures import render

# the square's corners (u, v) -> colour (rgba)
CORNER_RGBA = {(0, 0): (1.0, 0.0, 0.0, 0.2), (1, 0): (0.0, 1.0, 0.0, 0.4), (1, 1): (0.0, 0.0, 1.0, 0.6),
               (0, 1): (1.0, 1.0, 1.0, 1.0)}


def _scene(node, attributes: bool = True) -> Scene:
    scene = facing_square(Material("m", albedo=node), 16)
    mesh = scene.meshes[0]
    if attributes:
        cols = np.array([[CORNER_RGBA[(int(round(u)), int(round(v)))] for u, v in tri] for tri in mesh.uvs])
        mesh.attributes = {"Col": cols, "other": np.zeros_like(cols)}
    return scene


def _expected(rgba_of_point) -> np.ndarray:
    """Per pixel: the blend over the pixel centre's triangle of the square (the diagonal u = v splits it; the
    triangles are (0,0) (1,0) (1,1) and (0,0) (1,1) (0,1))."""
    u, v = pixel_uv(16)
    out = np.zeros((16, 16, 4))
    for y in range(16):
        for x in range(16):
            a, b = u[y, x], v[y, x]
            if a >= b:  # weights of (0,0), (1,0), (1,1)
                w = {(0, 0): 1 - a, (1, 0): a - b, (1, 1): b}
            else:
                w = {(0, 0): 1 - b, (0, 1): b - a, (1, 1): a}
            out[y, x] = sum(wk * np.array(CORNER_RGBA[k]) for k, wk in w.items())
    return rgba_of_point(out)


@pytest.mark.parametrize("output", ["color", "alpha", "fac"])
def test_attribute_is_the_corner_blend(device, output):
    want = _expected({"color": lambda c: c[..., :3],
                      "alpha": lambda c: np.repeat(c[..., 3:], 3, axis=-1),
                      "fac": lambda c: np.repeat(c[..., :3].mean(axis=-1, keepdims=True), 3, axis=-1)}[output])
    node = Attribute("Col", output)
    albedo = MixColor(a=(0.0, 0.0, 0.0), b=(1.0, 1.0, 1.0), factor=node) if output != "color" else node
    np.testing.assert_allclose(render(_scene(albedo)).albedo, want, atol=2e-5)


def test_a_mesh_without_the_attribute_reads_zero(device):
    np.testing.assert_allclose(render(_scene(Attribute("Col"), attributes=False)).albedo, 0.0)
    scene = _scene(Attribute("missing"))
    np.testing.assert_allclose(render(scene).albedo, 0.0)


def test_attributes_survive_the_scene_file(tmp_path):
    from restircl.scene.file import load_scene, save_scene

    scene = _scene(Attribute("Col", "alpha"))
    save_scene(scene, tmp_path / "s.npz")
    back = load_scene(tmp_path / "s.npz", Scene)
    assert list(back.meshes[0].attributes) == ["Col", "other"]
    np.testing.assert_array_equal(back.meshes[0].attributes["Col"], scene.meshes[0].attributes["Col"])
    node = back.materials[0].albedo
    assert isinstance(node, Attribute) and (node.name, node.output) == ("Col", "alpha")


def test_an_edit_that_names_another_attribute_uploads_its_colours(device):
    """An interactive edit of the materials alone (device_scene.edit) that reads another attribute sends that
    attribute's corner colours up with the geometry again."""
    from restircl import Renderer, Settings

    scene = _scene(Attribute("other"))
    scene.meshes[0].attributes["other"] = scene.meshes[0].attributes["Col"][..., ::-1].copy()
    r = Renderer(scene, Settings(method="light_array", jitter=False), interactive=True)
    first = r.render_frame(0).albedo
    np.testing.assert_allclose(first, _expected(lambda c: c[..., ::-1][..., :3]), atol=2e-5)  # (a, b, g)
    scene.materials[0].albedo = Attribute("Col")
    r.device_scene.edit(materials=True)
    np.testing.assert_allclose(r.render_frame(1).albedo, _expected(lambda c: c[..., :3]), atol=2e-5)
