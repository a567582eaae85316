"""Quad lights (opencl/lights/quad.h): Blender's square and rectangle area lights."""

from __future__ import annotations

import numpy as np

from ..scene.light import Light
from . import area
from .light_type import PlacedLight, SceneLightType
from .record import lanes


def accepts(lt: Light) -> bool:
    return lt.type == "area" and lt.shape in ("SQUARE", "RECTANGLE")


def _area(s: PlacedLight) -> float:
    ux, vy = area.axes(s)
    return float(np.linalg.norm(np.cross(ux, vy)))


def record(s: PlacedLight) -> np.ndarray:
    ux, vy = area.axes(s)
    corner = s.matrix[:3, 3] - 0.5 * ux - 0.5 * vy
    a = _area(s)
    # edge_u = vy, edge_v = ux: cross(edge_u, edge_v) points along local -Z, the emitting side
    return lanes(TYPE.code, p=corner, a=vy, b=ux, b_w=a, radiance=area.radiance(s, a))


def power(s: PlacedLight) -> float:
    return area.power(s, _area(s))


TYPE = SceneLightType("quad", code=1, flag="HAS_QUAD_LIGHTS", accepts=accepts, record=record, power=power)
