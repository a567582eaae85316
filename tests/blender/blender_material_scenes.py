"""Blender scenes with real materials, built as a user would (primitives, Principled BSDFs, an image and a checker
texture), for the agreement tests against Cycles (tests/blender/test_blender_materials_cycles.py)."""

from __future__ import annotations

import math

import bpy
import numpy as np
from restircl.eval import blender_scenes as scenes

_principled = scenes.principled_nodes


def pattern_image(name: str, size: int = 64, non_color: bool = False):
    """A packed image of soft coloured stripes and rings (smooth enough that texel filtering hardly matters)."""
    img = bpy.data.images.new(name, size, size, alpha=True)
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size
    px = np.ones((size, size, 4), np.float32)
    px[..., 0] = 0.5 + 0.4 * np.sin(2 * math.pi * 2 * x)
    px[..., 1] = 0.5 + 0.4 * np.cos(2 * math.pi * 3 * y)
    px[..., 2] = 0.5 + 0.4 * np.sin(2 * math.pi * 4 * np.hypot(x - 0.5, y - 0.5))
    img.pixels.foreach_set(px.reshape(-1))
    img.pack()
    if non_color:
        img.colorspace_settings.name = "Non-Color"
    return img


def normal_image(name: str, size: int = 64, slope: float = 15.0):
    """A packed tangent-space normal map of bumps (slopes along u and v up to `slope` degrees), Non-Color."""
    img = bpy.data.images.new(name, size, size, alpha=True)
    y, x = (np.mgrid[0:size, 0:size] + 0.5) / size
    k = 2 * math.pi * 3
    a = math.tan(math.radians(slope)) / k  # the height's amplitude: its steepest slope is tan(slope)
    dx, dy = a * k * np.cos(k * x) * np.sin(k * y), a * k * np.sin(k * x) * np.cos(k * y)
    n = np.stack([-dx, -dy, np.ones_like(dx)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    px = np.ones((size, size, 4), np.float32)
    px[..., :3] = 0.5 * n + 0.5
    img.pixels.foreach_set(px.reshape(-1))
    img.pack()
    img.colorspace_settings.name = "Non-Color"
    return img


def _image_node(tree, img):
    tex = tree.nodes.new("ShaderNodeTexImage")
    tex.image = img
    return tex


_object = scenes.primitive


def _sphere(name: str, mat, location, radius: float = 0.6):
    return _object(bpy.ops.mesh.primitive_uv_sphere_add, name, mat, smooth=True, segments=48, ring_count=24,
                   radius=radius, location=location)


def _lights():
    area = scenes.light("AREA", "Key", (-1.5, -1.5, 3.0), (math.radians(35), 0, math.radians(-40)), energy=300.0,
                        size=1.0)
    point = scenes.light("POINT", "Fill", (2.0, -1.0, 2.0), energy=150.0, shadow_soft_size=0.25,
                         color=(1.0, 0.9, 0.8))
    for ob in (area, point):
        ob.visible_camera = False


def user_scene(width: int, height: int):
    """The issue's typical scene: a metallic and a glossy sphere on an image-textured floor, a checker box."""
    sc = scenes.new_scene(width, height)
    floor, ftree, fp = _principled("Floor")
    ftree.links.new(_image_node(ftree, pattern_image("FloorImage")).outputs["Color"], fp.inputs["Base Color"])
    _object(bpy.ops.mesh.primitive_plane_add, "Floor", floor, size=8.0)
    box, btree, bp = _principled("Box")
    chk = btree.nodes.new("ShaderNodeTexChecker")
    chk.inputs["Color1"].default_value = (0.8, 0.2, 0.1, 1.0)
    chk.inputs["Color2"].default_value = (0.9, 0.9, 0.8, 1.0)
    chk.inputs["Scale"].default_value = 4.0
    btree.links.new(chk.outputs["Color"], bp.inputs["Base Color"])
    _object(bpy.ops.mesh.primitive_cube_add, "Box", box, size=0.8, location=(1.2, 0.8, 0.4),
            rotation=(0, 0, 0.4))
    metal = _principled("Metal", **{"Base Color": (0.95, 0.65, 0.35, 1.0), "Metallic": 1.0, "Roughness": 0.3})[0]
    _sphere("MetalSphere", metal, (-0.8, 0.2, 0.6))
    glossy = _principled("Glossy", **{"Base Color": (0.1, 0.2, 0.7, 1.0), "Roughness": 0.15})[0]
    _sphere("GlossySphere", glossy, (0.5, -0.6, 0.5), radius=0.5)
    _lights()
    scenes.camera((0, -5.0, 2.8), (0, 0.2, 0.4), lens=35.0)
    return sc


def _feature_material(feature: str):
    """(material, needs) for one feature case; needs: "glossy" and/or "textures" (a Principled BSDF at Blender's
    defaults has a specular layer: every case needs "glossy")."""
    kind, _, value = feature.partition(":")
    if kind in ("dielectric", "metal"):
        mat = _principled(feature, **{"Base Color": (0.8, 0.5, 0.3, 1.0), "Roughness": float(value),
                                      "Metallic": 1.0 if kind == "metal" else 0.0})[0]
        return mat, {"glossy"}
    if kind == "specular":
        return _principled(feature, **{"Specular IOR Level": float(value), "Roughness": 0.2})[0], {"glossy"}
    if kind == "mix":
        mat, tree, p = _principled(feature, **{"Metallic": 1.0, "Roughness": 0.2})
        d = tree.nodes.new("ShaderNodeBsdfDiffuse")
        d.inputs["Color"].default_value = (0.2, 0.7, 0.3, 1.0)
        m = tree.nodes.new("ShaderNodeMixShader")
        m.inputs["Fac"].default_value = 0.4
        out = tree.nodes["Material Output"]
        tree.links.new(d.outputs[0], m.inputs[1])
        tree.links.new(p.outputs[0], m.inputs[2])
        tree.links.new(m.outputs[0], out.inputs["Surface"])
        return mat, {"glossy"}
    mat, tree, p = _principled(feature, **{"Roughness": 0.3})
    if kind == "image_base":
        tree.links.new(_image_node(tree, pattern_image("Img")).outputs["Color"], p.inputs["Base Color"])
        return mat, {"textures", "glossy"}
    if kind == "image_roughness":
        tree.links.new(_image_node(tree, pattern_image("Rough", non_color=True)).outputs["Color"],
                       p.inputs["Roughness"])
        return mat, {"textures", "glossy"}
    if kind == "normal_map":
        nm = tree.nodes.new("ShaderNodeNormalMap")
        img = normal_image("Nrm", slope=float(value or 15.0))
        tree.links.new(_image_node(tree, img).outputs["Color"], nm.inputs["Color"])
        tree.links.new(nm.outputs["Normal"], p.inputs["Normal"])
        return mat, {"textures", "glossy"}
    if kind == "baked":
        noise = tree.nodes.new("ShaderNodeTexNoise")
        noise.inputs["Scale"].default_value = 3.0
        tree.links.new(noise.outputs["Color"], p.inputs["Base Color"])
        return mat, {"textures", "glossy"}
    raise ValueError(feature)


FEATURES = ("dielectric:0.05", "dielectric:0.3", "dielectric:1.0", "metal:0.05", "metal:0.3", "metal:1.0",
            "specular:1.0", "mix:0.4", "image_base", "image_roughness", "normal_map", "normal_map:48", "baked")


def feature_scene(feature: str, width: int, height: int):
    """A sphere (and the floor, for the texture cases) of one feature's material, lit by the key and fill lights.
    Returns (scene, needs)."""
    sc = scenes.new_scene(width, height)
    mat, needs = _feature_material(feature)
    ground = mat if "textures" in needs else _principled("Ground", **{"Roughness": 0.5})[0]
    _object(bpy.ops.mesh.primitive_plane_add, "Floor", ground, size=6.0)
    _sphere("Sphere", mat, (0.0, 0.0, 0.7), radius=0.7)
    _lights()
    scenes.camera((0, -4.0, 2.2), (0, 0, 0.5), lens=40.0)
    return sc, needs
