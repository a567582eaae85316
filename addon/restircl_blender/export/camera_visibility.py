"""Objects the camera does not see (Mesh.camera_visible off), while shadows and bounced light still meet them:
Object > Visibility > Ray Visibility > Camera off, and the objects of a view layer's Indirect Only collections
(with the collections inside them), as Cycles renders both."""

from __future__ import annotations

from .holdout import layer_collections


def hidden_objects(view_layer, objects) -> set[str]:
    """Names of the objects of `objects` (bpy objects) that camera rays pass through in `view_layer`."""
    names = {ob.name for ob in objects if getattr(ob, "visible_camera", True) is False}
    for lc, indirect in layer_collections(view_layer.layer_collection, "indirect_only"):
        if indirect:
            names.update(ob.name for ob in lc.collection.all_objects)
    return names


def mark(scene, view_layer, objects) -> None:
    """Set Mesh.camera_visible on the exported meshes (restircl.Scene `scene`)."""
    names = hidden_objects(view_layer, objects)
    for mesh in scene.meshes:
        mesh.camera_visible = mesh.name not in names
