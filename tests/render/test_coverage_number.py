"""The camera's choice at an alpha-masked cut-out's rim (opencl/camera/coverage_number.h): a still render's film
alpha of a leaf card seen against the world converges to the pixel's mean of the image's alpha, at the rate of a
stratified estimate, where the coverage varies across the pixel.

The expected coverage is computed here independently: each pixel's footprint sampled on a fine grid, the
orthographic ray of each point met with the card's plane, and the 32 x 32 leaf image's alpha interpolated
bilinearly (texel centres at half-integers, the image's bottom row at v = 0) at the UV found. The negative
control is the frames' own sequence (the random sampler's path), which is one number per frame for all pixels:
tied to the one Halton jitter point of the frame, its error at the rims stops falling.

Stills that shade in weighted layers (render/layers.py) draw no number: a sample's alpha is the coverage where its
ray meets the card. The number serves the stills that keep one surface per sample (ReSTIR's reuse, denoising,
Cryptomatte, ...) and the animation frames; its tests render with the layers off."""

from __future__ import annotations

import numpy as np
import pytest
from restircl import Camera, Environment, Light, Renderer, Scene, Settings, look_at, translation
from restircl.eval.scenes.alpha_cards import card, leaf_image, leaf_material
from restircl.render.camera import camera_record
from restircl.render.layers import CameraLayers

W, H = 24, 18
SAMPLES = 4096
GRID = 24  # points per pixel side of the expected coverage


def leaf_scene() -> Scene:
    """The 2 x 2 m leaf card in the plane z = 0 filling most of an orthographic view from above, a grey world."""
    cam = Camera(look_at((0.0, -0.01, 3.0), (0.0, 0.0, 0.0)), W, H, type="ORTHO", ortho_scale=2.6)
    light = Light("sun", "sun", (1.0, 1.0, 1.0), 2.0, translation(0.0, 0.0, 5.0))
    return Scene([card("leaf", (-1, -1, 0), (2, 0, 0), (0, 2, 0), 0)], [leaf_material()], [light], cam,
                 name="leaf", environment=Environment(color=(0.2, 0.2, 0.2), strength=1.0))


def bilinear_alpha(s: np.ndarray, t: np.ndarray) -> np.ndarray:
    alpha = leaf_image()[::-1, :, 3] / 255.0  # bottom row first
    n = alpha.shape[0]
    fx, fy = s * n - 0.5, t * n - 0.5
    x0, y0 = np.floor(fx).astype(int), np.floor(fy).astype(int)
    ax, ay = fx - x0, fy - y0

    def texel(x, y):  # the node's default extension, Repeat
        return alpha[np.mod(y, n), np.mod(x, n)]

    return ((1 - ay) * ((1 - ax) * texel(x0, y0) + ax * texel(x0 + 1, y0))
            + ay * ((1 - ax) * texel(x0, y0 + 1) + ax * texel(x0 + 1, y0 + 1)))


def expected_coverage(scene: Scene) -> np.ndarray:
    rec = camera_record(scene.camera, 0)
    origin, right, up, fwd = (rec[k][0, :3].astype(np.float64) for k in ("origin", "right", "up", "forward"))
    half_x, half_y = rec["lens"][0, 0], rec["lens"][0, 1]
    sub = (np.arange(GRID) + 0.5) / GRID
    px = (np.arange(W)[None, :, None, None] + sub[None, None, None, :])
    py = (np.arange(H)[:, None, None, None] + sub[None, None, :, None])
    nx = 2.0 * px / W - 1.0
    ny = 1.0 - 2.0 * py / H
    o = origin + (nx * half_x)[..., None] * right + (ny * half_y)[..., None] * up
    t = -o[..., 2] / fwd[2]
    hit = o + t[..., None] * fwd
    s, v = (hit[..., 0] + 1.0) / 2.0, (hit[..., 1] + 1.0) / 2.0
    inside = (s >= 0) & (s <= 1) & (v >= 0) & (v <= 1)
    a = np.where(inside, bilinear_alpha(np.clip(s, 0, 1), np.clip(v, 0, 1)), 0.0)
    return a.mean(axis=(2, 3))


def coverage_error(sampler: str, seed: int, samples: int = SAMPLES) -> tuple[float, np.ndarray]:
    """Mean squared error of the film alpha at the pixels where the coverage is neither 0 nor 1."""
    scene = leaf_scene()
    f = Renderer(scene, Settings(method="ris", sampler=sampler, seed=seed)).render_still(0, samples=samples)
    assert f.coverage is not None
    exp = expected_coverage(scene)
    rim = (exp > 0.02) & (exp < 0.98)
    return float(np.mean((f.coverage[rim] - exp[rim]) ** 2)), exp[rim]


@pytest.fixture
def one_surface(monkeypatch):
    """Stills keep one surface per sample, chosen by the camera's number."""
    monkeypatch.setattr(CameraLayers, "wanted", lambda *args: False)


def test_the_layers_film_alpha_is_the_coverage_met(device):
    """With the weighted layers, a sample's alpha is the coverage its ray met: only the jitter's error is left."""
    samples = SAMPLES // 16
    err, exp = coverage_error("auto", 3, samples)
    assert err < 0.05 * float(np.mean(exp * (1 - exp))) / samples


def test_the_rims_film_alpha_converges_as_a_stratified_estimate(device, one_surface):
    err, exp = coverage_error("auto", 3)
    assert exp.size >= 40  # the leaf's lobes put many pixels on its rim
    binomial = float(np.mean(exp * (1 - exp))) / SAMPLES  # what independent coins would leave
    assert err < 0.6 * binomial  # 0.31-0.34x at seeds 3 and 4; the frames' sequence 3-6x


def test_the_frames_own_sequence_is_tied_to_the_jitter(device, one_surface):
    """The negative control: one number per frame for all pixels leaves more than independent coins would."""
    err, exp = coverage_error("random", 3)
    binomial = float(np.mean(exp * (1 - exp))) / SAMPLES
    assert err > 2.0 * binomial
