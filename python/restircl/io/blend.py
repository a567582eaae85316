"""A .blend exported outside Blender's UI, in a Python that has the bpy module: the add-on's exporter (the same
code as an F12 render), over a range of frames. The farm's workers (farm/worker.py) and the evaluation tools'
Cycles bridge use it."""

from __future__ import annotations

import sys
from pathlib import Path

from ..farm.region import FrameRegion, blend_region
from ..scene.errors import SceneError
from ..scene.scene import Scene


def addon_module():
    """The restircl_blender add-on: an installed extension, else the source checkout's addon/ folder."""
    try:
        import restircl_blender
    except ImportError:
        addon_dir = Path(__file__).resolve().parents[3] / "addon"  # python/restircl/io/blend.py -> the checkout
        if not (addon_dir / "restircl_blender").is_dir():
            raise
        sys.path.insert(0, str(addon_dir))
        import restircl_blender
    return restircl_blender


def import_bpy():
    """The bpy module. A process started by one that had imported bpy (a Dask worker spawned by a test or by
    Blender) inherits its sys.path, in which Blender's scripts/modules folder, holding a package named bpy that
    needs Blender's own _bpy, comes before the module: those folders go, bpy puts them back when it loads."""
    if "bpy" not in sys.modules:
        sys.path[:] = [p for p in sys.path if not _blender_scripts(Path(p).parts)]
    import bpy

    return bpy


def _blender_scripts(parts: tuple[str, ...]) -> bool:
    return "scripts" in parts and ("bpy" in parts or "blender" in parts)


def open_blend(path: str | Path, width: int | None = None, height: int | None = None):
    """Open `path` and return its scene, with the render resolution set to width x height (at 100 %) if given."""
    bpy = import_bpy()
    bpy.ops.wm.open_mainfile(filepath=str(path))
    sc = bpy.context.scene
    sc.render.resolution_x = int(width or sc.render.resolution_x)
    sc.render.resolution_y = int(height or sc.render.resolution_y)
    if width or height:
        sc.render.resolution_percentage = 100
    return sc


def export_blend(path: str | Path, first: int, last: int, width: int | None = None,
                 height: int | None = None) -> Scene:
    """Open `path` and export Blender frames first..last (scene frame i is Blender frame first + i), with the
    resolution overridden if given. Geometry that deforms between frames cannot be one export: an error names it."""
    bpy = import_bpy()
    addon = addon_module()
    if not hasattr(bpy.types.Scene, "restircl"):  # the file's render engine, and its settings, are the add-on's
        addon.register()
    sc = open_blend(path, width, height)
    sc.frame_set(int(first))
    exp = addon.export.export_scene(bpy.context.evaluated_depsgraph_get(), list(range(first, last + 1)),
                                             frame_set=sc.frame_set)
    if exp.deforming:
        raise SceneError(f"{Path(path).name}: {', '.join(exp.deforming)} deform between frames, which one export "
                         f"cannot hold: render this file with Blender itself (docs/farm.md, Flamenco)")
    scene = exp.scene.validate()
    scene.name = Path(path).stem
    return scene


def export_blend_region(path: str | Path, first: int, last: int, width: int | None = None,
                        height: int | None = None) -> tuple[Scene, FrameRegion | None]:
    """export_blend, and the file's render region (Render Region, Crop to Render Region; None: the whole frame).
    The scene's camera still sees the whole frame: FrameRegion.apply narrows it."""
    scene = export_blend(path, first, last, width, height)
    return scene, blend_region(import_bpy().context.scene, addon_module())
