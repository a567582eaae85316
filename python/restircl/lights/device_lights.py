"""Scene lights and emissive triangles -> packed device Light records (opencl/types.h), with Blender's units.

Each type's conversion is in its module (sphere, spot, sun, quad, disk, triangle, environment; measured against
Cycles, docs/units.md); this gathers them in the order the device sees: the world (environment) first when the scene
has one, then the scene's lights, then emissive triangles; the environment's map and table after every record, then
the images and blocks of emissive triangles textured by an image (textured_emission.py).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..core import layouts as L
from ..scene.scene import Scene
from . import environment as env_light
from .area_sampling import apply_sampling_flags
from .light_groups import emitter_groups
from .light_type import PlacedLight
from .linking import ALL_SETS, emitter_masks, link_records, uses_linking
from .record import LANES
from .registry import type_of
from .textured_emission import point_emission_data, triangle_radiance
from .triangle import TYPE as TRIANGLE
from .triangle import emissive_triangles


@dataclass
class DeviceLights:
    records: np.ndarray  # layouts.LIGHT
    power: np.ndarray  # (N,) coarse importance of each light (luminance-weighted power, W)
    types: np.ndarray  # (N,) LIGHT_* codes
    source: np.ndarray  # (N,) index into scene.lights, len(scene.lights) for the world, -1 - triangle index for
    # emissive triangles
    data: np.ndarray = field(default_factory=lambda: np.zeros(0, np.float32))  # floats after the records (the
    # environment's map and table, lights/environment.py)
    environment: env_light.PackedMap | None = None

    def device_parts(self) -> list[np.ndarray]:
        """What the light buffer holds, in order: the records, then `data` (buffers.upload_parts)."""
        return [self.records, self.data] if len(self.data) else [self.records]

    def device_array(self) -> np.ndarray:
        """What the light buffer holds as one array (a copy when there is `data`)."""
        if len(self.data) == 0:
            return self.records
        return np.concatenate([self.records.view(np.float32).reshape(-1), self.data])

    def __len__(self) -> int:
        return len(self.records)

    @property
    def type_set(self) -> set[int]:
        return {int(t) for t in np.unique(self.types)}


def scene_lights(scene: Scene, frame: int, world=None, area_sampling: str = "area",
                 environment_table: str | None = None) -> DeviceLights:
    """Device light records for `frame`: the scene's lights first (in order), then emissive triangles, flagged for
    the density `area_sampling` asks for (area_sampling.py); the world's sampling table of kind
    `environment_table` (None: the default for its size, lights/environment.py)."""
    if world is None:
        world = scene.world_triangles(frame)
    recs: list[np.ndarray] = []
    power: list[float] = []
    types: list[int] = []
    radius = _scene_radius(world)
    sources: list[int] = []
    packed = None
    if scene.environment is not None:
        packed = env_light.packed_map(scene.environment, environment_table)
        recs.append(env_light.record(scene.environment, packed, frame))
        power.append(env_light.power(scene.environment, packed, frame, radius))
        types.append(env_light.TYPE.code)
        sources.append(len(scene.lights))
    for lt in scene.lights:
        rgb_power = np.asarray(lt.color, dtype=np.float64) * lt.power_at(frame)
        placed = PlacedLight(lt, Scene.at(lt.transforms, frame), rgb_power, radius)
        kind = type_of(lt)
        recs.append(kind.record(placed))
        power.append(kind.power(placed))
        types.append(kind.code)
        sources.append(len(sources) - (packed is not None))
    tri_recs, tri_power, tri_src = emissive_triangles(world, triangle_radiance(scene, world))
    all_recs = np.concatenate([np.array(recs, np.float32).reshape(-1, LANES), tri_recs]) if recs else tri_recs
    records = np.zeros(len(all_recs), L.LIGHT)
    flat = records.view(np.float32).reshape(-1, LANES)
    flat[:] = all_recs
    if packed is not None:
        env_light.place_data(flat, 0, packed)
    all_types = np.concatenate([np.array(types, np.int64), np.full(len(tri_recs), TRIANGLE.code, np.int64)])
    apply_sampling_flags(records, all_types, area_sampling)
    all_sources = np.concatenate([np.array(sources, np.int64), tri_src])
    data = env_light.data(packed) if packed is not None else np.zeros(0, np.float32)
    textured = point_emission_data(scene, world, flat, all_sources, len(data))
    if len(textured):
        data = np.concatenate([data, textured])
    if uses_linking(scene) or scene.light_groups:  # after the textures' blocks: link records index whole records
        masks = emitter_masks(scene, all_sources, world.object) if uses_linking(scene) else \
            [(ALL_SETS, ALL_SETS)] * len(all_sources)
        groups = emitter_groups(scene, all_sources, world.object) if scene.light_groups else None
        data = link_records(records, data, masks, groups)
    return DeviceLights(records, np.concatenate([np.array(power, np.float64), tri_power]), all_types, all_sources,
                        data, packed)


def _scene_radius(world) -> float:
    if len(world) == 0:
        return 1.0
    pts = np.concatenate([world.v0, world.v1, world.v2])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    return max(0.5 * float(np.linalg.norm(hi - lo)), 1e-3)
