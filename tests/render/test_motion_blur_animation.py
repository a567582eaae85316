"""Motion blur in animation frames (render/shutter.py, taa/sweep.h): a box sliding past a still camera, each frame
rendered at one time of its shutter (1 frame long, around the frame) and accumulated by TAA, comes out as the
motion-blurred still of that frame (F12's path, each sample at its own time). The error is scored on the blur's
band (where the blurred and the sharp stills differ), the relMSE of one frame per seed, the mean over two seeds.

Negative controls: sharp animation frames (no shutter), and blurred frames whose TAA reprojects and clips as a sharp
frame does (its sweep left out). Measured when written (96x72, frame 8, 512-sample references, 6 seeds): blurred
0.073-0.106, sharp 0.186-0.217, without the sweep 0.20-0.43."""

from __future__ import annotations

import numpy as np
import pytest
from restircl import Renderer, Settings
from restircl.render import pipeline
from restircl.render.still_method import still_settings
from restircl.scenes.builtin import many_lights, moving_box

from ..bias_controls import built_with

W, H, FRAMES, FRAME = 96, 72, 12, 8
SHUTTER = (-0.5, 0.5)
BOUND = 0.13


def sliding_box(shutter: tuple[float, float]):
    sc = moving_box(W, H, frames=FRAMES, pan=0.0, speed=0.3)
    assert sc.camera is not None
    sc.camera.shutter = shutter
    return sc


@pytest.fixture(scope="module")
def stills(device) -> tuple[np.ndarray, np.ndarray]:
    """The blurred still of FRAME and the blur's band (where the sharp still differs from it)."""
    def still(shutter, samples):
        sc = sliding_box(shutter)
        return Renderer(sc, still_settings(Settings(), sc), device).render_still(FRAME, samples).color[..., :3]

    blurred = still(SHUTTER, 512)
    band = np.abs(blurred - still((0.0, 0.0), 256)).sum(-1) > 0.05
    assert band.sum() > 150  # the box's blur is several pixels wide on both sides, and its shadow's
    return blurred, band


def band_error(stills, device, shutter) -> float:
    reference, band = stills
    errors = []
    for seed in (0, 1):
        r = Renderer(sliding_box(shutter), Settings(seed=seed), device)
        for f in range(FRAME + 1):
            out = r.render_frame(f)
        d = ((out.color[..., :3] - reference) ** 2).sum(-1)[band].mean()
        errors.append(d / (reference**2).sum(-1)[band].mean())
    return float(np.mean(errors))


def test_an_animation_frame_with_motion_blur_converges_to_the_blurred_still(stills, device):
    err = band_error(stills, device, SHUTTER)
    assert err < BOUND, f"relMSE on the blur's band {err:.3f}"


def test_sharp_animation_frames_fail_the_bound(stills, device):
    err = band_error(stills, device, (0.0, 0.0))
    assert err > BOUND, f"sharp frames passed: relMSE {err:.3f}"


def test_taa_without_the_sweep_fails_the_bound(stills, device, monkeypatch):
    """Blurred frames whose TAA follows each pixel's own surface and clips to its 3x3 neighbourhood: the blur's
    band keeps where it was, or is clipped away frame by frame."""
    monkeypatch.setattr(pipeline, "sweep", lambda *_args: (0.0, 0.0))
    err = band_error(stills, device, SHUTTER)
    assert err > BOUND, f"TAA without the sweep passed: relMSE {err:.3f}"


def test_a_still_camera_and_still_scene_with_motion_blur_on_render_as_without(device):
    """Nothing moves: the frame's time within its shutter changes nothing, the frames are bit for bit the same."""
    images = []
    for shutter in ((0.0, 0.0), SHUTTER):
        sc = moving_box(32, 24, frames=4, pan=0.0, speed=0.0)
        assert sc.camera is not None
        sc.camera.shutter = shutter
        r = Renderer(sc, Settings(seed=3), device)
        images.append([r.render_frame(f).color for f in range(3)])
    assert all(np.array_equal(a, b) for a, b in zip(*images, strict=True))


def flight_light(device, monkeypatch: pytest.MonkeyPatch, *defines: str) -> float:
    """The light in frame 23 of many_lights' flight (96x54) with a shutter of a frame around each frame."""
    with monkeypatch.context() as mp:
        if defines:
            built_with(mp, *defines)
        sc = many_lights(96, 54, frames=24)
        assert sc.camera is not None
        sc.camera.shutter = SHUTTER
        r = Renderer(sc, Settings(), device)
        for f in range(24):
            out = r.render_frame(f)
    return float(out.color[..., :3].sum())


def test_far_lamps_keep_their_light_under_a_flying_camera(device, monkeypatch):
    """The far lamps' paths over the shutter are about 1.5 pixels: a sharp frame's TAA rules keep them
    (TAA_SWEEP_MIN). Negative control: the blurred rules taken at every length drain them (TAA's clipping of a
    history kept across surface changes). Measured when written: 8331 and 3949, a converged blurred still 8392."""
    sc = many_lights(96, 54, frames=24)
    assert sc.camera is not None
    sc.camera.shutter = SHUTTER
    still = float(Renderer(sc, still_settings(Settings(), sc), device).render_still(23, 32).color[..., :3].sum())
    kept = flight_light(device, monkeypatch)
    drained = flight_light(device, monkeypatch, "TAA_SWEEP_MIN=0")
    assert abs(kept / still - 1.0) < 0.15 and drained < 0.7 * still, (kept, drained, still)
