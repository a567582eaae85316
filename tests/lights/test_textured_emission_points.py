"""An emissive quad of two triangles whose emission image varies within each triangle (a 2x2 image, one texel white,
Closest) lights a floor: next-event estimation reads the image at the sampled point (lights/textured_emission.py,
opencl/lights/textured_emission.h), so the image is exact against an independent reference, the same quad cut
into a 16x16 grid of cells whose triangles each lie within one texel (there the per-triangle mean is the texel
itself). Negative control: the two triangles shining with their mean (what lights did before) fail the bound."""

from __future__ import annotations

import math

import numpy as np
import pytest
from restircl import Camera, ImageTexture, Material, Mesh, Renderer, Scene, Settings, look_at
from restircl.eval.metrics import rel_mse
from restircl.lights import device_lights

SIZE = 24
BOUND = 5e-3  # both sides at 1024 samples: their noise is about 1e-3


def _emitter(cells: int) -> Mesh:
    """The unit-height quad [-1, 1]^2 at z = 1 facing down, as cells x cells squares of two triangles each."""
    g = np.linspace(0.0, 1.0, cells + 1)
    verts, tris, uvs = [], [], []
    for j in range(cells + 1):
        for i in range(cells + 1):
            verts.append((2 * g[i] - 1, 2 * g[j] - 1, 1.0))
    for j in range(cells):
        for i in range(cells):
            a, b, c, d = j * (cells + 1) + i, j * (cells + 1) + i + 1, (j + 1) * (cells + 1) + i + 1, \
                (j + 1) * (cells + 1) + i
            for t in ((a, c, b), (a, d, c)):  # facing -Z
                tris.append(t)
                uvs.append([(g[k % (cells + 1)], g[k // (cells + 1)]) for k in t])
    return Mesh("panel", np.array(verts), np.array(tris), 1, uvs=np.array(uvs))


def _scene(cells: int) -> Scene:
    img = np.zeros((2, 2, 3), np.float32)
    img[1, 0] = 1.0  # top left (rows bottom first): u < 1/2, v > 1/2
    glow = Material("glow", albedo=(0.0, 0.0, 0.0), emission=ImageTexture(img, colorspace="Non-Color",
                                                                          interpolation="Closest"),
                    emission_strength=4.0)
    floor = Mesh("floor", np.array([[-3, -3, 0], [3, -3, 0], [3, 3, 0], [-3, 3, 0]], float),
                 np.array([[0, 1, 2], [0, 2, 3]]), 0)
    cam = Camera(look_at((0.0, 0.0, 0.9), (0.0, 0.0, 0.0), (0, 1, 0)), SIZE, SIZE)
    cam.set_fov(math.radians(100))
    return Scene([floor, _emitter(cells)], [Material("floor", albedo=(0.5, 0.5, 0.5)), glow], [], cam)


def _render(scene: Scene, samples: int, seed: int = 1) -> np.ndarray:
    r = Renderer(scene, Settings(method="reference", seed=seed, max_bounces=0))
    return r.render_still(0, samples).color[..., :3]


@pytest.fixture(scope="module")
def reference() -> np.ndarray:
    return _render(_scene(16), 1024, seed=7)


def test_a_textured_quad_lights_the_floor_by_its_texels(device, reference):
    ours = _render(_scene(1), 1024)
    err = rel_mse(ours, reference)
    print(f"two textured triangles against the 16x16 cells: relMSE {err:.2e}, "
          f"mean {ours.mean() / reference.mean():.4f}")
    assert reference.mean() > 0.02
    assert err < BOUND


def test_the_triangle_means_fail_the_bound(device, reference, monkeypatch):
    monkeypatch.setattr(device_lights, "point_emission_data", lambda *a: np.zeros(0, np.float32))
    means = _render(_scene(1), 1024)
    err = rel_mse(means, reference)
    print(f"two triangles at their means against the 16x16 cells: relMSE {err:.2e}")
    assert err > 10 * BOUND
