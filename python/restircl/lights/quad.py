"""Quad lights (opencl/lights/quad.h): Blender's square and rectangle area lights."""

from __future__ import annotations

import numpy as np

from ..scene.light import Light
from . import area
from .bounds import Bounds
from .light_type import PlacedLight, SceneLightType
from .planar import corner_bounds, orthogonal_spans, spans
from .polygon import polygon_direct
from .record import lanes


def accepts(lt: Light) -> bool:
    return lt.type == "area" and lt.shape in ("SQUARE", "RECTANGLE")


def _area(s: PlacedLight) -> float:
    ux, vy = area.axes(s)
    return float(np.linalg.norm(np.cross(ux, vy)))


def record(s: PlacedLight) -> np.ndarray:
    edge_u, edge_v = area.emitting_spans(s)  # cross(edge_u, edge_v): the emitting side, local -Z
    corner = s.matrix[:3, 3] - 0.5 * edge_u - 0.5 * edge_v
    a = _area(s)
    return lanes(TYPE.code, p=corner, a=edge_u, b=edge_v, b_w=a, radiance=area.radiance(s, a))


def power(s: PlacedLight) -> float:
    return area.power(s, _area(s))


def _corners(lanes: np.ndarray) -> list[np.ndarray]:
    """The corners in winding order, whose normal cross(edge_u, edge_v) is the emitting side (opencl/lights/quad.h:
    origin a corner, spans the edges from it)."""
    p, a, b = spans(lanes)
    return [p, p + a, p + a + b, p + b]


def bounds(lanes: np.ndarray, flags: np.ndarray) -> Bounds:
    return corner_bounds(_corners(lanes), lanes, flags)


def solid_angle(lanes: np.ndarray, flags: np.ndarray) -> np.ndarray:
    """Rectangles: a spherical rectangle needs orthogonal edges (a sheared parallelogram keeps area sampling)."""
    return orthogonal_spans(lanes)


def analytic(x: np.ndarray, n: np.ndarray, lanes: np.ndarray, flags: np.ndarray) -> np.ndarray:
    return polygon_direct(x, n, np.stack(_corners(lanes), axis=1), flags)


TYPE = SceneLightType("quad", code=1, flag="HAS_QUAD_LIGHTS",
                      bounds=bounds, solid_angle=solid_angle, analytic=analytic,
                      accepts=accepts, record=record, power=power, has_shape=area.has_shape)
