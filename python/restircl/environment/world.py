"""The world light: Blender's World > Background (a colour, or an equirectangular image, times a strength).

This module is the scene model's side of it (what scripts and the add-on fill, and its validation); the device
light type, its importance-sampling tables and the kernels that use it live beside the other light types.

Directions follow Blender's equirectangular mapping of the World's default texture vector (Z up; the column from
the azimuth atan2(y, x), the row from the elevation, as Cycles maps them: the tests check it against Cycles),
optionally turned by `rotation` (a Mapping node's rotation, a 3x3 matrix applied to the world direction before the
lookup).
Image rows run top to bottom, as numpy and image files store them: row 0 is the zenith.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

#: Environment.interpolation's values (Blender's Cubic and Smart are read as Linear by the add-on's exporter)
INTERPOLATIONS = ("Closest", "Linear")


class WorldError(ValueError):
    """The environment is unusable; the message names the world. Scene.validate raises it as a SceneError."""


def emitter_problem(color, strength: float, per_frame: np.ndarray | None, strength_name: str,
                    per_frame_name: str) -> str | None:
    """What is wrong with an emitter's colour, strength and per-frame multipliers (a light's or the world's), or
    None: the checks Scene.validate and Environment.validate share."""
    col = np.asarray(color, dtype=np.float64)
    if col.shape != (3,) or not np.all(np.isfinite(col)) or np.any(col < 0):
        return f"color must be 3 finite numbers >= 0, got {color!r}"
    if not math.isfinite(strength) or strength < 0:
        return f"{strength_name} must be finite and >= 0, got {strength!r}"
    if per_frame is not None and (not np.all(np.isfinite(per_frame)) or np.any(per_frame < 0)):
        return f"{per_frame_name} must be finite and >= 0"
    return None


@dataclass
class Environment:
    name: str = "World"
    color: tuple[float, float, float] = (0.05, 0.05, 0.05)  # linear RGB without an image (an image replaces it)
    strength: float = 1.0  # Background strength (radiance = color * image * strength)
    image: np.ndarray | None = None  # (H, W, 3) or (H, W, 4) linear RGB(A), equirectangular, row 0 = zenith
    path: str | None = None  # an image file (EXR, HDR, PNG, ...) read instead of `image` when image is None
    rotation: np.ndarray | None = None  # (3, 3) rotation of the lookup direction (Mapping node), or None
    visible_camera: bool = True  # camera rays that miss the geometry see the world (Film > Transparent: alpha 0)
    strength_per_frame: np.ndarray | None = None  # optional (F,) multiplier of strength
    lightgroup: str = ""  # the light group (Scene.light_groups) its light counts in: World > Light Group
    # how the image is read between texel centres, as the Environment Texture's Interpolation in Blender: "Closest"
    # (texel by texel) or "Linear" (bilinear, Blender's default; wrapping across the seam and over the poles, as
    # Cycles' Environment Texture, whose extension is Repeat both ways)
    interpolation: str = "Closest"

    def __post_init__(self) -> None:
        if self.strength_per_frame is not None:
            self.strength_per_frame = np.asarray(self.strength_per_frame, dtype=np.float64).reshape(-1)

    def strength_at(self, frame: int) -> float:
        if self.strength_per_frame is None or len(self.strength_per_frame) == 0:
            return float(self.strength)
        return float(self.strength) * float(self.strength_per_frame[min(int(frame), len(self.strength_per_frame) - 1)])

    def validate(self) -> Environment:
        """Raise WorldError naming the world for what cannot be rendered; return self.

        Texel values (NaN, Inf, negative) are not checked here: the packer counts and zeroes them with a warning,
        so one bad texel never fails a render."""
        label = f"world {self.name!r}"
        problem = emitter_problem(self.color, self.strength, self.strength_per_frame, "strength",
                                  "strength_per_frame")
        if problem:
            raise WorldError(f"{label}: {problem}")
        if self.image is not None:
            shape = np.shape(self.image)
            if len(shape) != 3 or shape[2] not in (3, 4) or shape[0] < 1 or shape[1] < 1:
                raise WorldError(f"{label}: image must have shape (H, W, 3) or (H, W, 4), got {shape}")
        elif self.path is not None and not Path(self.path).is_file():
            raise WorldError(f"{label}: image file {self.path!r} not found")
        if self.interpolation not in INTERPOLATIONS:
            raise WorldError(f"{label}: interpolation must be one of {INTERPOLATIONS}, got {self.interpolation!r}")
        if self.rotation is not None:
            r = np.asarray(self.rotation, dtype=np.float64)
            if r.shape != (3, 3) or not np.all(np.isfinite(r)) or not np.allclose(r @ r.T, np.eye(3), atol=1e-5):
                raise WorldError(f"{label}: rotation must be a finite 3x3 rotation matrix")
        return self
