"""The weighted layers of a still (render/layers.py, opencl/camera/layers.h): a pixel seen through a pane of
coverage a is a times the pane plus (1 - a) times the floor behind in every sample, as Cycles weights them, where
animation frames choose one of the two by a coin of probability a (bvh/transparent.h).

Expected values are closed forms from renders of opaque scenes (as in test_transparency.py): the pane of coverage a
over a floor lit through it shows a P + (1 - a)^2 F, P the opaque pane, F the floor without a pane. The negative
control TEST_LAYER_WEIGHT_WHOLE shades the pane whole (weight 1 - its coverage lost): P + (1 - a)^2 F."""

from __future__ import annotations

import numpy as np
import pytest
from restircl import Renderer, Settings
from restircl.render.layers import CameraLayers

from ..bias_controls import built_with
from .test_transparency import pane_scene

A = 0.4
SAMPLES = 32


def _render(scene, seed: int = 5) -> np.ndarray:
    return Renderer(scene, Settings(method="ris", seed=seed)).render_still(0, samples=SAMPLES).color[..., :3]


@pytest.fixture(scope="module")
def closed_form() -> np.ndarray:
    """a P + (1 - a)^2 F per pixel, from twice the samples of the renders it is compared with."""
    pane = np.mean([_render(pane_scene(1.0), seed) for seed in (10, 11)], axis=0)
    floor = np.mean([_render(pane_scene(None), seed) for seed in (20, 21)], axis=0)
    assert pane.mean() > 0.05 and floor.mean() > 0.05
    return A * pane + (1 - A) ** 2 * floor


def _error(img: np.ndarray, ref: np.ndarray) -> float:
    return float(np.mean((img - ref) ** 2))


def test_layers_are_the_closed_form_with_less_noise(device, closed_form, monkeypatch):
    layered = [_render(pane_scene(A), seed) for seed in (1, 2)]
    assert np.mean(layered) == pytest.approx(closed_form.mean(), rel=0.02)
    monkeypatch.setattr(CameraLayers, "wanted", lambda *args: False)  # one surface per sample, by its coin
    coins = [_render(pane_scene(A), seed) for seed in (1, 2)]
    assert np.mean(coins) == pytest.approx(closed_form.mean(), rel=0.03)
    err_layers = np.mean([_error(x, closed_form) for x in layered])
    err_coins = np.mean([_error(x, closed_form) for x in coins])
    print(f"pane a = {A}, {SAMPLES} samples: squared error layers {err_layers:.3e}, coins {err_coins:.3e}")
    assert err_layers < 0.5 * err_coins


def test_the_pane_shaded_whole_misses_the_closed_form(device, closed_form, monkeypatch):
    built_with(monkeypatch, "TEST_LAYER_WEIGHT_WHOLE")
    seen = _render(pane_scene(A), 1)
    assert abs(seen.mean() / closed_form.mean() - 1) > 0.2


def test_film_alpha_of_the_layers_is_the_coverage_exactly(device):
    """Seen through a pane of coverage 0.3 to the world, every sample's w is 0.3: the film's alpha without noise."""
    f = Renderer(pane_scene(0.3, world=True), Settings(method="ris", seed=2, jitter=False)).render_still(0, samples=4)
    assert f.coverage is not None
    assert f.coverage[5:7, 7:9] == pytest.approx(np.full((2, 2), 0.3), abs=1e-6)
    assert f.coverage[0, 0] == 0.0


def test_animation_frames_keep_one_surface_per_pixel(device):
    r = Renderer(pane_scene(A), Settings(method="ris", seed=1))
    r.render_frame(0)
    assert not r.layers.layered and r.layers.state is None  # no layer ran
    r.render_still(0, samples=2)
    assert r.layers.layered
