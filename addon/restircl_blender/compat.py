"""Differences between the Blender releases the add-on supports (4.2 LTS to 5.3), in one place.

Each helper answers one question the same way on every release, so the readers in export/ need no version tests.
"""

from __future__ import annotations


def uses_nodes(id_block) -> bool:
    """Whether a material, light or world is shaded by its node tree.

    Before Blender 5 a node tree is used only when `use_nodes` is on (and may exist while it is off); from 5.0
    (materials, worlds) and 5.1 (lights) the tree is always used and `use_nodes` is deprecated, so reading it
    would only raise a DeprecationWarning.
    """
    tree = getattr(id_block, "node_tree", None)
    if tree is None:
        return False
    prop = id_block.bl_rna.properties.get("use_nodes")
    if prop is None or getattr(prop, "is_deprecated", False):
        return True
    return bool(id_block.use_nodes)


def visible_camera(ob) -> bool:
    """Object > Visibility > Ray Visibility > Camera. Every supported release (4.2 on) has it on the object, for
    lights too (Blender 2.9x kept it in `ob.cycles_visibility.camera`, read where the attribute is missing)."""
    if hasattr(ob, "visible_camera"):
        return bool(ob.visible_camera)
    legacy = getattr(ob, "cycles_visibility", None)
    return bool(getattr(legacy, "camera", True))


def world_visible_camera(world) -> bool:
    """World > Ray Visibility > Camera: `world.visibility.camera`? No: Blender keeps it in Cycles' settings of
    the world (`world.cycles_visibility.camera`) on every supported release; True where it is missing."""
    vis = getattr(world, "cycles_visibility", None)
    return bool(getattr(vis, "camera", True))


# The first release known to pick an extension's wheels by Python version (tools/build_extension.py).
PER_PYTHON_WHEELS = (4, 2, 13)


def import_error_hint(version: tuple[int, ...]) -> str:
    """What to do when restircl (or pyopencl) does not import on Blender `version`."""
    if tuple(version) < PER_PYTHON_WHEELS:
        return ("this Blender chooses an extension's wheels by platform only: install the zip built with "
                "`tools/build_extension.py --python-version 3.11`, or Blender 4.2.13 or newer")
    return "install the extension with its bundled wheels, or `pip install restircl` into Blender's Python"


def blender_version() -> tuple[int, ...]:
    """The running Blender's version, e.g. (5, 0, 1)."""
    import bpy

    return tuple(bpy.app.version)
