"""Feature flags: what a scene and its settings need, compiled in with -D and nothing more (DESIGN section 6)."""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from ..lights.light_groups import light_group_count
from ..lights.linking import uses_linking
from ..lights.registry import FEATURE_FLAGS
from ..lights.tree import tree_proposal
from ..scene.scene import Scene
from ..settings.table import Settings
from ..upload.device_scene import DeviceScene
from .plan import stills_use_pick_table

LIGHT_FLAGS = FEATURE_FLAGS  # light type code -> HAS_<TYPE>_LIGHTS, from each type's entry (restircl.lights)
# HAS_GLOSSY: some material has a specular lobe; HAS_TEXTURES: some material input is a texture node;
# HAS_TRANSMISSION: some closure refracts (Glass, Refraction, Principled Transmission: bsdf/microfacet_dielectric.h)
# HAS_TRANSPARENCY: some material's coverage is below 1 (materials/alpha.py: rays pass through, bvh/transparent.h)
# HAS_THIN_FILM: some closure has a thin film (materials/thin_film.py, opencl/bsdf/thin_film.h)
# HAS_THIN_SHADOW: shadow rays pass some smooth thin wall with its colour (upload/thin_wall_shadow.py; it turns
# HAS_TRANSPARENCY on: bvh/thin_wall_shadow.h)
MATERIAL_FLAGS = ("HAS_GLOSSY", "HAS_TEXTURES", "HAS_TRANSMISSION", "HAS_TRANSPARENCY", "HAS_THIN_FILM",
                  "HAS_THIN_SHADOW")
# HAS_LIGHT_TREE: RIS candidates (Settings.light_proposal) or NEE at path vertices (Settings.path_light_pick) come
# from the light tree (lights/tree.py)
# HAS_CAMERA_LIGHTS: camera rays test the lights visible to the camera that have a shape (lights/camera_visible.py)
# HAS_PICK_TABLE: still RIS renders pick lights from a per-pixel table (lights/pick_table.py); compiled in for the
# scene's RIS stills whatever the method, so that every method of a scene shares one build
# HAS_PATHS: light bounces after the primary hit (Settings.max_bounces > 0: the path pass, opencl/path/)
# HAS_GI_REUSE: ... and ReSTIR GI reuses them in animation and viewport frames (Settings.gi_reuse, opencl/restir_gi/)
# HAS_LIGHT_PASSES: the shading kernels also write Cycles' light passes (Settings.light_passes, opencl/film/)
# HAS_LIGHT_LINKING: some emitter has light or shadow linking (lights/linking.py, opencl/lights/linking.h)
# HAS_LIGHT_GROUPS: the number of light groups (Scene.light_groups, opencl/film/light_groups.h); the light passes'
# planes carry them, so it turns HAS_LIGHT_PASSES on
# HAS_DOF: the camera has an aperture (depth of field, opencl/camera/lens.h)
# HAS_HOLDOUT: some object is a holdout (Mesh.holdout: camera rays see a hole there)
# HAS_CAMERA_HIDDEN: some object is hidden from the camera (Mesh.camera_visible off, opencl/camera/hidden.h)
ALL_FLAGS = (*LIGHT_FLAGS.values(), "HAS_MOTION", "HAS_MOVING_OBJECTS", *MATERIAL_FLAGS, "HAS_LIGHT_TREE",
             "HAS_CAMERA_LIGHTS", "HAS_PICK_TABLE", "HAS_PATHS", "HAS_GI_REUSE", "HAS_LIGHT_PASSES",
             "HAS_LIGHT_LINKING", "HAS_LIGHT_GROUPS", "HAS_DOF", "HAS_HOLDOUT", "HAS_CAMERA_HIDDEN")


