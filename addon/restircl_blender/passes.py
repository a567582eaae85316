"""The passes (AOVs) of restircl.render.passes.PASSES in Blender: which the view layer has turned on, and their
registration with the Render Result (RenderEngine.update_render_passes)."""

from __future__ import annotations

from restircl.render.passes import PASSES, blender_name

from .compat import blender_version
from .cryptomatte import register_cryptomatte
from .light_groups import register_light_groups


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


def light_passes_on(view_layer) -> bool:
    """Whether the view layer has one of Cycles' light passes on (their toggles, as Cycles has them): the renderer
    then writes them (Settings.light_passes, which the add-on sets from here, not from its own property)."""
    return any(p.requires == "light_passes" and pass_on(view_layer, p) for p in PASSES)


def requirement_met(scene, view_layer, p) -> bool:
    """Whether the render setting pass `p` requires is on (the light passes: a toggle of the view layer)."""
    if p.requires is None:
        return True
    if p.requires == "light_passes":
        return light_passes_on(view_layer)
    return bool(getattr(getattr(scene, "restircl", None), p.requires, False))


def register_passes(engine, scene, view_layer) -> None:
    """RenderEngine.update_render_passes: the passes of restircl.render.passes.PASSES the view layer has turned on."""
    for p in PASSES:
        if not requirement_met(scene, view_layer, p):
            continue
        if pass_on(view_layer, p):
            engine.register_pass(scene, view_layer, blender_name(p, blender_version()), len(p.channels), p.channels,
                                 p.blender_type)
    register_light_groups(engine, scene, view_layer)
    register_cryptomatte(engine, scene, view_layer)
