"""restircl's Environment written as a Cycles World (the Cycles bridge, cycles.to_bpy): a Background of the
world's colour and strength, or, with an image, an Environment Texture of the same texels (the NaN and negative
ones zeroed as restircl zeroes them) with the world's interpolation (Closest: texel by texel; Linear), fed by the
Generated direction through a Mapping node of the world's rotation."""

from __future__ import annotations

import numpy as np

from ...environment.image import environment_texels
from ...environment.world import Environment


def world_to_bpy(bpy, sc, env: Environment) -> None:
    """Make scene sc's world emit `env` (sc.world exists: cycles.black_world made it)."""
    world = sc.world
    tree = world.node_tree
    bg = tree.nodes.get("Background")
    bg.inputs["Strength"].default_value = float(env.strength)
    if env.image is None and env.path is None:
        bg.inputs["Color"].default_value = (*map(float, env.color), 1.0)
    else:
        texels, _ = environment_texels(env)
        h, w = texels.shape[:2]
        img = bpy.data.images.new(f"{env.name}_map", w, h, alpha=True, float_buffer=True)
        img.colorspace_settings.name = "Non-Color"
        rgba = np.concatenate([texels, np.ones((h, w, 1), np.float32)], axis=2)[::-1]  # Blender: bottom row first
        img.pixels.foreach_set(np.ascontiguousarray(rgba, np.float32).reshape(-1))
        img.pack()
        tex = tree.nodes.new("ShaderNodeTexEnvironment")
        tex.image = img
        tex.interpolation = env.interpolation
        tex.projection = "EQUIRECTANGULAR"
        coords = tree.nodes.new("ShaderNodeTexCoord")
        mapping = tree.nodes.new("ShaderNodeMapping")
        mapping.vector_type = "POINT"
        if env.rotation is not None:
            from mathutils import Matrix

            rot = Matrix([list(map(float, row)) for row in np.asarray(env.rotation, np.float64)])
            mapping.inputs["Rotation"].default_value = rot.to_euler("XYZ")
        tree.links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
        tree.links.new(mapping.outputs["Vector"], tex.inputs["Vector"])
        tree.links.new(tex.outputs["Color"], bg.inputs["Color"])
    vis = getattr(world, "cycles_visibility", None)
    if vis is not None:
        vis.camera = bool(env.visible_camera)


def set_world_map(sc, resolution: int) -> None:
    """Cycles' importance map of scene sc's world: 0 leaves Blender's default (Automatic, which Cycles builds in
    every render call's synchronisation: seconds for the tuning sky on 2 cores,
    docs/measurements/error-vs-time.md), else Manual at `resolution` (the map's width)."""
    if resolution and sc.world is not None:
        sc.world.cycles.sampling_method = "MANUAL"
        sc.world.cycles.sample_map_resolution = int(resolution)
