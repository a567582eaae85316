"""The light samplers (uniform, light_array, ris) are unbiased: their mean equals the exhaustive reference within
4 standard errors (batch means), per pixel and over the image, on a scene with every light type, powers from
1e-6 to 1e6, a light touching the floor, a grazing sun and lights behind the surface."""

import numpy as np
import pytest

from ..bias_controls import wrong_pdf
from ..helpers import (
    Settings,
    assert_mean_equals_reference,
    below_only_scene,
    collect,
    luminance,
    mixed_lights_scene,
)

# Without jitter every pixel is one fixed shading point. The light array gives the weakest light 1 slot of about
# 4N + N: 8192 frames give it over 100 picks, enough for batch means to be near-normal.
FRAMES = 8192
BATCHES = 64
W, H = 16, 12
# The unbiasedness check runs at two sizes, as render/test_restir.py's: "quick" in the default suite (a quarter of the
# frames in half the batches, the reference as long), "full" behind the slow marker. Both judge by the measured
# standard errors; quick has half of full's resolution for a bias.
SIZES = {"quick": (2048, 32), "full": (FRAMES, BATCHES)}  # frames (samples and reference), batches
SIZE_PARAMS = [pytest.param("full", marks=pytest.mark.slow), "quick"]


@pytest.fixture(scope="module")
def references(reference_samples):
    """references(size): the exhaustive sampler's frames (shared with lights/test_tree_estimators.py)."""
    return lambda size: reference_samples(mixed_lights_scene(W, H), Settings(method="reference", seed=101,
                                                                             jitter=False), SIZES[size][0])


# "ris_tiles": RIS over candidates from presampled light tiles (lights/tiles.h), small tiles so that every pixel
# strip's candidates come from a few dozen light-array draws: correlated, but of the right marginal pdf.
SAMPLERS = {"uniform": {}, "light_array": {}, "ris": {},
            "ris_tiles": dict(light_tiles="on", light_tile_count=4, light_tile_size=32)}


@pytest.mark.parametrize("size", SIZE_PARAMS)
@pytest.mark.parametrize("method", list(SAMPLERS))
def test_sampler_mean_equals_reference(device, references, method, size):
    frames, batches = SIZES[size]
    reference = references(size)
    s = Settings(method=method.removesuffix("_tiles"), candidates=4, seed=7, jitter=False, **SAMPLERS[method])
    samples = collect(mixed_lights_scene(W, H), s, frames, device)
    assert np.all(np.isfinite(samples))
    assert_mean_equals_reference(samples, reference, batches, method)


@pytest.mark.parametrize("method", ["light_array", "ris"])
def test_the_harness_rejects_a_wrong_pdf(device, references, method, monkeypatch):
    """Negative control at the quick size: built with a light pdf 2 % too small (tests/bias_controls.py) the image
    is 2 % too bright, which the check above must reject by its image mean."""
    reference = references("quick")
    wrong_pdf(monkeypatch)
    s = Settings(method=method, candidates=4, seed=7, jitter=False)
    samples = collect(mixed_lights_scene(W, H), s, SIZES["quick"][0], device)
    with pytest.raises(AssertionError, match="outliers|image means"):
        assert_mean_equals_reference(samples, reference, SIZES["quick"][1], method)


def test_lights_behind_the_surface_give_exact_zero(device):
    for method in ("uniform", "light_array", "ris", "reference", "restir"):
        samples = collect(below_only_scene(), Settings(method=method, seed=3), 8, device)
        assert np.all(samples == 0.0), method


def test_ris_has_lower_variance_than_light_array(device):
    """Not a timing test: per-sample variance on the mixed scene, RIS with 8 candidates against one pick."""
    scene = mixed_lights_scene(W, H)
    la = collect(scene, Settings(method="light_array", seed=11, jitter=False), 512, device)
    ris = collect(scene, Settings(method="ris", candidates=8, seed=11, jitter=False), 512, device)
    v_la = luminance(la).var(axis=0).mean()
    v_ris = luminance(ris).var(axis=0).mean()
    assert v_ris < v_la
