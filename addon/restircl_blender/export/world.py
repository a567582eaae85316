"""Blender's World -> restircl.Environment.

Native: a Background or Emission shader on the World Output with a plain colour, or with an Environment Texture
(equirectangular) on its Color, whose Vector is the default or a Mapping node's rotation; times its Strength. A
world without a node tree uses World.color. Anything else (a Sky Texture, a gradient, a mix of shaders, a linked
Strength) is baked through Cycles to an equirectangular image (world_bake.py), with a warning naming the nodes
baked. The world's Ray Visibility > Camera becomes Environment.visible_camera."""

from __future__ import annotations

import math
import os
from collections.abc import Callable

import numpy as np

from ..compat import uses_nodes, world_visible_camera
from .images import READABLE
from .inputs import INTERPOLATIONS
from .nodes import find_input, resolve
from .world_bake import bake_world

WORLD_NOT_RENDERED = "world lighting is not rendered (direct light from lights and emissive objects only)"
BACKGROUND_SHADERS = ("ShaderNodeBackground", "ShaderNodeEmission")
FILE_FORMATS = tuple(e for e in READABLE if e in (".exr",))  # linear files the renderer reads by path


class _Bake(Exception):
    """The world needs baking; the message names what the native reader does not take."""


def read_world(scene, warn: Callable[[str], None], bake_resolution: int):
    """The scene's world as a restircl.Environment, or None where it emits nothing (or has no world)."""
    import restircl

    world = scene.world
    if world is None:
        return None
    if not hasattr(restircl, "Environment"):  # a restircl from before the world light
        world_warning(scene, warn)
        return None
    env = None
    if not uses_nodes(world):
        env = restircl.Environment(name=world.name, color=_rgb(world.color), strength=1.0)
    else:
        try:
            env = _native(world, warn)
        except _Bake as why:
            env = _baked(world, str(why), warn, bake_resolution)
    if env is None:
        return None
    env.visible_camera = world_visible_camera(world)
    if env.image is None and env.path is None and (env.strength <= 0 or max(env.color) <= 0):
        return None
    return env


def _rgb(c) -> tuple[float, float, float]:
    return (max(float(c[0]), 0.0), max(float(c[1]), 0.0), max(float(c[2]), 0.0))


def _surface(world):
    out = None
    for node in world.node_tree.nodes:
        if node.bl_idname == "ShaderNodeOutputWorld" and getattr(node, "is_active_output", True):
            out = node
            break
    if out is None:
        return None
    surface = find_input(out, ("Surface",))
    return None if surface is None else resolve(surface)


def _native(world, warn: Callable[[str], None]):
    import restircl

    src = _surface(world)
    if src is None or not src.linked:
        return None  # no World Output, or nothing on it: Cycles shows black
    node = src.node
    if node.bl_idname not in BACKGROUND_SHADERS:
        raise _Bake(f"{node.bl_label} {node.name!r} on the World Output")
    strength_in, color_in = find_input(node, ("Strength",)), find_input(node, ("Color",))
    if strength_in.is_linked:
        raise _Bake(f"a linked Strength of {node.name!r}")
    strength = float(strength_in.default_value)
    if not math.isfinite(strength) or strength < 0:
        warn(f"world {world.name!r}: strength {strength!r} is negative or not finite; the world is left out")
        return None
    col = resolve(color_in)
    if not col.linked:
        return restircl.Environment(name=world.name, color=_rgb(color_in.default_value), strength=strength)
    if col.kind != "ShaderNodeTexEnvironment" or col.socket.identifier != "Color":
        raise _Bake(f"{col.node.bl_label} {col.node.name!r} on the Color of {node.name!r}")
    return _environment_texture(world, col.node, strength, warn)


def _environment_texture(world, tex, strength: float, warn: Callable[[str], None]):
    import restircl

    if tex.projection != "EQUIRECTANGULAR":
        raise _Bake(f"the {tex.projection.lower().replace('_', ' ')} projection of {tex.name!r}")
    rotation = _vector_rotation(find_input(tex, ("Vector",)), tex)
    image = tex.image
    label = f"world {world.name!r}: Environment Texture {tex.name!r}"
    if image is None:
        warn(f"{label} has no image; the world is left out")
        return None
    data = _image(image, label, warn)
    if data is None:
        return None
    # Cycles reads between texels as the node says (Linear by default); Cubic and Smart are read as Linear, as the
    # Image Texture's are
    env = restircl.Environment(name=world.name, color=(1.0, 1.0, 1.0), strength=strength, rotation=rotation,
                               interpolation=INTERPOLATIONS.get(tex.interpolation, "Linear"))
    if isinstance(data, str):
        env.path = data
    else:
        env.image = data
    return env


