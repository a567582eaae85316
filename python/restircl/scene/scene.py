"""The scene model that scripts and the Blender add-on fill: meshes, materials, lights, a camera, a world, animation.

Conventions follow Blender: right-handed, Z up; a camera looks along its local -Z with +Y up; a light points
along its local -Z; transforms are 4x4 object-to-world matrices, one per frame (or one for all frames).
Light units follow Blender too (see docs/units.md): power in W for point, spot and area lights, strength in
W/m^2 for the sun, emission colour * strength (radiance) for emissive materials. Each part validates itself
(render/camera.py, mesh.py, light.py, materials/check.py, environment/world.py); a bad one raises SceneError naming it.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..environment.world import Environment, WorldError
from ..materials.check import MaterialError, check_material
from ..materials.material import Material
from .camera import Camera
from .errors import SceneError
from .file import load_scene, save_scene
from .interpolation import transform_at
from .light import Light
from .mesh import Mesh


@dataclass
class Scene:
    meshes: list[Mesh] = field(default_factory=list)
    materials: list[Material] = field(default_factory=list)
    lights: list[Light] = field(default_factory=list)
    camera: Camera | None = None
    name: str = "scene"
    environment: Environment | None = None  # the world light (None: camera rays that miss see black)
    frame_count: int | None = None  # default: the longest animation among camera, meshes and lights
    # the view layer's light groups: one pass each ("Combined_<name>") of the light of the emitters in it
    light_groups: list[str] = field(default_factory=list)

    # ---- animation ---------------------------------------------------------------------------------

    @property
    def frames(self) -> int:
        if self.frame_count is not None:
            return int(self.frame_count)
        n = 1
        if self.camera is not None:
            n = max(n, self.camera.transforms.shape[0])
        for obj in [*self.meshes, *self.lights]:
            n = max(n, obj.transforms.shape[0])
        return n

    @property
    def has_moving_objects(self) -> bool:
        return any(m.animated or m.deforms for m in self.meshes)

    @property
    def has_moving_lights(self) -> bool:
        return any(
            (lt.transforms.shape[0] > 1 and not np.allclose(lt.transforms, lt.transforms[:1]))
            or lt.power_per_frame is not None
            for lt in self.lights
        ) or (self.environment is not None and self.environment.strength_per_frame is not None)

    @staticmethod
    def at(transforms: np.ndarray, frame: float) -> np.ndarray:
        """The transform at `frame`; between two frames (a shutter's time) interpolated (scene/interpolation.py)."""
        return transform_at(transforms, frame)

    # ---- validation --------------------------------------------------------------------------------

    def validate(self) -> Scene:
        """Raise SceneError naming the first bad object; return self when the scene is usable."""
        if self.camera is None:
            raise SceneError("the scene has no camera")
        self.camera.validate()
        for i, mat in enumerate(self.materials):
            try:
                check_material(mat)
            except MaterialError as exc:
                raise SceneError(f"material {i} {mat.name!r}: {exc}") from None
        for mesh in self.meshes:
            mesh.validate(len(self.materials))
        for lt in self.lights:
            lt.validate()
        if self.environment is not None:
            try:
                self.environment.validate()
            except WorldError as exc:
                raise SceneError(str(exc)) from None
        if self.frame_count is not None and int(self.frame_count) < 1:
            raise SceneError(f"frame_count must be >= 1, got {self.frame_count!r}")
        return self

    # ---- per-frame world-space data ------------------------------------------------------------------

    def world_triangles(self, frame: int) -> WorldTriangles:
        """All triangles in world space at `frame`; degenerate ones are dropped with a warning."""
        v0s, v1s, v2s, mats, objs, prims = [], [], [], [], [], []
        dropped: dict[str, int] = {}
        for obj, mesh in enumerate(self.meshes):
            if len(mesh.triangles) == 0:
                continue
            m = self.at(mesh.transforms, frame)
            wv = mesh.vertices_at(frame) @ m[:3, :3].T + m[:3, 3]
            t = mesh.triangles
            a, b, c = wv[t[:, 0]], wv[t[:, 1]], wv[t[:, 2]]
            area2 = np.linalg.norm(np.cross(b - a, c - a), axis=1)
            ok = np.isfinite(area2) & (area2 > 0)
            # a triangle whose float32 edges vanish is degenerate on the device too
            a32, b32, c32 = a.astype(np.float32), b.astype(np.float32), c.astype(np.float32)
            ok &= np.linalg.norm(np.cross(b32 - a32, c32 - a32).astype(np.float64), axis=1) > 0
            if not np.all(ok):
                dropped[mesh.name] = int((~ok).sum())
            idx = np.nonzero(ok)[0]
            v0s.append(a[idx])
            v1s.append(b[idx])
            v2s.append(c[idx])
            mats.append(mesh.material_ids[idx])
            objs.append(np.full(len(idx), obj, np.int64))
            prims.append(idx)
        if dropped:
            names = ", ".join(f"{k!r} ({v})" for k, v in dropped.items())
            warnings.warn(f"dropped degenerate triangles: {names}", stacklevel=2)
        if not v0s:
            z3 = np.zeros((0, 3))
            zi = np.zeros(0, np.int64)
            return WorldTriangles(z3, z3, z3, zi, zi, zi)
        return WorldTriangles(
            np.concatenate(v0s), np.concatenate(v1s), np.concatenate(v2s),
            np.concatenate(mats), np.concatenate(objs), np.concatenate(prims),
        )

    @property
    def triangle_count(self) -> int:
        return int(sum(len(m.triangles) for m in self.meshes))

    # ---- files (the format: file.py) ---------------------------------------------------------

    def save(self, path: str | Path) -> None:
        """Write the scene as one versioned .npz file (no pickles)."""
        save_scene(self, path)

    @classmethod
    def load(cls, path: str | Path) -> Scene:
        """Read a scene written by save(); a corrupt or foreign file raises SceneFileError."""
        return load_scene(path, cls)


@dataclass
class WorldTriangles:
    v0: np.ndarray
    v1: np.ndarray
    v2: np.ndarray
    material: np.ndarray
    object: np.ndarray
    prim: np.ndarray  # index within its mesh

    def __len__(self) -> int:
        return len(self.v0)
