"""The scene model that scripts and the Blender add-on fill: meshes, materials, lights, a camera, animation.

Conventions follow Blender: right-handed, Z up; a camera looks along its local -Z with +Y up; a light points
along its local -Z; transforms are 4x4 object-to-world matrices, one per frame (or one for all frames).
Light units follow Blender too (see docs/units.md): power in W for point, spot and area lights, strength in
W/m^2 for the sun, emission colour * strength (radiance) for emissive materials.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .environment import Environment, WorldError, emitter_problem
from .material import Material
from .material_check import MaterialError, check_material

MAX_RESOLUTION = 16384
LIGHT_TYPES = ("point", "spot", "sun", "area")
AREA_SHAPES = ("SQUARE", "RECTANGLE", "DISK", "ELLIPSE")
SENSOR_FITS = ("AUTO", "HORIZONTAL", "VERTICAL")
CAMERA_TYPES = ("PERSP", "ORTHO")  # layouts.CAMERA_KINDS


class SceneError(ValueError):
    """The scene is invalid; the message names the offending object."""


class SceneFileError(SceneError):
    """A scene file is corrupt, foreign or of an unknown version."""


def _as_transforms(value: np.ndarray | None, what: str) -> np.ndarray:
    if value is None:
        return np.eye(4, dtype=np.float64)[None]
    m = np.asarray(value, dtype=np.float64)
    if m.shape == (4, 4):
        m = m[None]
    if m.ndim != 3 or m.shape[1:] != (4, 4) or m.shape[0] < 1:
        raise SceneError(f"{what}: transforms must have shape (4, 4) or (F, 4, 4), got {m.shape}")
    return m


def translation(x: float, y: float, z: float) -> np.ndarray:
    m = np.eye(4)
    m[:3, 3] = (x, y, z)
    return m


def look_at(eye: np.ndarray | tuple, target: np.ndarray | tuple, up: tuple = (0.0, 0.0, 1.0)) -> np.ndarray:
    """A Blender-style object matrix at `eye` whose -Z axis points at `target` (for cameras and lights)."""
    eye = np.asarray(eye, dtype=np.float64)
    fwd = np.asarray(target, dtype=np.float64) - eye
    n = np.linalg.norm(fwd)
    if not np.isfinite(n) or n == 0:
        raise SceneError("look_at: eye and target coincide or are not finite")
    fwd /= n
    upv = np.asarray(up, dtype=np.float64)
    right = np.cross(fwd, upv)
    if np.linalg.norm(right) < 1e-9:
        right = np.cross(fwd, np.array([0.0, 1.0, 0.0]) if abs(fwd[1]) < 0.9 else np.array([1.0, 0.0, 0.0]))
    right /= np.linalg.norm(right)
    true_up = np.cross(right, fwd)
    m = np.eye(4)
    m[:3, 0] = right
    m[:3, 1] = true_up
    m[:3, 2] = -fwd
    m[:3, 3] = eye
    return m


@dataclass
class Mesh:
    name: str
    vertices: np.ndarray  # (V, 3) object space
    triangles: np.ndarray  # (T, 3) vertex indices
    material_ids: np.ndarray | int = 0  # (T,) or one id for all triangles
    transforms: np.ndarray | None = None  # (4, 4) or (F, 4, 4) object-to-world
    uvs: np.ndarray | None = None  # (T, 3, 2) per-corner UV map (texture coordinates "uv", normal maps)
    normals: np.ndarray | None = None  # (T, 3, 3) per-corner object-space shading normals (smooth shading)

    def __post_init__(self) -> None:
        self.vertices = np.asarray(self.vertices, dtype=np.float64).reshape(-1, 3)
        self.triangles = np.asarray(self.triangles, dtype=np.int64).reshape(-1, 3)
        ids = np.asarray(self.material_ids, dtype=np.int64)
        self.material_ids = np.full(len(self.triangles), int(ids), np.int64) if ids.ndim == 0 else ids.reshape(-1)
        self.transforms = _as_transforms(self.transforms, f"mesh {self.name!r}")

    @property
    def animated(self) -> bool:
        return self.transforms.shape[0] > 1 and not np.allclose(self.transforms, self.transforms[:1])


@dataclass
class Light:
    name: str
    type: str  # point | spot | sun | area
    color: tuple[float, float, float] = (1.0, 1.0, 1.0)
    power: float = 100.0  # W (point, spot, area); W/m^2 (sun strength)
    transforms: np.ndarray | None = None  # (4, 4) or (F, 4, 4); the light points along local -Z
    radius: float = 0.0  # point, spot: Blender's shadow_soft_size
    soft_falloff: bool = True  # point, spot with radius > 0: Blender's default "soft falloff" (see docs/units.md)
    spot_size: float = math.pi / 4  # full cone angle (rad)
    spot_blend: float = 0.15
    angle: float = 0.0  # sun: angular diameter (rad)
    shape: str = "SQUARE"  # area: SQUARE | RECTANGLE | DISK | ELLIPSE
    size: float = 1.0  # area: size along local X
    size_y: float = 1.0  # area: size along local Y (RECTANGLE, ELLIPSE)
    power_per_frame: np.ndarray | None = None  # optional (F,) multiplier of power, e.g. to switch a light off
    visible_camera: bool = False  # Ray Visibility > Camera: the camera sees its shape (off: Blender's default)

    def __post_init__(self) -> None:
        self.transforms = _as_transforms(self.transforms, f"light {self.name!r}")
        if self.power_per_frame is not None:
            self.power_per_frame = np.asarray(self.power_per_frame, dtype=np.float64).reshape(-1)

    def power_at(self, frame: int) -> float:
        if self.power_per_frame is None or len(self.power_per_frame) == 0:
            return float(self.power)
        return float(self.power) * float(self.power_per_frame[min(frame, len(self.power_per_frame) - 1)])


@dataclass
class Camera:
    transforms: np.ndarray | None = None  # (4, 4) or (F, 4, 4) camera-to-world; looks along -Z
    width: int = 640
    height: int = 360
    lens: float = 50.0  # focal length (mm)
    sensor_width: float = 36.0
    sensor_height: float = 24.0
    sensor_fit: str = "AUTO"
    shift_x: float = 0.0
    shift_y: float = 0.0
    cuts: tuple[int, ...] = ()  # frames at which the camera cuts (history is reset)
    type: str = "PERSP"  # Blender's camera type: PERSP or ORTHO
    ortho_scale: float = 6.0  # ORTHO: the view's extent (world units) along the fitted axis, as in Blender

    def __post_init__(self) -> None:
        self.transforms = _as_transforms(self.transforms, "camera")
        self.cuts = tuple(int(c) for c in self.cuts)

    def set_fov(self, fov: float, axis: str = "horizontal") -> None:
        """Set the field of view (radians) along an axis by choosing the focal length; sensor fit follows."""
        if axis == "horizontal":
            self.sensor_fit = "HORIZONTAL"
            self.lens = self.sensor_width / (2.0 * math.tan(fov / 2.0))
        else:
            self.sensor_fit = "VERTICAL"
            self.lens = self.sensor_height / (2.0 * math.tan(fov / 2.0))

    def tan_half_fov(self) -> tuple[float, float, float, float]:
        """(tan half horizontal fov, tan half vertical fov, shift x, shift y in tan units), Blender's rules; an
        orthographic camera's view plane instead (view_plane)."""
        return self.view_plane()

    def view_plane(self) -> tuple[float, float, float, float]:
        """Half the view plane (x, y) and its shift (x, y), Blender's rules: in tan units at unit distance for a
        perspective camera, in world units for an orthographic one."""
        w, h = float(self.width), float(self.height)
        fit = self.sensor_fit
        if fit == "AUTO":
            fit = "HORIZONTAL" if w >= h else "VERTICAL"
            sensor = self.sensor_width
        else:
            sensor = self.sensor_width if fit == "HORIZONTAL" else self.sensor_height
        # half the fitted dimension: the tan of half its fov, or half the orthographic scale
        half = 0.5 * self.ortho_scale if self.type == "ORTHO" else 0.5 * sensor / self.lens
        if fit == "HORIZONTAL":
            tx, ty = half, half * h / w
        else:
            tx, ty = half * w / h, half
        # Blender's shift is a fraction of the fitted dimension of the view plane (checked against Blender's
        # own projection by tests/test_blender_camera.py).
        return tx, ty, 2.0 * self.shift_x * half, 2.0 * self.shift_y * half


