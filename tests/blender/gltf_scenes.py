"""A helmet-like glTF asset made here and imported through Blender's own glTF importer, so that its material has the
importer's node setup (what every glTF, Sketchfab or Substance export gives a Blender user): Base Color, Emissive and
Normal images linked directly, metallic and roughness from one packed occlusion-roughness-metallic (ORM) image
through Separate Color nodes, and a "glTF Material Output" group node that takes the occlusion.

The images are tiny numpy patterns; the asset goes through bpy's glTF exporter into a .glb in a temporary folder
and back through the importer (the io_scene_gltf2 add-on bpy ships), so no file is kept in the repository."""

from __future__ import annotations

import math
from pathlib import Path

import bpy
import numpy as np
import pytest
from restircl.eval import blender_scenes as scenes

SIZE = 16  # texels of each image side



def import_gltf(path) -> None:
    """Blender's own glTF importer on `path`; a test skips where that importer itself fails in this release
    (bpy 5.3.0's raises KeyError 'Iridescence Factor' on any material: its Principled BSDF has no such input)."""
    try:
        bpy.ops.import_scene.gltf(filepath=str(path))
    except RuntimeError as e:
        if "IMPORT_SCENE_OT_gltf" not in str(e) and "Traceback" not in str(e):
            raise
        last = [line for line in str(e).splitlines() if line.strip()][-1]
        pytest.skip(f"Blender {bpy.app.version_string}'s own glTF importer fails: {last}")

def orm_texels(size: int = SIZE) -> np.ndarray:
    """(size, size, 4) float32, rows bottom first (Blender's order): R occlusion, G roughness rising with u
    (0.15 .. 0.9), B metallic in two bands along v (0 below, 1 above, a ramp between)."""
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size
    px = np.ones((size, size, 4), np.float32)
    px[..., 0] = 0.6 + 0.4 * x
    px[..., 1] = 0.15 + 0.75 * x
    px[..., 2] = np.clip((y - 0.35) * 4.0, 0.0, 1.0)
    return px


def base_texels(size: int = SIZE) -> np.ndarray:
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size
    px = np.ones((size, size, 4), np.float32)
    px[..., 0] = 0.55 + 0.35 * np.sin(2 * math.pi * x)
    px[..., 1] = 0.45 + 0.2 * np.cos(2 * math.pi * y)
    px[..., 2] = 0.3 + 0.2 * x * y
    return px


def emissive_texels(size: int = SIZE) -> np.ndarray:
    """A dim glowing band (the visor): small, so that the light it sheds hardly matters."""
    y, _x = (np.mgrid[0:size, 0:size] + 0.5) / size
    px = np.zeros((size, size, 4), np.float32)
    px[..., 3] = 1.0
    band = (np.abs(y - 0.5) < 0.1)
    px[band, 0], px[band, 1], px[band, 2] = 0.05, 0.03, 0.01
    return px


