"""Blender scenes built with bpy: small helpers (the Blender tests and probes build their scenes with them), the
scene the Cycles agreement tests use, the example scenes, and the icon preview of a material.

    python -m restircl.eval.blender_scenes [outdir]   # writes many_lights.blend and area_interior.blend (blend/)

Needs the bpy module (Blender 4.2 to 5.3: pip install -e '.[blender]'). The helpers build everything from data (no
operators that need a window), so they work headless. Part of the evaluation tools: the library core never
imports it (tests/eval/test_eval_imports.py), and it goes into the extension's wheel with the rest of restircl.
"""

from __future__ import annotations

import colorsys
import math
import sys
import time
from pathlib import Path

import bpy
import numpy as np

from ..io.blend import addon_module
from .cycles.bridge import black_world, direct_only, node_material

# ---- scene and render settings ------------------------------------------------------------------------


def new_scene(width: int = 64, height: int = 48, engine: str = "CYCLES", reset: bool = True) -> bpy.types.Scene:
    """Empty factory scene with a black world, the given resolution and engine. reset=False keeps the data and
    preferences there are (factory settings would disable an installed extension)."""
    if reset:
        bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.render.resolution_x, sc.render.resolution_y = width, height
    sc.render.resolution_percentage = 100
    black_world(bpy, sc)  # shared with the scenes `restircl report` writes for Cycles
    sc.render.engine = engine
    return sc


def cycles_direct_only(sc: bpy.types.Scene, samples: int = 1024, seed: int = 0, threads: int = 0) -> None:
    """Cycles as the reference for direct light: no bounces, box filter 1 px, light threshold 0, no adaptive
    sampling, no denoising, no clamping (one definition of these settings, shared with `restircl report`)."""
    direct_only(sc, samples, seed, threads)


def exr_output(sc: bpy.types.Scene, path: str, multilayer: bool = True) -> None:
    im = sc.render.image_settings
    if hasattr(im, "media_type"):  # Blender 5: multilayer is a media type
        im.media_type = "MULTI_LAYER_IMAGE" if multilayer else "IMAGE"
        if not multilayer:
            im.file_format = "OPEN_EXR"
    else:
        im.file_format = "OPEN_EXR_MULTILAYER" if multilayer else "OPEN_EXR"
    im.color_depth = "32"
    im.exr_codec = "ZIP"
    sc.render.filepath = path


# ---- materials ----------------------------------------------------------------------------------------


def _material(name: str) -> tuple[bpy.types.Material, bpy.types.NodeTree, bpy.types.Node]:
    return node_material(bpy, name)  # shared with the scenes `restircl report` writes for Cycles


def diffuse_material(name: str, colour=(0.8, 0.8, 0.8)) -> bpy.types.Material:
    mat, tree, out = _material(name)
    d = tree.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (*colour, 1.0)
    d.inputs["Roughness"].default_value = 0.0
    tree.links.new(d.outputs[0], out.inputs["Surface"])
    mat.diffuse_color = (*colour, 1.0)
    return mat


def emission_material(name: str, colour=(1.0, 1.0, 1.0), strength: float = 1.0) -> bpy.types.Material:
    mat, tree, out = _material(name)
    e = tree.nodes.new("ShaderNodeEmission")
    e.inputs["Color"].default_value = (*colour, 1.0)
    e.inputs["Strength"].default_value = strength
    tree.links.new(e.outputs[0], out.inputs["Surface"])
    return mat


def principled_material(name: str, base=(0.8, 0.8, 0.8), emission=(0.0, 0.0, 0.0),
                        emission_strength: float = 0.0) -> bpy.types.Material:
    mat, tree, out = _material(name)
    p = tree.nodes.new("ShaderNodeBsdfPrincipled")
    p.inputs["Base Color"].default_value = (*base, 1.0)
    p.inputs["Emission Color"].default_value = (*emission, 1.0)
    p.inputs["Emission Strength"].default_value = emission_strength
    tree.links.new(p.outputs[0], out.inputs["Surface"])
    return mat


def principled_nodes(name: str, **inputs) -> tuple[bpy.types.Material, bpy.types.NodeTree, bpy.types.Node]:
    """A material of one Principled BSDF with these inputs (socket name: value): (material, tree, the BSDF node),
    for linking textures into its sockets."""
    mat, tree, out = _material(name)
    p = tree.nodes.new("ShaderNodeBsdfPrincipled")
    for k, v in inputs.items():
        p.inputs[k].default_value = v
    tree.links.new(p.outputs[0], out.inputs["Surface"])
    return mat, tree, p


# ---- objects ------------------------------------------------------------------------------------------


