"""Blender's area light, shared by the quad and disk types: a shape in the light's local XY plane, emitting
along local -Z, one-sided, of power P and area A: radiance P / (pi A)."""

from __future__ import annotations

import math

import numpy as np

from ..scene.light import Light
from .light_type import PlacedLight
from .record import LUMINANCE


def has_shape(lt: Light) -> bool:
    """An area light is its shape: rays meet it (and the camera sees it where it is visible to the camera)."""
    return True


def axes(s: PlacedLight) -> tuple[np.ndarray, np.ndarray]:
    """The shape's full extents along local X and Y in world space."""
    lt = s.light
    ux = s.matrix[:3, 0] * lt.size
    vy = s.matrix[:3, 1] * (lt.size_y if lt.shape in ("RECTANGLE", "ELLIPSE") else lt.size)
    return ux, vy


def emitting_spans(s: PlacedLight) -> tuple[np.ndarray, np.ndarray]:
    """(span_u, span_v): the shape's extents along local Y and X, ordered so that cross(span_u, span_v) points along
    the transform's -Z column, the side Blender's area light emits to, also where the transform mirrors (its basis
    is left-handed: cross(Y, X) then points along +Z, and the order swaps)."""
    ux, vy = axes(s)
    return (ux, vy) if np.linalg.det(s.matrix[:3, :3]) < 0 else (vy, ux)


def radiance(s: PlacedLight, area: float) -> np.ndarray:
    return s.rgb_power / (math.pi * area)


def power(s: PlacedLight, area: float) -> float:
    return float(LUMINANCE @ radiance(s, area)) * area * math.pi
