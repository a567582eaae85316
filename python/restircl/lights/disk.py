"""Disk lights (opencl/lights/disk.h): Blender's disk and ellipse area lights."""

from __future__ import annotations

import math

import numpy as np

from ..scene.light import Light
from . import area
from .light_type import PlacedLight, SceneLightType
from .record import lanes


def accepts(lt: Light) -> bool:
    return lt.type == "area" and lt.shape in ("DISK", "ELLIPSE")


def _area(s: PlacedLight) -> float:
    ux, vy = area.axes(s)
    return math.pi * 0.25 * float(np.linalg.norm(np.cross(ux, vy)))


def record(s: PlacedLight) -> np.ndarray:
    ux, vy = area.axes(s)
    a = _area(s)
    # semi-axes in the order that makes cross(axis_u, axis_v) point along local -Z, the emitting side
    return lanes(TYPE.code, p=s.matrix[:3, 3], a=0.5 * vy, b=0.5 * ux, b_w=a, radiance=area.radiance(s, a))


def power(s: PlacedLight) -> float:
    return area.power(s, _area(s))


TYPE = SceneLightType("disk", code=2, flag="HAS_DISK_LIGHTS", accepts=accepts, record=record, power=power)
