"""The scene file format: one compressed .npz holding a JSON header (the "meta" array) and the numeric arrays.

The header carries a magic string and a version number so that a foreign or newer file is refused with a
SceneFileError naming the problem instead of failing somewhere inside the loader; the file holds no pickles.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Protocol, TypeVar

import numpy as np

from ..environment.file import read_environment, write_environment
from ..materials.file import MaterialReader, MaterialWriter
from .camera import Camera
from .errors import SceneError, SceneFileError
from .light import Light
from .linking import Linking
from .mesh import Mesh

SCENE_FILE_MAGIC = "restircl-scene"
# 2: every Material field, texture nodes (a node table; images as arrays or paths), Mesh.uvs and Mesh.normals
# 3: the world (Scene.environment, environment/file.py)
SCENE_FILE_VERSION = 3
READABLE_VERSIONS = (1, 2, 3)


class SceneParts(Protocol):
    """What the file holds of a scene (scene.Scene, which builds on this module, has them all)."""

    name: str
    frame_count: int | None
    materials: list
    meshes: list[Mesh]
    lights: list[Light]
    camera: Camera | None
    environment: object
    light_groups: list[str]


S = TypeVar("S", bound=SceneParts)


def save_scene(scene: SceneParts, path: str | Path) -> None:
    """Write `scene` as one versioned .npz file (no pickles)."""
    arrays: dict[str, np.ndarray] = {}
    writer = MaterialWriter(arrays)
    materials = [writer.material(m) for m in scene.materials]
    meta: dict = {
        "magic": SCENE_FILE_MAGIC,
        "version": SCENE_FILE_VERSION,
        "name": scene.name,
        "frame_count": scene.frame_count,
        "materials": materials,
        "texture_nodes": writer.nodes,
        "meshes": [],
        "lights": [],
        "camera": None,
        "environment": write_environment(scene.environment, arrays),
        "light_groups": list(scene.light_groups),
    }
    for i, mesh in enumerate(scene.meshes):
        meta["meshes"].append({"name": mesh.name, "lightgroup": mesh.lightgroup, **_links(mesh.linking),
                               "attributes": list(mesh.attributes or {}), "holdout": bool(mesh.holdout),
                               "camera_visible": bool(mesh.camera_visible)})
        for k, a in enumerate((mesh.attributes or {}).values()):
            arrays[f"mesh{i}_attribute{k}"] = np.asarray(a, np.float64)
        arrays[f"mesh{i}_vertices"] = mesh.vertices
        arrays[f"mesh{i}_triangles"] = mesh.triangles
        arrays[f"mesh{i}_material_ids"] = mesh.material_ids
        arrays[f"mesh{i}_transforms"] = mesh.transforms
        for what in ("uvs", "normals", "deform", "deform_times", "deform_normals"):
            if getattr(mesh, what) is not None:
                arrays[f"mesh{i}_{what}"] = np.asarray(getattr(mesh, what), np.float64)
    for i, lt in enumerate(scene.lights):
        d = {k: getattr(lt, k) for k in ("name", "type", "power", "radius", "soft_falloff", "spot_size",
                                          "spot_blend", "angle", "shape", "size", "size_y",
                                          "visible_camera", "lightgroup")}
        d["color"] = list(map(float, lt.color))
        d.update(_links(lt.linking))
        meta["lights"].append(d)
        arrays[f"light{i}_transforms"] = lt.transforms
        if lt.power_per_frame is not None:
            arrays[f"light{i}_power_per_frame"] = lt.power_per_frame
    if scene.camera is not None:
        c = scene.camera
        meta["camera"] = {k: getattr(c, k) for k in ("width", "height", "lens", "sensor_width", "sensor_height",
                                                     "sensor_fit", "shift_x", "shift_y", "type",
                                                     "ortho_scale", "aperture_radius", "focus_distance",
                                                     "aperture_blades", "aperture_rotation", "aperture_ratio",
                                                     "shutter")}
        meta["camera"]["cuts"] = list(c.cuts)
        meta["camera"]["width"] = int(c.width)
        meta["camera"]["height"] = int(c.height)
        arrays["camera_transforms"] = c.transforms
        if c.focus_per_frame is not None:
            arrays["camera_focus_per_frame"] = np.asarray(c.focus_per_frame, np.float64)
    arrays["meta"] = np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)
    with open(path, "wb") as f:
        np.savez_compressed(f, **arrays)


def _links(lk: Linking) -> dict:
    """The header's entry of an emitter's light and shadow links (none when it has none)."""
    return {} if lk.empty else {"linking": {"receivers": dict(lk.receivers), "blockers": dict(lk.blockers)}}


def load_scene(path: str | Path, cls: type[S]) -> S:
    """Read a scene written by save_scene as a `cls`; a corrupt or foreign file raises SceneFileError."""
    path = Path(path)
    try:
        with np.load(path, allow_pickle=False) as z:
            data = {k: z[k] for k in z.files}
    except FileNotFoundError:
        raise
    except Exception as exc:  # zip errors, bad headers, pickles
        raise SceneFileError(f"{path}: not a restircl scene file ({type(exc).__name__}: {exc})") from exc
    try:
        meta = json.loads(bytes(data["meta"]).decode())
    except Exception as exc:
        raise SceneFileError(f"{path}: not a restircl scene file (no readable header)") from exc
    if not isinstance(meta, dict) or meta.get("magic") != SCENE_FILE_MAGIC:
        raise SceneFileError(f"{path}: not a restircl scene file (wrong magic)")
    if meta.get("version") not in READABLE_VERSIONS:
        raise SceneFileError(f"{path}: scene file version {meta.get('version')!r}, this restircl reads "
                             f"versions {', '.join(map(str, READABLE_VERSIONS))}")
    try:
        scene = cls(name=meta.get("name", "scene"), frame_count=meta.get("frame_count"))
        reader = MaterialReader(meta.get("texture_nodes", []), data)
        scene.materials = [reader.material(m) for m in meta["materials"]]
        for i, m in enumerate(meta["meshes"]):
            scene.meshes.append(Mesh(m["name"], data[f"mesh{i}_vertices"], data[f"mesh{i}_triangles"],
                                     data[f"mesh{i}_material_ids"], data[f"mesh{i}_transforms"],
                                     uvs=data.get(f"mesh{i}_uvs"), normals=data.get(f"mesh{i}_normals"),
                                     linking=Linking(**m.get("linking", {})), lightgroup=m.get("lightgroup", ""),
                                     attributes={n: data[f"mesh{i}_attribute{k}"]
                                                 for k, n in enumerate(m.get("attributes", []))} or None,
                                     holdout=bool(m.get("holdout", False)),
                                     camera_visible=bool(m.get("camera_visible", True)),
                                     deform=data.get(f"mesh{i}_deform"),
                                     deform_times=data.get(f"mesh{i}_deform_times"),
                                     deform_normals=data.get(f"mesh{i}_deform_normals")))
        for i, d in enumerate(meta["lights"]):
            d = dict(d)
            d["color"] = tuple(d["color"])
            d["linking"] = Linking(**d.get("linking", {}))
            scene.lights.append(Light(transforms=data[f"light{i}_transforms"],
                                      power_per_frame=data.get(f"light{i}_power_per_frame"), **d))
        if meta["camera"] is not None:
            c = dict(meta["camera"])
            c["cuts"] = tuple(c.get("cuts", ()))
            scene.camera = Camera(transforms=data["camera_transforms"],
                                  focus_per_frame=data.get("camera_focus_per_frame"), **c)
        scene.environment = read_environment(meta.get("environment"), data)
        scene.light_groups = list(meta.get("light_groups", []))
    except SceneError:
        raise
    except Exception as exc:
        raise SceneFileError(f"{path}: corrupt restircl scene file ({type(exc).__name__}: {exc})") from exc
    return scene
