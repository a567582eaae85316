"""A validation scene of a typical user's F12 (`restircl compare --kinds user`): built in Blender as a user builds
one (primitives from bpy's operators, with their UVs and smooth shading; Principled BSDFs; packed images; an HDRI
world) and exported by the add-on's exporter, as F12 exports it, so the Cycles side renders the very bpy scene and
ours what the add-on makes of it. Built once and never tuned on: a figure measured here is one the rules of the
still estimator, the light tree and the sampling modes were not fitted to.

    user  a terrace under an HDRI sky with a sun disk (the world lights, and is seen), an image-textured floor
          (Principled, roughness 0.45), a back wall with a checker texture, a gold sphere (metallic, roughness
          0.25), a glossy blue sphere (roughness 0.15), a brushed-steel cylinder (metallic 0.35), a box whose
          roughness is an image, and 43 lights of every Blender type: a sun, four area lights (square, rectangle,
          disk, ellipse), 10 spots and 28 point lights (radius 0 to 5 cm, 0.5 to 200 W)

Needs bpy (imported when a scene is built); `user_scene` returns the exported restircl Scene and the bpy scene.
"""

from __future__ import annotations

import math

import numpy as np

from ...scene.scene import Scene

KINDS = ("user",)
#: the HDRI's sun, towards it: about 30 degrees up, to the left of the camera
SUN = (-0.6, 0.5, 0.55)
#: the HDRI's strength: the world is bright enough to matter beside the lights, not to drown them
WORLD_STRENGTH = 0.35


def _image(bpy, name: str, size: int, pixels: np.ndarray, non_color: bool = False):
    """A packed image of `pixels` ((size, size, 3) rows bottom first, as Blender stores them)."""
    img = bpy.data.images.new(name, size, size, alpha=True)
    px = np.ones((size, size, 4), np.float32)
    px[..., :3] = pixels
    img.pixels.foreach_set(px.reshape(-1))
    img.pack()
    if non_color:
        img.colorspace_settings.name = "Non-Color"
    return img


def _planks(size: int = 128) -> np.ndarray:
    """Wood-like planks: bands of warm browns with a grain along them and dark joints."""
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size
    band = np.floor(y * 6)
    shade = 0.75 + 0.25 * np.sin(band * 2.7) ** 2
    grain = 0.85 + 0.15 * np.sin(2 * math.pi * (x * 3 + 0.3 * np.sin(2 * math.pi * y * 11 + band)))
    joint = np.where(np.abs(y * 6 - np.round(y * 6)) < 0.04, 0.35, 1.0)
    base = np.array([0.55, 0.33, 0.17])
    return (base * (shade * grain * joint)[..., None]).astype(np.float32)


def _roughness_map(size: int = 64) -> np.ndarray:
    """Rough and polished rings, 0.1 to 0.7 (Non-Color)."""
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size
    r = 0.4 + 0.3 * np.sin(2 * math.pi * 4 * np.hypot(x - 0.5, y - 0.5))
    return np.repeat(r[..., None], 3, axis=2).astype(np.float32)


def _textured(tree, img, socket) -> None:
    tex = tree.nodes.new("ShaderNodeTexImage")
    tex.image = img
    tree.links.new(tex.outputs["Color"], socket)


def _objects(bpy) -> None:
    from ..blender_scenes import primitive, principled_nodes

    mesh = bpy.ops.mesh
    floor, tree, p = principled_nodes("Floor", Roughness=0.45)
    _textured(tree, _image(bpy, "Planks", 128, _planks()), p.inputs["Base Color"])
    primitive(mesh.primitive_plane_add, "Floor", floor, size=14.0)
    wall, tree, p = principled_nodes("Wall", Roughness=0.8)
    chk = tree.nodes.new("ShaderNodeTexChecker")
    chk.inputs["Color1"].default_value = (0.75, 0.72, 0.66, 1.0)
    chk.inputs["Color2"].default_value = (0.35, 0.42, 0.5, 1.0)
    chk.inputs["Scale"].default_value = 6.0
    tree.links.new(chk.outputs["Color"], p.inputs["Base Color"])
    primitive(mesh.primitive_cube_add, "Wall", wall, size=1.0, location=(0.0, 2.6, 1.5), scale=(7.0, 0.2, 3.0))
    gold = principled_nodes("Gold", **{"Base Color": (1.0, 0.76, 0.34, 1.0), "Metallic": 1.0, "Roughness": 0.25})[0]
    primitive(mesh.primitive_uv_sphere_add, "GoldSphere", gold, smooth=True, segments=48, ring_count=24,
              radius=0.6, location=(-1.3, 0.4, 0.6))
    blue = principled_nodes("BlueGloss", **{"Base Color": (0.08, 0.2, 0.65, 1.0), "Roughness": 0.15})[0]
    primitive(mesh.primitive_uv_sphere_add, "BlueSphere", blue, smooth=True, segments=48, ring_count=24,
              radius=0.45, location=(0.35, -0.5, 0.45))
    steel = principled_nodes("Steel", **{"Base Color": (0.6, 0.6, 0.62, 1.0), "Metallic": 1.0, "Roughness": 0.35})[0]
    primitive(mesh.primitive_cylinder_add, "Column", steel, smooth=True, vertices=48, radius=0.3, depth=1.6,
              location=(1.6, 0.9, 0.8))
    box, tree, p = principled_nodes("Lacquer", **{"Base Color": (0.7, 0.12, 0.08, 1.0)})
    _textured(tree, _image(bpy, "Rings", 64, _roughness_map(), non_color=True), p.inputs["Roughness"])
    primitive(mesh.primitive_cube_add, "Box", box, size=0.7, location=(-0.2, 1.3, 0.35), rotation=(0, 0, 0.5))


