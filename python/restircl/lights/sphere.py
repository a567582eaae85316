"""Sphere lights (opencl/lights/sphere.h): Blender's point light. Power P gives the intensity I = P / (4 pi) per
colour channel; with radius r > 0 the emitter has radiance I / (pi r^2) and is a sphere (soft falloff off) or,
Blender's default soft falloff, a disk of radius r facing the shading point (irradiance I cos / (d^2 + r^2))."""

from __future__ import annotations

import math
from typing import TypedDict

import numpy as np

from ..scene.light import Light
from .bounds import Bounds, omnidirectional
from .light_type import NotAnalytic, PlacedLight, SceneLightType
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


def has_shape(lt: Light) -> bool:
    """Radius 0 is a delta: no ray meets a point."""
    return lt.radius > 0


def bounds(lanes: np.ndarray, flags: np.ndarray) -> Bounds:
    """The box of the sphere (or of every disk facing a shading point: the same ball), emitting everywhere."""
    p, r = lanes[:, 0:3], np.abs(lanes[:, 7])[:, None]
    return omnidirectional(p - r, p + r)


def solid_angle(lanes: np.ndarray, flags: np.ndarray) -> np.ndarray:
    """Soft-falloff disks (their cone, opencl/lights/sphere.h soft_disk_sample); a sphere's cone is sampled anyway."""
    return (flags & FLAG_SOFT_FALLOFF) != 0


def analytic(x: np.ndarray, n: np.ndarray, lanes: np.ndarray, flags: np.ndarray) -> np.ndarray:
    """A point: cos / d^2; a sphere of radius r: pi (r / D)^2 cos; a disk of radius r facing the point (soft
    falloff): pi r^2 / (D^2 + r^2) cos; both exact when the emitter is wholly above or below the horizon."""
    d = lanes[None, :, 0:3] - x[:, None, :]  # (P, S, 3)
    dc = np.linalg.norm(d, axis=-1)
    w = d / dc[..., None]
    cos = np.einsum("psk,pk->ps", w, n)
    rad = lanes[:, 7][None]
    soft = (flags & FLAG_SOFT_FALLOFF) != 0
    sin_a = np.where(soft[None], rad / np.sqrt(dc * dc + rad * rad), rad / dc)
    if np.any((rad > 0) & (dc <= rad)):
        raise NotAnalytic("a shading point inside a sphere light")
    if np.any((rad > 0) & (np.abs(cos) < sin_a * (1 - 1e-6))):
        raise NotAnalytic("a sphere light crosses the horizon of a shading point")
    geo = np.where(rad > 0, math.pi * sin_a**2 * cos, cos / (dc * dc))
    return np.where(cos > 0, geo, 0.0)


TYPE = SceneLightType("sphere", code=3, flag="HAS_SPHERE_LIGHTS",
                      bounds=bounds, solid_angle=solid_angle, analytic=analytic,
                      accepts=accepts, record=record, power=power, has_shape=has_shape)
