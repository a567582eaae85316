"""Emissive triangles (mesh lights, opencl/lights/triangle.h): one record per triangle whose material emits,
two-sided like Cycles' emission shader, radiance colour * strength."""

from __future__ import annotations

import math

import numpy as np

from .bounds import Bounds
from .light_type import LightType
from .planar import corner_bounds, spans
from .polygon import polygon_direct
from .record import FLAG_TWO_SIDED, LANES, LUMINANCE, lanes


def _corners(lanes: np.ndarray) -> list[np.ndarray]:
    """v0, v1, v2 (opencl/lights/triangle.h: origin v0, spans e1, e2)."""
    p, a, b = spans(lanes)
    return [p, p + a, p + b]


def bounds(lanes: np.ndarray, flags: np.ndarray) -> Bounds:
    return corner_bounds(_corners(lanes), lanes, flags)


def solid_angle(lanes: np.ndarray, flags: np.ndarray) -> np.ndarray:
    """Every triangle is a spherical triangle (spherical_tri.h)."""
    return np.ones(len(lanes), bool)


def analytic(x: np.ndarray, n: np.ndarray, lanes: np.ndarray, flags: np.ndarray) -> np.ndarray:
    return polygon_direct(x, n, np.stack(_corners(lanes), axis=1), flags)


TYPE = LightType("triangle", code=0, flag="HAS_TRIANGLE_LIGHTS",
                 bounds=bounds, solid_angle=solid_angle, analytic=analytic)


def emissive_triangles(world, radiance: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Records (n, 16), power (n,) and source (n,: -1 - triangle index) of the triangles of `world`
    (scene.WorldTriangles) whose radiance is > 0; `radiance` is (triangles, 3) (textured_emission.py)."""
    if not len(world):
        return np.zeros((0, LANES), np.float32), np.zeros(0), np.zeros(0, np.int64)
    le = np.asarray(radiance, np.float64).reshape(len(world), 3)
    emissive = np.nonzero(np.any(le > 0, axis=1))[0]
    if not len(emissive):
        return np.zeros((0, LANES), np.float32), np.zeros(0), np.zeros(0, np.int64)
    v0 = world.v0[emissive]
    e1 = world.v1[emissive] - v0
    e2 = world.v2[emissive] - v0
    area = 0.5 * np.linalg.norm(np.cross(e1, e2), axis=1)
    records = lanes(TYPE.code, p=v0, a=e1, b=e2, b_w=area, radiance=le[emissive], flags=FLAG_TWO_SIDED,
                    count=len(emissive))
    power = (le[emissive] @ LUMINANCE) * area * math.pi * 2.0  # both sides
    return records, power, -1 - emissive
