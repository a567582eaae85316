"""Spot lights (opencl/lights/spot.h): a sphere light (sphere.py) masked by a cone of Blender's spot size with a
smoothstep blend; the cone only masks, it does not concentrate the power."""

from __future__ import annotations

import math

import numpy as np

from ..scene.light import Light
from .light_type import PlacedLight, SceneLightType
from .record import LUMINANCE, lanes, unit
from .sphere import intensity, sphere_lanes


def accepts(lt: Light) -> bool:
    return lt.type == "spot"


def _cos_outer(s: PlacedLight) -> float:
    return math.cos(s.light.spot_size / 2.0)


def record(s: PlacedLight) -> np.ndarray:
    cos_outer = _cos_outer(s)
    axis = unit(-s.matrix[:3, 2])  # the light shines along its local -Z
    blend_width = (1.0 - cos_outer) * s.light.spot_blend
    return lanes(TYPE.code, **sphere_lanes(s), a=axis, b=(cos_outer, blend_width, 0.0))


def power(s: PlacedLight) -> float:
    return float(LUMINANCE @ intensity(s)) * 2.0 * math.pi * (1.0 - _cos_outer(s))


TYPE = SceneLightType("spot", code=4, flag="HAS_SPOT_LIGHTS", accepts=accepts, record=record, power=power)
