"""RIS and ReSTIR with candidates from the light tree (light_proposal="tree") are unbiased: their means equal the
exhaustive reference within 4 standard errors, per pixel and over the image, on the scene with every light type,
powers 1e-6..1e6, a light touching the floor, a grazing sun and lights behind the surface (as test_estimators.py
and test_restir.py check the light array); with BSDF candidates too, whose MIS weights take the tree's pick pdf of
the light a BSDF ray met (light_pick_pdf)."""

import numpy as np
import pytest

from .helpers import (
    Settings,
    allowed_outliers,
    batch_stats,
    below_only_scene,
    collect,
    luminance,
    mixed_lights_scene,
    occluder_scene,
    run_means,
)
from .test_restir import RUNS, assert_matches

FRAMES = 8192
BATCHES = 64
W, H = 16, 12
TREE = dict(light_proposal="tree", jitter=False)


@pytest.fixture(scope="module")
def reference(device):
    return collect(mixed_lights_scene(W, H), Settings(method="reference", seed=101, jitter=False), FRAMES, device)


@pytest.mark.parametrize("bsdf", ["off", "on"])
def test_ris_with_the_tree_matches_reference(device, reference, bsdf):
    s = Settings(method="ris", candidates=4, seed=9, bsdf_sampling=bsdf, **TREE)
    samples = collect(mixed_lights_scene(W, H), s, FRAMES, device)
    assert np.all(np.isfinite(samples))
    m, se = batch_stats(luminance(samples), BATCHES)
    mr, ser = batch_stats(luminance(reference), BATCHES)
    sigma = np.sqrt(se**2 + ser**2)
    live = sigma > 0
    z = np.abs(m - mr)[live] / sigma[live]
    assert np.all(np.abs(m - mr)[~live] <= 1e-5 * np.abs(mr[~live]) + 1e-12)
    assert int((z > 4).sum()) <= allowed_outliers(int(live.sum()), BATCHES), np.sort(z)[-5:]
    mi, si = batch_stats(samples.mean(axis=(1, 2)), BATCHES)
    mr2, sr2 = batch_stats(reference.mean(axis=(1, 2)), BATCHES)
    assert np.all(np.abs(mi - mr2) <= 4 * np.sqrt(si**2 + sr2**2)), (mi, mr2, si, sr2)


@pytest.fixture(scope="module")
def restir_refs(device):
    out = {}
    for scene in (occluder_scene(W, H), mixed_lights_scene(W, H)):
        ref = collect(scene, Settings(method="reference", seed=55, jitter=False), FRAMES, device)
        out[scene.name] = batch_stats(luminance(ref), 32)
    return out


@pytest.mark.parametrize("case", ["mixed_pairwise", "occluders_pairwise_novis", "occluders_z_temporal"])
def test_restir_with_the_tree_matches_reference(device, restir_refs, case):
    scene = mixed_lights_scene(W, H) if case.startswith("mixed") else occluder_scene(W, H)
    extra = {"mixed_pairwise": {}, "occluders_pairwise_novis": dict(visibility_reuse=False),
             "occluders_z_temporal": dict(bias_correction="z_count", spatial=False)}[case]
    s = Settings(method="restir", taa=False, seed=4, **TREE, **extra)
    runs = run_means(scene, s, RUNS, 96, device)
    assert np.all(np.isfinite(runs))
    assert_matches(runs, restir_refs[scene.name], case)


def test_lights_behind_the_surface_give_exact_zero(device):
    for method in ("ris", "restir"):
        samples = collect(below_only_scene(), Settings(method=method, seed=3, light_proposal="tree"), 8, device)
        assert np.all(samples == 0.0), method
