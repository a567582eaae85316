"""The passes (AOVs) of restircl.render.passes.PASSES in Blender: which the view layer has turned on, and their
registration with the Render Result (RenderEngine.update_render_passes)."""

from __future__ import annotations

from restircl.render.passes import PASSES, blender_name

from .compat import blender_version


def toggle_owner(view_layer, toggle: str):
    """The object and property name of a pass's toggle: 'use_pass_z' on the view layer, 'restircl.x' on ours."""
    owner_path, _, name = toggle.rpartition(".")
    owner = view_layer
    for part in filter(None, owner_path.split(".")):
        owner = getattr(owner, part, None)
    return owner, name


def pass_on(view_layer, p) -> bool:
    """Whether the view layer has pass `p` on (a pass without a toggle always is)."""
    if p.blender_toggle is None:
        return True
    owner, name = toggle_owner(view_layer, p.blender_toggle)
    return owner is None or bool(getattr(owner, name, True))  # the add-on's own toggles: on when unregistered


def register_passes(engine, scene, view_layer) -> None:
    """RenderEngine.update_render_passes: the passes of restircl.render.passes.PASSES the view layer has turned on."""
    props = getattr(scene, "restircl", None)
    for p in PASSES:
        if p.requires is not None and not getattr(props, p.requires, False):
            continue
        if pass_on(view_layer, p):
            engine.register_pass(scene, view_layer, blender_name(p, blender_version()), len(p.channels), p.channels,
                                 p.blender_type)
