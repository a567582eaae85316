"""RIS and ReSTIR with candidates from the light tree (light_proposal="tree") are unbiased: their means equal the
exhaustive reference within 4 standard errors, per pixel and over the image, on the scene with every light type,
powers 1e-6..1e6, a light touching the floor, a grazing sun and lights behind the surface (as test_estimators.py
and test_restir.py check the light array); with BSDF candidates too, whose MIS weights take the tree's pick pdf of
the light a BSDF ray met (light_pick_pdf)."""

import numpy as np
import pytest

from . import helpers as h
from .test_restir import RUNS, assert_matches

FRAMES = 8192
BATCHES = 64
W, H = 16, 12
TREE = dict(light_proposal="tree", jitter=False)


@pytest.fixture(scope="module")
def reference(device):
    return h.collect(h.mixed_lights_scene(W, H), h.Settings(method="reference", seed=101, jitter=False), FRAMES, device)


@pytest.mark.parametrize("bsdf", ["off", "on"])
def test_ris_with_the_tree_matches_reference(device, reference, bsdf):
    s = h.Settings(method="ris", candidates=4, seed=9, bsdf_sampling=bsdf, **TREE)
    samples = h.collect(h.mixed_lights_scene(W, H), s, FRAMES, device)
    assert np.all(np.isfinite(samples))
    m, se = h.batch_stats(h.luminance(samples), BATCHES)
    mr, ser = h.batch_stats(h.luminance(reference), BATCHES)
    sigma = np.sqrt(se**2 + ser**2)
    live = sigma > 0
    z = np.abs(m - mr)[live] / sigma[live]
    assert np.all(np.abs(m - mr)[~live] <= 1e-5 * np.abs(mr[~live]) + 1e-12)
    assert int((z > 4).sum()) <= h.allowed_outliers(int(live.sum()), BATCHES), np.sort(z)[-5:]
    mi, si = h.batch_stats(samples.mean(axis=(1, 2)), BATCHES)
    mr2, sr2 = h.batch_stats(reference.mean(axis=(1, 2)), BATCHES)
    assert np.all(np.abs(mi - mr2) <= 4 * np.sqrt(si**2 + sr2**2)), (mi, mr2, si, sr2)


@pytest.fixture(scope="module")
def restir_refs(device):
    out = {}
    for scene in (h.occluder_scene(W, H), h.mixed_lights_scene(W, H)):
        ref = h.collect(scene, h.Settings(method="reference", seed=55, jitter=False), FRAMES, device)
        out[scene.name] = h.batch_stats(h.luminance(ref), 32)
    return out


@pytest.mark.parametrize("case", ["mixed_pairwise", "occluders_pairwise_novis", "occluders_z_temporal"])
def test_restir_with_the_tree_matches_reference(device, restir_refs, case):
    scene = h.mixed_lights_scene(W, H) if case.startswith("mixed") else h.occluder_scene(W, H)
    extra = {"mixed_pairwise": {}, "occluders_pairwise_novis": dict(visibility_reuse=False),
             "occluders_z_temporal": dict(bias_correction="z_count", spatial=False)}[case]
    s = h.Settings(method="restir", taa=False, seed=4, **TREE, **extra)
    runs = h.run_means(scene, s, RUNS, 96, device)
    assert np.all(np.isfinite(runs))
    assert_matches(runs, restir_refs[scene.name], case)


def test_lights_behind_the_surface_give_exact_zero(device):
    for method in ("ris", "restir"):
        samples = h.collect(h.below_only_scene(), h.Settings(method=method, seed=3, light_proposal="tree"), 8, device)
        assert np.all(samples == 0.0), method
