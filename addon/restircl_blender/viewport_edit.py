"""Scene edits while the viewport runs: what changed in the depsgraph, applied to the viewport session's scene so
that only what changed is uploaded (DeviceScene.edit), and the history is dropped only where the change demands.

- a moved object (its transform only): its geometry is not read again; the motion rows of the next frame take
  its history along (M_before M_after^-1), as an animated object's;
- a light's power, colour or size, a material's inputs: their records are uploaded again (a material's texels only
  when an image changed); the history stays, except where a light switched or its power jumped (DeviceScene
  decides, as for animated lights);
- another geometry (topology), a light added or removed: uploaded again and the history is dropped;
- what the compiled kernels cannot show (a new light type, a material that becomes glossy, textured,
  emissive or transparent, another world, objects added or removed): a new renderer.
No bpy here: the add-on fills SceneEdit from depsgraph.updates (viewport.py), tests fill it by hand."""

from __future__ import annotations

import copy
from dataclasses import dataclass, field

import numpy as np
from restircl import Camera, Light, Material, Renderer, Scene

from .export.fingerprint import fingerprint


@dataclass
class SceneEdit:
    """transforms: new object-to-world matrices by object name (meshes and lights), read without re-exporting
    anything else; lights, materials: the lights or the materials re-read alone (in the session's order), for an
    edit that touched only them; scene: a whole re-export to compare with the session's scene (lights, materials,
    geometry)."""

    transforms: dict[str, np.ndarray] = field(default_factory=dict)
    scene: Scene | None = None
    lights: list[Light] | None = None
    materials: list[Material] | None = None


def _same(a, b) -> bool:
    return fingerprint(x=a) == fingerprint(x=b)


def _geometry(mesh) -> tuple:
    return (mesh.name, mesh.vertices, mesh.triangles, mesh.material_ids, mesh.uvs, mesh.normals)


def _kernel_needs(scene: Scene) -> tuple:
    """What of a scene decides the compiled kernels beyond the light array (features.py): the light types and
    which materials are glossy, textured or emissive, whether any is transparent, the world."""
    from restircl.lights.camera_visible import camera_light_indices
    from restircl.lights.registry import type_of
    from restircl.upload.alpha import scene_is_transparent
    from restircl.upload.materials import uses_glossy, uses_textures

    # the device light types (a square and a disk area light are two) and whether the camera sees any light
    light_types = sorted({type_of(lt).code for lt in scene.lights})
    return (light_types, bool(camera_light_indices(scene)), [uses_glossy(m) for m in scene.materials],
            [uses_textures(m) for m in scene.materials], [m.is_emissive for m in scene.materials],
            fingerprint(env=scene.environment), scene_is_transparent(scene))


def _move(objects, name: str, matrix: np.ndarray) -> tuple[int, np.ndarray] | None:
    """Give the one object called `name` the transform `matrix`; (its index, its old transform) when it moved."""
    hits = [i for i, o in enumerate(objects) if o.name == name]
    if len(hits) != 1:
        return None
    obj = objects[hits[0]]
    old = np.array(obj.transforms[0])
    new = np.asarray(matrix, np.float64).reshape(1, 4, 4)
    if np.array_equal(old, new[0]):
        return None
    obj.transforms = new
    return hits[0], old


def apply_edit(sc: Scene, r: Renderer, edit: SceneEdit, view: Camera) -> tuple[str, Scene]:
    """Apply `edit` to scene `sc` and its renderer `r`: ('none', sc) nothing changed, ('kept', sc) uploaded with
    the history kept, ('reset', sc) uploaded with the history dropped, or ('rebuilt', new) where the kernels cannot
    show the edited scene `new` (seen by `view`) and the caller makes a new renderer for it."""
    moved, lights = _apply_moves(sc, edit.transforms)
    new = _edited_scene(sc, edit)
    if new is not None and (len(new.meshes) != len(sc.meshes) or len(new.materials) != len(sc.materials)
                            or _kernel_needs(new) != _kernel_needs(sc)):
        new.camera = view
        return "rebuilt", new
    geometry = materials = False
    if new is not None:
        geometry = _take_meshes(sc, new, moved)
        if new.lights is not sc.lights and not _same(sc.lights, new.lights):
            lights = True
            sc.lights = new.lights
        if new.materials is not sc.materials:
            changed = [not _same(a, b) for a, b in zip(sc.materials, new.materials, strict=True)]
            if any(changed):
                materials = True
                # emissive triangles are lights: their records change with an emissive material only
                lights |= any(c and m.is_emissive for c, m in zip(changed, new.materials, strict=True))
                sc.materials = new.materials
    if not (moved or lights or geometry or materials):
        return "none", sc
    r.device_scene.edit(geometry=geometry, lights=lights, materials=materials, moved=moved or None)
    if geometry:
        r.reset()
        return "reset", sc
    return "kept", sc


def _edited_scene(sc: Scene, edit: SceneEdit) -> Scene | None:
    """The scene to compare with `sc`: the edit's re-export, or `sc` with the re-read lights or materials."""
    if edit.scene is not None or (edit.lights is None and edit.materials is None):
        return edit.scene
    new = copy.copy(sc)  # the lights or the materials alone: the rest of the scene is the session's
    new.meshes = list(sc.meshes)
    new.lights = sc.lights if edit.lights is None else edit.lights
    new.materials = sc.materials if edit.materials is None else edit.materials
    return new


def _apply_moves(sc: Scene, transforms: dict[str, np.ndarray]) -> tuple[dict[int, np.ndarray], bool]:
    """Objects moved by name: (mesh index -> its transform before, whether a light moved)."""
    moved: dict[int, np.ndarray] = {}
    lights = False
    for name, m in transforms.items():
        hit = _move(sc.meshes, name, m)
        if hit is not None:
            moved[hit[0]] = hit[1]
        lights |= _move(sc.lights, name, m) is not None
    return moved, lights


def _take_meshes(sc: Scene, new: Scene, moved: dict[int, np.ndarray]) -> bool:
    """Take the re-exported meshes of `new` into `sc`: True where a geometry changed; moved ones go to `moved`."""
    geometry = False
    for i, (a, b) in enumerate(zip(sc.meshes, new.meshes, strict=True)):
        if a is b:  # not re-exported
            continue
        if not _same(_geometry(a), _geometry(b)):
            geometry = True
            sc.meshes[i] = b
        elif not np.array_equal(a.transforms, b.transforms):
            moved[i] = np.array(a.transforms[0])
            a.transforms = b.transforms
    return geometry
