"""Evaluated Blender depsgraph -> restircl.Scene, one reader per Blender data-block type.

Geometry (meshes with modifiers applied, collection and geometry-nodes instances) is read once, at the first
frame asked for; transforms of every instance, light and the camera are sampled at each frame asked for, so an
animation render exports its geometry once and its motion as per-frame matrices.

    scene.py        Export and export_scene, which calls the readers below in turn
    mesh.py         geometry, instances and the probes that detect deforming objects
    material.py     the material node reader
    light.py        lights in Blender's units, converted as Cycles does (docs/units.md)
    camera.py       the render camera, its resolution, depth of field and camera cuts
    holdout.py      the holdout objects (view layer collections, object visibility, the Holdout shader)
    camera_visibility.py  objects hidden from camera rays (Ray Visibility > Camera, Indirect Only collections)
    motion.py       the frames sampled and the per-frame tracks of transforms
    world.py        the world (not rendered: a warning when it would light the scene)
    fingerprint.py  the hash the engine compares to reuse a renderer
    report.py       ExportError and the warnings list

Everything that cannot be represented becomes a warning in `Export.warnings` (the engine shows them with
`RenderEngine.report`); a scene that cannot be rendered at all raises ExportError.
"""

from .camera import render_resolution
from .report import ExportError
from .scene import Export, export_lights, export_materials, export_scene

__all__ = ["Export", "ExportError", "export_lights", "export_materials", "export_scene", "render_resolution"]
