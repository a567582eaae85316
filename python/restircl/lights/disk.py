"""Disk lights (opencl/lights/disk.h): Blender's disk and ellipse area lights."""

from __future__ import annotations

import math

import numpy as np

from ..scene.light import Light
from . import area
from .bounds import Bounds
from .light_type import PlacedLight, SceneLightType, no_closed_form
from .planar import orthogonal_spans, planar_bounds, spans
from .record import lanes


def accepts(lt: Light) -> bool:
    return lt.type == "area" and lt.shape in ("DISK", "ELLIPSE")


def _area(s: PlacedLight) -> float:
    ux, vy = area.axes(s)
    return math.pi * 0.25 * float(np.linalg.norm(np.cross(ux, vy)))


def record(s: PlacedLight) -> np.ndarray:
    axis_u, axis_v = area.emitting_spans(s)  # cross(axis_u, axis_v): the emitting side, local -Z
    a = _area(s)
    return lanes(TYPE.code, p=s.matrix[:3, 3], a=0.5 * axis_u, b=0.5 * axis_v, b_w=a, radiance=area.radiance(s, a))


def power(s: PlacedLight) -> float:
    return area.power(s, _area(s))


def bounds(lanes: np.ndarray, flags: np.ndarray) -> Bounds:
    """The ellipse centre + cos t a + sin t b reaches sqrt(a_i^2 + b_i^2) from the centre along axis i."""
    p, a, b = spans(lanes)
    ext = np.sqrt(a**2 + b**2)
    return planar_bounds(p - ext, p + ext, lanes, flags)


def solid_angle(lanes: np.ndarray, flags: np.ndarray) -> np.ndarray:
    """Ellipses with orthogonal semi-axes: sampled through their bounding rectangle (opencl/lights/disk.h)."""
    return orthogonal_spans(lanes)


TYPE = SceneLightType("disk", code=2, flag="HAS_DISK_LIGHTS",
                      bounds=bounds, solid_angle=solid_angle, analytic=no_closed_form("disk lights"),
                      accepts=accepts, record=record, power=power, has_shape=area.has_shape)