def derive_flags(light_types: Iterable[int], motion: bool, moving_objects: bool,
                 materials: dict[str, bool] | None = None, light_tree: bool = False,
                 camera_lights: bool = False, pick_table: bool = False, paths: bool = False,
                 gi_reuse: bool = False, light_passes: bool = False,
                 light_linking: bool = False, light_groups: int = 0, dof: bool = False,
                 holdout: bool = False, camera_hidden: bool = False) -> dict[str, bool | int]:
    """Flags for a scene with these light types, whether anything moves between frames, what its materials
    need (MATERIAL_FLAGS -> bool, python/restircl/upload/materials.py), whether it samples from the light tree,
    whether the camera sees lights, whether still renders pick lights from the per-pixel table, whether light
    bounces (paths), whether ReSTIR GI reuses the bounces (gi_reuse, only with paths) and whether the light passes
    are written, whether some emitter links lights or shadows, how many light groups there are, whether the camera
    has an aperture (dof), whether some object is a holdout and whether some object is hidden from the camera."""
    types = set(light_types)
    flags = {name: t in types for t, name in LIGHT_FLAGS.items()}
    flags["HAS_MOTION"] = bool(motion or moving_objects)
    flags["HAS_MOVING_OBJECTS"] = bool(moving_objects)
    for name in MATERIAL_FLAGS:
        flags[name] = bool((materials or {}).get(name, False))
    flags["HAS_LIGHT_TREE"] = bool(light_tree)
    flags["HAS_CAMERA_LIGHTS"] = bool(camera_lights)
    flags["HAS_PICK_TABLE"] = bool(pick_table)
    flags["HAS_PATHS"] = bool(paths)
    flags["HAS_GI_REUSE"] = bool(paths and gi_reuse)
    flags["HAS_LIGHT_PASSES"] = bool(light_passes)
    flags["HAS_LIGHT_LINKING"] = bool(light_linking)
    flags["HAS_LIGHT_GROUPS"] = int(light_groups) if light_groups else False
    if light_groups:
        flags["HAS_LIGHT_PASSES"] = True
    flags["HAS_DOF"] = bool(dof)
    flags["HAS_HOLDOUT"] = bool(holdout)
    flags["HAS_CAMERA_HIDDEN"] = bool(camera_hidden)
    return flags


def general_flags() -> dict[str, bool]:
    """Every feature on: the general build that specialised builds must match."""
    return dict.fromkeys(ALL_FLAGS, True)


def renderer_flags(scene: Scene, ds: DeviceScene, settings: Settings, *, interactive: bool,
                   light_tree: bool, path_light_tree: bool = False) -> dict[str, bool | int]:
    """The flags of a renderer of `scene` (uploaded as `ds`) with `settings`: what they need (Settings.specialise),
    else every feature. interactive: the view may change and objects move by edits (Renderer's interactive).
    light_tree: RIS candidates come from the tree; path_light_tree: NEE at path vertices does."""
    if not settings.specialise:
        return with_transparent_bound(general_flags(), settings)
    cam = scene.camera
    # a camera animation whose transforms are all equal does not move: no motion vectors to compile
    moving_camera = interactive or (cam is not None and bool(np.any(cam.transforms != cam.transforms[:1])))
    # a light the camera sees that moves needs motion vectors of its own
    moving = moving_camera or ds.moving_objects or (ds.moving_lights and bool(ds.camera_lights))
    return with_transparent_bound(derive_flags(ds.lights.type_set, moving, ds.moving_objects or interactive,
                                               ds.material_flags, light_tree or path_light_tree,
                                               camera_lights=bool(ds.camera_lights),
                                               pick_table=stills_use_pick_table(
                                                   settings, ds.sampled_light_count,
                                                   tree_proposal("ris", settings.light_proposal, ds.lights.types)),
                                               paths=settings.max_bounces > 0, gi_reuse=settings.gi_reuse,
                                               light_passes=settings.light_passes, light_linking=uses_linking(scene),
                                               light_groups=light_group_count(scene),
                                               dof=interactive or (cam is not None and cam.has_dof),
                                               holdout=any(m.holdout for m in scene.meshes),
                                               camera_hidden=not all(m.camera_visible for m in scene.meshes)),
                                  settings)


def with_transparent_bound(flags: dict, settings: Settings) -> dict:
    """The flags, with Light Paths > Transparent (the -D TRANSPARENT_MAX_BOUNCES) where rays pass surfaces."""
    if flags.get("HAS_TRANSPARENCY"):
        flags["TRANSPARENT_MAX_BOUNCES"] = int(settings.transparent_max_bounces)
    return flags


def describe(flags: dict[str, bool]) -> list[str]:
    return [name.removeprefix("HAS_").lower() for name in ALL_FLAGS if flags.get(name)]