def primitive(op, name: str, mat, smooth: bool = False, **kw) -> bpy.types.Object:
    """An object made by one of bpy.ops.mesh's primitive operators, as a user adds one (with its UVs), named, with
    material `mat` and, with smooth, smooth shading."""
    op(**kw)
    ob = bpy.context.object
    ob.name = name
    ob.data.materials.append(mat)
    if smooth:
        for f in ob.data.polygons:
            f.use_smooth = True
    return ob


def link(ob: bpy.types.Object, collection: bpy.types.Collection | None = None) -> bpy.types.Object:
    (collection or bpy.context.scene.collection).objects.link(ob)
    return ob


def mesh_object(name: str, verts, faces, material=None, location=(0, 0, 0), rotation=(0, 0, 0),
                scale=(1, 1, 1), collection=None) -> bpy.types.Object:
    me = bpy.data.meshes.new(name)
    me.from_pydata([tuple(v) for v in verts], [], [tuple(f) for f in faces])
    me.update()
    if material is not None:
        me.materials.append(material)
    ob = bpy.data.objects.new(name, me)
    ob.location, ob.rotation_euler, ob.scale = location, rotation, scale
    return link(ob, collection)


def quad(name: str, size_x: float, size_y: float | None = None, material=None, location=(0, 0, 0),
         rotation=(0, 0, 0), facing_down: bool = False, collection=None) -> bpy.types.Object:
    """A rectangle in the local XY plane, normal +Z (or -Z with facing_down)."""
    sx, sy = size_x / 2, (size_y if size_y is not None else size_x) / 2
    face = (3, 2, 1, 0) if facing_down else (0, 1, 2, 3)
    return mesh_object(name, [(-sx, -sy, 0), (sx, -sy, 0), (sx, sy, 0), (-sx, sy, 0)], [face], material,
                       location, rotation, collection=collection)


def box(name: str, size=(1, 1, 1), material=None, location=(0, 0, 0), rotation=(0, 0, 0), inward=False,
        collection=None) -> bpy.types.Object:
    x, y, z = (s / 2 for s in size)
    verts = [(-x, -y, -z), (x, -y, -z), (x, y, -z), (-x, y, -z), (-x, -y, z), (x, -y, z), (x, y, z), (-x, y, z)]
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    if inward:
        faces = [tuple(reversed(f)) for f in faces]
    return mesh_object(name, verts, faces, material, location, rotation, collection=collection)


def uv_sphere(name: str, radius: float = 1.0, segments: int = 16, rings: int = 8, material=None,
              location=(0, 0, 0), collection=None) -> bpy.types.Object:
    verts = [(0.0, 0.0, radius)]
    for i in range(1, rings):
        th = math.pi * i / rings
        for j in range(segments):
            ph = 2 * math.pi * j / segments
            verts.append((radius * math.sin(th) * math.cos(ph), radius * math.sin(th) * math.sin(ph),
                          radius * math.cos(th)))
    verts.append((0.0, 0.0, -radius))
    faces = []
    for j in range(segments):
        faces.append((0, 1 + j, 1 + (j + 1) % segments))
    for i in range(rings - 2):
        a, b = 1 + i * segments, 1 + (i + 1) * segments
        for j in range(segments):
            k = (j + 1) % segments
            faces.append((a + j, b + j, b + k, a + k))
    last = len(verts) - 1
    a = 1 + (rings - 2) * segments
    for j in range(segments):
        faces.append((a + j, last, a + (j + 1) % segments))
    return mesh_object(name, verts, faces, material, location, collection=collection)


def light(kind: str, name: str | None = None, location=(0, 0, 0), rotation=(0, 0, 0), **props) -> bpy.types.Object:
    """A light object; props are Light datablock attributes (energy, color, shadow_soft_size, size, ...)."""
    ld = bpy.data.lights.new(name or kind.title(), kind)
    for k, v in props.items():
        setattr(ld, k, v)
    ob = bpy.data.objects.new(name or kind.title(), ld)
    ob.location, ob.rotation_euler = location, rotation
    return link(ob)


def camera(location=(0, 0, 5), target=(0, 0, 0), lens: float = 35.0, name: str = "Camera",
           make_active: bool = True, **props) -> bpy.types.Object:
    cd = bpy.data.cameras.new(name)
    cd.lens = lens
    cd.clip_start = 0.01
    cd.clip_end = 1000.0
    for k, v in props.items():
        setattr(cd, k, v)
    ob = bpy.data.objects.new(name, cd)
    ob.location = location
    point_at(ob, target)
    link(ob)
    if make_active:
        bpy.context.scene.camera = ob
    return ob


def point_at(ob: bpy.types.Object, target) -> None:
    from mathutils import Vector

    direction = Vector(target) - Vector(ob.location)
    ob.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()


# ---- the scene the Cycles agreement tests use ----------------------------------------------------------


LIGHT_KINDS = ("point", "sphere", "sphere_soft", "spot", "sun", "area_square", "area_rectangle", "area_disk",
               "area_ellipse", "emission")