def _vector_rotation(vector_in, tex) -> np.ndarray | None:
    """The rotation of a Mapping node on the texture's Vector (None: the default direction)."""
    if vector_in is None or not vector_in.is_linked:
        return None
    src = resolve(vector_in)
    if src.kind == "ShaderNodeTexCoord" and src.socket.identifier == "Generated":
        return None  # the world's default vector
    if src.kind != "ShaderNodeMapping":
        raise _Bake(f"{src.label()} {getattr(src.node, 'name', '')!r} on the Vector of {tex.name!r}")
    m = src.node
    inner = find_input(m, ("Vector",))
    if inner is not None and inner.is_linked:
        s = resolve(inner)
        if not (s.kind == "ShaderNodeTexCoord" and s.socket.identifier == "Generated"):
            raise _Bake(f"{s.label()} on the Vector of Mapping {m.name!r}")
    values = {}
    for name in ("Location", "Rotation", "Scale"):
        sock = find_input(m, (name,))
        if sock is not None and sock.is_linked:
            raise _Bake(f"a linked {name} of Mapping {m.name!r}")
        values[name] = np.array(sock.default_value[:3], dtype=np.float64) if sock is not None else None
    kind = m.vector_type
    moves = values["Location"] is not None and kind in ("POINT", "TEXTURE") and np.any(values["Location"] != 0)
    scales = values["Scale"] is not None and np.any(values["Scale"] != 1)
    if moves or scales:
        raise _Bake(f"the location or scale of Mapping {m.name!r}")
    r = euler_xyz(values["Rotation"]) if values["Rotation"] is not None else np.eye(3)
    return r.T if kind == "TEXTURE" else r  # Texture mapping applies the inverse


def euler_xyz(angles: np.ndarray) -> np.ndarray:
    """Blender's XYZ Euler rotation matrix (X first, then Y, then Z)."""
    x, y, z = (float(a) for a in angles)
    cx, sx, cy, sy, cz, sz = math.cos(x), math.sin(x), math.cos(y), math.sin(y), math.cos(z), math.sin(z)
    rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return rz @ ry @ rx


def _image(image, label: str, warn: Callable[[str], None]) -> np.ndarray | str | None:
    """A linear file on disk by path; anything else (packed, HDR, PNG, generated) as linear float pixels."""
    import bpy

    source = getattr(image, "source", "FILE")
    if source not in ("FILE", "GENERATED"):
        warn(f"{label}: image {image.name!r} of source {source} is not supported; the world is left out")
        return None
    if source == "FILE" and image.packed_file is None:
        path = bpy.path.abspath(image.filepath_raw or image.filepath, library=image.library)
        if not os.path.isfile(path):
            warn(f"{label}: image file {path!r} of {image.name!r} is missing; the world is left out")
            return None
        if os.path.splitext(path)[1].lower() in FILE_FORMATS and not image.is_dirty:
            return os.path.normpath(path)
    try:
        w, h, c = int(image.size[0]), int(image.size[1]), int(image.channels)
        buf = np.empty(w * h * c, dtype=np.float32)
        image.pixels.foreach_get(buf)
    except (RuntimeError, ValueError, ReferenceError):
        w = h = c = 0
    if w <= 0 or h <= 0 or c <= 0:
        warn(f"{label}: image {image.name!r} has no pixels (0x0 or unreadable); the world is left out")
        return None
    px = buf.reshape(h, w, c)[::-1]
    rgb = np.repeat(px[..., :1], 3, axis=2) if c < 3 else px[..., :3]
    if not image.is_float and image.colorspace_settings.name == "sRGB":
        rgb = srgb_to_linear(rgb)  # byte images' pixels are the stored (encoded) values
    return np.ascontiguousarray(rgb, dtype=np.float32)


def srgb_to_linear(v: np.ndarray) -> np.ndarray:
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4).astype(np.float32)


def _baked(world, why: str, warn: Callable[[str], None], resolution: int):
    import restircl

    if resolution <= 0:
        warn(f"world {world.name!r}: {why} is not rendered natively and baking is off (Bake Resolution 0); "
             "the world is left out")
        return None
    try:
        pixels = bake_world(world, 2 * resolution, resolution)
    except (RuntimeError, ValueError, TypeError, KeyError) as e:
        warn(f"world {world.name!r}: baking {why} failed ({str(e).strip()}); the world is left out")
        return None
    warn(f"world {world.name!r}: {why} baked to a {2 * resolution}x{resolution} equirectangular image "
         f"(node types: {', '.join(_node_types(world))})")
    return restircl.Environment(name=world.name, color=(1.0, 1.0, 1.0), strength=1.0, image=pixels)


def _node_types(world) -> list[str]:
    """The node types that feed the World Output (through node groups as they are)."""
    tree = world.node_tree
    out = next((n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputWorld"
                and getattr(n, "is_active_output", True)), None)
    seen, todo = set(), [out] if out is not None else []
    while todo:
        node = todo.pop()
        for sock in node.inputs:
            for link in sock.links:
                if link.from_node not in seen:
                    seen.add(link.from_node)
                    todo.append(link.from_node)
    return sorted({n.bl_label for n in seen if n.bl_idname != "NodeReroute"})


def world_warning(scene, warn: Callable[[str], None]) -> None:
    """For a restircl without the world light: warn when the world would light the scene."""
    world = scene.world
    if world is None:
        return
    if not uses_nodes(world):
        if any(c > 0 for c in world.color):
            warn(WORLD_NOT_RENDERED)
        return
    for node in world.node_tree.nodes:
        if node.bl_idname == "ShaderNodeBackground":
            col, strength = node.inputs["Color"], node.inputs["Strength"]
            lit = col.is_linked or strength.is_linked or (
                strength.default_value > 0 and any(c > 0 for c in col.default_value[:3]))
            if lit:
                warn(WORLD_NOT_RENDERED)
            return
