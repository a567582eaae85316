"""The light samplers stay unbiased with a glossy BSDF (the target function and every shading site evaluate it for
the pixel's view): light_array and ris (target = luminance of the full BSDF times the light) against the
exhaustive reference, per pixel and over the image, on material_balls (dielectric, metal, Glossy and Mix spheres)
with two point lights and an area light."""

import numpy as np
import pytest
from restircl.scenes import material_balls

from .helpers import Settings, allowed_outliers, batch_stats, collect, luminance

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
    m, se = batch_stats(luminance(samples), BATCHES)
    mr, ser = batch_stats(luminance(reference), BATCHES)
    sigma = np.sqrt(se**2 + ser**2)
    z = np.abs(m - mr) / np.where(sigma > 0, sigma, 1.0)
    exact = sigma == 0
    assert np.all(np.abs(m - mr)[exact] <= 1e-5 * np.abs(mr[exact]) + 1e-12)
    n_out = int((z[~exact] > 4).sum())
    assert n_out <= allowed_outliers(int((~exact).sum()), BATCHES), (method, n_out, np.sort(z.ravel())[-5:])
    mi, si = batch_stats(samples.mean(axis=(1, 2)), BATCHES)
    mr2, sr2 = batch_stats(reference.mean(axis=(1, 2)), BATCHES)
    assert np.all(np.abs(mi - mr2) <= 4 * np.sqrt(si**2 + sr2**2)), (method, mi, mr2, si, sr2)
