"""The Bump node (materials/textures.py Bump, opencl/textures/bump.h) on a square facing the camera: a height that
rises linearly in u (h = u, a 256-texel ramp read between texel centres) has the surface gradient (1/2, 0, 0) per
world unit on the square (u = (x + 1) / 2), so the shading normal is normalize(N - distance grad h), written out
here; Invert flips the tilt, Strength blends towards N, a constant height leaves N."""

from __future__ import annotations

import numpy as np
import pytest
from restircl import Bump, ImageTexture, Material

from ..texture_scenes import facing_square
from .test_textures import render

RAMP = ((np.arange(256) + 0.5) / 256).astype(np.float32)[None, :].repeat(2, axis=0)


def _normal(bump: Bump) -> np.ndarray:
    f = render(facing_square(Material("m", normal=bump), 16))
    return f.normal[2:-2, 2:-2].reshape(-1, 3).astype(np.float64)  # away from the border texels


def _unit(v) -> np.ndarray:
    v = np.asarray(v, np.float64)
    return v / np.linalg.norm(v)


@pytest.mark.parametrize(("distance", "invert", "strength"), [(1.0, False, 1.0), (0.4, True, 1.0),
                                                              (2.0, False, 0.5)])
def test_bump_tilts_by_the_height_gradient(device, distance, invert, strength):
    h = ImageTexture(RAMP, colorspace="Non-Color", extension="EXTEND")
    n = _normal(Bump(height=h, strength=strength, distance=distance, invert=invert))
    d = -distance if invert else distance
    tilted = _unit([-0.5 * d, 0.0, 1.0])
    want = _unit(strength * tilted + (1 - strength) * np.array([0.0, 0.0, 1.0]))
    np.testing.assert_allclose(n, np.broadcast_to(want, n.shape), atol=2e-3)


def test_a_constant_height_leaves_the_normal(device):
    np.testing.assert_allclose(_normal(Bump(height=0.7)), np.broadcast_to([0.0, 0.0, 1.0], (144, 3)), atol=1e-6)