def _world(bpy, sc) -> None:
    from ...scenes.hdri_sky import sky_map

    texels = sky_map(128, 256, sun=np.array(SUN))
    h, w = texels.shape[:2]
    img = bpy.data.images.new("UserSky", w, h, alpha=True, float_buffer=True)
    img.colorspace_settings.name = "Linear Rec.709"
    rgba = np.concatenate([texels, np.ones((h, w, 1), np.float32)], axis=2)[::-1]  # Blender: bottom row first
    img.pixels.foreach_set(np.ascontiguousarray(rgba, np.float32).reshape(-1))
    img.pack()
    tree = sc.world.node_tree
    bg = tree.nodes.get("Background")
    bg.inputs["Strength"].default_value = WORLD_STRENGTH
    tex = tree.nodes.new("ShaderNodeTexEnvironment")
    tex.image = img
    tree.links.new(tex.outputs["Color"], bg.inputs["Color"])


def _lights() -> None:
    from ..blender_scenes import light

    rng = np.random.default_rng(43)
    light("SUN", "Sun", (0, 0, 10), (math.radians(40), 0, math.radians(30)), energy=2.0, angle=math.radians(2.0),
          color=(1.0, 0.93, 0.85))
    for name, loc, rot, props in (
            ("AreaSquare", (-3.0, -2.0, 2.6), (math.radians(50), 0, math.radians(-55)), {"shape": "SQUARE",
                                                                                         "size": 1.0}),
            ("AreaRect", (0.5, -0.5, 3.2), (0, 0, 0), {"shape": "RECTANGLE", "size": 2.0, "size_y": 0.5}),
            ("AreaDisk", (3.2, -1.8, 2.0), (math.radians(60), 0, math.radians(55)), {"shape": "DISK", "size": 0.8}),
            ("AreaEllipse", (-2.5, 2.0, 2.8), (math.radians(-35), 0, 0), {"shape": "ELLIPSE", "size": 1.2,
                                                                           "size_y": 0.6})):
        light("AREA", name, loc, rot, energy=float(rng.uniform(80, 250)), **props)
    for k in range(10):
        x = -4.5 + k
        light("SPOT", f"Spot{k}", (x, 2.2, 2.9), (math.radians(-25), 0, 0), energy=float(rng.uniform(40, 300)),
              spot_size=math.radians(float(rng.uniform(35, 70))), spot_blend=float(rng.uniform(0.1, 0.6)),
              shadow_soft_size=0.05, color=tuple(rng.uniform(0.7, 1.0, 3)))
    for k in range(28):
        pos = (float(rng.uniform(-5, 5)), float(rng.uniform(-3, 2.3)), float(rng.uniform(0.15, 2.5)))
        light("POINT", f"Point{k}", pos, energy=float(math.exp(rng.uniform(math.log(0.5), math.log(200.0)))),
              shadow_soft_size=float(rng.choice([0.0, 0.02, 0.05])), color=tuple(rng.uniform(0.5, 1.0, 3)))


def user_scene(width: int, height: int) -> tuple[Scene, object]:
    """(restircl Scene as the add-on exports it, the bpy scene) of the module's docstring at width x height."""
    import bpy

    from ...io.blend import addon_module
    from ..blender_scenes import camera, new_scene

    sc = new_scene(width, height)
    _objects(bpy)
    _world(bpy, sc)
    _lights()
    camera((0.6, -6.2, 2.1), (0.0, 0.6, 0.7), lens=30.0)
    bpy.context.view_layer.update()
    exp = addon_module().export.export_scene(bpy.context.evaluated_depsgraph_get())
    if exp.warnings:
        raise RuntimeError(f"the user scene exports with warnings: {list(exp.warnings)}")
    scene = exp.scene
    scene.name = "user"
    return scene.validate(), sc
