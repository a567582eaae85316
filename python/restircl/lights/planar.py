"""The planar emitters (opencl/lights/planar.h: triangle, quad, disk): a record holds an origin p, two spans a and b
and the area; the emitting side is along cross(a, b), and the other side too where the record is two-sided. What
the host computes the same way for each of them: their tree bounds and whether their spans are orthogonal."""

from __future__ import annotations

import numpy as np

from .bounds import Bounds
from .record import FLAG_TWO_SIDED


def spans(lanes: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Origin, span_u and span_v of records (k, 16): planar.h planar_light."""
    return lanes[:, 0:3], lanes[:, 4:7], lanes[:, 8:11]


def planar_bounds(lo: np.ndarray, hi: np.ndarray, lanes: np.ndarray, flags: np.ndarray) -> Bounds:
    """The bounds of planar records whose shapes lie in these boxes: normals along cross(a, b) (a degenerate shape
    emits anywhere), emission over the hemisphere around them."""
    _, a, b = spans(lanes)
    k = len(lanes)
    normal = np.cross(a, b)
    length = np.linalg.norm(normal, axis=1)
    facing = length > 0
    axis = np.tile([0.0, 0.0, 1.0], (k, 1))
    axis[facing] = normal[facing] / length[facing, None]
    theta_o = np.where(facing, 0.0, np.pi)
    return Bounds(lo, hi, axis, theta_o, np.full(k, 0.5 * np.pi), (flags & FLAG_TWO_SIDED) != 0)


def corner_bounds(corners: list[np.ndarray], lanes: np.ndarray, flags: np.ndarray) -> Bounds:
    """planar_bounds of shapes that are the convex hull of their corners (each (k, 3))."""
    return planar_bounds(np.minimum.reduce(corners), np.maximum.reduce(corners), lanes, flags)


def orthogonal_spans(lanes: np.ndarray) -> np.ndarray:
    """(k,) bool: the spans are orthogonal (to 1e-4 of their lengths), as a spherical rectangle needs
    (spherical_rect.h)."""
    _, a, b = spans(lanes)
    la, lb = np.linalg.norm(a, axis=1), np.linalg.norm(b, axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.abs((a * b).sum(1)) <= 1e-4 * la * lb
