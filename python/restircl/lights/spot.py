"""Spot lights (opencl/lights/spot.h): a sphere light (sphere.py) masked by a cone of Blender's spot size with a
smoothstep blend; the cone only masks, it does not concentrate the power."""

from __future__ import annotations

import math

import numpy as np

from ..scene.light import Light
from . import sphere
from .bounds import Bounds
from .light_type import PlacedLight, SceneLightType
from .record import LUMINANCE, lanes, unit
from .sphere import intensity, sphere_lanes


def accepts(lt: Light) -> bool:
    return lt.type == "spot"


def _cos_outer(s: PlacedLight) -> float:
    return math.cos(s.light.spot_size / 2.0)


def record(s: PlacedLight) -> np.ndarray:
    cos_outer = _cos_outer(s)
    axis = unit(-s.matrix[:3, 2])  # the light shines along its local -Z
    blend_width = (1.0 - cos_outer) * s.light.spot_blend
    return lanes(TYPE.code, **sphere_lanes(s), a=axis, b=(cos_outer, blend_width, 0.0))


def power(s: PlacedLight) -> float:
    return float(LUMINANCE @ intensity(s)) * 2.0 * math.pi * (1.0 - _cos_outer(s))


def bounds(lanes: np.ndarray, flags: np.ndarray) -> Bounds:
    """The sphere's box, emitting inside the cone about the axis only (the mask is zero beyond cos_outer)."""
    b = sphere.bounds(lanes, flags)
    axis, cos_outer = lanes[:, 4:7], lanes[:, 8]
    length = np.linalg.norm(axis, axis=1)
    b.axis = np.where(length[:, None] > 0, axis / np.maximum(length, 1e-30)[:, None], b.axis)
    b.theta_o = np.where(length > 0, np.arccos(np.clip(cos_outer, -1.0, 1.0)), np.pi)
    b.theta_e = np.zeros(len(lanes))
    return b


def mask(lanes: np.ndarray, x: np.ndarray) -> np.ndarray:
    """opencl/lights/spot.h spot_mask of spot records (S, 16) at points x (P, 3): (P, S)."""
    out = x[:, None, :] - lanes[None, :, 0:3]
    out = out / np.linalg.norm(out, axis=-1, keepdims=True)
    c = np.einsum("psk,sk->ps", out, lanes[:, 4:7])
    cos_outer, blend_width = lanes[:, 8][None], lanes[:, 9][None]
    t = np.clip((c - cos_outer) / np.where(blend_width > 0, blend_width, 1.0), 0.0, 1.0)
    m = np.where(blend_width > 0, t * t * (3 - 2 * t), 1.0)
    return np.where(c > cos_outer, m, 0.0)


def analytic(x: np.ndarray, n: np.ndarray, lanes: np.ndarray, flags: np.ndarray) -> np.ndarray:
    """The sphere's, masked by the cone at the point."""
    return sphere.analytic(x, n, lanes, flags) * mask(lanes, x)


TYPE = SceneLightType("spot", code=4, flag="HAS_SPOT_LIGHTS",
                      bounds=bounds, solid_angle=sphere.solid_angle, analytic=analytic,
                      accepts=accepts, record=record, power=power, has_shape=sphere.has_shape)
