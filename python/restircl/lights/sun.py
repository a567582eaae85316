"""The sun (opencl/lights/sun.h). Strength S (W/m^2) and angular diameter theta: radiance S / (pi sin^2(theta / 2))
inside its cone, so that the irradiance at normal incidence is S; S itself when theta = 0."""

from __future__ import annotations

import math

import numpy as np

from ..scene.light import Light
from .light_type import PlacedLight, SceneLightType
from .record import LUMINANCE, lanes, unit


def accepts(lt: Light) -> bool:
    return lt.type == "sun"


def record(s: PlacedLight) -> np.ndarray:
    half = s.light.angle / 2.0
    omc = 2.0 * math.sin(half / 2.0) ** 2  # 1 - cos(half), exact for tiny angles
    sin2 = math.sin(half) ** 2
    le = s.rgb_power / (math.pi * sin2) if omc > 0 else s.rgb_power
    towards = unit(s.matrix[:3, 2])  # the light shines along its -Z
    return lanes(TYPE.code, a=towards, b=(math.cos(half), omc, 0.0), radiance=le)


def power(s: PlacedLight) -> float:
    """What falls on a disk of the scene's radius: the light array weighs a sun against the local lights by it."""
    return float(LUMINANCE @ s.rgb_power) * math.pi * s.scene_radius * s.scene_radius


TYPE = SceneLightType("sun", code=5, flag="HAS_SUN_LIGHTS", accepts=accepts, record=record, power=power)
