"""The depth of field of the 3D view, by Cycles' rules for its viewport: looking through the camera (the view's
perspective is Camera View), the view's lens is that camera's thin lens (its aperture from the camera's own focal
length and F-stop, whatever the view's zoom; its focus distance or focus object; blades, rotation, ratio); the
camera is the view's local camera when the 3D view has one, else the scene's. Any other view is a pinhole. Read on
Blender's main thread (view_draw) each redraw, so an edit of the camera's depth of field shows at once."""

from __future__ import annotations

from .export.camera import lens_params


def view_camera_object(context, depsgraph):
    """The camera object the 3D view looks through (evaluated), or None outside Camera View."""
    rv3d, v3d = context.region_data, context.space_data
    if getattr(rv3d, "view_perspective", "PERSP") != "CAMERA":
        return None
    cam = v3d.camera if getattr(v3d, "use_local_camera", False) else depsgraph.scene.camera
    if cam is None or getattr(cam, "type", None) != "CAMERA":
        return None  # looking through a light (Cycles: no aperture either)
    return cam.evaluated_get(depsgraph) if hasattr(cam, "evaluated_get") else cam


def view_lens(context, depsgraph) -> dict:
    """The restircl.Camera lens fields (aperture_radius, focus_distance, aperture_blades, aperture_rotation,
    aperture_ratio) of the 3D view in `context`; empty for a pinhole."""
    cam = view_camera_object(context, depsgraph)
    if cam is None or cam.data.type not in ("PERSP", "ORTHO"):
        return {}
    return lens_params(cam, lambda _message: None)  # the export warns about a focus bone; the view need not
