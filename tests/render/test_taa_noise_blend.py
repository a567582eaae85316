"""TAA's noise-aware blend (opencl/taa/blend_weight.h, Settings.taa_noise_blend): on a moving frame the new sample's
weight a rises above the fixed max(1/n, alpha_min) where the sample is quiet against what the history has drifted
by, and stays at the fixed weight on a noisy sample; a still scene keeps the fixed blend.

The TAA stage runs frame after frame on a hand-made G-buffer (one flat surface facing the camera at depth 2, every
pixel reprojecting by the same motion) with hand-made samples; the moments history's w holds the weight a each
pixel took, which the tests read."""

from types import SimpleNamespace

import numpy as np
import pyopencl as cl
from restircl import Renderer, Settings, scenes
from restircl.core import layouts as L

W, H = 24, 12
INNER = (slice(3, H - 3), slice(4, W - 4))  # away from the border, where the history of a moving image runs out


def _gbuffer(motion_x: float) -> np.ndarray:
    g = np.zeros((H, W), L.GSAMPLE)
    g["pos"][..., 3] = 2.0
    g["normal"][..., 2] = 1.0
    g["motion"][..., 0] = motion_x  # where the pixel was last frame, in pixels
    g["motion"][..., 2] = 1.0  # a reprojection ...
    g["motion"][..., 3] = 2.0  # ... onto the same surface
    return g


def _run(blend: bool, moving: bool, motion_x: float, samples: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """TAA over the frames `samples` ((H, W, 3) each; the first frame starts without history): the last frame's
    output (H, W, 4) and the blend weight a each pixel took in it (with the blend on; None off)."""
    r = Renderer(scenes.cornell_box(W, H), Settings(taa_noise_blend=blend, taa_fresh_fill=False))
    q, h = r.device.queue, r.history
    g = _gbuffer(motion_x)
    for slot in (0, 1):
        cl.enqueue_copy(q, h.gbuf(slot), g)
    out = np.empty((H, W, 4), np.float32)
    for t, s in enumerate(samples):
        cl.enqueue_copy(q, r.buffers.sample, np.concatenate([s, np.ones((H, W, 1))], axis=2).astype(np.float32))
        state = SimpleNamespace(frame_params=r.frame_params(), plan=SimpleNamespace(history=t > 0), sweep=(0.0, 0.0))
        cl.enqueue_copy(q, out, r.taa.run(state, moving))  # type: ignore[arg-type]
        h.swap()
    if not blend:
        return out, None
    mom = np.empty((H, W, 4), np.float32)
    cl.enqueue_copy(q, mom, h.taa_moments(h.prev, True))
    return out, mom[..., 3]


def _noisy(frames: int, seed: int = 3) -> list[np.ndarray]:
    """A grey surface under noise: each frame's sample 1 times a uniform factor in [0.2, 1.8] per pixel (relative
    standard deviation 0.46, about RIS's on these orbits), the same in every channel."""
    rng = np.random.default_rng(seed)
    return [np.repeat(rng.uniform(0.2, 1.8, (H, W, 1)), 3, axis=2) for _ in range(frames)]


def _texture(t: int, speed: float) -> np.ndarray:
    """A noise-free image moving right by `speed` pixels a frame: a sinusoid of period 5 pixels along x between 0.5
    and 1.5, point-sampled at the pixel centres of frame t."""
    u = np.arange(W) + 0.5 - speed * t
    row = 1.0 + 0.5 * np.sin(2.0 * np.pi * u / 5.0)
    return np.repeat(np.broadcast_to(row, (H, W))[..., None], 3, axis=2).copy()


def test_a_noisy_sample_keeps_the_fixed_weight():
    """Motion flagged but the image still (a camera still while something else moves): after 40 frames of noise the
    fixed blend's weight is alpha_min (0.1), and the noise-aware blend's stays there on nearly every pixel."""
    samples = _noisy(40)
    on, a = _run(True, True, 0.0, samples)
    off, _ = _run(False, True, 0.0, samples)
    inner = a[INNER]
    assert np.median(inner) == np.float32(0.1)
    assert np.mean(inner <= 0.1 + 1e-6) > 0.8
    assert np.mean(inner) < 0.13
    # the output's noise (its spread over the pixels; the truth is 1 everywhere) grows by less than 15 %
    assert np.std(on[INNER][..., 0]) < 1.15 * np.std(off[INNER][..., 0])


def test_a_quiet_sample_under_motion_is_trusted_more():
    """A noise-free image moving by half a pixel a frame: the bilinear history blurs it every frame; the fixed blend
    keeps 0.9 of that blurred history, the noise-aware one takes far more of the sharp sample and ends far closer to
    the frame's true image."""
    frames = 30
    samples = [_texture(t, 0.5) for t in range(frames)]
    on, a = _run(True, True, -0.5, samples)
    off, _ = _run(False, True, -0.5, samples)
    truth = samples[-1][INNER][..., 0]
    err_on = np.sqrt(np.mean((on[INNER][..., 0] - truth) ** 2))
    err_off = np.sqrt(np.mean((off[INNER][..., 0] - truth) ** 2))
    assert err_off > 0.05  # the fixed blend's blur and lag are there to be removed (the sinusoid's amplitude: 0.5)
    assert err_on < 0.5 * err_off
    assert np.median(a[INNER]) > 0.3


def test_a_still_scene_is_unchanged():
    """A still scene (no motion flagged) keeps the fixed blend 1/n: the same bits with the blend on or off."""
    samples = _noisy(12, seed=4)
    on, _ = _run(True, False, 0.0, samples)
    off, _ = _run(False, False, 0.0, samples)
    np.testing.assert_array_equal(on, off)