@dataclass
class Scene:
    meshes: list[Mesh] = field(default_factory=list)
    materials: list[Material] = field(default_factory=list)
    lights: list[Light] = field(default_factory=list)
    camera: Camera | None = None
    name: str = "scene"
    environment: Environment | None = None  # the world light (None: camera rays that miss see black)
    frame_count: int | None = None  # default: the longest animation among camera, meshes and lights

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
        return any(m.animated for m in self.meshes)

    @property
    def has_moving_lights(self) -> bool:
        return any(
            (lt.transforms.shape[0] > 1 and not np.allclose(lt.transforms, lt.transforms[:1]))
            or lt.power_per_frame is not None
            for lt in self.lights
        ) or (self.environment is not None and self.environment.strength_per_frame is not None)

    @staticmethod
    def at(transforms: np.ndarray, frame: int) -> np.ndarray:
        return transforms[min(max(frame, 0), transforms.shape[0] - 1)]

    # ---- validation --------------------------------------------------------------------------------

    def validate(self) -> Scene:
        """Raise SceneError naming the first bad object; return self when the scene is usable."""
        cam = self.camera
        if cam is None:
            raise SceneError("the scene has no camera")
        # attributes may have been replaced after construction: normalise their shapes again
        cam.transforms = _as_transforms(cam.transforms, "camera")
        for obj in self.meshes:
            obj.transforms = _as_transforms(obj.transforms, f"mesh {obj.name!r}")
        for obj in self.lights:
            obj.transforms = _as_transforms(obj.transforms, f"light {obj.name!r}")
        for what, v in (("width", cam.width), ("height", cam.height)):
            if not isinstance(v, (int, np.integer)) or not 1 <= int(v) <= MAX_RESOLUTION:
                raise SceneError(f"camera: {what} must be an integer in 1..{MAX_RESOLUTION}, got {v!r}")
        if not np.all(np.isfinite(cam.transforms)):
            raise SceneError("camera: transform contains NaN or Inf")
        for what, v in (("lens", cam.lens), ("sensor_width", cam.sensor_width), ("sensor_height", cam.sensor_height)):
            if not math.isfinite(v) or v <= 0:
                raise SceneError(f"camera: {what} must be finite and positive, got {v!r}")
        if not (math.isfinite(cam.shift_x) and math.isfinite(cam.shift_y)):
            raise SceneError("camera: shift is not finite")
        if cam.type not in CAMERA_TYPES:
            raise SceneError(f"camera: type must be one of {CAMERA_TYPES}, got {cam.type!r}")
        if cam.type == "ORTHO" and not (math.isfinite(cam.ortho_scale) and cam.ortho_scale > 0):
            raise SceneError(f"camera: ortho_scale must be finite and positive, got {cam.ortho_scale!r}")
        if cam.sensor_fit not in SENSOR_FITS:
            raise SceneError(f"camera: sensor_fit must be one of {SENSOR_FITS}, got {cam.sensor_fit!r}")
        _check_basis(cam.transforms, "camera")
        for i, mat in enumerate(self.materials):
            try:
                check_material(mat)
            except MaterialError as exc:
                raise SceneError(f"material {i} {mat.name!r}: {exc}") from None
        n_mat = len(self.materials)
        for mesh in self.meshes:
            label = f"mesh {mesh.name!r}"
            if not np.all(np.isfinite(mesh.vertices)):
                raise SceneError(f"{label}: vertices contain NaN or Inf")
            if not np.all(np.isfinite(mesh.transforms)):
                raise SceneError(f"{label}: transform contains NaN or Inf")
            if len(mesh.triangles) and (mesh.triangles.min() < 0 or mesh.triangles.max() >= len(mesh.vertices)):
                raise SceneError(f"{label}: triangle vertex index out of range 0..{len(mesh.vertices) - 1}")
            if len(mesh.material_ids) != len(mesh.triangles):
                raise SceneError(f"{label}: {len(mesh.material_ids)} material ids for {len(mesh.triangles)} triangles")
            if len(mesh.material_ids) and (mesh.material_ids.min() < 0 or mesh.material_ids.max() >= n_mat):
                raise SceneError(f"{label}: material id out of range 0..{n_mat - 1}")
            for what, corner in (("uvs", 2), ("normals", 3)):
                a = getattr(mesh, what)
                if a is not None and (np.shape(a) != (len(mesh.triangles), 3, corner) or not np.all(np.isfinite(a))):
                    raise SceneError(f"{label}: {what} must be finite, shape ({len(mesh.triangles)}, 3, {corner}), "
                                     f"got shape {np.shape(a)}")
        for lt in self.lights:
            label = f"light {lt.name!r}"
            if lt.type not in LIGHT_TYPES:
                raise SceneError(f"{label}: type must be one of {LIGHT_TYPES}, got {lt.type!r}")
            if not np.all(np.isfinite(lt.transforms)):
                raise SceneError(f"{label}: transform contains NaN or Inf")
            _check_basis(lt.transforms, label)
            problem = emitter_problem(lt.color, lt.power, lt.power_per_frame, "power/strength", "power_per_frame")
            if problem:
                raise SceneError(f"{label}: {problem}")
            for what in ("radius", "angle", "size", "size_y", "spot_blend"):
                v = getattr(lt, what)
                if not math.isfinite(v) or v < 0:
                    raise SceneError(f"{label}: {what} must be finite and >= 0, got {v!r}")
            if lt.type == "spot" and not (0 < lt.spot_size <= math.pi):
                raise SceneError(f"{label}: spot_size must be in (0, pi], got {lt.spot_size!r}")
            if lt.type == "sun" and lt.angle >= math.pi:
                raise SceneError(f"{label}: angle must be below pi, got {lt.angle!r}")
            if lt.type == "area":
                if lt.shape not in AREA_SHAPES:
                    raise SceneError(f"{label}: shape must be one of {AREA_SHAPES}, got {lt.shape!r}")
                if lt.size <= 0 or (lt.shape in ("RECTANGLE", "ELLIPSE") and lt.size_y <= 0):
                    raise SceneError(f"{label}: area light size must be > 0")
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
            wv = mesh.vertices @ m[:3, :3].T + m[:3, 3]
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

    # ---- files (the format: scene_file.py) ---------------------------------------------------------

    def save(self, path: str | Path) -> None:
        """Write the scene as one versioned .npz file (no pickles)."""
        from .scene_file import save_scene  # here, not at the top: scene_file builds on this module

        save_scene(self, path)

    @classmethod
    def load(cls, path: str | Path) -> Scene:
        """Read a scene written by save(); a corrupt or foreign file raises SceneFileError."""
        from .scene_file import load_scene  # see save

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


def _check_basis(transforms: np.ndarray, label: str) -> None:
    det = np.linalg.det(transforms[:, :3, :3])
    if np.any(~np.isfinite(det)) or np.any(np.abs(det) < 1e-30):
        raise SceneError(f"{label}: transform is singular (zero scale)")
