"""A light object as Blender describes it: point, spot, sun or area, with its colour, power (W; the sun's strength
in W/m^2), shape and transforms per frame. Emissive meshes are lights too, made from their materials
(lights/triangle.py)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..environment.world import emitter_problem
from .errors import SceneError
from .linking import Linking
from .transforms import as_transforms, check_basis

LIGHT_TYPES = ("point", "spot", "sun", "area")


AREA_SHAPES = ("SQUARE", "RECTANGLE", "DISK", "ELLIPSE")


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
    linking: Linking = field(default_factory=Linking)  # light and shadow linking (scene/linking.py)
    lightgroup: str = ""  # the light group (Scene.light_groups) its light counts in: Object > Shading > Light Group

    def __post_init__(self) -> None:
        self.transforms = as_transforms(self.transforms, f"light {self.name!r}")
        if self.power_per_frame is not None:
            self.power_per_frame = np.asarray(self.power_per_frame, dtype=np.float64).reshape(-1)

    def power_at(self, frame: int) -> float:
        if self.power_per_frame is None or len(self.power_per_frame) == 0:
            return float(self.power)
        return float(self.power) * float(self.power_per_frame[min(int(frame), len(self.power_per_frame) - 1)])

    def validate(self) -> None:
        """Raise SceneError naming the light and the bad field."""
        self.transforms = as_transforms(self.transforms, f"light {self.name!r}")
        label = f"light {self.name!r}"
        self.linking.validate(label)
        if self.type not in LIGHT_TYPES:
            raise SceneError(f"{label}: type must be one of {LIGHT_TYPES}, got {self.type!r}")
        if not np.all(np.isfinite(self.transforms)):
            raise SceneError(f"{label}: transform contains NaN or Inf")
        check_basis(self.transforms, label)
        problem = emitter_problem(self.color, self.power, self.power_per_frame, "power/strength", "power_per_frame")
        if problem:
            raise SceneError(f"{label}: {problem}")
        for what in ("radius", "angle", "size", "size_y", "spot_blend"):
            v = getattr(self, what)
            if not math.isfinite(v) or v < 0:
                raise SceneError(f"{label}: {what} must be finite and >= 0, got {v!r}")
        if self.type == "spot" and not (0 < self.spot_size <= math.pi):
            raise SceneError(f"{label}: spot_size must be in (0, pi], got {self.spot_size!r}")
        if self.type == "sun" and self.angle >= math.pi:
            raise SceneError(f"{label}: angle must be below pi, got {self.angle!r}")
        if self.type == "area":
            if self.shape not in AREA_SHAPES:
                raise SceneError(f"{label}: shape must be one of {AREA_SHAPES}, got {self.shape!r}")
            if self.size <= 0 or (self.shape in ("RECTANGLE", "ELLIPSE") and self.size_y <= 0):
                raise SceneError(f"{label}: area light size must be > 0")
