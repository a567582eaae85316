"""Sphere lights (opencl/lights/sphere.h): Blender's point light. Power P gives the intensity I = P / (4 pi) per
colour channel; with radius r > 0 the emitter has radiance I / (pi r^2) and is a sphere (soft falloff off) or,
Blender's default soft falloff, a disk of radius r facing the shading point (irradiance I cos / (d^2 + r^2))."""

from __future__ import annotations

import math
from typing import TypedDict

import numpy as np

from ..scene.light import Light
from .light_type import PlacedLight, SceneLightType
from .record import LUMINANCE, lanes

#: LIGHT_FLAG_SOFT_FALLOFF (opencl/codes.h): radius > 0 and a disk facing the shading point (Blender's default)
FLAG_SOFT_FALLOFF = 2


class SphereLanes(TypedDict):
    p: np.ndarray  # centre
    a_w: float  # radius; 0: a point
    radiance: np.ndarray  # radiance of the surface, or the point's intensity
    flags: int


def accepts(lt: Light) -> bool:
    return lt.type == "point"


def intensity(s: PlacedLight) -> np.ndarray:
    return s.rgb_power / (4.0 * math.pi)


def sphere_lanes(s: PlacedLight) -> SphereLanes:
    """The lanes a sphere and a spot share."""
    i = intensity(s)
    radius = float(s.light.radius)
    le = i / (math.pi * radius * radius) if radius > 0 else i
    flags = FLAG_SOFT_FALLOFF if (s.light.soft_falloff and radius > 0) else 0
    return SphereLanes(p=s.matrix[:3, 3], a_w=radius, radiance=le, flags=flags)


def record(s: PlacedLight) -> np.ndarray:
    return lanes(TYPE.code, **sphere_lanes(s))


def power(s: PlacedLight) -> float:
    return float(LUMINANCE @ intensity(s)) * 4.0 * math.pi


TYPE = SceneLightType("sphere", code=3, flag="HAS_SPHERE_LIGHTS", accepts=accepts, record=record, power=power)
