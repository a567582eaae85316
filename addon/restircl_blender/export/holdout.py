"""Holdout (Mesh.holdout): objects that camera rays see as a hole (colour and alpha 0, as Cycles renders them),
while shadows and bounced light still see them. Blender marks them three ways: a view layer's collection set to
Holdout (with the collections inside it), the object's own Visibility > Holdout, and a material whose surface is
the Holdout shader (on every slot of the object; other rays then see the black the material export gives it).
Indirect Only collections are not rendered as such (a warning)."""

from __future__ import annotations

from collections.abc import Callable


def _layer_collections(layer_collection, inherited: bool = False):
    """(layer collection, holdout) of every collection under `layer_collection`, holdout passed down."""
    for child in layer_collection.children:
        held = inherited or bool(getattr(child, "holdout", False))
        yield child, held
        yield from _layer_collections(child, held)


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
    for lc, held in _layer_collections(view_layer.layer_collection):
        if held:
            names.update(ob.name for ob in lc.collection.all_objects)
    for ob in objects:
        slots = [s.material for s in getattr(ob, "material_slots", [])]
        if getattr(ob, "is_holdout", False) or (slots and all(_holdout_material(m) for m in slots)):
            names.add(ob.name)
    return names


def mark(scene, view_layer, objects, warn: Callable[[str], None]) -> None:
    """Set Mesh.holdout on the exported meshes (restircl.Scene `scene`) of the holdout objects."""
    names = holdout_objects(view_layer, objects)
    for mesh in scene.meshes:
        mesh.holdout = mesh.name in names
    indirect = [lc.name for lc, _ in _layer_collections(view_layer.layer_collection)
                if getattr(lc, "indirect_only", False)]
    if indirect:
        warn(f"collection(s) {', '.join(repr(n) for n in indirect[:5])}: Indirect Only is not rendered; their "
             "objects are seen by the camera as usual")
