"""An image-textured plane (UV map, sRGB image on the Base Color, Linear and Closest) against Cycles with direct
light only: relMSE below 1 % once both are converged. The texture is magnified (a texel covers several pixels),
where our mip level is 0 and Cycles' pixel average and ours sample the same bilinear (or nearest) image; where a
texture is minified our mips blur by design and Cycles' does not (docs/textures.md)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl import Camera, ImageTexture, Light, Material, Renderer, Scene, Settings, look_at  # noqa: E402
from restircl.eval import cycles  # noqa: E402

from .test_blender_support import needs_renderer, relmse  # noqa: E402
from .texture_scenes import SQUARE_UVS, square_mesh  # noqa: E402

pytestmark = [pytest.mark.blender, needs_renderer]

BOUND = 0.01
IMAGE = np.random.default_rng(12).integers(0, 256, (6, 8, 3), dtype=np.uint8)


def textured_scene(interpolation: str, png: Path, width: int = 64, height: int = 48) -> Scene:
    cam = Camera(look_at((0.3, -2.6, 2.2), (0, 0, 0), (0, 0, 1)), width, height)
    cam.set_fov(math.radians(45))
    lamp = Light("lamp", "point", (1, 1, 1), 150.0, look_at((0.6, -0.4, 1.6), (0, 0, 0)), radius=0.1)
    tex = ImageTexture(str(png), colorspace="sRGB", interpolation=interpolation)
    return Scene([square_mesh(1.0)], [Material("painted", albedo=tex)], [lamp], cam)


def to_cycles(scene: Scene, interpolation: str, png: Path):
    """The scene in bpy (the Cycles bridge writes constant materials: a grey one stands in for the texture, which
    is then linked to its Diffuse BSDF's Color here), with the UV map."""
    sc = cycles.to_bpy(Scene(scene.meshes, [Material("painted")], scene.lights, scene.camera))
    me = bpy.data.meshes["square"]
    uv = me.uv_layers.new(name="UVMap")
    uv.data.foreach_set("uv", SQUARE_UVS.reshape(-1).astype(np.float32))
    im = bpy.data.images.load(str(png))
    im.colorspace_settings.name = "sRGB"
    tree = bpy.data.materials["painted"].node_tree
    diffuse = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeBsdfDiffuse")
    node = tree.nodes.new("ShaderNodeTexImage")
    node.image, node.interpolation, node.extension = im, interpolation, "REPEAT"
    tree.links.new(node.outputs["Color"], diffuse.inputs["Color"])
    return sc


@pytest.mark.parametrize("interpolation", ["Linear", "Closest"])
def test_image_textured_plane_agrees_with_cycles(tmp_path, interpolation):
    from PIL import Image

    png = tmp_path / "painted.png"  # both read the same file from disk
    Image.fromarray(IMAGE, "RGB").save(png)
    scene = textured_scene(interpolation, png)
    ours = Renderer(scene, Settings(method="reference")).render_still(0, samples=64).color
    cyc = cycles.render(to_cycles(scene, interpolation, png), samples=256, seed=1, threads=2, workdir=tmp_path).image
    err = relmse(ours, cyc)
    print(f"{interpolation}: relMSE {100 * err:.3f} %, mean ours/cycles {ours[..., :3].mean() / cyc.mean():.4f}")
    assert cyc.mean() > 0.01, "the comparison scene is dark: nothing is tested"
    assert err < BOUND
