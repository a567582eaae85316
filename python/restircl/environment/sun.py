"""Whether a world has a sun: a small, very bright part of the map that holds much of its power (a Sky Texture's
sun disc baked into the map, an HDRI's sun). render/still_method.py turns the BSDF MIS sample
(opencl/direct/bsdf_mis.h) on for such worlds: there RIS's one shadow ray goes to the sun most of the time, also where
the sun is occluded, and the sky in the shadows is left to the few other samples
(docs/measurements/error-vs-time.md, "The sky's sun").

The measure: the share of the map's power (luminance x solid angle) in its brightest texels that together cover
SUN_SOLID_ANGLE_FRACTION of the sphere. A 1.6-degree sun of 1e3 times the sky holds 0.68 of the tuning `sky`'s
power in 2e-4 of the sphere; a sky without a sun has a few percent in its brightest 1 %."""

from __future__ import annotations

import numpy as np

from ..lights.record import LUMINANCE
from .image import environment_texels
from .table import row_solid_angles
from .world import Environment

#: the part of the sphere a sun may cover (1 %: a disc of about 11 degrees radius)
SUN_SOLID_ANGLE_FRACTION = 0.01
#: a world is sunny when its brightest SUN_SOLID_ANGLE_FRACTION holds at least this share of its power
SUNNY_SHARE = 0.3
#: maps above this many texels are measured on block means (which keep each block's power)
MAX_TEXELS = 1 << 22


def _block_means(lum: np.ndarray) -> np.ndarray:
    h, w = lum.shape
    k = 1
    while (h // k) * (w // k) > MAX_TEXELS:
        k *= 2
    if k == 1:
        return lum
    h2, w2 = h // k, w // k
    return lum[: h2 * k, : w2 * k].reshape(h2, k, w2, k).mean(axis=(1, 3))


def sun_share(env: Environment) -> float:
    """The share of the world's power in its brightest SUN_SOLID_ANGLE_FRACTION of the sphere (0 for a black or
    constant world)."""
    if env.image is None and env.path is None:
        return 0.0
    rgb, _ = environment_texels(env)
    lum = _block_means(rgb @ np.asarray(LUMINANCE, np.float32))
    h, w = lum.shape
    solid = np.broadcast_to(row_solid_angles(h, w)[:, None], (h, w)).ravel()
    power = lum.ravel().astype(np.float64) * solid
    total = power.sum()
    if not total > 0:
        return 0.0
    order = np.argsort(lum.ravel(), kind="stable")[::-1]
    covered = np.cumsum(solid[order])
    n = int(np.searchsorted(covered, SUN_SOLID_ANGLE_FRACTION * 4.0 * np.pi, side="right"))
    return float(power[order[:n]].sum() / total)


def is_sunny(env: Environment | None) -> bool:
    """Whether the world has a sun (module docstring)."""
    return env is not None and sun_share(env) >= SUNNY_SHARE
