"""The light samplers (uniform, light_array, ris) are unbiased: their mean equals the exhaustive reference within
4 standard errors (batch means), per pixel and over the image, on a scene with every light type, powers from
1e-6 to 1e6, a light touching the floor, a grazing sun and lights behind the surface."""

import numpy as np
import pytest

from ..helpers import (
    Settings,
    allowed_outliers,
    batch_stats,
    below_only_scene,
    collect,
    constant,
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
    m, se = batch_stats(luminance(samples), batches)
    mr, ser = batch_stats(luminance(reference), batches)
    sigma = np.sqrt(se**2 + ser**2)
    exact = constant(sigma, mr)
    z = np.abs(m - mr) / np.where(exact, 1.0, sigma)
    assert np.all(np.abs(m - mr)[exact] <= 1e-5 * np.abs(mr[exact]) + 1e-12)
    n_out = int((z[~exact] > 4).sum())
    assert n_out <= allowed_outliers(int((~exact).sum()), batches), (method, n_out, np.sort(z.ravel())[-5:])
    # the image mean, per channel
    img = samples.mean(axis=(1, 2))
    ref = reference.mean(axis=(1, 2))
    mi, si = batch_stats(img, batches)
    mr2, sr2 = batch_stats(ref, batches)
    assert np.all(np.abs(mi - mr2) <= 4 * np.sqrt(si**2 + sr2**2)), (method, mi, mr2, si, sr2)


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
