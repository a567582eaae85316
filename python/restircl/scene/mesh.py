"""A triangle mesh: object-space vertices, triangles with a material id each, transforms per frame, and optional
per-corner UVs and shading normals, and vertices that deform within a still's shutter (scene/deformation.py)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .deformation import at_time, check_deform
from .errors import SceneError
from .linking import Linking
from .transforms import as_transforms


@dataclass
class Mesh:
    name: str
    vertices: np.ndarray  # (V, 3) object space
    triangles: np.ndarray  # (T, 3) vertex indices
    material_ids: np.ndarray | int = 0  # (T,) or one id for all triangles
    transforms: np.ndarray | None = None  # (4, 4) or (F, 4, 4) object-to-world
    uvs: np.ndarray | None = None  # (T, 3, 2) per-corner UV map (texture coordinates "uv", normal maps)
    normals: np.ndarray | None = None  # (T, 3, 3) per-corner object-space shading normals (smooth shading)
    linking: Linking = field(default_factory=Linking)  # as an emitter: light and shadow linking (scene/linking.py)
    lightgroup: str = ""  # as an emitter: the light group (Scene.light_groups) its emission counts in
    pass_index: int = 0  # Object > Relations > Pass Index: the Object Index pass (render/index_passes.py)
    asset: str = ""  # the Cryptomatte asset it belongs to (Blender: the root of its parent chain); "": its own name
    attributes: dict[str, np.ndarray] | None = None  # name -> (T, 3, 4) per-corner RGBA (colour attributes)
    holdout: bool = False  # camera rays that meet it see nothing, with alpha 0 (Blender's Holdout); other rays
    # see it as it is
    camera_visible: bool = True  # off: camera rays pass through it (Ray Visibility > Camera, Indirect Only)
    # (S, V, 3) object-space vertices at the S scene frames deform_times (S,), increasing: the deformation within a
    # still's shutter, interpolated linearly between them (scene/deformation.py); None: the vertices at all times
    deform: np.ndarray | None = None
    deform_times: np.ndarray | None = None
    deform_normals: np.ndarray | None = None  # (S, T, 3, 3) the shading normals (`normals`) at deform_times

    def __post_init__(self) -> None:
        self.vertices = np.asarray(self.vertices, dtype=np.float64).reshape(-1, 3)
        self.triangles = np.asarray(self.triangles, dtype=np.int64).reshape(-1, 3)
        ids = np.asarray(self.material_ids, dtype=np.int64)
        self.material_ids = np.full(len(self.triangles), int(ids), np.int64) if ids.ndim == 0 else ids.reshape(-1)
        self.transforms = as_transforms(self.transforms, f"mesh {self.name!r}")
        if self.deform is not None:
            self.deform = np.asarray(self.deform, dtype=np.float64)
        if self.deform_times is not None:
            self.deform_times = np.asarray(self.deform_times, dtype=np.float64).reshape(-1)
        if self.deform_normals is not None:
            self.deform_normals = np.asarray(self.deform_normals, dtype=np.float64)

    @property
    def animated(self) -> bool:
        return self.transforms.shape[0] > 1 and not np.allclose(self.transforms, self.transforms[:1])

    @property
    def deforms(self) -> bool:
        return self.deform is not None

    def vertices_at(self, frame: float) -> np.ndarray:
        """The object-space vertices at `frame` (a time within a still's shutter: deformed)."""
        return at_time(self.vertices, self.deform, self.deform_times, frame)

    def normals_at(self, frame: float) -> np.ndarray | None:
        """The per-corner shading normals at `frame` (deformed; not normalised), None where the mesh has none."""
        if self.normals is None:
            return None
        return at_time(np.asarray(self.normals, np.float64), self.deform_normals, self.deform_times, frame)

    def validate(self, material_count: int) -> None:
        """Raise SceneError naming the mesh and the bad field."""
        self.transforms = as_transforms(self.transforms, f"mesh {self.name!r}")
        label = f"mesh {self.name!r}"
        self.linking.validate(label)
        if not np.all(np.isfinite(self.vertices)):
            raise SceneError(f"{label}: vertices contain NaN or Inf")
        if not np.all(np.isfinite(self.transforms)):
            raise SceneError(f"{label}: transform contains NaN or Inf")
        check_deform(self.deform, self.deform_times, self.deform_normals, (len(self.vertices), len(self.triangles)),
                     label)
        if self.deform_normals is not None and self.normals is None:
            raise SceneError(f"{label}: deform_normals without normals")
        t = self.triangles
        if len(t) and (t.min() < 0 or t.max() >= len(self.vertices)):
            raise SceneError(f"{label}: triangle vertex index out of range 0..{len(self.vertices) - 1}")
        ids = self.material_ids
        if len(ids) != len(t):
            raise SceneError(f"{label}: {len(ids)} material ids for {len(t)} triangles")
        if len(ids) and (ids.min() < 0 or ids.max() >= material_count):
            raise SceneError(f"{label}: material id out of range 0..{material_count - 1}")
        for what, corner in (("uvs", 2), ("normals", 3)):
            a = getattr(self, what)
            if a is not None and (np.shape(a) != (len(t), 3, corner) or not np.all(np.isfinite(a))):
                raise SceneError(f"{label}: {what} must be finite, shape ({len(t)}, 3, {corner}), "
                                 f"got shape {np.shape(a)}")
        for name, a in (self.attributes or {}).items():
            if not isinstance(name, str) or np.shape(a) != (len(t), 3, 4) or not np.all(np.isfinite(a)):
                raise SceneError(f"{label}: attribute {name!r} must be finite, shape ({len(t)}, 3, 4), "
                                 f"got shape {np.shape(a)}")
