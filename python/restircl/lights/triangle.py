"""Emissive triangles (mesh lights, opencl/lights/triangle.h): one record per triangle whose material emits,
two-sided like Cycles' emission shader, radiance colour * strength."""

from __future__ import annotations

import math

import numpy as np

from .light_type import LightType
from .record import FLAG_TWO_SIDED, LANES, LUMINANCE, lanes

TYPE = LightType("triangle", code=0, flag="HAS_TRIANGLE_LIGHTS")


def emissive_triangles(world, radiance: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Records (n, 16), power (n,) and source (n,: -1 - triangle index) of the triangles of `world`
    (scene.WorldTriangles) whose material has radiance > 0; `radiance` is (materials, 3)."""
    if not (len(world) and len(radiance)):
        return np.zeros((0, LANES), np.float32), np.zeros(0), np.zeros(0, np.int64)
    le = radiance[world.material]
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
