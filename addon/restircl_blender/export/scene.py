"""The export of one evaluated depsgraph: Export, and export_scene calling the reader of each data-block type."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

from ..light_groups import light_group_names, object_group
from . import camera_visibility, holdout
from .camera import CameraReader
from .fingerprint import fingerprint
from .light import LightReader
from .material import MaterialTable, scene_bake_resolution
from .mesh import GEOMETRY_TYPES, MeshReader
from .motion import Frames
from .report import Warnings
from .world import read_world


@dataclass
class Export:
    scene: object  # restircl.Scene
    frames: list[int]  # Blender frame number of each scene frame index
    warnings: list[str] = field(default_factory=list)
    stats: dict = field(default_factory=dict)
    deforming: list[str] = field(default_factory=list)  # objects whose geometry changes between frames
    material_reads: list[tuple] = field(default_factory=list)  # MaterialTable.reads: export_materials reads again
    deform_handled: list[str] = field(default_factory=list)  # objects whose deformation export_scene's `deform` read

    def index_of(self, frame: int) -> int:
        """Scene frame index of a Blender frame (the last sampled frame at or before it)."""
        best = 0
        for i, f in enumerate(self.frames):
            if f <= frame:
                best = i
        return best

    def fingerprint(self) -> str:
        """A hash of everything exported: equal fingerprints mean an identical scene."""
        return fingerprint(scene=self.scene, frames=self.frames)


def export_lights(depsgraph) -> tuple[list, list[str]]:
    """The lights alone at the current frame (a viewport edit that touched only lights), and the warnings."""
    scene = depsgraph.scene
    warnings = Warnings()
    lights = LightReader(Frames.choose(None, int(scene.frame_current), False), warnings.add)
    for inst in depsgraph.object_instances:
        if inst.object.type == "LIGHT":
            lights.read(inst)
    return lights.build(), list(warnings)


def export_materials(depsgraph, reads: list[tuple]) -> tuple[list | None, list[str]]:
    """The materials alone, read again in the order of an export's `material_reads` (a viewport edit that touched
    only materials, their node trees or images), and the warnings; None instead of the materials when the edit
    changed what the meshes' export depends on (a material gone, reading the UV map or baking now): then the scene
    is exported again."""
    import bpy

    scene = depsgraph.scene
    warnings = Warnings()
    table = MaterialTable(warnings.add, scene_bake_resolution(scene))
    materials = {(m.original or m).name: m for m in depsgraph.ids if isinstance(m, bpy.types.Material)}
    if not table.read_again(reads, materials, bpy.data.objects):
        return None, list(warnings)
    return table.materials, list(warnings)


def export_scene(depsgraph, frames: Sequence[int] | None = None,
                 frame_set: Callable[[int], None] | None = None, camera=None,
                 bake_resolution: int | None = None, deform: Callable[[object], list[int]] | None = None) -> Export:
    """Export the evaluated scene.

    `frames` are the Blender frame numbers to sample motion at (default: only the current frame); it must
    contain the current frame, where the geometry is read. `frame_set(frame)` moves the depsgraph to a frame
    (RenderEngine.frame_set or Scene.frame_set); the depsgraph is moved back to the current frame at the end.
    `camera` overrides the scene camera (an evaluated camera object). `bake_resolution` overrides the scene's
    setting (0: no baking). `deform(ob)`: the frames among `frames` at which an object that may deform has its
    vertices read (a still's deformation steps, motion_blur.deform_frames); None: nowhere."""
    import restircl

    scene = depsgraph.scene
    sampled = Frames.choose(frames, int(scene.frame_current), frame_set is not None)
    warnings = Warnings()
    bake = scene_bake_resolution(scene) if bake_resolution is None else bake_resolution
    materials = MaterialTable(warnings.add, bake)
    meshes = MeshReader(sampled, materials, warnings.add, deform)
    lights = LightReader(sampled, warnings.add)
    cameras = CameraReader(sampled, camera)

    readers: dict[str, MeshReader | LightReader] = {kind: meshes for kind in GEOMETRY_TYPES}
    readers["LIGHT"] = lights
    for inst in depsgraph.object_instances:  # the current frame: geometry, materials, lights, camera
        reader = readers.get(inst.object.type)
        if reader is not None:
            reader.read(inst)
    cameras.read(scene, warnings.add)

    def other_frame(k: int) -> None:  # motion (and light power) only
        for inst in depsgraph.object_instances:
            reader = readers.get(inst.object.type)
            if reader is not None:
                reader.sample(inst, k)
        cameras.sample(depsgraph.scene, k)

    sampled.visit_others(frame_set, other_frame)

    sc = restircl.Scene(name=scene.name, frame_count=sampled.count)
    sc.materials = materials.materials
    sc.meshes = meshes.build()
    holdout.mark(sc, depsgraph.view_layer, scene.objects)
    camera_visibility.mark(sc, depsgraph.view_layer, scene.objects)
    sc.lights = lights.build()
    redone = [n for n in meshes.deforming if n not in meshes.deform_handled]
    if redone:
        warnings.add(f"object(s) {', '.join(repr(n) for n in redone[:5])} deform during the animation: "
                     "the geometry is exported again each frame and the reuse history starts over")
    sc.camera = cameras.build()
    sc.environment = read_world(scene, warnings.add, bake)
    sc.light_groups = light_group_names(depsgraph.view_layer)
    if sc.environment is not None and scene.world is not None:
        sc.environment.lightgroup = object_group(scene.world)
    stats = {
        "objects": meshes.count, "instances": meshes.instances, "triangles": sc.triangle_count,
        "lights": len(sc.lights), "materials": len(sc.materials), "emissive_materials": materials.emissive_count,
    }
    if not sc.meshes and not sc.lights:
        warnings.add("the scene is empty: nothing to render")
    elif not sc.lights and not stats["emissive_materials"] and sc.environment is None:
        warnings.add("the scene has no lights and no emissive materials: the image is black")
    return Export(scene=sc, frames=sampled.numbers, warnings=list(warnings), stats=stats,
                  deforming=meshes.deforming, material_reads=materials.reads,
                  deform_handled=meshes.deform_handled)
