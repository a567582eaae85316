"""Baking a world node graph the renderer does not evaluate (a Sky Texture, gradients, mixed shaders) to an
equirectangular image, through Cycles' Environment bake: each texel of a sphere whose UVs are the equirectangular
map (the one restircl.Environment and Cycles' Environment Texture use) gets the world's radiance in the direction
of its point. The sphere lives in a scene of its own, removed afterwards, also when the bake fails."""

from __future__ import annotations

import math

import numpy as np

BAKE_SAMPLES = 4  # a few samples per texel: antialiasing of the world at texel scale
CELL_TEXELS = 2  # the sphere's grid has a vertex every this many texels (its chords bend directions by far less)


def sphere_grid(width: int, height: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(vertices (V, 3) on the unit sphere, quads (F, 4), per-vertex uv (V, 2)) of an equirectangular grid:
    u = 0.5 - atan2(y, x) / 2 pi, v = 0.5 + elevation / pi (Cycles' equirectangular map, v = 0 at the nadir)."""
    cols = max(4, width // CELL_TEXELS)
    rows = max(2, height // CELL_TEXELS)
    u = np.linspace(0.0, 1.0, cols + 1)
    v = np.linspace(0.0, 1.0, rows + 1)
    uu, vv = np.meshgrid(u, v)
    phi = (0.5 - uu) * 2.0 * math.pi
    lat = (vv - 0.5) * math.pi
    verts = np.stack([np.cos(lat) * np.cos(phi), np.cos(lat) * np.sin(phi), np.sin(lat)], axis=-1).reshape(-1, 3)
    idx = np.arange((rows + 1) * (cols + 1)).reshape(rows + 1, cols + 1)
    quads = np.stack([idx[:-1, :-1], idx[:-1, 1:], idx[1:, 1:], idx[1:, :-1]], axis=-1).reshape(-1, 4)
    return verts, quads, np.stack([uu, vv], axis=-1).reshape(-1, 2)


def bake_world(world, width: int, height: int) -> np.ndarray:
    """(height, width, 3) float32, rows top (zenith) first: the radiance of `world` (an original World)."""
    import bpy

    world = world.original if getattr(world, "original", None) is not None else world
    verts, quads, uv = sphere_grid(width, height)
    scene = bpy.data.scenes.new("restircl-world-bake")
    image = bpy.data.images.new("restircl-world-bake", width, height, alpha=False, float_buffer=True)
    me = bpy.data.meshes.new("restircl-world-bake")
    mat = None
    ob = None
    try:
        me.from_pydata(verts.tolist(), [], quads.tolist())
        layer = me.uv_layers.new(name="UVMap")
        corner_uv = uv[np.array([v for p in me.polygons for v in p.vertices])]
        layer.data.foreach_set("uv", corner_uv.astype(np.float32).reshape(-1))
        me.update()
        mat = bpy.data.materials.new("restircl-world-bake")
        if mat.node_tree is None:  # Blender < 5: node trees are opt-in
            mat.use_nodes = True
        node = mat.node_tree.nodes.new("ShaderNodeTexImage")
        node.image = image
        mat.node_tree.nodes.active = node
        me.materials.append(mat)
        ob = bpy.data.objects.new("restircl-world-bake", me)
        scene.collection.objects.link(ob)
        scene.world = world
        scene.render.engine = "CYCLES"
        scene.cycles.samples = BAKE_SAMPLES
        with bpy.context.temp_override(scene=scene, view_layer=scene.view_layers[0], active_object=ob, object=ob,
                                       selected_objects=[ob], selected_editable_objects=[ob]):
            bpy.ops.object.bake(type="ENVIRONMENT", use_clear=True, target="IMAGE_TEXTURES",
                                use_selected_to_active=False, margin=0)
        buf = np.empty(width * height * 4, dtype=np.float32)
        image.pixels.foreach_get(buf)
        return np.ascontiguousarray(buf.reshape(height, width, 4)[::-1, :, :3])
    finally:
        if ob is not None:
            bpy.data.objects.remove(ob)
        bpy.data.meshes.remove(me)
        if mat is not None:
            bpy.data.materials.remove(mat)
        bpy.data.scenes.remove(scene)
        bpy.data.images.remove(image)
