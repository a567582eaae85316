"""Clamp Direct (Settings.clamp_direct, Cycles' Light Paths > Clamping > Direct Light; opencl/direct/clamp.h): every
contribution of direct light (what the camera sees of the emitters and the world, a light sample at the first
surface, the emitters a BSDF sample of it meets) is scaled down to an rgb sum of 3x the clamp, each on its own, in
every direct estimator; bounced light is left to Clamp Indirect. 0 (the default) leaves the image as it was."""

from __future__ import annotations

import numpy as np
import pytest
from restircl import Renderer, Settings

from .path_reference import path_test_scene

CLAMP = 0.05


def _scene():
    return path_test_scene(24, 18, light="both", world=(0.2, 0.25, 0.3), light_visible=True)


def _frame(**kw):
    r = Renderer(_scene(), Settings(jitter=False, light_passes=True, **kw))
    return r.render_still(0, samples=1)


@pytest.mark.parametrize(("method", "contributions", "extra"), [
    ("light_array", 2, {}),  # what the camera sees, one light sample
    ("ris", 3, {"bsdf_mis_sample": True}),  # ... and the BSDF sample's lights
    ("restir", 2, {}),  # the shaded reservoir sample
])
def test_each_direct_contribution_is_capped(device, method, contributions, extra):
    plain = _frame(method=method, **extra)
    clamped = _frame(method=method, clamp_direct=CLAMP, **extra)
    limit = 3 * CLAMP * contributions * (1 + 1e-5)
    assert plain.noisy.sum(axis=-1).max() > 4 * limit  # the scene has contributions far above the clamp
    assert clamped.noisy.sum(axis=-1).max() <= limit
    # what the camera sees is one contribution: the lamps and the world each within 3x the clamp
    seen = clamped.emission + clamped.environment
    assert seen.sum(axis=-1).max() <= 3 * CLAMP * (1 + 1e-5)
    assert plain.emission.sum(axis=-1).max() > 3 * CLAMP


def test_bounced_light_is_not_direct(device):
    """The path pass's light keeps Clamp Indirect's rule: the same with and without Clamp Direct (its random
    numbers are its own stream, so the two renders draw the same paths)."""
    plain = _frame(method="ris", max_bounces=2)
    clamped = _frame(method="ris", max_bounces=2, clamp_direct=CLAMP)
    assert clamped.diffuse_indirect.max() > 0
    assert np.array_equal(plain.diffuse_indirect, clamped.diffuse_indirect)
    assert not np.array_equal(plain.diffuse_direct, clamped.diffuse_direct)


def test_a_clamp_no_contribution_reaches_changes_nothing(device):
    kw = {"method": "ris", "bsdf_mis_sample": True}
    plain = Renderer(_scene(), Settings(**kw)).render_still(0, samples=2)
    high = Renderer(_scene(), Settings(**kw, clamp_direct=1e30)).render_still(0, samples=2)
    assert np.array_equal(plain.color, high.color)