def comparison_scene(kind: str, width: int = 64, height: int = 48, reset: bool = True):
    """A floor, a wall and a box (for shadows) lit by one kind of light, or every kind for 'mixed'.
    Light objects are hidden from camera rays (restircl does not draw lights; emissive meshes it does)."""
    sc = new_scene(width, height, reset=reset)
    quad("Floor", 12.0, 12.0, diffuse_material("Floor", (0.8, 0.8, 0.8)))
    quad("Wall", 12.0, 4.0, diffuse_material("Wall", (0.6, 0.7, 0.5)), location=(0, 3, 2),
         rotation=(math.pi / 2, 0, 0), facing_down=True)
    box("Box", (0.8, 0.8, 0.8), diffuse_material("BoxMat", (0.7, 0.3, 0.2)), location=(0.3, 0.2, 0.4),
        rotation=(0, 0, 0.5))
    camera((0, -5.5, 3.5), (0, 0.5, 0.3), lens=30.0)
    mixed = kind == "mixed"

    def add(*args, **kwargs):
        ob = light(*args, **kwargs)
        ob.visible_camera = False
        return ob

    if kind == "point" or mixed:
        add("POINT", "Point", (-1.2, -0.5, 1.5), energy=80.0, shadow_soft_size=0.0, color=(1.0, 0.9, 0.8))
    if kind in ("sphere", "sphere_soft"):
        add("POINT", "Sphere", (-1.0, -0.3, 1.2), energy=80.0, shadow_soft_size=0.3,
            use_soft_falloff=kind == "sphere_soft")
    if kind == "spot" or mixed:
        add("SPOT", "Spot", (1.5, -1.0, 2.5), (math.radians(20), math.radians(15), 0), energy=200.0,
            spot_size=math.radians(60), spot_blend=0.4, shadow_soft_size=0.0, color=(0.7, 0.8, 1.0))
    if kind == "sun" or mixed:
        add("SUN", "Sun", (0, 0, 5), (math.radians(30), math.radians(-20), 0), energy=1.5, angle=math.radians(5))
    for shape, sx, sy in (("SQUARE", 1.0, 1.0), ("RECTANGLE", 1.5, 0.5), ("DISK", 1.0, 1.0),
                          ("ELLIPSE", 1.5, 0.6)):
        if kind == "area_" + shape.lower() or (mixed and shape in ("RECTANGLE", "DISK")):
            loc = (-0.5, -0.5, 2.0) if shape != "DISK" or not mixed else (-2.0, 1.0, 1.8)
            add("AREA", "Area" + shape.title(), loc, (math.radians(15), 0, 0.3), energy=120.0, shape=shape,
                size=sx, size_y=sy)
    if kind == "emission" or mixed:
        quad("Lamp", 0.8, 0.4, emission_material("Glow", (1.0, 0.6, 0.3), 12.0),
             location=(1.0, 0.8, 1.8), rotation=(math.radians(-30), 0, 0), facing_down=True)
    return sc


# ---- example scenes -----------------------------------------------------------------------------------


def many_lights_scene(n_side: int = 12, frames: int = 48, width: int = 320, height: int = 180) -> bpy.types.Scene:
    """A floor with pillars lit by n_side^2 small coloured point and spot lights and a few emissive strips;
    the camera dollies and pans over 'frames' frames."""
    sc = new_scene(width, height, engine="RESTIRCL" if hasattr(bpy.types, "RESTIRCL_PT_sampling") else "CYCLES")
    floor = diffuse_material("Floor", (0.7, 0.7, 0.7))
    stone = diffuse_material("Pillar", (0.6, 0.5, 0.4))
    quad("Floor", 40.0, 40.0, floor)
    for i in range(5):
        for j in range(5):
            box(f"Pillar.{i}{j}", (0.8, 0.8, 3.0), stone, location=(-12 + 6 * i, -12 + 6 * j, 1.5))
    for i in range(n_side):
        for j in range(n_side):
            hue = ((i * n_side + j) * 0.618034) % 1.0
            col = colorsys.hsv_to_rgb(hue, 0.7, 1.0)
            x, y = -15 + 30 * (i + 0.5) / n_side, -15 + 30 * (j + 0.5) / n_side
            if (i + j) % 4 == 0:
                light("SPOT", f"Spot.{i}.{j}", (x, y, 3.0), (0, 0, 0), energy=60.0, color=col,
                      spot_size=math.radians(70), spot_blend=0.3, shadow_soft_size=0.05)
            else:
                light("POINT", f"Point.{i}.{j}", (x, y, 0.6), energy=15.0, color=col, shadow_soft_size=0.05,
                      use_soft_falloff=False)
    glow = emission_material("Strip", (1.0, 0.8, 0.5), 8.0)
    for k in range(4):
        quad(f"Strip.{k}", 6.0, 0.2, glow, location=(-9 + 6 * k, 0.0, 3.5), facing_down=True)
    cam = camera((-16, -16, 4), (0, 0, 0.5), lens=24.0)
    sc.frame_start, sc.frame_end = 1, frames
    for f, (loc, tgt) in ((1, ((-16, -16, 4), (0, 0, 0.5))), (frames, ((10, -18, 3), (4, 6, 1.0)))):
        cam.location = loc
        point_at(cam, tgt)
        cam.keyframe_insert("location", frame=f)
        cam.keyframe_insert("rotation_euler", frame=f)
    return sc


