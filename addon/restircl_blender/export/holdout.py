"""Holdout (Mesh.holdout): objects that camera rays see as a hole (colour and alpha 0, as Cycles renders them),
while shadows and bounced light still see them. Blender marks them three ways: a view layer's collection set to
Holdout (with the collections inside it), the object's own Visibility > Holdout, and a material whose surface is
the Holdout shader (on every slot of the object; other rays then see the black the material export gives it)."""

from __future__ import annotations


def layer_collections(layer_collection, flag: str, inherited: bool = False):
    """(layer collection, on) of every collection under `layer_collection`, its `flag` (holdout, indirect_only)
    passed down to the collections inside it."""
    for child in layer_collection.children:
        on = inherited or bool(getattr(child, flag, False))
        yield child, on
        yield from layer_collections(child, flag, on)


def _holdout_material(mat) -> bool:
    tree = getattr(mat, "node_tree", None) if mat is not None else None
    if tree is None:
        return False
    for node in tree.nodes:
        if node.bl_idname == "ShaderNodeOutputMaterial" and node.is_active_output:
            links = node.inputs["Surface"].links
            return bool(links) and links[0].from_node.bl_idname == "ShaderNodeHoldout"
    return False


def holdout_objects(view_layer, objects) -> set[str]:
    """Names of the objects of `objects` (bpy objects) that are holdouts in `view_layer`."""
    names: set[str] = set()
    for lc, held in layer_collections(view_layer.layer_collection, "holdout"):
        if held:
            names.update(ob.name for ob in lc.collection.all_objects)
    for ob in objects:
        slots = [s.material for s in getattr(ob, "material_slots", [])]
        if getattr(ob, "is_holdout", False) or (slots and all(_holdout_material(m) for m in slots)):
            names.add(ob.name)
    return names


def mark(scene, view_layer, objects) -> None:
    """Set Mesh.holdout on the exported meshes (restircl.Scene `scene`) of the holdout objects."""
    names = holdout_objects(view_layer, objects)
    for mesh in scene.meshes:
        mesh.holdout = mesh.name in names
