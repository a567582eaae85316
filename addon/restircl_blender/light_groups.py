"""Light groups in Blender (View Layer > Light Groups; an object's and the world's Light Group): the groups the
view layer lists become restircl.Scene.light_groups, each emitter's group its lightgroup, and each group a pass
named as Cycles names it, "Combined_<name>" (RGB), registered with the Render Result and filled from
Frame.light_groups."""

from __future__ import annotations

import numpy as np

PREFIX = "Combined_"


def light_group_names(view_layer) -> list[str]:
    """The view layer's light groups, in its order (none before Blender 3.2)."""
    return [lg.name for lg in getattr(view_layer, "lightgroups", ())]


def object_group(ob) -> str:
    """An object's (or the world's) Light Group; "" for none."""
    orig = ob.original if getattr(ob, "original", None) is not None else ob
    return str(getattr(orig, "lightgroup", "") or "")


def register_light_groups(engine, scene, view_layer) -> None:
    """RenderEngine.update_render_passes: one RGB pass per light group of the view layer."""
    for name in light_group_names(view_layer):
        engine.register_pass(scene, view_layer, PREFIX + name, 3, "RGB", "COLOR")


def light_group_data(frame, pass_name: str, height: int, width: int) -> np.ndarray | None:
    """The (H, W, 3) float32 light of group pass `pass_name` of a restircl Frame, or None where it has none."""
    groups = getattr(frame, "light_groups", None)
    if not groups or not pass_name.startswith(PREFIX):
        return None
    arr = groups.get(pass_name[len(PREFIX):])
    if arr is None or np.shape(arr)[:2] != (height, width):
        return None
    return np.asarray(arr, dtype=np.float32)
