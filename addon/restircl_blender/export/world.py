"""The world: not rendered yet, so the export only warns when it would light the scene."""

from __future__ import annotations

from collections.abc import Callable

from ..compat import uses_nodes

WORLD_NOT_RENDERED = "world lighting is not rendered (direct light from lights and emissive objects only)"


def world_warning(scene, warn: Callable[[str], None]) -> None:
    world = scene.world
    if world is None:
        return
    if not uses_nodes(world):
        if any(c > 0 for c in world.color):
            warn(WORLD_NOT_RENDERED)
        return
    for node in world.node_tree.nodes:
        if node.bl_idname == "ShaderNodeBackground":
            col, strength = node.inputs["Color"], node.inputs["Strength"]
            lit = col.is_linked or strength.is_linked or (
                strength.default_value > 0 and any(c > 0 for c in col.default_value[:3]))
            if lit:
                warn(WORLD_NOT_RENDERED)
            return
