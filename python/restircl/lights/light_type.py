"""What the host knows of a device light type: its code and feature flag, and for the types made from scene
lights, which scene lights it takes, how it packs one into a record and its power."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..scene.light import Light


@dataclass(frozen=True)
class PlacedLight:
    """A scene light at one frame: what a type's packer and power read."""

    light: Light
    matrix: np.ndarray  # (4, 4) object-to-world at the frame; the light points along its local -Z
    rgb_power: np.ndarray  # (3,) float64: colour * power at the frame (W; W/m^2 for the sun)
    scene_radius: float  # half the diagonal of the scene's bounds


@dataclass(frozen=True)
class LightType:
    name: str
    code: int  # LIGHT_<NAME> in opencl/lights/<name>.h
    flag: str  # HAS_<NAME>_LIGHTS: compiles the type's code in (render/features.py)


@dataclass(frozen=True)
class SceneLightType(LightType):
    """A type made from the scene's lights (every type but the emissive triangles, which come from geometry)."""

    accepts: Callable[[Light], bool]  # the scene lights this type packs
    record: Callable[[PlacedLight], np.ndarray]  # (16,) float32 lanes of the Light record (record.lanes)
    power: Callable[[PlacedLight], float]  # coarse importance for the light array: luminance-weighted power, W
