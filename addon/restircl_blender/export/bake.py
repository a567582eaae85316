"""Baking a node graph the renderer does not evaluate (a Noise Texture, a Color Ramp, ...) to an image, through
Cycles' own bake: the socket that feeds the input is wired for a moment into an Emission shader on the Material
Output, and an Emit bake on the object's UV map writes what it outputs into a float image (what glTF exporters
do). Everything is put back afterwards, also when the bake fails. A UV map of zero area on the material's faces is a
failed bake told before baking, from the mesh (bake_uv.py: what Blender writes into such an image differs between
releases). Every baked image is checked: all zero, or one value (but for texels left zero) where a texture feeds the
graph, is a failed bake (no texel of the object's UV map was written, or one spread by the bake's margin: a missing
UV map, faces outside it). A failure is a note in the export's warnings, which Blender's report shows, and the
input's own value is used."""

from __future__ import annotations

from functools import cached_property

import numpy as np

from .bake_uv import zero_uv_area
from .nodes import Source, find_input, output_node
from .notes import Notes

BAKE_SAMPLES = 4  # a few samples per texel: antialiasing of the graph at texel scale


class Baker:
    """bake(source, want) for the material `mat` on object `ob` (both original, not evaluated, datablocks)."""

    def __init__(self, mat, ob, size: int, notes: Notes):
        self.mat = mat.original if getattr(mat, "original", None) is not None else mat
        self.ob = ob
        self.size = size
        self.notes = notes
        self.count = 0

    @cached_property
    def no_texels(self) -> str:
        """Why the object's UV map leaves the bake nothing to write ("" when it does not)."""
        return zero_uv_area(self.ob, self.mat, self.size)

    def __call__(self, src: Source, want: str):
        from restircl import ImageTexture

        if self.no_texels:
            self.notes.note(f"baking {src.label()} {src.node.name!r} failed: {self.no_texels}; the input's value is "
                            "used")
            return None
        try:
            pixels = bake_socket(self.mat, self.ob, _original_socket(self.mat, src), self.size)
        except (RuntimeError, ValueError, TypeError, KeyError) as e:
            self.notes.note(f"baking {src.label()} {src.node.name!r} failed ({str(e).strip()}); "
                            "the input's value is used")
            return None
        image = pixels[..., 0] if want == "value" else pixels[..., :3]
        why = bake_failure(image, src.node)
        if why:
            self.notes.note(f"baking {src.label()} {src.node.name!r} failed: {why}; the input's value is used")
            return None
        self.count += 1
        return ImageTexture(image=np.ascontiguousarray(image), colorspace="Non-Color", coords="uv",
                            name=f"{self.mat.name}/{src.node.name} (baked)")


def bake_failure(image: np.ndarray, node) -> str:
    """Why a baked image cannot be what the graph gives ("" when it may be): all zero, or constant (but for texels
    left zero) while a texture node feeds the graph."""
    if not np.all(np.isfinite(image)):
        return "the baked image holds NaN or infinite texels"
    if not np.any(image):
        return (f"the baked {image.shape[1]}x{image.shape[0]} image is all zero (does the object's UV map cover "
                "an area?)")
    texels = image.reshape(-1, image.shape[-1] if image.ndim == 3 else 1)
    written = texels[np.any(texels != 0, axis=1)]  # a bake margin spreads one texel's value over the unwritten zeros
    if float(np.ptp(written, axis=0).max()) <= 1e-6 and _has_texture(node):
        where = "" if len(written) == len(texels) else f" on the {len(written)} texels not zero"
        return f"the baked image is one value ({float(written.flat[0]):g}){where} while a texture feeds it"
    return ""


def _has_texture(node, limit: int = 64) -> bool:
    todo, seen = [node], 0
    while todo and seen < limit:
        n = todo.pop()
        seen += 1
        if n.bl_idname.startswith("ShaderNodeTex") and n.bl_idname != "ShaderNodeTexCoord":
            return True
        todo.extend(lk.from_node for s in n.inputs if s.is_linked for lk in s.links)
    return False


def _original_socket(mat, src: Source):
    """The output socket of `src` in the original material's tree (the reader walks the evaluated copy)."""
    node = mat.node_tree.nodes.get(src.node.name)
    sock = None if node is None else next((s for s in node.outputs if s.identifier == src.socket.identifier), None)
    if sock is None:
        raise KeyError(f"node {src.node.name!r} is not in the original material")
    return sock


def bake_socket(mat, ob, socket, size: int) -> np.ndarray:
    """(size, size, 4) float32, rows top first: what `socket` (an output in mat's top-level tree) emits, baked on
    ob's active render UV map."""
    import bpy

    tree = mat.node_tree
    out = output_node(tree)
    surface = find_input(out, ("Surface",)) if out is not None else None
    if surface is None:
        raise RuntimeError("no Material Output")
    old = surface.links[0].from_socket if surface.is_linked else None
    # a scene of its own: the bake's render never meets the render in progress (Blender keeps one per scene)
    scene = bpy.data.scenes.new("restircl-bake")
    image = bpy.data.images.new("restircl-bake", size, size, alpha=False, float_buffer=True)
    dummy = bpy.data.images.new("restircl-bake-other", 4, 4, alpha=False, float_buffer=True)
    added = []  # (tree, node, previous active node)
    emit = tree.nodes.new("ShaderNodeEmission")
    try:
        emit.inputs["Strength"].default_value = 1.0
        tree.links.new(socket, emit.inputs["Color"])
        tree.links.new(emit.outputs[0], surface)
        # the bake writes into the active image node of every material of the object: ours, and a dummy image
        # for the others
        for slot in ob.material_slots:
            m = slot.material
            if m is None or m.node_tree is None or any(t == m.node_tree for t, _n, _p in added):
                continue
            node = m.node_tree.nodes.new("ShaderNodeTexImage")
            node.image = image if m == mat else dummy
            added.append((m.node_tree, node, m.node_tree.nodes.active))
            m.node_tree.nodes.active = node
        scene.collection.objects.link(ob)
        scene.render.engine = "CYCLES"
        scene.cycles.samples = BAKE_SAMPLES
        with bpy.context.temp_override(scene=scene, view_layer=scene.view_layers[0], active_object=ob, object=ob,
                                       selected_objects=[ob], selected_editable_objects=[ob]):
            bpy.ops.object.bake(type="EMIT", use_clear=True, target="IMAGE_TEXTURES", use_selected_to_active=False)
        buf = np.empty(size * size * 4, dtype=np.float32)
        image.pixels.foreach_get(buf)
        return np.ascontiguousarray(buf.reshape(size, size, 4)[::-1])
    finally:
        tree.nodes.remove(emit)
        if old is not None:
            tree.links.new(old, surface)
        for t, node, prev in added:
            t.nodes.remove(node)
            t.nodes.active = prev
        bpy.data.scenes.remove(scene)
        bpy.data.images.remove(image)
        bpy.data.images.remove(dummy)
