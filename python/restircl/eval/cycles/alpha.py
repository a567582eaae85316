"""A Material's coverage (restircl.materials.alpha) for the Cycles bridge (eval/cycles/bridge.py): the surface
shader mixed with a white Transparent BSDF by the coverage, as a constant or an Image Texture's Alpha (or grey) on
the mesh's UV map, which the bridge writes too."""

from __future__ import annotations

import numpy as np

from ...materials.alpha import alpha_source
from ...materials.material import Material
from ...scene.mesh import Mesh


def write_uvs(me, mesh: Mesh) -> None:
    """The mesh's per-corner UV map into bpy mesh `me` (made by from_pydata of its triangles, in order)."""
    if mesh.uvs is None:
        return
    layer = me.uv_layers.new(name="UVMap")
    layer.data.foreach_set("uv", np.asarray(mesh.uvs, np.float32).reshape(-1))


def _image(bpy, source, name: str):
    """A float bpy image holding the source image's texels as the renderer reads them (linear, bottom row first)."""
    from ...io.image_load import read_image_file, to_linear_rgba

    node = source.image
    pixels = read_image_file(node.image) if isinstance(node.image, str) else np.asarray(node.image)
    rgba = to_linear_rgba(pixels, node.colorspace if node.colorspace == "sRGB" else "Non-Color")
    h, w = rgba.shape[:2]
    img = bpy.data.images.new(name, w, h, alpha=True, float_buffer=True)
    img.colorspace_settings.name = "Non-Color"
    img.alpha_mode = "STRAIGHT"
    img.pixels.foreach_set(np.ascontiguousarray(rgba, np.float32).reshape(-1))
    return img


def apply_alpha(bpy, bmat, mat: Material) -> None:
    """Mix bpy material `bmat`'s surface with a Transparent BSDF by mat's coverage (nothing for coverage 1)."""
    source = alpha_source(mat.alpha)
    if source.image is None and source.constant >= 1.0:
        return
    tree = bmat.node_tree
    out = next(n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial")
    surface = out.inputs["Surface"].links[0].from_socket
    mix = tree.nodes.new("ShaderNodeMixShader")
    clear = tree.nodes.new("ShaderNodeBsdfTransparent")
    clear.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    tree.links.new(clear.outputs[0], mix.inputs[1])
    tree.links.new(surface, mix.inputs[2])
    tree.links.new(mix.outputs[0], out.inputs["Surface"])
    if source.image is None:
        mix.inputs["Fac"].default_value = float(source.constant)
        return
    tex = tree.nodes.new("ShaderNodeTexImage")
    tex.image = _image(bpy, source, f"{mat.name}-alpha")
    tex.interpolation = source.image.interpolation
    tex.extension = source.image.extension
    uv = tree.nodes.new("ShaderNodeUVMap")
    uv.uv_map = "UVMap"
    tree.links.new(uv.outputs[0], tex.inputs["Vector"])
    value = tex.outputs["Alpha" if source.channel == "alpha" else "Color"]
    if source.invert:
        inv = tree.nodes.new("ShaderNodeMath")
        inv.operation = "SUBTRACT"
        inv.inputs[0].default_value = 1.0
        tree.links.new(value, inv.inputs[1])
        value = inv.outputs[0]
    tree.links.new(value, mix.inputs["Fac"])
