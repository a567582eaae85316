"""Light groups (Blender's view-layer Light Groups, Cycles' "Combined_<name>" passes): Scene.light_groups names the
groups, each emitter (Light.lightgroup, Mesh.lightgroup for its emissive triangles, Environment.lightgroup for the
world) names the one its light counts in. On the device a light's group is in its link record (lights/linking.py),
and the kernels add each contribution to the plane of its light's group (opencl/film/light_groups.h)."""

from __future__ import annotations

import numpy as np

from ..scene.errors import SceneError

#: most light groups a scene may have (each is a plane of float4 per pixel, summed over a still's samples)
MAX_GROUPS = 32


def group_of(scene, name: str) -> int:
    """The index of light group `name` in scene.light_groups; -1 for no group, or one the scene does not list (as
    Cycles: an emitter in a group the view layer lacks counts in no group pass)."""
    return scene.light_groups.index(name) if name in scene.light_groups else -1


def emitter_groups(scene, source: np.ndarray, tri_object: np.ndarray) -> list[int]:
    """The light group of each device light by its source (DeviceLights.source: a scene light, the world, or
    -1 - an emissive triangle of the world, whose mesh tri_object names)."""
    out = []
    for src in np.asarray(source, np.int64).tolist():
        if 0 <= src < len(scene.lights):
            out.append(group_of(scene, scene.lights[src].lightgroup))
        elif src < 0:
            out.append(group_of(scene, scene.meshes[int(tri_object[-1 - src])].lightgroup))
        else:
            out.append(group_of(scene, scene.environment.lightgroup if scene.environment is not None else ""))
    return out


def light_group_count(scene) -> int:
    """The number of light groups of `scene` (SceneError for a name listed twice, or more than MAX_GROUPS)."""
    names = list(scene.light_groups)
    if len(set(names)) != len(names):
        raise SceneError(f"light groups: a name is listed twice in {names}")
    if len(names) > MAX_GROUPS:
        raise SceneError(f"light groups: at most {MAX_GROUPS}, the scene has {len(names)}")
    return len(names)