def normal_texels(size: int = SIZE) -> np.ndarray:
    """Gentle bumps along u (slopes under 10 degrees), tangent space, [0, 1] encoded."""
    _y, x = (np.mgrid[0:size, 0:size] + 0.5) / size
    s = 0.15 * np.sin(2 * math.pi * 3 * x)
    n = np.stack([-s, np.zeros_like(s), np.ones_like(s)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    px = np.ones((size, size, 4), np.float32)
    px[..., :3] = 0.5 * n + 0.5
    return px


def _image(name: str, px: np.ndarray, non_color: bool):
    h, w = px.shape[:2]
    img = bpy.data.images.new(name, w, h, alpha=True)
    img.pixels.foreach_set(px.reshape(-1))
    img.pack()
    if non_color:
        img.colorspace_settings.name = "Non-Color"
    return img


def _source_material(name: str):
    """The material as an artist sets it up for the glTF exporter (images, Separate Color, occlusion group)."""
    mat = bpy.data.materials.new(name)
    if mat.node_tree is None:  # Blender before 5.0 makes a new material without a node tree
        mat.use_nodes = True
    tree = mat.node_tree
    p = tree.nodes["Principled BSDF"]

    def tex(img):
        node = tree.nodes.new("ShaderNodeTexImage")
        node.image = img
        return node

    tree.links.new(tex(_image(f"{name}_base", base_texels(), False)).outputs["Color"], p.inputs["Base Color"])
    tree.links.new(tex(_image(f"{name}_emit", emissive_texels(), False)).outputs["Color"], p.inputs["Emission Color"])
    p.inputs["Emission Strength"].default_value = 1.0
    sep = tree.nodes.new("ShaderNodeSeparateColor")
    tree.links.new(tex(_image(f"{name}_orm", orm_texels(), True)).outputs["Color"], sep.inputs["Color"])
    tree.links.new(sep.outputs["Green"], p.inputs["Roughness"])
    tree.links.new(sep.outputs["Blue"], p.inputs["Metallic"])
    nm = tree.nodes.new("ShaderNodeNormalMap")
    tree.links.new(tex(_image(f"{name}_normal", normal_texels(), True)).outputs["Color"], nm.inputs["Color"])
    tree.links.new(nm.outputs["Normal"], p.inputs["Normal"])
    group = bpy.data.node_groups.get("glTF Material Output") or bpy.data.node_groups.new("glTF Material Output",
                                                                                          "ShaderNodeTree")
    if not group.interface.items_tree:
        group.interface.new_socket("Occlusion", in_out="INPUT", socket_type="NodeSocketFloat")
        group.nodes.new("NodeGroupInput")
    gn = tree.nodes.new("ShaderNodeGroup")
    gn.node_tree = group
    tree.links.new(sep.outputs["Red"], gn.inputs["Occlusion"])
    return mat


def import_helmet(folder: Path, name: str = "Helmet", radius: float = 0.6, location=(0.0, 0.0, 0.6)):
    """A UV sphere with the helmet material, exported to folder/<name>.glb and imported back into the current
    scene; the imported object (the source object is removed)."""
    bpy.ops.preferences.addon_enable(module="io_scene_gltf2")
    mat = _source_material(f"{name}Source")
    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=radius, location=location)
    src = bpy.context.object  # Blender's primitive: its UV map covers [0, 1]^2
    src.data.materials.append(mat)
    for f in src.data.polygons:
        f.use_smooth = True
    for ob in bpy.context.view_layer.objects:
        ob.select_set(ob == src)
    path = folder / f"{name}.glb"
    bpy.ops.export_scene.gltf(filepath=str(path), use_selection=True, export_format="GLB")
    bpy.data.objects.remove(src)
    bpy.data.materials.remove(mat)
    before = set(bpy.data.objects)
    import_gltf(path)
    new = [ob for ob in bpy.data.objects if ob not in before and ob.type == "MESH"]
    assert len(new) == 1, new
    new[0].name = name
    return new[0]


def _stage(sc, floor: float, key: tuple, spot: tuple, points: list[tuple]) -> None:
    """A grey floor of side `floor`, an area light key = (location, energy, size), a spot = (location, energy) and
    point lights (location, energy, colour, radius), all hidden from the camera."""
    scenes.quad("Floor", floor, material=scenes.diffuse_material("FloorGrey", (0.5, 0.5, 0.5)))
    scenes.light("AREA", "Key", key[0], (math.radians(35), 0, math.radians(-40)), energy=key[1], size=key[2])
    scenes.light("SPOT", "Spot", spot[0], (math.radians(45), 0, math.radians(45)), energy=spot[1],
                 spot_size=math.radians(60), shadow_soft_size=0.2)
    for k, (location, energy, colour, radius) in enumerate(points):
        scenes.light("POINT", f"P{k}", location, energy=energy, shadow_soft_size=radius, color=colour)
    for ob in sc.objects:
        if ob.type == "LIGHT":
            ob.visible_camera = False


def helmet_scene(folder: Path, width: int, height: int):
    """The issue's scene at small size: the helmet on a grey floor under an area light, a spot and a few points."""
    sc = scenes.new_scene(width, height)
    import_helmet(folder)
    ring = [((1.6 * math.cos(a), 1.6 * math.sin(a), 1.4), 20.0, (1.0, 0.85, 0.7), 0.1)
            for a in (2 * math.pi * k / 4 for k in range(4))]
    _stage(sc, 6.0, ((-1.5, -1.5, 3.0), 300.0, 1.0), ((2.0, -2.0, 2.5), 400.0), ring)
    scenes.camera((0, -3.6, 2.2), (0, 0, 0.5), lens=40.0)
    return sc


def import_real_helmet(path: Path):
    """Khronos' DamagedHelmet (restircl.eval.assets) through Blender's glTF importer, standing on z = 0."""
    bpy.ops.preferences.addon_enable(module="io_scene_gltf2")
    before = set(bpy.data.objects)
    import_gltf(path)
    ob = next(o for o in bpy.data.objects if o not in before and o.type == "MESH")
    bpy.context.view_layer.update()
    zmin = min((ob.matrix_world @ v.co).z for v in ob.data.vertices)
    root = ob
    while root.parent is not None:
        root = root.parent
    root.location.z -= zmin
    return ob


def real_helmet_scene(path: Path, width: int, height: int):
    """The issue's scene: the real helmet on a grey floor under an area light, a spot and 30 small point lights
    (two rings of warm ones around it, at three heights)."""
    sc = scenes.new_scene(width, height)
    import_real_helmet(path)
    helmet_stage(sc)
    return sc


def helmet_stage(sc) -> None:
    """The real helmet's stage (of an object about 2 units across standing at the origin): a floor, an area light,
    a spot, 30 small point lights in two rings at three heights, and the camera."""
    ring = []
    for k in range(30):
        r, a = 2.2 + 0.4 * (k % 2), 2 * math.pi * k / 30
        ring.append(((r * math.cos(a), r * math.sin(a), 0.6 + 0.25 * (k % 3)), 8.0,
                     (1.0, 0.8 - 0.01 * k, 0.6 + 0.01 * k), 0.05))
    _stage(sc, 8.0, ((-2.0, -2.5, 4.0), 600.0, 1.5), ((2.5, -2.5, 3.0), 500.0), ring)
    scenes.camera((0.6, -4.5, 2.3), (0, 0, 0.9), lens=45.0)
