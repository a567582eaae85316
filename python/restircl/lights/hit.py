"""What the BSDF-sampled candidates (opencl/direct/bsdf_candidates.h) need of the lights on the host side: the map
from a triangle the BVH hits (leaf order) to its emissive-triangle light, and how many analytic lights a ray is tested
against."""

from __future__ import annotations

import numpy as np

from .device_lights import DeviceLights


def triangle_lights(order: np.ndarray, lights: DeviceLights) -> np.ndarray:
    """(triangles,) int32 in BVH leaf order: the light index of each emissive triangle, -1 for the others.
    `order` is BVH.order (leaf i holds world triangle order[i]); an emissive triangle's light has source
    -1 - (its world triangle index) (lights/triangle.py)."""
    light_of_world = np.full(len(order), -1, np.int32)
    tri = np.nonzero(lights.source < 0)[0]
    light_of_world[-1 - lights.source[tri]] = tri
    return light_of_world[np.asarray(order, np.int64)]


def analytic_light_count(lights: DeviceLights) -> int:
    """The scene's analytic lights (every light that is not an emissive triangle): they come first."""
    return int(np.count_nonzero(lights.source >= 0))
