"""The sun (opencl/lights/sun.h). Strength S (W/m^2) and angular diameter theta: radiance S / (pi sin^2(theta / 2))
inside its cone, so that the irradiance at normal incidence is S; S itself when theta = 0."""

from __future__ import annotations

import math

import numpy as np

from ..scene.light import Light
from .bounds import DISTANT
from .light_type import NotAnalytic, PlacedLight, SceneLightType, no_solid_angle
from .record import LUMINANCE, lanes, unit


def accepts(lt: Light) -> bool:
    return lt.type == "sun"


def record(s: PlacedLight) -> np.ndarray:
    half = s.light.angle / 2.0
    omc = 2.0 * math.sin(half / 2.0) ** 2  # 1 - cos(half), exact for tiny angles
    sin2 = math.sin(half) ** 2
    le = s.rgb_power / (math.pi * sin2) if omc > 0 else s.rgb_power
    towards = unit(s.matrix[:3, 2])  # the light shines along its -Z
    return lanes(TYPE.code, a=towards, b=(math.cos(half), omc, 0.0), radiance=le)


def power(s: PlacedLight) -> float:
    """What falls on a disk of the scene's radius: the light array weighs a sun against the local lights by it."""
    return float(LUMINANCE @ s.rgb_power) * math.pi * s.scene_radius * s.scene_radius


def has_shape(lt: Light) -> bool:
    """Angle 0 is a delta: no ray meets one direction."""
    return lt.angle > 0


def analytic(x: np.ndarray, n: np.ndarray, lanes: np.ndarray, flags: np.ndarray) -> np.ndarray:
    """Radiance over a cap of 1 - cos = omc around the direction: pi sin^2 cos, or cos for a delta; exact when the
    cap is wholly above or below the horizon."""
    cos = n @ lanes[:, 4:7].T  # (P, S)
    omc = lanes[:, 9][None]
    sin2 = omc * (2 - omc)
    if np.any((omc > 0) & (np.abs(cos) < np.sqrt(sin2) * (1 - 1e-6))):
        raise NotAnalytic("a sun crosses the horizon of a shading point")
    geo = np.where(omc > 0, math.pi * sin2 * cos, cos)
    return np.where(cos > 0, geo, 0.0)


TYPE = SceneLightType("sun", code=5, flag="HAS_SUN_LIGHTS",
                      bounds=DISTANT, solid_angle=no_solid_angle, analytic=analytic,
                      accepts=accepts, record=record, power=power, has_shape=has_shape)
