"""Textured planes against Cycles with direct light only: an 8-bit sRGB image on the Base Color (Linear and
Closest, read from the same PNG), a checker on Generated coordinates, and a tangent-space normal map from a
Non-Color image; relMSE below 1 % once both are converged. The images are magnified (a texel covers several
pixels), where our mip level is 0 and Cycles' pixel average and ours sample the same filtered image; where a
texture is minified our mips blur by design and Cycles does not (docs/textures.md).

Measured when written (64x48, ours 64 samples, Cycles 256): relMSE 0.004 % (Linear), 0.014 % (Closest), 0.014 %
(checker), 0.096 % (normal map). What the bound tells apart: the same plane without its normal map is 3.5 % from
Cycles' normal-mapped one, the checker with its colours swapped 277 %."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

bpy = pytest.importorskip("bpy")

from restircl import (  # noqa: E402
    Camera,
    CheckerTexture,
    ImageTexture,
    Light,
    Material,
    NormalMap,
    Renderer,
    Scene,
    Settings,
    look_at,
)
from restircl.eval.cycles import bridge as cycles  # noqa: E402

from ..texture_scenes import SQUARE_UVS, square_mesh  # noqa: E402
from .test_blender_support import needs_renderer, relmse  # noqa: E402

pytestmark = [pytest.mark.blender, needs_renderer]

BOUND = 0.01
IMAGE = np.random.default_rng(12).integers(0, 256, (6, 8, 3), dtype=np.uint8)
CHECKER = ((0.8, 0.3, 0.1), (0.1, 0.4, 0.7))


# the normal-map cases: (steepest slope of the bumps, Principled BSDF with a specular layer or Diffuse BSDF)
NORMAL_MAPS = {"normal_map": (31.0, False), "normal_map_48": (48.0, False), "normal_map_48_glossy": (48.0, True)}


def normal_map_image(n: int = 16, slope: float = 31.0) -> np.ndarray:
    """A smooth bumpy height field's tangent-space normals, encoded n * 0.5 + 0.5 in 8 bits; its steepest slope
    (along u or v) is `slope` degrees."""
    y, x = np.mgrid[0:n, 0:n] * (2 * np.pi / n)
    a = math.tan(math.radians(slope))
    dx, dy = a * np.cos(x) * np.cos(y), -a * np.sin(x) * np.sin(y)
    nrm = np.stack([-dx, -dy, np.ones_like(dx)], -1)
    nrm /= np.linalg.norm(nrm, axis=-1, keepdims=True)
    return np.round((nrm * 0.5 + 0.5) * 255).astype(np.uint8)


def our_material(case: str, png: Path) -> Material:
    if case in ("Linear", "Closest"):
        return Material("painted", albedo=ImageTexture(str(png), colorspace="sRGB", interpolation=case))
    if case == "checker":
        return Material("painted", albedo=CheckerTexture(*CHECKER, scale=5.0, coords="generated"))
    glossy = NORMAL_MAPS[case][1]
    return Material("painted", albedo=(0.7, 0.7, 0.7), roughness=0.3, specular=0.5 if glossy else 0.0,
                    normal=NormalMap(ImageTexture(str(png), colorspace="Non-Color"), strength=1.0))


def cycles_material(case: str, png: Path) -> None:
    """Link the case's nodes into the Diffuse BSDF that the Cycles bridge wrote for the grey stand-in."""
    tree = bpy.data.materials["painted"].node_tree
    diffuse = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeBsdfDiffuse")
    if case == "checker":
        coords = tree.nodes.new("ShaderNodeTexCoord")
        node = tree.nodes.new("ShaderNodeTexChecker")
        node.inputs["Color1"].default_value = (*CHECKER[0], 1.0)
        node.inputs["Color2"].default_value = (*CHECKER[1], 1.0)
        node.inputs["Scale"].default_value = 5.0
        tree.links.new(coords.outputs["Generated"], node.inputs["Vector"])
        tree.links.new(node.outputs["Color"], diffuse.inputs["Color"])
        return
    im = bpy.data.images.load(str(png))
    im.colorspace_settings.name = "sRGB" if case in ("Linear", "Closest") else "Non-Color"
    node = tree.nodes.new("ShaderNodeTexImage")
    node.image, node.interpolation, node.extension = im, "Closest" if case == "Closest" else "Linear", "REPEAT"
    if case in NORMAL_MAPS:
        diffuse.inputs["Color"].default_value = (0.7, 0.7, 0.7, 1.0)
        if NORMAL_MAPS[case][1]:  # a Principled BSDF at Blender's defaults, but for these two inputs
            diffuse = tree.nodes.new("ShaderNodeBsdfPrincipled")
            diffuse.inputs["Base Color"].default_value = (0.7, 0.7, 0.7, 1.0)
            diffuse.inputs["Roughness"].default_value = 0.3
            out = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
            tree.links.new(diffuse.outputs[0], out.inputs["Surface"])
        nm = tree.nodes.new("ShaderNodeNormalMap")
        nm.space, nm.uv_map = "TANGENT", "UVMap"
        nm.inputs["Strength"].default_value = 1.0
        tree.links.new(node.outputs["Color"], nm.inputs["Color"])
        tree.links.new(nm.outputs["Normal"], diffuse.inputs["Normal"])
    else:
        tree.links.new(node.outputs["Color"], diffuse.inputs["Color"])


def textured_scene(material: Material, width: int = 64, height: int = 48) -> Scene:
    cam = Camera(look_at((0.3, -2.6, 2.2), (0, 0, 0), (0, 0, 1)), width, height)
    cam.set_fov(math.radians(45))
    lamp = Light("lamp", "point", (1, 1, 1), 150.0, look_at((0.6, -0.4, 1.6), (0, 0, 0)), radius=0.1)
    return Scene([square_mesh(1.0)], [material], [lamp], cam)


def to_cycles(scene: Scene, case: str, png: Path):
    """The scene in bpy (the Cycles bridge writes constant materials: a grey one stands in, and the case's nodes
    are linked into it here), with the UV map."""
    sc = cycles.to_bpy(Scene(scene.meshes, [Material("painted")], scene.lights, scene.camera))
    uv = bpy.data.meshes["square"].uv_layers.new(name="UVMap")
    uv.data.foreach_set("uv", SQUARE_UVS.reshape(-1).astype(np.float32))
    cycles_material(case, png)
    return sc


@pytest.mark.parametrize("case", ["Linear", "Closest", "checker", *NORMAL_MAPS])
def test_textured_plane_agrees_with_cycles(tmp_path, case):
    from PIL import Image

    png = tmp_path / "texture.png"  # both renderers read the same file
    Image.fromarray(normal_map_image(slope=NORMAL_MAPS[case][0]) if case in NORMAL_MAPS else IMAGE, "RGB").save(png)
    scene = textured_scene(our_material(case, png))
    ours = Renderer(scene, Settings(method="reference")).render_still(0, samples=64).color
    cyc = cycles.render(to_cycles(scene, case, png), samples=256, seed=1, threads=2, workdir=tmp_path).image
    err = relmse(ours, cyc)
    print(f"{case}: relMSE {100 * err:.3f} %, mean ours/cycles {ours[..., :3].mean() / cyc.mean():.4f}")
    assert cyc.mean() > 0.01, "the comparison scene is dark: nothing is tested"
    assert err < BOUND
