"""Cycles' Transmission Direct, Indirect and Color passes (render/light_passes.py, opencl/film/light_passes.h) on a
rough glass pane with a light behind it (eval/scenes/glass_pane.py): the passes of every pixel recombine to the image
with the transmission term, for still estimators and an animation frame; light that reaches the pane from behind is
transmission's alone (the pane's pixels hold no diffuse light: glass has no Lambert part), and only the pane's
pixels have a transmission colour, 1 - F at their view. Agreement with Cycles'
passes: tests/blender/test_blender_transmission_passes.py."""

from __future__ import annotations

import numpy as np
import pytest
from restircl import Renderer, Settings
from restircl.eval.scenes.glass_pane import glass_pane

from .test_light_passes import _mismatch, recombined


@pytest.mark.parametrize(("method", "bounces"), [("ris", 0), ("ris", 4), ("restir", 3), ("reference", 2)])
def test_transmission_passes_recombine(device, method, bounces):
    f = Renderer(glass_pane(32, 24), Settings(method=method, max_bounces=bounces, light_passes=True)).render_still(
        0, samples=8)
    assert _mismatch(recombined(f), f.color[..., :3]) < 1e-5
    pane = f.transmission_color.max(axis=-1) > 0
    assert 0.1 < pane.mean() < 0.5
    assert f.transmission_direct[pane].max() > 0 and not np.any(f.transmission_direct[~pane])
    assert (f.transmission_indirect.max() > 0) == (bounces > 0)
    inside = pane & (f.albedo.max(axis=-1) == 0)  # every sample on the pane (its edges mix in the floor)
    assert inside.mean() > 0.1 and not np.any(f.diffuse_direct[inside])
    # 1 - F: near 1 - F(0) = 0.966 at IOR 1.45 where the view is near the pane's normal, below 1 everywhere
    assert np.all(f.transmission_color[inside] < 1.0) and 0.9 < np.median(f.transmission_color[inside]) < 0.967


def test_animation_frame_transmission_passes_recombine(device):
    r = Renderer(glass_pane(32, 24), Settings(method="restir", max_bounces=3, light_passes=True))
    for _ in range(2):
        f = r.render_frame(0)
        assert _mismatch(recombined(f), f.noisy) < 1e-5
    assert f.transmission_direct.max() > 0 and f.transmission_indirect.max() > 0
