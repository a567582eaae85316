"""The light samplers stay unbiased with a glossy BSDF (the target function and every shading site evaluate it for
the pixel's view): light_array and ris (target = luminance of the full BSDF times the light) against the
exhaustive reference, per pixel and over the image, on material_balls (dielectric, metal, Glossy and Mix spheres)
with two point lights and an area light."""

import numpy as np
import pytest
from restircl.scenes.builtin import material_balls

from ..bias_controls import wrong_pdf
from ..helpers import Settings, assert_mean_equals_reference, collect

FRAMES = 1024
BATCHES = 32
W, H = 32, 18


@pytest.fixture(scope="module")
def scene():
    return material_balls(W, H, area_light=True)


@pytest.fixture(scope="module")
def reference(device, scene):
    return collect(scene, Settings(method="reference", seed=101, jitter=False), FRAMES, device)


@pytest.mark.parametrize("method", ["light_array", "ris"])
def test_sampler_mean_equals_reference_with_glossy_bsdf(device, scene, reference, method):
    samples = collect(scene, Settings(method=method, candidates=4, seed=7, jitter=False), FRAMES, device)
    assert np.all(np.isfinite(samples))
    assert_mean_equals_reference(samples, reference, BATCHES, method)


def test_the_harness_rejects_a_wrong_pdf(device, scene, reference, monkeypatch):
    """Negative control: RIS with a light pdf 2 % too small (tests/bias_controls.py) must be rejected."""
    wrong_pdf(monkeypatch)
    samples = collect(scene, Settings(method="ris", candidates=4, seed=7, jitter=False), FRAMES, device)
    with pytest.raises(AssertionError, match="outliers|image means"):
        assert_mean_equals_reference(samples, reference, BATCHES, "ris, wrong pdf")