def area_interior_scene(width: int = 320, height: int = 240) -> bpy.types.Scene:
    """A room lit by ceiling area lights of every shape, a window-like emissive panel and a small sun patch."""
    sc = new_scene(width, height, engine="RESTIRCL" if hasattr(bpy.types, "RESTIRCL_PT_sampling") else "CYCLES")
    walls = diffuse_material("Walls", (0.75, 0.75, 0.7))
    red = diffuse_material("Red", (0.7, 0.1, 0.1))
    green = diffuse_material("Green", (0.1, 0.6, 0.15))
    box("Room", (8.0, 6.0, 3.0), walls, location=(0, 0, 1.5), inward=True)
    box("Sofa", (2.4, 0.9, 0.8), red, location=(0.0, 2.0, 0.4))
    box("Table", (1.2, 1.2, 0.5), green, location=(0.5, -0.5, 0.25), rotation=(0, 0, 0.4))
    uv_sphere("Ball", 0.35, material=diffuse_material("Ball", (0.8, 0.8, 0.8)), location=(-2.0, -1.0, 0.35))
    light("AREA", "Ceiling.Square", (-2.5, 0.0, 2.95), energy=150.0, shape="SQUARE", size=1.0)
    light("AREA", "Ceiling.Rectangle", (0.0, 0.0, 2.95), energy=200.0, shape="RECTANGLE", size=2.0, size_y=0.4)
    light("AREA", "Ceiling.Disk", (2.5, 0.0, 2.95), energy=120.0, shape="DISK", size=0.8,
          color=(1.0, 0.85, 0.7))
    light("AREA", "Wall.Ellipse", (3.95, -2.0, 1.6), (0, -math.pi / 2, 0), energy=80.0, shape="ELLIPSE",
          size=1.2, size_y=0.6, color=(0.7, 0.8, 1.0))
    quad("Window", 1.6, 1.0, emission_material("Window", (0.8, 0.9, 1.0), 3.0),
         location=(-3.98, 1.0, 1.6), rotation=(0, math.pi / 2, 0))
    camera((3.2, -2.6, 1.6), (-1.0, 0.8, 0.8), lens=20.0)
    return sc


# ---- material previews --------------------------------------------------------------------------------


def preview_icon(material: bpy.types.Material, engine: str, timeout: float = 300.0) -> np.ndarray:
    """The icon preview (H, W, 4) that `engine` renders of a copy of `material` (a fresh preview each time), through
    Blender's own preview job. The job runs on a thread of its own: wait (sleeping, so the job gets Python) until
    its pixels arrive."""
    bpy.context.scene.render.engine = engine
    mat = material.copy()
    mat.asset_generate_preview()  # ed.lib_id_generate_preview's job; that operator's poll fails in 5.3
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        time.sleep(0.05)
        w, h = mat.preview.image_size
        px = np.array(mat.preview.image_pixels_float[:], np.float32).reshape(h, w, 4)
        if px[..., 3].sum() > 0:  # the film is transparent: alpha arrives with the render
            time.sleep(0.2)  # the job's last writes
            return np.array(mat.preview.image_pixels_float[:], np.float32).reshape(h, w, 4)
    raise AssertionError(f"no {engine} preview of {material.name} within {timeout} s")


# ---- the example .blend files -------------------------------------------------------------------------


def main(argv: list[str]) -> None:
    """Write the example scenes into argv[0] (default: blend/ of the working directory, the repository root)."""
    outdir = Path(argv[0]) if argv else Path("blend")
    outdir.mkdir(parents=True, exist_ok=True)
    try:
        addon = addon_module()
        if not hasattr(bpy.types.Scene, "restircl"):
            addon.register()
    except Exception as exc:  # the scenes are still useful with Cycles
        print(f"restircl add-on not registered ({exc}); scenes use Cycles")
    for name, build in (("many_lights", many_lights_scene), ("area_interior", area_interior_scene)):
        build()
        path = outdir / f"{name}.blend"
        bpy.ops.wm.save_as_mainfile(filepath=str(path), compress=True)
        print(f"wrote {path}")


if __name__ == "__main__":
    main(sys.argv[1:])
